//! Threads for one batch: the pieces of a split batch, taken from the two ends by the calling
//! thread and the helpers (a persistent rayon pool, or scoped threads without the `rayon`
//! feature), and the waiting that keeps short batches from losing to wake-ups.

use crate::drv::Job;
use crate::drv::Sink;
use crate::Isa;
use crate::PathCounts;
use crate::Real;
#[cfg(feature = "rayon")]
use std::sync::OnceLock;

/// [`crate::Engine::WAIT_AWAKE`].
pub(crate) const WAIT_AWAKE: std::time::Duration = std::time::Duration::from_micros(200);

/// Set by the unit test of a system out of threads only.
#[cfg(test)]
pub(crate) static REFUSE_THREADS: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// The pairs of a split batch not taken yet, `front..back`, and their outputs.
pub(super) struct Left<'a, T> {
    pub(super) front: usize,
    pub(super) back: usize,
    pub(super) sink: Sink<'a, T>,
}

/// Runs `job` in pieces of `piece` pairs (the last one shorter) on `threads` threads
/// ([`together`]), each taking the next piece as it finishes one: the calling thread from the
/// front, the helpers from the back. A batch run again (a planner's next step, a benchmark's
/// next round) then leaves about the same half in each core's cache; taken in one order by
/// both, the pieces went to either core. With the caller's wait of [`together`], 2 threads
/// answered 4000 nearby Armadillo pairs at 1.24-1.61x one thread's speed in one order and
/// 1.45-1.75x from the two ends (`spin tri_tri arm_nearby f32 avx2fma 1 4000 1|2`, two copies
/// of each build alternated twice; the machine is shared and noisy).
///
/// A piece's job is made by the thread that takes it, its outputs split off the ones left
/// under the lock, and each thread adds up its own path counts. The jobs had been made in a
/// vector by the caller before the split and their counts summed after it: 0.63-0.75 µs and
/// about 0.8 µs of a 23 µs batch on two threads (0.25-0.33 µs to make them on one), the
/// helper's jobs written on one core and read on the other (throwaway timestamps, `spin
/// tri_tri arm_nearby f32 avx2fma 1 4000 2`, 2026-11-29, the AMD EPYC). Without that vector,
/// with the driver's spare open-pair lists (`drv.rs`, `Pending`) and the caller's spinning
/// wait ([`together`]): 143.7 -> 157.0 M/s on two threads (medians), faster in 10 of 10 rounds
/// alternated with the parent's binary (the machine noisy), and two threads over one 1.40-1.77x (median
/// 1.59x) -> 1.54-1.80x (1.66x) in 8 rounds of both builds alternated; later, quieter,
/// 1.69-1.81x (1.75x). Pieces shrinking towards the end (each a quarter of what was left,
/// down to 256 pairs) were no better this time either: 1.63-1.89x (1.74x) in those 8 rounds.
pub(super) fn run_pieces<T: Real>(isa: Isa, threads: usize, piece: usize, job: Job<'_, T>) -> PathCounts {
    use std::sync::Mutex;
    let Job { query, a, b, n, prm, sink, widen, exact, .. } = job;
    let left = Mutex::new(Left { front: 0, back: n, sink });
    let total = Mutex::new(PathCounts::default());
    together(threads.min(n.div_ceil(piece)), &|caller| {
        let mut mine = PathCounts::default();
        loop {
            let (start, len, sink) = {
                let mut l = left.lock().unwrap_or_else(|e| e.into_inner());
                if l.front >= l.back {
                    break;
                }
                let rest = std::mem::take(&mut l.sink);
                // the first piece left, or the last one (the pieces start at multiples of
                // `piece`: `front` is one, and `back` is one or `n`)
                let start = if caller { l.front } else { (l.back - 1) / piece * piece };
                let len = if caller { piece.min(l.back - l.front) } else { l.back - start };
                let (x, y) = rest.split_at(if caller { len } else { start - l.front });
                let (sink, rest) = if caller { (x, y) } else { (y, x) };
                l.sink = rest;
                if caller {
                    l.front += len;
                } else {
                    l.back = start;
                }
                (start, len, sink)
            };
            let mut job = Job {
                query,
                a: a.from(start),
                b: b.from(start),
                n: len,
                prm,
                sink,
                counts: PathCounts::default(),
                widen,
                exact,
            };
            crate::arch::run(isa, &mut job);
            mine.add(&job.counts);
        }
        total.lock().unwrap_or_else(|e| e.into_inner()).add(&mine);
    });
    total.into_inner().unwrap_or_else(|e| e.into_inner())
}

