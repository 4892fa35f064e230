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

use crate::algo::{Kernel, Params};
use crate::isa::Token;
use crate::lanes::{GatherIx, Lanes, Mask, MAX_LANES, V3};
use crate::query::Query;
use crate::real::{Precision, Real};
use crate::types::{ClosestPoints, Intersection, Interval, PathCounts, Point};

/// Pairs per chunk: the most a stage ever gathers at once.
pub(crate) const CHUNK: usize = 256;

/// Where one side's primitives come from (K points each). Crate-private plumbing.
#[derive(Clone, Copy)]
pub enum Src<'a, T> {
    /// Padded SoA columns: coordinate `j` (0..3K) of primitive `i` is `data[j * cap + base + i]`.
    Soa { data: &'a [T], cap: usize, base: usize, k: usize },
    /// AoS: primitive `i` is `flat[i*3K .. (i+1)*3K]`.
    Aos { flat: &'a [T], k: usize },
    /// One primitive against every primitive of the other side.
    One { flat: &'a [T], k: usize },
}

impl<'a, T: Real> Src<'a, T> {
    /// The same source starting at primitive `start` (for splitting a batch across threads;
    /// SoA splits must be multiples of `batch::PAD` so that vector loads stay in the padded columns).
    pub(crate) fn from(self, start: usize) -> Src<'a, T> {
        match self {
            Src::Soa { data, cap, base, k } => Src::Soa { data, cap, base: base + start, k },
            Src::Aos { flat, k } => Src::Aos { flat: &flat[start * 3 * k..], k },
            one @ Src::One { .. } => one,
        }
    }

    /// Points per primitive.
    pub(crate) fn k(&self) -> usize {
        match *self {
            Src::Soa { k, .. } | Src::Aos { k, .. } | Src::One { k, .. } => k,
        }
    }

    /// Coordinate `j` of primitive `i`.
    #[inline(always)]
    pub(crate) fn at(&self, i: usize, j: usize) -> T {
        match *self {
            Src::Soa { data, cap, base, .. } => data[j * cap + base + i],
            Src::Aos { flat, k } => flat[i * 3 * k + j],
            Src::One { flat, .. } => flat[j],
        }
    }

    /// Primitive `i` as points (unused slots repeat the first point).
    #[cfg(feature = "exact")]
    pub(crate) fn prim(&self, i: usize) -> [Point<T>; 3] {
        let mut out = [[T::ZERO; 3]; 3];
        for v in 0..3 {
            let vv = if v < self.k() { v } else { 0 };
            out[v] = [self.at(i, 3 * vv), self.at(i, 3 * vv + 1), self.at(i, 3 * vv + 2)];
        }
        out
    }

    /// The primitives `start..end` cut for vector loads ([`Run`]); `n` is the pairs' count rounded
    /// up to whole vectors, `k` the kernel's arity (a constant: every column used is then cut
    /// to the one length `n` in the compiled code, so the loads of a group share one bounds
    /// check instead of two per column).
    #[inline(always)]
    fn run(self, k: usize, start: usize, n: usize) -> Run<'a, T> {
        debug_assert_eq!(k, self.k());
        let mut cols: [&'a [T]; 9] = [&[]; 9];
        if let Src::Soa { data, cap, base, .. } = self {
            // Columns are padded to a multiple of `batch::PAD` with copies of the last primitive.
            for (j, c) in cols.iter_mut().enumerate().take(3 * k) {
                let at = j * cap + base + start;
                *c = &data[at..at + n];
            }
        }
        Run { src: self, cols, start, k }
    }
}

/// A source's primitives `start..` as one stage pass reads them in order: for SoA input, its
/// columns cut once to the same length, so that a vector load's bounds check (the same for every
/// column) is made once per group, not twice per column (those checks were 90 of the quick
/// stage's 886 instructions per group: `perf annotate` of `spin tri_tri arm_nearby f32 avx2fma`).
struct Run<'a, T> {
    src: Src<'a, T>,
    cols: [&'a [T]; 9],
    start: usize,
    /// The kernel's arity (a constant in the compiled code: see [`Src::run`]).
    k: usize,
}

impl<T: Real> Run<'_, T> {
    /// [`Run::load`] with the arity (a kernel's constant) turned into a const parameter.
    #[inline(always)]
    fn load_k<L: Lanes<S = T>>(&self, kk: L::K, i: usize, lanes: usize) -> [V3<L>; 3] {
        match self.k {
            1 => self.load::<L, 1>(kk, i, lanes),
            2 => self.load::<L, 2>(kk, i, lanes),
            _ => self.load::<L, 3>(kk, i, lanes),
        }
    }

    /// The primitives `i .. i + lanes` (`lanes <= L::N`; lanes beyond repeat the last one),
    /// `K` points each (the kernel's arity, a constant, so the loops unroll and the layout is
    /// matched once, not per coordinate).
    #[inline(always)]
    fn load<L: Lanes<S = T>, const K: usize>(&self, kk: L::K, i: usize, lanes: usize) -> [V3<L>; 3] {
        let mut coord = [L::splat(kk, T::ZERO); 9];
        match self.src {
            Src::Soa { .. } => {
                let o = i - self.start;
                for (c, col) in coord.iter_mut().zip(&self.cols).take(3 * K) {
                    *c = L::load(kk, &col[o..]);
                }
            }
            Src::One { flat, .. } => {
                for (j, c) in coord.iter_mut().enumerate().take(3 * K) {
                    *c = L::splat(kk, flat[j]);
                }
            }
            Src::Aos { flat, .. } => {
                for (j, c) in coord.iter_mut().enumerate().take(3 * K) {
                    let mut buf = L::ZEROS;
                    for (l, slot) in buf.as_mut().iter_mut().enumerate() {
                        *slot = flat[(i + l.min(lanes - 1)) * 3 * K + j];
                    }
                    *c = L::load(kk, buf.as_ref());
                }
            }
        }
        to_points(&coord, K)
    }
}

