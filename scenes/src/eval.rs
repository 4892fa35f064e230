//! The differential harness: run a kernel variant over cases, judge it against the oracle with
//! the metrics of ACCURACY.md, and summarise. Shared by `cargo test`, the fuzz targets and the
//! accuracy report.

use rug::Rational;
use tridist::{Engine, Isa, Point, Prims, Real, TriangleBatch};
use tridist_oracle::metrics::{self, Precision};

use crate::families::{self, Case};

/// A query as the harness sees it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Query {
    /// Segment-segment squared distance + closest points.
    SegSeg,
    /// Point-triangle squared distance + closest point.
    PointTri,
    /// Triangle-triangle (PQP) squared distance + closest points.
    TriTri,
    /// Triangle-triangle brute force (15 features + SAT).
    TriTriBrute,
    /// Triangle-triangle intersection only.
    Intersect,
    /// Triangle-triangle by the penalty method (default options).
    Penalty,
}

impl Query {
    /// Every query judged against the oracle.
    pub const ALL: [Query; 6] =
        [Query::SegSeg, Query::PointTri, Query::TriTri, Query::TriTriBrute, Query::Intersect, Query::Penalty];
    /// Short name.
    pub fn name(self) -> &'static str {
        match self {
            Query::SegSeg => "seg_seg",
            Query::PointTri => "point_tri",
            Query::TriTri => "tri_tri",
            Query::TriTriBrute => "tri_tri_brute",
            Query::Intersect => "intersect",
            Query::Penalty => "penalty",
        }
    }
    /// Parses [`Query::name`].
    pub fn parse(s: &str) -> Option<Query> {
        Query::ALL.into_iter().find(|q| q.name() == s)
    }
}

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
}

impl Variant {
    /// Every variant.
    pub const ALL: [Variant; 5] =
        [Variant::Scalar, Variant::Soa, Variant::Sse41, Variant::Avx, Variant::Avx2Fma];
    /// Short name.
    pub fn name(self) -> &'static str {
        match self {
            Variant::Scalar => "scalar",
            Variant::Soa => "soa",
            Variant::Sse41 => "sse41",
            Variant::Avx => "avx",
            Variant::Avx2Fma => "avx2fma",
        }
    }
    /// Parses [`Variant::name`] (`auto` = the best available SoA variant).
    pub fn parse(s: &str) -> Option<Variant> {
        if s == "auto" {
            return Some(Variant::from_isa(Isa::best()));
        }
        Variant::ALL.into_iter().find(|v| v.name() == s)
    }
    /// The instruction set it runs.
    pub fn isa(self) -> Isa {
        match self {
            Variant::Scalar | Variant::Soa => Isa::Scalar,
            Variant::Sse41 => Isa::Sse41,
            Variant::Avx => Isa::Avx,
            Variant::Avx2Fma => Isa::Avx2Fma,
        }
    }
    /// The SoA variant of an instruction set.
    pub fn from_isa(i: Isa) -> Variant {
        match i {
            Isa::Scalar => Variant::Soa,
            Isa::Sse41 => Variant::Sse41,
            Isa::Avx => Variant::Avx,
            Isa::Avx2Fma => Variant::Avx2Fma,
        }
    }
    /// Can this CPU run it?
    pub fn available(self) -> bool {
        self.isa().is_available()
    }
    fn engine(self) -> Result<Engine, tridist::Error> {
        Engine::new(self.isa())
    }
}

/// What a kernel returned for a batch.
#[derive(Clone, Debug, Default)]
pub struct Output<T> {
    /// Squared distances (for `Intersect`: 0 = overlap, 1 = disjoint, NaN = invalid).
    pub d: Vec<T>,
    /// First closest points.
    pub p: Vec<Point<T>>,
    /// Second closest points.
    pub q: Vec<Point<T>>,
}

