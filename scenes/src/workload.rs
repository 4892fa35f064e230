//! Throughput workloads shared by the report and the criterion benches: every query of the
//! registry x variant x precision on prepared pairs in both layouts. Timing: one warm-up pass, then the median of
//! repeated passes; each measurement first checks its results against the scalar AoS variant (a
//! fast wrong kernel cannot win).

use std::time::{Duration, Instant};

use crate::eval::Variant;
use crate::float::Float;
use tridist::{
    Batch, ClosestPoints, Engine, Intersection, Outputs, PathCounts, Point, Prims, Query, Triangle,
};

/// Prepared primitives of one arity in both layouts.
struct Side<T: Float, const KA: usize, const KB: usize> {
    a: Vec<[Point<T>; KA]>,
    b: Vec<[Point<T>; KB]>,
    ba: Batch<T, KA>,
    bb: Batch<T, KB>,
}

impl<T: Float, const KA: usize, const KB: usize> Side<T, KA, KB> {
    fn new(a: Vec<[Point<T>; KA]>, b: Vec<[Point<T>; KB]>) -> Self {
        Side { ba: Batch::from_slice(&a), bb: Batch::from_slice(&b), a, b }
    }
    fn run(&self, e: Engine, q: Query, aos: bool, out: Outputs<'_, T>) -> Result<PathCounts, tridist::Error> {
        if aos {
            e.run(q, Prims::Aos(&self.a), Prims::Aos(&self.b), out)
        } else {
            e.run(q, &self.ba, &self.bb, out)
        }
    }
}

/// Prepared inputs in both layouts: triangle pairs, and from them (the paper's protocol) every
/// edge pair (segment-segment) and every vertex-triangle pair (point-triangle).
pub struct Workload<T: Float> {
    tri: Side<T, 3, 3>,
    seg: Side<T, 2, 2>,
    pt: Side<T, 1, 3>,
    /// Margin of the within-margin query.
    pub margin: f64,
}

impl<T: Float> Workload<T> {
    /// From triangle pairs given in f64 (rounded to T).
    pub fn new(pairs: &[(Triangle<f64>, Triangle<f64>)], margin: f64) -> Self {
        let c = |t: &Triangle<f64>| t.map(|p| p.map(T::from_f64));
        let p: Vec<(Triangle<T>, Triangle<T>)> = pairs.iter().map(|(a, b)| (c(a), c(b))).collect();
        let (sa, sb) = crate::protocol::edge_pairs(&p);
        let (pa, pb) = crate::protocol::vertex_pairs(&p);
        Workload {
            tri: Side::new(p.iter().map(|x| x.0).collect(), p.iter().map(|x| x.1).collect()),
            seg: Side::new(sa, sb),
            pt: Side::new(pa, pb),
            margin,
        }
    }

    /// The triangle pairs (AoS), for peers measured on the same inputs.
    pub fn triangles(&self) -> (&[Triangle<T>], &[Triangle<T>]) {
        (&self.tri.a, &self.tri.b)
    }

    /// Number of queries of one pass.
    pub fn len(&self, q: Query) -> usize {
        match q.arity() {
            (2, 2) => self.seg.a.len(),
            (1, 3) => self.pt.a.len(),
            _ => self.tri.a.len(),
        }
    }

    /// Runs one pass of `q` on `e` (AoS inputs when `aos`): squared distances into `out`
    /// (verdicts into `verdicts` for intersection), the default penalty options.
    ///
    /// # Errors
    /// As the batch API.
    pub fn run(
        &self,
        q: Query,
        e: Engine,
        aos: bool,
        out: &mut [T],
        verdicts: &mut [Intersection],
    ) -> Result<PathCounts, tridist::Error> {
        let e = if q == Query::Within { e.margin(self.margin) } else { e };
        let o = if q.is_verdict() { Outputs::new().verdicts(verdicts) } else { Outputs::new().sqdist(out) };
        match q.arity() {
            (2, 2) => self.seg.run(e, q, aos, o),
            (1, 3) => self.pt.run(e, q, aos, o),
            _ => self.tri.run(e, q, aos, o),
        }
    }

