//! The steps after a kernel's own stages, for the pairs still open (the next query's full
//! pipeline, f64, the exact oracle), and the single queries' one-pair job. They rerun pairs
//! through `crate::arch::dispatch` on the same token: the module graph's one cycle.

use super::job::{Job, Lane, Pending, Sink};
use super::src::Src;
use crate::algo::Params;
use crate::arch::dispatch::{self, Entries};
use crate::query::Query;
use crate::real::{Precision, Real};
use crate::types::{Intersection, Interval, PathCounts, Point};

/// The steps after a kernel's own stages, for the pairs still open: the full pipeline of the
/// next query (brute force after PQP; triangle-triangle distance after the cheap tests of
/// within-margin and intersection), or recomputation in f64 (f32 input), then the exact oracle.
/// Out of line: rare, and one copy per precision and instruction set.
#[inline(never)]
pub(super) fn escalate<T: Real, Tk: Entries>(
    tk: Tk,
    job: &mut Job<'_, T>,
    next: Option<Query>,
    widen: bool,
    open: &mut Pending<T>,
) {
    if let Some(next) = next {
        job.counts.delegated += open.len() as u64;
        rerun::<T, T, Tk>(tk, job, next, job.widen, job.exact, open);
    } else if widen && job.widen && T::PRECISION == Precision::F32 {
        job.counts.widened += open.len() as u64;
        let q = job.query;
        rerun::<T, f64, Tk>(tk, job, q, false, false, open);
    }
    if job.exact && !open.is_empty() {
        exact(job, open);
    }
    job.counts.uncertified += open.len() as u64;
}

/// Reruns the `open` pairs of `job` as a sub-job of `query` in precision `W` (gathered into
/// AoS buffers, exact conversion when widening), converts and post-processes the answers for
/// `job.query`, writes them, and keeps open the ones the sub-job did not accept.
pub(super) fn rerun<T: Real, W: Real, Tk: Entries>(
    tk: Tk,
    job: &mut Job<'_, T>,
    query: Query,
    widen: bool,
    exact: bool,
    open: &mut Pending<T>,
) {
    let n = open.len();
    let (ka, kb) = (job.a.k(), job.b.k());
    let mut fa = Vec::with_capacity(n * 3 * ka);
    let mut fb = Vec::with_capacity(n * 3 * kb);
    for &i in open.as_slice() {
        for j in 0..3 * ka {
            fa.push(W::from_f64(job.a.at(i as usize, j).to_f64()));
        }
        for j in 0..3 * kb {
            fb.push(W::from_f64(job.b.at(i as usize, j).to_f64()));
        }
    }
    let mut d = vec![W::ZERO; n];
    let mut p = vec![[W::ZERO; 3]; n];
    let mut q = vec![[W::ZERO; 3]; n];
    let mut iv = vec![Interval::default(); n];
    let mut ok = vec![false; n];
    let mut sub = Job {
        query,
        a: Src::Aos { flat: &fa, k: ka },
        b: Src::Aos { flat: &fb, k: kb },
        n,
        prm: job.prm.convert::<W>(),
        sink: Sink {
            d: Some(&mut d),
            p: Some(&mut p),
            q: Some(&mut q),
            iv: Some(&mut iv),
            ok: Some(&mut ok),
            ..Sink::default()
        },
        counts: PathCounts::default(),
        widen,
        exact,
    };
    dispatch::run_with(tk, &mut sub);
    let c = sub.counts;
    job.counts.refined += c.refined;
    job.counts.compacted += c.compacted;
    job.counts.recertified += c.recertified;
    job.counts.widened += c.widened;
    job.counts.exact += c.exact;
    let ids: Vec<u32> = open.as_slice().to_vec();
    open.clear();
    let cv = |x: W| T::from_f64(x.to_f64());
    let cv3 = |x: Point<W>| x.map(cv);
    for (m, &i) in ids.iter().enumerate() {
        let (lo, hi) = outward::<T, W>(iv[m]);
        let lane = post(
            job.query,
            job.prm.margin,
            Lane { d: cv(d[m]), p: cv3(p[m]), q: cv3(q[m]), lo, hi, ok: ok[m], it: 0 },
        );
        job.sink.put(i as usize, &lane);
        if !lane.ok {
            open.push(i as usize);
        }
    }
}

