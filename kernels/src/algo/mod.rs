//! The algorithms, each written once over [`Lanes`] (scalar, SSE4.1, AVX and AVX2+FMA all
//! instantiate these same functions), one file per algorithm:
//!
//! | file | algorithm |
//! |---|---|
//! | [`seg_seg`] | segment-segment closest points (Ericson 5.1.9, accurate cross products) |
//! | [`point_tri`] | point-triangle closest point (Ericson 5.1.5, Voronoi regions by triple products) |
//! | [`sat`] | triangle-triangle separating-axis overlap (PQP's TriContact) and its certified fast form |
//! | [`fast`] | the fast stage of triangle-triangle distance (15 features, plain loops, one certificate) |
//! | [`pqp`] | the accurate stage: PQP's TriDist with certified early exits (Larsen et al.) |
//! | [`brute`] | brute force: 15 feature pairs + separating axes (Krestenitis & Koziara's baseline) |
//! | [`within`] | within-margin: a certified bounding-box test, the rest by the distance pipeline |
//! | [`penalty`] | Krestenitis & Koziara's penalty method with a regularised Newton step |
//! | [`cert`] | the per-pair certificate: a rigorous interval `[lo, hi]` around the exact distance |
//! | [`nodes`] | the mesh traversal's node test: one node against a node's children, a lane per child |
//!
//! Precision policy (ARCHITECTURE.md; the long form docs/notes/precision.md):
//! - every query first scales its input by one power of two so that the largest absolute
//!   coordinate lies in [1, 2): the scaling is exact, so power-of-two scaling of the input scales
//!   the answer exactly, no intermediate (up to fourth powers of coordinates) can overflow or
//!   underflow, and every threshold below is relative to the pair's own magnitude;
//! - non-finite input gives NaN (checked up front, masked per lane);
//! - every division is guarded (`safe_div`), so degenerate segments and triangles give the
//!   distance of the point or segment they are instead of NaN;
//! - every answer carries a certificate ([`cert`]): an interval that provably contains the exact
//!   distance, whose width decides whether the answer is accepted or escalated.

pub(crate) mod cert;
pub(crate) mod fast;
pub(crate) mod nodes;

// Each query's algorithm file is declared by its registry line (`crate::query`), so adding a
// query touches that line and its file only.
macro_rules! declare_algorithm_files {
    ([] $($v:ident, $name:literal, $m:ident :: $k:ident, $about:literal;)*) => {
        $(pub(crate) mod $m;)*
    };
}
crate::query::for_each_query!(declare_algorithm_files);

macro_rules! query_arity {
    ([] $($v:ident, $name:literal, $m:ident :: $k:ident, $about:literal;)*) => {
        impl crate::Query {
            /// Points per primitive of the first and the second side (1 point, 2 segment,
            /// 3 triangle).
            pub fn arity(self) -> (usize, usize) {
                match self {
                    $(crate::Query::$v => (<$m::$k as Kernel>::KA, <$m::$k as Kernel>::KB),)*
                }
            }
        }
    };
}
crate::query::for_each_query!(query_arity);

use crate::lanes::{Cx, Lanes, Mask, V3};
use crate::real::Real;

/// Squared distance and a pair of closest points (first on the first primitive), prescaled.
#[derive(Clone, Copy)]
pub(crate) struct Res<L> {
    pub d: L,
    pub p: V3<L>,
    pub q: V3<L>,
}

/// What one stage of a query answers for a group of lanes, in the caller's units: the squared
/// distance `d`, closest points `p`, `q`, the certified interval `[lo, hi]` of the distance
/// (unsquared), whether the answer is accepted (`ok`: certified within the tolerance, or
/// non-finite input), and iterations (penalty method).
#[derive(Clone, Copy)]
pub(crate) struct Out<L: Lanes> {
    pub d: L,
    pub p: V3<L>,
    pub q: V3<L>,
    pub lo: L,
    pub hi: L,
    pub ok: L::M,
    pub it: L,
}

