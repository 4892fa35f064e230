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
        let inv = k.one().div(sc.p);
        let m = k.splat(prm.margin).mul(inv);
        // The box gap (prescaled): each coordinate difference is rounded once (relative u), so
        // the computed squared gap is at most (1 + 8u) times the exact one; beyond the margin
        // with that slack, the exact distance (at least the exact box gap) is beyond it too.
        // In the caller's units as well: a squared distance that underflows to 0 there is
        // within a margin of 0 (fuzzing found subnormal pairs skipped in prescaled units).
        let gap2 = aabb_gap2(&s, &t);
        let slack = k.one().add(k.u().mul(k.c(16.0)));
        let margin2 = k.splat(prm.margin).mul(k.splat(prm.margin));
        let far = gap2.gt(m.mul(m).mul(slack)).and(gap2.mul(sc.p.mul(sc.p)).gt(margin2));
        let out = Out { d: k.inf(), p: k.v0(), q: k.v0(), lo: k.zero(), hi: k.inf(), ok: far, it: k.zero() };
        nan_where_invalid(out, &sc)
    }
}