/// An interval of precision `W` narrowed to `T`, rounded outward (its lower end at least 0).
pub(crate) fn outward<T: Real, W: Real>(iv: Interval<W>) -> (T, T) {
    let l = T::from_f64(iv.lo.to_f64());
    let lo = if l.to_f64() > iv.lo.to_f64() { l.step(false) } else { l };
    let h = T::from_f64(iv.hi.to_f64());
    let hi = if h.to_f64() < iv.hi.to_f64() { h.step(true) } else { h };
    (lo.max_f(T::ZERO), hi)
}

/// Query-specific post-processing of a full distance answer: within-margin keeps it only
/// when within the margin (`+inf` beyond).
pub(crate) fn post<T: Real>(query: Query, margin: T, mut lane: Lane<T>) -> Lane<T> {
    if beyond_margin(query, margin, lane.d) {
        lane.d = T::INFINITY;
    }
    lane
}

/// Is a full answer's squared distance `d` beyond within-margin's margin (`false` for the
/// other queries)? A square beyond `T`'s range is beyond any finite margin.
pub(crate) fn beyond_margin<T: Real>(query: Query, margin: T, d: T) -> bool {
    query == Query::Within && d > margin * margin
}

/// One pair without a batch set-up (the single queries): a job of one pair on the portable
/// entry points, so the scalar code is compiled once for batches and single queries alike.
pub(crate) fn single<T: Real>(
    query: Query,
    a: &[Point<T>; 3],
    b: &[Point<T>; 3],
    prm: &Params<T>,
    exact: bool,
) -> Lane<T> {
    let (ka, kb) = query.arity();
    let (mut d, mut p, mut q) = ([T::ZERO], [[T::ZERO; 3]], [[T::ZERO; 3]]);
    let (mut iv, mut ok, mut it, mut v) = ([Interval::default()], [false], [0u32], [Intersection::Invalid]);
    let mut job = Job {
        query,
        a: Src::One { flat: a[..ka].as_flattened(), k: ka },
        b: Src::One { flat: b[..kb].as_flattened(), k: kb },
        n: 1,
        prm: *prm,
        sink: Sink {
            d: Some(&mut d),
            p: Some(&mut p),
            q: Some(&mut q),
            iv: Some(&mut iv),
            ok: Some(&mut ok),
            iters: Some(&mut it),
            verdict: Some(&mut v),
            cp: None,
            dist: None,
        },
        counts: PathCounts::default(),
        widen: true,
        exact,
    };
    dispatch::run_with(crate::lanes::Portable, &mut job);
    Lane { d: d[0], p: p[0], q: q[0], lo: iv[0].lo, hi: iv[0].hi, ok: ok[0], it: it[0] }
}

/// Exact answers for the `open` pairs (feature `exact`).
#[cfg(feature = "exact")]
pub(super) fn exact<T: Real>(job: &mut Job<'_, T>, open: &mut Pending<T>) {
    for &i in open.as_slice() {
        let (a, b) = (job.a.prim(i as usize), job.b.prim(i as usize));
        let e = crate::exact::answer(job.a.k(), &a, job.b.k(), &b);
        let lane = match e {
            Some(x) => Lane { d: x.d, p: x.p, q: x.q, lo: x.lo, hi: x.hi, ok: true, it: 0 },
            None => continue,
        };
        let lane = post(job.query, job.prm.margin, lane);
        job.sink.put(i as usize, &lane);
        job.counts.exact += 1;
    }
    open.clear();
}

#[cfg(not(feature = "exact"))]
pub(super) fn exact<T: Real>(_: &mut Job<'_, T>, _: &mut Pending<T>) {}

/// `max` that keeps `self` for NaN.
pub(super) trait MaxF {
    fn max_f(self, o: Self) -> Self;
}
impl<T: Real> MaxF for T {
    fn max_f(self, o: T) -> T {
        if self < o {
            o
        } else {
            self
        }
    }
}
