//! The per-pair certificate: a rigorous interval `[lo, hi]` that contains the exact distance
//! between two primitives (point, segment or triangle), computed in the working precision from
//! any claimed pair of closest points.
//!
//! * `hi`: the claimed points are re-expressed as parametric points of their primitives
//!   (clamped barycentric or segment parameters, so the *exact* points with those parameters
//!   lie on the primitives), their difference `W` is evaluated, and `hi = |W|` rounded up plus a
//!   bound on the rounding of that evaluation. Any pair of points on the primitives is at least
//!   as far apart as the exact distance, so `d* <= hi`.
//! * `lo`: the projection gap along `v = W`: every unit direction `v` separates the primitives
//!   by at most their distance, so `min_k v.b_k - max_k v.a_k` over the vertices (rounded down,
//!   minus a bound on the dot products' rounding), divided by `|v|` rounded up, is a lower
//!   bound (0 when it is not positive). When the claimed points are the closest pair, `v` is
//!   the separating direction and `lo` meets `hi` up to rounding.
//!
//! The width `hi - lo` bounds the error of the answer `|W|`, whatever algorithm produced the
//! claimed points: a missed candidate, a wrong contact decision or an ill-conditioned
//! construction shows up as a wide interval. The answer reported stays the algorithm's own,
//! clamped into the interval.
//!
//! Error analysis (running bounds, Higham ch. 3; `u` the unit roundoff, input prescaled):
//! every difference of input points (`a_1 - a_0`, `b_0 - a_0`, ...) is rounded once, so it is
//! within `u` of its magnitude, componentwise. The parameters are clamped so that the exact
//! points with those parameters lie on the primitives (a sum that reaches 1 is made exactly 1:
//! `1 - x` is exact for `x >= 1/2`). `W = r + m_1 f + m_2 g - l_1 e_1 - l_2 e_2` is evaluated by
//! four multiply-adds, each rounding once (twice unfused) a partial sum bounded componentwise by
//! `mu = |r| + m_1 |f| + m_2 |g| + l_1 |e_1| + l_2 |e_2|`; with the differences' own rounding,
//! `|W_c - W^_c| <= 10 u mu_c` (a margin over the 6 u of the analysis), so
//! `hi = |W^| (1 + 8u) + 10 u |mu|`. Each projection `v.d` of a vertex difference `d` is within `4 u sum_c |v_c| |d_c|`
//! of `v.(exact d)` (one rounding of `d`, three of the dot product); `lo` subtracts 6 u of those
//! sums for both sides from the gap and divides by `|v|` rounded up. Underflow: an operation
//! in the subnormal range errs absolutely by up to half the smallest subnormal, which no
//! relative term covers, so both bounds move outward by 16 such steps, and `|W|` is bounded by
//! `2 max_c |W_c|` where its squares may have underflowed (a pair one subnormal apart would
//! otherwise get `hi = 0`; found by the extensive run, `near_miss` case 29554). The tests check
//! `lo <= d* <= hi` against the exact oracle on every input family, and the `cert` fuzz target
//! on arbitrary pairs under every tolerance.

use crate::lanes::{Cx, Lanes, Mask, V3};

/// A certified interval of the distance (prescaled units).
#[derive(Clone, Copy)]
pub(crate) struct Cert<L> {
    pub lo: L,
    pub hi: L,
}

/// Running-bound factor of the witness evaluation, in units of `u mu`.
const C_HI: f64 = 10.0;
/// Running-bound factor of one projection, in units of `u sum |v_c| |d_c|`.
const C_LO: f64 = 6.0;