/// Runs `query` with `variant` over `cases` (closest points included where the query has them).
///
/// # Errors
/// When the variant is unavailable.
pub fn run<T: Real>(query: Query, variant: Variant, cases: &[Case<T>]) -> Result<Output<T>, tridist::Error> {
    let e = variant.engine()?;
    let n = cases.len();
    let mut o = Output { d: vec![T::ZERO; n], p: vec![[T::ZERO; 3]; n], q: vec![[T::ZERO; 3]; n] };
    let aos = variant == Variant::Scalar;
    match query {
        Query::TriTri | Query::TriTriBrute => {
            let a: Vec<_> = cases.iter().map(|c| c.a).collect();
            let b: Vec<_> = cases.iter().map(|c| c.b).collect();
            let (ba, bb) = (TriangleBatch::from_slice(&a), TriangleBatch::from_slice(&b));
            let (pa, pb): (Prims<T, 3>, Prims<T, 3>) =
                if aos { ((&a).into(), (&b).into()) } else { ((&ba).into(), (&bb).into()) };
            if query == Query::TriTri {
                e.closest_points_triangle_triangle(pa, pb, &mut o.d, &mut o.p, &mut o.q)?;
            } else {
                e.closest_points_triangle_triangle_brute(pa, pb, &mut o.d, &mut o.p, &mut o.q)?;
            }
        }
        Query::Penalty => {
            run_penalty(variant, cases, &tridist::PenaltyOptions::default(), &mut o)?;
        }
        Query::Intersect => {
            let a: Vec<_> = cases.iter().map(|c| c.a).collect();
            let b: Vec<_> = cases.iter().map(|c| c.b).collect();
            let (ba, bb) = (TriangleBatch::from_slice(&a), TriangleBatch::from_slice(&b));
            let mut flags = vec![None; n];
            if aos {
                e.intersect_triangle_triangle(&a, &b, &mut flags)?;
            } else {
                e.intersect_triangle_triangle(&ba, &bb, &mut flags)?;
            }
            o.d = flags
                .iter()
                .map(|f| match f {
                    Some(true) => T::ZERO,
                    Some(false) => T::ONE,
                    None => T::NAN,
                })
                .collect();
        }
        Query::SegSeg => {
            let (a, b): (Vec<_>, Vec<_>) = cases.iter().map(families::segments).unzip();
            let (ba, bb) = (tridist::SegmentBatch::from_slice(&a), tridist::SegmentBatch::from_slice(&b));
            if aos {
                e.closest_points_segment_segment(&a, &b, &mut o.d, &mut o.p, &mut o.q)?;
            } else {
                e.closest_points_segment_segment(&ba, &bb, &mut o.d, &mut o.p, &mut o.q)?;
            }
        }
        Query::PointTri => {
            let (a, b): (Vec<_>, Vec<_>) = cases
                .iter()
                .map(|c| {
                    let (p, t) = families::point_triangle(c);
                    ([p], t)
                })
                .unzip();
            let (ba, bb) = (tridist::PointBatch::from_slice(&a), TriangleBatch::from_slice(&b));
            if aos {
                e.closest_point_point_triangle(&a, &b, &mut o.d, &mut o.q)?;
            } else {
                e.closest_point_point_triangle(&ba, &bb, &mut o.d, &mut o.q)?;
            }
            o.p = a.iter().map(|p| p[0]).collect();
        }
    }
    Ok(o)
}

/// Runs the penalty method with `opts`; returns the iteration counts.
///
/// # Errors
/// When the variant is unavailable or the options are invalid.
pub fn run_penalty<T: Real>(
    variant: Variant,
    cases: &[Case<T>],
    opts: &tridist::PenaltyOptions<T>,
    o: &mut Output<T>,
) -> Result<Vec<u32>, tridist::Error> {
    let e = variant.engine()?;
    let n = cases.len();
    o.d.resize(n, T::ZERO);
    o.p.resize(n, [T::ZERO; 3]);
    o.q.resize(n, [T::ZERO; 3]);
    let mut it = vec![0u32; n];
    let a: Vec<_> = cases.iter().map(|c| c.a).collect();
    let b: Vec<_> = cases.iter().map(|c| c.b).collect();
    if variant == Variant::Scalar {
        e.closest_points_triangle_triangle_penalty(&a, &b, opts, &mut o.d, &mut o.p, &mut o.q, &mut it)?;
    } else {
        let (ba, bb) = (TriangleBatch::from_slice(&a), TriangleBatch::from_slice(&b));
        e.closest_points_triangle_triangle_penalty(&ba, &bb, opts, &mut o.d, &mut o.p, &mut o.q, &mut it)?;
    }
    Ok(it)
}

/// The exact answer for one case.
#[derive(Clone, Debug)]
pub struct Truth {
    /// Exact squared distance (0 for overlapping triangles).
    pub d2: Rational,
    /// The magnitude S of the query's input.
    pub s: f64,
}

fn prec<T: Real>() -> Precision {
    if T::NAME == "f32" {
        metrics::F32
    } else {
        metrics::F64
    }
}

fn to64<const K: usize, T: Real>(p: &[Point<T>; K]) -> [[f64; 3]; K] {
    p.map(|v| v.map(|x| x.to_f64()))
}

