//! A batch job and what it carries: the caller's outputs ([`Sink`]), one pair's answer
//! ([`Lane`]) and the lists of pairs still open after a stage ([`Pending`]).

use super::src::Src;
use crate::algo::Params;
use crate::query::Query;
use crate::real::Real;
use crate::types::{ClosestPoints, Intersection, Interval, PathCounts, Point};

/// Pairs per chunk: the most a stage ever gathers at once.
pub(crate) const CHUNK: usize = 256;

/// Caller-provided outputs (any subset), indexed by pair. Crate-private plumbing.
#[derive(Default)]
pub(crate) struct Sink<'a, T> {
    pub d: Option<&'a mut [T]>,
    /// Distances: the square root of `d` (the correctly rounded mode writes its own).
    pub dist: Option<&'a mut [T]>,
    pub verdict: Option<&'a mut [Intersection]>,
    pub cp: Option<&'a mut [ClosestPoints<T>]>,
    pub p: Option<&'a mut [Point<T>]>,
    pub q: Option<&'a mut [Point<T>]>,
    pub iv: Option<&'a mut [Interval<T>]>,
    pub iters: Option<&'a mut [u32]>,
    /// Accepted (certified within the tolerance) or not: the escalation steps read it back.
    pub ok: Option<&'a mut [bool]>,
}

pub(super) fn split<X>(s: Option<&mut [X]>, at: usize) -> (Option<&mut [X]>, Option<&mut [X]>) {
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
        let (e0, e1) = split(self.dist, at);
        let (v0, v1) = split(self.verdict, at);
        let (c0, c1) = split(self.cp, at);
        let (p0, p1) = split(self.p, at);
        let (q0, q1) = split(self.q, at);
        let (i0, i1) = split(self.iv, at);
        let (t0, t1) = split(self.iters, at);
        let (o0, o1) = split(self.ok, at);
        (
            Sink { d: d0, dist: e0, verdict: v0, cp: c0, p: p0, q: q0, iv: i0, iters: t0, ok: o0 },
            Sink { d: d1, dist: e1, verdict: v1, cp: c1, p: p1, q: q1, iv: i1, iters: t1, ok: o1 },
        )
    }

    #[inline(always)]
    pub(crate) fn put(&mut self, i: usize, o: &Lane<T>) {
        if let Some(s) = self.d.as_deref_mut() {
            s[i] = o.d;
        }
        if let Some(s) = self.dist.as_deref_mut() {
            s[i] = o.d.sqrt();
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
    pub(super) idx: Vec<u32>,
    pub(super) ans: Vec<[T; 7]>,
}

thread_local! {
    /// Index lists of dropped [`Pending`]s, each with room for a chunk, for this thread's next
    /// batches (at most [`SPARES`]).
    static SPARE: std::cell::RefCell<Vec<Vec<u32>>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// How many index lists a thread keeps for its next batches: the two of [`run`].
pub(super) const SPARES: usize = 2;

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
    pub(super) fn new() -> Self {
        Pending { idx: Vec::new(), ans: Vec::new() }
    }
    pub(super) fn len(&self) -> usize {
        self.idx.len()
    }
    pub(super) fn is_empty(&self) -> bool {
        self.idx.is_empty()
    }
    pub(super) fn clear(&mut self) {
        self.idx.clear();
        self.ans.clear();
    }
    /// An open pair whose answer the next step does not read (it recomputes the pair): the
    /// re-certification, the only reader of `ans`, runs only on pairs pushed with theirs.
    #[inline(always)]
    pub(super) fn push(&mut self, i: usize) {
        if self.idx.capacity() == 0 {
            // room for a whole chunk at the first open pair: a spare list of this thread's
            // earlier batches, or one allocation per list and batch, not one per doubling
            self.idx = SPARE.try_with(|s| s.try_borrow_mut().ok()?.pop()).ok().flatten().unwrap_or_default();
            self.idx.reserve_exact(CHUNK);
        }
        self.idx.push(i as u32);
    }
    #[inline(always)]
    pub(super) fn push_answer(&mut self, i: usize, l: &Lane<T>) {
        if self.ans.capacity() == 0 {
            self.ans.reserve_exact(CHUNK);
        }
        self.push(i);
        self.ans.push([l.d, l.p[0], l.p[1], l.p[2], l.q[0], l.q[1], l.q[2]]);
    }
    pub(super) fn as_slice(&self) -> &[u32] {
        &self.idx
    }
}

/// One batch query. Crate-private plumbing.
pub(crate) struct Job<'a, T> {
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

impl<T> Sink<'_, T> {
    /// Are squared distances the only output asked for (no distances, verdicts, points,
    /// intervals, iterations or acceptance)? Asked once per pass, not per group (eight tests).
    #[inline(always)]
    pub(super) fn only_d(&self) -> bool {
        self.dist.is_none()
            && self.verdict.is_none()
            && self.cp.is_none()
            && self.p.is_none()
            && self.q.is_none()
            && self.iv.is_none()
            && self.iters.is_none()
            && self.ok.is_none()
    }
}