/// Per-job constants, in the working precision.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Params<S> {
    /// Within-margin: the margin.
    pub margin: S,
    /// Tolerance on the certified width: `scaled * S` (the pair's magnitude), `absolute`, and
    /// `relative * lo`; the largest applies.
    pub tol_scaled: S,
    pub tol_abs: S,
    pub tol_rel: S,
    /// Penalty method options (already validated).
    pub penalty: PenaltyParams<S>,
    /// Triangle-triangle distance runs its quick stage first ([`crate::Engine::quick_stage`]);
    /// off, every pair goes straight to the full fast stage.
    pub quick: bool,
    /// Triangle-triangle distance answers proven contacts with the exact interval `[0, 0]`: a
    /// vertex the input triangles share ([`fast::exact_at_shared_vertex`]) and, in f64, an edge
    /// crossing the other triangle ([`fast::prove_crossing`]). Set by the correctly rounded
    /// mode's f64 pass only, where it replaces a proof per pair (the compare alone cost the
    /// default tolerance 7-14 % on mesh neighbours, which it does not need).
    pub exact_contacts: bool,
}

impl<S: Real> Params<S> {
    /// The same parameters in another precision (f32 to f64 is exact; escalation widens).
    pub(crate) fn convert<W: Real>(&self) -> Params<W> {
        let c = |x: S| W::from_f64(x.to_f64());
        let p = &self.penalty;
        Params {
            margin: c(self.margin),
            tol_scaled: c(self.tol_scaled),
            tol_abs: c(self.tol_abs),
            tol_rel: c(self.tol_rel),
            penalty: PenaltyParams {
                rho: c(p.rho),
                reg: c(p.reg),
                tol: c(p.tol),
                max_iter: p.max_iter,
                start: p.start.map(c),
            },
            quick: self.quick,
            exact_contacts: self.exact_contacts,
        }
    }
}

/// Options of the penalty method, relative to the pair (see [`crate::PenaltyOptions`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct PenaltyParams<S> {
    pub rho: S,
    pub reg: S,
    pub tol: S,
    pub max_iter: u32,
    pub start: [S; 4],
}

/// One query's algorithm, as the batch driver runs it. Stage 0 runs on every pair. When
/// `STAGES == 3` (triangle-triangle distance), stage 0 is a quick stage on a few candidates,
/// stage 1 the full fast stage on the pairs stage 0 did not accept, gathered into full vectors
/// (lane compaction), and stage 2 the accurate stage on the pairs stage 1 did not accept,
/// gathered likewise; before the accurate stage, when `RECERT`, the previous stage's own answer
/// is re-certified with the tight certificate (the answer is usually right, only its first
/// interval too wide). Pairs still not accepted are handed to the full pipeline of the `NEXT`
/// query (same precision), or else re-run in f64 (`WIDEN`, f32 input only).
pub(crate) trait Kernel {
    /// Points per primitive of each side (1 point, 2 segment, 3 triangle).
    const KA: usize;
    const KB: usize;
    const STAGES: u8 = 1;
    const WIDEN: bool = true;
    const NEXT: Option<crate::Query> = None;
    /// Is stage 0's answer a distance with closest points, worth re-certifying tightly before
    /// anything is recomputed?
    const RECERT: bool = true;
    /// Must a tightly certified answer also be sharp ([`sharp_tight`]) to be accepted? (For a
    /// query whose later stages can do better; the last stage of a pipeline accepts on the
    /// tolerance alone, so that "uncertified" keeps meaning "interval wider than the
    /// tolerance".)
    const SHARP: bool = false;
    /// Runs stage `ST` on raw (unscaled) input.
    fn stage<L: Lanes, const ST: u8>(a: &[V3<L>; 3], b: &[V3<L>; 3], prm: &Params<L::S>) -> Out<L>;
}

/// Input scaled by a power of two: `pts[k] = input[k] / p` (`inv = 1 / p`); `m` is the largest
/// absolute coordinate of the input (the magnitude `S`, at least the smallest positive normal;
/// unspecified in non-finite lanes).
pub(crate) struct Scaled<L: Lanes, const K: usize> {
    pub pts: [V3<L>; K],
    pub p: L,
    pub inv: L,
    pub m: L,
    pub finite: L::M,
}

