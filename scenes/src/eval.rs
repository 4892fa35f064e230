//! The differential harness: run a kernel variant over cases, judge it against the oracle with
//! the metrics of ACCURACY.md (and its certified intervals against the exact distance), and
//! summarise. Shared by `cargo test`, the fuzz targets and the accuracy report.
//!
//! Queries come from the kernels' registry ([`Query`]): the harness maps a query to its
//! primitives by its arity (triangle pairs, segment pairs, point-triangle pairs), so a new
//! query of an existing arity needs nothing here.

use rug::Rational;
use tridist::{Engine, Intersection, Interval, Isa, Outputs, PathCounts, Point, Prims, Query};
use tridist_oracle::metrics::{self, Precision};

use crate::families::{self, Case};
use crate::float::Float;

/// A kernel variant: instruction set and layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Variant {
    /// Scalar over plain arrays (the paper's "non-SIMD layout").
    Scalar,
    /// Scalar over SoA columns (the paper's "SIMD layout").
    Soa,
    /// SSE4.1 over SoA.
    Sse41,
    /// AVX (no FMA) over SoA.
    Avx,
    /// AVX2 + FMA over SoA.
    Avx2Fma,
    /// AVX-512VL over SoA: AVX2 + FMA's 256-bit vectors with 32 registers (fused).
    Avx512Vl,
    /// AVX-512 over SoA (fused, as AVX2 + FMA).
    Avx512,
}

impl Variant {
    /// Every variant.
    pub const ALL: [Variant; 7] = [
        Variant::Scalar,
        Variant::Soa,
        Variant::Sse41,
        Variant::Avx,
        Variant::Avx2Fma,
        Variant::Avx512Vl,
        Variant::Avx512,
    ];
    /// Short name.
    pub fn name(self) -> &'static str {
        match self {
            Variant::Scalar => "scalar",
            Variant::Soa => "soa",
            Variant::Sse41 => "sse41",
            Variant::Avx => "avx",
            Variant::Avx2Fma => "avx2fma",
            Variant::Avx512Vl => "avx512vl",
            Variant::Avx512 => "avx512",
        }
    }
    /// Parses [`Variant::name`] (`auto` is [`Variant::auto`]).
    pub fn parse(s: &str) -> Option<Variant> {
        Variant::ALL.into_iter().find(|v| v.name() == s)
    }
    /// The SoA variant of the instruction set `TRIDIST_ISA` names, or of the best available
    /// one when it is unset or empty ([`tridist::Engine::from_env`]: a name that is no usable
    /// variant is an error, not `Engine::auto`'s fallback).
    pub fn auto() -> Result<Variant, tridist::Error> {
        tridist::Engine::from_env().map(|e| Variant::from_isa(e.isa()))
    }
    /// The instruction set it runs.
    pub fn isa(self) -> Isa {
        match self {
            Variant::Scalar | Variant::Soa => Isa::Scalar,
            Variant::Sse41 => Isa::Sse41,
            Variant::Avx => Isa::Avx,
            Variant::Avx2Fma => Isa::Avx2Fma,
            Variant::Avx512Vl => Isa::Avx512Vl,
            Variant::Avx512 => Isa::Avx512,
        }
    }
    /// The SoA variant of an instruction set.
    pub fn from_isa(i: Isa) -> Variant {
        match i {
            Isa::Scalar => Variant::Soa,
            Isa::Sse41 => Variant::Sse41,
            Isa::Avx => Variant::Avx,
            Isa::Avx2Fma => Variant::Avx2Fma,
            Isa::Avx512Vl => Variant::Avx512Vl,
            Isa::Avx512 => Variant::Avx512,
            // `Isa` is non-exhaustive: a variant added to the library needs its row here (the
            // suite enumerates `Isa::ALL`, so the first test run names it).
            other => unimplemented!("the harness has no variant for the instruction set {other}"),
        }
    }
    /// Can this CPU run it?
    pub fn available(self) -> bool {
        self.isa().is_available()
    }
    /// Does it fuse multiply-adds (different rounding from the unfused variants)?
    pub fn fused(self) -> bool {
        matches!(self, Variant::Avx2Fma | Variant::Avx512Vl | Variant::Avx512)
    }
    /// The engine (default tolerance).
    ///
    /// # Errors
    /// When the variant is unavailable.
    pub fn engine(self) -> Result<Engine, tridist::Error> {
        Engine::new(self.isa())
    }
    /// The engine a check runs this variant on, or `None` to skip it: only a variant this CPU
    /// lacks is skipped, and not when the run requires its instruction set
    /// ([`required_isas`], `TRIDIST_REQUIRE_ISA`): then, as for any other error, this panics
    /// with the reason, so a check cannot pass having compared nothing on the CPU it claims.
    pub fn engine_or_skip(self) -> Option<Engine> {
        match self.engine() {
            Ok(e) => Some(e),
            Err(tridist::Error::Unavailable(isa)) if !required_isas().contains(&isa) => None,
            Err(e) => panic!(
                "variant {} cannot run: {e} (required by {REQUIRE_ENV}: {:?})",
                self.name(),
                required_isas()
            ),
        }
    }
}