impl<'a, T: Real> Src<'a, T> {
    /// The primitives `idx[0..]` (at most `L::N`; lanes beyond repeat the last one). The
    /// layout is matched once, not per coordinate (compaction gathers a large share of the
    /// pairs when the quick stage of triangle distance leaves them open). `k`: the kernel's
    /// arity, a constant, as for [`Src::run`].
    #[inline(always)]
    fn gather<L: Lanes<S = T>>(&self, k: usize, kk: L::K, idx: &[u32]) -> [V3<L>; 3] {
        debug_assert_eq!(k, self.k());
        let mut coord = [L::splat(kk, T::ZERO); 9];
        let mut at = [0usize; MAX_LANES];
        for (l, a) in at.iter_mut().enumerate().take(L::N) {
            *a = idx[l.min(idx.len() - 1)] as usize;
        }
        match *self {
            Src::Soa { data, cap, base, .. } => {
                let ix = GatherIx::new(at);
                // every column cut to the one length `cap - base`, so that the compiled code
                // checks each lane's index once for all columns, not once per column
                for (j, c) in coord.iter_mut().enumerate().take(3 * k) {
                    *c = L::gather(kk, &data[j * cap + base..][..cap - base], &ix);
                }
            }
            Src::Aos { flat, .. } => {
                for a in at.iter_mut() {
                    *a *= 3 * k;
                }
                let ix = GatherIx::new(at);
                // every coordinate's view cut to one length (the first index of the last
                // primitive, plus one), for one check per lane as above
                let m = (flat.len() + 1).saturating_sub(3 * k);
                for (j, c) in coord.iter_mut().enumerate().take(3 * k) {
                    *c = L::gather(kk, &flat[j..][..m], &ix);
                }
            }
            Src::One { flat, .. } => {
                for (j, c) in coord.iter_mut().enumerate().take(3 * k) {
                    *c = L::splat(kk, flat[j]);
                }
            }
        }
        to_points(&coord, k)
    }
}

#[inline(always)]
fn to_points<L: Lanes>(c: &[L; 9], k: usize) -> [V3<L>; 3] {
    let v = |m: usize| V3::new(c[3 * m], c[3 * m + 1], c[3 * m + 2]);
    [v(0), if k > 1 { v(1) } else { v(0) }, if k > 2 { v(2) } else { v(0) }]
}