/// Scales all points by one power of two so that the largest absolute coordinate is in [1, 2)
/// (or below 1 for all-subnormal input). Exact except for coordinates that become subnormal,
/// which are then below 2^-126 (f32) of the largest one.
#[inline(always)]
pub(crate) fn prescale<L: Lanes, const K: usize>(pts: [V3<L>; K]) -> Scaled<L, K> {
    let k = Cx::of(pts[0].x);
    // The largest exponent of the coordinates (and of the smallest normal) by the integer
    // maximum of their bit patterns ([`Lanes::max_exp`]): it gives the power of two and
    // finiteness (no exponent field all ones: no NaN, no infinity), and it is on the path in
    // front of every lane's arithmetic, where a floating-point maximum takes four cycles to its
    // one (nearby Armadillo pairs: `spin tri_tri arm_nearby f32 avx2fma`, see docs/notes/kernel-speed.md).
    // The magnitude itself (thresholds at the end) is that maximum where it is exact (f32, and
    // f64 on AVX-512 and scalar: 18 operations fewer, `spin tri_tri arm_nearby f32 avx2fma`
    // 70.9-71.4 -> 72.4-72.6 M/s), else the floating-point maximum beside it.
    // Both reduced as trees (a chain of 3K dependent operations would lie on every lane's
    // critical path).
    const { assert!(K <= 6, "prescale takes at most six points") };
    let mut exps = [k.zero(); 18];
    let mut maxs = [k.zero(); 18];
    let mut n = 0;
    for v in &pts {
        for x in [v.x, v.y, v.z] {
            let a = x.abs();
            (exps[n], maxs[n]) = (a, a);
            n += 1;
        }
    }
    while n > 1 {
        let h = n / 2;
        for i in 0..h {
            exps[i] = exps[i].max_exp(exps[i + n - h]);
            maxs[i] = maxs[i].max(maxs[i + n - h]);
        }
        n -= h;
    }
    let tiny = k.splat(L::S::MIN_POSITIVE);
    let e = exps[0].max_exp(tiny);
    let m = if L::MAX_EXP_EXACT { e } else { maxs[0].max(tiny) };
    let finite = e.lt(k.inf());
    let (p, inv) = (e.exponent(), e.recip_exponent());
    let mut out = pts;
    for v in out.iter_mut() {
        *v = v.scale(inv);
    }
    if !finite.all() {
        // Keep NaN/inf out of the arithmetic (it would defeat the early exits); the lane's
        // result is replaced by NaN at the end.
        for v in out.iter_mut() {
            *v = V3::select(finite, *v, k.v0());
        }
    }
    Scaled { pts: out, p, inv, m, finite }
}

/// The raw points of a query as `KA + KB` prescaled points (unused slots are ignored).
#[inline(always)]
pub(crate) fn scale_pair<L: Lanes, const KA: usize, const KB: usize>(
    a: &[V3<L>; 3],
    b: &[V3<L>; 3],
) -> (Scaled<L, 6>, [V3<L>; 3], [V3<L>; 3]) {
    // Only the used points enter the magnitude: unused slots repeat a used point.
    let pts = [
        a[0],
        a[(KA > 1) as usize],
        a[2 * (KA > 2) as usize],
        b[0],
        b[(KB > 1) as usize],
        b[2 * (KB > 2) as usize],
    ];
    let sc = prescale(pts);
    let s = [sc.pts[0], sc.pts[1], sc.pts[2]];
    let t = [sc.pts[3], sc.pts[4], sc.pts[5]];
    (sc, s, t)
}

/// The pair in a local frame with `a[0]` at the origin, prescaled: `(x - a_0) / p` for every
/// vertex (the first exactly 0), and the origin `a_0 / p` to add back. The raw differences are
/// taken first and scaled after, so that the prescaling (the magnitude of 18 coordinates
/// reduced as a tree, and its power of two) runs beside the differences instead of in front
/// of them: the quick stage of triangle distance is bound by its dependency chains
/// (docs/notes/kernel-speed.md, "The critical path"). The bits are those of `x / p - a_0 / p` whenever no
/// scaled value is subnormal: rounding commutes with scaling by a power of two, and a
/// subnormal raw difference is exact. Where one is (coordinates below 2^-126 (f32) of the
/// pair's magnitude), this rounds once in the normal range and once when scaled, no more than
/// the other order's two underflows. A raw difference can overflow only when the magnitude
/// exceeds `MAX / 2` (`|x - a_0| <= 2 S`, and a rounded value of at most `MAX` stays at most
/// `MAX`): such lanes, and non-finite ones (zeroed by [`prescale`]), take the differences of
/// the scaled points, lane by lane, so a pair's answer never depends on its neighbours.
#[inline(always)]
pub(crate) fn local_pair<L: Lanes>(
    a: &[V3<L>; 3],
    b: &[V3<L>; 3],
    sc: &Scaled<L, 6>,
) -> ([V3<L>; 3], [V3<L>; 3], V3<L>) {
    let k = Cx::of(sc.inv);
    let (o, inv) = (a[0], sc.inv);
    let mut ls = [k.v0(), a[1].sub(o).scale(inv), a[2].sub(o).scale(inv)];
    let mut lt = [b[0].sub(o).scale(inv), b[1].sub(o).scale(inv), b[2].sub(o).scale(inv)];
    let odd = sc.m.gt(k.splat(L::S::MAX).mul(k.c(0.5))).or(sc.finite.not());
    let p = &sc.pts;
    if odd.any() {
        for i in 1..3 {
            ls[i] = V3::select(odd, p[i].sub(p[0]), ls[i]);
        }
        for i in 0..3 {
            lt[i] = V3::select(odd, p[3 + i].sub(p[0]), lt[i]);
        }
    }
    (ls, lt, p[0])
}

