//! Where a job's primitives come from (SoA columns, AoS slices, one broadcast primitive) and
//! how a stage pass loads or gathers them into lanes.

use crate::lanes::{GatherIx, Lanes, MAX_LANES, V3};
use crate::real::Real;
use crate::types::Point;

/// Where one side's primitives come from (K points each). Crate-private plumbing.
#[derive(Clone, Copy)]
pub(crate) enum Src<'a, T> {
    /// Padded SoA columns: coordinate `j` (0..3K) of primitive `i` is `data[j * cap + base + i]`.
    Soa { data: &'a [T], cap: usize, base: usize, k: usize },
    /// AoS: primitive `i` is `flat[i*3K .. (i+1)*3K]`.
    Aos { flat: &'a [T], k: usize },
    /// One primitive against every primitive of the other side.
    One { flat: &'a [T], k: usize },
}

impl<'a, T: Real> Src<'a, T> {
    /// A batch's SoA columns.
    pub(crate) fn of_batch<const K: usize>(b: &'a crate::Batch<T, K>) -> Src<'a, T> {
        let (data, cap) = b.columns();
        Src::Soa { data, cap, base: 0, k: K }
    }

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
    pub(super) fn run(self, k: usize, start: usize, n: usize) -> Run<'a, T> {
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
pub(super) struct Run<'a, T> {
    pub(super) src: Src<'a, T>,
    pub(super) cols: [&'a [T]; 9],
    pub(super) start: usize,
    /// The kernel's arity (a constant in the compiled code: see [`Src::run`]).
    pub(super) k: usize,
}

impl<T: Real> Run<'_, T> {
    /// [`Run::load`] with the arity (a kernel's constant) turned into a const parameter.
    #[inline(always)]
    pub(super) fn load_k<L: Lanes<S = T>>(&self, kk: L::K, i: usize, lanes: usize) -> [V3<L>; 3] {
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
    pub(super) fn load<L: Lanes<S = T>, const K: usize>(
        &self,
        kk: L::K,
        i: usize,
        lanes: usize,
    ) -> [V3<L>; 3] {
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
    pub(super) fn gather<L: Lanes<S = T>>(&self, k: usize, kk: L::K, idx: &[u32]) -> [V3<L>; 3] {
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
pub(super) fn to_points<L: Lanes>(c: &[L; 9], k: usize) -> [V3<L>; 3] {
    let v = |m: usize| V3::new(c[3 * m], c[3 * m + 1], c[3 * m + 2]);
    [v(0), if k > 1 { v(1) } else { v(0) }, if k > 2 { v(2) } else { v(0) }]
}
