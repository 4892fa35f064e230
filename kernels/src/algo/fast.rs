//! The fast stage of triangle-triangle distance: every lane runs the same straight-line code,
//! with no early exit, no per-candidate certification and no parameter recovery. In a local
//! frame (`o = a_0`, so far from the origin the arithmetic is as accurate as near it):
//!
//! * the nine edge pairs (Ericson 5.1.9, the closest-point parameter from the pair's dot
//!   products, or from plain cross products where the edges are nearly parallel; edge norms
//!   and reciprocals shared; the certificate sees what rounding costs);
//! * the six vertex-face candidates whose projection falls inside the face, as parametric
//!   points (barycentric weights from the same inside tests);
//! * where the triangles straddle each other's planes, the edge crossing deepest inside the
//!   other triangle as a contact candidate (distance 0), interpolating the same inside tests.
//!
//! Every candidate is a pair of points with parameters in [0, 1] on exact local vertices, so
//! one static error bound covers them all, and each carries the direction its optimality is
//! certified along (the common normal of two edges, a face normal, or the witness). The
//! certificate ([`FastOut`]) is computed once, at the end: `hi = |W| + 24 u R`,
//! `lo = gap along v - 8 u R` (`R` the largest local vertex norm; see the constants and
//! [`lower`]; `v` need not be unit, so the quick stage projects on `W` itself).
//! Pairs whose interval is within the tolerance are done; the others are re-certified tightly
//! and, if need be, recomputed by the accurate stage ([`super::pqp`]).
//!
//! In front of it runs the quick stage ([`tri_tri_quick`], stage 0 of the `tri_tri` query):
//! one of the nine edge pairs per lane, the two triangles' "front" edges along the direction
//! between their centroids, with the same arithmetic and certificate, accepted only when the
//! candidate is the closest pair as far as the arithmetic can tell. On nearby triangles of a
//! mesh it answers nearly every pair (99.2 % of the Armadillo's nearby pairs) with 139.5
//! instructions per pair where this stage alone took 350.7 (callgrind with
//! `--toggle-collect='*TriTri::run*'` on `spin tri_tri arm_nearby f32 avx2fma 0.5`, at
//! eaee2b6 and its parent); the pairs it leaves open (three
//! quarters of random unit-cube pairs: a quarter intersect, and the front edges are not the
//! closest pair of half the others) are gathered into full vectors and answered here (random
//! pairs: 486.0 instructions per pair instead of 365.4).

use super::{normal_pair, Res, SHARP_E};
use crate::lanes::{Cx, Lanes, Mask, V3};
use crate::real::Real;

/// The fast stage's answer (local frame) and its certified interval.
pub(crate) struct FastOut<L: Lanes> {
    pub r: Res<L>,
    pub lo: L,
    pub hi: L,
    /// Is the answer sharp: the closest pair as far as the arithmetic can tell (see
    /// [`tri_tri_quick`] and [`certified`])?
    pub sharp: L::M,
    /// The candidate's code ([`Best`]'s; 0 from the quick stage): 15-20 name the edge of a
    /// contact candidate, which [`prove_crossing`] tests.
    pub code: L,
}

/// Static rounding bound of any candidate's witness difference, in units of `u R`: an edge
/// pair `W = -r + t f - s e` rounds `r`, `f`, `e` once each and two multiply-adds (three
/// unfused), each partial sum at most `|r| + |f| + |e| <= 6R`: at most `20 u R`; vertex-face
/// and contact witnesses have fewer or smaller terms; plus `2 u R` for the local frame's own
/// rounding. Rounded up.
const C_HI: f64 = 24.0;
/// Static rounding bound of the projection gap, in units of `u R |v|`: two dot products of at
/// most `3 u |v| R` each, plus the local frame's `2 u R` (to first order: [`lower`] takes it
/// times `1 + 4u`, which covers the terms of order `u^2` and its own rounding).
const C_LO: f64 = 8.0;

/// How far barycentric parameters `l1, l2 >= 0` overshoot the face (`l1 + l2 - 1`, or 0): the
/// point with those parameters lies within that times the face's edge lengths (at most 2R),
/// added to the certificate's `hi`. (For candidates inside the face it is a few rounding
/// errors; the exact clamping of [`super::cert`] would cost more than it saves here.)
#[inline(always)]
fn overshoot<L: Lanes>(l1: L, l2: L) -> L {
    let k = Cx::of(l1);
    l1.add(l2).sub(k.one()).max(k.zero())
}

/// The best candidate so far, kept small (the vector registers are few): its squared
/// distance, up to three parameters and a code naming the candidate (0-8 edge pair 3i+j, 9-11
/// vertex of t over the face of s, 12-14 vertex of s over the face of t, 15-17 an edge of t
/// crossing s, 18-20 an edge of s crossing t). The points and the certification direction are
/// rebuilt from these once, at the end.
struct Best<L> {
    d: L,
    a: L,
    b: L,
    c: L,
    code: L,
}

impl<L: Lanes> Best<L> {
    #[inline(always)]
    fn keep(&mut self, d: L, a: L, b: L, code: L) {
        let better = d.lt(self.d);
        self.d = d.min(self.d);
        self.a = L::select(better, a, self.a);
        self.b = L::select(better, b, self.b);
        self.code = L::select(better, code, self.code);
    }
}

/// `x[i]` for a lane index `i` in {0, 1, 2} given as masks `i == 1`, `i == 2`.
#[inline(always)]
fn pick<L: Lanes>(is1: L::M, is2: L::M, x: &[V3<L>; 3]) -> V3<L> {
    V3::select(is2, x[2], V3::select(is1, x[1], x[0]))
}

/// Is `x` strictly inside (0, 1) by more than rounding?
#[inline(always)]
fn interior<L: Lanes>(x: L) -> L::M {
    let k = Cx::of(x);
    let eps = k.u().mul(k.c(64.0));
    x.gt(eps).and(x.lt(k.one().sub(eps)))
}