/// Finishes a stage: certifies `r` (prescaled) against the prescaled primitives
/// ([`cert::certify`]), decides acceptance, and undoes the scaling: squared distance times p^2, points and interval times p;
/// NaN for non-finite input lanes (accepted: nothing to escalate). Overflow of the squared
/// distance gives +inf (documented); the interval saturates to +inf alike.
#[inline(always)]
///
/// `s`, `t` and `r` are either prescaled or, for a stage that works in a local frame, relative
/// to `origin` (then `s[0]` must be exactly 0: the certificate's allowance for its own local
/// frame covers the stage's); `origin` is added back to the points.
pub(crate) fn finish<L: Lanes, const KA: usize, const KB: usize, const TIGHT: bool>(
    sc: &Scaled<L, 6>,
    s: &[V3<L>; 3],
    t: &[V3<L>; 3],
    origin: Option<V3<L>>,
    r: Res<L>,
    prm: &Params<L::S>,
) -> Out<L> {
    let c = if TIGHT {
        cert::certify_tight::<L, KA, KB>(s, t, r.p, r.q)
    } else {
        cert::certify::<L, KA, KB>(s, t, r.p, r.q)
    };
    // The answer must agree with its own points: a distance answer is its points' distance, a
    // contact answer (0) has its points together, within 8 u S. [`conclude`]'s interval test
    // alone cannot see an answer too small by less than `lo + 8 u S`: a false overlap (d = 0)
    // of the FMA variants' f32 separating-axis test, its points 23 u S apart, was accepted at
    // `lo^2` with E 16.7 (`fuzz/regressions/tri_tri/fma-f32-answer-at-lo-near-parallel`).
    // (The fast stage, which does not come here, has its own test of this, `FastOut::sharp`.)
    let reach = r.d.sqrt().add(rounding_allowance(sc));
    let own = r.p.sub(r.q).norm2().le(reach.mul(reach));
    conclude(sc, c.lo, c.hi, origin, r, prm, own)
}

/// The rounding an answer may show against its own interval and points: 8 u S, prescaled.
#[inline(always)]
fn rounding_allowance<L: Lanes>(sc: &Scaled<L, 6>) -> L {
    allowance(sc, 8.0)
}

/// `c u S`, prescaled (S the pair's largest absolute coordinate).
#[inline(always)]
pub(crate) fn allowance<L: Lanes>(sc: &Scaled<L, 6>, c: f64) -> L {
    let k = Cx::of(sc.m);
    k.u().mul(k.c(c)).mul(sc.m.mul(sc.inv))
}

/// Decides acceptance of an answer `r` with certified interval `[lo, hi]` (prescaled, points
/// relative to `origin` when given) and undoes the scaling (see [`finish`]). `sharp`: the
/// stage's own test that its answer agrees with its points (also required).
#[inline(always)]
pub(crate) fn conclude<L: Lanes>(
    sc: &Scaled<L, 6>,
    lo: L,
    hi: L,
    origin: Option<V3<L>>,
    r: Res<L>,
    prm: &Params<L::S>,
    sharp: L::M,
) -> Out<L> {
    let c = cert::Cert { lo, hi };
    // Accepted when the interval is within the tolerance *and* the algorithm's own distance is
    // consistent with it (within 8 u S, its own rounding): a wrong answer with a narrow
    // interval around the right one is not passed off as right.
    let k = Cx::of(c.lo);
    let eps = rounding_allowance(sc);
    let lo_e = c.lo.sub(eps).max(k.zero());
    let hi_e = c.hi.add(eps);
    let consistent = r.d.ge(lo_e.mul(lo_e)).and(r.d.le(hi_e.mul(hi_e)));
    let ok = accept(c.lo, c.hi, sc, prm).and(consistent).and(sharp);
    // The algorithm's own answer (exactly 0 for contact, accurately rounded otherwise; points
    // on their primitives up to rounding), its distance kept inside the certified interval
    // by `unscale`.
    let (p, q) = match origin {
        Some(o) => (r.p.add(o), r.q.add(o)),
        None => (r.p, r.q),
    };
    unscale(Res { d: r.d, p, q }, c.lo, c.hi, ok, sc)
}

