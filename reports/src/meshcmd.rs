//! `tridist mesh`: the mesh queries on two OFF files in poses.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::Args;
use tridist::{Engine, Mesh, Pose, Real, TreeShape};
use tridist_scenes::eval::Variant;

use crate::{parse_variant, Fail, Prec};

#[derive(Args, Debug)]
pub struct MeshArgs {
    /// The first mesh (OFF).
    pub a: PathBuf,
    /// The second mesh (OFF).
    pub b: PathBuf,
    /// Pose of the first mesh: `tx,ty,tz` or `tx,ty,tz,ax,ay,az,degrees` (translation, then
    /// rotation about the axis, applied first).
    #[arg(long, value_parser = parse_pose, default_value = "0,0,0", allow_hyphen_values = true)]
    pub pose_a: [f64; 7],
    /// Pose of the second mesh, as --pose-a.
    #[arg(long, value_parser = parse_pose, default_value = "0,0,0", allow_hyphen_values = true)]
    pub pose_b: [f64; 7],
    /// Contacts: report whether the meshes come within this distance (finite, non-negative;
    /// `mesh_within_margin`, which stops at its first hit) and the triangle pairs within it.
    #[arg(long, value_parser = crate::non_negative, allow_hyphen_values = true)]
    pub margin: Option<f64>,
    /// With --margin: print at most this many contacts (the closest first).
    #[arg(long, default_value_t = 10, allow_negative_numbers = true)]
    pub show: usize,
    /// With --margin: keep at most this many contacts, the closest (the search then narrows
    /// to the last one kept, so memory stays bounded whatever the margin); the count line
    /// then says "N or more".
    #[arg(long, default_value_t = 1_000_000, allow_negative_numbers = true)]
    pub max_contacts: usize,
    /// The closest point of the second mesh to this point `x,y,z`.
    #[arg(long, value_parser = parse_point, allow_hyphen_values = true)]
    pub point: Option<[f64; 3]>,
    /// Working precision (the meshes are rounded to it).
    #[arg(long, value_enum, default_value = "f64")]
    pub precision: Prec,
    /// Instruction set of the leaf kernels (`auto`: the best this CPU runs, or the one
    /// `TRIDIST_ISA` names).
    #[arg(long, default_value = "auto", value_parser = parse_variant)]
    pub variant: Variant,
    /// Most children of a tree node, 2 to 8 (`Mesh::with_shape`). Contacts, the verdict and
    /// the closest point are the same for every tree, the distance within its documented
    /// slack (`TreeShape`); the time differs.
    #[arg(long, default_value_t = tridist::TreeShape::DEFAULT.width, value_parser = tree_width, allow_negative_numbers = true)]
    pub width: usize,
    /// Most triangles of a tree leaf, 1 to 8: larger leaves build faster and suit contact
    /// queries (`--margin`); see "Leaf size" in reports/MESH.md.
    #[arg(long, default_value_t = tridist::TreeShape::DEFAULT.leaf, value_parser = leaf_size, allow_negative_numbers = true)]
    pub leaf: usize,
    /// Time the queries at each pose of the second mesh in this file (one per line: an optional
    /// label, then 3, 7 or 12 numbers; `tridist poses` writes them) instead of one --pose-b:
    /// a line per pose with the distance, the triangle pair, the verdict, with --margin the
    /// contact count, and each query's time.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["pose_b", "point"])]
    pub poses: Option<PathBuf>,
    /// Centre and scale both meshes to fit [-1, 1]^3 (largest side), as the report's
    /// protocols and `tridist poses` place them.
    #[arg(long)]
    pub normalise: bool,
    /// Tolerance of the queries, as `tridist eval` takes it: `default` (64 u S), `exact`, `K`
    /// or `scaled:K` (K u S), `abs:X`, `rel:R`, or `correctly-rounded` (the distance and the
    /// closest point's distance are the exact minimum's, correctly rounded in the working
    /// precision: squared distance and distance each `RN`; a distance that needs the exact
    /// oracle prints as `undecided`, a square that does fails as the library's
    /// `Error::Undecided`).
    #[arg(long, default_value = "default", value_parser = crate::parse_tolerance, allow_hyphen_values = true)]
    pub tolerance: tridist::Tolerance,
    /// Threads of the contact query (`Engine::threads`; the other queries run on one).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=256), allow_negative_numbers = true)]
    pub threads: u32,
    /// With --poses: each time is the median of repeated calls within this many milliseconds.
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u32).range(1..=60_000), allow_negative_numbers = true)]
    pub budget_ms: u32,
}

/// A tree width the library accepts ([`TreeShape::check`], so the message is the library's).
fn tree_width(s: &str) -> Result<usize, String> {
    let w: usize = s.parse().map_err(|e| format!("{e}"))?;
    TreeShape { width: w, ..TreeShape::default() }.check().map(|()| w).map_err(|e| e.to_string())
}