/// The environment variable that names the instruction sets a run must exercise: a
/// comma-separated list of [`tridist::Isa`] names (`avx2fma,avx512`), or `detected` for every
/// one this CPU runs ([`OPT_IN`] variants only where compiled in). CI sets it, so that "skipped: the CPU lacks it" cannot hide a variant
/// that the machine has (or a build that left it out).
pub const REQUIRE_ENV: &str = "TRIDIST_REQUIRE_ISA";

/// The variants compiled only on request (the library's features `avx` and `avx512vl`; this
/// crate's `all-variants`).
pub const OPT_IN: [Isa; 2] = [Isa::Avx, Isa::Avx512Vl];

/// The instruction sets this run must exercise ([`REQUIRE_ENV`]; none when unset). An unknown
/// name panics: a typo must not turn the requirement off.
pub fn required_isas() -> Vec<Isa> {
    let Ok(s) = std::env::var(REQUIRE_ENV) else { return vec![] };
    let mut out = vec![];
    for name in s.split(',').map(str::trim).filter(|n| !n.is_empty()) {
        if name == "detected" {
            out.extend(Isa::ALL.into_iter().filter(|i| {
                // What the CPU runs, compiled or not: a variant left out of the build fails. The
                // opt-in variants (features `avx`, `avx512vl`, this crate's `all-variants`) are
                // required where compiled in; the build that turns them on checks that it did
                // (tests/opt_in.rs).
                if !i.is_compiled() && OPT_IN.contains(i) {
                    return false;
                }
                let mut all = *i == Isa::Scalar;
                #[cfg(target_arch = "x86_64")]
                {
                    all |= match i {
                        Isa::Sse41 => std::is_x86_feature_detected!("sse4.1"),
                        Isa::Avx => std::is_x86_feature_detected!("avx"),
                        Isa::Avx2Fma => {
                            std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")
                        }
                        Isa::Avx512Vl => {
                            std::is_x86_feature_detected!("avx512f")
                                && std::is_x86_feature_detected!("avx512vl")
                        }
                        Isa::Avx512 => std::is_x86_feature_detected!("avx512f"),
                        _ => false,
                    };
                }
                all
            }));
        } else {
            out.push(
                Isa::parse(name).unwrap_or_else(|| panic!("{REQUIRE_ENV}: unknown instruction set {name:?}")),
            );
        }
    }
    out
}

/// What a kernel returned for a batch.
#[derive(Clone, Debug, Default)]
pub struct Output<T> {
    /// Squared distances (within-margin: `+inf` beyond the margin; intersection: 0 for
    /// intersecting, 1 for disjoint, NaN for invalid).
    pub d: Vec<T>,
    /// Distances, when asked for ([`run_with_distances`]; a peer's output carries its own;
    /// empty otherwise): the square root of `d`, except under the correctly rounded mode,
    /// where it is decided on its own ([`tridist::Outputs::distances`]); verdict queries: NaN.
    pub dist: Vec<T>,
    /// First closest points.
    pub p: Vec<Point<T>>,
    /// Second closest points.
    pub q: Vec<Point<T>>,
    /// Certified intervals.
    pub iv: Vec<Interval<T>>,
    /// Intersection verdicts.
    pub verdict: Vec<Intersection>,
    /// Whether each pair met the engine's tolerance ([`tridist::Outputs::certified`]; under
    /// the correctly rounded mode, `false` for an undecided pair).
    pub certified: Vec<bool>,
    /// Which path the pairs took.
    pub counts: PathCounts,
}

impl<T: Float> Output<T> {
    /// `n` pairs' worth of zeros (verdicts `Invalid`, no paths counted; distances NaN when
    /// asked for, else none), to be written.
    fn zeroed(n: usize, distances: bool) -> Self {
        Output {
            d: vec![T::ZERO; n],
            dist: vec![T::NAN; if distances { n } else { 0 }],
            p: vec![[T::ZERO; 3]; n],
            q: vec![[T::ZERO; 3]; n],
            iv: vec![Interval::default(); n],
            verdict: vec![Intersection::Invalid; n],
            certified: vec![false; n],
            counts: PathCounts::default(),
        }
    }
}

/// The primitives of a case for a query, as `K`-point arrays padded to 3 (by arity: triangle
/// pairs as they are, segment pairs from edge 0 of each triangle, point-triangle from vertex 0
/// of `b` against `a`).
pub fn prims<T: Float>(query: Query, c: &Case<T>) -> ([Point<T>; 3], [Point<T>; 3]) {
    match query.arity() {
        (2, 2) => {
            let (a, b) = families::segments(c);
            ([a[0], a[1], a[0]], [b[0], b[1], b[0]])
        }
        (1, 3) => {
            let (p, t) = families::point_triangle(c);
            ([p; 3], t)
        }
        _ => (c.a, c.b),
    }
}

