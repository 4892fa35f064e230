//! Throughput workloads shared by the report and the criterion benches: every query x variant x
//! precision on prepared pairs in both layouts. Timing: one warm-up pass, then the median of
//! repeated passes; each measurement first checks its results against the scalar AoS variant (a
//! fast wrong kernel cannot win).

use std::time::{Duration, Instant};

use crate::eval::Variant;
use tridist::{Engine, PointBatch, Real, SegmentBatch, Triangle, TriangleBatch};

/// Queries whose throughput is measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TQuery {
    /// Point-triangle (6 per triangle pair).
    TriPoint,
    /// Segment-segment (9 per triangle pair).
    SegSeg,
    /// Triangle-triangle, PQP.
    TriTri,
    /// Triangle-triangle, brute force.
    Brute,
    /// Intersection only.
    Intersect,
    /// Within-margin.
    Within,
    /// Penalty method (default options).
    Penalty,
}

impl TQuery {
    /// Every measured query.
    pub const ALL: [TQuery; 7] = [
        TQuery::TriPoint,
        TQuery::SegSeg,
        TQuery::TriTri,
        TQuery::Brute,
        TQuery::Intersect,
        TQuery::Within,
        TQuery::Penalty,
    ];
    /// Name for tables.
    pub fn name(self) -> &'static str {
        match self {
            TQuery::TriPoint => "tri_point",
            TQuery::SegSeg => "seg_seg",
            TQuery::TriTri => "tri_tri",
            TQuery::Brute => "tri_tri_brute",
            TQuery::Intersect => "intersect",
            TQuery::Within => "within",
            TQuery::Penalty => "penalty",
        }
    }
}

/// Prepared inputs in both layouts.
pub struct Workload<T: Real> {
    ta: Vec<Triangle<T>>,
    tb: Vec<Triangle<T>>,
    bta: TriangleBatch<T>,
    btb: TriangleBatch<T>,
    sa: Vec<[[T; 3]; 2]>,
    sb: Vec<[[T; 3]; 2]>,
    bsa: SegmentBatch<T>,
    bsb: SegmentBatch<T>,
    pa: Vec<[[T; 3]; 1]>,
    pb: Vec<Triangle<T>>,
    bpa: PointBatch<T>,
    bpb: TriangleBatch<T>,
    /// Margin of the within-margin query.
    pub margin: T,
}

impl<T: Real> Workload<T> {
    /// From triangle pairs given in f64 (rounded to T).
    pub fn new(pairs: &[(Triangle<f64>, Triangle<f64>)], margin: f64) -> Self {
        let c = |t: &Triangle<f64>| t.map(|p| p.map(T::from_f64));
        let p: Vec<(Triangle<T>, Triangle<T>)> = pairs.iter().map(|(a, b)| (c(a), c(b))).collect();
        let ta: Vec<_> = p.iter().map(|x| x.0).collect();
        let tb: Vec<_> = p.iter().map(|x| x.1).collect();
        let (sa, sb) = crate::protocol::edge_pairs(&p);
        let (pa, pb) = crate::protocol::vertex_pairs(&p);
        Workload {
            bta: TriangleBatch::from_slice(&ta),
            btb: TriangleBatch::from_slice(&tb),
            bsa: SegmentBatch::from_slice(&sa),
            bsb: SegmentBatch::from_slice(&sb),
            bpa: PointBatch::from_slice(&pa),
            bpb: TriangleBatch::from_slice(&pb),
            ta,
            tb,
            sa,
            sb,
            pa,
            pb,
            margin: T::from_f64(margin),
        }
    }

    /// The triangle pairs (AoS), for peers measured on the same inputs.
    pub fn triangles(&self) -> (&[Triangle<T>], &[Triangle<T>]) {
        (&self.ta, &self.tb)
    }

    /// Number of queries of one pass.
    pub fn len(&self, q: TQuery) -> usize {
        match q {
            TQuery::TriPoint => self.pa.len(),
            TQuery::SegSeg => self.sa.len(),
            _ => self.ta.len(),
        }
    }

