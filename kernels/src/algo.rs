//! The algorithms, each written once over [`Lanes`] (scalar, SSE4.1, AVX, AVX2+FMA all
//! instantiate these same functions).
//!
//! Precision policy (see ARCHITECTURE.md):
//! - every query first scales its input by one power of two so that the largest absolute
//!   coordinate lies in [1, 2): the scaling is exact, so power-of-two scaling of the input scales
//!   the answer exactly, no intermediate (up to fourth powers of coordinates) can overflow or
//!   underflow, and every threshold below is relative to the pair's own magnitude;
//! - non-finite input gives NaN (checked up front, masked per lane);
//! - every division is guarded (`safe_div`), so degenerate segments and triangles give the
//!   distance of the point or segment they are instead of NaN;
//! - the triangle-triangle early exits are *certified*: an edge pair is accepted only when the
//!   plane through its closest points separates all six vertices, so nearly parallel edges
//!   (the PQP/FCL trap) cannot end the search with a wrong pair.

use crate::lanes::{Lanes, Mask, V3};
use crate::real::Real;

/// Squared distance and a pair of closest points (first on the first primitive).
#[derive(Clone, Copy)]
pub(crate) struct Res<L> {
    pub d: L,
    pub p: V3<L>,
    pub q: V3<L>,
}

#[inline(always)]
fn c<L: Lanes>(x: f64) -> L {
    L::splat(L::S::from_f64(x))
}

#[inline(always)]
fn u<L: Lanes>() -> L {
    L::splat(L::S::UNIT_ROUNDOFF)
}

#[inline(always)]
fn true_mask<L: Lanes>() -> L::M {
    L::zero().le(L::zero())
}

/// Input scaled by a power of two: `pts[k] = input[k] / p`.
pub(crate) struct Scaled<L: Lanes, const K: usize> {
    pub pts: [V3<L>; K],
    pub p: L,
    pub finite: L::M,
}

/// Scales all points by one power of two so that the largest absolute coordinate is in [1, 2)
/// (or below 1 for all-subnormal input). Exact except for coordinates that become subnormal,
/// which are then below 2^-126 (f32) of the largest one.
#[inline(always)]
pub(crate) fn prescale<L: Lanes, const K: usize>(pts: [V3<L>; K]) -> Scaled<L, K> {
    let big = L::splat(L::S::MAX);
    let mut m = L::splat(L::S::MIN_POSITIVE);
    let mut finite = true_mask::<L>();
    for v in &pts {
        for x in [v.x, v.y, v.z] {
            let a = x.abs();
            finite = finite.and(a.le(big));
            m = m.max(a);
        }
    }
    let p = m.exponent();
    let inv = L::one().div(p);
    let mut out = pts;
    for v in out.iter_mut() {
        *v = v.scale(inv);
    }
    if !finite.all() {
        // Keep NaN/inf out of the arithmetic (it would defeat the early exits); the lane's
        // result is replaced by NaN at the end.
        for v in out.iter_mut() {
            *v = V3::select(finite, *v, V3::zero());
        }
    }
    Scaled { pts: out, p, finite }
}

/// Undoes [`prescale`] on a result: squared distance times p^2, points times p; NaN for
/// non-finite input lanes. Overflow of the squared distance gives +inf (documented).
#[inline(always)]
pub(crate) fn unscale<L: Lanes>(r: Res<L>, p: L, finite: L::M) -> Res<L> {
    // d*p is exact while normal; when it is subnormal (p < 1, tiny d) its rounding error is
    // below 2^-150 and is then multiplied by p < 1 again, far below the final rounding. So the
    // result is the correctly rounded d*p^2 except in double-rounding ties.
    let d = r.d.mul(p).mul(p);
    let nan = L::splat(L::S::NAN);
    let nan3 = V3::new(nan, nan, nan);
    Res {
        d: L::select(finite, d, nan),
        p: V3::select(finite, r.p.scale(p), nan3),
        q: V3::select(finite, r.q.scale(p), nan3),
    }
}

