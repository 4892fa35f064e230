//! Poses files: `tridist poses` writes the report's protocols' poses for any two meshes, and
//! `tridist mesh A B --poses FILE` times the mesh queries at each of them, so that MESH.md's
//! figures can be reproduced on anyone's meshes.
//!
//! A poses file has one pose of the second mesh per line: an optional label (a first word that
//! is not a number), then 3 numbers (a translation), 7 (translation, rotation axis, angle in
//! degrees: `tx ty tz ax ay az deg`, as `--pose-b`) or 12 (translation, then the 3x3 matrix's
//! rows: any finite matrix, so scaled and sheared poses too); blank and `#` lines ignored.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, ValueEnum};
use tridist::{Engine, Mesh, Pose, Real};
use tridist_scenes::protocol::{
    ball_placements, ball_radius, near_contact_pose, normalise, trajectory_pose, NEAR_GAP,
};
use tridist_scenes::workload::median_time;

use crate::Fail;

/// The protocols `tridist poses` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Protocol {
    /// TrueForm's: a uniform random rotation, then a translation uniform in the ball of twice
    /// the first mesh's bounding-box diagonal (MESH.md, "TrueForm's protocol").
    Ball,
    /// The seed's trajectory: from 3 units on +x through the first mesh to 3 units on -x,
    /// rotating once about (1, 2, 3) (MESH.md's first table).
    Trajectory,
    /// Near contact: a random rotation, then moved along a random direction until the meshes
    /// are --gap apart (MESH.md, "Near contact at random orientations").
    Near,
}

#[derive(Args, Debug)]
pub struct PosesArgs {
    /// The first (fixed) mesh (OFF).
    pub a: PathBuf,
    /// The second (moving) mesh (OFF).
    pub b: PathBuf,
    /// Which placements.
    #[arg(long, value_enum)]
    pub protocol: Protocol,
    /// How many poses.
    #[arg(long, default_value_t = 100, value_parser = clap::value_parser!(u32).range(1..=1_000_000), allow_negative_numbers = true)]
    pub count: u32,
    /// Seed of the random protocols.
    #[arg(long, default_value_t = tridist_scenes::DEFAULT_SEED)]
    pub seed: u64,
    /// The gap of the near protocol, in the normalised meshes' units (they span 2).
    #[arg(long, default_value_t = NEAR_GAP, value_parser = crate::non_negative, allow_hyphen_values = true)]
    pub gap: f64,
}

/// The mesh `path`, optionally centred and scaled to fit [-1, 1]^3 as the report's protocols
/// place them (its errors name the file).
pub fn load_scene(path: &std::path::Path, normalised: bool) -> Result<tridist_scenes::mesh::Mesh, Fail> {
    let mut m = tridist_scenes::mesh::Mesh::load(path).map_err(|e| Fail(e.to_string()))?;
    if normalised {
        if m.vertices.is_empty() {
            return Err(Fail(format!("{}: no vertex to normalise", path.display())));
        }
        normalise(&mut m);
    }
    Ok(m)
}

/// `tridist poses`: the poses of a protocol for two meshes, normalised as the report places
/// them (use `tridist mesh --normalise --poses`), on stdout.
pub fn cmd_poses(a: &PosesArgs) -> Result<ExitCode, Fail> {
    let (ma, mb) = (load_scene(&a.a, true)?, load_scene(&a.b, true)?);
    let n = a.count as usize;
    let poses: Vec<Pose<f64>> = match a.protocol {
        Protocol::Ball => ball_placements(n, ball_radius(&ma), a.seed),
        Protocol::Trajectory => (0..n).map(|k| trajectory_pose(k, n).1).collect(),
        Protocol::Near => {
            let mesh =
                |m: &tridist_scenes::mesh::Mesh| Mesh::<f64>::new(m.vertices.clone(), m.triangles.clone());
            let (ta, tb) = (mesh(&ma)?, mesh(&mb)?);
            (0..n as u64).map(|k| near_contact_pose(&ta, &tb, a.seed, k, a.gap)).collect::<Result<_, _>>()?
        }
    };
    let name = format!("{:?}", a.protocol).to_lowercase();
    outln!(
        "# tridist poses --protocol {name} --count {n} --seed {}: poses of {} for {} fixed, both normalised to [-1, 1]^3 (time them with `tridist mesh A B --normalise --poses FILE`); label, translation, rotation rows",
        a.seed,
        a.b.display(),
        a.a.display()
    );
    for (k, p) in poses.iter().enumerate() {
        let nums: Vec<String> =
            p.translation.iter().chain(p.rotation.iter().flatten()).map(|x| format!("{x:?}")).collect();
        outln!("{name}-{k} {}", nums.join(" "));
    }
    Ok(ExitCode::SUCCESS)
}