/// The fast candidate and its certificate for local triangles `s` (with `s[0] = 0`) and `t`.
#[inline(always)]
pub(crate) fn tri_tri_fast<L: Lanes>(s: &[V3<L>; 3], t: &[V3<L>; 3]) -> FastOut<L> {
    let k = Cx::of(t[0].x);
    let z = k.zero();
    let one = k.one();
    let tiny = k.splat(L::S::MIN_POSITIVE);
    let e = [s[1], s[2].sub(s[1]), s[2].neg()];
    let f = [t[1].sub(t[0]), t[2].sub(t[1]), t[0].sub(t[2])];
    let ee = [e[0].norm2(), e[1].norm2(), e[2].norm2()];
    let ff = [f[0].norm2(), f[1].norm2(), f[2].norm2()];
    let iea = [one.div(ee[0].max(tiny)), one.div(ee[1].max(tiny)), one.div(ee[2].max(tiny))];
    let ifb = [one.div(ff[0].max(tiny)), one.div(ff[1].max(tiny)), one.div(ff[2].max(tiny))];
    let mut best = Best { d: k.inf(), a: z, b: z, c: z, code: z };
    for i in 0..3 {
        for j in 0..3 {
            // Ericson 5.1.9 with d = b_j - a_i and the lines' closest-point parameter from the
            // dot products the pair needs anyway, (e.d |f|^2 - e.f f.d) / (|e|^2 |f|^2 -
            // (e.f)^2), except where the edges are within about 7 degrees of parallel: there
            // by Lagrange's identity, s0 = n . (d x f) / |n|^2 with n = e x f, from plain
            // cross products ([`edge_pair`]). Rounding moves the candidate along the edges
            // only (the points stay on them and the certificate stays rigorous); for nearly
            // parallel edges that can widen the interval, and such pairs are re-certified or
            // go on to the accurate stage ([`super::seg_seg`]'s accurately rounded cross
            // products). The dot-product form everywhere sent 12.5 % (f32) and 7.9 % (f64) of
            // the near-parallel family's pairs to the accurate stage, the cross products none,
            // and so does the mix (`spin tri_tri near_parallel <prec> avx2fma 0.2 4000 1
            // sqdist full`, the path counts); the mix saves 16 operations per edge pair
            // elsewhere (docs/notes/kernel-speed.md, "The lines' parameter from dot products").
            let (d2, ss, tt) = edge_pair(s[i], e[i], iea[i], t[j], f[j], ifb[j], Some((ee[i], ff[j])));
            best.keep(d2, ss, tt, k.c((3 * i + j) as f64));
        }
    }
    // Vertex-face: accurate normals from the best-conditioned edge pairs, inside tests
    // g_m . (x - a_m) >= 0 with g_m = n x e_m (their values are barycentric weights times |n|^2).
    let (na, ok_a, inn_a, thin_a) = face(&e);
    let (nb, ok_b, inn_b, thin_b) = face(&f);
    // heights over the other's plane (times |n|) and inside values, per vertex:
    // g_m . (x - a_m) = g_m . x - g_m . a_m
    let mut h_b = [z; 3];
    let mut h_a = [z; 3];
    let mut wa = [[z; 3]; 3]; // wa[k][m]: vertex k of t against edge m of s
    let mut wb = [[z; 3]; 3]; // wb[k][m]: vertex k of s against edge m of t
    let hb0 = nb.dot(t[0]);
    for m in 0..3 {
        let ga = na.cross(e[m]);
        let gb = nb.cross(f[m]);
        let (ca, cb) = (ga.dot(s[m]), gb.dot(t[m]));
        for kk in 0..3 {
            wa[kk][m] = ga.dot(t[kk]).sub(ca);
            wb[kk][m] = gb.dot(s[kk]).sub(cb);
        }
    }
    for kk in 0..3 {
        h_b[kk] = na.dot(t[kk]);
        h_a[kk] = nb.dot(s[kk]).sub(hb0);
        let (d2, l1, l2) = over_s(s, &wa[kk], ok_a, inn_a, t[kk]);
        best.keep(d2, l1, l2, k.c((9 + kk) as f64));
        let (d2, m1, m2) = over_t(t, &f, &wb[kk], ok_b, inn_b, s[kk]);
        best.keep(d2, m1, m2, k.c((12 + kk) as f64));
    }
    // Contact: only where each triangle has vertices on both sides of (or on) the other's
    // plane; the crossing of an edge deepest inside the other triangle, interpolating the
    // inside values along the edge.
    let maybe = straddles(&h_b).and(straddles(&h_a)).and(ok_a).and(ok_b);
    if maybe.any() {
        let none = k.splat(-L::S::INFINITY);
        let (mut depth, mut ca, mut cb, mut cc, mut code) = (none, z, z, z, z);
        for kk in 0..3 {
            let k1 = (kk + 1) % 3;
            for (h, w, inn, base) in [(&h_b, &wa, inn_a, 15), (&h_a, &wb, inn_b, 18)] {
                // edge kk of one triangle through the other's plane
                let tau = crossing(h[kk], h[k1]);
                let wm = lerp3(w[kk], w[k1], tau);
                let dep = wm[0].min(wm[1]).min(wm[2]).mul(inn);
                let dep = L::select(h[kk].mul(h[k1]).le(z), dep, none);
                let better = dep.gt(depth);
                depth = L::select(better, dep, depth);
                ca = L::select(better, wm[2].mul(inn).max(z), ca);
                cb = L::select(better, wm[0].mul(inn).max(z), cb);
                cc = L::select(better, tau, cc);
                code = L::select(better, k.c((base + kk) as f64), code);
            }
        }
        let hit = maybe.and(depth.ge(z));
        best.d = L::select(hit, z, best.d);
        best.a = L::select(hit, ca, best.a);
        best.b = L::select(hit, cb, best.b);
        best.c = L::select(hit, cc, best.c);
        best.code = L::select(hit, code, best.code);
    }
    let out = certified(s, t, &e, &f, (na, nb), &best, (inn_a, inn_b), (thin_a, thin_b));
    at_shared_vertex(s, t, out)
}

/// A vertex the triangles share answered exactly: distance 0 at that vertex (the first of the
/// nine vertex pairs that match, in the order of `s`'s vertices), as the quick stage answers
/// a vertex shared by its front edges. The contact candidate answers such pairs 0 too, but
/// with a crossing point and its projection on the other plane, which came 1.4 `u S` apart
/// on mesh neighbours sharing an edge (f64, the unfused variants; found by the differential
/// suite without the quick stage, which sends those pairs here). The interval stays the
/// certified one (it holds 0), with `lo` 0.
#[inline(always)]
fn at_shared_vertex<L: Lanes>(s: &[V3<L>; 3], t: &[V3<L>; 3], mut o: FastOut<L>) -> FastOut<L> {
    let k = Cx::of(o.lo);
    let Some((shared, x)) = shared_vertex(s, t) else {
        return o;
    };
    o.r.d = L::select(shared, k.zero(), o.r.d);
    o.r.p = V3::select(shared, x, o.r.p);
    o.r.q = V3::select(shared, x, o.r.q);
    o.lo = L::select(shared, k.zero(), o.lo);
    o.sharp = o.sharp.or(shared);
    o
}

