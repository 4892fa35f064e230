//! The benchmark protocol of Shellshear & Ytterlid (seed 000, section 3) on real meshes: one mesh
//! moved in 10 steps from a non-colliding position through the other to another non-colliding
//! one while rotating 360 degrees; at each step, triangles of the moving mesh against triangles
//! of the static one, either four triangles sharing a vertex ("neighbouring") or four random
//! triangles ("random") against one static triangle. Segment-segment and point-triangle use all
//! edge and vertex combinations of those triangle pairs, as the paper did.

use tridist::{Pose, Triangle};

use crate::mesh::Mesh;
use crate::rng::Rng;

/// How the moving triangles of one group are chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Grouping {
    /// Triangles sharing a vertex (the paper's "neighbouring").
    Neighbouring,
    /// Random triangles.
    Random,
}

impl Grouping {
    /// Name for reports.
    pub fn name(self) -> &'static str {
        match self {
            Grouping::Neighbouring => "neighbouring",
            Grouping::Random => "random",
        }
    }
}

/// The axis-aligned bounding box of the mesh's vertices (lower and upper corners).
fn bounding_box(m: &Mesh) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for v in &m.vertices {
        for k in 0..3 {
            lo[k] = lo[k].min(v[k]);
            hi[k] = hi[k].max(v[k]);
        }
    }
    (lo, hi)
}

/// The mesh centred and scaled to fit [-1, 1]^3 (its largest side).
pub fn normalise(m: &mut Mesh) {
    let (lo, hi) = bounding_box(m);
    let c = [0, 1, 2].map(|k| (lo[k] + hi[k]) / 2.0);
    let s = (0..3).map(|k| hi[k] - lo[k]).fold(0.0f64, f64::max) / 2.0;
    for v in &mut m.vertices {
        *v = [0, 1, 2].map(|k| (v[k] - c[k]) / s);
    }
}

/// The mesh's triangles, centred and scaled to fit [-1, 1]^3 ([`normalise`]).
pub fn normalised(m: &Mesh) -> Vec<Triangle<f64>> {
    let mut m = m.clone();
    normalise(&mut m);
    (0..m.triangles.len()).map(|i| m.triangle(i)).collect()
}

/// `n` triangle pairs (moving, static) following the protocol: 10 steps, 4 moving triangles per
/// static triangle. Fixed seed, so every run measures the same work.
pub fn pairs(
    fixed: &Mesh,
    moving: &Mesh,
    grouping: Grouping,
    n: usize,
    seed: u64,
) -> Vec<(Triangle<f64>, Triangle<f64>)> {
    let st = normalised(fixed);
    let mv = normalised(moving);
    // triangles around each vertex of the moving mesh
    let mut fan: Vec<Vec<usize>> = vec![Vec::new(); moving.vertices.len()];
    for (t, tri) in moving.triangles.iter().enumerate() {
        for &v in tri {
            fan[v as usize].push(t);
        }
    }
    let fans: Vec<&Vec<usize>> = fan.iter().filter(|f| f.len() >= 4).collect();
    let mut r = Rng::new(seed);
    let steps = 10;
    let per_step = n.div_ceil(steps);
    let mut out = Vec::with_capacity(n);
    for step in 0..steps {
        let f = step as f64 / (steps - 1) as f64;
        let angle = f * std::f64::consts::TAU;
        let (sn, cs) = angle.sin_cos();
        let shift = -3.0 + 6.0 * f; // from one side (no contact) through to the other
        let place =
            |t: Triangle<f64>| t.map(|p| [cs * p[0] - sn * p[1] + shift, sn * p[0] + cs * p[1], p[2]]);
        while out.len() < (step + 1) * per_step && out.len() < n {
            let s = st[r.below(st.len())];
            let group: Vec<usize> = match grouping {
                Grouping::Neighbouring if !fans.is_empty() => fans[r.below(fans.len())][..4].to_vec(),
                _ => (0..4).map(|_| r.below(mv.len())).collect(),
            };
            for g in group {
                if out.len() < n {
                    out.push((place(mv[g]), s));
                }
            }
        }
    }
    out
}

/// All 9 edge pairs of each triangle pair.
pub fn edge_pairs<T: Copy>(
    p: &[(Triangle<T>, Triangle<T>)],
) -> (Vec<tridist::Segment<T>>, Vec<tridist::Segment<T>>) {
    let mut a = Vec::with_capacity(9 * p.len());
    let mut b = Vec::with_capacity(9 * p.len());
    for (s, t) in p {
        for i in 0..3 {
            for j in 0..3 {
                a.push([s[i], s[(i + 1) % 3]]);
                b.push([t[j], t[(j + 1) % 3]]);
            }
        }
    }
    (a, b)
}