/// Parameters `(l1, l2)` of the point `w` (local to the primitive's first vertex) on the
/// primitive spanned by `e1` (and `e2` for a triangle) from its first vertex, clamped so that
/// the exact point with those parameters lies on the primitive. Triangles: barycentric
/// coordinates from triple products with the accurately rounded normal; degenerate triangles
/// (tiny normal) use their longest edge.
#[inline(always)]
fn params<L: Lanes, const K: usize>(w: V3<L>, e1: V3<L>, e2: V3<L>) -> (L, L) {
    let k = Cx::of(w.x);
    match K {
        1 => (k.zero(), k.zero()),
        2 => (w.dot(e1).safe_div(e1.norm2()).clamp01(), k.zero()),
        _ => {
            let n = e1.cross_accurate(e2);
            let nn = n.norm2();
            // Accurately rounded cross products: for a sliver, w and the edges are nearly
            // parallel, and a plain cross product's rounding, divided by the small |n|^2,
            // would move the recovered point by u |w| / sin(angle).
            let mut l1 = w.cross_accurate(e2).dot(n).safe_div(nn).clamp01();
            let mut l2 = e1.cross_accurate(w).dot(n).safe_div(nn).clamp01();
            // Degenerate: |n| below the rounding noise of the cross product.
            let tiny = e1.norm_inf().mul(e2.norm_inf()).mul(k.u()).mul(k.c(16.0));
            let deg = n.norm_inf().le(tiny);
            if deg.any() {
                // The longest of the three edges e1, e2, e2 - e1, as (l1, l2) parameters.
                let e3 = e2.sub(e1);
                let (n1, n2, n3) = (e1.norm2(), e2.norm2(), e3.norm2());
                let s1 = w.dot(e1).safe_div(n1).clamp01();
                let s2 = w.dot(e2).safe_div(n2).clamp01();
                let s3 = w.sub(e1).dot(e3).safe_div(n3).clamp01();
                let use1 = n1.ge(n2).and(n1.ge(n3));
                let use2 = n2.ge(n3).andnot(use1);
                let d1 = L::select(use1, s1, L::select(use2, k.zero(), k.one().sub(s3)));
                let d2 = L::select(use1, k.zero(), L::select(use2, s2, s3));
                l1 = L::select(deg, d1, l1);
                l2 = L::select(deg, d2, l2);
            }
            // l1 + l2 <= 1 exactly: when the rounded sum reaches 1, the larger one (then
            // at least 1/2) stays and the other becomes 1 - larger, which is exact.
            let full = l1.add(l2).ge(k.one());
            let first = l1.ge(l2);
            let l2f = L::select(first, k.one().sub(l1), l2);
            let l1f = L::select(first, l1, k.one().sub(l2));
            (L::select(full, l1f, l1), L::select(full, l2f, l2))
        }
    }
}

/// Where a witness point lies on its primitive, from its parameters: a vertex, the interior of
/// an edge (`edge`, direction `dir`) or the interior of the face (`face`). Parameters within
/// `64 u` of 0 count as 0.
#[inline(always)]
fn feature<L: Lanes, const K: usize>(l1: L, l2: L, e1: V3<L>, e2: V3<L>) -> (L::M, L::M, V3<L>) {
    let k = Cx::of(l1);
    let tau = k.u().mul(k.c(64.0));
    match K {
        1 => (k.no(), k.no(), k.v0()),
        2 => (l1.gt(tau).and(l1.lt(k.one().sub(tau))), k.no(), e1),
        _ => {
            let l0 = k.one().sub(l1).sub(l2);
            let (z0, z1, z2) = (l0.le(tau), l1.le(tau), l2.le(tau));
            let zeros = [z0, z1, z2];
            let face = z0.or(z1).or(z2).not();
            // exactly one zero: on the edge opposite that vertex
            let on0 = zeros[0].andnot(zeros[1]).andnot(zeros[2]);
            let on1 = zeros[1].andnot(zeros[0]).andnot(zeros[2]);
            let on2 = zeros[2].andnot(zeros[0]).andnot(zeros[1]);
            let dir = V3::select(on0, e2.sub(e1), V3::select(on1, e2, e1));
            (on0.or(on1).or(on2), face, dir)
        }
    }
}

