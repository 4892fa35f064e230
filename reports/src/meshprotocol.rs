//! MESH.md's "TrueForm's protocol" section: mesh distance at random rigid placements of the
//! second mesh (the protocol TrueForm publishes its mesh figures with), tridist beside every C++
//! mesh peer built here (FCL, Coal, TrueForm in three tree configurations, TrueForm also on its
//! default threads), per placement, in the same run; the same contenders on the seed's
//! trajectory and at near contact ("Every peer on the trajectory and at near contact"), and at
//! scale.

use std::fmt::Write as _;
use std::time::{Duration, Instant};

use tridist::{Engine, Mesh, Pose, Real};
use tridist_scenes::mesh::Mesh as SceneMesh;
use tridist_scenes::mesh_peer::{trueform_threads, MeshLib, MeshPeer};
use tridist_scenes::protocol::{
    ball_placements, ball_radius, carried_normalised, near_contact_pose, placed_magnitude, trajectory_pose,
};

use crate::meshreport::{bursts_of, mesh, ms, pose_in, ratio};
use crate::report::Settings;

/// The pairs measured (fixed mesh, moving mesh).
const PAIRS: [(&str, &str); 2] = [("armadillo.off", "armadillo.off"), ("armadillo.off", "fandisk_large.off")];

/// One contender's distance and time (seconds) per placement.
struct Column {
    name: String,
    /// Seconds to build both meshes' trees (one build; NaN where the column reuses another's).
    build: f64,
    /// Why it was not measured, when it was not.
    missing: Option<&'static str>,
    d: Vec<f64>,
    t: Vec<f64>,
}

impl Column {
    fn new(name: &str) -> Column {
        Column { name: name.into(), build: f64::NAN, missing: None, d: Vec::new(), t: Vec::new() }
    }
}

/// tridist's distance (not squared) at `p`, NaN on an error.
fn distance<T: Real>(e: &Engine, a: &Mesh<T>, b: &Mesh<T>, p: &Pose<T>) -> f64 {
    e.mesh_distance(a, &Pose::identity(), b, p).ok().flatten().map_or(f64::NAN, |r| r.sqdist.to_f64().sqrt())
}

/// Every contender on every placement of one pair: per placement, the one-thread contenders
/// in alternated bursts (`bursts_of`), then TrueForm on its default threads in bursts of its own.
fn measure(
    a: &SceneMesh,
    b: &SceneMesh,
    poses: &[Pose<f64>],
    budget: Duration,
    libs: &[MeshLib],
) -> Result<Vec<Column>, String> {
    let e = Engine::auto();
    // everything one thread, TrueForm's build too (TBB's default until the first call)
    trueform_threads(1);
    let timed = |f: &mut dyn FnMut()| {
        let t0 = Instant::now();
        f();
        t0.elapsed().as_secs_f64()
    };
    let (mut m32, mut m64) = (None, None);
    let b32 = timed(&mut || m32 = Some((mesh::<f32>(a), mesh::<f32>(b))));
    let b64 = timed(&mut || m64 = Some((mesh::<f64>(a), mesh::<f64>(b))));
    let ((a32, b32m), (a64, b64m)) = (m32.ok_or("no build")?, m64.ok_or("no build")?);
    let (a32, b32m, a64, b64m) = (a32?, b32m?, a64?, b64m?);
    let mut cols = vec![Column::new("tridist f32"), Column::new("tridist f64")];
    (cols[0].build, cols[1].build) = (b32, b64);
    let mut peers: Vec<(MeshLib, Option<(MeshPeer, MeshPeer)>)> = Vec::new();
    for &l in libs {
        let mut m = None;
        let secs = timed(&mut || {
            m = MeshPeer::new(l, &a.vertices, &a.triangles).zip(MeshPeer::new(l, &b.vertices, &b.triangles))
        });
        let mut c = Column::new(&format!("{}, one thread", l.name()));
        c.missing = m.is_none().then(|| l.how_to_get());
        c.build = secs;
        cols.push(c);
        peers.push((l, m));
    }
    let tf = MeshLib::TrueFormAabbF32;
    let tf_models = peers.iter().find(|(l, _)| *l == tf).and_then(|(_, m)| m.as_ref());
    let mut c = Column::new(&format!("{}, TBB's default threads", tf.name()));
    c.missing = tf_models.is_none().then(|| tf.how_to_get());
    cols.push(c);
    let id = Pose::<f64>::identity();
    for p in poses {
        let (p32, p64) = (pose_in::<f32>(p), pose_in::<f64>(p));
        let mut d = vec![f64::NAN; cols.len()];
        let t = {
            let (d_t, d_p) = d.split_at_mut(2);
            let [d32, d64] = d_t else { unreachable!("two tridist columns") };
            let mut fs: Vec<Box<dyn FnMut() + '_>> = vec![
                Box::new(|| *d32 = distance(&e, &a32, &b32m, &p32)),
                Box::new(|| *d64 = distance(&e, &a64, &b64m, &p64)),
            ];
            for ((_, m), slot) in peers.iter().zip(d_p.iter_mut()) {
                if let Some((ma, mb)) = m {
                    fs.push(Box::new(move || *slot = ma.distance(&id, mb, p)));
                }
            }
            let mut refs: Vec<&mut dyn FnMut()> =
                fs.iter_mut().map(|f| &mut **f as &mut dyn FnMut()).collect();
            bursts_of(&mut refs, budget)
        };
        // the measured columns' times, in order
        let mut t = t.into_iter();
        for (k, c) in cols.iter_mut().enumerate().take(2 + peers.len()) {
            if c.missing.is_none() {
                c.t.push(t.next().unwrap_or(f64::NAN));
                c.d.push(d[k]);
            }
        }
        if let Some((ma, mb)) = tf_models {
            trueform_threads(0);
            let mut dd = f64::NAN;
            let t = bursts_of(&mut [&mut || dd = ma.distance(&id, mb, p)], budget);
            trueform_threads(1);
            let c = cols.last_mut().expect("the default-threads column");
            c.t.push(t[0]);
            c.d.push(dd);
        }
    }
    Ok(cols)
}