/// All 6 vertex-triangle pairs of each triangle pair.
pub fn vertex_pairs<T: Copy>(p: &[(Triangle<T>, Triangle<T>)]) -> (Vec<[[T; 3]; 1]>, Vec<Triangle<T>>) {
    let mut a = Vec::with_capacity(6 * p.len());
    let mut b = Vec::with_capacity(6 * p.len());
    for (s, t) in p {
        for k in 0..3 {
            a.push([s[k]]);
            b.push(*t);
            a.push([t[k]]);
            b.push(*s);
        }
    }
    (a, b)
}

/// Nearby triangle pairs of one mesh (normalised to [-1, 1]^3): a triangle at random and
/// another whose centroid lies within `k` mean edge lengths of its centroid (a few share a
/// vertex or an edge; most are a fraction of an edge apart). The workload of issue 13's FCL
/// comparison, "nearby triangle pairs of one mesh".
pub fn nearby_pairs(m: &Mesh, k: f64, n: usize, seed: u64) -> Vec<(Triangle<f64>, Triangle<f64>)> {
    let tris = normalised(m);
    let cent: Vec<[f64; 3]> =
        tris.iter().map(|t| [0, 1, 2].map(|c| (t[0][c] + t[1][c] + t[2][c]) / 3.0)).collect();
    let edge = |a: [f64; 3], b: [f64; 3]| {
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    };
    let mean = tris.iter().map(|t| edge(t[0], t[1]) + edge(t[1], t[2]) + edge(t[2], t[0])).sum::<f64>()
        / (3.0 * tris.len() as f64);
    let r = k * mean;
    // grid of cells of size r over [-1, 1]^3
    let cells = ((2.0 / r).ceil() as usize).clamp(1, 256);
    let cell = |p: [f64; 3]| p.map(|x| (((x + 1.0) / 2.0 * cells as f64) as usize).min(cells - 1));
    let mut grid: std::collections::HashMap<[usize; 3], Vec<usize>> = std::collections::HashMap::new();
    for (i, c) in cent.iter().enumerate() {
        grid.entry(cell(*c)).or_default().push(i);
    }
    let mut rng = Rng::new(seed);
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let i = rng.below(tris.len());
        let c0 = cell(cent[i]);
        let mut near = Vec::new();
        for dx in 0..3 {
            for dy in 0..3 {
                for dz in 0..3 {
                    let c = [c0[0] + dx, c0[1] + dy, c0[2] + dz];
                    if c.iter().any(|&x| x == 0 || x > cells) {
                        continue;
                    }
                    if let Some(v) = grid.get(&[c[0] - 1, c[1] - 1, c[2] - 1]) {
                        near.extend(v.iter().copied().filter(|&j| j != i && edge(cent[i], cent[j]) <= r));
                    }
                }
            }
        }
        if near.is_empty() {
            continue;
        }
        let j = near[rng.below(near.len())];
        out.push((tris[i], tris[j]));
    }
    out
}

/// A named triangle-pair workload of the benches and the report.
pub struct Named {
    /// Short id (criterion group names, CSV).
    pub id: &'static str,
    /// Title in reports.
    pub title: &'static str,
    /// The pairs (f64; rounded to the precision measured).
    pub pairs: Vec<(Triangle<f64>, Triangle<f64>)>,
}

/// The standard workloads, `n` pairs each: random unit-cube pairs (about a quarter intersect),
/// nearby triangles of the Armadillo (within 3 mean edge lengths: the FCL comparison of issue
/// 13), and the paper's protocol (Armadillo and the CAD part, neighbouring or random groups).
///
/// # Errors
/// When a carried mesh is missing or malformed.
pub fn standard(n: usize, seed: u64) -> Result<Vec<Named>, String> {
    let load = |f: &str| crate::mesh::carried(f).map_err(|e| format!("data/meshes/{f}: {e}"));
    let arm = load("armadillo.off")?;
    let fan = load("fandisk_large.off")?;
    let rnd =
        crate::families::generate::<f64>(crate::Family::Random, seed, n).into_iter().map(|c| (c.a, c.b));
    Ok(vec![
        Named { id: "random", title: "random unit cube", pairs: rnd.collect() },
        Named {
            id: "arm_nearby",
            title: "Armadillo, nearby triangles",
            pairs: nearby_pairs(&arm, 3.0, n, seed),
        },
        Named {
            id: "arm_arm_neighbouring",
            title: "Armadillo vs Armadillo, neighbouring",
            pairs: pairs(&arm, &arm, Grouping::Neighbouring, n, seed),
        },
        Named {
            id: "arm_arm_random",
            title: "Armadillo vs Armadillo, random",
            pairs: pairs(&arm, &arm, Grouping::Random, n, seed),
        },
        Named {
            id: "cad_cad_neighbouring",
            title: "Fandisk vs Fandisk, neighbouring",
            pairs: pairs(&fan, &fan, Grouping::Neighbouring, n, seed),
        },
        Named {
            id: "cad_arm_random",
            title: "Fandisk vs Armadillo, random",
            pairs: pairs(&fan, &arm, Grouping::Random, n, seed),
        },
    ])
}

