//! The batch driver: one pipeline for every query. (Named `drv`, not `driver`, so that its
//! functions sort before `algo`'s and LLVM inlines them top-down: see the module list in
//! `lib.rs`.)
//!
//! A batch is processed in chunks of [`CHUNK`] pairs. Stage 0 of the query's kernel runs on
//! every pair, a vector of lanes at a time (SoA columns are loaded directly; AoS slices and a
//! broadcast primitive are gathered); every lane's answer is written, and the indices of the
//! pairs it did not accept (certificate wider than the tolerance) are collected. For
//! triangle-triangle distance stage 0 is the quick stage (one edge pair per triangle pair),
//! and its open pairs are gathered into full vectors (lane compaction) for stage 1, the full
//! fast stage (counted as refined); on lanes with a register compress (AVX-512, AVX-512VL) the
//! quick stage packs their coordinates from its registers instead ([`Packed`]). The open
//! pairs' answers are then re-certified tightly, and those still open gathered for the
//! kernel's accurate stage when it has one; what is still open goes to the full pipeline of
//! the kernel's next query (brute force after PQP's undecided lanes, triangle-triangle
//! distance after the cheap tests of within-margin and intersection), or, for f32 input, is
//! recomputed in f64 from the exactly widened input by the same instruction set's f64
//! code, and finally, with the `exact` feature, by the exact oracle. Whatever is left is
//! counted as uncertified (answered, with its interval).
//!
//! A pair's answer depends only on its own lanes (masks and selects, never on its neighbours),
//! so it is the same in every lane position, in the tail, alone or in a batch (tested).
//! Everything generic over the lane type is `#[inline(always)]` and runs inside the
//! `#[target_feature]` entry points (`crate::arch`); the rarely taken escalation steps are out
//! of line, once per precision and instruction set.

mod escalate;
mod job;
mod src;

pub(crate) use escalate::{beyond_margin, outward, post, single};
pub(crate) use job::{Job, Lane, Pending, Sink, CHUNK};
pub(crate) use src::Src;

use crate::algo::Kernel;
use crate::arch::dispatch::{self, Entries};
use crate::lanes::{Lanes, Mask, MAX_LANES, V3};
use crate::query::Query;
use crate::real::Real;
use crate::types::{ClosestPoints, Interval};
use escalate::escalate;
use src::to_points;