/// Caller-provided outputs (any subset), indexed by pair. Crate-private plumbing.
#[derive(Default)]
pub struct Sink<'a, T> {
    pub d: Option<&'a mut [T]>,
    pub verdict: Option<&'a mut [Intersection]>,
    pub cp: Option<&'a mut [ClosestPoints<T>]>,
    pub p: Option<&'a mut [Point<T>]>,
    pub q: Option<&'a mut [Point<T>]>,
    pub iv: Option<&'a mut [Interval<T>]>,
    pub iters: Option<&'a mut [u32]>,
    /// Accepted (certified within the tolerance) or not: the escalation steps read it back.
    pub ok: Option<&'a mut [bool]>,
}

fn split<X>(s: Option<&mut [X]>, at: usize) -> (Option<&mut [X]>, Option<&mut [X]>) {
    match s {
        Some(s) => {
            let (x, y) = s.split_at_mut(at);
            (Some(x), Some(y))
        }
        None => (None, None),
    }
}

impl<'a, T: Real> Sink<'a, T> {
    /// The outputs of pairs `..at` and `at..`.
    pub(crate) fn split_at(self, at: usize) -> (Sink<'a, T>, Sink<'a, T>) {
        let (d0, d1) = split(self.d, at);
        let (v0, v1) = split(self.verdict, at);
        let (c0, c1) = split(self.cp, at);
        let (p0, p1) = split(self.p, at);
        let (q0, q1) = split(self.q, at);
        let (i0, i1) = split(self.iv, at);
        let (t0, t1) = split(self.iters, at);
        let (o0, o1) = split(self.ok, at);
        (
            Sink { d: d0, verdict: v0, cp: c0, p: p0, q: q0, iv: i0, iters: t0, ok: o0 },
            Sink { d: d1, verdict: v1, cp: c1, p: p1, q: q1, iv: i1, iters: t1, ok: o1 },
        )
    }

    #[inline(always)]
    fn put(&mut self, i: usize, o: &Lane<T>) {
        if let Some(s) = self.d.as_deref_mut() {
            s[i] = o.d;
        }
        if let Some(s) = self.verdict.as_deref_mut() {
            s[i] = o.verdict();
        }
        if let Some(s) = self.cp.as_deref_mut() {
            s[i] = ClosestPoints { sqdist: o.d, p: o.p, q: o.q };
        }
        if let Some(s) = self.p.as_deref_mut() {
            s[i] = o.p;
        }
        if let Some(s) = self.q.as_deref_mut() {
            s[i] = o.q;
        }
        if let Some(s) = self.iv.as_deref_mut() {
            s[i] = Interval { lo: o.lo, hi: o.hi };
        }
        if let Some(s) = self.iters.as_deref_mut() {
            s[i] = o.it;
        }
        if let Some(s) = self.ok.as_deref_mut() {
            s[i] = o.ok;
        }
    }
}

/// One pair's answer.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Lane<T> {
    pub d: T,
    pub p: Point<T>,
    pub q: Point<T>,
    pub lo: T,
    pub hi: T,
    pub ok: bool,
    pub it: u32,
}

impl<T: Real> Lane<T> {
    /// The intersection verdict of a distance answer: disjoint when a positive lower bound is
    /// certain, intersecting when within the tolerance of contact, else (uncertified) the
    /// answer's own zero test.
    pub(crate) fn verdict(&self) -> Intersection {
        if self.d.is_nan() {
            Intersection::Invalid
        } else if self.lo > T::ZERO {
            Intersection::Disjoint
        } else if self.ok || self.d == T::ZERO {
            Intersection::Intersecting
        } else {
            Intersection::Disjoint
        }
    }
}