/// A leaf size the library accepts ([`TreeShape::check`]).
fn leaf_size(s: &str) -> Result<usize, String> {
    let n: usize = s.parse().map_err(|e| format!("{e}"))?;
    TreeShape { leaf: n, ..TreeShape::default() }.check().map(|()| n).map_err(|e| e.to_string())
}

fn parse_list(s: &str) -> Result<Vec<f64>, String> {
    let v: Result<Vec<f64>, _> = s.split(',').map(|x| x.trim().parse::<f64>()).collect();
    let v = v.map_err(|e| format!("{e} in {s:?}"))?;
    if v.iter().any(|x| !x.is_finite()) {
        return Err(format!("non-finite number in {s:?}"));
    }
    Ok(v)
}

fn parse_pose(s: &str) -> Result<[f64; 7], String> {
    let v = parse_list(s)?;
    match v.len() {
        3 => Ok([v[0], v[1], v[2], 0.0, 0.0, 1.0, 0.0]),
        7 => {
            let p = [v[0], v[1], v[2], v[3], v[4], v[5], v[6]];
            // a zero axis names no rotation: say so here, as a usage error
            pose::<f64>(&p)?;
            Ok(p)
        }
        n => Err(format!("a pose is 3 or 7 numbers (tx,ty,tz[,ax,ay,az,degrees]), found {n}")),
    }
}

fn parse_point(s: &str) -> Result<[f64; 3], String> {
    let v = parse_list(s)?;
    <[f64; 3]>::try_from(v.as_slice()).map_err(|_| format!("a point is 3 numbers x,y,z, found {}", v.len()))
}

/// The pose in precision `T`. Its numbers are finite (`parse_list`), but in f32 a translation
/// beyond f32's range is not.
fn pose<T: Real>(p: &[f64; 7]) -> Result<Pose<T>, String> {
    let axis = [p[3], p[4], p[5]].map(T::from_f64);
    Pose::from_axis_angle(axis, p[6].to_radians(), [p[0], p[1], p[2]].map(T::from_f64))
        .map_err(|e| format!("{e} (in {})", T::PRECISION.name()))
}

fn load<T: Real>(path: &std::path::Path, shape: TreeShape, normalise: bool) -> Result<Mesh<T>, Fail> {
    // the loader's errors name the file
    let m = crate::posescmd::load_scene(path, normalise)?;
    let v = m.vertices.iter().map(|p| p.map(T::from_f64)).collect();
    Mesh::with_shape(v, m.triangles, shape).map_err(|e| Fail(format!("{}: {e}", path.display())))
}

/// A number as the shortest decimal that reads back to it, in exponent form when plain
/// notation would run past 16 digits of zeros (`1e200`, not two hundred digits).
fn num(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-5..1e16).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

fn fmt3<T: Real>(p: [T; 3]) -> String {
    format!("{} {} {}", num(p[0].to_f64()), num(p[1].to_f64()), num(p[2].to_f64()))
}

/// The distance of an answer: the root of its squared distance, or, where that square
/// overflowed to `+inf` (the documented answer; its closest points stay finite), the distance
/// of the closest points, computed without squaring them whole (halved, then scaled by their
/// largest component, so only a distance beyond the largest f64 is infinite). An overflowed
/// square has points far apart, so that component is finite and not 0.
fn distance<T: Real>(sqdist: T, p: [T; 3], q: [T; 3]) -> f64 {
    let s = sqdist.to_f64();
    if s.is_finite() || s.is_nan() {
        return s.sqrt();
    }
    let half = [0, 1, 2].map(|k| q[k].to_f64() * 0.5 - p[k].to_f64() * 0.5);
    let m = half.iter().fold(0.0, |m: f64, x| m.max(x.abs()));
    2.0 * m * half.iter().map(|x| (x / m) * (x / m)).sum::<f64>().sqrt()
}

/// How an answer's distance prints: under the correctly rounded mode the library's own
/// (`undecided` where it needs the exact oracle), otherwise [`distance`] of its square and
/// points.
fn shown<T: Real>(e: &Engine, own: Option<T>, sqdist: T, p: [T; 3], q: [T; 3]) -> String {
    if e.current_tolerance().correctly_rounded {
        own.map_or("undecided (needs the exact oracle: feature `exact`)".into(), |d| num(d.to_f64()))
    } else {
        num(distance(sqdist, p, q))
    }
}

/// How a squared distance prints: its value, or that it overflowed.
fn squared<T: Real>(sqdist: T) -> String {
    let s = sqdist.to_f64();
    if s == f64::INFINITY {
        format!("overflows {}", T::PRECISION.name())
    } else {
        num(s)
    }
}

/// Milliseconds since `t0`.
fn ms_since(t0: Instant) -> f64 {
    t0.elapsed().as_secs_f64() * 1e3
}