/// Runs `job` with lane type `L` and the kernel `K` of `job.query`. Instantiated once per
/// query, instruction set and precision, inside its `#[target_feature]` entry point.
#[inline(always)]
pub(crate) fn run<L: Lanes, K: Kernel>(kk: L::K, job: &mut Job<'_, L::S>)
where
    L::K: Entries,
{
    let n = job.n;
    // Without the quick stage (`Engine::quick_stage(false)`), triangle-triangle distance runs
    // its full fast stage on every pair, loaded in place like stage 0: the same arithmetic per
    // lane as on gathered pairs, so a pair's answer does not depend on its neighbours either way.
    let direct = K::STAGES == 3 && !job.prm.quick;
    // The open pairs after a step and those still open after the next one: two lists for the
    // whole batch, cleared and swapped, not allocated per chunk (see [`Pending`]).
    let (mut open, mut still) = (Pending::new(), Pending::new());
    // With a register compress, the quick stage packs its open pairs' coordinates (already in
    // its registers) into chunk columns that the full fast stage loads in order.
    let pack = K::STAGES == 3 && L::COMPRESS && !direct;
    debug_assert!(!pack || (K::KA, K::KB) == (3, 3), "packing is for triangle pairs");
    let mut packed = Packed::<L::S>::new(pack, n);
    let mut start = 0;
    while start < n {
        let end = (start + CHUNK).min(n);
        open.clear();
        // (the answers of open pairs are kept only for the tight re-certification, which
        // follows the last stage before the accurate one)
        if !direct {
            let recert = K::RECERT && K::STAGES == 1;
            pass::<L, K, 0>(kk, job, Span::Run(start, end), &mut open, recert, &mut packed);
        }
        job.counts.pairs += (end - start) as u64;
        if K::NEXT == Some(Query::TriTri) {
            // within-margin and intersection: decided by their own cheap test
            job.counts.prefiltered += (end - start - open.len()) as u64;
        }
        if K::STAGES == 3 && (direct || !open.is_empty()) {
            // one call site, so the full fast stage is inlined once per entry point
            let span = if direct { Span::Run(start, end) } else { Span::Ids(open.as_slice()) };
            job.counts.refined += span.len() as u64;
            still.clear();
            pass::<L, K, 1>(kk, job, span, &mut still, K::RECERT, &mut packed);
            std::mem::swap(&mut open, &mut still);
        }
        if K::RECERT && !open.is_empty() {
            job.counts.recertified += open.len() as u64;
            still.clear();
            // out of line, in an entry point of its own ([`recert`])
            debug_assert_eq!((job.a.k(), job.b.k()), (K::KA, K::KB));
            dispatch::recert_with(kk, job, &open, &mut still, K::SHARP);
            std::mem::swap(&mut open, &mut still);
        }
        if K::STAGES == 3 && !open.is_empty() {
            // out of line, in an entry point of its own ([`accurate`])
            debug_assert_eq!(job.query, Query::TriTri, "the accurate stage is triangle-triangle distance's");
            job.counts.compacted += open.len() as u64;
            still.clear();
            dispatch::accurate_with(kk, job, &open, &mut still);
            std::mem::swap(&mut open, &mut still);
        }
        if !open.is_empty() {
            escalate(kk, job, K::NEXT, K::WIDEN, &mut open);
        }
        start = end;
    }
}

/// The accurate stage of triangle-triangle distance (PQP's TriDist, stage 2 of
/// [`crate::algo::pqp::TriTri`]) on the `open` pairs, gathered into full vectors; the pairs it
/// does not accept go to `still`. A rare path (the pairs that neither fast stage nor the tight
/// re-certification accepts), which [`run`] reaches through its token
/// ([`crate::arch::dispatch::Entries::accurate_f32`]): an entry point of its own per
/// instruction set and precision (`crate::arch::dispatch::rare_modules`), not inlined into the
/// query's. Out of line, this stage and [`recert`] halved the kernels crate's release build
/// (docs/notes/build-time.md); the headline workloads reach these paths once per chunk at most.
#[inline(always)]
pub(crate) fn accurate<L: Lanes>(
    kk: L::K,
    job: &mut Job<'_, L::S>,
    open: &Pending<L::S>,
    still: &mut Pending<L::S>,
) {
    pass::<L, crate::algo::pqp::TriTri, 2>(
        kk,
        job,
        Span::Ids(open.as_slice()),
        still,
        false,
        &mut Packed::new(false, 0),
    );
}

/// The pairs one stage pass runs on: a run `start..end` of the batch, loaded in place, or the
/// pairs of an open list (gathered, or read from the packed columns when they are on).
#[derive(Clone, Copy)]
enum Span<'s> {
    Run(usize, usize),
    Ids(&'s [u32]),
}

impl Span<'_> {
    fn len(self) -> usize {
        match self {
            Span::Run(start, end) => end - start,
            Span::Ids(ix) => ix.len(),
        }
    }
}

/// Runs stage `ST` of `K` on the pairs of `span` (read from `packed` when it is on: stage 1),
/// writes every pair's answer and collects the ones not accepted (with their answers when
/// `answers`); stage 0 with `packed` on also packs the pairs it leaves open.
#[inline(always)]
fn pass<L: Lanes, K: Kernel, const ST: u8>(
    kk: L::K,
    job: &mut Job<'_, L::S>,
    span: Span<'_>,
    open: &mut Pending<L::S>,
    answers: bool,
    packed: &mut Packed<L::S>,
) {
    let pack = packed.on && ST < 2;
    let groups = span.len().div_ceil(L::N);
    // (an open list's pairs are gathered: its runs are cut empty)
    let (start, end, idx) = match span {
        Span::Run(start, end) => (start, end, None),
        Span::Ids(ix) => (0, 0, Some(ix)),
    };
    let cut = if idx.is_some() { 0 } else { groups * L::N };
    let (ra, rb) = (job.a.run(K::KA, start, cut), job.b.run(K::KB, start, cut));
    let only_d = job.sink.only_d();
    if pack && ST == 1 {
        if let Some(ix) = idx {
            packed.pad(ix.len(), groups * L::N);
        }
    }
    for g in 0..groups {
        let (a, b, ids) = match idx {
            Some(ix) => {
                let part = &ix[g * L::N..((g + 1) * L::N).min(ix.len())];
                if pack {
                    (
                        packed.load::<L>(kk, 0, g * L::N),
                        packed.load::<L>(kk, 9, g * L::N),
                        Ids::Gathered(part),
                    )
                } else {
                    (
                        job.a.gather::<L>(K::KA, kk, part),
                        job.b.gather::<L>(K::KB, kk, part),
                        Ids::Gathered(part),
                    )
                }
            }
            None => {
                let i = start + g * L::N;
                let n = L::N.min(end - i);
                (ra.load_k::<L>(kk, i, n), rb.load_k::<L>(kk, i, n), Ids::Run { at: i, n })
            }
        };
        let o = K::stage::<L, ST>(&a, &b, &job.prm);
        if pack && ST == 0 {
            let n = match ids {
                Ids::Run { n, .. } => n,
                Ids::Gathered(ix) => ix.len(),
            };
            let shut = !o.ok.bits() & ((1u32 << n) - 1);
            if shut != 0 {
                packed.put(open.len(), shut, &a, &b);
            }
        }
        write::<L>(job, &o, ids, open, (answers, only_d));
    }
}