/// Closest points of segments `p1 + s*d1` and `p2 + t*d2`, s, t in [0, 1]
/// (Ericson, Real-Time Collision Detection 5.1.9), with a relative parallelism test and
/// guarded divisions for zero-length segments. Input must be prescaled.
#[inline(always)]
pub(crate) fn seg_seg<L: Lanes>(p1: V3<L>, d1: V3<L>, p2: V3<L>, d2: V3<L>) -> Res<L> {
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
    let n = d1.cross_accurate(d2);
    let m = d2.cross_accurate(r);
    let s0 = n.dot(m).safe_div(n.norm2()).clamp01();
    let t = b.mul_add(s0, f).safe_div(e).clamp01();
    // Re-project s from the (clamped) t; equal to s0 when t was not clamped.
    let s = b.mul_add(t, cc.neg()).safe_div(a).clamp01();
    let p = p1.add_scaled(d1, s);
    let q = p2.add_scaled(d2, t);
    Res { d: p.sub(q).norm2(), p, q }
}

/// Closest point to `x` on segment `a + t*d`.
#[inline(always)]
fn point_segment<L: Lanes>(x: V3<L>, a: V3<L>, d: V3<L>) -> V3<L> {
    let t = x.sub(a).dot(d).safe_div(d.norm2()).clamp01();
    a.add_scaled(d, t)
}

/// The two edges of a triangle that meet opposite its longest edge (`e` = [`edges`]), in
/// counter-clockwise order: the best-conditioned pair for its normal. At a needle's tip both
/// edges are long and nearly parallel, and their own rounding swamps the cross product (fuzzing
/// found a point 15 u S beside a needle of tip angle 1e-16 reported touching it).
#[inline(always)]
fn normal_pair<L: Lanes>(e: &[V3<L>; 3]) -> (V3<L>, V3<L>) {
    let (l0, l1, l2) = (e[0].norm2(), e[1].norm2(), e[2].norm2());
    let long0 = l0.ge(l1).and(l0.ge(l2));
    let long1 = l1.ge(l2).andnot(long0);
    // e0 x e1 = e1 x e2 = e2 x e0 in exact arithmetic.
    let u = V3::select(long0, e[1], V3::select(long1, e[2], e[0]));
    let v = V3::select(long0, e[2], V3::select(long1, e[0], e[1]));
    (u, v)
}

/// The triangle's normal (unnormalised, orientation of `e0 x e1`), accurately rounded from the
/// best-conditioned edge pair.
#[inline(always)]
pub(crate) fn normal<L: Lanes>(e: &[V3<L>; 3]) -> V3<L> {
    let (u, v) = normal_pair(e);
    u.cross_accurate(v)
}

