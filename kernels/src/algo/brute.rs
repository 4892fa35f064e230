//! Brute force (Krestenitis & Koziara's baseline): the minimum over the 15 feature pairs (9
//! edge-edge, 6 vertex-face) unless the separating-axis test finds an overlap, then a contact
//! point pair, with 0 where a contact candidate comes within 2 u S (see [`overlap`]).

use super::point_tri::point_triangle;
use super::sat::overlaps;
use super::seg_seg::seg_seg;
use super::{allowance, edges, finish, keep_min, normal, scale_pair, swap, Kernel, Out, Params, Res};
use crate::lanes::{Cx, Lanes, Mask, V3};

/// The brute-force query (registry entry `tri_tri_brute`).
pub(crate) struct Brute;

impl Kernel for Brute {
    const KA: usize = 3;
    const KB: usize = 3;
    #[inline(always)]
    fn stage<L: Lanes, const ST: u8>(a: &[V3<L>; 3], b: &[V3<L>; 3], prm: &Params<L::S>) -> Out<L> {
        let (sc, s, t) = scale_pair::<L, 3, 3>(a, b);
        let r = tri_tri_brute(&s, &t, allowance(&sc, CONTACT));
        finish::<L, 3, 3, false>(&sc, &s, &t, None, r, prm)
    }
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
        let num = L::select(den.lt(Cx::of(h0).zero()), h0.neg(), h0);
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

/// How close (in `u S`) a contact candidate must come for an overlap to be answered 0.
const CONTACT: f64 = 2.0;

/// Brute force: `overlaps ? contact : min15`, both computed for every lane (the contact's
/// distance 0 within `reach`: see [`overlap`]).
#[inline(always)]
fn tri_tri_brute<L: Lanes>(s: &[V3<L>; 3], t: &[V3<L>; 3], reach: L) -> Res<L> {
    let mut best = min15(s, t);
    overlap(s, t, overlaps(s, t), reach, &mut best);
    best
}

/// For the `hit` lanes (the separating-axis test found no separating axis): a contact point
/// pair, and squared distance 0 where the pair comes within `reach` (prescaled, [`CONTACT`]
/// u S), else the pair's own squared distance.
///
/// The test cannot separate triangles a few `u S` apart (it decides on rounded axes), so its
/// "overlap" alone would answer 0 for them: `fuzz/regressions/tri_tri/fused-f64-brute-overlap-
/// 6-uS-apart`, two triangles 6.08 u S apart through one vertex, answered 0 (E 6.08). The best
/// of the 15 feature pairs and the 6 edge-plane crossings is the distance where the triangles
/// are apart (up to its rounding), and within `reach` of 0 where they truly overlap: their
/// intersection segment ends where an edge of one crosses the other, which the crossing
/// candidates find, or the edge-edge candidates where that crossing lies near an edge. So
/// answering 0 only within `reach` keeps an overlap's answer 0 and bounds the error of a false
/// one by `reach` plus the candidates' rounding; the differential suite (`TRIDIST_EXTENSIVE=1`)
/// measures both. Its run on this change (30,000 pairs per family and precision) answered no
/// intersecting or touching pair with a positive distance (E 0 in those rows, as before).
/// Since point-triangle's offset from the plane is compensated (3545ef6), the crossing
/// candidates' distances are those of the rounded crossing points themselves, and one of the
/// 30,000 intersecting f32 pairs (`intersecting/1898041687/18252`, on the unfused variants) is
/// answered 1.44e-14 instead of 0: its crossing point, rounded, lies 2.16 `u S` from the other
/// triangle, beyond the 2 `u S` reach (E 2.16, within the target of 8; `scenes/src/measured.in`).
#[inline(always)]
fn overlap<L: Lanes>(s: &[V3<L>; 3], t: &[V3<L>; 3], hit: L::M, reach: L, best: &mut Res<L>) {
    if hit.any() {
        let mut cp = *best;
        contact_points(s, t, &mut cp);
        let zero = hit.and(cp.d.le(reach.mul(reach)));
        best.p = V3::select(hit, cp.p, best.p);
        best.q = V3::select(hit, cp.q, best.q);
        best.d = L::select(zero, Cx::of(best.d).zero(), L::select(hit, cp.d, best.d));
    }
}