/// A stage's answer at a vertex the input triangles `a`, `b` share (every coordinate equal,
/// compared before the local frame, so the test is exact: equal local coordinates alone do
/// not prove equal points, the frame's differences being rounded) made an exact interval
/// `[0, 0]` where the stage answered 0: the distance is 0, proven. So the correctly rounded
/// mode decides mesh neighbours from the f64 pass alone, without a proof of its own per pair
/// (only there: [`super::Params::exact_contacts`]).
/// Only lanes the stage answered 0 can share a vertex (equal points have equal local
/// coordinates, which both stages answer 0), so other vectors cost one compare.
#[inline(always)]
pub(crate) fn exact_at_shared_vertex<L: Lanes>(
    a: &[V3<L>; 3],
    b: &[V3<L>; 3],
    mut o: FastOut<L>,
) -> FastOut<L> {
    let z = Cx::of(o.lo).zero();
    let zero = o.r.d.eq(z);
    if !zero.any() {
        return o;
    }
    if let Some((shared, _)) = shared_vertex(a, b) {
        let exact = shared.and(zero);
        o.lo = L::select(exact, z, o.lo);
        o.hi = L::select(exact, z, o.hi);
    }
    o
}

/// A contact candidate of the full fast stage (code 15-20: an edge of one input triangle
/// crossing the other) made an exact interval `[0, 0]` where the crossing is proven: the
/// edge's ends strictly on either side of the other triangle's plane, and its line strictly
/// inside that triangle's three edges, each sign by [`orient3d`] on the input coordinates
/// (the test of the mode's per-pair proof, `engine::rounded::crossing`, on the one edge the
/// stage names). f64 only (the static error bound is f64's); the mode's f64 pass asks for it
/// ([`super::Params::exact_contacts`]), where it replaces that scalar proof for most
/// intersecting pairs.
#[inline(always)]
pub(crate) fn prove_crossing<L: Lanes>(a: &[V3<L>; 3], b: &[V3<L>; 3], mut o: FastOut<L>) -> FastOut<L> {
    let k = Cx::of(o.lo);
    let z = k.zero();
    let maybe = o.code.ge(k.c(15.0)).and(o.r.d.eq(z)).and(o.hi.gt(z));
    if L::S::PRECISION != crate::real::Precision::F64 || !maybe.any() {
        return o;
    }
    // the edge (its index j) of t = b crossing s = a (codes 15-17), or of a crossing b (18-20)
    let of_a = o.code.ge(k.c(18.0));
    let j = o.code.sub(L::select(of_a, k.c(18.0), k.c(15.0)));
    let (j1, j2) = (j.eq(k.one()), j.eq(k.c(2.0)));
    let (n1, n2) = (j.eq(k.zero()), j1); // the edge's second vertex: index j + 1 mod 3
    let (ea, eb) = ((pick(j1, j2, a), pick(n1, n2, a)), (pick(j1, j2, b), pick(n1, n2, b)));
    let (p, q) = (V3::select(of_a, ea.0, eb.0), V3::select(of_a, ea.1, eb.1));
    let u = [V3::select(of_a, b[0], a[0]), V3::select(of_a, b[1], a[1]), V3::select(of_a, b[2], a[2])];
    let (sp, sq) = (orient3d(u[0], u[1], u[2], p), orient3d(u[0], u[1], u[2], q));
    let apart = sp.0.and(sq.1).or(sp.1.and(sq.0));
    let e0 = orient3d(p, q, u[0], u[1]);
    let e1 = orient3d(p, q, u[1], u[2]);
    let e2 = orient3d(p, q, u[2], u[0]);
    let inside = e0.0.and(e1.0).and(e2.0).or(e0.1.and(e1.1).and(e2.1));
    let proven = maybe.and(apart).and(inside);
    o.lo = L::select(proven, z, o.lo);
    o.hi = L::select(proven, z, o.hi);
    o
}

/// The sign of `det[a - d, b - d, c - d]` where the floating-point value proves it, as masks
/// (positive, negative; neither: not proven): Shewchuk's static error bound of `orient3d`
/// (`o3derrboundA = (7 + 56u) u` for f64, covering the rounded differences), on differences
/// in `[1e-80, 1e80]` or zero, so that no product underflows or overflows. No fused
/// operations, so the bound holds on every instruction set. (The mode's per-pair proof,
/// `engine::rounded::orient3d`, is this on one lane.)
#[inline(always)]
pub(crate) fn orient3d<L: Lanes>(a: V3<L>, b: V3<L>, c: V3<L>, d: V3<L>) -> (L::M, L::M) {
    let k = Cx::of(a.x);
    let (ad, bd, cd) = (a.sub(d), b.sub(d), c.sub(d));
    let (small, big) = (k.c(1e-80), k.c(1e80));
    let mut safe = k.yes();
    for x in [ad.x, ad.y, ad.z, bd.x, bd.y, bd.z, cd.x, cd.y, cd.z] {
        let m = x.abs();
        safe = safe.and(m.eq(k.zero()).or(m.ge(small).and(m.le(big))));
    }
    let (bc, cb) = (bd.y.mul(cd.z), bd.z.mul(cd.y));
    let (ca, ac) = (cd.y.mul(ad.z), cd.z.mul(ad.y));
    let (ab, ba) = (ad.y.mul(bd.z), ad.z.mul(bd.y));
    let det = ad.x.mul(bc.sub(cb)).add(bd.x.mul(ca.sub(ac))).add(cd.x.mul(ab.sub(ba)));
    let perm = bc
        .abs()
        .add(cb.abs())
        .mul(ad.x.abs())
        .add(ca.abs().add(ac.abs()).mul(bd.x.abs()))
        .add(ab.abs().add(ba.abs()).mul(cd.x.abs()));
    let bound = k.c(7.771_561_172_376_103e-16).mul(perm);
    (safe.and(det.gt(bound)), safe.and(det.neg().gt(bound)))
}

/// A vertex `x` of `t` over the face of `s` (`s[0] = 0`): its squared distance to the point
/// `l1 s_1 + l2 s_2` of the face with the barycentric weights `(l1, l2)` from the inside values
/// `wa` (`+inf` unless inside, and the face not degenerate).
#[inline(always)]
fn over_s<L: Lanes>(s: &[V3<L>; 3], wa: &[L; 3], ok: L::M, inn: L, x: V3<L>) -> (L, L, L) {
    let k = Cx::of(inn);
    let z = k.zero();
    let inside = wa[0].ge(z).and(wa[1].ge(z)).and(wa[2].ge(z)).and(ok);
    let (l1, l2) = (wa[2].mul(inn), wa[0].mul(inn));
    let w = x.sub(s[1].scale(l1).add_scaled(s[2], l2));
    (L::select(inside, w.norm2(), k.inf()), l1, l2)
}

