//! Segment-segment closest points (Ericson, *Real-Time Collision Detection*, 5.1.9; the SIMD
//! port of Shellshear & Ytterlid, JCGT 2014), with the closest-point parameter from accurately
//! rounded cross products and guarded divisions for zero-length segments.

use super::{finish, scale_pair, Kernel, Out, Params, Res};
use crate::lanes::{Lanes, V3};

/// The segment-segment query (registry entry `seg_seg`).
pub(crate) struct SegSeg;

impl Kernel for SegSeg {
    const KA: usize = 2;
    const KB: usize = 2;
    #[inline(always)]
    fn stage<L: Lanes, const ST: u8>(a: &[V3<L>; 3], b: &[V3<L>; 3], prm: &Params<L::S>) -> Out<L> {
        let (sc, s, t) = scale_pair::<L, 2, 2>(a, b);
        // Solved from the nearest pair of endpoints (a segment reversed where its other end is
        // in that pair): the parameters' error is relative to their distance from those ends,
        // not absolute (about u, so u L on the points), where the closest points are near
        // them: fuzzing found shared and nearly shared endpoints answered 6.5 and 7.6 u S
        // apart from a's start. The triangle kernels' edge pairs keep [`seg_seg`]'s form:
        // their answers come from the face and edge stages together.
        let dd = |x: V3<L>, y: V3<L>| x.sub(y).norm2();
        let (d00, d01, d10, d11) = (dd(s[0], t[0]), dd(s[0], t[1]), dd(s[1], t[0]), dd(s[1], t[1]));
        // a's end first when it holds the nearest pair, then b's end for that end of a
        let fa = d10.min(d11).lt(d00.min(d01));
        let fb = L::select(fa, d11, d01).lt(L::select(fa, d10, d00));
        let (pa, qa) = (V3::select(fa, s[1], s[0]), V3::select(fa, s[0], s[1]));
        let (pb, qb) = (V3::select(fb, t[1], t[0]), V3::select(fb, t[0], t[1]));
        let (da, db) = (qa.sub(pa), qb.sub(pb));
        // Then each point is projected from the end of its segment nearer to it, b's from a's
        // first point, a's from b's point: the parameter's error is then relative to the
        // (small) offset from that end, and so is the rounding of the point's evaluation.
        // Solved from the nearest pair alone, a point at the far end of a long segment was off
        // by about u L (fuzzing: nearly coincident segments 3.6e-5 apart and 370 long, the
        // closest pair at the far ends, answered 8.3 u S off without FMA).
        let s0 = seg_seg_s0(pa, da, pb, db);
        let q = project_near(pa.add_scaled(da, s0), pb, qb, db);
        let p = project_near(q, pa, qa, da);
        let r = Res { d: p.sub(q).norm2(), p, q };
        finish::<L, 2, 2, false>(&sc, &s, &t, None, r, prm)
    }
}

/// Closest points of segments `p1 + s*d1` and `p2 + t*d2`, s, t in [0, 1], prescaled input.
#[inline(always)]
pub(crate) fn seg_seg<L: Lanes>(p1: V3<L>, d1: V3<L>, p2: V3<L>, d2: V3<L>) -> Res<L> {
    let (s, t) = seg_seg_params(p1, d1, p2, d2);
    let p = p1.add_scaled(d1, s);
    let q = p2.add_scaled(d2, t);
    Res { d: p.sub(q).norm2(), p, q }
}

/// The closest points' parameters `(s, t)` of segments `p1 + s*d1` and `p2 + t*d2`.
#[inline(always)]
pub(crate) fn seg_seg_params<L: Lanes>(p1: V3<L>, d1: V3<L>, p2: V3<L>, d2: V3<L>) -> (L, L) {
    let r = p1.sub(p2);
    let a = d1.norm2();
    let e = d2.norm2();
    let b = d1.dot(d2);
    let cc = d1.dot(r);
    let f = d2.dot(r);
    // Ericson's s0 = (b*f - c*e) / (a*e - b^2) loses about u/sin^2(angle) to cancellation, which
    // moves the distance by about u*L/sin(angle): E grows like 1/sin(angle) at every angle, and
    // without bound for nearly parallel segments (the PQP/FCL trap). Instead, by Lagrange's
    // identity, s0 = (n . (d2 x r)) / |n|^2 with n = d1 x d2, from cross products whose
    // components are rounded once (Kahan's algorithm with FMA, Dekker's products without):
    // the error drops to about u*L at every angle. Exactly parallel segments (n = 0) get
    // s0 = 0; the projections below then find the right pair.
    let s0 = seg_seg_s0(p1, d1, p2, d2);
    let t = b.mul_add(s0, f).safe_div(e).clamp01();
    // Re-project s from the (clamped) t; equal to s0 when t was not clamped.
    let s = b.mul_add(t, cc.neg()).safe_div(a).clamp01();
    (s, t)
}

/// The parameter `s0` on `p1 + s*d1` of the closest points of the two lines, clamped to
/// [0, 1] (see [`seg_seg_params`]).
#[inline(always)]
fn seg_seg_s0<L: Lanes>(p1: V3<L>, d1: V3<L>, p2: V3<L>, d2: V3<L>) -> L {
    let n = d1.cross_accurate(d2);
    let m = d2.cross_accurate(p1.sub(p2));
    n.dot(m).safe_div(n.norm2()).clamp01()
}

/// Closest point to `x` on the segment from `a` to `b` (`d = b - a`), projected from the end
/// of the segment nearer to `x`'s projection: the parameter then errs relatively to its
/// distance from that end, and the point's evaluation by rounding of that offset.
#[inline(always)]
fn project_near<L: Lanes>(x: V3<L>, a: V3<L>, b: V3<L>, d: V3<L>) -> V3<L> {
    let e = d.norm2();
    let t = x.sub(a).dot(d).safe_div(e).clamp01();
    // from b: `1 - t` measured from it, the point `b - t' d`
    let tb = b.sub(x).dot(d).safe_div(e).clamp01();
    let far = t.gt(crate::lanes::Cx::of(t).c(0.5));
    V3::select(far, b.add_scaled(d, tb.neg()), a.add_scaled(d, t))
}

/// Closest point to `x` on segment `a + t*d`.
#[inline(always)]
pub(crate) fn point_segment<L: Lanes>(x: V3<L>, a: V3<L>, d: V3<L>) -> V3<L> {
    let t = x.sub(a).dot(d).safe_div(d.norm2()).clamp01();
    a.add_scaled(d, t)
}