/// Indices of the pairs of a chunk still open after a stage, with the answer they had (squared
/// distance and closest points, for the tight re-certification). Empty vectors until a pair is
/// open: a batch of a few pairs, as a mesh query's leaves make, would otherwise spend more on
/// clearing fixed buffers than on its kernels. At the first open pair a list takes room for a
/// whole chunk, kept for the rest of the batch ([`run`] clears and swaps two lists): grown by
/// doubling, and made anew per chunk, the lists of random pairs (three quarters open after the
/// quick stage) cost two threads about 30 % of their speed: glibc's allocator took 8 % of the
/// calling thread's time and the kernel's locks (futex and scheduler) 5 %, against 1.5 % in
/// all on one thread (`perf record` of `spin tri_tri random f32 avx2fma 2 32000 2`); `spin
/// tri_tri random f32 avx2fma 1 4000 2`: 24.0-25.4 M/s, now 35.3-35.7, against 17.9-19.0 on
/// one thread; 32000 pairs: 24.0-27.6, now 32.2-34.3.
///
/// The index lists outlive the batch: dropped, a list with room goes back to its thread's
/// spares ([`SPARE`]) and the next batch's first open pair takes it from there, so that a
/// thread answering many small batches (a split batch's pieces, a mesh query's leaf pairs)
/// does not allocate and free a list per batch: two threads on 4000 nearby Armadillo pairs
/// 160.3 -> 175.0 M/s (medians of 8 rounds alternated, faster in 6; `spin tri_tri arm_nearby
/// f32 avx2fma 1 4000 2`, 2026-11-29, the AMD EPYC, noisy).
pub(crate) struct Pending<T> {
    idx: Vec<u32>,
    ans: Vec<[T; 7]>,
}

thread_local! {
    /// Index lists of dropped [`Pending`]s, each with room for a chunk, for this thread's next
    /// batches (at most [`SPARES`]).
    static SPARE: std::cell::RefCell<Vec<Vec<u32>>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// How many index lists a thread keeps for its next batches: the two of [`run`].
const SPARES: usize = 2;

impl<T> Drop for Pending<T> {
    fn drop(&mut self) {
        let mut idx = std::mem::take(&mut self.idx);
        if idx.capacity() >= CHUNK {
            idx.clear();
            // (at thread exit the spares may be gone: the list is then freed)
            let _ = SPARE.try_with(|s| {
                if let Ok(mut s) = s.try_borrow_mut() {
                    if s.len() < SPARES {
                        s.push(idx);
                    }
                }
            });
        }
    }
}

impl<T: Real> Pending<T> {
    fn new() -> Self {
        Pending { idx: Vec::new(), ans: Vec::new() }
    }
    fn len(&self) -> usize {
        self.idx.len()
    }
    fn is_empty(&self) -> bool {
        self.idx.is_empty()
    }
    fn clear(&mut self) {
        self.idx.clear();
        self.ans.clear();
    }
    /// An open pair whose answer the next step does not read (it recomputes the pair): the
    /// re-certification, the only reader of `ans`, runs only on pairs pushed with theirs.
    #[inline(always)]
    fn push(&mut self, i: usize) {
        if self.idx.capacity() == 0 {
            // room for a whole chunk at the first open pair: a spare list of this thread's
            // earlier batches, or one allocation per list and batch, not one per doubling
            self.idx = SPARE.try_with(|s| s.try_borrow_mut().ok()?.pop()).ok().flatten().unwrap_or_default();
            self.idx.reserve_exact(CHUNK);
        }
        self.idx.push(i as u32);
    }
    #[inline(always)]
    fn push_answer(&mut self, i: usize, l: &Lane<T>) {
        if self.ans.capacity() == 0 {
            self.ans.reserve_exact(CHUNK);
        }
        self.push(i);
        self.ans.push([l.d, l.p[0], l.p[1], l.p[2], l.q[0], l.q[1], l.q[2]]);
    }
    fn as_slice(&self) -> &[u32] {
        &self.idx
    }
}

/// One batch query. Crate-private plumbing.
pub struct Job<'a, T> {
    pub query: Query,
    pub a: Src<'a, T>,
    pub b: Src<'a, T>,
    pub n: usize,
    pub prm: Params<T>,
    pub sink: Sink<'a, T>,
    pub counts: PathCounts,
    /// Recompute uncertified f32 pairs in f64.
    pub widen: bool,
    /// Recompute uncertified pairs exactly (feature `exact`).
    pub exact: bool,
}