/// A vertex `x` of `s` over the face of `t`: the point `b_0 + m1 f_0 - m2 f_2`, as [`over_s`].
#[inline(always)]
fn over_t<L: Lanes>(t: &[V3<L>; 3], f: &[V3<L>; 3], wb: &[L; 3], ok: L::M, inn: L, x: V3<L>) -> (L, L, L) {
    let k = Cx::of(inn);
    let z = k.zero();
    let inside = wb[0].ge(z).and(wb[1].ge(z)).and(wb[2].ge(z)).and(ok);
    let (m1, m2) = (wb[2].mul(inn), wb[0].mul(inn));
    let w = t[0].add_scaled(f[0], m1).add_scaled(f[2], m2.neg()).sub(x);
    (L::select(inside, w.norm2(), k.inf()), m1, m2)
}

/// The quick stage of triangle-triangle distance (stage 0 of the `tri_tri` query), in the
/// same local frame as [`tri_tri_fast`]: one of its fifteen candidates, chosen per lane along
/// the direction `c` between the centroids: the edge of each triangle opposite its rearmost
/// vertex along `c` (its "front" edge), as an edge pair, with the same arithmetic and the same
/// certificate as there. On nearby triangles of a mesh that pair holds the answer nearly
/// always (triangles sharing an edge or a vertex included: the shared edge is both front
/// edges, and a shared vertex is nearly always on both); a pair it misses gets a wide interval
/// and goes on to the full fast stage, gathered with the others into full vectors
/// (`scenes/tests/paths.rs` bounds how often, per workload). The choice from the rounded `c`
/// needs no care: any edge pair gives points on the triangles and a rigorous interval.
#[inline(always)]
pub(crate) fn tri_tri_quick<L: Lanes>(s: &[V3<L>; 3], t: &[V3<L>; 3]) -> FastOut<L> {
    let k = Cx::of(t[0].x);
    let (z, one) = (k.zero(), k.one());
    let tiny = k.splat(L::S::MIN_POSITIVE);
    // three times the centroids' difference (s[0] = 0), and every vertex's projection on it;
    // the edge opposite the rearmost vertex is edge (rear + 1) mod 3
    let c = t[0].add(t[1]).add(t[2]).sub(s[1]).sub(s[2]);
    let (r1, r2) = extreme([z, c.dot(s[1]), c.dot(s[2])], true);
    let (i1, i2) = (r1.or(r2).not(), r1);
    let (r1, r2) = extreme([c.dot(t[0]), c.dot(t[1]), c.dot(t[2])], false);
    let (j1, j2) = (r1.or(r2).not(), r1);
    // the front edges from their first vertices to the next ones: edge i is s[i+1] - s[i]
    // (the same operation as [`tri_tri_fast`]'s edges, also for s[0] = 0)
    let (i0, j0) = (i1.or(i2).not(), j1.or(j2).not());
    let (si, sn, tj, tn) = (pick(i1, i2, s), pick(i0, i1, s), pick(j1, j2, t), pick(j0, j1, t));
    let (ei, fj) = (sn.sub(si), tn.sub(tj));
    let (iea, ifb) = (one.div(ei.norm2().max(tiny)), one.div(fj.norm2().max(tiny)));
    let (d, a, b) = edge_pair(si, ei, iea, tj, fj, ifb, None);
    // the answer (its certification direction below)
    let (p, q) = (si.add_scaled(ei, a), tj.add_scaled(fj, b));
    // A vertex shared by the front edges (mesh neighbours; identical triangles share all
    // three, and two front edges of three vertices share one) is answered exactly: distance
    // 0 at that vertex, as the full stage's contact candidate answers it, not the edge pair's
    // rounding of it (1e-32 where the edges meet at an angle). The first of the four vertex
    // pairs that match, in this order: (si, tj), (si, tn), (sn, tj), (sn, tn).
    let (p, q, d, shared) = match shared_vertex(&[si, sn], &[tj, tn]) {
        Some((shared, x)) => {
            (V3::select(shared, x, p), V3::select(shared, x, q), L::select(shared, z, d), shared)
        }
        None => (p, q, d, k.no()),
    };
    // (`q - p`, not the edge pair's own witness difference, one multiply-add sooner: that sent
    // 2.3 % of the Armadillo's nearby pairs to the full stage instead of 0.85 %, by the
    // sharpness test below; why was not investigated)
    let w = q.sub(p);
    let wn = w.norm2_up().sqrt();
    let both = interior(a).and(interior(b)).andnot(shared);
    // The certification direction: the edges' common normal where both parameters are
    // interior (scaled to unit magnitude: products of small differences underflow), `w`
    // itself elsewhere, unscaled (see [`lower`]) and, being `q - p`, oriented from `s` to
    // `t`; the normal is not oriented (its gap is taken both ways). So the projections wait
    // for `w` alone.
    let (g, vn) = if both.any() {
        let n = ei.cross_accurate(fj).unit_pow2();
        let (up, down) = gaps(s, t, V3::select(both, n, w));
        (L::select(both, up.max(down), up), L::select(both, n.norm2_up().sqrt(), wn))
    } else {
        (gaps(s, t, w).0, wn)
    };
    let (rr, gv) = (extent(s, t), g.div(vn));
    let (lo, hi) = (lower(gv, vn, rr), upper(wn, z, rr));
    // Accepted (within the tolerance, by the caller) only when, besides, the candidate is the
    // closest pair as far as the arithmetic can tell, its distance within `SHARP u` of the gap
    // along `v` (the input is prescaled: `u S >= u`), so that its error is the full stage's;
    // and, unless at a shared vertex, the gap shows the pair apart. The tolerance alone would
    // not do: it is relative to the coordinates' magnitude, so far from the origin it exceeds
    // the triangles' size, and a candidate that merely came near the distance within it was
    // accepted where the full stage finds the closest pair (f32 pairs 1e5 from the origin:
    // E 51, beyond the target of 8; needles: E 3.2; found by the differential and mesh
    // suites); an intersecting pair needs the full stage's contact candidate.
    let sharp = wn.sub(gv).le(k.u().mul(k.c(SHARP))).and(lo.gt(z).or(shared));
    FastOut { r: Res { d, p, q }, lo, hi, sharp, code: z }
}