    /// Runs one pass of `q` on `e` (AoS inputs when `aos`), writing into `out`.
    pub fn run(
        &self,
        q: TQuery,
        e: Engine,
        aos: bool,
        out: &mut [T],
        flags: &mut [Option<bool>],
    ) -> Result<(), tridist::Error> {
        match (q, aos) {
            (TQuery::TriPoint, true) => e.sqdist_point_triangle(&self.pa, &self.pb, out),
            (TQuery::TriPoint, false) => e.sqdist_point_triangle(&self.bpa, &self.bpb, out),
            (TQuery::SegSeg, true) => e.sqdist_segment_segment(&self.sa, &self.sb, out),
            (TQuery::SegSeg, false) => e.sqdist_segment_segment(&self.bsa, &self.bsb, out),
            (TQuery::TriTri, true) => e.sqdist_triangle_triangle(&self.ta, &self.tb, out),
            (TQuery::TriTri, false) => e.sqdist_triangle_triangle(&self.bta, &self.btb, out),
            (TQuery::Brute, true) => e.sqdist_triangle_triangle_brute(&self.ta, &self.tb, out),
            (TQuery::Brute, false) => e.sqdist_triangle_triangle_brute(&self.bta, &self.btb, out),
            (TQuery::Intersect, true) => e.intersect_triangle_triangle(&self.ta, &self.tb, flags),
            (TQuery::Intersect, false) => e.intersect_triangle_triangle(&self.bta, &self.btb, flags),
            (TQuery::Within, true) => e.within_margin_triangle_triangle(&self.ta, &self.tb, self.margin, out),
            (TQuery::Within, false) => {
                e.within_margin_triangle_triangle(&self.bta, &self.btb, self.margin, out)
            }
            (TQuery::Penalty, aos) => {
                // Outputs the caller does not read still have to exist: allocated per pass,
                // a small part of the iteration's cost.
                let n = self.ta.len();
                let (mut p, mut q, mut it) = (vec![[T::ZERO; 3]; n], vec![[T::ZERO; 3]; n], vec![0u32; n]);
                let o = tridist::PenaltyOptions::default();
                if aos {
                    e.closest_points_triangle_triangle_penalty(
                        &self.ta, &self.tb, &o, out, &mut p, &mut q, &mut it,
                    )
                } else {
                    e.closest_points_triangle_triangle_penalty(
                        &self.bta, &self.btb, &o, out, &mut p, &mut q, &mut it,
                    )
                }
            }
        }
    }
}

/// Median seconds per call of `f` after one warm-up call, repeating until `budget` is used
/// (at least 3 timed calls).
pub fn median_time(mut f: impl FnMut(), budget: Duration) -> f64 {
    f();
    let start = Instant::now();
    let mut times = Vec::new();
    while times.len() < 3 || (start.elapsed() < budget && times.len() < 1000) {
        let t = Instant::now();
        f();
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(|a, b| a.total_cmp(b));
    times[times.len() / 2]
}

/// A result fingerprint: (pairs reported at distance 0 or overlapping, sum of distances).
pub fn fingerprint<T: Real>(q: TQuery, out: &[T], flags: &[Option<bool>]) -> (usize, f64) {
    if q == TQuery::Intersect {
        (flags.iter().filter(|f| **f == Some(true)).count(), 0.0)
    } else {
        let zeros = out.iter().filter(|d| **d == T::ZERO).count();
        let sum = out.iter().map(|d| d.to_f64()).filter(|d| d.is_finite()).map(f64::sqrt).sum();
        (zeros, sum)
    }
}

/// Runs `q` on `variant` once and compares its results with the scalar AoS variant: `None` when
/// the variant is unavailable, `Err` when they disagree beyond rounding.
pub fn check<T: Real>(w: &Workload<T>, q: TQuery, variant: Variant) -> Option<Result<(), String>> {
    let e = Engine::new(variant.isa()).ok()?;
    let n = w.len(q);
    let (mut out, mut flags) = (vec![T::ZERO; n], vec![None; n]);
    let (mut ref_out, mut ref_flags) = (vec![T::ZERO; n], vec![None; n]);
    if let Err(err) = w.run(q, e, variant == Variant::Scalar, &mut out, &mut flags) {
        return Some(Err(err.to_string()));
    }
    if let Err(err) = w.run(q, Engine::scalar(), true, &mut ref_out, &mut ref_flags) {
        return Some(Err(err.to_string()));
    }
    let (z, s) = fingerprint(q, &out, &flags);
    let (rz, rs) = fingerprint(q, &ref_out, &ref_flags);
    // Touching decisions may flip within rounding. The penalty method is an iteration whose
    // result depends on rounding (FMA, lane grouping): it gets looser tolerances.
    let (tol_zero, tol_sum) = if q == TQuery::Penalty { (n / 10 + 2, 2e-2) } else { (n / 100 + 2, 1e-3) };
    if z.abs_diff(rz) > tol_zero || (s - rs).abs() > tol_sum * rs.abs().max(1e-300) {
        return Some(Err(format!("result check failed: zeros {z} vs {rz}, sum {s} vs {rs}")));
    }
    Some(Ok(()))
}

/// Measures queries/s of `q` on `variant` after [`check`]: `None` when the variant is
/// unavailable, `Err` when the check fails.
pub fn measure<T: Real>(
    w: &Workload<T>,
    q: TQuery,
    variant: Variant,
    budget: Duration,
) -> Option<Result<f64, String>> {
    if let Err(e) = check(w, q, variant)? {
        return Some(Err(e));
    }
    let e = Engine::new(variant.isa()).ok()?;
    let n = w.len(q);
    let (mut out, mut flags) = (vec![T::ZERO; n], vec![None; n]);
    let aos = variant == Variant::Scalar;
    let t = median_time(
        || {
            let _ = w.run(q, e, aos, &mut out, &mut flags);
            std::hint::black_box(&out);
        },
        budget,
    );
    Some(Ok(n as f64 / t))
}
