//! Point-triangle closest point (Ericson, *Real-Time Collision Detection*, 5.1.5; the SIMD
//! port of Shellshear & Ytterlid, JCGT 2014): Voronoi regions written with masks, decided by
//! triple products of accurately rounded cross products; interior points projected along the
//! accurate normal; degenerate triangles handled as the segments they are.

use super::cert::{diff2, dot2};
use super::seg_seg::point_segment;
use super::{degenerate, finish, normal, scale_pair, Kernel, Out, Params, Res};
use crate::lanes::{Cx, Lanes, Mask, V3};
use crate::real::Real;

/// The point-triangle query (registry entry `point_tri`): the first side is a point.
pub(crate) struct PointTri;

impl Kernel for PointTri {
    const KA: usize = 1;
    const KB: usize = 3;
    #[inline(always)]
    fn stage<L: Lanes, const ST: u8>(a: &[V3<L>; 3], b: &[V3<L>; 3], prm: &Params<L::S>) -> Out<L> {
        let (sc, s, t) = scale_pair::<L, 1, 3>(a, b);
        let r = point_triangle(s[0], t[0], t[1], t[2]);
        finish::<L, 1, 3, false>(&sc, &s, &t, None, r, prm)
    }
}

/// Closest point on triangle (a, b, c) to `x` (Ericson 5.1.5, Voronoi regions written with
/// masks). Degenerate (collinear or point-like) triangles are handled as the segments they are.
/// Input must be prescaled. Returns `Res { p: x, q: closest point }`.
#[inline(always)]
pub(crate) fn point_triangle<L: Lanes>(x: V3<L>, a: V3<L>, b: V3<L>, cv: V3<L>) -> Res<L> {
    let ab = b.sub(a);
    let ac = cv.sub(a);
    let ap = x.sub(a);
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    let k = Cx::of(x.x);
    let z = k.zero();
    // Regions are tested in Ericson's order; the first match wins (`done` tracks it).
    let m_a = d1.le(z).and(d2.le(z));
    let mut q = a;
    let mut done = m_a;
    let bp = x.sub(b);
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    let m_b = d3.ge(z).and(d4.le(d3)).andnot(done);
    q = V3::select(m_b, b, q);
    done = done.or(m_b);
    // Ericson's region determinants va, vb, vc (= n . (b-x) x (c-x), ...) computed as triple
    // products with accurately rounded cross products: the dot-product form (d1*d4 - d3*d2)
    // misclassifies points inside thin triangles (found by fuzzing: a point on a sliver came
    // back 490 u S away).
    // n is scaled by a power of two to unit magnitude (exact; only signs and the direction are
    // used): triple products multiply four lengths and underflowed for a needle of aspect 1e22
    // in f32 (found by fuzzing: a point inside it came back 27000 u S away).
    // Each triple product takes one side as an edge, `(a - x) x (b - x) = (a - x) x (b - a)`:
    // the differences of `x` to two vertices of a short edge round to the same vector when `x`
    // is far from it, and their cross product to zero (found by fuzzing: f32, a needle 0.09
    // wide and 1e18 long, its short edge taken for the closest feature, E 21011).
    let tri_edges = [ab, cv.sub(b), a.sub(cv)];
    let n = normal(&tri_edges);
    let n = n.scale(n.norm_inf().max(k.splat(L::S::MIN_POSITIVE)).recip_exponent());
    let (xa, xb) = (a.sub(x), b.sub(x));
    let vc = n.dot(xa.cross_accurate(ab));
    let m_ab = vc.le(z).and(d1.ge(z)).and(d3.le(z)).andnot(done);
    if m_ab.any() {
        let v = d1.safe_div(d1.sub(d3));
        q = V3::select(m_ab, a.add_scaled(ab, v), q);
    }
    done = done.or(m_ab);
    let cp = x.sub(cv);
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    let m_c = d6.ge(z).and(d5.le(d6)).andnot(done);
    q = V3::select(m_c, cv, q);
    done = done.or(m_c);
    let vb = n.dot(xa.cross_accurate(tri_edges[2]));
    let m_ac = vb.le(z).and(d2.ge(z)).and(d6.le(z)).andnot(done);
    if m_ac.any() {
        let w = d2.safe_div(d2.sub(d6));
        q = V3::select(m_ac, a.add_scaled(ac, w), q);
    }
    done = done.or(m_ac);
    let va = n.dot(xb.cross_accurate(tri_edges[1]));
    let d43 = d4.sub(d3);
    let d56 = d5.sub(d6);
    let m_bc = va.le(z).and(d43.ge(z)).and(d56.ge(z)).andnot(done);
    if m_bc.any() {
        let w = d43.safe_div(d43.add(d56));
        q = V3::select(m_bc, b.add_scaled(cv.sub(b), w), q);
    }
    done = done.or(m_bc);
    if !done.all() {
        // Interior: project x onto the plane along an accurately rounded normal instead of
        // rebuilding it from barycentric coordinates, which are ill-conditioned for thin
        // triangles (a point on a sliver came back 150 u S away; found by fuzzing).
        // The offset `(x - a) . n` compensated (the certificate's exact difference and Dot2):
        // rounded as `ap . n`, its error grew with `|x - a|`, and the projection moved off the
        // plane by up to 7.7 u S where `x` was 1.9 S from the triangle (found by the CI's fuzz
        // smoke run: f32, S 2.8e-12, over the bound table's 7.5).
        let (dh, dl) = diff2(x, a);
        let h = dot2(n, dh, dl).div(n.norm2().max(k.splat(L::S::MIN_POSITIVE)));
        let proj = x.sub(n.scale(h));
        q = V3::select(done, q, proj);
    }
    let deg = degenerate(&tri_edges);
    if deg.any() {
        // A degenerate triangle is the union of its edges.
        let mut best = point_segment(x, a, ab);
        let mut bd = x.sub(best).norm2();
        for (o, d) in [(a, ac), (b, cv.sub(b))] {
            let cand = point_segment(x, o, d);
            let cd = x.sub(cand).norm2();
            let better = cd.lt(bd);
            best = V3::select(better, cand, best);
            bd = L::select(better, cd, bd);
        }
        q = V3::select(deg, best, q);
    }
    Res { d: x.sub(q).norm2(), p: x, q }
}