/// Is one of the points `xs` also one of `ys` (every coordinate equal), and the first such
/// of `xs` (the last of `xs` where none is): the shared vertex both stages answer exactly.
/// `None` when no lane can have one: screened by one coordinate, so that groups with no common
/// vertex pay `M N` compares and no selects.
/// (Loops, no closures: closures compile without the entry point's target features.)
#[inline(always)]
fn shared_vertex<L: Lanes, const M: usize, const N: usize>(
    xs: &[V3<L>; M],
    ys: &[V3<L>; N],
) -> Option<(L::M, V3<L>)> {
    let k = Cx::of(xs[0].x);
    let mut maybe = k.no();
    for x in xs {
        for y in ys {
            maybe = maybe.or(x.x.eq(y.x));
        }
    }
    if !maybe.any() {
        return None;
    }
    let (mut shared, mut x) = (k.no(), xs[M - 1]);
    // from the last to the first, so that the first match is the one kept
    for i in (0..M).rev() {
        let mut at = k.no();
        for y in ys {
            at = at.or(same(xs[i], *y));
        }
        x = V3::select(at, xs[i], x);
        shared = shared.or(at);
    }
    Some((shared, x))
}

/// Are two points the same (every coordinate equal)? (A function, not a closure: see
/// [`straddles`].)
#[inline(always)]
fn same<L: Lanes>(x: V3<L>, y: V3<L>) -> L::M {
    x.x.eq(y.x).and(x.y.eq(y.y)).and(x.z.eq(y.z))
}

/// How far (in units of `u`, prescaled: of `u S` at least) the quick stage's candidate may be
/// from the gap along its direction.
const SHARP: f64 = 1.0;

/// The index of the smallest (`min`) or largest of three values, as masks `index == 1`,
/// `index == 2` (ties to the lower index).
#[inline(always)]
fn extreme<L: Lanes>(x: [L; 3], min: bool) -> (L::M, L::M) {
    let (a, b) = if min { (x[1].lt(x[0]), x[1].min(x[0])) } else { (x[1].gt(x[0]), x[1].max(x[0])) };
    let two = if min { x[2].lt(b) } else { x[2].gt(b) };
    (a.andnot(two), two)
}

/// A triangle's normal from its edges `e` (accurately rounded from the best-conditioned pair),
/// whether it is above the rounding noise (not degenerate), `1 / |n|^2`, and whether the
/// triangle is thin (its barycentric weights then err by far more than `u`).
#[inline(always)]
fn face<L: Lanes>(e: &[V3<L>; 3]) -> (V3<L>, L::M, L, L::M) {
    let k = Cx::of(e[0].x);
    let (p, q) = normal_pair(e);
    let n = p.cross_accurate(q);
    let ok = n.norm_inf().gt(p.norm_inf().mul(q.norm_inf()).mul(k.u().mul(k.c(16.0))));
    // thin: twice its area below an eighth of its longest edge squared (the barycentric
    // weights' rounding is amplified by that ratio)
    let l2 = e[0].norm2().max(e[1].norm2()).max(e[2].norm2());
    let nn = n.norm2();
    let thin = nn.mul(k.c(64.0)).lt(l2.mul(l2));
    (n, ok, k.one().div(nn.max(k.splat(L::S::MIN_POSITIVE))), thin)
}

/// Squared distance and parameters `(s, t)` of the closest points of the edges `a + s e` and
/// `b + t f` (Ericson 5.1.9; see [`tri_tri_fast`]). `iea`, `ifb`: reciprocals of the squared
/// edge lengths. The lines' parameter comes from plain cross products (`gram` `None`: the quick
/// stage), or, given the squared edge lengths `(|e|^2, |f|^2)` (the full fast stage), from the
/// dot products already formed, `(e.d |f|^2 - e.f f.d) / (|e|^2 |f|^2 - (e.f)^2)` (with the
/// parallel test, 8 operations where the cross products take 24), except in lanes whose edges
/// are within about 7 degrees of parallel (`|e x f|^2 < |e|^2 |f|^2 / 64`), where that form's
/// cancellation costs `u / sin^2` and the cross products are taken instead (when any lane of
/// the vector needs them). The rounding of either moves the points along their edges only.
/// Where `|e|^2 |f|^2` underflows (edges below about the fourth root of the smallest normal
/// number, the input being prescaled to [1, 2)), the test cannot see parallel edges and the
/// parameter may be anywhere in [0, 1]: that moves the point by less than its edge's length,
/// far below `u`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn edge_pair<L: Lanes>(
    a: V3<L>,
    e: V3<L>,
    iea: L,
    b: V3<L>,
    f: V3<L>,
    ifb: L,
    gram: Option<(L, L)>,
) -> (L, L, L) {
    let d = b.sub(a);
    let bb = e.dot(f);
    let (ed, fd) = (e.dot(d), f.dot(d));
    let s0 = match gram {
        None => by_cross(d, e, f),
        Some((ee, ff)) => {
            let k = Cx::of(bb);
            let eff = ee.mul(ff);
            let den = eff.sub(bb.mul(bb));
            let s0 = ed.mul(ff).sub(bb.mul(fd)).safe_div(den);
            let flat = den.lt(eff.mul(k.c(1.0 / 64.0)));
            if flat.any() {
                L::select(flat, by_cross(d, e, f), s0)
            } else {
                s0
            }
        }
    }
    .clamp01();
    // t = (bb s0 - fd) / |f|^2 and s = (bb t + ed) / |e|^2, each one multiply-add after the
    // parameter it waits for: the products with the reciprocals are formed beside the
    // division, off the quick stage's critical path (the parameters are clamped and only
    // move the points along their edges, so their rounding is the certificate's concern,
    // not their exactness)
    let tt = bb.mul(ifb).mul_add(s0, fd.mul(ifb).neg()).clamp01();
    let ss = bb.mul(iea).mul_add(tt, ed.mul(iea)).clamp01();
    // W = q - p = (b - a) + t f - s e
    let w = d.add_scaled(f, tt).add_scaled(e, ss.neg());
    (w.norm2(), ss, tt)
}

/// The lines' closest-point parameter on `e` by Lagrange's identity from plain cross
/// products, `n . (d x f) / |n|^2` with `n = e x f` (a function, not a closure: closures
/// compile without the entry point's target features).
#[inline(always)]
fn by_cross<L: Lanes>(d: V3<L>, e: V3<L>, f: V3<L>) -> L {
    let n = e.cross(f);
    n.dot(d.cross(f)).safe_div(n.norm2())
}