/// The projection direction for `lo`: `w` made normal to the tangent spaces of the witness
/// features (the face normal for a face-interior point, the common normal of two edges, `w`
/// without its component along one edge), so that a witness slightly misplaced along its
/// feature does not tilt the direction and cost `lo` the feature's extent times the tilt. Any
/// direction gives a valid bound; this one makes it tight.
#[inline(always)]
fn direction<L: Lanes, const KA: usize, const KB: usize>(
    w: V3<L>,
    a: (L, L, V3<L>, V3<L>),
    b: (L, L, V3<L>, V3<L>),
) -> V3<L> {
    let (ea, fa, da) = feature::<L, KA>(a.0, a.1, a.2, a.3);
    let (eb, fb, db) = feature::<L, KB>(b.0, b.1, b.2, b.3);
    let k = Cx::of(w.x);
    let mut v = w;
    if KA == 3 || KB == 3 {
        let na = a.2.cross_accurate(a.3);
        let nb = b.2.cross_accurate(b.3);
        v = V3::select(fa, along(na, w), V3::select(fb, along(nb, w), v));
    }
    let both = ea.and(eb).andnot(fa.or(fb));
    if both.any() {
        let c = da.cross_accurate(db);
        // parallel edges: only one edge's direction to remove
        let par = c.norm_inf().le(da.norm_inf().mul(db.norm_inf()).mul(k.u()).mul(k.c(64.0)));
        v = V3::select(both, V3::select(par, without(w, da), along(c, w)), v);
    }
    let only_a = ea.andnot(eb).andnot(fa.or(fb));
    let only_b = eb.andnot(ea).andnot(fa.or(fb));
    V3::select(only_a, without(w, da), V3::select(only_b, without(w, db), v))
}

/// `n` or `-n`, whichever points the way `w` does.
#[inline(always)]
fn along<L: Lanes>(n: V3<L>, w: V3<L>) -> V3<L> {
    let k = Cx::of(w.x);
    n.scale(L::select(w.dot(n).lt(k.zero()), k.one().neg(), k.one()))
}

/// `v` without its component along `d`.
#[inline(always)]
fn without<L: Lanes>(v: V3<L>, d: V3<L>) -> V3<L> {
    v.sub(d.scale(v.dot(d).safe_div(d.norm2())))
}

/// Componentwise absolute value.
#[inline(always)]
fn vabs<L: Lanes>(v: V3<L>) -> V3<L> {
    V3::new(v.x.abs(), v.y.abs(), v.z.abs())
}

/// Certifies the claimed closest points `p` (on the first primitive, `KA` points of `s`) and
/// `q` (on the second, `KB` points of `t`). All prescaled.
#[inline(always)]
pub(crate) fn certify<L: Lanes, const KA: usize, const KB: usize>(
    s: &[V3<L>; 3],
    t: &[V3<L>; 3],
    p: V3<L>,
    q: V3<L>,
) -> Cert<L> {
    let k = Cx::of(p.x);
    let u = k.u();
    let o = s[0];
    let e1 = s[1].sub(o);
    let e2 = s[2].sub(o);
    let r = t[0].sub(o);
    let (f, g) = (t[1].sub(t[0]), t[2].sub(t[0]));
    let (l1, l2) = params::<L, KA>(p.sub(o), e1, e2);
    let (m1, m2) = params::<L, KB>(q.sub(t[0]), f, g);
    let w = r.add_scaled(f, m1).add_scaled(g, m2).add_scaled(e1, l1.neg()).add_scaled(e2, l2.neg());
    let mu = vabs(r)
        .add_scaled(vabs(f), m1)
        .add_scaled(vabs(g), m2)
        .add_scaled(vabs(e1), l1)
        .add_scaled(vabs(e2), l2);
    let up = k.one().add(u.mul(k.c(8.0)));
    let norm = norm_up(w, up);
    // Underflow: each operation in the subnormal range errs by up to half a subnormal step
    // absolutely, which no relative term covers; 16 steps cover the evaluation of W and mu.
    let tiny = k.splat(<L::S as crate::real::sealed::Sealed>::TINY).mul(k.c(16.0));
    let hi = norm.add(u.mul(k.c(C_HI)).mul(norm_up(mu, up))).add(tiny);
    // lo: projection gaps along w and along v (w made normal to the witness features: tight
    // when the witness is slightly misplaced along its features; w itself is the right one when
    // the features were misjudged, e.g. for degenerate primitives); the larger bound. Vertex
    // differences from a_0 (a_0 itself projects to 0).
    let v = direction::<L, KA, KB>(w, (l1, l2, e1, e2), (m1, m2, f, g));
    let d1 = t[1].sub(o);
    let d2 = t[2].sub(o);
    let lo = gap_lo::<L, KA, KB>(w, [e1, e2], [r, d1, d2], up).max(gap_lo::<L, KA, KB>(
        v,
        [e1, e2],
        [r, d1, d2],
        up,
    ));
    Cert { lo, hi }
}