/// Re-certifies an earlier stage's answer (raw units: squared distance `d`, points `p` on the
/// first primitive and `q` on the second) with the tight certificate: the driver's second pass
/// over the pairs whose first interval was too wide, before anything is recomputed.
#[inline(always)]
pub(crate) fn recertify<L: Lanes, const KA: usize, const KB: usize>(
    a: &[V3<L>; 3],
    b: &[V3<L>; 3],
    d: L,
    p: V3<L>,
    q: V3<L>,
    prm: &Params<L::S>,
    sharp: bool,
) -> Out<L> {
    let (sc, s, t) = scale_pair::<L, KA, KB>(a, b);
    let k = Cx::of(d);
    let inv = sc.inv;
    let (p, q) = (p.scale(inv), q.scale(inv));
    // An answer whose square overflowed in the caller's units (documented +inf) is the
    // witness's own squared distance here.
    let d = L::select(d.le(k.splat(L::S::MAX)), d.mul(inv).mul(inv), p.sub(q).norm2());
    let mut out = finish::<L, KA, KB, true>(&sc, &s, &t, None, Res { d, p, q }, prm);
    if sharp {
        out.ok = out.ok.and(sharp_tight(&sc, &out));
    }
    out
}

/// Relative slack of the tight certificate ([`cert::certify_tight`]: `|W|` rounded up by 4u,
/// the gap down by about 7.5u), rounded up: the width of the tight interval around an exact
/// answer, in units of `u` times the distance.
const TIGHT_REL: f64 = 12.0;
/// How far (in units of `u`, prescaled) the full fast stage's answer may be from its own gap
/// along its direction and still be accepted there ([`fast`]'s `certified`): a routing rule
/// (the excess is computed plainly, not an error bound), set at the E target of ACCURACY.md.
/// Answers beyond it go to the tight certificate, which bounds their error
/// ([`SHARP_TIGHT`]). (At 5.5, `spin tri_tri random f32 avx2fma 2` fell from 27 to 17 M/s
/// and `scenes/tests/paths.rs` re-certified 39 of 2000 random pairs instead of 23.)
pub(crate) const SHARP_E: f64 = 8.0;

/// How wide (in units of `u S`, beyond the certificate's own slack) a tightly certified
/// interval may be for its answer to be accepted before the last stage ([`sharp_tight`]): an
/// error bound, so below the loosest E row of the bound table (5.75 for f32 triangle pairs).
/// At 8 (the E target) the `tri_tri` fuzz target found an f32 segment touching a face
/// answered 6.77 u S away (exactly 0; `fuzz/regressions/tri_tri/segment-touching-face-*`).
/// At 5 no throughput is lost (`spin tri_tri random|near_parallel f32 avx2fma 2`, 8 and 5
/// alternated: 27.5-28.3 M/s and 19.7-20.2 M/s either way) and 0-2 of 2000 near-parallel
/// pairs more go to the accurate stage (`scenes/tests/paths.rs`).
pub(crate) const SHARP_TIGHT: f64 = 5.0;

/// Is the tightly certified answer in `out` (unscaled) sharp: its interval no wider than
/// `SHARP_TIGHT u S` plus the certificate's own slack? The interval bounds the answer's error,
/// so a sharp answer has `E <= SHARP_TIGHT + TIGHT_REL d / S`. A wider interval within the
/// tolerance means the algorithm answered a pair of points that is not the closest one (a
/// missed candidate: f32, a point over a long sliver whose inside tests failed by rounding,
/// answered 49 u S too far under the 64 u S default tolerance; found by `cargo fuzz run
/// tri_tri`): such a pair goes on to the accurate stage instead. Non-finite lanes are sharp
/// (nothing to improve).
#[inline(always)]
pub(crate) fn sharp_tight<L: Lanes>(sc: &Scaled<L, 6>, out: &Out<L>) -> L::M {
    let k = Cx::of(out.lo);
    let allowed = k.u().mul(k.c(SHARP_TIGHT).mul(sc.m).add(k.c(TIGHT_REL).mul(out.hi)));
    out.hi.sub(out.lo).gt(allowed).not().or(sc.finite.not())
}