/// The answer of every lane rebuilt from its best candidate, and its certificate (static
/// bounds on the local extent `R`; see the constants).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn certified<L: Lanes>(
    s: &[V3<L>; 3],
    t: &[V3<L>; 3],
    e: &[V3<L>; 3],
    f: &[V3<L>; 3],
    (na, nb): (V3<L>, V3<L>),
    best: &Best<L>,
    inn: (L, L),
    thin: (L::M, L::M),
) -> FastOut<L> {
    let (d, p, q, w, v, over) = rebuild(s, t, e, f, na, nb, best, inn, thin);
    let (lo, hi, excess) = interval(s, t, w, v, over);
    // Sharp, as the quick stage's answer must be (see there), with the E target as the
    // allowance: the candidate within `SHARP_E u` of the gap along its direction, or a
    // contact whose witness points meet (below; its gap is negative, so the first rule cannot
    // judge it).
    // Otherwise a missed candidate within the tolerance was accepted: f32, a degenerate
    // triangle (a segment) through a face, where the contact candidates need two proper faces,
    // answered by an edge pair 16 u S away (a contact miss under the 64 u S default; found by
    // `cargo fuzz run tri_tri`). Such pairs go on to the tight re-certification and the
    // accurate stages. (Correct answers come within this of their gap: random unit-cube
    // pairs, 2000 per variant, 11-23 re-certified at 8 u, 318 at 1 u; `scenes/tests/paths.rs`.)
    // A contact is sharp when its two witness points (the crossing point and its parametric
    // point on the other face) meet within the same `SHARP_E u`: otherwise the pair may be
    // apart by about that much, and the answer 0 was only within the tolerance (f64, a vertex
    // 6e-14 = 5.7 u S from another triangle's vertex, the edges through it "crossing" by
    // rounding, answered 0: E 5.7 over the bound table's 5.0; found by `cargo fuzz run
    // tri_tri`, now re-certified tightly and answered with E 0.75-0.9). Genuine contacts of
    // random pairs pass: 14-26 of 2000 re-certified instead of 11-23.
    let k = Cx::of(lo);
    let near = k.u().mul(k.c(SHARP_E));
    let met = w.norm2().le(near.mul(near));
    let sharp = excess.le(near).or(best.code.ge(k.c(15.0)).and(met));
    FastOut { r: Res { d, p, q }, lo, hi, sharp, code: best.code }
}

/// The certificate of a candidate with witness difference `w` (of parametric points on the
/// triangles whose parameters overshoot their range by `over`), projected along `v` (oriented
/// like `w`): static bounds on the local extent `R`, see the constants. Returns `lo`, `hi` and,
/// as plainly computed, `|w|` less the gap along `v` (about 0 when the candidate is the
/// closest pair).
#[inline(always)]
fn interval<L: Lanes>(s: &[V3<L>; 3], t: &[V3<L>; 3], w: V3<L>, v: V3<L>, over: L) -> (L, L, L) {
    let rr = extent(s, t);
    let wn = w.norm2_up().sqrt();
    let (g, _) = gaps(s, t, v);
    let vn = v.norm2_up().sqrt();
    let gv = g.div(vn);
    // how far the candidate is from the gap along v, as computed (no allowances)
    let excess = wn.sub(gv);
    (lower(gv, vn, rr), upper(wn, over, rr), excess)
}

/// `R (1 + 4u)`, `R` the largest norm of the local vertices (`s[0] = 0`): an upper bound on
/// the local extent the constants are relative to, also where the squares underflow
/// ([`V3::norm2_up`]).
#[inline(always)]
fn extent<L: Lanes>(s: &[V3<L>; 3], t: &[V3<L>; 3]) -> L {
    let k = Cx::of(s[0].x);
    let mut r2 = s[1].norm2_up().max(s[2].norm2_up());
    for x in t {
        r2 = r2.max(x.norm2_up());
    }
    r2.sqrt().mul(up4(k))
}

/// `1 + 4u`: the factor that rounds the certificate's norms up.
#[inline(always)]
fn up4<L: Lanes>(k: Cx<L>) -> L {
    k.one().add(k.u().mul(k.c(4.0)))
}

/// The gaps between the triangles' projections on `v`, as computed: `t` beyond `s` along `v`,
/// and `s` beyond `t` (the gap along `-v`).
#[inline(always)]
fn gaps<L: Lanes>(s: &[V3<L>; 3], t: &[V3<L>; 3], v: V3<L>) -> (L, L) {
    let z = Cx::of(s[0].x).zero();
    let (s1, s2) = (v.dot(s[1]), v.dot(s[2]));
    let (t0, t1, t2) = (v.dot(t[0]), v.dot(t[1]), v.dot(t[2]));
    let (smax, smin) = (z.max(s1).max(s2), z.min(s1).min(s2));
    let (tmin, tmax) = (t0.min(t1).min(t2), t0.max(t1).max(t2));
    (tmin.sub(smax), smin.sub(tmax))
}

/// The certified lower bound from the quotient `gv = g / vn` of a gap `g` along a direction
/// `v` by its norm as computed (`vn = sqrt(v . v + m)`, [`V3::norm2_up`], `m` the smallest
/// normal number), and the extent bound `rr` ([`extent`]): `g / |v| - C_LO u R (1 + 4u)`,
/// rounded down, or 0. The projections' rounding is relative to `|v| R` but where a result
/// underflows, off by at most half the smallest subnormal, `m u`: six such roundings per gap,
/// divided by `|v| >= u^2`, stay below `6 m / u`, which `rr >= sqrt(m)` ([`extent`]'s floor)
/// covers. So the direction need not be scaled; lanes with `vn < u^2` get 0 (there `vn` may
/// exceed `|v|` by more than rounding, or `v = 0`). The gap is divided first, so that the
/// allowance is formed beside the projections (and the quotient is the one the sharpness
/// tests compare): `vn >= |v| (1 - 2u)`, and `1 - 8u` covers that, the quotient's and the
/// gap's roundings and the last one.
#[inline(always)]
fn lower<L: Lanes>(gv: L, vn: L, rr: L) -> L {
    let k = Cx::of(gv);
    let u = k.u();
    let c = u.mul(k.c(C_LO)).mul(up4(k)).mul(rr);
    let lo = gv.mul_add(k.one().sub(u.mul(k.c(8.0))), c.neg()).max(k.zero());
    L::select(vn.ge(u.mul(u)), lo, k.zero())
}

/// The certified upper bound from the witness difference's norm `wn` (`sqrt(w . w + m)`), the
/// parameters' overshoot `over` (a face point's moves it off the face by at most that times
/// `2R`) and the extent bound `rr`, one multiply-add after `wn`.
#[inline(always)]
fn upper<L: Lanes>(wn: L, over: L, rr: L) -> L {
    let k = Cx::of(wn);
    let u = k.u();
    wn.mul_add(up4(k), u.mul(k.c(C_HI)).add(over.mul(k.c(2.0))).mul(rr))
}