/// `|w|` rounded up (`up` covers the relative rounding). Where `w.w` is below
/// `MIN_POSITIVE / u` its squares may have underflowed (a subnormal difference squares to 0),
/// so the bound is `2 max_c |w_c|` there (exact, and at least `sqrt(3) max_c |w_c| >= |w|`).
#[inline(always)]
fn norm_up<L: Lanes>(w: V3<L>, up: L) -> L {
    let k = Cx::of(w.x);
    let n2 = w.norm2();
    let small = n2.lt(k.splat(<L::S as crate::real::Real>::MIN_POSITIVE).div(k.u()));
    L::select(small, w.norm_inf().mul(k.c(2.0)), n2.sqrt().mul(up))
}

/// The lower bound from the projection gap along `v` of the local vertices (`sa`: the first
/// primitive's vertices after `a_0`, which is the origin; `tb`: the second's), with the running
/// error bound of the dot products.
#[inline(always)]
fn gap_lo<L: Lanes, const KA: usize, const KB: usize>(v: V3<L>, sa: [V3<L>; 2], tb: [V3<L>; 3], up: L) -> L {
    let v = v.unit_pow2();
    let k = Cx::of(v.x);
    let u = k.u();
    let av = vabs(v);
    let mut smax = k.zero();
    let mut sig_s = k.zero();
    for d in sa.iter().take(KA - 1) {
        smax = smax.max(v.dot(*d));
        sig_s = sig_s.max(av.dot(vabs(*d)));
    }
    let mut tmin = k.inf();
    let mut sig_t = k.zero();
    for d in tb.iter().take(KB) {
        tmin = tmin.min(v.dot(*d));
        sig_t = sig_t.max(av.dot(vabs(*d)));
    }
    let low = k.one().sub(u.mul(k.c(4.0)));
    let vnorm = v.norm2().sqrt().mul(up);
    // the dot products' subnormal rounding (half a step each, absolutely): 16 steps
    let tiny = k.splat(<L::S as crate::real::sealed::Sealed>::TINY).mul(k.c(16.0));
    let num = tmin.sub(smax).mul(low).sub(u.mul(k.c(C_LO)).mul(sig_s.add(sig_t)).mul(up)).sub(tiny);
    num.safe_div(vnorm).mul(low).max(k.zero())
}

/// `x - y` as an unevaluated sum `hi + lo`, exactly.
#[inline(always)]
pub(super) fn diff2<L: Lanes>(x: V3<L>, y: V3<L>) -> (V3<L>, V3<L>) {
    let (hx, lx) = x.x.two_sum(y.x.neg());
    let (hy, ly) = x.y.two_sum(y.y.neg());
    let (hz, lz) = x.z.two_sum(y.z.neg());
    (V3::new(hx, hy, hz), V3::new(lx, ly, lz))
}

/// `v . (dh + dl)` with a compensated dot product (Ogita, Rump & Oishi's Dot2): the error is
/// at most `u |result|` plus terms of order `u^2 |v| |d|`.
#[inline(always)]
pub(super) fn dot2<L: Lanes>(v: V3<L>, dh: V3<L>, dl: V3<L>) -> L {
    let (px, ex) = v.x.two_prod(dh.x);
    let (py, ey) = v.y.two_prod(dh.y);
    let (pz, ez) = v.z.two_prod(dh.z);
    let (s1, c1) = px.two_sum(py);
    let (s2, c2) = s1.two_sum(pz);
    s2.add(c1.add(c2).add(ex.add(ey).add(ez)).add(v.dot(dl)))
}

/// One component of `W = r + m1 f + m2 g - l1 e1 - l2 e2` from the differences' high parts
/// `h = [r, f, g, e1, e2]` and low parts `l`, parameters `c = [l1, l2, m1, m2]`: the products
/// and the sum by TwoProduct and TwoSum, their error terms added at the end. (A function, not a
/// closure: closures compile without the entry point's target features.)
#[inline(always)]
fn witness_comp<L: Lanes>(c: [L; 4], h: [L; 5], l: [L; 5]) -> L {
    let [l1, l2, m1, m2] = c;
    let (p1, q1) = m1.two_prod(h[1]);
    let (p2, q2) = m2.two_prod(h[2]);
    let (p3, q3) = l1.neg().two_prod(h[3]);
    let (p4, q4) = l2.neg().two_prod(h[4]);
    let (s1, c1) = h[0].two_sum(p1);
    let (s2, c2) = s1.two_sum(p2);
    let (s3, c3) = s2.two_sum(p3);
    let (s4, c4) = s3.two_sum(p4);
    let small = l[0].add(m1.mul(l[1])).add(m2.mul(l[2])).sub(l1.mul(l[3])).sub(l2.mul(l[4]));
    let errs = c1.add(c2).add(c3.add(c4)).add(q1.add(q2).add(q3.add(q4)));
    s4.add(errs.add(small))
}