/// The section and its summary for the README.
pub fn protocol_md(t: &mut String, s: &Settings, seed: u64) -> Result<String, String> {
    let n = 4 * s.mesh_poses;
    let budget = s.budget / 2;
    let _ = writeln!(
        t,
        "## TrueForm's protocol: random placements\n\nMesh distance (closest pair with its points; tridist `mesh_distance`, FCL and Coal `distance` with nearest points, TrueForm `tf::neighbor_search` of two forms) with the second mesh at {n} random rigid placements: a uniformly random rotation about the origin, then a translation uniform in the ball of twice the fixed mesh's bounding-box diagonal (`protocol::ball_placements`, seed {seed}); both meshes scaled to [-1, 1]^3. This is the protocol TrueForm publishes its mesh distance figures with: most placements are separated, where a query spends its time in the trees, not in the triangle kernels. Per placement each contender's time is the median of {} alternated bursts of repeated calls within {:.1} ms in all (as above), one thread, TrueForm also on TBB's default threads (every core) in bursts of its own. Peers: FCL 0.7 (Debian's `libfcl-dev`, the library as shipped), Coal 3.0.3 (the PyPI wheel's `libcoal`; FCL's maintained fork, OBBRSS), TrueForm 0.10.7 (the PyPI wheel's headers, compiled here with `-O3 -march=native`, trees of 4 children and 4 triangles per leaf as its own benchmarks build them; axis-aligned boxes in float as its benchmarks use, axis-aligned and OBBRSS in double). Coal and TrueForm: `bash scenes/peer/install.sh`, then rebuild. Over tridist: the peer's time over tridist's at each placement (above 1: tridist is faster), the median and the worst placement, over the placements where the peer's distance is right; wrong: off tridist f64's (itself checked against an exact brute force by the test suite) by more than 64 u S in the peer's precision, S the scene's magnitude, or not finite; |Δd|: the largest difference from tridist f64's distance among the right ones; build: both meshes' trees, one build each (the tables above time tridist's builds in rounds).\n",
        crate::meshreport::BURSTS,
        budget.as_secs_f64() * 1e3,
    );
    let mut summary = Vec::new();
    for (fa, fb) in PAIRS {
        let (a, b) = (carried_normalised(fa)?, carried_normalised(fb)?);
        let poses = ball_placements(n, ball_radius(&a), seed);
        let cols = measure(&a, &b, &poses, budget, &MeshLib::ALL)?;
        let name = |f: &str| f.trim_end_matches(".off").trim_end_matches("_large").to_string();
        let separated = cols[1].d.iter().filter(|&&d| d > 0.0).count();
        let _ = writeln!(
            t,
            "### {} ({} triangles) vs {} ({} triangles)\n\n{separated} of the {n} placements separated.\n\n| library | median ms | mean ms | over tridist f64 (median) | worst | placements where it is faster | over tridist f32 (median) | worst | wrong distances | \\|Δd\\| of the rest | build ms |\n|---|---|---|---|---|---|---|---|---|---|---|",
            name(fa),
            a.triangles.len(),
            name(fb),
            b.triangles.len(),
        );
        let line = rows(t, &cols, &poses);
        let _ = writeln!(t);
        summary.push(format!(
            "{} vs {}: tridist f64 {} ms median per placement; peer time over tridist f64's, median (worst placement): {}",
            name(fa),
            name(fb),
            ms(crate::common::median(cols[1].t.clone())),
            if line.is_empty() { "no C++ peer built".to_string() } else { line.join(", ") }
        ));
    }
    Ok(format!(" TrueForm's protocol ({n} random placements, one thread): {}.", summary.join("; ")))
}

