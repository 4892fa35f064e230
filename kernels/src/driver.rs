//! The batch driver: loads lanes from SoA columns, AoS slices or a broadcast primitive, runs one
//! query over them, and stores the lanes the caller asked for. The tail of a batch goes through
//! the same code: SoA columns are padded to a multiple of 8 lanes, AoS input is gathered into a
//! padded lane buffer.

use crate::algo::{self, Res, SelectExt};
use crate::lanes::{Lanes, Mask, V3};
use crate::real::Real;

/// Which query a job runs (crate-private plumbing of [`crate::Engine`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QueryKind {
    SegSeg,
    PointTri,
    TriTri,
    TriTriBrute,
    Intersect,
    Within,
    Penalty,
}

/// Where one side's primitives come from (K points each). Crate-private plumbing.
#[derive(Clone, Copy)]
pub enum Src<'a, T> {
    /// Padded SoA columns: coordinate `j` (0..3K) of primitive `i` is `data[j * cap + base + i]`.
    Soa { data: &'a [T], cap: usize, base: usize, k: usize },
    /// AoS: primitive `i` is `flat[i*3K .. (i+1)*3K]`.
    Aos { flat: &'a [T], len: usize, k: usize },
    /// One primitive against every primitive of the other side.
    One { flat: &'a [T], k: usize },
}

/// Caller-provided outputs. Crate-private plumbing.
pub enum DOut<'a, T> {
    Real(&'a mut [T]),
    Flag(&'a mut [Option<bool>]),
}

/// One batch query. Crate-private plumbing.
pub struct Job<'a, T> {
    pub query: QueryKind,
    pub a: Src<'a, T>,
    pub b: Src<'a, T>,
    pub n: usize,
    pub param: T,
    pub d: DOut<'a, T>,
    pub p: Option<&'a mut [[T; 3]]>,
    pub q: Option<&'a mut [[T; 3]]>,
    /// Penalty-method options and iteration counts (penalty query only).
    pub penalty: crate::PenaltyOptions<T>,
    pub iters: Option<&'a mut [u32]>,
}

impl<'a, T: Real> Src<'a, T> {
    /// The same source starting at primitive `start` (for splitting a batch across threads).
    pub(crate) fn from(self, start: usize) -> Src<'a, T> {
        match self {
            Src::Soa { data, cap, base, k } => Src::Soa { data, cap, base: base + start, k },
            Src::Aos { flat, len, k } => Src::Aos { flat: &flat[start * 3 * k..], len: len - start, k },
            one @ Src::One { .. } => one,
        }
    }
    #[inline(always)]
    fn k(&self) -> usize {
        match *self {
            Src::Soa { k, .. } | Src::Aos { k, .. } | Src::One { k, .. } => k,
        }
    }
    #[inline(always)]
    fn coord<L: Lanes<S = T>>(&self, i: usize, j: usize) -> L {
        match *self {
            Src::Soa { data, cap, base, .. } => L::load(&data[j * cap + base + i..]),
            Src::One { flat, .. } => L::splat(flat[j]),
            Src::Aos { flat, len, k } => {
                if L::N == 1 {
                    L::splat(flat[i * 3 * k + j])
                } else {
                    let mut buf = [T::ZERO; 8];
                    for (l, slot) in buf.iter_mut().enumerate().take(L::N) {
                        // Pad the tail with the last primitive (a valid, finite-if-input-is input).
                        let ii = (i + l).min(len - 1);
                        *slot = flat[ii * 3 * k + j];
                    }
                    L::load(&buf)
                }
            }
        }
    }
    #[inline(always)]
    fn load<L: Lanes<S = T>>(&self, i: usize) -> [V3<L>; 3] {
        let mut out = [V3::zero(); 3];
        for (v, slot) in out.iter_mut().enumerate().take(self.k()) {
            *slot = V3::new(self.coord(i, 3 * v), self.coord(i, 3 * v + 1), self.coord(i, 3 * v + 2));
        }
        out
    }
}

/// Segment-segment query on raw (unscaled) input.
#[inline(always)]
pub(crate) fn q_seg_seg<L: Lanes>(a: &[V3<L>; 3], b: &[V3<L>; 3]) -> Res<L> {
    let sc = algo::prescale([a[0], a[1], b[0], b[1]]);
    let [p1, q1, p2, q2] = sc.pts;
    algo::unscale(algo::seg_seg(p1, q1.sub(p1), p2, q2.sub(p2)), sc.p, sc.finite)
}

/// Point-triangle query on raw input (`a[0]` is the point).
#[inline(always)]
pub(crate) fn q_point_tri<L: Lanes>(a: &[V3<L>; 3], b: &[V3<L>; 3]) -> Res<L> {
    let sc = algo::prescale([a[0], b[0], b[1], b[2]]);
    let [x, t0, t1, t2] = sc.pts;
    algo::unscale(algo::point_triangle(x, t0, t1, t2), sc.p, sc.finite)
}

#[inline(always)]
fn scale_tris<L: Lanes>(a: &[V3<L>; 3], b: &[V3<L>; 3]) -> algo::Scaled<L, 6> {
    algo::prescale([a[0], a[1], a[2], b[0], b[1], b[2]])
}

#[inline(always)]
fn split<L: Lanes>(p: [V3<L>; 6]) -> ([V3<L>; 3], [V3<L>; 3]) {
    ([p[0], p[1], p[2]], [p[3], p[4], p[5]])
}

/// Triangle-triangle distance on raw input (PQP, or brute force when `BRUTE`).
#[inline(always)]
pub(crate) fn q_tri_tri<L: Lanes, const BRUTE: bool>(a: &[V3<L>; 3], b: &[V3<L>; 3]) -> Res<L> {
    let sc = scale_tris(a, b);
    let (s, t) = split(sc.pts);
    let r = if BRUTE { algo::tri_tri_brute(&s, &t) } else { algo::tri_tri_pqp(&s, &t) };
    algo::unscale(r, sc.p, sc.finite)
}

/// Intersection on raw input, encoded as a distance: 0 = overlap, 1 = disjoint, NaN = invalid.
#[inline(always)]
pub(crate) fn q_intersect<L: Lanes>(a: &[V3<L>; 3], b: &[V3<L>; 3]) -> Res<L> {
    let sc = scale_tris(a, b);
    let (s, t) = split(sc.pts);
    let hit = algo::intersect(&s, &t);
    let d = L::select(hit, L::zero(), L::one());
    let d = L::select(sc.finite, d, L::splat(L::S::NAN));
    Res { d, p: V3::zero(), q: V3::zero() }
}

/// Within-margin on raw input: the squared distance when it is at most `margin^2`, else +inf.
/// Pairs whose bounding boxes are farther apart than the margin skip the distance query.
#[inline(always)]
pub(crate) fn q_within<L: Lanes>(a: &[V3<L>; 3], b: &[V3<L>; 3], margin: L::S) -> Res<L> {
    let sc = scale_tris(a, b);
    let (s, t) = split(sc.pts);
    let m = L::splat(margin).div(sc.p);
    let m2 = m.mul(m);
    let inf = L::splat(L::S::INFINITY);
    // The box gap is a lower bound up to rounding; keep slack for
    // the margin (relative) and for the rounding of the full query near contact (absolute, in
    // prescaled units where S is about 1), so that no pair the full query puts within the
    // margin is skipped.
    let uu = L::splat(L::S::UNIT_ROUNDOFF);
    let slack = L::one().add(uu.mul(L::splat(L::S::from_f64(16.0))));
    let abs = uu.mul(L::splat(L::S::from_f64(64.0)));
    let gap2 = algo::aabb_gap2(&s, &t);
    // The verdict is the caller's: a squared distance that underflows to 0 in the caller's
    // units is within a margin of 0 (fuzzing found subnormal pairs skipped by the prescaled box
    // test that the full query puts at 0), so the box gap must also exceed the margin there.
    let margin2 = L::splat(margin).mul(L::splat(margin));
    let far = gap2.gt(m2.mul(slack).add(abs.mul(abs))).and(gap2.mul(sc.p.mul(sc.p)).gt(margin2));
    if far.all() {
        return algo::unscale(Res { d: inf, p: V3::zero(), q: V3::zero() }, sc.p, sc.finite);
    }
    let full = algo::unscale(algo::tri_tri_pqp(&s, &t), sc.p, sc.finite);
    let beyond = far.or(full.d.gt(margin2));
    L::select_res(beyond, Res { d: inf, p: full.p, q: full.q }, full)
}

#[inline(always)]
fn store_lanes<L: Lanes>(v: L, out: &mut [L::S], i: usize, n: usize) {
    if i + L::N <= n {
        v.store(&mut out[i..]);
    } else {
        let mut buf = [L::S::ZERO; 8];
        v.store(&mut buf);
        out[i..n].copy_from_slice(&buf[..n - i]);
    }
}

#[inline(always)]
fn store_points<L: Lanes>(v: V3<L>, out: &mut [[L::S; 3]], i: usize, n: usize) {
    let mut b = [[L::S::ZERO; 8]; 3];
    v.x.store(&mut b[0]);
    v.y.store(&mut b[1]);
    v.z.store(&mut b[2]);
    for l in 0..(n - i).min(L::N) {
        out[i + l] = [b[0][l], b[1][l], b[2][l]];
    }
}

/// One query on one group of lanes, selected by a constant (folded away in each instance, so
/// no function pointer or closure stands between the `#[target_feature]` entry point and the
/// intrinsics: everything inlines into the entry point).
#[inline(always)]
fn eval<L: Lanes, const Q: u8>(a: &[V3<L>; 3], b: &[V3<L>; 3], param: L::S) -> Res<L> {
    match Q {
        0 => q_seg_seg(a, b),
        1 => q_point_tri(a, b),
        2 => q_tri_tri::<L, false>(a, b),
        3 => q_tri_tri::<L, true>(a, b),
        4 => q_intersect(a, b),
        _ => q_within(a, b, param),
    }
}

/// Penalty method on raw input: result and iterations per lane.
#[inline(always)]
pub(crate) fn q_penalty<L: Lanes>(
    a: &[V3<L>; 3],
    b: &[V3<L>; 3],
    o: crate::PenaltyOptions<L::S>,
) -> (Res<L>, L) {
    let sc = scale_tris(a, b);
    let (s, t) = split(sc.pts);
    let params =
        algo::PenaltyParams { rho: o.rho, reg: o.reg, tol: o.tol, max_iter: o.max_iter, start: o.start };
    let (r, it) = algo::tri_tri_penalty(&s, &t, params);
    (algo::unscale(r, sc.p, sc.finite), it)
}

#[inline(always)]
fn run_q<L: Lanes, const Q: u8, const PTS: bool>(job: &mut Job<'_, L::S>) {
    let n = job.n;
    let param = job.param;
    let mut i = 0;
    while i < n {
        let a = job.a.load::<L>(i);
        let b = job.b.load::<L>(i);
        let r = if Q == 6 {
            let (r, it) = q_penalty(&a, &b, job.penalty);
            if let Some(out) = job.iters.as_deref_mut() {
                let mut buf = [L::S::ZERO; 8];
                it.store(&mut buf);
                for l in 0..(n - i).min(L::N) {
                    out[i + l] = buf[l].to_f64() as u32;
                }
            }
            r
        } else {
            eval::<L, Q>(&a, &b, param)
        };
        match &mut job.d {
            DOut::Real(out) => store_lanes(r.d, out, i, n),
            DOut::Flag(out) => {
                let mut buf = [L::S::ZERO; 8];
                r.d.store(&mut buf);
                for l in 0..(n - i).min(L::N) {
                    let d = buf[l];
                    out[i + l] = if d == L::S::ZERO {
                        Some(true)
                    } else if d == L::S::ONE {
                        Some(false)
                    } else {
                        None
                    };
                }
            }
        }
        if PTS {
            if let Some(p) = job.p.as_deref_mut() {
                store_points(r.p, p, i, n);
            }
            if let Some(q) = job.q.as_deref_mut() {
                store_points(r.q, q, i, n);
            }
        }
        i += L::N;
    }
}

/// Runs a job with lane type `L`. Instantiated once per ISA and precision.
#[inline(always)]
pub(crate) fn run<L: Lanes>(job: &mut Job<'_, L::S>) {
    let pts = job.p.is_some() || job.q.is_some();
    macro_rules! go {
        ($q:literal) => {
            if pts {
                run_q::<L, $q, true>(job)
            } else {
                run_q::<L, $q, false>(job)
            }
        };
    }
    match job.query {
        QueryKind::SegSeg => go!(0),
        QueryKind::PointTri => go!(1),
        QueryKind::TriTri => go!(2),
        QueryKind::TriTriBrute => go!(3),
        QueryKind::Intersect => run_q::<L, 4, false>(job),
        QueryKind::Within => go!(5),
        QueryKind::Penalty => go!(6),
    }
}