/// Rebuilds the winner of every lane from its code and parameters: the answer's squared
/// distance and points on `s` and `t`, the witness difference `w = q - p` (of parametric
/// points), the certification
/// direction (the common normal of two edges met in their interiors, a face normal, or `w`)
/// and the parameters' overshoot.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn rebuild<L: Lanes>(
    s: &[V3<L>; 3],
    t: &[V3<L>; 3],
    e: &[V3<L>; 3],
    f: &[V3<L>; 3],
    na: V3<L>,
    nb: V3<L>,
    best: &Best<L>,
    inn: (L, L),
    thin: (L::M, L::M),
) -> (L, V3<L>, V3<L>, V3<L>, V3<L>, L) {
    let k = Cx::of(best.d);
    let c = best.code;
    let (ee, vfa, vfb, cta) = (c.lt(k.c(9.0)), c.lt(k.c(12.0)), c.lt(k.c(15.0)), c.lt(k.c(18.0)));
    let (vfa, vfb, cta) = (vfa.andnot(ee), vfb.andnot(vfa), cta.andnot(vfb));
    let ctb = cta.or(vfb).or(vfa).or(ee).not();
    // indices: an edge pair's i and j; a vertex's or crossing edge's index
    let i1 = c.ge(k.c(3.0)).and(c.lt(k.c(6.0)));
    let i2 = c.ge(k.c(6.0)).and(ee);
    let jf = c.sub(L::select(i2, k.c(6.0), L::select(i1, k.c(3.0), k.zero())));
    let base = L::select(
        ee,
        jf,
        c.sub(L::select(vfa, k.c(9.0), L::select(vfb, k.c(12.0), L::select(cta, k.c(15.0), k.c(18.0))))),
    );
    let (j1, j2) = (base.eq(k.one()), base.eq(k.c(2.0)));
    let (a, b) = (best.a, best.b);
    // points of each kind, then the lane's own
    let face_a = s[1].scale(a).add_scaled(s[2], b);
    let face_b = t[0].add_scaled(f[0], a).add_scaled(f[2], b.neg());
    let p_ee = pick(i1, i2, s).add_scaled(pick(i1, i2, e), a);
    let q_ee = pick(j1, j2, t).add_scaled(pick(j1, j2, f), b);
    let p_vb = pick(j1, j2, s);
    let q_va = pick(j1, j2, t);
    let x_ta = pick(j1, j2, t).add_scaled(pick(j1, j2, f), best.c);
    let x_sb = pick(j1, j2, s).add_scaled(pick(j1, j2, e), best.c);
    let p = V3::select(ee, p_ee, V3::select(vfb, p_vb, V3::select(ctb, x_sb, face_a)));
    let q = V3::select(ee, q_ee, V3::select(vfa, q_va, V3::select(cta, x_ta, face_b)));
    let w = q.sub(p);
    // A contact is answered with the crossing point and its projection onto the other plane
    // along the accurate normal (the parametric face point above, from interpolated
    // barycentric weights, is what the certificate needs but is less accurate).
    let ct = cta.or(ctb);
    let (p_out, q_out) = if ct.any() {
        let pa_x = x_ta.sub(na.scale(na.dot(x_ta).mul(inn.0)));
        let pb_x = x_sb.sub(nb.scale(nb.dot(x_sb.sub(t[0])).mul(inn.1)));
        (V3::select(cta, pa_x, p), V3::select(ctb, pb_x, q))
    } else {
        (p, q)
    };
    // Likewise a vertex over a thin face is answered with its projection along the accurate
    // normal and its height over the plane: the parametric face point's barycentric weights
    // err by about u |e| |x| / |n| of the face, which near a vertex of a long thin face came
    // to 40 u S (fuzzing: a point 1e-4 from a sliver's vertex, inside it, answered 1.2e-4
    // away). (On well-shaped faces both are as accurate; the parametric point is kept.)
    let (sa, sb) = (vfa.and(thin.0), vfb.and(thin.1));
    let vf = sa.or(sb);
    let (d_out, p_out, q_out) = if vf.any() {
        let ha = na.dot(q_va);
        let hb = nb.dot(p_vb.sub(t[0]));
        let d = L::select(sa, ha.mul(ha).mul(inn.0), L::select(sb, hb.mul(hb).mul(inn.1), best.d));
        let pa = q_va.sub(na.scale(ha.mul(inn.0)));
        let qb = p_vb.sub(nb.scale(hb.mul(inn.1)));
        (d, V3::select(sa, pa, p_out), V3::select(sb, qb, q_out))
    } else {
        (best.d, p_out, q_out)
    };
    // direction
    let both = ee.and(interior(a)).and(interior(b));
    let n = pick(i1, i2, e).cross_accurate(pick(j1, j2, f));
    let v = V3::select(both, n, V3::select(vfa, na, V3::select(vfb, nb, w)));
    // oriented like w; scaled to unit magnitude (products of small local differences underflow)
    let v = v.unit_pow2();
    let v = V3::select(both.or(vfa).or(vfb), V3::select(v.dot(w).lt(k.zero()), v.neg(), v), w.unit_pow2());
    let over = L::select(ee, k.zero(), overshoot(a, b));
    (d_out, p_out, q_out, w, v, over)
}

/// Parameter of the crossing of an edge whose ends are at heights `h0`, `h1` over a plane,
/// clamped to [0, 1]; the sign moved to the numerator so the guarded division sees a
/// non-negative divisor.
#[inline(always)]
fn crossing<L: Lanes>(h0: L, h1: L) -> L {
    let k = Cx::of(h0);
    let den = h0.sub(h1);
    let num = L::select(den.lt(k.zero()), h0.neg(), h0);
    num.safe_div(den.abs()).clamp01()
}

/// Do heights `h` of three vertices over a plane have both signs (or a zero)? (A function, not
/// a closure: closures compile without the entry point's target features.)
#[inline(always)]
fn straddles<L: Lanes>(h: &[L; 3]) -> L::M {
    let z = Cx::of(h[0]).zero();
    let lo = h[0].min(h[1]).min(h[2]);
    let hi = h[0].max(h[1]).max(h[2]);
    lo.le(z).and(hi.ge(z))
}