/// Is the triangle with edges `e` ([`edges`]) degenerate (its normal is below the rounding
/// noise of the cross product of its best-conditioned edge pair)? Relative test.
#[inline(always)]
pub(crate) fn degenerate<L: Lanes>(e: &[V3<L>; 3]) -> L::M {
    // Unsquared (max-)norms: squares of a needle's width underflow.
    let (a, b) = normal_pair(e);
    let n = a.cross(b);
    let tol = u::<L>().mul(c(16.0));
    n.norm_inf().le(a.norm_inf().mul(b.norm_inf()).mul(tol))
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
    let z = L::zero();
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
    let tri_edges = [ab, cv.sub(b), a.sub(cv)];
    let n = normal(&tri_edges);
    let n = n.scale(L::one().div(n.norm_inf().max(L::splat(L::S::MIN_POSITIVE)).exponent()));
    let (xa, xb, xc) = (a.sub(x), b.sub(x), cv.sub(x));
    let vc = n.dot(xa.cross_accurate(xb));
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
    let vb = n.dot(xc.cross_accurate(xa));
    let m_ac = vb.le(z).and(d2.ge(z)).and(d6.le(z)).andnot(done);
    if m_ac.any() {
        let w = d2.safe_div(d2.sub(d6));
        q = V3::select(m_ac, a.add_scaled(ac, w), q);
    }
    done = done.or(m_ac);
    let va = n.dot(xb.cross_accurate(xc));
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
        let h = ap.dot(n).div(n.norm2().max(L::splat(L::S::MIN_POSITIVE)));
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

/// Keeps the better (smaller squared distance) of two results per lane.
#[inline(always)]
fn keep_min<L: Lanes>(best: &mut Res<L>, cand: Res<L>) {
    let better = cand.d.lt(best.d);
    best.d = L::select(better, cand.d, best.d);
    best.p = V3::select(better, cand.p, best.p);
    best.q = V3::select(better, cand.q, best.q);
}

#[inline(always)]
fn swap<L: Lanes>(r: Res<L>) -> Res<L> {
    Res { d: r.d, p: r.q, q: r.p }
}

#[inline(always)]
fn edges<L: Lanes>(t: &[V3<L>; 3]) -> [V3<L>; 3] {
    [t[1].sub(t[0]), t[2].sub(t[1]), t[0].sub(t[2])]
}

/// Projection interval test on one axis: true where the axis separates the triangles.
#[inline(always)]
fn separated_on<L: Lanes>(ax: V3<L>, s: &[V3<L>; 3], t: &[V3<L>; 3]) -> L::M {
    let p0 = ax.dot(s[0]);
    let p1 = ax.dot(s[1]);
    let p2 = ax.dot(s[2]);
    let q0 = ax.dot(t[0]);
    let q1 = ax.dot(t[1]);
    let q2 = ax.dot(t[2]);
    let mx1 = p0.max(p1).max(p2);
    let mn1 = p0.min(p1).min(p2);
    let mx2 = q0.max(q1).max(q2);
    let mn2 = q0.min(q1).min(q2);
    mn1.gt(mx2).or(mn2.gt(mx1))
}

/// Triangle-triangle overlap by separating axes (PQP's TriContact: 2 face normals, 9 edge
/// cross products, 6 in-plane edge normals), with an early out once every lane is separated.
/// Touching counts as overlapping. When *both* triangles are degenerate the axes vanish, so those
/// lanes are decided by the edge-edge distance instead. Input must be prescaled.
#[inline(always)]
pub(crate) fn intersect<L: Lanes>(s_in: &[V3<L>; 3], t_in: &[V3<L>; 3]) -> L::M {
    // Work relative to s[0] (smaller magnitudes, as PQP does).
    let o = s_in[0];
    let s = [V3::zero(), s_in[1].sub(o), s_in[2].sub(o)];
    let t = [t_in[0].sub(o), t_in[1].sub(o), t_in[2].sub(o)];
    let e = edges(&s);
    let f = edges(&t);
    let n = normal(&e);
    let m = normal(&f);
    let mut sep = separated_on(n, &s, &t).or(separated_on(m, &s, &t));
    if sep.all() {
        return sep.not();
    }
    for ei in &e {
        for fj in &f {
            sep = sep.or(separated_on(ei.cross(*fj), &s, &t));
        }
        if sep.all() {
            return sep.not();
        }
    }
    for k in 0..3 {
        sep = sep.or(separated_on(e[k].cross(n), &s, &t));
        sep = sep.or(separated_on(f[k].cross(m), &s, &t));
    }
    let deg_s = degenerate(&e);
    let deg_t = degenerate(&f);
    if deg_s.or(deg_t).andnot(sep).any() {
        // A degenerate triangle has no in-plane edge normals of its own (n x e = 0): when it
        // lies in the other's plane, the separating line can be normal to its edges within the
        // other's plane, so add the cross-normal axes e x m and f x n.
        for k in 0..3 {
            sep = sep.or(separated_on(e[k].cross(m), &s, &t));
            sep = sep.or(separated_on(f[k].cross(n), &s, &t));
        }
    }
    let both_deg = deg_s.and(deg_t);
    if both_deg.andnot(sep).any() {
        // Two segments/points: they touch iff an edge pair is at distance zero.
        let mut dmin = L::splat(L::S::INFINITY);
        for i in 0..3 {
            for j in 0..3 {
                dmin = dmin.min(seg_seg(s[i], e[i], t[j], f[j]).d);
            }
        }
        // Touching within 4 u S (the input is prescaled: S is about 1).
        let tol = u::<L>().mul(c(4.0));
        sep = L::select_mask(both_deg, dmin.gt(tol.mul(tol)), sep);
    }
    sep.not()
}

/// Minimum over the 15 feature pairs (9 edge-edge, 6 vertex-face), the brute-force baseline of
/// Krestenitis & Koziara. Does not detect interpenetration.
#[inline(always)]
fn min15<L: Lanes>(s: &[V3<L>; 3], t: &[V3<L>; 3]) -> Res<L> {
    let e = edges(s);
    let f = edges(t);
    let mut best = seg_seg(s[0], e[0], t[0], f[0]);
    for i in 0..3 {
        for j in 0..3 {
            if i + j > 0 {
                keep_min(&mut best, seg_seg(s[i], e[i], t[j], f[j]));
            }
        }
    }
    vertex_faces(s, t, &mut best);
    best
}

#[inline(always)]
fn vertex_faces<L: Lanes>(s: &[V3<L>; 3], t: &[V3<L>; 3], best: &mut Res<L>) {
    for k in 0..3 {
        // point_triangle(x, ..) returns p = x: a vertex of s needs no swap, one of t does.
        keep_min(best, point_triangle(s[k], t[0], t[1], t[2]));
        keep_min(best, swap(point_triangle(t[k], s[0], s[1], s[2])));
    }
}

/// Candidates where an edge of `a` crosses the plane of `b` (see [`contact_points`]).
#[inline(always)]
fn pierce<L: Lanes>(a: &[V3<L>; 3], b: &[V3<L>; 3], flip: bool, best: &mut Res<L>) {
    let ea = edges(a);
    let n = normal(&edges(b));
    for k in 0..3 {
        let h0 = a[k].sub(b[0]).dot(n);
        let h1 = a[(k + 1) % 3].sub(b[0]).dot(n);
        // Parameter of the plane crossing, h0 / (h0 - h1), clamped to the edge; the sign is
        // moved to the numerator so the guarded division sees a non-negative divisor.
        let den = h0.sub(h1);
        let num = L::select(den.lt(L::zero()), h0.neg(), h0);
        let tpar = num.safe_div(den.abs()).clamp01();
        let x = a[k].add_scaled(ea[k], tpar);
        let r = point_triangle(x, b[0], b[1], b[2]);
        keep_min(best, if flip { swap(r) } else { r });
    }
}

/// For interpenetrating lanes: a point where an edge of one triangle pierces the other (or the
/// nearest feature pair when none is found numerically), so that both returned closest points
/// lie on their triangles. The distance reported is 0 regardless.
#[inline(always)]
fn contact_points<L: Lanes>(s: &[V3<L>; 3], t: &[V3<L>; 3], best: &mut Res<L>) {
    pierce(s, t, false, best);
    pierce(t, s, true, best);
}

/// Brute force: `intersect ? 0 : min15`, both computed for every lane.
#[inline(always)]
pub(crate) fn tri_tri_brute<L: Lanes>(s: &[V3<L>; 3], t: &[V3<L>; 3]) -> Res<L> {
    let mut best = min15(s, t);
    overlap(s, t, intersect(s, t), &mut best);
    best
}

/// For the `hit` lanes (overlapping triangles): squared distance 0 and a contact point pair.
#[inline(always)]
fn overlap<L: Lanes>(s: &[V3<L>; 3], t: &[V3<L>; 3], hit: L::M, best: &mut Res<L>) {
    if hit.any() {
        let mut cp = *best;
        contact_points(s, t, &mut cp);
        best.p = V3::select(hit, cp.p, best.p);
        best.q = V3::select(hit, cp.q, best.q);
        best.d = L::select(hit, L::zero(), best.d);
    }
}

/// One side of PQP's vertex-face case: if all of `t` lies strictly (beyond rounding) on one side
/// of `s`'s plane, the triangles are disjoint and the vertex of `t` nearest that plane is the
/// only vertex-face candidate. Returns (shown disjoint, candidate).
#[inline(always)]
fn plane_side<L: Lanes>(s: &[V3<L>; 3], t: &[V3<L>; 3]) -> (L::M, Res<L>) {
    let e0 = s[1].sub(s[0]);
    let e1 = s[2].sub(s[0]);
    let n = e0.cross(e1);
    let h = [t[0].sub(s[0]).dot(n), t[1].sub(s[0]).dot(n), t[2].sub(s[0]).dot(n)];
    let reach = t[0].sub(s[0]).norm_inf().max(t[1].sub(s[0]).norm_inf()).max(t[2].sub(s[0]).norm_inf());
    // Error of h: the cross product's own rounding (a few u*|e0||e1|) times the reach, plus
    // the dot product's. Relative to the data; large for slivers (then the fallback decides).
    let tol = u::<L>().mul(c(32.0)).mul(e0.norm1().mul(e1.norm1())).mul(reach);
    let z = L::zero();
    let ntol = z.sub(tol);
    let above = h[0].gt(tol).and(h[1].gt(tol)).and(h[2].gt(tol));
    let below = h[0].lt(ntol).and(h[1].lt(ntol)).and(h[2].lt(ntol));
    let side = above.or(below);
    let a = [h[0].abs(), h[1].abs(), h[2].abs()];
    let m01 = a[1].lt(a[0]);
    let v01 = V3::select(m01, t[1], t[0]);
    let a01 = L::select(m01, a[1], a[0]);
    let v = V3::select(a[2].lt(a01), t[2], v01);
    (side, point_triangle(v, s[0], s[1], s[2]))
}

/// Triangle-triangle distance after PQP's TriDist (Larsen et al.; seed 000 listing 13):
/// 9 edge pairs with an early exit, then the vertex-face case, then "shown disjoint ? edge
/// minimum : overlapping". Made robust: the early exit is certified against all six vertices,
/// the disjointness tests carry rounding margins, and lanes that stay undecided get the brute
/// force answer instead of PQP's unconditional 0. Input must be prescaled.
#[inline(always)]
pub(crate) fn tri_tri_pqp<L: Lanes>(s: &[V3<L>; 3], t: &[V3<L>; 3]) -> Res<L> {
    let e = edges(s);
    let f = edges(t);
    let inf = L::splat(L::S::INFINITY);
    let mut best = Res { d: inf, p: s[0], q: t[0] };
    let mut done = L::zero().lt(L::zero()); // false mask
    let mut disjoint = done;
    let z = L::zero();
    let tol_k = u::<L>().mul(c(64.0));
    'pairs: for i in 0..3 {
        for j in 0..3 {
            let r = seg_seg(s[i], e[i], t[j], f[j]);
            let v = r.q.sub(r.p);
            // Plane through the pair, normal v: S must lie on the near side, T on the far side.
            let sp = v.dot(r.p);
            let tq = v.dot(r.q);
            let mut max_s = v.dot(s[0]).sub(sp);
            let mut min_t = v.dot(t[0]).sub(tq);
            for k in 1..3 {
                max_s = max_s.max(v.dot(s[k]).sub(sp));
                min_t = min_t.min(v.dot(t[k]).sub(tq));
            }
            let cert = max_s.le(z).and(min_t.ge(z)).andnot(done);
            let better = r.d.lt(best.d).andnot(done).or(cert);
            best.d = L::select(better, r.d, best.d);
            best.p = V3::select(better, r.p, best.p);
            best.q = V3::select(better, r.q, best.q);
            done = done.or(cert);
            // Separated along v by more than the rounding of these dot products.
            let gap = r.d.sub(max_s).add(min_t);
            disjoint = disjoint.or(gap.gt(tol_k.mul(v.norm1())));
            if done.all() {
                break 'pairs;
            }
        }
    }
    if done.all() {
        return best;
    }
    let (side_s, cand_s) = plane_side(s, t);
    let (side_t, cand_t) = plane_side(t, s);
    disjoint = disjoint.or(side_s).or(side_t);
    // The nearest-to-plane vertex candidates are real point pairs, so they are kept whether or
    // not the side test was conclusive: with a rounding margin on that test, a pair whose
    // triangle lies on one side by less than the margin can still be shown disjoint by the edge
    // test, and PQP's "edge minimum" would then miss its vertex-face answer (found by fuzzing:
    // twice the distance for nearly parallel f32 triangles at 1e12).
    let mut vf = best;
    keep_min(&mut vf, swap(cand_s));
    keep_min(&mut vf, cand_t);
    let keep = done.not();
    best = L::select_res(keep, vf, best);
    // Lanes neither certified nor shown disjoint: decide overlap by separating axes. The edge
    // loop ran all nine pairs for them (no early break while a lane is open), so the
    // brute-force answer only lacks the six vertex-face candidates.
    let undecided = done.or(disjoint).not();
    if undecided.any() {
        let hit = intersect(s, t);
        let apart = undecided.andnot(hit);
        if apart.any() {
            let mut vf = best;
            vertex_faces(s, t, &mut vf);
            best = L::select_res(apart, vf, best);
        }
        overlap(s, t, undecided.and(hit), &mut best);
    }
    best
}