/// Runs `job` with lane type `L` and the kernel `K` of `job.query`. Instantiated once per
/// query, instruction set and precision, inside its `#[target_feature]` entry point.
#[inline(always)]
pub(crate) fn run<L: Lanes, K: Kernel>(kk: L::K, job: &mut Job<'_, L::S>) {
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
            <L::S as crate::real::sealed::Sealed>::recert_with(kk, job, &open, &mut still, K::SHARP);
            std::mem::swap(&mut open, &mut still);
        }
        if K::STAGES == 3 && !open.is_empty() {
            // out of line, in an entry point of its own ([`accurate`])
            debug_assert_eq!(job.query, Query::TriTri, "the accurate stage is triangle-triangle distance's");
            job.counts.compacted += open.len() as u64;
            still.clear();
            <L::S as crate::real::sealed::Sealed>::accurate_with(kk, job, &open, &mut still);
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
/// ([`crate::isa::Token::accurate_f32`]): an entry point of its own per instruction set and
/// precision (`crate::isa::rare_modules`), not inlined into the query's. Out of line, this
/// stage and [`recert`] halved the kernels crate's release build (ARCHITECTURE.md,
/// "Compile-time budget"); the headline workloads' speed did not move, since they reach these
/// paths once per chunk at most.
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
/// (ARCHITECTURE.md, "Where the kernels' time goes"). The bits are the gathered path's: the
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

impl<T> Sink<'_, T> {
    /// Are squared distances the only output asked for (no verdicts, points, intervals,
    /// iterations or acceptance)? Asked once per pass, not per group (seven tests).
    #[inline(always)]
    fn only_d(&self) -> bool {
        self.verdict.is_none()
            && self.cp.is_none()
            && self.p.is_none()
            && self.q.is_none()
            && self.iv.is_none()
            && self.iters.is_none()
            && self.ok.is_none()
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
/// [`crate::isa::Token::recert_f32`]: one entry point per instruction set and precision for
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

/// The steps after a kernel's own stages, for the pairs still open: the full pipeline of the
/// next query (brute force after PQP; triangle-triangle distance after the cheap tests of
/// within-margin and intersection), or recomputation in f64 (f32 input), then the exact oracle.
/// Out of line: rare, and one copy per precision and instruction set.
#[inline(never)]
fn escalate<T: Real, Tk: Token>(
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
fn rerun<T: Real, W: Real, Tk: Token>(
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
    W::run_with(tk, &mut sub);
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
        // Outward rounding of the interval when narrowing.
        let lo = {
            let l = cv(iv[m].lo);
            if l.to_f64() > iv[m].lo.to_f64() {
                l.step(false)
            } else {
                l
            }
        };
        let hi = {
            let h = cv(iv[m].hi);
            if h.to_f64() < iv[m].hi.to_f64() {
                h.step(true)
            } else {
                h
            }
        };
        let lane = post(
            job.query,
            job.prm.margin,
            Lane { d: cv(d[m]), p: cv3(p[m]), q: cv3(q[m]), lo: lo.max_f(T::ZERO), hi, ok: ok[m], it: 0 },
        );
        job.sink.put(i as usize, &lane);
        if !lane.ok {
            open.push(i as usize);
        }
    }
}

/// Query-specific post-processing of a full distance answer: within-margin keeps it only
/// when within the margin (`+inf` beyond).
fn post<T: Real>(query: Query, margin: T, mut lane: Lane<T>) -> Lane<T> {
    if query == Query::Within && lane.d > margin * margin {
        lane.d = T::INFINITY;
    }
    lane
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
        },
        counts: PathCounts::default(),
        widen: true,
        exact,
    };
    T::run_with(crate::isa::Portable, &mut job);
    Lane { d: d[0], p: p[0], q: q[0], lo: iv[0].lo, hi: iv[0].hi, ok: ok[0], it: it[0] }
}

/// Exact answers for the `open` pairs (feature `exact`).
#[cfg(feature = "exact")]
fn exact<T: Real>(job: &mut Job<'_, T>, open: &mut Pending<T>) {
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
fn exact<T: Real>(_: &mut Job<'_, T>, _: &mut Pending<T>) {}

/// `max` that keeps `self` for NaN.
trait MaxF {
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