/// The within-margin margin used for a case when none is given: an eighth of its magnitude.
pub fn default_margin<T: Float>(c: &Case<T>) -> T {
    let s = c.a.iter().chain(c.b.iter()).flatten().fold(0.0f64, |m, x| m.max(x.to_f64().abs()));
    T::from_f64(s / 8.0)
}

/// Runs `query` with `variant` over `cases`, asking for every output the query has but
/// distances ([`Output::dist`] is left empty: see [`run_with_distances`]). Within-margin runs
/// each case with its own margin (`margins`, else [`default_margin`]).
///
/// # Errors
/// When the variant is unavailable.
pub fn run<T: Float>(
    query: Query,
    variant: Variant,
    cases: &[Case<T>],
    margins: Option<&[T]>,
) -> Result<Output<T>, tridist::Error> {
    run_with(variant.engine()?, query, variant, cases, margins)
}

/// [`run`] on a given engine (its tolerance, penalty options).
///
/// # Errors
/// As the batch API.
pub fn run_with<T: Float>(
    e: Engine,
    query: Query,
    variant: Variant,
    cases: &[Case<T>],
    margins: Option<&[T]>,
) -> Result<Output<T>, tridist::Error> {
    run_asking(e, query, variant, cases, margins, false)
}

/// [`run_with`] asking for distances too ([`tridist::Outputs::distances`]): under the
/// correctly rounded mode a pair is then certified only when its distance is decided as well
/// as its square.
///
/// # Errors
/// As the batch API.
pub fn run_with_distances<T: Float>(
    e: Engine,
    query: Query,
    variant: Variant,
    cases: &[Case<T>],
    margins: Option<&[T]>,
) -> Result<Output<T>, tridist::Error> {
    run_asking(e, query, variant, cases, margins, true)
}

fn run_asking<T: Float>(
    e: Engine,
    query: Query,
    variant: Variant,
    cases: &[Case<T>],
    margins: Option<&[T]>,
    distances: bool,
) -> Result<Output<T>, tridist::Error> {
    if query == Query::Within {
        let mut o = Output::zeroed(cases.len(), distances);
        for (i, c) in cases.iter().enumerate() {
            let m = margins.map_or_else(|| default_margin(c), |m| m[i]);
            let one = run_pairs(e.margin(m.to_f64()), query, variant, std::slice::from_ref(c), distances)?;
            o.d[i] = one.d[0];
            if distances {
                o.dist[i] = one.dist[0];
            }
            o.p[i] = one.p[0];
            o.q[i] = one.q[0];
            o.iv[i] = one.iv[0];
            o.verdict[i] = one.verdict[0];
            o.certified[i] = one.certified[0];
            o.counts.add(&one.counts);
        }
        return Ok(o);
    }
    run_pairs(e, query, variant, cases, distances)
}

fn run_pairs<T: Float>(
    e: Engine,
    query: Query,
    variant: Variant,
    cases: &[Case<T>],
    distances: bool,
) -> Result<Output<T>, tridist::Error> {
    let mut o = Output::zeroed(cases.len(), distances);
    let (pa, pb): (Vec<_>, Vec<_>) = cases.iter().map(|c| prims(query, c)).unzip();
    // a verdict query computes no distance: asking it for one is an error
    let out = if query.is_verdict() {
        Outputs::new().verdicts(&mut o.verdict).certified(&mut o.certified)
    } else {
        let out = Outputs::new().sqdist(&mut o.d);
        let out = if distances { out.distances(&mut o.dist) } else { out };
        out.points(&mut o.p, &mut o.q)
            .intervals(&mut o.iv)
            .verdicts(&mut o.verdict)
            .certified(&mut o.certified)
    };
    o.counts = match query.arity() {
        (2, 2) => {
            let a: Vec<[Point<T>; 2]> = pa.iter().map(|t| [t[0], t[1]]).collect();
            let b: Vec<[Point<T>; 2]> = pb.iter().map(|t| [t[0], t[1]]).collect();
            run_layout(e, query, variant, &a, &b, out)?
        }
        (1, 3) => {
            let a: Vec<[Point<T>; 1]> = pa.iter().map(|t| [t[0]]).collect();
            run_layout(e, query, variant, &a, &pb, out)?
        }
        _ => run_layout(e, query, variant, &pa, &pb, out)?,
    };
    if query.is_verdict() {
        o.d = o
            .verdict
            .iter()
            .map(|v| match v {
                Intersection::Intersecting => T::ZERO,
                Intersection::Disjoint => T::ONE,
                Intersection::Invalid => T::NAN,
            })
            .collect();
    }
    Ok(o)
}

/// The variant's layout: plain slices for the scalar AoS variant, SoA batches otherwise.
fn run_layout<T: Float, const KA: usize, const KB: usize>(
    e: Engine,
    query: Query,
    variant: Variant,
    a: &[[Point<T>; KA]],
    b: &[[Point<T>; KB]],
    out: Outputs<'_, T>,
) -> Result<PathCounts, tridist::Error> {
    if variant == Variant::Scalar {
        e.run(query, Prims::Aos(a), Prims::Aos(b), out)
    } else {
        let (ba, bb) = (tridist::Batch::from_slice(a), tridist::Batch::from_slice(b));
        e.run(query, &ba, &bb, out)
    }
}