/// Is the certified width `hi - lo` (prescaled) within the tolerance? `!(width > tol)`, so NaN
/// (non-finite input) is accepted.
#[inline(always)]
pub(crate) fn accept<L: Lanes>(lo: L, hi: L, sc: &Scaled<L, 6>, prm: &Params<L::S>) -> L::M {
    let k = Cx::of(lo);
    let inv = sc.inv;
    let tol = k
        .splat(prm.tol_scaled)
        .mul(sc.m.mul(inv))
        .max(k.splat(prm.tol_abs).mul(inv))
        .max(k.splat(prm.tol_rel).mul(lo));
    hi.sub(lo).gt(tol).not()
}

/// Undoes [`prescale`]: see [`finish`].
#[inline(always)]
pub(crate) fn unscale<L: Lanes>(r: Res<L>, lo: L, hi: L, ok: L::M, sc: &Scaled<L, 6>) -> Out<L> {
    let k = Cx::of(r.d);
    let p = sc.p;
    // d*p is exact while normal; when it is subnormal (p < 1, tiny d) its rounding error is
    // below 2^-150 and is then multiplied by p < 1 again, far below the final rounding. So the
    // result is the correctly rounded d*p^2 except in double-rounding ties.
    let d = r.d.mul(p).mul(p);
    // lo*p, hi*p are exact unless subnormal; then one subnormal step keeps them outward. (An
    // exact `hi` of 0, a proven contact, stays exact.)
    let tiny = k.splat(<L::S as crate::real::sealed::Sealed>::TINY);
    let lo = lo.mul(p).sub(tiny).max(k.zero());
    let hi = L::select(hi.eq(k.zero()), hi, hi.mul(p).add(tiny));
    // The answer kept between the squares of `lo` and `hi`, each rounded once, so that it is
    // the square of a distance in the interval (the tolerance's guarantee). Clamped here, in
    // the caller's units, not before unscaling: where everything is normal the two give the
    // same bits (p is a power of two), but a prescaled square below the normal range has lost
    // its bits (a distance under about `sqrt(MIN_POSITIVE) S`, e.g. 1 apart at 3e38 in f32,
    // squared to 0), and so has a clamp to a subnormal prescaled `hi^2`, which rounds up by up
    // to half a subnormal step, times p^2 here: an f32 point 1.125 from a triangle at S 7.4e19
    // was answered 5.0625076 with hi 2.2500014 when only the lower end was clamped here
    // (`fuzz/regressions/point_tri/scalar-f32-answer-above-hi-subnormal-square`).
    let d = d.max(lo.mul(lo)).min(hi.mul(hi));
    let nan = k.nan();
    let nan3 = V3::splat(nan);
    let f = sc.finite;
    Out {
        d: L::select(f, d, nan),
        p: V3::select(f, r.p.scale(p), nan3),
        q: V3::select(f, r.q.scale(p), nan3),
        lo: L::select(f, lo, nan),
        hi: L::select(f, hi, nan),
        ok: ok.or(f.not()),
        it: k.zero(),
    }
}

/// NaN answers (verdict, interval) for non-finite input lanes, which are accepted: nothing to
/// escalate. For stages whose output is not a scaled distance (the intersection verdict).
#[inline(always)]
pub(crate) fn nan_where_invalid<L: Lanes>(o: Out<L>, sc: &Scaled<L, 6>) -> Out<L> {
    let nan = Cx::of(o.d).nan();
    let f = sc.finite;
    Out {
        d: L::select(f, o.d, nan),
        lo: L::select(f, o.lo, nan),
        hi: L::select(f, o.hi, nan),
        ok: o.ok.or(f.not()),
        ..o
    }
}

/// Keeps the better (smaller squared distance) of two results per lane.
#[inline(always)]
pub(crate) fn keep_min<L: Lanes>(best: &mut Res<L>, cand: Res<L>) {
    let better = cand.d.lt(best.d);
    *best = L::select_res(better, cand, *best);
}

#[inline(always)]
pub(crate) fn swap<L: Lanes>(r: Res<L>) -> Res<L> {
    Res { d: r.d, p: r.q, q: r.p }
}