/// The near-contact gaps of [`peers_md`], as fractions of the scene's size (2: both meshes in
/// [-1, 1]^3).
const NEAR_FRACTIONS: [f64; 5] = [1e-1, 1e-2, 1e-3, 1e-4, 1e-5];

/// Placements per gap in [`peers_md`].
const PER_GAP: usize = 2;

/// MESH.md's "Every peer on the trajectory and at near contact": the contenders of
/// [`protocol_md`] on the trajectory tables' meshes and poses, and at near contact at gaps of
/// [`NEAR_FRACTIONS`] of the scene's size; its README phrase.
pub fn peers_md(t: &mut String, s: &Settings, seed: u64) -> Result<String, String> {
    let (a, b) = (carried_normalised("armadillo.off")?, carried_normalised("fandisk_large.off")?);
    let budget = s.budget / 2;
    let _ = writeln!(
        t,
        "## Every peer on the trajectory and at near contact\n\nThe contenders of TrueForm's protocol below (tridist, FCL, Coal, TrueForm in three tree configurations, and on TBB's default threads), timed and judged as there, on the Armadillo ({} triangles) and the fandisk ({} triangles) of the tables above: the seed's trajectory ({} poses through each other), and near contact: the fandisk at a random orientation moved along a random direction until its distance to the armadillo is a fraction {} of the scene's size 2 (`protocol::near_contact_pose`), {PER_GAP} placements per gap. Times within {:.1} ms per placement in all, one thread.\n",
        a.triangles.len(),
        b.triangles.len(),
        s.mesh_poses,
        NEAR_FRACTIONS.map(|f| format!("{f:.0e}")).join(", "),
        budget.as_secs_f64() * 1e3,
    );
    let trajectory: Vec<Pose<f64>> = (0..s.mesh_poses).map(|k| trajectory_pose(k, s.mesh_poses).1).collect();
    let (a64, b64) = (mesh::<f64>(&a)?, mesh::<f64>(&b)?);
    let mut near = Vec::new();
    for (i, f) in NEAR_FRACTIONS.iter().enumerate() {
        for k in 0..PER_GAP {
            near.push(near_contact_pose(&a64, &b64, seed, (i * PER_GAP + k) as u64, 2.0 * f)?);
        }
    }
    let mut summary = Vec::new();
    for (what, poses) in [("the trajectory", &trajectory), ("near contact", &near)] {
        let cols = measure(&a, &b, poses, budget, &MeshLib::ALL)?;
        let _ = writeln!(
            t,
            "### {what} ({} placements)\n\n| library | median ms | mean ms | over tridist f64 (median) | worst | placements where it is faster | over tridist f32 (median) | worst | wrong distances | \\|Δd\\| of the rest | build ms |\n|---|---|---|---|---|---|---|---|---|---|---|",
            poses.len()
        );
        let line = rows(t, &cols, poses);
        let _ = writeln!(t);
        summary.push(format!(
            "{what}: {}",
            if line.is_empty() { "no C++ peer built".to_string() } else { line.join(", ") }
        ));
    }
    Ok(format!(" Every peer, time over tridist f64's, median (worst placement): {}.", summary.join("; ")))
}