/// The exact answer for one case.
#[derive(Clone, Debug)]
pub struct Truth {
    /// Exact squared distance (0 for overlapping triangles).
    pub d2: Rational,
    /// The magnitude S of the query's input.
    pub s: f64,
}

/// The oracle's view of precision `T`.
pub fn prec<T: Float>() -> Precision {
    crate::float::metrics_precision(T::PRECISION)
}

/// The primitives (as exact points) of a case for a query: (first, second).
pub fn exact_prims<T: Float>(
    query: Query,
    c: &Case<T>,
) -> (Vec<tridist_oracle::P3>, Vec<tridist_oracle::P3>) {
    let (ka, kb) = query.arity();
    let (a, b) = prims(query, c);
    let ex = |v: &[Point<T>]| -> Vec<tridist_oracle::P3> {
        v.iter()
            .map(|p| {
                tridist_oracle::exact_point(&p.map(|x| x.to_f64())).expect("families generate finite input")
            })
            .collect()
    };
    (ex(&a[..ka]), ex(&b[..kb]))
}

/// The exact squared distance of two primitives given as exact points.
pub fn exact_d2(a: &[tridist_oracle::P3], b: &[tridist_oracle::P3]) -> Rational {
    match (a.len(), b.len()) {
        (2, 2) => {
            tridist_oracle::segment_segment(&[a[0].clone(), a[1].clone()], &[b[0].clone(), b[1].clone()]).d2
        }
        (1, 3) => tridist_oracle::point_triangle(&a[0], &[b[0].clone(), b[1].clone(), b[2].clone()]).d2,
        _ => {
            tridist_oracle::triangle_triangle(
                &[a[0].clone(), a[1].clone(), a[2].clone()],
                &[b[0].clone(), b[1].clone(), b[2].clone()],
            )
            .d2
        }
    }
}

/// `RN(D*)`: an exact squared distance rounded to nearest (ties to even) in `T`, what
/// [`tridist::Tolerance::CORRECTLY_ROUNDED`] must return.
pub fn rn<T: Float>(d2: &Rational) -> T {
    match T::PRECISION {
        tridist::Precision::F32 => T::from_f64(tridist_oracle::round::to_f32(d2) as f64),
        tridist::Precision::F64 => T::from_f64(tridist_oracle::round::to_f64(d2)),
    }
}

/// `RN(sqrt(D*))` in `T`: the exact distance correctly rounded.
pub fn rn_sqrt<T: Float>(d2: &Rational) -> T {
    let r = match T::PRECISION {
        tridist::Precision::F32 => tridist_oracle::round::sqrt_to_f32(d2).map(f64::from),
        tridist::Precision::F64 => tridist_oracle::round::sqrt_to_f64(d2),
    };
    r.map_or(T::NAN, T::from_f64)
}

/// Computes the exact answers for `cases` under `query`.
pub fn truth<T: Float>(query: Query, cases: &[Case<T>]) -> Vec<Truth> {
    cases
        .iter()
        .map(|c| {
            let (a, b) = exact_prims(query, c);
            let (ka, kb) = query.arity();
            let (pa, pb) = prims(query, c);
            let coords = pa[..ka].iter().chain(pb[..kb].iter()).flatten().map(|x| x.to_f64());
            Truth { d2: exact_d2(&a, &b), s: metrics::magnitude(coords, prec::<T>()) }
        })
        .collect()
}

/// The contact tolerance `c` of ACCURACY.md's contact classification, in units of `u*S`.
pub const CONTACT_C: f64 = 8.0;

/// The judgement of one case.
#[derive(Clone, Debug, Default)]
pub struct Judged {
    /// Excess E over the correctly rounded answer (distance queries), 0 for intersection.
    pub excess: f64,
    /// ULP error of the squared distance, where meaningful.
    pub ulp: Option<f64>,
    /// Exact distance 0, kernel says more than `c*u*S` (or "disjoint" for intersection).
    pub contact_miss: bool,
    /// Exact distance beyond `c*u*S`, kernel says 0 (or "overlap").
    pub false_zero: bool,
    /// Exact distance positive (not rounding to 0), kernel says exactly 0 (or "overlap").
    pub false_zero_strict: bool,
    /// Non-finite output for finite input (the documented overflow outcome excepted).
    pub nonfinite: bool,
    /// Largest offset of a returned closest point from its primitive (scaled), and the error of
    /// `|p - q|` against the exact distance (scaled).
    pub point_error: f64,
    /// The certified interval misses the exact distance, or the answer is not the square of a
    /// distance in it, rounded once ([`answer_in_interval`]).
    pub interval_miss: bool,
    /// Width of the certified interval, scaled by `u*S` (0 for non-finite or verdict answers).
    pub width: f64,
    /// Intersection verdict, or within-margin decision, wrong beyond its allowance: for a
    /// verdict, "intersecting" said of a pair farther than `c u S`, or "disjoint" of a pair
    /// whose penetration no translation of `c u S` removes (decided exactly); for within-margin,
    /// the wrong side of a margin farther than `c u S` away.
    pub misjudged: bool,
}