#[inline(always)]
pub(crate) fn edges<L: Lanes>(t: &[V3<L>; 3]) -> [V3<L>; 3] {
    [t[1].sub(t[0]), t[2].sub(t[1]), t[0].sub(t[2])]
}

/// The two edges of a triangle that meet opposite its longest edge (`e` = [`edges`]), in
/// counter-clockwise order: the best-conditioned pair for its normal. At a needle's tip both
/// edges are long and nearly parallel, and their own rounding swamps the cross product (fuzzing
/// found a point 15 u S beside a needle of tip angle 1e-16 reported touching it).
#[inline(always)]
pub(crate) fn normal_pair<L: Lanes>(e: &[V3<L>; 3]) -> (V3<L>, V3<L>) {
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

/// Is the triangle with edges `e` ([`edges`]) degenerate? True when its normal is below the
/// rounding noise of the cross product of its best-conditioned edge pair (relative test), or
/// below the smallest normal number, where the products' underflow (an absolute error of up to
/// one subnormal step each) leaves its direction wrong by more than that noise. Input is
/// prescaled (largest coordinate about 1), so such a triangle is narrower than
/// `sqrt(MIN_POSITIVE)`, far below `u`: handling it as the union of its edges costs nothing.
#[inline(always)]
pub(crate) fn degenerate<L: Lanes>(e: &[V3<L>; 3]) -> L::M {
    // Unsquared (max-)norms: squares of a needle's width underflow.
    let (a, b) = normal_pair(e);
    let n = a.cross(b).norm_inf();
    let k = Cx::of(a.x);
    let tol = k.u().mul(k.c(16.0));
    // Found by fuzzing (f64, no FMA): a sliver 2e-323 wide whose normal's small component
    // underflowed to 0, tilting the plane onto a point 0.0039 away, answered 0.
    n.le(a.norm_inf().mul(b.norm_inf()).mul(tol)).or(n.lt(k.splat(L::S::MIN_POSITIVE)))
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
    let gap = lo_t.sub(hi_s).max(lo_s.sub(hi_t)).max(Cx::of(lo_s).zero());
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

#[cfg(test)]
mod tests {
    use super::*;

    /// [`local_pair`] gives the differences of the scaled points, bit for bit and finite, on
    /// pairs of ordinary, huge, tiny and near-`MAX` magnitude (there every raw difference
    /// across the origin overflows: the lanes that must take the scaled points' differences).
    fn local_pair_is_the_scaled_difference<S: Real + Lanes<S = S>>() -> usize {
        let mut checked = 0;
        let big = S::MAX * S::from_f64(0.75);
        for (mag, i) in [(S::from_f64(1.0), 0), (S::from_f64(1e30), 1), (S::from_f64(1e-30), 2), (big, 3)] {
            let c = |x: f64| S::from_f64(x) * mag;
            // a near -mag, b near +mag, with distinct coordinates of both signs
            let a = [[-1.0, 0.1, 0.0], [-0.75, 0.25, -0.5], [-0.75, -0.25, 0.5]].map(|p| p.map(c));
            let b = [[1.0, 0.0, 0.1], [0.75, -0.25, 0.5], [0.625, 0.25, -0.5]].map(|p| p.map(c));
            let v = |p: [S; 3]| V3::new(p[0], p[1], p[2]);
            let (a, b) = (a.map(v), b.map(v));
            let sc = prescale([a[0], a[1], a[2], b[0], b[1], b[2]]);
            let (ls, lt, o) = local_pair(&a, &b, &sc);
            let p = &sc.pts;
            for (j, got) in ls.iter().chain(&lt).enumerate() {
                let want = p[j].sub(p[0]);
                for (g, w) in [(got.x, want.x), (got.y, want.y), (got.z, want.z)] {
                    assert!(g.is_finite(), "case {i} point {j}: {g:?}");
                    assert_eq!(g.bits(), w.bits(), "case {i} point {j}");
                    checked += 1;
                }
            }
            assert_eq!((o.x.bits(), o.y.bits(), o.z.bits()), (p[0].x.bits(), p[0].y.bits(), p[0].z.bits()));
        }
        checked
    }

    #[test]
    fn local_pair_is_the_scaled_difference_at_every_magnitude() {
        assert_eq!(local_pair_is_the_scaled_difference::<f32>(), 4 * 6 * 3);
        assert_eq!(local_pair_is_the_scaled_difference::<f64>(), 4 * 6 * 3);
    }
}