/// The poses of a poses file, with their labels (`pose-K` where a line has none).
///
/// # Errors
/// Every malformed line, with its number, and a file with no pose.
pub fn read_poses(text: &str) -> Result<Vec<(String, Pose<f64>)>, String> {
    let (mut out, mut errors) = (Vec::new(), Vec::new());
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let mut words: Vec<&str> = line.split_whitespace().collect();
        let label = match words.first() {
            Some(w) if w.parse::<f64>().is_err() => Some(words.remove(0).to_string()),
            _ => None,
        };
        let parsed = words
            .iter()
            .map(|w| w.parse::<f64>().map_err(|e| format!("{w:?}: {e}")))
            .collect::<Result<Vec<_>, _>>();
        let pose = parsed.and_then(|v| {
            if v.iter().any(|x| !x.is_finite()) {
                return Err("a non-finite number".to_string());
            }
            match v.len() {
                3 => Ok(Pose::translation([v[0], v[1], v[2]])),
                7 => Pose::from_axis_angle([v[3], v[4], v[5]], v[6].to_radians(), [v[0], v[1], v[2]])
                    .map_err(|e| e.to_string()),
                12 => Ok(Pose {
                    translation: [v[0], v[1], v[2]],
                    rotation: [[v[3], v[4], v[5]], [v[6], v[7], v[8]], [v[9], v[10], v[11]]],
                }),
                n => Err(format!("a pose is 3, 7 or 12 numbers after an optional label, found {n}")),
            }
        });
        match pose {
            Ok(p) => out.push((label.unwrap_or_else(|| format!("pose-{}", out.len())), p)),
            Err(e) => errors.push(format!("line {}: {e}", i + 1)),
        }
    }
    if let Some(first) = errors.first() {
        return Err(format!("{} malformed line(s), first: {first}", errors.len()));
    }
    if out.is_empty() {
        return Err("no pose in the file".into());
    }
    Ok(out)
}

/// The pose in precision `T` ([`crate::meshreport::pose_in`]), or why it cannot be (a number
/// beyond `T`'s range).
fn pose_in<T: Real>(label: &str, p: &Pose<f64>) -> Result<Pose<T>, Fail> {
    let q = crate::meshreport::pose_in::<T>(p);
    if q.rotation.iter().flatten().chain(&q.translation).any(|x| !x.is_finite()) {
        return Err(Fail(format!("pose {label}: beyond the range of {}", T::PRECISION.name())));
    }
    Ok(q)
}

/// `tridist mesh A B --poses FILE`: per pose, the distance, the triangle pair and the query's
/// time, the intersection verdict and its time, and with a margin the contact count and its
/// time; each time the median of repeated calls within `budget`.
pub fn timed<T: Real>(
    e: &Engine,
    ma: &Mesh<T>,
    pa: &Pose<T>,
    mb: &Mesh<T>,
    poses: &[(String, Pose<f64>)],
    margin: Option<(T, f64)>,
    budget: std::time::Duration,
) -> Result<ExitCode, Fail> {
    let m = margin.map_or(String::new(), |(_, asked)| format!(" contacts_within_{asked} contacts_ms"));
    outln!("# label distance tri_a tri_b distance_ms intersect intersect_ms{m}");
    for (label, p) in poses {
        let pb = pose_in::<T>(label, p)?;
        let mut d = Ok(None);
        let t_d = median_time(|| d = e.mesh_distance(ma, pa, mb, &pb), budget);
        let d = d?;
        let mut hit = Ok(None);
        let t_i = median_time(|| hit = e.mesh_intersect(ma, pa, mb, &pb), budget);
        let hit = if hit?.is_some() { "yes" } else { "no" };
        let (dist, ta, tb) = match d {
            // under the correctly rounded mode the library's own distance (or `undecided`)
            Some(r) if e.current_tolerance().correctly_rounded => (
                r.distance.map_or("undecided".into(), |d| format!("{}", d.to_f64())),
                r.tri_a.to_string(),
                r.tri_b.to_string(),
            ),
            Some(r) => (format!("{}", r.sqdist.to_f64().sqrt()), r.tri_a.to_string(), r.tri_b.to_string()),
            None => ("inf".into(), "-".into(), "-".into()),
        };
        let mut line = format!("{label} {dist} {ta} {tb} {:.4} {hit} {:.4}", t_d * 1e3, t_i * 1e3);
        if let Some((m, _)) = margin {
            let mut c = Ok(Vec::new());
            let t_c = median_time(|| c = e.mesh_contacts(ma, pa, mb, &pb, m, None), budget);
            line += &format!(" {} {:.4}", c?.len(), t_c * 1e3);
        }
        outln!("{line}");
    }
    Ok(ExitCode::SUCCESS)
}