/// A carried mesh (`data/meshes/`), centred and scaled to [-1, 1]^3 (largest side).
pub fn carried_normalised(name: &str) -> Result<Mesh, String> {
    let mut m = crate::mesh::carried(name).map_err(|e| format!("{name}: {e}"))?;
    normalise(&mut m);
    Ok(m)
}

/// Pose `k` of `poses` along the seed's mesh trajectory (the mesh report and the mesh
/// benches): the moving mesh from 3 units to the +x side, through the fixed one, to 3 units to
/// the -x side, rotating once about the axis (1, 2, 3) on the way. As translation and scaled
/// axis (parry's form) and as tridist's matrix.
pub fn trajectory_pose(k: usize, poses: usize) -> (([f64; 3], [f64; 3]), Pose<f64>) {
    let t = (k as f64) / (poses.max(2) - 1) as f64;
    let x = 3.0 - 6.0 * t;
    let angle = std::f64::consts::TAU * t;
    let n = 14f64.sqrt();
    let axis = [1.0 / n, 2.0 / n, 3.0 / n];
    (
        ([x, 0.0, 0.0], axis.map(|a| a * angle)),
        Pose::from_axis_angle(axis, angle, [x, 0.0, 0.0]).expect("a unit axis"),
    )
}

/// The gap of the mesh report's near-contact placements ([`near_contact_pose`]): 0.05 % of
/// the scene's size.
pub const NEAR_GAP: f64 = 1e-3;

/// The distance of `a` at rest and `b` in `pose` on `e` (f64; `+inf` when a mesh is empty).
///
/// # Errors
/// The mesh query's error, as text.
pub fn mesh_gap(
    e: &tridist::Engine,
    a: &tridist::Mesh<f64>,
    b: &tridist::Mesh<f64>,
    pose: &Pose<f64>,
) -> Result<f64, String> {
    let r = e.mesh_distance(a, &Pose::identity(), b, pose).map_err(|x| x.to_string())?;
    Ok(r.map_or(f64::INFINITY, |r| r.sqdist.sqrt()))
}

