//! Small mesh-vs-mesh scenes in poses, by family, for the mesh queries' differential tests
//! and fuzz target: two meshes (f64 vertices, rounded to the working precision by the caller)
//! and a pose for each.

use crate::rng::Rng;
use rug::Rational;
use tridist::{Engine, Isa, Mesh, Pose, Real, TreeShape};
use tridist_oracle as oracle;

/// The mesh scene families.
pub const FAMILIES: &[&str] = &[
    "separated",
    "near_parallel",
    "touching",
    "interpenetrating",
    "far",
    "degenerate",
    "needles",
    "sheared",
];

/// The tree widths the differential tests and the fuzz target run (every variant on
/// [`tridist::TreeShape::DEFAULT.width`], the best one on the others), and the report's "Tree width"
/// table compares.
pub const TREE_WIDTHS: [usize; 3] = [2, 4, 8];

/// The leaf sizes the differential tests and the fuzz target run besides
/// [`tridist::TreeShape::DEFAULT.leaf`] (the best variant, at the default width): the smallest and the
/// largest a tree may have.
pub const TEST_LEAVES: [usize; 2] = [1, tridist::TreeShape::MAX_LEAF];

/// The tree shapes the differential tests and the fuzz target run: the default, then
/// every other width of [`TREE_WIDTHS`] and every leaf size of [`TEST_LEAVES`] (each
/// changing one of the two).
pub fn test_shapes() -> Vec<TreeShape> {
    let d = TreeShape::default();
    let widths = TREE_WIDTHS.into_iter().filter(|&w| w != d.width).map(|width| TreeShape { width, ..d });
    let leaves = TEST_LEAVES.into_iter().map(|leaf| TreeShape { leaf, ..d });
    std::iter::once(d).chain(widths).chain(leaves).collect()
}

/// An indexed mesh in f64.
#[derive(Clone, Debug)]
pub struct SceneMesh {
    /// Vertices.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles.
    pub triangles: Vec<[u32; 3]>,
}

impl SceneMesh {
    /// The mesh in precision `T` (vertices rounded).
    pub fn mesh<T: Real>(&self) -> tridist::Mesh<T> {
        self.mesh_shaped(TreeShape::default())
    }

    /// [`SceneMesh::mesh`] with a tree of `shape` ([`tridist::Mesh::with_shape`]).
    pub fn mesh_shaped<T: Real>(&self, shape: TreeShape) -> tridist::Mesh<T> {
        let v = self.vertices.iter().map(|p| p.map(T::from_f64)).collect();
        tridist::Mesh::with_shape(v, self.triangles.clone(), shape).expect("generated meshes are valid")
    }
}

/// Two meshes and their poses (f64; round with [`pose_in`]).
#[derive(Clone, Debug)]
pub struct MeshScene {
    /// Family name.
    pub family: &'static str,
    /// First mesh.
    pub a: SceneMesh,
    /// Second mesh.
    pub b: SceneMesh,
    /// Pose of the first mesh.
    pub pose_a: Pose<f64>,
    /// Pose of the second mesh.
    pub pose_b: Pose<f64>,
}

/// A pose rounded to precision `T` (entry by entry).
pub fn pose_in<T: Real>(p: &Pose<f64>) -> Pose<T> {
    Pose { rotation: p.rotation.map(|r| r.map(T::from_f64)), translation: p.translation.map(T::from_f64) }
}