/// Does the interval contain the exact distance (`lo^2 <= d2 <= hi^2`, lo, hi >= 0)?
pub fn interval_contains(iv: &Interval<impl Float>, d2: &Rational) -> bool {
    let (lo, hi) = (iv.lo.to_f64(), iv.hi.to_f64());
    if !(lo >= 0.0 && hi >= lo) {
        return false;
    }
    let sq = |x: f64| Rational::from_f64(x).map(|r| Rational::from(&r * &r));
    let lo_ok = sq(lo).is_some_and(|l| l <= *d2);
    let hi_ok = hi == f64::INFINITY || sq(hi).is_some_and(|h| *d2 <= h);
    lo_ok && hi_ok
}

/// Is a finite squared distance `d` the square of a distance in the interval, rounded once
/// (what `Tolerance` documents of every certified answer): `lo^2 (1 - u) - t <= d <= hi^2 (1 +
/// u) + t`, exactly, `u` the unit roundoff and `t` the smallest subnormal of the precision
/// (round to nearest errs by at most `u` relative, or half a subnormal step where the square
/// underflows)? An infinite `hi` bounds nothing above. A non-finite answer passes: it is
/// judged as a non-finite output or the documented overflow instead.
pub fn answer_in_interval<T: Float>(iv: &Interval<T>, d: T) -> bool {
    let (lo, hi, d) = (iv.lo.to_f64(), iv.hi.to_f64(), d.to_f64());
    if !d.is_finite() {
        return true;
    }
    let (Some(lr), Some(dr)) = (Rational::from_f64(lo), Rational::from_f64(d)) else {
        return false;
    };
    let u = Rational::from_f64(prec::<T>().u).unwrap_or_default();
    let t = Rational::from_f64(T::from_bits_u64(1).to_f64()).unwrap_or_default();
    let one = Rational::from(1);
    let below = Rational::from(&lr * &lr) * Rational::from(&one - &u) - &t;
    let above = Rational::from_f64(hi).map(|h| Rational::from(&h * &h) * Rational::from(&one + &u) + &t);
    below <= dr && above.is_none_or(|a| dr <= a)
}

/// Judges one kernel output against the truth. `c` is the allowance (in `u S`) of verdicts
/// and margin decisions (bound table), `margin` the within-margin margin of the case.
pub fn judge<T: Float>(
    query: Query,
    c: &Case<T>,
    t: &Truth,
    out: &Output<T>,
    i: usize,
    allow: f64,
    margin: Option<T>,
) -> Judged {
    let pr = prec::<T>();
    let d = out.d[i].to_f64();
    // exactly: `u S` underflows in f64 where S is near the smallest normal ([`metrics::c_us`])
    let allow_r = metrics::c_us(allow, t.s, pr);
    if query.is_verdict() {
        let exact_hit = t.d2 == 0;
        let said = out.verdict[i].as_bool();
        let (miss, false_hit) = (exact_hit && said == Some(false), !exact_hit && said == Some(true));
        let misjudged = if false_hit {
            t.d2 > Rational::from(&allow_r * &allow_r)
        } else if miss {
            let (a, b) = exact_prims(query, c);
            let tri = |v: &[tridist_oracle::P3]| [v[0].clone(), v[1].clone(), v[2].clone()];
            !tridist_oracle::penetration_at_most(&tri(&a), &tri(&b), &allow_r)
        } else {
            false
        };
        // A verdict is wrong when it is on the wrong side farther than the row's allowance
        // from a change of verdict (misjudged); a wrong side within it is only counted strictly.
        return Judged {
            contact_miss: miss && misjudged,
            false_zero: false_hit && misjudged,
            false_zero_strict: false_hit,
            nonfinite: said.is_none(),
            misjudged,
            ..Judged::default()
        };
    }
    let mut j = Judged::default();
    // The certified interval (every distance query, penalty included).
    let iv = &out.iv[i];
    j.interval_miss = !interval_contains(iv, &t.d2) || !answer_in_interval(iv, out.d[i]);
    // In u S, dividing by S first (u S underflows for subnormal inputs); an infinite hi is an
    // infinite width (nothing certified).
    let w = iv.hi.to_f64() - iv.lo.to_f64();
    j.width = if w == 0.0 {
        0.0
    } else if t.s > 0.0 {
        w / t.s / pr.u
    } else {
        f64::INFINITY
    };
    if query == Query::Within {
        let m = margin.map_or(0.0, |m| m.to_f64());
        let m2 = Rational::from_f64(m).map(|r| Rational::from(&r * &r)).unwrap_or_default();
        let within = t.d2 <= m2;
        let said = d.is_finite();
        // the square of `m + x` (0 below 0), exactly
        let near = |x: &Rational| {
            let r = Rational::from_f64(m).unwrap_or_default() + x;
            if r < 0 {
                Rational::new()
            } else {
                Rational::from(&r * &r)
            }
        };
        if said != within {
            // The wrong side is allowed within `allow u S` of the margin, and where the squares
            // (what the caller compares) are within a few subnormal steps of each other: the
            // documented underflow of squared distances.
            let tiny = T::from_bits_u64(1).to_f64();
            let squares_close =
                Rational::from(&t.d2 - &m2).abs() <= Rational::from_f64(4.0 * tiny).unwrap_or_default();
            j.misjudged =
                !squares_close && (t.d2 > near(&allow_r) || t.d2 < near(&Rational::from(-&allow_r)));
        }
        if !said {
            return j;
        }
    }
    let overflow = pr.round(&t.d2).is_infinite();
    // +inf is documented where the squared distance, or an answer within the method's error
    // bound (the E target; 8 S for the penalty approximation, as in the bound table), overflows.
    let reach = if query == Query::Penalty { 8.0 / pr.u } else { metrics::OVERFLOW_REACH };
    let documented_overflow = d == f64::INFINITY && metrics::overflow_allowed(&t.d2, t.s, pr, reach);
    j.nonfinite = !(d.is_finite() || documented_overflow);
    j.excess = metrics::excess_within(d, &t.d2, t.s, pr, reach);
    if !overflow && d.is_finite() {
        let (a, b) = exact_prims(query, c);
        let p = out.p[i].map(|x| x.to_f64());
        let q = out.q[i].map(|x| x.to_f64());
        j.point_error = metrics::point_offset(p, &a, t.s, pr)
            .max(metrics::point_offset(q, &b, t.s, pr))
            .max(metrics::gap_error(p, q, &t.d2, t.s, pr));
    }
    j.ulp = metrics::ulp_error(d, &t.d2, t.s, pr);
    j.contact_miss = metrics::contact_miss(d, &t.d2, t.s, pr, CONTACT_C);
    j.false_zero = metrics::false_zero(d, &t.d2, t.s, pr, CONTACT_C);
    j.false_zero_strict = metrics::false_zero_strict(d, &t.d2, pr);
    j
}

