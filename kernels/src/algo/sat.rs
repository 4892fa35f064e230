//! Separating axes: PQP's TriContact overlap test (Larsen et al.; the SIMD port of Shellshear &
//! Ytterlid, JCGT 2014), used by the accurate stages, and the certified fast stage of the
//! intersection query (every separating axis proven beyond rounding, every overlap proven by a
//! piercing witness; the rest goes to the full distance pipeline).

use super::seg_seg::seg_seg;
use super::{cert, degenerate, edges, normal, scale_pair, Kernel, Out, Params, SelectExt};
use crate::lanes::{Cx, Lanes, Mask, V3};

/// The intersection query (registry entry `intersect`).
pub(crate) struct Intersect;

impl Kernel for Intersect {
    const KA: usize = 3;
    const KB: usize = 3;
    const WIDEN: bool = false;
    const RECERT: bool = false;
    const NEXT: Option<crate::Query> = Some(crate::Query::TriTri);
    #[inline(always)]
    fn stage<L: Lanes, const ST: u8>(a: &[V3<L>; 3], b: &[V3<L>; 3], prm: &Params<L::S>) -> Out<L> {
        let (sc, s, t) = scale_pair::<L, 3, 3>(a, b);
        let k = Cx::of(s[0].x);
        // Local frame (o = s[0]); every local vertex is within u R of its exact value.
        let o = s[0];
        let ls = [k.v0(), s[1].sub(o), s[2].sub(o)];
        let lt = [t[0].sub(o), t[1].sub(o), t[2].sub(o)];
        let mut r2 = ls[1].norm2().max(ls[2].norm2());
        for x in &lt {
            r2 = r2.max(x.norm2());
        }
        let u = k.u();
        let r = r2.sqrt().mul(k.one().add(u.mul(k.c(8.0))));
        // An axis a separates beyond rounding when the projection gap exceeds the dot
        // products' rounding (3 u |a| R each side) and the input perturbation (2 u R |a|),
        // with |a| <= |a|_1: 9 u R |a|_1 (the subtraction's own rounding is in the 1 + 4u).
        let slack = u.mul(k.c(9.0)).mul(r);
        let e = edges(&ls);
        let f = edges(&lt);
        let n = e[0].cross(e[1]);
        let m = f[0].cross(f[1]);
        let mut sep = separated_by(n, &ls, &lt, slack).or(separated_by(m, &ls, &lt, slack));
        if !sep.all() {
            for ei in &e {
                for fj in &f {
                    sep = sep.or(separated_by(ei.cross(*fj), &ls, &lt, slack));
                }
            }
        }
        if !sep.all() {
            for kk in 0..3 {
                sep = sep.or(separated_by(e[kk].cross(n), &ls, &lt, slack));
                sep = sep.or(separated_by(f[kk].cross(m), &ls, &lt, slack));
            }
        }
        // Overlap witness for the rest: the edge crossing the other's plane deepest inside the
        // other triangle, certified as a contact point of both (hi within the tolerance).
        let mut hit = k.no();
        let mut hi = k.inf();
        let open = sep.not();
        if open.any() {
            // (local frame with ls[0] = 0: the certificate's own allowance covers its rounding)
            let (x, _) = deepest_crossing(&ls, &lt);
            let c = cert::certify::<L, 3, 3>(&ls, &lt, x, x);
            hi = c.hi;
            hit = super::accept(k.zero(), c.hi, &sc, prm).and(open);
        }
        // Verdict encoding for the driver: lo > 0 disjoint, lo = 0 with ok: intersecting.
        let lo = L::select(sep, k.one(), k.zero());
        let out = Out {
            d: L::select(sep, k.one(), k.zero()),
            p: k.v0(),
            q: k.v0(),
            lo,
            hi: L::select(sep, k.inf(), hi),
            ok: sep.or(hit),
            it: k.zero(),
        };
        super::nan_where_invalid(out, &sc)
    }
}

/// Does axis `a` separate the local triangles by more than `slack * |a|_1` (certainly)?
#[inline(always)]
fn separated_by<L: Lanes>(a: V3<L>, s: &[V3<L>; 3], t: &[V3<L>; 3], slack: L) -> L::M {
    let (p0, p1, p2) = (a.dot(s[0]), a.dot(s[1]), a.dot(s[2]));
    let (q0, q1, q2) = (a.dot(t[0]), a.dot(t[1]), a.dot(t[2]));
    let mx1 = p0.max(p1).max(p2);
    let mn1 = p0.min(p1).min(p2);
    let mx2 = q0.max(q1).max(q2);
    let mn2 = q0.min(q1).min(q2);
    let k = Cx::of(slack);
    let low = k.one().sub(k.u().mul(k.c(4.0)));
    let need = slack.mul(a.norm1());
    mn1.sub(mx2).mul(low).gt(need).or(mn2.sub(mx1).mul(low).gt(need))
}

/// The point where an edge of one triangle crosses the other's plane that lies deepest inside
/// that other triangle, over the six edges, and its depth (the smallest barycentric weight,
/// negative outside, -inf when no edge crosses; the certificate judges the point anyway).
#[inline(always)]
pub(crate) fn deepest_crossing<L: Lanes>(s: &[V3<L>; 3], t: &[V3<L>; 3]) -> (V3<L>, L) {
    let k = Cx::of(s[0].x);
    let mut best = s[0];
    let mut depth = k.splat(-<L::S as crate::real::Real>::INFINITY);
    for (a, b) in [(s, t), (t, s)] {
        let n = b[1].sub(b[0]).cross(b[2].sub(b[0]));
        let nn = n.norm2();
        let h = [a[0].sub(b[0]).dot(n), a[1].sub(b[0]).dot(n), a[2].sub(b[0]).dot(n)];
        for kk in 0..3 {
            let (h0, h1) = (h[kk], h[(kk + 1) % 3]);
            let den = h0.sub(h1);
            let num = L::select(den.lt(k.zero()), h0.neg(), h0);
            let tpar = num.safe_div(den.abs()).clamp01();
            let x = a[kk].add_scaled(a[(kk + 1) % 3].sub(a[kk]), tpar);
            // barycentric weights of x in b (times |n|^2)
            let mut w = k.inf();
            for m in 0..3 {
                let ed = b[(m + 1) % 3].sub(b[m]);
                w = w.min(ed.cross(x.sub(b[m])).dot(n));
            }
            let crosses = h0.mul(h1).le(k.zero());
            let d = L::select(crosses, w.safe_div(nn), depth);
            let better = d.gt(depth);
            best = V3::select(better, x, best);
            depth = L::select(better, d, depth);
        }
    }
    (best, depth)
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
pub(crate) fn overlaps<L: Lanes>(s_in: &[V3<L>; 3], t_in: &[V3<L>; 3]) -> L::M {
    // Work relative to s[0] (smaller magnitudes, as PQP does).
    let o = s_in[0];
    let k = Cx::of(o.x);
    let s = [k.v0(), s_in[1].sub(o), s_in[2].sub(o)];
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
        let mut dmin = k.inf();
        for i in 0..3 {
            for j in 0..3 {
                dmin = dmin.min(seg_seg(s[i], e[i], t[j], f[j]).d);
            }
        }
        // Touching within 4 u S (the input is prescaled: S is about 1).
        let tol = k.u().mul(k.c(4.0));
        sep = L::select_mask(both_deg, dmin.gt(tol.mul(tol)), sep);
    }
    sep.not()
}