/// The coordinates of one chunk's open pairs, packed by the quick stage for the full fast
/// stage (triangle-triangle distance, on lanes with a register compress: [`Lanes::COMPRESS`]):
/// 18 columns (the first triangle's 9 coordinates, then the second's), pair `m` of the chunk's
/// open list at row `m`. The quick stage has each group's coordinates in registers; compressing
/// them by the open lanes (`vcompressps`/`vcompresspd`) and storing them costs one instruction
/// pair per column and group, where gathering them back costs a hardware gather per column and
/// group of open pairs, on whose results the stage then waits. On the Zen 5 reference machine
/// that raised `spin tri_tri random f32 avx512 1` from 34.4-36.4 to 46.9-48.2 M/s
/// (docs/notes/kernel-speed.md). The bits are the gathered path's: the
/// same coordinates in the same lanes, the tail lanes repeating the last open pair ([`Packed::pad`]).
struct Packed<T: Real> {
    /// Pack at all (a constant of the entry point: the kernel, the lanes and the quick stage).
    on: bool,
    /// Rows per column: a chunk's pairs (or the batch's, if fewer) plus a vector's slack, so
    /// that a compress's full-vector store at the last open row stays in its column.
    rows: usize,
    /// At least `18 * rows` values, taken at the batch's first open pair from this thread's
    /// spare (`Sealed::pack_spare`), given back when the batch is done.
    c: Vec<T>,
}

impl<T: Real> Drop for Packed<T> {
    fn drop(&mut self) {
        if !self.c.is_empty() {
            let c = std::mem::take(&mut self.c);
            // (at thread exit the spare may be gone: the buffer is then freed)
            let _ = <T as crate::real::sealed::Sealed>::pack_spare().try_with(|s| {
                if let Ok(mut s) = s.try_borrow_mut() {
                    if s.len() < c.len() {
                        *s = c;
                    }
                }
            });
        }
    }
}

impl<T: Real> Packed<T> {
    fn new(on: bool, n: usize) -> Self {
        Packed { on, rows: n.min(CHUNK) + MAX_LANES, c: Vec::new() }
    }
    /// The lanes `m` (bits) of the group `a`, `b` at rows `at..` of every column (`at`: the
    /// chunk's open pairs so far).
    #[inline(always)]
    fn put<L: Lanes<S = T>>(&mut self, at: usize, m: u32, a: &[V3<L>; 3], b: &[V3<L>; 3]) {
        let rows = self.rows;
        if self.c.is_empty() {
            let spare = <T as crate::real::sealed::Sealed>::pack_spare();
            self.c = spare
                .try_with(|s| s.try_borrow_mut().map(|mut s| std::mem::take(&mut *s)))
                .ok()
                .and_then(Result::ok)
                .unwrap_or_default();
            if self.c.len() < 18 * rows {
                self.c.resize(18 * rows, T::ZERO);
            }
        }
        let c = &mut self.c[..18 * rows];
        for (s, side) in [a, b].into_iter().enumerate() {
            for (v, p) in side.iter().enumerate() {
                for (d, x) in [p.x, p.y, p.z].into_iter().enumerate() {
                    let j = 9 * s + 3 * v + d;
                    x.compress(m, &mut c[j * rows + at..][..L::N]);
                }
            }
        }
    }
    /// Rows `n..full` repeat row `n - 1`, as a gather's lanes beyond its pairs do (`n >= 1`,
    /// `full` the open pairs rounded up to whole vectors).
    fn pad(&mut self, n: usize, full: usize) {
        let rows = self.rows;
        let c = &mut self.c[..18 * rows];
        for col in c.chunks_exact_mut(rows) {
            let last = col[n - 1];
            col[n..full].fill(last);
        }
    }
    /// Side `side` (0 or 9: the first column of its triangle) of the open pairs `at..at + N`.
    #[inline(always)]
    fn load<L: Lanes<S = T>>(&self, kk: L::K, side: usize, at: usize) -> [V3<L>; 3] {
        let rows = self.rows;
        let c = &self.c[..18 * rows];
        let mut coord = [L::splat(kk, T::ZERO); 9];
        for (j, x) in coord.iter_mut().enumerate() {
            *x = L::load(kk, &c[(side + j) * rows + at..][..L::N]);
        }
        to_points(&coord, 3)
    }
}