/// The table rows of one pair's columns (the header is the caller's), and the README's phrase
/// per peer.
fn rows(t: &mut String, cols: &[Column], poses: &[Pose<f64>]) -> Vec<String> {
    let n = poses.len();
    // a peer's distance is wrong where it is off tridist f64's by more than 64 u S in the
    // peer's precision (S: the moved meshes' magnitude); its times are compared on the
    // placements it answered right
    let mags: Vec<f64> = poses.iter().map(|p| placed_magnitude(p.translation)).collect();
    let mut line = Vec::new();
    for c in cols {
        if let Some(how) = c.missing {
            let _ = writeln!(t, "| {} | not built ({how}) | | | | | | | | | |", c.name);
            continue;
        }
        let u = if c.name.contains("float") || c.name.ends_with("f32") {
            f32::EPSILON as f64 / 2.0
        } else {
            f64::EPSILON / 2.0
        };
        let right: Vec<bool> =
            c.d.iter().zip(&cols[1].d).zip(&mags).map(|((x, y), s)| (x - y).abs() <= 64.0 * u * s).collect();
        let wrong = right.iter().filter(|r| !**r).count();
        let over = |k: usize| -> Vec<f64> {
            c.t.iter().zip(&cols[k].t).zip(&right).filter(|(_, r)| **r).map(|((p, q), _)| p / q).collect()
        };
        let (o64, o32) = (over(1), over(0));
        let worst = |v: &[f64]| {
            if v.is_empty() {
                f64::NAN
            } else {
                v.iter().copied().fold(f64::INFINITY, f64::min)
            }
        };
        let med = |v: &[f64]| if v.is_empty() { f64::NAN } else { crate::common::median(v.to_vec()) };
        let faster = o64.iter().filter(|&&r| r < 1.0).count();
        let dd =
            c.d.iter()
                .zip(&cols[1].d)
                .zip(&right)
                .filter(|(_, r)| **r)
                .map(|((x, y), _)| (x - y).abs())
                .fold(0.0f64, f64::max);
        let own = c.name.starts_with("tridist");
        let cell = |x: String| if own { "-".to_string() } else { x };
        let _ = writeln!(
            t,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.1e} | {} |",
            c.name,
            ms(crate::common::median(c.t.clone())),
            ms(c.t.iter().sum::<f64>() / c.t.len() as f64),
            cell(ratio(med(&o64), 2)),
            cell(ratio(worst(&o64), 2)),
            cell(format!("{faster} of {}", o64.len())),
            cell(ratio(med(&o32), 2)),
            cell(ratio(worst(&o32), 2)),
            cell(format!("{wrong} of {n}")),
            dd,
            ms(c.build)
        );
        if !own {
            let w = ratio(worst(&o64), 2);
            let bad = if wrong > 0 { format!(", {wrong} of {n} distances wrong") } else { String::new() };
            line.push(format!(
                "{} {} (worst {w}{bad})",
                c.name.replace(", one thread", ""),
                ratio(med(&o64), 2)
            ));
        }
    }
    line
}

/// MESH.md's "Scale" section: TrueForm's protocol on the Armadillo against itself, subdivided
/// `Settings::mesh_scale` times (208,000 and 832,000 triangles per mesh), build and query per
/// library; its README phrase.
pub fn scale_md(t: &mut String, s: &Settings, seed: u64) -> Result<String, String> {
    let n = s.mesh_poses;
    let budget = s.budget / 4;
    let libs = [MeshLib::Fcl, MeshLib::Coal, MeshLib::TrueFormAabbF32];
    let base = carried_normalised("armadillo.off")?;
    let most = base.triangles.len() << (2 * s.mesh_scale);
    let _ = writeln!(
        t,
        "## Scale: the same protocol at up to {most} triangles per mesh\n\nThe Armadillo against itself as above, and each triangle split into four at its edges' midpoints up to {} times (`Mesh::subdivided`: the same surface, 4 times the triangles a level; `--mesh-scale`), at the first {n} placements of the protocol; times as above within {:.1} ms per placement in all; one build of each library's trees of both meshes, timed once (single builds of this size vary by a few percent). TrueForm in the configuration of its own benchmarks only (axis-aligned boxes in float).\n",
        s.mesh_scale,
        budget.as_secs_f64() * 1e3
    );
    let poses = ball_placements(n, ball_radius(&base), seed);
    let mut growth = Vec::new();
    // the Armadillo's 52,000 triangles, then 208,000 and 832,000 (`--mesh-scale`)
    for level in 0..=s.mesh_scale {
        let a = base.subdivided(level);
        let cols = measure(&a, &a, &poses, budget, &libs)?;
        let _ = writeln!(
            t,
            "### {} triangles per mesh\n\n| library | median ms | mean ms | over tridist f64 (median) | worst | placements where it is faster | over tridist f32 (median) | worst | wrong distances | \\|Δd\\| of the rest | build ms |\n|---|---|---|---|---|---|---|---|---|---|---|",
            a.triangles.len()
        );
        rows(t, &cols, &poses);
        let _ = writeln!(t);
        let coal = cols.iter().find(|c| c.name.starts_with("Coal") && c.missing.is_none());
        let over = |x: f64, y: f64| ratio(x / y, 2);
        growth.push(format!(
            "{} triangles: tridist f64 build {} ms, query {} ms{}",
            a.triangles.len(),
            ms(cols[1].build),
            ms(crate::common::median(cols[1].t.clone())),
            coal.map_or(String::new(), |c| format!(
                " (Coal's build {} tridist's, its median query time {} tridist's median)",
                over(c.build, cols[1].build),
                over(crate::common::median(c.t.clone()), crate::common::median(cols[1].t.clone()))
            ))
        ));
    }
    Ok(format!(" At scale (the Armadillo subdivided, {n} placements): {}.", growth.join("; ")))
}
