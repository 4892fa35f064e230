//! Small mesh-vs-mesh scenes in poses, by family, for the mesh queries' differential tests
//! and fuzz target: two meshes (f64 vertices, rounded to the working precision by the caller)
//! and a pose for each.

use crate::rng::Rng;
use tridist::{Pose, Real};

/// The mesh scene families.
pub const FAMILIES: &[&str] =
    &["separated", "near_parallel", "touching", "interpenetrating", "far", "degenerate", "needles"];

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
        let v = self.vertices.iter().map(|p| p.map(T::from_f64)).collect();
        tridist::Mesh::new(v, self.triangles.clone()).expect("generated meshes are valid")
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
    Pose::from_axis_angle(rng.dir(), rng.range(0.0, std::f64::consts::TAU), t)
}

/// Scene `index` of `family` (deterministic in `seed`). Blobs have `k` segments (about
/// `2 k^2` triangles), plates `k/2` cells a side.
///
/// # Panics
/// On an unknown family name (a test's typo).
pub fn scene(family: &'static str, seed: u64, index: u64, k: usize) -> MeshScene {
    let mut rng = Rng::new(seed ^ index.wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ family.len() as u64);
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
            );
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
        _ => panic!("unknown mesh family {family}"),
    };
    MeshScene { family, a, b, pose_a, pose_b }
}
