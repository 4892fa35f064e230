//! Within-margin: pairs whose bounding boxes are certainly farther apart than the margin are
//! answered `+inf` by the box test alone; the others go to the full triangle-triangle pipeline
//! (fast stage, compaction, escalation), whose squared distance is kept when within the margin.
//! So the answer is exactly the full query's, thresholded (the `within` fuzz target checks it).

use super::{aabb_gap2, nan_where_invalid, scale_pair, Kernel, Out, Params};
use crate::lanes::{Cx, Lanes, Mask, V3};

/// The within-margin query (registry entry `within`).
pub(crate) struct Within;

impl Kernel for Within {
    const KA: usize = 3;
    const KB: usize = 3;
    const WIDEN: bool = false;
    const RECERT: bool = false;
    const NEXT: Option<crate::Query> = Some(crate::Query::TriTri);
    #[inline(always)]
    fn stage<L: Lanes, const ST: u8>(a: &[V3<L>; 3], b: &[V3<L>; 3], prm: &Params<L::S>) -> Out<L> {
        let (sc, s, t) = scale_pair::<L, 3, 3>(a, b);
        let k = Cx::of(sc.p);
        let inv = sc.inv;
        let m = k.splat(prm.margin).mul(inv);
        // The box gap (prescaled) is a lower bound of the exact distance up to the rounding of
        // the coordinate differences (relative u). The full query's answer may be off the exact
        // distance by up to its tolerance (absolute `tol`, relative `rel`), so a pair is
        // skipped only when even the lowest answer the full query could give,
        // `gap (1 - rel) - tol`, exceeds the margin (with slack for this test's own rounding):
        // then within-margin is exactly the full query thresholded.
        let gap = aabb_gap2(&s, &t).sqrt().mul(k.one().sub(k.u().mul(k.c(8.0))));
        let tol = k
            .splat(prm.tol_scaled)
            .mul(sc.m.mul(inv))
            .max(k.splat(prm.tol_abs).mul(inv))
            .add(k.u().mul(k.c(8.0)));
        let low = gap.mul(k.one().sub(k.splat(prm.tol_rel))).sub(tol);
        // In the caller's units as well: a squared distance that underflows to 0 there is
        // within a margin of 0 (fuzzing found subnormal pairs skipped in prescaled units).
        let margin2 = k.splat(prm.margin).mul(k.splat(prm.margin));
        let far =
            low.gt(m.mul(k.one().add(k.u().mul(k.c(8.0))))).and(low.mul(low).mul(sc.p.mul(sc.p)).gt(margin2));
        let out = Out { d: k.inf(), p: k.v0(), q: k.v0(), lo: k.zero(), hi: k.inf(), ok: far, it: k.zero() };
        nan_where_invalid(out, &sc)
    }
}