    /// Runs one pass of the distance query `q` (not a verdict query) on `e`, SoA inputs, with
    /// squared distances and closest points into `out`: the outputs a contact or clearance code
    /// asks for, and what FCL's `TriangleDistance` computes.
    ///
    /// # Errors
    /// As the batch API.
    pub fn run_points(
        &self,
        q: Query,
        e: Engine,
        out: &mut [ClosestPoints<T>],
    ) -> Result<PathCounts, tridist::Error> {
        let e = if q == Query::Within { e.margin(self.margin) } else { e };
        let o = Outputs::new().closest_points(out);
        match q.arity() {
            (2, 2) => self.seg.run(e, q, false, o),
            (1, 3) => self.pt.run(e, q, false, o),
            _ => self.tri.run(e, q, false, o),
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
pub fn fingerprint<T: Float>(q: Query, out: &[T], flags: &[Intersection]) -> (usize, f64) {
    if q.is_verdict() {
        (flags.iter().filter(|f| **f == Intersection::Intersecting).count(), 0.0)
    } else {
        let zeros = out.iter().filter(|d| **d == T::ZERO).count();
        let sum = out.iter().map(|d| d.to_f64()).filter(|d| d.is_finite()).map(f64::sqrt).sum();
        (zeros, sum)
    }
}

/// Runs `q` on `variant` once and compares its results with the scalar AoS variant: `None` when
/// the variant is unavailable, `Err` when they disagree beyond rounding.
pub fn check<T: Float>(w: &Workload<T>, q: Query, variant: Variant) -> Option<Result<(), String>> {
    check_engine(w, q, variant, Engine::new(variant.isa()).ok()?)
}

/// [`check`] of the engine `e` of `variant` as the caller set it up (threads, tolerance,
/// stages).
pub fn check_engine<T: Float>(
    w: &Workload<T>,
    q: Query,
    variant: Variant,
    e: Engine,
) -> Option<Result<(), String>> {
    let n = w.len(q);
    let (mut out, mut flags) = (vec![T::ZERO; n], vec![Intersection::Invalid; n]);
    let (mut ref_out, mut ref_flags) = (vec![T::ZERO; n], vec![Intersection::Invalid; n]);
    if let Err(err) = w.run(q, e, variant == Variant::Scalar, &mut out, &mut flags) {
        return Some(Err(err.to_string()));
    }
    if let Err(err) = w.run(q, Engine::scalar(), true, &mut ref_out, &mut ref_flags) {
        return Some(Err(err.to_string()));
    }
    let (z, s) = fingerprint(q, &out, &flags);
    let (rz, rs) = fingerprint(q, &ref_out, &ref_flags);
    // Touching decisions may flip within rounding.
    if z.abs_diff(rz) > n / 100 + 2 && q != Query::Penalty {
        return Some(Err(format!("result check failed: zeros {z} vs {rz}")));
    }
    if q == Query::Penalty {
        // An iteration whose path depends on rounding (FMA, lane grouping): a few pairs may
        // stop elsewhere (each answer is feasible; its accuracy is judged by the oracle).
        // Checked pair by pair (the workloads are unit-sized): at most a tenth may differ by
        // more than 1e-2.
        let far = out
            .iter()
            .zip(&ref_out)
            .filter(|(a, b)| {
                (a.to_f64().sqrt() - b.to_f64().sqrt()).abs().partial_cmp(&1e-2)
                    != Some(std::cmp::Ordering::Less)
            })
            .count();
        if far > n / 10 + 2 {
            return Some(Err(format!("result check failed: {far} of {n} penalty answers differ by > 1e-2")));
        }
    } else if (s - rs).abs() > 1e-3 * rs.abs().max(1e-300) {
        return Some(Err(format!("result check failed: sum of distances {s} vs {rs}")));
    }
    Some(Ok(()))
}

/// [`measure`] with closest points ([`Workload::run_points`], SoA layout), after checking that
/// the squared distances are those of the same variant's pass without points, bit for bit (the
/// same kernels; only the outputs differ): `None` when the variant is unavailable.
pub fn measure_points<T: Float>(
    w: &Workload<T>,
    q: Query,
    variant: Variant,
    budget: Duration,
) -> Option<Result<Measured, String>> {
    let e = Engine::new(variant.isa()).ok()?;
    let n = w.len(q);
    let (mut d, mut flags) = (vec![T::ZERO; n], vec![Intersection::Invalid; n]);
    let mut cp = vec![ClosestPoints::<T>::default(); n];
    let counts = match w.run(q, e, false, &mut d, &mut flags).and_then(|_| w.run_points(q, e, &mut cp)) {
        Ok(c) => c,
        Err(err) => return Some(Err(err.to_string())),
    };
    let bits = |x: T| x.to_f64().to_bits();
    if let Some(i) = (0..n).find(|&i| bits(cp[i].sqdist) != bits(d[i])) {
        return Some(Err(format!(
            "result check failed: pair {i} has squared distance {:e} with points, {:e} without",
            cp[i].sqdist.to_f64(),
            d[i].to_f64()
        )));
    }
    let t = median_time(
        || {
            let _ = w.run_points(q, e, &mut cp);
            std::hint::black_box(&cp);
        },
        budget,
    );
    Some(Ok(Measured { qps: n as f64 / t, counts }))
}

/// One throughput measurement.
#[derive(Clone, Copy, Debug, Default)]
pub struct Measured {
    /// Queries per second (median pass).
    pub qps: f64,
    /// Which path the pairs of one pass took.
    pub counts: PathCounts,
}

/// Measures queries/s of `q` on `variant` after [`check_engine`] of the engine timed: `None`
/// when the variant is unavailable, `Err` when the check fails. `engine` is the variant's
/// engine as the caller configured it (threads, tolerance, stages); `None` means
/// [`Engine::new`] of the variant.
pub fn measure<T: Float>(
    w: &Workload<T>,
    q: Query,
    variant: Variant,
    engine: Option<Engine>,
    budget: Duration,
) -> Option<Result<Measured, String>> {
    let e = match engine {
        Some(e) => e,
        None => Engine::new(variant.isa()).ok()?,
    };
    if let Err(e) = check_engine(w, q, variant, e)? {
        return Some(Err(e));
    }
    let n = w.len(q);
    let (mut out, mut flags) = (vec![T::ZERO; n], vec![Intersection::Invalid; n]);
    let aos = variant == Variant::Scalar;
    let counts = match w.run(q, e, aos, &mut out, &mut flags) {
        Ok(c) => c,
        Err(err) => return Some(Err(err.to_string())),
    };
    let t = median_time(
        || {
            let _ = w.run(q, e, aos, &mut out, &mut flags);
            std::hint::black_box(&out);
        },
        budget,
    );
    Some(Ok(Measured { qps: n as f64 / t, counts }))
}