/// The pairs of one group of lanes: `n` consecutive ones from `at` (a pass in order), or
/// the indices a gathered pass took (rising strictly: an open list is pushed in order).
#[derive(Clone, Copy)]
enum Ids<'a> {
    Run { at: usize, n: usize },
    Gathered(&'a [u32]),
}

impl Ids<'_> {
    /// The pair in lane `l`.
    #[inline(always)]
    fn of(self, l: usize) -> usize {
        match self {
            Ids::Run { at, .. } => at + l,
            Ids::Gathered(ix) => ix[l] as usize,
        }
    }
}

/// Writes every lane's answer and collects the ones not accepted (with their answers when
/// `answers`). `only_d`: [`Sink::only_d`] of `job.sink`.
#[inline(always)]
fn write<L: Lanes>(
    job: &mut Job<'_, L::S>,
    o: &crate::algo::Out<L>,
    ids: Ids<'_>,
    open: &mut Pending<L::S>,
    (answers, only_d): (bool, bool),
) {
    debug_assert_eq!(only_d, job.sink.only_d());
    let ok = o.ok.bits();
    // Gathered indices rise strictly, so first and last `n - 1` apart means consecutive.
    let (at, n, consecutive) = match ids {
        Ids::Run { at, n } => (at, n, true),
        Ids::Gathered(ix) => {
            debug_assert!(ix.windows(2).all(|w| w[0] < w[1]));
            let (at, n) = (ix[0] as usize, ix.len());
            (at, n, ix[n - 1] as usize == at + n - 1)
        }
    };
    let shut = !ok & ((1u32 << n) - 1);
    // The common cases: squared distances only (no verdict queries, no other output), and the
    // open pairs' answers not needed (the next stage recomputes them and writes over these):
    // one vector store for consecutive pairs, a scatter for gathered ones, then the open
    // lanes' indices.
    if only_d && (shut == 0 || !answers) {
        if let Some(d) = job.sink.d.as_deref_mut() {
            if consecutive && n == L::N {
                o.d.store(&mut d[at..at + L::N]);
            } else {
                let mut buf = L::ZEROS;
                o.d.store(buf.as_mut());
                for (l, &x) in buf.as_ref().iter().enumerate().take(n) {
                    d[ids.of(l)] = x;
                }
            }
        }
        let mut rest = shut;
        while rest != 0 {
            open.push(ids.of(rest.trailing_zeros() as usize));
            rest &= rest - 1;
        }
        return;
    }
    let mut cols = [L::ZEROS; 10];
    for (slot, v) in cols.iter_mut().zip([o.d, o.p.x, o.p.y, o.p.z, o.q.x, o.q.y, o.q.z, o.lo, o.hi, o.it]) {
        v.store(slot.as_mut());
    }
    let buf = cols.each_ref().map(AsRef::as_ref);
    // Each requested output tested once per group, then written lane by lane: consecutive
    // pairs through one slice of it (one bounds check), gathered ones by index. (Through
    // `Sink::put`, eight tests and a bounds check per lane, and a 640-byte lane buffer cleared
    // per group, asking for closest points took 199 instructions per pair against 128 for
    // squared distances alone, now 147: callgrind of `spin tri_tri arm_nearby f32 avx2fma 0.3
    // 4000 1 points|sqdist`.)
    macro_rules! each {
        ($out:expr, $l:ident => $val:expr) => {
            if let Some(s) = $out.as_deref_mut() {
                if consecutive {
                    for ($l, x) in s[at..at + n].iter_mut().enumerate() {
                        *x = $val;
                    }
                } else {
                    for $l in 0..n {
                        s[ids.of($l)] = $val;
                    }
                }
            }
        };
    }
    let sink = &mut job.sink;
    each!(sink.d, l => buf[0][l]);
    each!(sink.dist, l => buf[0][l].sqrt());
    each!(sink.cp, l => ClosestPoints { sqdist: buf[0][l], p: [buf[1][l], buf[2][l], buf[3][l]], q: [buf[4][l], buf[5][l], buf[6][l]] });
    each!(sink.p, l => [buf[1][l], buf[2][l], buf[3][l]]);
    each!(sink.q, l => [buf[4][l], buf[5][l], buf[6][l]]);
    each!(sink.iv, l => Interval { lo: buf[7][l], hi: buf[8][l] });
    each!(sink.iters, l => buf[9][l].to_f64() as u32);
    each!(sink.ok, l => ok >> l & 1 == 1);
    each!(sink.verdict, l => lane_of(&buf, ok, l).verdict());
    let mut rest = shut;
    while rest != 0 {
        let l = rest.trailing_zeros() as usize;
        if answers {
            open.push_answer(ids.of(l), &lane_of(&buf, ok, l));
        } else {
            open.push(ids.of(l));
        }
        rest &= rest - 1;
    }
}