/// Lower bound on the distance of two triangles from their bounding boxes (squared).
#[inline(always)]
pub(crate) fn aabb_gap2<L: Lanes>(s: &[V3<L>; 3], t: &[V3<L>; 3]) -> L {
    gap2_axis([s[0].x, s[1].x, s[2].x], [t[0].x, t[1].x, t[2].x])
        .add(gap2_axis([s[0].y, s[1].y, s[2].y], [t[0].y, t[1].y, t[2].y]))
        .add(gap2_axis([s[0].z, s[1].z, s[2].z], [t[0].z, t[1].z, t[2].z]))
}

/// Squared gap between the intervals spanned by `a` and `b` (0 when they overlap).
#[inline(always)]
fn gap2_axis<L: Lanes>(a: [L; 3], b: [L; 3]) -> L {
    let lo_s = a[0].min(a[1]).min(a[2]);
    let hi_s = a[0].max(a[1]).max(a[2]);
    let lo_t = b[0].min(b[1]).min(b[2]);
    let hi_t = b[0].max(b[1]).max(b[2]);
    let gap = lo_t.sub(hi_s).max(lo_s.sub(hi_t)).max(L::zero());
    gap.mul(gap)
}

/// Helpers for selecting whole results and masks.
pub(crate) trait SelectExt: Lanes {
    #[inline(always)]
    fn select_res(m: Self::M, a: Res<Self>, b: Res<Self>) -> Res<Self> {
        Res { d: Self::select(m, a.d, b.d), p: V3::select(m, a.p, b.p), q: V3::select(m, a.q, b.q) }
    }
    #[inline(always)]
    fn select_mask(m: Self::M, a: Self::M, b: Self::M) -> Self::M {
        m.and(a).or(b.andnot(m))
    }
}
impl<L: Lanes> SelectExt for L {}