/// Summary of a (query, variant, precision, family) run.
#[derive(Clone, Debug, Default)]
pub struct Stats {
    /// Cases.
    pub n: usize,
    /// Largest excess E.
    pub max_excess: f64,
    /// 99th percentile of excess E.
    pub p99: f64,
    /// Median excess E.
    pub median: f64,
    /// Largest ULP error where meaningful.
    pub max_ulp: Option<f64>,
    /// Contact misses.
    pub contact_misses: usize,
    /// False zeros beyond `c*u*S` (false overlaps for intersection).
    pub false_zeros: usize,
    /// Strict false zeros: any positive exact distance reported as 0.
    pub strict_false_zeros: usize,
    /// Non-finite outputs for finite input.
    pub nonfinite: usize,
    /// Largest closest-point error (scaled).
    pub max_point_error: f64,
    /// Certified intervals that miss the exact distance or the answer (must be 0; see
    /// [`Judged::interval_miss`]).
    pub interval_misses: usize,
    /// Largest and median certified width (scaled).
    pub max_width: f64,
    /// Median certified width (scaled).
    pub median_width: f64,
    /// Verdicts or margin decisions wrong beyond their allowance.
    pub misjudged: usize,
    /// Which path the pairs took.
    pub counts: PathCounts,
    /// Index of the case with the largest excess (or the first classification error).
    pub worst: Option<usize>,
}

/// Judges a whole batch (`allow`: the verdict allowance in `u S`; `margins`: within-margin).
pub fn summarise<T: Float>(
    query: Query,
    cases: &[Case<T>],
    truth: &[Truth],
    out: &Output<T>,
    allow: f64,
    margins: Option<&[T]>,
) -> (Stats, Vec<Judged>) {
    let js: Vec<Judged> = (0..cases.len())
        .map(|i| {
            let m =
                (query == Query::Within).then(|| margins.map_or_else(|| default_margin(&cases[i]), |m| m[i]));
            judge(query, &cases[i], &truth[i], out, i, allow, m)
        })
        .collect();
    let bad = |j: &Judged| j.misjudged || j.interval_miss || j.nonfinite;
    let mut ex: Vec<f64> =
        js.iter().map(|j| if j.excess.is_nan() { f64::INFINITY } else { j.excess }).collect();
    let worst = (0..js.len()).max_by(|&a, &b| {
        let ka = (bad(&js[a]), ex[a].max(js[a].point_error));
        let kb = (bad(&js[b]), ex[b].max(js[b].point_error));
        ka.partial_cmp(&kb).unwrap_or(core::cmp::Ordering::Equal)
    });
    ex.sort_by(|a, b| a.total_cmp(b));
    let mut w: Vec<f64> = js.iter().map(|j| j.width).collect();
    w.sort_by(|a, b| a.total_cmp(b));
    let pct =
        |v: &[f64], p: f64| if v.is_empty() { 0.0 } else { v[((v.len() - 1) as f64 * p).round() as usize] };
    let st = Stats {
        n: js.len(),
        max_excess: ex.last().copied().unwrap_or(0.0),
        p99: pct(&ex, 0.99),
        median: pct(&ex, 0.5),
        max_ulp: js
            .iter()
            .filter_map(|j| j.ulp)
            .fold(None, |m: Option<f64>, x| Some(m.map_or(x, |m| m.max(x)))),
        contact_misses: js.iter().filter(|j| j.contact_miss).count(),
        false_zeros: js.iter().filter(|j| j.false_zero).count(),
        strict_false_zeros: js.iter().filter(|j| j.false_zero_strict).count(),
        nonfinite: js.iter().filter(|j| j.nonfinite).count(),
        max_point_error: js.iter().map(|j| j.point_error).fold(0.0, f64::max),
        interval_misses: js.iter().filter(|j| j.interval_miss).count(),
        max_width: w.last().copied().unwrap_or(0.0),
        median_width: pct(&w, 0.5),
        misjudged: js.iter().filter(|j| j.misjudged).count(),
        counts: out.counts,
        worst,
    };
    (st, js)
}