/// `f` on every item, on up to `threads` threads ([`together`]), each thread with its own
/// state made by `init`; results in item order.
pub(crate) fn par_map_init<I: Sync, St, R: Send>(
    threads: usize,
    items: &[I],
    init: impl Fn() -> St + Sync + Send,
    f: impl Fn(&mut St, &I) -> R + Sync + Send,
) -> Vec<R> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Mutex;
    let next = AtomicUsize::new(0);
    let out: Mutex<Vec<Option<R>>> = Mutex::new((0..items.len()).map(|_| None).collect());
    together(threads.min(items.len()), &|_| {
        let mut st = None;
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            let Some(item) = items.get(i) else { break };
            let r = f(st.get_or_insert_with(&init), item);
            out.lock().unwrap_or_else(|e| e.into_inner())[i] = Some(r);
        }
    });
    out.into_inner().unwrap_or_else(|e| e.into_inner()).into_iter().flatten().collect()
}

/// Runs `work` on `threads` threads at once, the calling thread one of them (`work(true)`; the
/// helpers run `work(false)`): it neither waits idle for the others to start nor sleeps while
/// they finish. The helpers come from a persistent pool of `threads - 1` with the `rayon`
/// feature, scoped threads started per call without it. Helpers the system refuses to start
/// are left out: the threads that run take their pieces (the caller alone at worst), with the
/// same answers, instead of a panic.
///
/// Done with its share, the caller waits for the helpers awake ([`WAIT_AWAKE`], [`crate::Engine::WAIT_AWAKE`]:
/// spinning for its first 10 µs, the imbalance between two threads' last pieces of a small
/// batch, then yielding its core to any thread that needs it) before the pool's own wait,
/// which sleeps. (Yielding from the start, each look at the helpers was a system call; the
/// spin's own share of the gain above was within the noise: 153.8 -> 157.6 M/s, 5 of 8
/// rounds.)
/// Asleep, it needed waking when the last helper finished, and the helpers, idle meanwhile, had gone to sleep
/// too by the time the next batch came: 2 threads answered 4000 nearby Armadillo pairs (30 µs
/// batches) at 0.88-1.26x one thread's speed, 1.24-1.61x with the wait alone and 1.45-1.80x
/// with the two ends of [`run_pieces`] as well (`spin tri_tri arm_nearby f32 avx2fma 1 4000
/// 1|2`, copies of each build alternated; the machine is shared and noisy).
pub(super) fn together(threads: usize, work: &(dyn Fn(bool) + Sync)) {
    if threads <= 1 {
        return work(true);
    }
    #[cfg(feature = "rayon")]
    {
        use std::sync::atomic::{AtomicUsize, Ordering};
        /// How long the caller's wait spins before it yields.
        const SPIN: std::time::Duration = std::time::Duration::from_micros(10);
        let done = AtomicUsize::new(0);
        let done = &done;
        let Some(pool) = pool(threads - 1) else {
            return work(true);
        };
        pool.in_place_scope(|s| {
            for _ in 1..threads {
                s.spawn(move |_| {
                    work(false);
                    done.fetch_add(1, Ordering::Release);
                });
            }
            work(true);
            let t0 = std::time::Instant::now();
            while done.load(Ordering::Acquire) < threads - 1 {
                let waited = t0.elapsed();
                if waited >= WAIT_AWAKE {
                    break;
                }
                if waited < SPIN {
                    std::hint::spin_loop();
                } else {
                    std::thread::yield_now();
                }
            }
        });
    }
    #[cfg(not(feature = "rayon"))]
    std::thread::scope(|s| {
        for _ in 1..threads {
            if refused() || std::thread::Builder::new().spawn_scoped(s, || work(false)).is_err() {
                break;
            }
        }
        work(true);
    });
}

/// Whether starting threads is refused, as a system out of threads would: in the unit tests,
/// on request, to test that batches still complete; never otherwise.
pub(super) fn refused() -> bool {
    #[cfg(test)]
    return REFUSE_THREADS.load(std::sync::atomic::Ordering::Relaxed);
    #[cfg(not(test))]
    false
}

/// A persistent pool per thread count, made on first use; `None` when the system refuses its
/// threads (tried again at the next call).
#[cfg(feature = "rayon")]
pub(super) fn pool(threads: usize) -> Option<std::sync::Arc<rayon::ThreadPool>> {
    use std::sync::{Arc, Mutex};
    type Pools = Mutex<Vec<(usize, Arc<rayon::ThreadPool>)>>;
    static POOLS: OnceLock<Pools> = OnceLock::new();
    if refused() {
        return None;
    }
    let mut pools = POOLS.get_or_init(|| Mutex::new(Vec::new())).lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, p)) = pools.iter().find(|(n, _)| *n == threads) {
        return Some(p.clone());
    }
    let p = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(|i| format!("tridist-{i}"))
        .build()
        .ok()?;
    let p = Arc::new(p);
    pools.push((threads, p.clone()));
    Some(p)
}