/// Options of the penalty method, already scaled to the prescaled input.
#[derive(Clone, Copy)]
pub(crate) struct PenaltyParams<S> {
    pub rho: S,
    pub reg: S,
    pub tol: S,
    pub max_iter: u32,
    pub start: [S; 4],
}

/// Krestenitis & Koziara's penalty method (seed 003, Algorithm 1): minimise
/// |x(a,b) - y(g,d)|^2 + rho * sum max(0, c_i)^2 over the barycentric parameters with a
/// regularised Newton step (Hessian + reg * I, no line search), every lane iterating
/// independently until its step, measured on the geometry, is below `tol` or `max_iter` is
/// reached. `rho` and `reg` are relative to the pair's own curvature (trace of the Hessian of
/// the distance term / 4), so the method behaves the same at every scale. Input must be
/// prescaled. Returns the result and the iterations each lane used.
#[inline(always)]
pub(crate) fn tri_tri_penalty<L: Lanes>(
    s: &[V3<L>; 3],
    t: &[V3<L>; 3],
    o: PenaltyParams<L::S>,
) -> (Res<L>, L) {
    let ba = s[1].sub(s[0]);
    let ca = s[2].sub(s[0]);
    let ed = t[1].sub(t[0]);
    let fd = t[2].sub(t[0]);
    let two = c::<L>(2.0);
    // Hessian of |x - y|^2 (symmetric 4x4), upper triangle.
    let h00 = two.mul(ba.norm2());
    let h01 = two.mul(ba.dot(ca));
    let h02 = two.mul(ba.dot(ed)).neg();
    let h03 = two.mul(ba.dot(fd)).neg();
    let h11 = two.mul(ca.norm2());
    let h12 = two.mul(ca.dot(ed)).neg();
    let h13 = two.mul(ca.dot(fd)).neg();
    let h22 = two.mul(ed.norm2());
    let h23 = two.mul(ed.dot(fd));
    let h33 = two.mul(fd.norm2());
    let scale = h00.add(h11).add(h22).add(h33).mul(c(0.25)).max(L::splat(L::S::MIN_POSITIVE));
    let rho = L::splat(o.rho).mul(scale);
    let reg = L::splat(o.reg).mul(scale);
    let tol2 = L::splat(o.tol).mul(L::splat(o.tol));
    let mut x = [L::splat(o.start[0]), L::splat(o.start[1]), L::splat(o.start[2]), L::splat(o.start[3])];
    let mut done = L::zero().lt(L::zero());
    let mut iters = L::zero();
    let z = L::zero();
    let one = L::one();
    for _ in 0..o.max_iter {
        let xp = s[0].add_scaled(ba, x[0]).add_scaled(ca, x[1]);
        let yp = t[0].add_scaled(ed, x[2]).add_scaled(fd, x[3]);
        let xy = xp.sub(yp);
        let mut g =
            [two.mul(xy.dot(ba)), two.mul(xy.dot(ca)), two.mul(xy.dot(ed)).neg(), two.mul(xy.dot(fd)).neg()];
        // constraints c_i <= 0: -a, -b, a+b-1, -g, -d, g+d-1; penalty on the violated ones
        let cs = [
            x[0].neg(),
            x[1].neg(),
            x[0].add(x[1]).sub(one),
            x[2].neg(),
            x[3].neg(),
            x[2].add(x[3]).sub(one),
        ];
        // (No closures or `array::map` here: they are compiled without the entry point's
        // target features and would call the intrinsics out of line.)
        let mut act = [z; 6];
        let mut pen = [z; 6];
        for k in 0..6 {
            act[k] = L::select(cs[k].ge(z), one, z);
            pen[k] = cs[k].max(z);
        }
        g[0] = g[0].add(rho.mul(pen[2].sub(pen[0])));
        g[1] = g[1].add(rho.mul(pen[2].sub(pen[1])));
        g[2] = g[2].add(rho.mul(pen[5].sub(pen[3])));
        g[3] = g[3].add(rho.mul(pen[5].sub(pen[4])));
        let m00 = h00.add(rho.mul(act[0].add(act[2]))).add(reg);
        let m01 = h01.add(rho.mul(act[2]));
        let m11 = h11.add(rho.mul(act[1].add(act[2]))).add(reg);
        let m22 = h22.add(rho.mul(act[3].add(act[5]))).add(reg);
        let m23 = h23.add(rho.mul(act[5]));
        let m33 = h33.add(rho.mul(act[4].add(act[5]))).add(reg);
        let dx = solve_spd4(
            [[m00, m01, h02, h03], [m01, m11, h12, h13], [h02, h12, m22, m23], [h03, h13, m23, m33]],
            g,
        );
        let step = ba.scale(dx[0]).add_scaled(ca, dx[1]);
        let stept = ed.scale(dx[2]).add_scaled(fd, dx[3]);
        let err2 = step.norm2().add(stept.norm2());
        let open = done.not();
        for k in 0..4 {
            x[k] = L::select(open, x[k].sub(dx[k]), x[k]);
        }
        iters = L::select(open, iters.add(one), iters);
        done = done.or(err2.lt(tol2));
        if done.all() {
            break;
        }
    }
    // The penalty solution lies outside the triangles by about 1/rho, and an iteration that
    // diverged may be anywhere: bring the parameters back into each triangle (clamp, then scale
    // onto a + b <= 1; NaN goes back to the start) so that the points are real points of the
    // triangles and the distance an upper bound. Not the exact projection: the gap to the true
    // distance is what the accuracy report measures.
    let (a0, b0) = feasible(x[0], x[1], L::splat(o.start[0]), L::splat(o.start[1]));
    let (g0, d0) = feasible(x[2], x[3], L::splat(o.start[2]), L::splat(o.start[3]));
    let p = s[0].add_scaled(ba, a0).add_scaled(ca, b0);
    let q = t[0].add_scaled(ed, g0).add_scaled(fd, d0);
    (Res { d: p.sub(q).norm2(), p, q }, iters)
}