/// A reproducible description of one case and the kernel's answer, for failure messages:
/// inputs as decimals and bits, the exact answer (rational and rounded), the kernel's answer.
pub fn describe<T: Float>(
    query: Query,
    c: &Case<T>,
    t: &Truth,
    out: &Output<T>,
    i: usize,
    j: &Judged,
) -> String {
    let bits = |x: T| format!("{x:e} (0x{:x})", x.to_bits_u64());
    let tri = |v: &[Point<T>]| {
        v.iter()
            .map(|p| format!("[{}, {}, {}]", bits(p[0]), bits(p[1]), bits(p[2])))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let pr = prec::<T>();
    format!(
        "case {label} ({q}, {prec})\n  a = [{a}]\n  b = [{b}]\n  text: {line}\n  exact D* = {d2} ~ {r:e} (rounded)\n  kernel D^ = {k}, interval [{lo:e}, {hi:e}], verdict {v:?}\n  p^ = {p:?}, q^ = {qq:?}\n  S = {s:e}, excess E = {e}, width {w:.3} uS, interval miss = {im}, contact miss = {cm}, false zero = {fz}, misjudged = {mj}, non-finite = {nf}, point error = {pe}",
        label = c.label,
        q = query.name(),
        prec = T::NAME,
        a = tri(&c.a),
        b = tri(&c.b),
        line = case_line(c),
        d2 = t.d2,
        r = pr.round(&t.d2),
        k = bits(out.d[i]),
        lo = out.iv[i].lo,
        hi = out.iv[i].hi,
        v = out.verdict[i],
        p = out.p[i],
        qq = out.q[i],
        s = t.s,
        e = j.excess,
        w = j.width,
        im = j.interval_miss,
        cm = j.contact_miss,
        fz = j.false_zero,
        mj = j.misjudged,
        nf = j.nonfinite,
        pe = j.point_error,
    )
}

/// The case as one text line (label + 18 coordinates, shortest round-trip decimals): the
/// format of `tridist eval` and of the regression files.
pub fn case_line<T: Float>(c: &Case<T>) -> String {
    let mut s = c.label.replace(char::is_whitespace, "_");
    for x in c.a.iter().chain(c.b.iter()).flatten() {
        s.push(' ');
        s.push_str(&format!("{x:?}"));
    }
    s
}

/// Parses a case line (label + 18 numbers). `Err` says what is wrong.
pub fn parse_case_line<T: Float>(line: &str) -> Result<Case<T>, String> {
    let mut it = line.split_whitespace();
    let label = it.next().ok_or("empty line")?.to_string();
    let nums: Vec<&str> = it.collect();
    if nums.len() != 18 {
        return Err(format!("expected a label and 18 coordinates, found {} coordinates", nums.len()));
    }
    let mut v = [T::ZERO; 18];
    for (slot, s) in v.iter_mut().zip(&nums) {
        *slot = s.parse::<T>().map_err(|_| format!("not a number: {s:?}"))?;
    }
    let p = |k: usize| [v[3 * k], v[3 * k + 1], v[3 * k + 2]];
    Ok(Case { label, a: [p(0), p(1), p(2)], b: [p(3), p(4), p(5)] })
}

/// A case line with an optional trailing `exact=NUM/DEN` field (case files of `tridist cases
/// --exact`, the public-bug set): the case and the exact squared distance, when given.
pub fn parse_case_line_exact<T: Float>(line: &str) -> Result<(Case<T>, Option<Rational>), String> {
    let (body, exact) = match line.trim_end().rsplit_once(char::is_whitespace) {
        Some((body, last)) if last.starts_with("exact=") => {
            let r = last["exact=".len()..]
                .parse::<Rational>()
                .map_err(|_| format!("not an exact fraction: {last:?}"))?;
            (body, Some(r))
        }
        _ => (line, None),
    };
    Ok((parse_case_line::<T>(body)?, exact))
}

/// One row of a sweep.
#[derive(Clone, Debug)]
pub struct Row {
    /// Query.
    pub query: Query,
    /// Variant.
    pub variant: Variant,
    /// "f32" or "f64".
    pub precision: &'static str,
    /// Family.
    pub family: crate::Family,
    /// Measured figures.
    pub stats: Stats,
}

/// Margins for within-margin cases that straddle the exact distance: every other case gets a
/// margin within a few ulps of its exact distance (the hard decisions), the others
/// [`default_margin`].
pub fn margins<T: Float>(cases: &[Case<T>], truth: &[Truth]) -> Vec<T> {
    cases
        .iter()
        .zip(truth)
        .enumerate()
        .map(|(i, (c, t))| {
            if i % 2 == 0 {
                default_margin(c)
            } else {
                let d = T::from_f64(t.d2.to_f64().sqrt());
                let k = (i / 2 % 5) as i32 - 2;
                let m = families::ulp_step(d, k);
                if m < T::ZERO {
                    T::ZERO
                } else {
                    m
                }
            }
        })
        .collect()
}

/// Judges every available variant of `query` on `n` cases of `family` (seeded), calling
/// `on_worst` with a reproducible description of each row's worst case.
pub fn sweep_family<T: Float>(
    query: Query,
    family: crate::Family,
    seed: u64,
    n: usize,
    on_worst: impl FnMut(&Row, String),
) -> Vec<Row> {
    sweep_family_with::<T>(query, family, seed, n, |e| e, on_worst)
}

/// [`sweep_family`] with each variant's engine set up by `setup` (for example
/// `|e| e.quick_stage(false)`), judged against the same bound table.
pub fn sweep_family_with<T: Float>(
    query: Query,
    family: crate::Family,
    seed: u64,
    n: usize,
    setup: impl Fn(Engine) -> Engine,
    mut on_worst: impl FnMut(&Row, String),
) -> Vec<Row> {
    let cases = families::generate::<T>(family, seed, n);
    let tr = truth(query, &cases);
    let ms = margins(&cases, &tr);
    let mut rows = Vec::new();
    for v in Variant::ALL {
        let Some(e) = v.engine_or_skip() else { continue };
        let out = run_with(setup(e), query, v, &cases, Some(&ms)).unwrap_or_else(|err| {
            panic!("{} {} {}: the variant returned an error: {err}", query.name(), v.name(), T::NAME)
        });
        let allow = crate::bounds::bound(query, v, T::NAME, family).allow;
        let (stats, js) = summarise(query, &cases, &tr, &out, allow, Some(&ms));
        let row = Row { query, variant: v, precision: T::NAME, family, stats };
        if let Some(w) = row.stats.worst {
            on_worst(&row, describe(query, &cases[w], &tr[w], &out, w, &js[w]));
        }
        rows.push(row);
    }
    rows
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One rounding either way passes, one step beyond it fails, an underflowed square passes
    /// only where the exact square is below the smallest subnormal, and an infinite `hi`
    /// bounds nothing above.
    #[test]
    fn answers_are_squares_of_the_interval_rounded_once() {
        let iv = |lo: f32, hi: f32| Interval { lo, hi };
        let up = |x: f32| f32::from_bits(x.to_bits() + 1);
        let down = |x: f32| f32::from_bits(x.to_bits() - 1);
        // 3^2 = 9 exactly; its neighbours are 1.8 u away relative, beyond one rounding
        assert!(answer_in_interval(&iv(3.0, 3.0), 9.0f32));
        assert!(!answer_in_interval(&iv(3.0, 3.0), up(9.0)));
        assert!(!answer_in_interval(&iv(3.0, 3.0), down(9.0)));
        // 1.1^2 is not representable: its nearest rounding passes; two steps from it (1.5 ulp
        // or more from the square, beyond u relative) do not
        let x = 1.1f32;
        let near = ((x as f64) * (x as f64)) as f32;
        assert!(answer_in_interval(&iv(x, x), near));
        assert!(
            !answer_in_interval(&iv(x, x), down(down(near))) && !answer_in_interval(&iv(x, x), up(up(near)))
        );
        // squares below the smallest subnormal round to 0; squares above it do not
        assert!(answer_in_interval(&iv(1e-23, 1e-23), 0.0f32));
        assert!(!answer_in_interval(&iv(1e-20, 1e-20), 0.0f32));
        // no upper bound
        assert!(answer_in_interval(&iv(1.0, f32::INFINITY), 1e30f32));
        assert!(!answer_in_interval(&iv(f32::NAN, 1.0), 0.5f32));
        // non-finite answers are judged elsewhere
        assert!(answer_in_interval(&iv(1.0, 1.0), f32::INFINITY));
        // f64: the same at its own unit roundoff
        let up64 = |x: f64| f64::from_bits(x.to_bits() + 1);
        assert!(answer_in_interval(&Interval { lo: 3.0, hi: 3.0 }, 9.0f64));
        assert!(!answer_in_interval(&Interval { lo: 3.0, hi: 3.0 }, up64(9.0)));
    }
}