/// Near-contact placement `k` of the mesh report (MESH.md, "Near contact at random
/// orientations") for the base seed `seed`: `b` rotated about a random axis by a random angle
/// and moved along a random direction until its distance to `a` (both in [-1, 1]^3, `a` at
/// rest) is `gap`, by bisection on the translation with tridist f64, starting where they
/// overlap (at the origin, or where a vertex of each coincides when they do not overlap there).
/// The pose returned is the far end of the last bracket, so its distance is at least the gap.
pub fn near_contact_pose(
    a: &tridist::Mesh<f64>,
    b: &tridist::Mesh<f64>,
    seed: u64,
    k: u64,
    gap: f64,
) -> Result<Pose<f64>, String> {
    let e = tridist::Engine::auto();
    let mut rng = Rng::new(seed ^ 0x6e65_6172 ^ k);
    let (axis, angle, dir) = (rng.dir(), rng.range(0.0, std::f64::consts::TAU), rng.dir());
    let turned = Pose::from_axis_angle(axis, angle, [0.0; 3]).expect("a unit axis");
    // The bisection needs the meshes closer than the gap at its start: where they overlap at
    // rest (the report's meshes do), from there; else from where a vertex of each coincides.
    let base = match (a.triangle(0), b.triangle(0)) {
        (Some(ta), Some(tb)) if mesh_gap(&e, a, b, &turned)? >= gap => {
            let v = turned.apply(tb[0]);
            [0, 1, 2].map(|k| ta[0][k] - v[k])
        }
        _ => [0.0; 3],
    };
    let at = |t: f64| {
        Pose::from_axis_angle(axis, angle, [0, 1, 2].map(|k| base[k] + dir[k] * t)).expect("a unit axis")
    };
    // Both meshes lie in [-1, 1]^3 (within sqrt(3) of the origin, turned or not): translated
    // by 4 or more they are separated in any direction.
    let reach = base.iter().map(|c| c * c).sum::<f64>().sqrt();
    let (mut lo, mut hi) = (0.0, 4.0 + reach);
    for _ in 0..48 {
        let mid = 0.5 * (lo + hi);
        if mesh_gap(&e, a, b, &at(mid))? < gap {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(at(hi))
}

/// TrueForm's published mesh-distance protocol (its benchmarks of mesh-to-mesh closest points):
/// the second mesh at random rigid placements, a uniformly random rotation (a uniform unit
/// quaternion, Shoemake's method) about the origin, then a translation uniform in the ball of
/// `radius` about the origin (rejection from the cube). Both meshes are in [-1, 1]^3 there
/// ([`carried_normalised`]) and the radius is twice the diagonal of the fixed mesh's bounding
/// box ([`ball_radius`]), so most placements are separated and some overlap. `n` placements
/// from `seed`, the same on every run.
pub fn ball_placements(n: usize, radius: f64, seed: u64) -> Vec<Pose<f64>> {
    let mut r = Rng::new(seed ^ 0x7472_7565_666f_726d);
    (0..n)
        .map(|_| {
            let (u1, u2, u3) = (r.unit(), r.unit(), r.unit());
            let tau = std::f64::consts::TAU;
            let (s1, s2) = ((1.0 - u1).sqrt(), u1.sqrt());
            let q =
                [s1 * (tau * u2).sin(), s1 * (tau * u2).cos(), s2 * (tau * u3).sin(), s2 * (tau * u3).cos()];
            // q = (x, y, z, w) as axis and angle (any axis for the identity)
            let w = q[3].clamp(-1.0, 1.0);
            let angle = 2.0 * w.acos();
            let axis = if q[..3].iter().all(|&c| c == 0.0) { [0.0, 0.0, 1.0] } else { [q[0], q[1], q[2]] };
            let t = loop {
                let p = [r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0)];
                if p.iter().map(|c| c * c).sum::<f64>() <= 1.0 {
                    break p.map(|c| c * radius);
                }
            };
            Pose::from_axis_angle(axis, angle, t).expect("a non-zero finite axis")
        })
        .collect()
}

/// A bound of every coordinate of a mesh in [-1, 1]^3 turned rigidly, then moved by
/// `translation` (within sqrt(3) of the origin once turned): the `S` of the error bounds.
pub fn placed_magnitude(translation: [f64; 3]) -> f64 {
    3f64.sqrt() + translation.iter().fold(0.0f64, |m, t| m.max(t.abs()))
}

/// The radius of [`ball_placements`] for the fixed mesh `m`: twice the diagonal of its
/// axis-aligned bounding box.
pub fn ball_radius(m: &Mesh) -> f64 {
    let (lo, hi) = bounding_box(m);
    2.0 * (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt()
}

#[cfg(test)]
mod ball_tests {
    use super::*;

    /// The placements are rigid, inside the ball, reproducible, and spread: rotations about
    /// every axis (the mean of each rotation column near 0, as for uniform rotations) and
    /// translations filling the ball (the mean distance from the centre near 3/4 of the radius).
    #[test]
    fn ball_placements_are_uniform_rigid_and_reproducible() {
        let n = 4000;
        let p = ball_placements(n, 5.0, 1);
        assert_eq!(p.len(), n);
        assert_eq!(p, ball_placements(n, 5.0, 1));
        assert_ne!(p, ball_placements(n, 5.0, 2));
        let mut col = [[0.0f64; 3]; 3];
        let mut reach = 0.0;
        for q in &p {
            let r = q.rotation;
            for i in 0..3 {
                let row = r[i];
                assert!((row.iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-12, "orthonormal rows");
                for j in 0..3 {
                    col[i][j] += r[i][j] / n as f64;
                }
            }
            let d = q.translation.iter().map(|x| x * x).sum::<f64>().sqrt();
            assert!(d <= 5.0 + 1e-12);
            reach += d / n as f64;
        }
        assert!(col.iter().flatten().all(|m| m.abs() < 0.05), "{col:?}");
        assert!((reach / 5.0 - 0.75).abs() < 0.02, "{reach}");
    }
}