/// `a + tau (b - a)`, componentwise.
#[inline(always)]
fn lerp3<L: Lanes>(a: [L; 3], b: [L; 3], tau: L) -> [L; 3] {
    [a[0].add(tau.mul(b[0].sub(a[0]))), a[1].add(tau.mul(b[1].sub(a[1]))), a[2].add(tau.mul(b[2].sub(a[2])))]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes::Portable;
    use rug::Rational;

    /// [`gaps`] and [`lower`] on one lane type: local triangles (`s[0] = 0`) of extent
    /// `2^-e` for each `e` of `extents`, apart along x by `2^-j` of that (`j` random up to
    /// the precision: gaps from the extent down to below the rounding), projected on
    /// directions of magnitude `2^-m` for each `m` of `mags`, unscaled as the quick stage
    /// passes `w`, down to where the products and `v . v` underflow, of either orientation.
    /// The bound never exceeds the exact gap between the projections (`f32`/`f64` values are
    /// rationals) divided by the exact `|v|`: `lo^2 v.v <= G^2`; and [`upper`] of `v`'s norm
    /// as computed is at least the exact `|v|`. Returns (pairs checked, pairs with `lo > 0`).
    fn bounds_hold_at<L: Lanes>(k: L::K, extents: &[i32], mags: &[i32]) -> (usize, usize) {
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut rnd = move || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let prec = if L::S::PRECISION == crate::Precision::F32 { 24 } else { 53 };
        let q = |x: L::S| Rational::from_f64(x.to_f64()).expect("finite");
        let (mut checked, mut positive) = (0, 0);
        for &e in extents {
            for &m in mags {
                for _ in 0..64 {
                    // one pair per lane: s at 0 <= x <= 1, t at x >= 1 + 2^-j (a vertex of
                    // each at those bounds, so that the gap is the difference of projections
                    // as large as the extent), the direction near +-x with its other
                    // components too small to close the gap
                    let mut pts = vec![[[L::S::ZERO; 3]; 6]; L::N];
                    let mut dir = vec![[L::S::ZERO; 3]; L::N];
                    for l in 0..L::N {
                        let j = ((rnd() + 1.0) / 2.0 * prec as f64) as i32;
                        let dx = 2f64.powi(-j);
                        for (i, p) in pts[l].iter_mut().enumerate().skip(1) {
                            let r = rnd().abs();
                            let x = match i {
                                1 => 1.0,
                                2 => r,
                                3 => 1.0 + dx,
                                _ => 1.0 + dx + r,
                            };
                            *p = [x, rnd(), rnd()].map(|x| L::S::from_f64(x * 2f64.powi(-e)));
                        }
                        let sign = if rnd() < 0.0 { -1.0 } else { 1.0 };
                        let side = 2f64.powi(-j - 3);
                        let d = [sign * (1.0 + rnd() / 4.0), rnd() * side, rnd() * side];
                        dir[l] = d.map(|x| L::S::from_f64(x * 2f64.powi(-m)));
                    }
                    // a vector of one value per lane
                    let lanes = |f: &dyn Fn(usize) -> L::S| {
                        let mut b = [L::S::ZERO; 16];
                        for (l, x) in b[..L::N].iter_mut().enumerate() {
                            *x = f(l);
                        }
                        L::load(k, &b[..L::N])
                    };
                    let vtx = |i: usize| {
                        V3::new(lanes(&|l| pts[l][i][0]), lanes(&|l| pts[l][i][1]), lanes(&|l| pts[l][i][2]))
                    };
                    let (s, t) = ([vtx(0), vtx(1), vtx(2)], [vtx(3), vtx(4), vtx(5)]);
                    let v = V3::new(lanes(&|l| dir[l][0]), lanes(&|l| dir[l][1]), lanes(&|l| dir[l][2]));
                    let (up, down) = gaps(&s, &t, v);
                    let (vn, rr) = (v.norm2_up().sqrt(), extent(&s, &t));
                    let lo = lower(up.max(down).div(vn), vn, rr);
                    // (and `upper` bounds the norm of `v` taken as a witness difference)
                    let hi = upper(vn, Cx::of(vn).zero(), rr);
                    let (mut got, mut got_hi) = ([L::S::ZERO; 16], [L::S::ZERO; 16]);
                    lo.store(&mut got[..L::N]);
                    hi.store(&mut got_hi[..L::N]);
                    for l in 0..L::N {
                        let dot = |p: &[L::S; 3]| -> Rational {
                            (0..3).map(|c| q(dir[l][c]) * q(p[c])).fold(Rational::new(), |a, b| a + b)
                        };
                        let ps: Vec<Rational> = pts[l].iter().map(dot).collect();
                        let (smin, smax) = (ps[..3].iter().min().unwrap(), ps[..3].iter().max().unwrap());
                        let (tmin, tmax) = (ps[3..].iter().min().unwrap(), ps[3..].iter().max().unwrap());
                        let gap = (Rational::from(tmin - smax)).max(Rational::from(smin - tmax));
                        let vv = dot(&dir[l]);
                        let hi = q(got_hi[l]);
                        assert!(
                            Rational::from(&hi * &hi) >= vv,
                            "extent 2^-{e}, |v| 2^-{m}: hi {hi} below |v|"
                        );
                        let lo = got[l];
                        assert!(lo >= L::S::ZERO, "extent 2^-{e}, |v| 2^-{m}: lo {lo:?}");
                        if lo > L::S::ZERO {
                            positive += 1;
                            let lo2 = q(lo) * q(lo) * vv;
                            assert!(
                                gap > 0 && lo2 <= Rational::from(&gap * &gap),
                                "extent 2^-{e}, |v| 2^-{m}: lo {lo:?} above the exact gap"
                            );
                        }
                        checked += 1;
                    }
                }
            }
        }
        (checked, positive)
    }

    /// The quick stage's certificate projects on `w` unscaled: its lower bound holds at every
    /// magnitude of the direction and of the triangles, on the unfused scalar types and the
    /// fused AVX2+FMA ones. Directions below `u^2` (`f32`: from 2^-48 on; `f64`: 2^-106) give
    /// 0; `v . v` turns subnormal at 2^-63 (`f32`) and 2^-511 (`f64`), and so do the squares
    /// of the smallest extents (the extent's own underflow, found by this test: `R` computed
    /// 0, the bound above the gap); products of those with the smaller directions underflow.
    #[test]
    fn the_certificate_holds_along_unscaled_directions_at_every_magnitude() {
        let (e32, m32) = ([0, 20, 50, 70, 100], [0, 30, 47, 66, 75]);
        let (e64, m64) = ([0, 200, 480, 600, 950], [0, 100, 105, 300, 515, 530]);
        for (checked, positive) in
            [bounds_hold_at::<f32>(Portable, &e32, &m32), bounds_hold_at::<f64>(Portable, &e64, &m64)]
        {
            // the pairs are apart: the bound is positive for most directions not below u^2 and
            // extents not below sqrt(m) (`extent`'s floor)
            assert!(positive * 4 > checked, "{positive} of {checked}");
        }
        #[cfg(target_arch = "x86_64")]
        if let Some(k) = crate::arch::x86_simd::Avx2Fma::detect() {
            use crate::arch::x86_simd::{F32x8, F64x4};
            let (c, p) = bounds_hold_at::<F32x8<crate::arch::x86_simd::Avx2Fma>>(k, &e32, &m32);
            assert!(p * 4 > c, "{p} of {c}");
            let (c, p) = bounds_hold_at::<F64x4<crate::arch::x86_simd::Avx2Fma>>(k, &e64, &m64);
            assert!(p * 4 > c, "{p} of {c}");
        }
    }
}