pub fn cmd_mesh(a: &MeshArgs) -> Result<ExitCode, Fail> {
    match a.precision {
        Prec::F32 => run::<f32>(a),
        Prec::F64 => run::<f64>(a),
    }
}

fn run<T: Real>(a: &MeshArgs) -> Result<ExitCode, Fail> {
    if !a.variant.available() {
        return Err(Fail(format!("variant {} is not available on this CPU", a.variant.name())));
    }
    let e = Engine::new(a.variant.isa())?.threads(a.threads as usize).tolerance(a.tolerance);
    let t0 = Instant::now();
    let shape = TreeShape { width: a.width, leaf: a.leaf };
    // the poses file is read first: a malformed one fails before the trees are built
    let poses = match &a.poses {
        Some(f) => {
            let text = std::fs::read_to_string(f).map_err(|e| Fail(format!("{}: {e}", f.display())))?;
            Some(crate::posescmd::read_poses(&text).map_err(|e| Fail(format!("{}: {e}", f.display())))?)
        }
        None => None,
    };
    let (ma, mb) = (load::<T>(&a.a, shape, a.normalise)?, load::<T>(&a.b, shape, a.normalise)?);
    let build = t0.elapsed().as_secs_f64();
    let (pa, pb) = (
        pose::<T>(&a.pose_a).map_err(|e| Fail(format!("--pose-a: {e}")))?,
        pose::<T>(&a.pose_b).map_err(|e| Fail(format!("--pose-b: {e}")))?,
    );
    outln!(
        "meshes: {} triangles ({} nodes), {} triangles ({} nodes; trees of width {}, leaves of {}); load and build {:.3} s; {} {}",
        ma.len(),
        ma.node_count(),
        mb.len(),
        mb.node_count(),
        a.width,
        a.leaf,
        build,
        e.isa(),
        T::PRECISION.name()
    );
    if let Some(poses) = poses {
        let margin = a.margin.map(|m| (T::from_f64(m), m));
        if margin.is_some_and(|(m, _)| !m.is_finite()) {
            return Err(Fail(format!("--margin beyond the range of {}", T::PRECISION.name())));
        }
        let budget = std::time::Duration::from_millis(a.budget_ms.into());
        return crate::posescmd::timed(&e, &ma, &pa, &mb, &poses, margin, budget);
    }
    let t0 = Instant::now();
    match e.mesh_distance(&ma, &pa, &mb, &pb)? {
        Some(d) => {
            outln!("distance: {} (squared {})", shown(&e, d.distance, d.sqdist, d.p, d.q), squared(d.sqdist));
            outln!("closest points: {} | {}", fmt3(d.p), fmt3(d.q));
            outln!("triangle pair: {} {}", d.tri_a, d.tri_b);
        }
        None => outln!("distance: inf (a mesh is empty)"),
    }
    outln!("distance query: {:.3} ms", ms_since(t0));
    let t0 = Instant::now();
    match e.mesh_intersect(&ma, &pa, &mb, &pb)? {
        Some((i, j)) => outln!("intersect: yes (triangles {i} {j})"),
        None => outln!("intersect: no"),
    }
    outln!("intersection query: {:.3} ms", ms_since(t0));
    if let Some(m) = a.margin {
        let t0 = Instant::now();
        if !T::from_f64(m).is_finite() {
            return Err(Fail(format!("--margin {} is beyond the range of {}", num(m), T::PRECISION.name())));
        }
        match e.mesh_within_margin(&ma, &pa, &mb, &pb, T::from_f64(m))? {
            Some((i, j)) => outln!("within {}: yes (triangles {i} {j}; {:.3} ms)", num(m), ms_since(t0)),
            None => outln!("within {}: no ({:.3} ms)", num(m), ms_since(t0)),
        }
        let t0 = Instant::now();
        let c = e.mesh_contacts(&ma, &pa, &mb, &pb, T::from_f64(m), Some(a.max_contacts))?;
        let ms = ms_since(t0);
        if c.len() >= a.max_contacts {
            outln!("contacts within {}: {} or more (stopped at --max-contacts; {ms:.3} ms)", num(m), c.len());
        } else {
            outln!("contacts within {}: {} ({ms:.3} ms)", num(m), c.len());
        }
        for k in c.iter().take(a.show) {
            let d = num(distance(k.sqdist, k.p, k.q));
            outln!("  {} {} {d} | {} | {}", k.tri_a, k.tri_b, fmt3(k.p), fmt3(k.q));
        }
    }
    if let Some(x) = a.point {
        match e.mesh_closest_point(&mb, &pb, x.map(T::from_f64))? {
            Some(p) => outln!(
                "closest point of the second mesh: {} at {} (triangle {})",
                fmt3(p.point),
                shown(&e, p.distance, p.sqdist, x.map(T::from_f64), p.point),
                p.tri
            ),
            None => outln!("closest point: none (the second mesh is empty)"),
        }
    }
    Ok(ExitCode::SUCCESS)
}