/// The primitives (as exact points) of a case for a query: (first, second).
fn exact_prims<T: Real>(query: Query, c: &Case<T>) -> (Vec<tridist_oracle::P3>, Vec<tridist_oracle::P3>) {
    let ex = |v: &[[f64; 3]]| -> Vec<tridist_oracle::P3> {
        v.iter().map(|p| tridist_oracle::exact_point(p).expect("families generate finite input")).collect()
    };
    match query {
        Query::SegSeg => {
            let (a, b) = families::segments(c);
            (ex(&to64(&a)), ex(&to64(&b)))
        }
        Query::PointTri => {
            let (p, t) = families::point_triangle(c);
            (ex(&to64(&[p])), ex(&to64(&t)))
        }
        _ => (ex(&to64(&c.a)), ex(&to64(&c.b))),
    }
}

/// Computes the exact answers for `cases` under `query`.
pub fn truth<T: Real>(query: Query, cases: &[Case<T>]) -> Vec<Truth> {
    cases
        .iter()
        .map(|c| {
            let (a, b) = exact_prims(query, c);
            let d2 = match query {
                Query::SegSeg => {
                    tridist_oracle::segment_segment(
                        &[a[0].clone(), a[1].clone()],
                        &[b[0].clone(), b[1].clone()],
                    )
                    .d2
                }
                Query::PointTri => {
                    tridist_oracle::point_triangle(&a[0], &[b[0].clone(), b[1].clone(), b[2].clone()]).d2
                }
                _ => {
                    tridist_oracle::triangle_triangle(
                        &[a[0].clone(), a[1].clone(), a[2].clone()],
                        &[b[0].clone(), b[1].clone(), b[2].clone()],
                    )
                    .d2
                }
            };
            let coords = match query {
                Query::SegSeg => {
                    let (a, b) = families::segments(c);
                    a.iter().chain(b.iter()).flatten().map(|x| x.to_f64()).collect::<Vec<_>>()
                }
                Query::PointTri => {
                    let (p, t) = families::point_triangle(c);
                    p.iter().chain(t.iter().flatten()).map(|x| x.to_f64()).collect()
                }
                _ => c.a.iter().chain(c.b.iter()).flatten().map(|x| x.to_f64()).collect(),
            };
            Truth { d2, s: metrics::magnitude(coords, prec::<T>()) }
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
}

/// Judges one kernel output against the truth.
pub fn judge<T: Real>(query: Query, c: &Case<T>, t: &Truth, out: &Output<T>, i: usize) -> Judged {
    let pr = prec::<T>();
    let d = out.d[i].to_f64();
    if query == Query::Intersect {
        let exact_hit = t.d2 == 0;
        let said = if d == 0.0 {
            Some(true)
        } else if d == 1.0 {
            Some(false)
        } else {
            None
        };
        // A miss or a false overlap only counts beyond the contact tolerance.
        let tol = Rational::from_f64((CONTACT_C * pr.u * t.s).powi(2)).unwrap_or_default();
        return Judged {
            contact_miss: exact_hit && said == Some(false),
            false_zero: said == Some(true) && t.d2 > tol,
            false_zero_strict: said == Some(true) && t.d2 > 0,
            nonfinite: said.is_none(),
            ..Judged::default()
        };
    }
    let overflow = pr.round(&t.d2).is_infinite();
    // +inf is documented where the squared distance, or an answer within the method's error
    // bound (the E target; 8 S for the penalty approximation, as in the bound table), overflows.
    let reach = if query == Query::Penalty { 8.0 / pr.u } else { metrics::OVERFLOW_REACH };
    let documented_overflow = d == f64::INFINITY && metrics::overflow_allowed(&t.d2, t.s, pr, reach);
    let nonfinite = !(d.is_finite() || documented_overflow);
    let excess = metrics::excess_within(d, &t.d2, t.s, pr, reach);
    let mut point_error = 0.0f64;
    if !overflow && d.is_finite() {
        let (a, b) = exact_prims(query, c);
        let p = out.p[i].map(|x| x.to_f64());
        let q = out.q[i].map(|x| x.to_f64());
        point_error = point_error
            .max(metrics::point_offset(p, &a, t.s, pr))
            .max(metrics::point_offset(q, &b, t.s, pr))
            .max(metrics::gap_error(p, q, &t.d2, t.s, pr));
    }
    Judged {
        excess,
        ulp: metrics::ulp_error(d, &t.d2, t.s, pr),
        contact_miss: metrics::contact_miss(d, &t.d2, t.s, pr, CONTACT_C),
        false_zero: metrics::false_zero(d, &t.d2, t.s, pr, CONTACT_C),
        false_zero_strict: metrics::false_zero_strict(d, &t.d2, pr),
        nonfinite,
        point_error,
    }
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
    /// Index of the case with the largest excess (or the first classification error).
    pub worst: Option<usize>,
}

/// Judges a whole batch.
pub fn summarise<T: Real>(
    query: Query,
    cases: &[Case<T>],
    truth: &[Truth],
    out: &Output<T>,
) -> (Stats, Vec<Judged>) {
    let js: Vec<Judged> = (0..cases.len()).map(|i| judge(query, &cases[i], &truth[i], out, i)).collect();
    let mut ex: Vec<f64> =
        js.iter().map(|j| if j.excess.is_nan() { f64::INFINITY } else { j.excess }).collect();
    let worst = (0..js.len()).max_by(|&a, &b| {
        let ka = (js[a].contact_miss || js[a].false_zero || js[a].nonfinite, ex[a].max(js[a].point_error));
        let kb = (js[b].contact_miss || js[b].false_zero || js[b].nonfinite, ex[b].max(js[b].point_error));
        ka.partial_cmp(&kb).unwrap_or(core::cmp::Ordering::Equal)
    });
    ex.sort_by(|a, b| a.total_cmp(b));
    let pct = |p: f64| if ex.is_empty() { 0.0 } else { ex[((ex.len() - 1) as f64 * p).round() as usize] };
    let st = Stats {
        n: js.len(),
        max_excess: ex.last().copied().unwrap_or(0.0),
        p99: pct(0.99),
        median: pct(0.5),
        max_ulp: js
            .iter()
            .filter_map(|j| j.ulp)
            .fold(None, |m: Option<f64>, x| Some(m.map_or(x, |m| m.max(x)))),
        contact_misses: js.iter().filter(|j| j.contact_miss).count(),
        false_zeros: js.iter().filter(|j| j.false_zero).count(),
        strict_false_zeros: js.iter().filter(|j| j.false_zero_strict).count(),
        nonfinite: js.iter().filter(|j| j.nonfinite).count(),
        max_point_error: js.iter().map(|j| j.point_error).fold(0.0, f64::max),
        worst,
    };
    (st, js)
}

/// A reproducible description of one case and the kernel's answer, for failure messages:
/// inputs as decimals and bits, the exact answer (rational and rounded), the kernel's answer.
pub fn describe<T: Real>(
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
        "case {label} ({q}, {prec})\n  a = [{a}]\n  b = [{b}]\n  text: {line}\n  exact D* = {d2} ~ {r:e} (rounded)\n  kernel D^ = {k}\n  p^ = {p:?}, q^ = {qq:?}\n  S = {s:e}, excess E = {e}, contact miss = {cm}, false zero = {fz}, non-finite = {nf}, point error = {pe}",
        label = c.label,
        q = query.name(),
        prec = T::NAME,
        a = tri(&c.a),
        b = tri(&c.b),
        line = case_line(c),
        d2 = t.d2,
        r = pr.round(&t.d2),
        k = bits(out.d[i]),
        p = out.p[i],
        qq = out.q[i],
        s = t.s,
        e = j.excess,
        cm = j.contact_miss,
        fz = j.false_zero,
        nf = j.nonfinite,
        pe = j.point_error,
    )
}

/// The case as one text line (label + 18 coordinates, shortest round-trip decimals): the
/// format of `tridist eval` and of the regression files.
pub fn case_line<T: Real>(c: &Case<T>) -> String {
    let mut s = c.label.replace(char::is_whitespace, "_");
    for x in c.a.iter().chain(c.b.iter()).flatten() {
        s.push(' ');
        s.push_str(&format!("{x:?}"));
    }
    s
}

/// Parses a case line (label + 18 numbers). `Err` says what is wrong.
pub fn parse_case_line<T: Real>(line: &str) -> Result<Case<T>, String> {
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

/// Judges every available variant of `query` on `n` cases of `family` (seeded), calling
/// `on_worst` with a reproducible description of each row's worst case.
pub fn sweep_family<T: Real>(
    query: Query,
    family: crate::Family,
    seed: u64,
    n: usize,
    mut on_worst: impl FnMut(&Row, String),
) -> Vec<Row> {
    let cases = families::generate::<T>(family, seed, n);
    let tr = truth(query, &cases);
    let mut rows = Vec::new();
    for v in Variant::ALL {
        let Ok(out) = run(query, v, &cases) else { continue };
        let (stats, js) = summarise(query, &cases, &tr, &out);
        let row = Row { query, variant: v, precision: T::NAME, family, stats };
        if let Some(w) = row.stats.worst {
            on_worst(&row, describe(query, &cases[w], &tr[w], &out, w, &js[w]));
        }
        rows.push(row);
    }
    rows
}