/// Lane `l` of a group's answer stored as columns (`d`, `p`, `q`, `lo`, `hi`, iterations) and
/// acceptance bits.
#[inline(always)]
fn lane_of<T: Real>(buf: &[&[T]; 10], ok: u32, l: usize) -> Lane<T> {
    Lane {
        d: buf[0][l],
        p: [buf[1][l], buf[2][l], buf[3][l]],
        q: [buf[4][l], buf[5][l], buf[6][l]],
        lo: buf[7][l],
        hi: buf[8][l],
        ok: ok >> l & 1 == 1,
        it: buf[9][l].to_f64() as u32,
    }
}

/// The tight re-certification of the `open` pairs' answers (gathered into full vectors), for
/// primitives of `job`'s arity (every query with `Kernel::RECERT`: triangle-triangle distance
/// and its brute force, segment-segment and point-triangle); `sharp` is the kernel's
/// `Kernel::SHARP`. Out of line like [`accurate`], through
/// [`crate::arch::dispatch::Entries::recert_f32`]: one entry point per instruction set and precision for
/// all three arities, where every query's entry point had inlined a copy of its own.
#[inline(always)]
pub(crate) fn recert<L: Lanes>(
    kk: L::K,
    job: &mut Job<'_, L::S>,
    open: &Pending<L::S>,
    still: &mut Pending<L::S>,
    sharp: bool,
) {
    let (ka, kb) = (job.a.k(), job.b.k());
    let ix = open.as_slice();
    debug_assert_eq!(open.ans.len(), ix.len(), "re-certification of pairs pushed without their answers");
    let only_d = job.sink.only_d();
    for g in 0..ix.len().div_ceil(L::N) {
        let (lo, hi) = (g * L::N, ((g + 1) * L::N).min(ix.len()));
        let part = &ix[lo..hi];
        let (a, b) = (job.a.gather::<L>(ka, kk, part), job.b.gather::<L>(kb, kk, part));
        let mut cols = [[L::S::ZERO; MAX_LANES]; 7];
        for l in 0..L::N {
            let ans = &open.ans[lo + l.min(part.len() - 1)];
            for (c, col) in cols.iter_mut().enumerate() {
                col[l] = ans[c];
            }
        }
        // (no closure: closures compile without the entry point's target features)
        let mut v = [L::splat(kk, L::S::ZERO); 7];
        for (x, col) in v.iter_mut().zip(&cols) {
            *x = L::load(kk, col);
        }
        let (d, p, q) = (v[0], V3::new(v[1], v[2], v[3]), V3::new(v[4], v[5], v[6]));
        let o = match (ka, kb) {
            (2, 2) => crate::algo::recertify::<L, 2, 2>(&a, &b, d, p, q, &job.prm, sharp),
            (1, 3) => crate::algo::recertify::<L, 1, 3>(&a, &b, d, p, q, &job.prm, sharp),
            _ => crate::algo::recertify::<L, 3, 3>(&a, &b, d, p, q, &job.prm, sharp),
        };
        write::<L>(job, &o, Ids::Gathered(part), still, (false, only_d));
    }
}