/// A closed blob: a UV sphere of radius about 1 with `k` segments, radially perturbed by up to
/// 15 %.
pub fn blob(rng: &mut Rng, k: usize) -> SceneMesh {
    let k = k.max(3);
    let rings = k - 1;
    let mut vertices = vec![[0.0, 0.0, 1.0]];
    for i in 1..=rings {
        let th = std::f64::consts::PI * i as f64 / k as f64;
        for j in 0..k {
            let ph = 2.0 * std::f64::consts::PI * j as f64 / k as f64;
            let r = 1.0 + rng.range(-0.15, 0.15);
            vertices.push([r * th.sin() * ph.cos(), r * th.sin() * ph.sin(), r * th.cos()]);
        }
    }
    vertices.push([0.0, 0.0, -1.0]);
    let south = (vertices.len() - 1) as u32;
    let at = |i: usize, j: usize| (1 + (i - 1) * k + j % k) as u32;
    let mut triangles = Vec::new();
    for j in 0..k {
        triangles.push([0, at(1, j), at(1, j + 1)]);
        triangles.push([south, at(rings, j + 1), at(rings, j)]);
    }
    for i in 1..rings {
        for j in 0..k {
            triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    SceneMesh { vertices, triangles }
}

/// A square plate of `m` x `m` cells in z = 0 spanning [0, 1]^2, z jittered by up to `jitter`.
pub fn plate(rng: &mut Rng, m: usize, jitter: f64) -> SceneMesh {
    let m = m.max(1);
    let mut vertices = Vec::new();
    for i in 0..=m {
        for j in 0..=m {
            let z = if jitter > 0.0 { rng.range(-jitter, jitter) } else { 0.0 };
            vertices.push([i as f64 / m as f64, j as f64 / m as f64, z]);
        }
    }
    let at = |i: usize, j: usize| (i * (m + 1) + j) as u32;
    let mut triangles = Vec::new();
    for i in 0..m {
        for j in 0..m {
            triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    SceneMesh { vertices, triangles }
}

fn random_pose(rng: &mut Rng, t: [f64; 3]) -> Pose<f64> {
    Pose::from_axis_angle(rng.dir(), rng.range(0.0, std::f64::consts::TAU), t).expect("a unit axis")
}

/// A pose that is not rigid, as [`Pose`] allows (any matrix, applied as given): a shear of up
/// to 1 in one off-diagonal entry, then per-axis scales of 1/4 to 4 (log-uniform), then a
/// random rotation and the translation `t`.
fn linear_pose(rng: &mut Rng, t: [f64; 3]) -> Pose<f64> {
    let r = random_pose(rng, t).rotation;
    let scale = [0, 1, 2].map(|_| rng.log_range(0.25, 4.0));
    let (i, j) = (rng.below(3), rng.below(2));
    let j = if j >= i { j + 1 } else { j };
    let h = rng.range(-1.0, 1.0);
    // rotation * diag(scale) * (I + h e_i e_j^T)
    let mut m = [[0.0; 3]; 3];
    for (row, out) in m.iter_mut().enumerate() {
        for (col, x) in out.iter_mut().enumerate() {
            *x = (0..3)
                .map(|k| {
                    let id = if k == col { 1.0 } else { 0.0 };
                    let shear = id + if (k, col) == (i, j) { h } else { 0.0 };
                    r[row][k] * scale[k] * shear
                })
                .sum();
        }
    }
    Pose { rotation: m, translation: t }
}

/// Scene `index` of `family` (deterministic in `seed`). Blobs have `k` segments (about
/// `2 k^2` triangles), plates `k/2` cells a side.
///
/// # Panics
/// On an unknown family name (a test's typo).
pub fn scene(family: &'static str, seed: u64, index: u64, k: usize) -> MeshScene {
    // Seeded through the generator's own mixing: `seed ^ index * G ^ family.len()`, `G` the
    // generator's increment, made scenes shifted copies of one stream (scenes 13 and 16 of a
    // family were the same scenes) and families of one name length share their streams.
    let mix = |x: u64| Rng::new(x).next_u64();
    let name = family.bytes().fold(0u64, |h, b| mix(h ^ u64::from(b)));
    let mut rng = Rng::new(mix(seed ^ mix(index ^ mix(name))));
    let id = Pose::identity();
    let (a, b, pose_a, pose_b) = match family {
        "separated" => {
            let d = rng.dir().map(|x| x * rng.range(2.4, 5.0));
            (blob(&mut rng, k), blob(&mut rng, k), random_pose(&mut rng, [0.0; 3]), random_pose(&mut rng, d))
        }
        "interpenetrating" => {
            let d = rng.dir().map(|x| x * rng.range(0.0, 1.6));
            (blob(&mut rng, k), blob(&mut rng, k), random_pose(&mut rng, [0.0; 3]), random_pose(&mut rng, d))
        }
        "far" => {
            let o = rng.dir().map(|x| x * 1e5);
            let d = rng.dir().map(|x| x * rng.range(1.7, 2.6));
            let b_at = [o[0] + d[0], o[1] + d[1], o[2] + d[2]];
            (blob(&mut rng, k), blob(&mut rng, k), random_pose(&mut rng, o), random_pose(&mut rng, b_at))
        }
        "near_parallel" => {
            // two plates facing each other, a gap of 1e-1 .. 1e-6 and a tilt of up to 1e-4
            let gap = rng.log_range(1e-6, 1e-1);
            let tilt = rng.range(-1e-4, 1e-4);
            let b_pose = Pose::from_axis_angle(
                [1.0, 0.0, 0.0],
                tilt,
                [rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), gap],
            )
            .expect("the x axis");
            (plate(&mut rng, k / 2, 0.0), plate(&mut rng, k / 2, 0.0), id, b_pose)
        }
        "touching" => {
            // coplanar plates sharing a boundary line exactly, or stacked with a shared vertex
            let m = k / 2;
            let b_pose = if rng.below(2) == 0 {
                Pose::translation([1.0, rng.below(m + 1) as f64 / m as f64 * 0.5, 0.0])
            } else {
                Pose::translation([1.0, 1.0, 0.0])
            };
            (plate(&mut rng, m, 0.0), plate(&mut rng, m, 0.0), id, b_pose)
        }
        "degenerate" => {
            // blobs with collapsed vertices (zero-area and segment-like triangles) and
            // repeated triangles
            let mut a = blob(&mut rng, k);
            let mut b = blob(&mut rng, k);
            for m in [&mut a, &mut b] {
                for _ in 0..m.vertices.len() / 4 {
                    let (i, j) = (rng.below(m.vertices.len()), rng.below(m.vertices.len()));
                    m.vertices[i] = m.vertices[j];
                }
                let extra: Vec<[u32; 3]> = m.triangles.iter().step_by(5).copied().collect();
                m.triangles.extend(extra);
            }
            let d = rng.dir().map(|x| x * rng.range(1.0, 2.6));
            (a, b, random_pose(&mut rng, [0.0; 3]), random_pose(&mut rng, d))
        }
        "needles" => {
            // slivers: blobs squashed 1e-4 along one axis, near each other
            let mut a = blob(&mut rng, k);
            let mut b = blob(&mut rng, k);
            for v in a.vertices.iter_mut().chain(b.vertices.iter_mut()) {
                v[2] *= 1e-4;
            }
            let d = [rng.range(-2.2, 2.2), rng.range(-0.5, 0.5), rng.range(-1e-4, 1e-3)];
            (a, b, id, Pose::translation(d))
        }
        "sheared" => {
            // blobs moved by scaled and sheared matrices (see [`linear_pose`]), apart, near or
            // through each other: the moved boxes must contain the moved vertices under any
            // linear map, not only rotations
            let d = rng.dir().map(|x| x * rng.range(0.5, 4.0));
            (blob(&mut rng, k), blob(&mut rng, k), linear_pose(&mut rng, [0.0; 3]), linear_pose(&mut rng, d))
        }
        _ => panic!("unknown mesh family {family}"),
    };
    MeshScene { family, a, b, pose_a, pose_b }
}

/// The largest E of the mesh queries (distance, contacts' distances, closest point) over every
/// family, precision and variant, measured by `TRIDIST_EXTENSIVE=1 cargo test --release -p
/// tridist-scenes --test mesh -- --nocapture` (48 scenes per family, seed 1; each family's
/// largest printed; 2026-11-26: separated/46, f32, a closest-point query). (On the 4 scenes
/// per family of the default run it had been measured as 1.498; more scenes, seeded
/// independently, found larger errors, within the triangle kernels' own, whose answers these
/// are.)
pub const MEASURED_E: f64 = 3.478;
/// The bound: measured x 1.25 + 0.25, as the triangle rows (`scenes/src/measured.in`).
pub const BOUND_E: f64 = 4.6;
/// The largest `|p - q|` error of a contact's closest points against its pair's exact
/// distance, measured as [`MEASURED_E`] (sheared/18, f64); the triangle suite's point errors
/// reach 5.1 (`measured.in`).
pub const MEASURED_GAP: f64 = 2.556;
/// Its bound, as [`BOUND_E`].
pub const BOUND_GAP: f64 = 3.45;

fn moved<T: Real>(m: &Mesh<T>, p: &Pose<T>) -> Vec<[[f64; 3]; 3]> {
    m.triangles().iter().map(|t| t.map(|v| p.apply(m.vertices()[v as usize]).map(Real::to_f64))).collect()
}

fn exact_tri(t: &[[f64; 3]; 3]) -> [oracle::P3; 3] {
    oracle::exact_points(t).expect("finite")
}

fn mag(ts: &[[[f64; 3]; 3]]) -> f64 {
    ts.iter().flatten().flatten().fold(0.0f64, |m, x| m.max(x.abs()))
}

fn rat(x: f64) -> Rational {
    Rational::from_f64(x).expect("finite")
}

/// `Err(format!(...))` unless `cond`.
macro_rules! ensure {
    ($cond:expr, $($fmt:tt)*) => {{
        // through a bool: a NaN comparison fails the check
        let ok: bool = $cond;
        if !ok {
            return Err(format!($($fmt)*));
        }
    }};
}

/// The largest E allowed to the mesh answers: `distance` for the mesh distance, the reported
/// pair and the closest points' offsets from their triangles, `point` for the closest point
/// to a query point.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Triangle-triangle answers.
    pub distance: f64,
    /// Point-triangle answers.
    pub point: f64,
    /// `|p - q|` of a contact's closest points against its pair's exact distance.
    pub gap: f64,
    /// The engines' tolerance, in `u S` ([`tridist::Tolerance::scaled`]): the verdicts
    /// (contacts, clearance, intersection) are judged outside `tolerance + 1` `u S` of a
    /// change of verdict ([`Limits::tight`] for a pass under a tight one).
    pub tolerance: f64,
}

impl Limits {
    /// The measured mesh row ([`BOUND_E`]), for the generated families.
    pub const MEASURED: Limits = Limits {
        distance: BOUND_E,
        point: BOUND_E,
        gap: BOUND_GAP,
        tolerance: tridist::Tolerance::DEFAULT.scaled,
    };

    /// The same limits under the tolerance `scaled` `u S`: the engines are given it, and the
    /// contact sets, the clearance check and the intersection pair are judged outside
    /// `scaled + 1` `u S` of a change of verdict instead of the default's 65.
    pub fn tight(self, scaled: f64) -> Limits {
        Limits { tolerance: scaled, ..self }
    }

    /// The kernels' own loosest rows over every family (E and point error) in `precision`:
    /// what fuzzed (adversarial) scenes are held to, as the fuzzed triangle pairs are. A mesh
    /// answer is a kernel answer, and its E is scaled by the whole scene's magnitude, at least
    /// the pair's, so the kernels' bounds hold for it.
    pub fn kernels(precision: &str) -> Limits {
        let b = |q| {
            let r = crate::bounds::bound_any_family(q, crate::eval::Variant::Scalar, precision);
            r.max_excess.max(r.max_point_error)
        };
        Limits {
            distance: b(tridist::Query::TriTri),
            point: b(tridist::Query::PointTri),
            gap: b(tridist::Query::TriTri),
            tolerance: tridist::Tolerance::DEFAULT.scaled,
        }
    }
}

/// `|err| / (u S)`: 0 when the error is 0 (also for S = 0, all coordinates zero; found by the
/// `mesh` fuzz target), the smallest positive normal standing in for a zero S otherwise.
fn excess(err: f64, u: f64, s: f64) -> f64 {
    if err == 0.0 {
        0.0
    } else {
        err.abs() / (u * s.max(f64::MIN_POSITIVE))
    }
}

/// The distance of a returned point from its triangle, as an excess E (exactly).
fn off_triangle<T: Real>(pt: [T; 3], t: &[oracle::P3; 3], u: f64, s: f64) -> f64 {
    let x = oracle::exact_point(&pt.map(Real::to_f64)).expect("finite");
    excess(oracle::point_triangle(&x, t).d2.to_f64().sqrt(), u, s)
}

/// The largest errors seen by [`check_scene`] and where: E of the distances (mesh distance,
/// contacts' distances, closest point; [`MEASURED_E`]) and the contacts' `|p - q|` error
/// ([`MEASURED_GAP`]).
#[derive(Clone, Debug, Default)]
pub struct Worst {
    /// Largest E.
    pub e: f64,
    /// Where (family/index, precision, variant, what).
    pub what: String,
    /// Largest error of a contact's `|p - q|` against its pair's exact distance.
    pub gap: f64,
    /// Where, as `what`.
    pub gap_what: String,
}

/// The contact margins `check_scene` tries for a scene whose minimum distance is `dstar`: half
/// the minimum (no contacts but within rounding of it; 0 where the meshes touch), just above the
/// minimum and 5 % of the size. All grow with `dstar` ([`Brute`] relies on it).
fn margins(dstar: f64, big_s: f64) -> [f64; 3] {
    [dstar * 0.5, dstar * 1.5 + 1e-3 * big_s.min(4.0), 0.05 * big_s.min(4.0)]
}

/// How far from a change of verdict a pair of magnitude `s` may get either verdict: the
/// verdict contract, the tolerance (`tol` `u S`, 64 by default) plus one unit, exactly
/// ([`oracle::metrics::c_us`]: in f64 arithmetic `u S` underflows to nothing where S is near
/// the smallest normal).
fn allowance<T: Real>(s: f64, tol: f64) -> Rational {
    oracle::metrics::c_us(tol + 1.0, s, crate::float::metrics_precision(T::PRECISION))
}

/// The exact squared distance of every triangle pair that can matter to the checks: pairs
/// whose bounding boxes are apart by more than `far` are skipped, and computed only if a query
/// reports them. `far` is above an upper bound of the minimum distance (so the minimum is never
/// skipped and a skipped pair never intersects) and above the largest contact margin the checks
/// use plus its allowance, so a skipped pair must be absent from every contact set. The box gap
/// is a certified lower bound: each coordinate difference is rounded once (relative error
/// <= 2^-53), covered by the factor 1 - 1e-12; the upper bound (a vertex-vertex distance, a few
/// roundings) by 1 + 1e-12.
struct Brute<'a> {
    ea: &'a [[oracle::P3; 3]],
    eb: &'a [[oracle::P3; 3]],
    d2: Vec<Vec<Option<Rational>>>,
}

impl<'a> Brute<'a> {
    fn new<T: Real>(
        ta: &[[[f64; 3]; 3]],
        tb: &[[[f64; 3]; 3]],
        ea: &'a [[oracle::P3; 3]],
        eb: &'a [[oracle::P3; 3]],
        big_s: f64,
        tol: f64,
    ) -> Self {
        // each triangle's box once, then the largest per-axis gap of a pair's boxes
        let boxes = |ts: &[[[f64; 3]; 3]]| -> Vec<[[f64; 3]; 2]> {
            ts.iter()
                .map(|t| {
                    let lo = [0, 1, 2].map(|k| t.iter().map(|v| v[k]).fold(f64::INFINITY, f64::min));
                    let hi = [0, 1, 2].map(|k| t.iter().map(|v| v[k]).fold(f64::NEG_INFINITY, f64::max));
                    [lo, hi]
                })
                .collect()
        };
        let (ba, bb) = (boxes(ta), boxes(tb));
        let gap = |x: &[[f64; 3]; 2], y: &[[f64; 3]; 2]| {
            (0..3).map(|k| (y[0][k] - x[1][k]).max(x[0][k] - y[1][k])).fold(0.0f64, f64::max) * (1.0 - 1e-12)
        };
        let vv = |x: &[[f64; 3]; 3], y: &[[f64; 3]; 3]| {
            (0..3).map(|k| (x[0][k] - y[0][k]).powi(2)).sum::<f64>().sqrt() * (1.0 + 1e-12)
        };
        let upper = ta.iter().flat_map(|x| tb.iter().map(move |y| vv(x, y))).fold(f64::INFINITY, f64::min);
        // check_scene's margins grow with d* <= upper; rounded to T, plus the allowance
        let u = T::UNIT_ROUNDOFF.to_f64();
        let margin = margins(upper, big_s).into_iter().fold(0.0, f64::max) * (1.0 + 4.0 * u);
        let far = (upper.max(margin + allowance::<T>(big_s, tol).to_f64())) * (1.0 + 1e-12);
        let d2 = ba
            .iter()
            .zip(ea)
            .map(|(x, ex)| {
                bb.iter()
                    .zip(eb)
                    .map(|(y, ey)| (gap(x, y) <= far).then(|| oracle::triangle_triangle(ex, ey).d2))
                    .collect()
            })
            .collect();
        Brute { ea, eb, d2 }
    }

    /// The exact minimum over all pairs.
    fn min(&self) -> Rational {
        self.d2.iter().flatten().flatten().min().expect("the nearest pair is never skipped").clone()
    }

    /// The pair's exact squared distance if it was computed.
    fn known(&self, i: usize, j: usize) -> Option<&Rational> {
        self.d2[i][j].as_ref()
    }

    /// The pair's exact squared distance, computed now if it was skipped.
    fn get(&mut self, i: usize, j: usize) -> Rational {
        let (ea, eb) = (self.ea, self.eb);
        self.d2[i][j].get_or_insert_with(|| oracle::triangle_triangle(&ea[i], &eb[j]).d2).clone()
    }
}

/// Checks the mesh queries of every available instruction set on scene `s` in precision `T`
/// against the exact brute force over all pairs (computed once); `idx` seeds the query
/// points. `Err` with a reproducible description on a violation (see `scenes/tests/mesh.rs`
/// for what is checked).
pub fn check_scene<T: Real>(s: &MeshScene, idx: u64, lim: &Limits, worst: &mut Worst) -> Result<(), String> {
    let fam = s.family;
    let (ma, mb) = (s.a.mesh::<T>(), s.b.mesh::<T>());
    let (pa, pb) = (pose_in::<T>(&s.pose_a), pose_in::<T>(&s.pose_b));
    let (ta, tb) = (moved(&ma, &pa), moved(&mb, &pb));
    let (ea, eb): (Vec<_>, Vec<_>) = (ta.iter().map(exact_tri).collect(), tb.iter().map(exact_tri).collect());
    let u = T::UNIT_ROUNDOFF.to_f64();
    let big_s = mag(&ta).max(mag(&tb));
    // all pairs, exactly, except those certified too far apart to matter (`Brute`)
    let mut d2 = Brute::new::<T>(&ta, &tb, &ea, &eb, big_s, lim.tolerance);
    let best = d2.min();
    let any_hit = best == 0;
    let dstar = best.to_f64().sqrt();
    // Under a tight tolerance, two margins that decide one pair by a few `u S` (the hard
    // decisions): 4 u S (of the pair) below its distance, where it must be left out, and 4 u S
    // above, where it must be in (the allowance is `tolerance + 1` `u S`; rounding the margin
    // moves it by at most `u S`). The pair: the farthest within the default margins' reach.
    let hard: Vec<f64> = if lim.tolerance <= 2.0 {
        let reach = margins(dstar, big_s).into_iter().fold(0.0, f64::max);
        let mut pick: Option<(f64, f64)> = None;
        for i in 0..ta.len() {
            for j in 0..tb.len() {
                if let Some(d) = d2.known(i, j) {
                    let d = d.to_f64().sqrt();
                    let sp = mag(&[ta[i], tb[j]]);
                    if d + 8.0 * u * sp <= reach && d > 16.0 * u * sp && pick.is_none_or(|(best, _)| d > best)
                    {
                        pick = Some((d, sp));
                    }
                }
            }
        }
        pick.map_or_else(Vec::new, |(d, sp)| vec![d - 4.0 * u * sp, d + 4.0 * u * sp])
    } else {
        Vec::new()
    };
    let mut rng = Rng::new(idx);
    let points: Vec<([T; 3], Rational)> = (0..4)
        .map(|_| {
            let t = &ta[rng.below(ta.len())];
            let x = [0, 1, 2].map(|k| T::from_f64(t[0][k] + rng.range(-0.3, 0.3)));
            let xe = oracle::exact_point(&x.map(Real::to_f64)).expect("finite");
            (x, eb.iter().map(|t| oracle::point_triangle(&xe, t).d2).min().expect("non-empty"))
        })
        .collect();
    let mut note = |v: f64, what: &str, tag: &str| {
        let gap = what.starts_with("contact points'");
        let (most, at) =
            if gap { (&mut worst.gap, &mut worst.gap_what) } else { (&mut worst.e, &mut worst.what) };
        if v > *most {
            (*most, *at) = (v, format!("{tag} {what}"));
        }
        let bound = if what.starts_with("closest point") {
            lim.point
        } else if gap {
            lim.gap
        } else {
            lim.distance
        };
        ensure!(v <= bound, "{tag}: {what} E = {v} (bound {bound})");
        Ok(())
    };
    // every variant on the default tree; the best variant also on the other shapes (the
    // answers must not depend on the tree)
    let isas: Vec<Isa> = Isa::ALL
        .into_iter()
        .filter(|&i| crate::eval::Variant::from_isa(i).engine_or_skip().is_some())
        .collect();
    let best = Engine::auto().isa();
    let runs = isas
        .iter()
        .map(|&i| (i, TreeShape::default()))
        .chain(test_shapes().into_iter().skip(1).map(|shape| (best, shape)));
    for (isa, shape) in runs {
        let e = Engine::new(isa)
            .map(|e| e.tolerance(tridist::Tolerance::scaled(lim.tolerance)))
            .map_err(|e| format!("{isa}: {e}"))?;
        let (ma, mb) = if shape == TreeShape::default() {
            (ma.clone(), mb.clone())
        } else {
            (s.a.mesh_shaped::<T>(shape), s.b.mesh_shaped::<T>(shape))
        };
        let tag = format!(
            "{fam}/{idx} {} {} width {} leaf {}",
            T::PRECISION.name(),
            e.isa(),
            shape.width,
            shape.leaf
        );

        // 1. distance
        let r = e.mesh_distance(&ma, &pa, &mb, &pb).map_err(|e| format!("{tag}: {e}"))?.expect("non-empty");
        let err = excess(r.sqdist.to_f64().sqrt() - dstar, u, big_s);
        // above the exact minimum the search may stop within its slack of the smallest kernel
        // answer (`Engine::mesh_distance`): that many `u S` beyond a kernel answer's own error
        // (`S` there is the moved roots' boxes', a hair above `big_s`); the tolerance's width
        // where the search could answer enough pairs to widen it
        let widens =
            ma.len() * mb.len() >= tridist::Engine::MESH_DISTANCE_WIDEN_AFTER.max(ma.len() + mb.len());
        let slack = if widens { e.current_tolerance().scaled } else { tridist::Engine::MESH_DISTANCE_SLACK };
        let err = if r.sqdist.to_f64().sqrt() > dstar { (err - slack * (1.0 + 1e-6)).max(0.0) } else { err };
        let pair = d2.get(r.tri_a, r.tri_b).to_f64().sqrt();
        let err_pair = excess(r.sqdist.to_f64().sqrt() - pair, u, big_s);
        for (pt, t) in [(r.p, &ea[r.tri_a]), (r.q, &eb[r.tri_b])] {
            note(off_triangle(pt, t, u, big_s), "point off its triangle", &tag)?;
        }
        note(err, "distance", &tag)?;
        note(err_pair, "reported pair", &tag)?;

        // 2. contacts (and the clearance check) at half the minimum, a margin just above it
        // and 5 % of the size
        for margin in margins(dstar, big_s).into_iter().chain(hard.iter().copied()) {
            let m = T::from_f64(margin);
            let got = e.mesh_contacts(&ma, &pa, &mb, &pb, m, None).map_err(|e| format!("{tag}: {e}"))?;
            let mut seen = std::collections::HashSet::new();
            for c in &got {
                ensure!(seen.insert((c.tri_a, c.tri_b)), "{tag}: pair {:?} twice", (c.tri_a, c.tri_b));
                ensure!(c.sqdist.to_f64() <= m.to_f64() * m.to_f64(), "{tag}: contact beyond the margin");
                // each contact's answer is its pair's, with points on its triangles
                let s = big_s;
                let own = d2.get(c.tri_a, c.tri_b).to_f64().sqrt();
                note(excess(c.sqdist.to_f64().sqrt() - own, u, s), "contact distance", &tag)?;
                for (pt, t) in [(c.p, &ea[c.tri_a]), (c.q, &eb[c.tri_b])] {
                    note(off_triangle(pt, t, u, s), "contact point off its triangle", &tag)?;
                }
                // |p - q| against the pair's exact distance, as the triangle suite's point error
                let pq = (0..3).map(|k| (c.p[k].to_f64() - c.q[k].to_f64()).powi(2)).sum::<f64>().sqrt();
                note(excess(pq - own, u, s), "contact points' distance", &tag)?;
            }
            for i in 0..ta.len() {
                for j in 0..tb.len() {
                    let Some(d) = d2.known(i, j) else {
                        // apart by more than any margin plus its allowance (Brute::new)
                        ensure!(!seen.contains(&(i, j)), "{tag}: far pair ({i}, {j}) reported");
                        continue;
                    };
                    let s = mag(&[ta[i], tb[j]]);
                    let allow = allowance::<T>(s, lim.tolerance);
                    let (lo, hi) = (rat(m.to_f64()) - &allow, rat(m.to_f64()) + &allow);
                    // (a pair within `allow` of the margin may go either way; when the margin
                    // is below the allowance, that includes touching pairs: the kernels answer
                    // an exact 0 within `c u S`, as the triangle suite's contact misses allow)
                    if lo > 0 && *d <= Rational::from(&lo * &lo) {
                        ensure!(
                            seen.contains(&(i, j)),
                            "{tag}: pair ({i}, {j}) at {} within margin {margin} missed",
                            d.to_f64().sqrt()
                        );
                    }
                    if *d > Rational::from(&hi * &hi) {
                        ensure!(
                            !seen.contains(&(i, j)),
                            "{tag}: pair ({i}, {j}) at {} beyond margin {margin} reported",
                            d.to_f64().sqrt()
                        );
                    }
                }
            }
            // the clearance check decides as the contacts do: a hit exactly when there is a
            // contact, and the pair it names is one
            match e.mesh_within_margin(&ma, &pa, &mb, &pb, m).map_err(|e| format!("{tag}: {e}"))? {
                Some(p) => ensure!(seen.contains(&p), "{tag}: within {margin}: pair {p:?} is not a contact"),
                None => ensure!(got.is_empty(), "{tag}: within {margin}: none, with {} contacts", got.len()),
            }
            // a cap keeps the first of the order (distance, then triangle numbers)
            let capped =
                e.mesh_contacts(&ma, &pa, &mb, &pb, m, Some(3)).map_err(|e| format!("{tag}: {e}"))?;
            ensure!(
                capped[..] == got[..got.len().min(3)],
                "{tag}: capped contacts are not the first of the order"
            );
            ensure!(
                got.windows(2)
                    .all(|w| (w[0].sqdist, w[0].tri_a, w[0].tri_b) <= (w[1].sqdist, w[1].tri_a, w[1].tri_b)),
                "{tag}: contacts out of order"
            );
        }

        // 3. intersection
        match e.mesh_intersect(&ma, &pa, &mb, &pb).map_err(|e| format!("{tag}: {e}"))? {
            Some((i, j)) => {
                let allow = allowance::<T>(mag(&[ta[i], tb[j]]), lim.tolerance);
                let d = d2.get(i, j);
                ensure!(
                    d <= Rational::from(&allow * &allow),
                    "{tag}: pair ({i}, {j}) said intersecting at {}",
                    d.to_f64().sqrt()
                );
            }
            None => ensure!(!any_hit, "{tag}: intersecting meshes said apart"),
        }

        // 4. closest point of the second mesh to points around the first
        for (x, exact_min) in &points {
            let xe = oracle::exact_point(&x.map(Real::to_f64)).expect("finite");
            let r =
                e.mesh_closest_point(&mb, &pb, *x).map_err(|e| format!("{tag}: {e}"))?.expect("non-empty");
            let s = big_s.max(x.iter().fold(0.0f64, |m, c| m.max(c.to_f64().abs())));
            note(excess(r.sqdist.to_f64().sqrt() - exact_min.to_f64().sqrt(), u, s), "closest point", &tag)?;
            let own = oracle::point_triangle(&xe, &eb[r.tri]).d2.to_f64().sqrt();
            note(excess(own - r.sqdist.to_f64().sqrt(), u, s), "closest point's triangle", &tag)?;
        }
    }
    Ok(())
}

/// The `mesh` fuzz target's input: two small meshes (up to 10 vertices and 12 triangles each,
/// coordinates on a grid of 1/256 so that touching, coplanar and shared-vertex configurations
/// are frequent), scaled by a power of two, optionally far from the origin, in two poses: a
/// rotation (or none) and a translation, each optionally after a linear part (per-axis scales,
/// a shear, or any matrix, singular ones included).
pub fn fuzz_scene(data: &[u8]) -> Option<MeshScene> {
    use arbitrary::{Arbitrary, Unstructured};
    let mut u = Unstructured::new(data);
    let scale = 2f64.powi(i32::from(i8::arbitrary(&mut u).ok()? % 40));
    let far = if bool::arbitrary(&mut u).ok()? { 1e5 } else { 0.0 };
    let mesh = |u: &mut Unstructured<'_>| -> Option<SceneMesh> {
        let nv = 3 + usize::from(u8::arbitrary(u).ok()? % 8);
        let nt = 1 + usize::from(u8::arbitrary(u).ok()? % 12);
        let mut vertices = Vec::with_capacity(nv);
        for _ in 0..nv {
            let c = <[i16; 3]>::arbitrary(u).ok()?;
            vertices.push(c.map(|x| f64::from(x) / 256.0 * scale / 64.0));
        }
        let mut triangles = Vec::with_capacity(nt);
        for _ in 0..nt {
            let t = <[u8; 3]>::arbitrary(u).ok()?;
            triangles.push(t.map(|i| u32::from(i) % nv as u32));
        }
        Some(SceneMesh { vertices, triangles })
    };
    let a = mesh(&mut u)?;
    let b = mesh(&mut u)?;
    let pose = |u: &mut Unstructured<'_>| -> Option<Pose<f64>> {
        let axis = <[i8; 3]>::arbitrary(u).ok()?.map(f64::from);
        let axis = if axis == [0.0; 3] { [0.0, 0.0, 1.0] } else { axis };
        // a quarter of the poses are translations only (exact motion)
        let angle = if u8::arbitrary(u).ok()? % 4 == 0 {
            0.0
        } else {
            f64::from(u16::arbitrary(u).ok()?) / 65536.0 * std::f64::consts::TAU
        };
        let t = <[i16; 3]>::arbitrary(u).ok()?.map(|x| f64::from(x) / 256.0 * scale / 64.0 + far);
        Pose::from_axis_angle(axis, angle, t).ok()
    };
    let (pose_a, pose_b) = (pose(&mut u)?, pose(&mut u)?);
    // then, per pose, an optional linear part applied before the rotation (`Pose` applies any
    // matrix as given): read after both poses, so that an input ending there (exhausted bytes
    // read as zeros: kind 0) keeps the rigid poses it decoded to before this part existed
    let linear = |u: &mut Unstructured<'_>, p: Pose<f64>| -> Option<Pose<f64>> {
        let kind = u8::arbitrary(u).ok()? % 4;
        if kind == 0 {
            return Some(p);
        }
        let e = <[i8; 9]>::arbitrary(u).ok()?.map(i32::from);
        let rotation = std::array::from_fn(|i| {
            std::array::from_fn(|j| match (kind, i == j) {
                // per-axis scales of 2^-4 to 2^4
                (1, true) => 2f64.powi(e[i] % 5),
                (1, false) => 0.0,
                // a shear: the identity plus off-diagonal entries of up to 2
                (2, true) => 1.0,
                // (and any matrix) entries of up to 2 in steps of 1/64, singular ones included
                _ => f64::from(e[3 * i + j]) / 64.0,
            })
        });
        Some(p.compose(&Pose { rotation, translation: [0.0; 3] }))
    };
    let (pose_a, pose_b) = (linear(&mut u, pose_a)?, linear(&mut u, pose_b)?);
    Some(MeshScene { family: "fuzz", a, b, pose_a, pose_b })
}