/// Barycentric parameters brought into the triangle: NaN or infinite back to the start
/// `(u0, v0)`, clamp at 0, then scale onto `u + v <= 1`. (An iteration that diverged to
/// infinity made `inf / inf` here: NaN closest points for finite f32 input, found by the
/// extensive differential run on parallel faces.)
#[inline(always)]
fn feasible<L: Lanes>(u: L, v: L, u0: L, v0: L) -> (L, L) {
    let big = L::splat(L::S::MAX);
    let ok = u.abs().le(big).and(v.abs().le(big));
    let u = L::select(ok, u, u0).max(L::zero());
    let v = L::select(ok, v, v0).max(L::zero());
    let sum = u.add(v);
    let over = sum.gt(L::one());
    (L::select(over, u.safe_div(sum), u), L::select(over, v.safe_div(sum), v))
}

/// Solves a symmetric positive definite 4x4 system by Gaussian elimination without pivoting,
/// fused and unrolled (no allocation, four divisions).
#[inline(always)]
fn solve_spd4<L: Lanes>(mut m: [[L; 4]; 4], mut r: [L; 4]) -> [L; 4] {
    for k in 0..4 {
        let inv = L::one().safe_div(m[k][k]);
        for i in (k + 1)..4 {
            let f = m[i][k].mul(inv);
            for j in (k + 1)..4 {
                m[i][j] = m[i][j].sub(f.mul(m[k][j]));
            }
            r[i] = r[i].sub(f.mul(r[k]));
        }
    }
    let mut x = [L::zero(); 4];
    for k in (0..4).rev() {
        let mut acc = r[k];
        for j in (k + 1)..4 {
            acc = acc.sub(m[k][j].mul(x[j]));
        }
        x[k] = acc.safe_div(m[k][k]);
    }
    x
}