/// The tight certificate of the claimed closest points (see the module docs): the witness
/// difference and the projection gaps evaluated with error-free transformations, directly on
/// the prescaled input (no local frame). Slack: about `12 u` relative to the distance, and an
/// absolute `2^12 u^2` (coordinates below 2) plus a few subnormals for the error terms'
/// underflow.
#[inline(always)]
pub(crate) fn certify_tight<L: Lanes, const KA: usize, const KB: usize>(
    s: &[V3<L>; 3],
    t: &[V3<L>; 3],
    p: V3<L>,
    q: V3<L>,
) -> Cert<L> {
    let k = Cx::of(p.x);
    let u = k.u();
    // |W^| from sqrt(fl(w.w)): 3u for the sum of squares, halved by the root, the root's own
    // rounding, and u for W^'s components: 4u. A quotient: 2u.
    let up = k.one().add(u.mul(k.c(4.0)));
    let low = k.one().sub(u.mul(k.c(2.0)));
    // absolute slack of the second-order terms and of underflowing error terms
    let tiny = k.splat(<L::S as crate::real::sealed::Sealed>::TINY);
    let abs = u.mul(u).mul(k.c(4096.0)).add(tiny.mul(k.c(64.0)));
    let o = s[0];
    let (e1h, e1l) = diff2(s[1], o);
    let (e2h, e2l) = diff2(s[2], o);
    let (rh, rl) = diff2(t[0], o);
    let (fh, fl) = diff2(t[1], t[0]);
    let (gh, gl) = diff2(t[2], t[0]);
    let (l1, l2) = params::<L, KA>(p.sub(o), e1h, e2h);
    let (m1, m2) = params::<L, KB>(q.sub(t[0]), fh, gh);
    let c = [l1, l2, m1, m2];
    let w = V3::new(
        witness_comp(c, [rh.x, fh.x, gh.x, e1h.x, e2h.x], [rl.x, fl.x, gl.x, e1l.x, e2l.x]),
        witness_comp(c, [rh.y, fh.y, gh.y, e1h.y, e2h.y], [rl.y, fl.y, gl.y, e1l.y, e2l.y]),
        witness_comp(c, [rh.z, fh.z, gh.z, e1h.z, e2h.z], [rl.z, fl.z, gl.z, e1l.z, e2l.z]),
    );
    let norm = w.norm2().sqrt().mul(up);
    let hi = norm.add(abs);
    // lo: the smallest projection of a difference b_l - a_k onto v (every pair of vertices),
    // v = w made normal to the witness features.
    // projection directions scaled to unit magnitude (their norms must not underflow)
    let v = direction::<L, KA, KB>(w, (l1, l2, e1h, e2h), (m1, m2, fh, gh)).unit_pow2();
    let wd = w.unit_pow2();
    let (wnorm, vnorm) = (wd.norm2().sqrt().mul(up), v.norm2().sqrt().mul(up));
    let (mut gw, mut gv) = (k.inf(), k.inf());
    for ka in 0..KA {
        for kb in 0..KB {
            let (dh, dl) = diff2(t[kb], s[ka]);
            gw = gw.min(dot2(wd, dh, dl));
            gv = gv.min(dot2(v, dh, dl));
        }
    }
    // each compensated projection is within 1.5 u of its magnitude (plus the absolute terms)
    let two = u.mul(k.c(1.5));
    let lw = gw.sub(gw.abs().mul(two)).sub(abs.mul(wnorm)).safe_div(wnorm);
    let lv = gv.sub(gv.abs().mul(two)).sub(abs.mul(vnorm)).safe_div(vnorm);
    let lo = lw.max(lv).mul(low).max(k.zero());
    Cert { lo, hi }
}
