//! The mesh report (MESH.md): tree build time and per-pose query times along the seed's
//! trajectory (Shellshear & Ytterlid's protocol: one real mesh moved through another), tridist
//! and parry3d on the same meshes and poses in the same run, with agreement checks.

use std::fmt::Write as _;
use std::time::{Duration, Instant};

use tridist::{Batch, ClosestPoints, Engine, Mesh, Pose, Precision, Real, TreeShape};
use tridist_scenes::mesh_peer::{MeshLib, MeshPeer};
use tridist_scenes::mesh_scenes::TREE_WIDTHS;
use tridist_scenes::peer::{Peer, PeerPose};
use tridist_scenes::protocol::{carried_normalised as normalised, trajectory_pose as pose_k, NEAR_GAP};
use tridist_scenes::workload::median_time;

use crate::common::header;
use crate::report::Settings;

struct Row {
    x: f64,
    d: f64,
    t_d: f64,
    t_i: f64,
    hit: bool,
    contacts: usize,
    t_c: f64,
    /// The contact query on two threads.
    t_c2: f64,
    /// The clearance check within the contacts' margin (`mesh_within_margin`) and its time.
    within: bool,
    t_w: f64,
    parry_d: f64,
    parry_t_d: f64,
    parry_hit: Option<bool>,
    parry_t_i: f64,
    /// FCL (double; NaN when not built): distance, its time, verdict, its time.
    fcl_d: f64,
    fcl_t_d: f64,
    fcl_hit: Option<bool>,
    fcl_t_i: f64,
}

/// A scene mesh as tridist's, rounded to `T`.
pub(crate) fn mesh<T: Real>(m: &tridist_scenes::mesh::Mesh) -> Result<Mesh<T>, String> {
    mesh_shaped(m, TreeShape::default())
}

/// [`mesh`] with a tree of `shape`.
fn mesh_shaped<T: Real>(m: &tridist_scenes::mesh::Mesh, shape: TreeShape) -> Result<Mesh<T>, String> {
    Mesh::with_shape(m.vertices.iter().map(|p| p.map(T::from_f64)).collect(), m.triangles.clone(), shape)
        .map_err(|e| e.to_string())
}

/// A pose in precision `T` (rounded from f64).
pub(crate) fn pose_in<T: Real>(p: &Pose<f64>) -> Pose<T> {
    Pose { rotation: p.rotation.map(|r| r.map(T::from_f64)), translation: p.translation.map(T::from_f64) }
}

/// One tree shape's means: build of both meshes, nodes of both; per trajectory pose
/// distance, intersection, contacts; per near placement distance, intersection, contacts
/// (seconds).
struct ShapeRow {
    shape: TreeShape,
    nodes: usize,
    build: f64,
    t: [f64; 6],
}

/// The leaf sizes the report's "Leaf size" table compares (at the default width).
const REPORT_LEAVES: [usize; 4] = [2, 4, 6, 8];

/// Every shape of `shapes` on the same poses, the shapes alternated pose by pose (so the
/// machine's drift falls on all of them alike), checked to give the same answers.
fn shape_rows<T: Real>(
    a: &tridist_scenes::mesh::Mesh,
    b: &tridist_scenes::mesh::Mesh,
    shapes: &[TreeShape],
    budget: Duration,
    poses: usize,
    near: &[Pose<f64>],
) -> Result<Vec<ShapeRow>, String> {
    let e = Engine::auto();
    let id = Pose::<T>::identity();
    let mut trees = Vec::new();
    let mut rows = Vec::new();
    for &shape in shapes {
        let mut built = None;
        let build =
            median_time(|| built = Some((mesh_shaped::<T>(a, shape), mesh_shaped::<T>(b, shape))), budget);
        let (ma, mb) = built.ok_or("no build")?;
        let (ma, mb) = (ma?, mb?);
        rows.push(ShapeRow { shape, nodes: ma.node_count() + mb.node_count(), build, t: [0.0; 6] });
        trees.push((ma, mb));
    }
    let all: Vec<(bool, Pose<T>)> = (0..poses)
        .map(|k| (true, pose_in::<T>(&pose_k(k, poses).1)))
        .chain(near.iter().map(|p| (false, pose_in::<T>(p))))
        .collect();
    let m = T::from_f64(0.02);
    for (on_path, p) in &all {
        let mut seen: Option<(f64, bool, usize)> = None;
        for ((ma, mb), row) in trees.iter().zip(&mut rows) {
            let (mut d, mut hit, mut c) = (f64::NAN, false, 0);
            let t_d = median_time(
                || d = e.mesh_distance(ma, &id, mb, p).ok().flatten().map_or(f64::NAN, |r| r.sqdist.to_f64()),
                budget,
            );
            let t_i = median_time(|| hit = matches!(e.mesh_intersect(ma, &id, mb, p), Ok(Some(_))), budget);
            let t_c = median_time(
                || c = e.mesh_contacts(ma, &id, mb, p, m, None).map_or(usize::MAX, |c| c.len()),
                budget,
            );
            let (n, at) = if *on_path { (poses, 0) } else { (near.len(), 3) };
            for (k, t) in [t_d, t_i, t_c].into_iter().enumerate() {
                row.t[at + k] += t / n as f64;
            }
            // the same answers for every shape (verdict, contact count; the distance within the
            // search's slack, as `TreeShape` documents it: each tree's answer is within
            // `MESH_DISTANCE_SLACK u S` of the same smallest kernel answer, S at most the pose's
            // largest translation plus sqrt(3) for meshes in [-1, 1]^3)
            let now = (d, hit, c);
            let mag = tridist_scenes::protocol::placed_magnitude(p.translation.map(Real::to_f64));
            let slack = Engine::MESH_DISTANCE_SLACK * T::UNIT_ROUNDOFF.to_f64() * mag;
            let apart =
                |x: f64, y: f64| (x.sqrt() - y.sqrt()).abs().is_nan() || (x.sqrt() - y.sqrt()).abs() > slack;
            if seen.is_some_and(|s| apart(s.0, now.0) || s.1 != now.1 || s.2 != now.2) {
                return Err(format!(
                    "tree {:?}: answers differ from {:?}: {now:?} vs {seen:?}",
                    row.shape, shapes[0]
                ));
            }
            seen = Some(now);
        }
    }
    Ok(rows)
}

/// One table of [`shape_rows`] per precision, a row per shape (`label` names it), its times
/// also as ratios to the default shape's.
fn shapes_md(
    t: &mut String,
    (a, b): (&tridist_scenes::mesh::Mesh, &tridist_scenes::mesh::Mesh),
    s: &Settings,
    near: &[Pose<f64>],
    shapes: &[TreeShape],
    label: (&str, fn(&TreeShape) -> usize),
) -> Result<(), String> {
    for p in [Precision::F32, Precision::F64] {
        let rows = match p {
            Precision::F32 => shape_rows::<f32>(a, b, shapes, s.budget, s.mesh_poses, near)?,
            Precision::F64 => shape_rows::<f64>(a, b, shapes, s.budget, s.mesh_poses, near)?,
        };
        let def = rows.iter().find(|r| r.shape == TreeShape::default()).ok_or("no default shape")?;
        let (build0, t0) = (def.build, def.t);
        let _ = writeln!(t, "| {} {} | nodes (both) | build ms (both) | distance ms | intersect ms | contacts ms | near: distance ms | near: intersect ms | near: contacts ms | build, default's / this | distance | near: distance | near: contacts |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|", p.name(), label.0);
        for r in &rows {
            let _ = writeln!(
                t,
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                (label.1)(&r.shape),
                r.nodes,
                ms(r.build),
                ms(r.t[0]),
                ms(r.t[1]),
                ms(r.t[2]),
                ms(r.t[3]),
                ms(r.t[4]),
                ms(r.t[5]),
                ratio(build0 / r.build, 2),
                ratio(t0[0] / r.t[0], 2),
                ratio(t0[3] / r.t[3], 2),
                ratio(t0[5] / r.t[5], 2),
            );
        }
        let _ = writeln!(t);
    }
    Ok(())
}

/// The tree-width and leaf-size sections of MESH.md.
fn shapes_sections(
    t: &mut String,
    a: &tridist_scenes::mesh::Mesh,
    b: &tridist_scenes::mesh::Mesh,
    s: &Settings,
    near: &[Pose<f64>],
) -> Result<(), String> {
    let d = TreeShape::default();
    let _ = writeln!(
        t,
        "## Tree width

The same binary splits (binned surface-area splits, see the `mesh` module's docs) collapsed into trees of 2, 4 and 8 children per node (`Mesh::with_width`: a node's children are the binary descendants found by opening the one of largest box area until there are that many, so every width has the same tree quality; the default is {}), {} triangles per leaf. The node tests (box and oriented-box gaps in f64) run on the engine's instruction set with a lane per child: on avx2fma's 4 f64 lanes, one vector per node of width 4, two of width 8, and half-empty vectors at width 2; a wider tree visits fewer levels and tests more child pairs per visit. Means per pose over the {} trajectory poses and the {} near-contact placements above (distance, intersection, contacts within 0.02); the widths alternated pose by pose, one thread, `Engine::auto()`; every width gave the same answers (verdict and contact count; the distance within the search's slack, `Engine::MESH_DISTANCE_SLACK` u S, as `TreeShape` documents: where pairs tie within it a tree may answer another of them), checked. The ratios are the default's time over this width's (above 1: faster than the default).
",
        d.width,
        d.leaf,
        s.mesh_poses,
        near.len()
    );
    let widths: Vec<TreeShape> = TREE_WIDTHS.iter().map(|&width| TreeShape { width, ..d }).collect();
    shapes_md(t, (a, b), s, near, &widths, ("width", |s| s.width))?;
    let _ = writeln!(
        t,
        "## Leaf size

The same splits stopped at leaves of at most {} triangles (`Mesh::with_shape`, `TreeShape {{ width, leaf }}`; the default is {} at width {}), measured as the table above (the leaf sizes alternated pose by pose, the same answers checked). A larger leaf means fewer nodes to build and to test, and more triangle pairs handed to the kernels per leaf pair: the contact query, which visits every node pair within its margin, and the build gain; the distance and intersection queries, which stop early, answer more pairs than they need.
",
        {
            let n = REPORT_LEAVES.map(|n| n.to_string());
            format!("{} and {}", n[..n.len() - 1].join(", "), n[n.len() - 1])
        },
        d.leaf,
        d.width
    );
    let leaves: Vec<TreeShape> = REPORT_LEAVES.iter().map(|&leaf| TreeShape { leaf, ..d }).collect();
    shapes_md(t, (a, b), s, near, &leaves, ("leaf", |s| s.leaf))
}

/// The agreement cell: "ok", or how far the libraries' distances differ.
fn agreement(agree: bool, diff: f64) -> String {
    if agree {
        "ok".to_string()
    } else {
        format!("**differ by {diff:.1e}**")
    }
}

/// How the builds are timed ([`alternated`]), as the report says it.
const BUILD_TIMING: &str = "medians of at least 5 rounds of one build of each library, after a warm-up";

/// How tridist's and FCL's query times are taken, as the report says it: [`bursts`], so
/// that a noisy moment of the shared machine falls on both (timed one after the other, the
/// f32 distance at pose +1.91 gave FCL / tridist 1.86x in the report of fbb6124 and 0.69x in
/// that of 461b0e9, tridist's own time 0.058 and 0.104 ms, with no change to the query; `spin
/// mesh distance 2 f32 1 0.5` gave 0.061 ms in the next session). Not call by call: each
/// library's calls then met the other's data in the caches, and tridist's near-contact
/// distance came out 1.5x slower on average in a report run of c7d7247 than in the committed
/// one of e5239ff, though c7d7247's queries are the faster (0.080 -> 0.118 ms, placement 8
/// 0.036 -> 0.117; FCL's moved both ways): a different measurement from the repeated queries
/// the report had timed.
const FCL_TIMING: &str = "tridist's and FCL's distance and intersection times per pose alternate in 5 rounds of one burst of each (a warm-up call, then repeated calls within a fifth of the budget: each library with its own data in the caches, as repeated queries have it), the median of the bursts' medians, so that a noisy moment of the shared machine falls on both";

/// Median seconds per call of each of `fs`, timed in rounds of one call of each after a
/// warm-up call of each: at least 5 rounds, and until 3 `budget`s are used (at most 200).
fn alternated<const N: usize>(mut fs: [&mut dyn FnMut(); N], budget: Duration) -> [f64; N] {
    fs.iter_mut().for_each(|f| f());
    let mut times: [Vec<f64>; N] = std::array::from_fn(|_| Vec::new());
    let start = Instant::now();
    while times[0].len() < 5 || (start.elapsed() < 3 * budget && times[0].len() < 200) {
        for (f, t) in fs.iter_mut().zip(times.iter_mut()) {
            let at = Instant::now();
            f();
            t.push(at.elapsed().as_secs_f64());
        }
    }
    times.map(crate::common::median)
}

/// Median seconds per call of each of `fs`, in [`BURSTS`] rounds of one burst of each: a
/// burst is [`median_time`] within a fifth of `budget` (a warm-up call, then calls until that
/// is used), so that each library runs with its own data in the caches, as repeated queries
/// do, and a noisy moment of the machine falls on all of them; the median of the bursts'.
fn bursts<const N: usize>(mut fs: [&mut dyn FnMut(); N], budget: Duration) -> [f64; N] {
    let t = bursts_of(&mut fs, budget);
    std::array::from_fn(|i| t[i])
}

/// [`bursts`] of any number of functions.
pub(crate) fn bursts_of(fs: &mut [&mut dyn FnMut()], budget: Duration) -> Vec<f64> {
    let mut times: Vec<Vec<f64>> = vec![Vec::new(); fs.len()];
    for _ in 0..BURSTS {
        for (f, t) in fs.iter_mut().zip(times.iter_mut()) {
            t.push(median_time(f, budget / BURSTS as u32));
        }
    }
    times.into_iter().map(crate::common::median).collect()
}

/// Rounds of [`bursts`].
pub(crate) const BURSTS: usize = 5;

fn rows<T: Peer + Real>(
    a: &tridist_scenes::mesh::Mesh,
    b: &tridist_scenes::mesh::Mesh,
    budget: Duration,
    poses: usize,
) -> Result<Built, String> {
    // Builds: one of each library per round after a warm-up of each (one cold build also
    // pays the allocator's first page faults), at least 5 rounds and 3 budgets, medians: the
    // three alternate, so that a noisy moment of the shared machine falls on all of them
    // (timed one after the other, 3 builds each, the same build measured 57.6 and 44.1 ms in
    // one run). Each peer from the same f64 data.
    let (ma, mb) = (mesh::<T>(a)?, mesh::<T>(b)?);
    let pa = T::trimesh(&a.vertices, &a.triangles).ok_or("parry refused the first mesh")?;
    let pb = T::trimesh(&b.vertices, &b.triangles).ok_or("parry refused the second mesh")?;
    let fcl = MeshPeer::new(MeshLib::Fcl, &a.vertices, &a.triangles).zip(MeshPeer::new(
        MeshLib::Fcl,
        &b.vertices,
        &b.triangles,
    ));
    let [build, parry_build, fcl_build] = alternated(
        [
            &mut || drop((mesh::<T>(a), mesh::<T>(b))),
            &mut || drop((T::trimesh(&a.vertices, &a.triangles), T::trimesh(&b.vertices, &b.triangles))),
            &mut || {
                if fcl.is_some() {
                    drop(MeshPeer::new(MeshLib::Fcl, &a.vertices, &a.triangles).zip(MeshPeer::new(
                        MeshLib::Fcl,
                        &b.vertices,
                        &b.triangles,
                    )))
                }
            },
        ],
        budget,
    );
    let e = Engine::auto();
    let margin = T::from_f64(MARGIN);
    let id = Pose::<T>::identity();
    let peer_id: PeerPose = ([0.0; 3], [0.0; 3]);
    let mut out = Vec::new();
    for k in 0..poses {
        let (pp, pose64) = pose_k(k, poses);
        let pose = Pose {
            rotation: pose64.rotation.map(|r| r.map(T::from_f64)),
            translation: pose64.translation.map(T::from_f64),
        };
        let mut d = f64::NAN;
        let mut run_d = || {
            d = e
                .mesh_distance(&ma, &id, &mb, &pose)
                .ok()
                .flatten()
                .map_or(f64::NAN, |r| r.sqdist.to_f64().sqrt())
        };
        let mut hit = false;
        let mut run_i = || hit = matches!(e.mesh_intersect(&ma, &id, &mb, &pose), Ok(Some(_)));
        // tridist and FCL in alternated bursts (FCL_TIMING)
        let (mut fcl_d, mut fcl_t_d, mut fcl_hit, mut fcl_t_i) = (f64::NAN, f64::NAN, None, f64::NAN);
        let (t_d, t_i) = match &fcl {
            Some((fa, fb)) => {
                let id64 = Pose::<f64>::identity();
                let [t_d, f_d] =
                    bursts([&mut run_d, &mut || fcl_d = fa.distance(&id64, fb, &pose64)], budget);
                let [t_i, f_i] =
                    bursts([&mut run_i, &mut || fcl_hit = fa.collide(&id64, fb, &pose64)], budget);
                (fcl_t_d, fcl_t_i) = (f_d, f_i);
                (t_d, t_i)
            }
            None => (median_time(run_d, budget), median_time(run_i, budget)),
        };
        // one and two threads alternated, three rounds, medians (the machine's drift falls on
        // both alike)
        let mut contacts = 0;
        let (mut t1, mut t2) = (Vec::new(), Vec::new());
        for _ in 0..3 {
            for (e, t) in [(e.threads(1), &mut t1), (e.threads(2), &mut t2)] {
                t.push(median_time(
                    || {
                        contacts = e
                            .mesh_contacts(&ma, &id, &mb, &pose, margin, None)
                            .map_or(usize::MAX, |c| c.len())
                    },
                    budget,
                ));
            }
        }
        let (t_c, t_c2) = (crate::common::median(t1), crate::common::median(t2));
        let mut within = false;
        let t_w = median_time(
            || within = matches!(e.mesh_within_margin(&ma, &id, &mb, &pose, margin), Ok(Some(_))),
            budget,
        );
        let mut parry_d = f64::NAN;
        let parry_t_d = median_time(|| parry_d = T::mesh_distance(&pa, &peer_id, &pb, &pp), budget);
        let mut parry_hit = None;
        let parry_t_i = median_time(|| parry_hit = T::mesh_intersects(&pa, &peer_id, &pb, &pp), budget);
        out.push(Row {
            x: pp.0[0],
            d,
            t_d,
            t_i,
            hit,
            contacts,
            t_c,
            t_c2,
            within,
            t_w,
            parry_d,
            parry_t_d,
            parry_hit,
            parry_t_i,
            fcl_d,
            fcl_t_d,
            fcl_hit,
            fcl_t_i,
        });
    }
    // the pose with the most contacts (the first of them), measured again for the summary
    let deep =
        out.iter().enumerate().max_by_key(|(k, r)| (r.contacts, std::cmp::Reverse(*k))).map(|(k, _)| k);
    let scaling = match deep {
        Some(k) if out[k].contacts > 0 => {
            let pose = pose_in::<T>(&pose_k(k, poses).1);
            Some(contact_scaling(&e, &ma, &mb, &pose, margin, budget))
        }
        _ => None,
    };
    Ok(Built { build, parry_build, fcl_build: fcl.is_some().then_some(fcl_build), rows: out, scaling })
}

/// Rounds of [`contact_scaling`].
const SCALING_ROUNDS: usize = 5;

/// The contact query at one pose on one thread, on two threads, and as two independent
/// one-thread workers running it at once (the machine's ceiling at that moment), in
/// [`SCALING_ROUNDS`] rounds: one and two threads call by call ([`alternated`], at least 375
/// ms), then the two workers (at least 250 ms). The medians of the rounds' two-thread speed
/// and of the two workers' combined speed, over one thread's.
fn contact_scaling<T: Real>(
    e: &Engine,
    a: &Mesh<T>,
    b: &Mesh<T>,
    pose: &Pose<T>,
    margin: T,
    budget: Duration,
) -> Scaling {
    let budget = budget.max(Duration::from_millis(250));
    let id = Pose::<T>::identity();
    let run = |e: &Engine| e.mesh_contacts(a, &id, b, pose, margin, None).is_ok();
    let (one_thread, two_threads) = (e.threads(1), e.threads(2));
    let (mut two, mut apart) = (Vec::new(), Vec::new());
    for _ in 0..SCALING_ROUNDS {
        // one and two threads call by call ([`alternated`], within half the budget), so that a
        // noisy moment of the shared machine falls on both (timed in turn, 250 ms of one then
        // 250 ms of the other, the rounds of one report run ranged over 1.57x-1.97x)
        let [one, both] = alternated(
            [
                &mut || {
                    run(&one_thread);
                },
                &mut || {
                    run(&two_threads);
                },
            ],
            budget / 2,
        );
        two.push(one / both);
        // two workers, each calling the one-thread query until the budget is spent (NaN,
        // printed "-", if a call fails)
        let calls = crate::common::two_workers(budget, || (), |_| run(&one_thread));
        apart.push(calls.map_or(f64::NAN, |c| c * one));
    }
    Scaling { two: crate::common::median(two), apart: crate::common::median(apart) }
}

/// Two threads' speed on the contact query and the two independent workers' (the ceiling),
/// over one thread's ([`contact_scaling`]).
#[derive(Clone, Copy)]
struct Scaling {
    two: f64,
    apart: f64,
}

/// One precision's measurements.
struct Built {
    build: f64,
    parry_build: f64,
    fcl_build: Option<f64>,
    rows: Vec<Row>,
    /// At the pose with the most contacts (`None` when no pose has any).
    scaling: Option<Scaling>,
}

/// Milliseconds, or "-" for a peer not measured (NaN).
pub(crate) fn ms(s: f64) -> String {
    if s.is_nan() {
        "-".into()
    } else {
        format!("{:.3}", s * 1e3)
    }
}

/// A ratio, or "-" for a peer not measured.
pub(crate) fn ratio(x: f64, digits: usize) -> String {
    if x.is_nan() {
        "-".into()
    } else {
        format!("{x:.digits$}x")
    }
}

fn verdict(h: Option<bool>) -> &'static str {
    match h {
        Some(true) => "yes",
        Some(false) => "no",
        None => "-",
    }
}

/// One near-contact placement: its distance (tridist f64) and the times of tridist (f32, f64)
/// and FCL for the distance and the intersection test.
struct NearRow {
    pose: Pose<f64>,
    d: f64,
    t_d32: f64,
    t_d64: f64,
    fcl_d: f64,
    fcl_t_d: f64,
    hit: bool,
    t_i32: f64,
    t_i64: f64,
    fcl_hit: Option<bool>,
    fcl_t_i: f64,
    /// The contacts within [`MARGIN`] (f64) and the contact query's times (f32, f64).
    contacts: usize,
    t_c32: f64,
    t_c64: f64,
    /// [`kernel_floor`]: its time (f32) and whether it gave every contact's distance.
    t_k32: f64,
    floor_same: bool,
    /// The clearance check within [`MARGIN`] (f64) and its times (f32, f64).
    within: bool,
    t_w32: f64,
    t_w64: f64,
}

/// The margin of the contact query (1 % of the scene's size).
const MARGIN: f64 = 0.02;

/// The fandisk rotated about a random axis by a random angle and moved along a random
/// direction until its distance to the armadillo is [`NEAR_GAP`]
/// ([`tridist_scenes::protocol::near_contact_pose`], which `spin mesh <query> n<k>` also
/// uses), one placement per `k`.
fn near_rows(
    a: &tridist_scenes::mesh::Mesh,
    b: &tridist_scenes::mesh::Mesh,
    budget: Duration,
    placements: usize,
    seed: u64,
) -> Result<Vec<NearRow>, String> {
    let (a32, b32, a64, b64) = (mesh::<f32>(a)?, mesh::<f32>(b)?, mesh::<f64>(a)?, mesh::<f64>(b)?);
    let fcl = MeshPeer::new(MeshLib::Fcl, &a.vertices, &a.triangles).zip(MeshPeer::new(
        MeshLib::Fcl,
        &b.vertices,
        &b.triangles,
    ));
    let e = Engine::auto();
    let (id32, id64) = (Pose::<f32>::identity(), Pose::<f64>::identity());
    let mut out = Vec::new();
    for k in 0..placements {
        let pose64 = tridist_scenes::protocol::near_contact_pose(&a64, &b64, seed, k as u64, NEAR_GAP)?;
        let pose32 = Pose {
            rotation: pose64.rotation.map(|r| r.map(|x| x as f32)),
            translation: pose64.translation.map(|x| x as f32),
        };
        let d = tridist_scenes::protocol::mesh_gap(&e, &a64, &b64, &pose64)?;
        let mut hit = false;
        let mut run_d32 = || drop(e.mesh_distance(&a32, &id32, &b32, &pose32));
        let mut run_d64 = || drop(e.mesh_distance(&a64, &id64, &b64, &pose64));
        let mut run_i32 = || drop(e.mesh_intersect(&a32, &id32, &b32, &pose32));
        let mut run_i64 = || hit = matches!(e.mesh_intersect(&a64, &id64, &b64, &pose64), Ok(Some(_)));
        // tridist and FCL in alternated bursts (FCL_TIMING)
        let (mut fcl_d, mut fcl_t_d, mut fcl_hit, mut fcl_t_i) = (f64::NAN, f64::NAN, None, f64::NAN);
        let ([t_d32, t_d64], [t_i32, t_i64]) = match &fcl {
            Some((fa, fb)) => {
                let [d32, d64, f_d] = bursts(
                    [&mut run_d32, &mut run_d64, &mut || fcl_d = fa.distance(&id64, fb, &pose64)],
                    budget,
                );
                let [i32_, i64_, f_i] = bursts(
                    [&mut run_i32, &mut run_i64, &mut || fcl_hit = fa.collide(&id64, fb, &pose64)],
                    budget,
                );
                (fcl_t_d, fcl_t_i) = (f_d, f_i);
                ([d32, d64], [i32_, i64_])
            }
            None => (
                [median_time(run_d32, budget), median_time(run_d64, budget)],
                [median_time(run_i32, budget), median_time(run_i64, budget)],
            ),
        };
        let mut contacts = 0;
        let t_c32 =
            median_time(|| drop(e.mesh_contacts(&a32, &id32, &b32, &pose32, MARGIN as f32, None)), budget);
        let t_c64 = median_time(
            || {
                contacts =
                    e.mesh_contacts(&a64, &id64, &b64, &pose64, MARGIN, None).map_or(usize::MAX, |c| c.len())
            },
            budget,
        );
        let (t_k32, floor_same) = kernel_floor(&e, &a32, &b32, &pose32, budget)?;
        let mut within = false;
        let t_w32 =
            median_time(|| drop(e.mesh_within_margin(&a32, &id32, &b32, &pose32, MARGIN as f32)), budget);
        let t_w64 = median_time(
            || within = matches!(e.mesh_within_margin(&a64, &id64, &b64, &pose64, MARGIN), Ok(Some(_))),
            budget,
        );
        out.push(NearRow {
            contacts,
            t_c32,
            t_c64,
            t_k32,
            floor_same,
            within,
            t_w32,
            t_w64,
            pose: pose64,
            d,
            t_d32,
            t_d64,
            fcl_d,
            fcl_t_d,
            hit,
            t_i32,
            t_i64,
            fcl_hit,
            fcl_t_i,
        });
    }
    Ok(out)
}

/// The floor under any f32 contact query that returns these contacts: the triangle kernel
/// alone on the contacts' own triangle pairs, moved beforehand ([`Mesh::triangle_at`], as the
/// queries move them) and run as one batch with closest points, as the contact query computes
/// them, with no traversal at all. Returns its median time and whether it gave each contact's
/// squared distance bit for bit (the same question asked). No contacts: zero time, `true`.
/// (The contacts come from a call of their own, untimed: keeping the timed calls' answers
/// alive would keep the allocator from reusing their memory, which changes the contact
/// query's time; see docs/notes/kernel-speed.md, "Contacts on two threads at the deepest pose". "Any contact query" means
/// one built on these kernels: a faster kernel would lower the floor.)
fn kernel_floor(
    e: &Engine,
    a: &Mesh<f32>,
    b: &Mesh<f32>,
    pose: &Pose<f32>,
    budget: Duration,
) -> Result<(f64, bool), String> {
    let found =
        e.mesh_contacts(a, &Pose::identity(), b, pose, MARGIN as f32, None).map_err(|x| x.to_string())?;
    if found.is_empty() {
        return Ok((0.0, true));
    }
    let named =
        |t: Option<[[f32; 3]; 3]>| t.ok_or_else(|| "a contact names no triangle of its mesh".to_string());
    let ta = found.iter().map(|c| named(a.triangle(c.tri_a))).collect::<Result<Vec<_>, _>>()?;
    let tb = found.iter().map(|c| named(b.triangle_at(c.tri_b, pose))).collect::<Result<Vec<_>, _>>()?;
    let (ta, tb) = (Batch::from_slice(&ta), Batch::from_slice(&tb));
    let mut out = vec![ClosestPoints::default(); found.len()];
    let t = median_time(|| drop(e.closest_points_triangle_triangle(&ta, &tb, &mut out)), budget);
    let same = out.iter().zip(&found).all(|(o, c)| o.sqdist.to_bits() == c.sqdist.to_bits());
    Ok((t, same))
}

/// The near-contact section of MESH.md; returns its sentence for the README's results.
fn near_md(t: &mut String, rows: &[NearRow]) -> String {
    let _ = writeln!(
        t,
        "## Near contact at random orientations

The fandisk rotated about a random axis by a random angle and moved along a random direction until its distance to the armadillo is {NEAR_GAP} (0.05 % of the scene's size; bisection on the translation with tridist f64), one placement per row, the same meshes and timing as above. Contacts: the triangle pairs within {MARGIN} (1 % of the scene's size, so twenty times the gap; their count in f64) and the contact query's time; the distance query answers one pair of them. Kernels alone: the floor under any contact query with these answers, the f32 triangle kernel with closest points run as one batch on exactly the contacts' triangle pairs (moved beforehand as the queries move them), with no traversal; the agreement column also checks that it gives every contact's squared distance bit for bit. Within: the clearance check at the same margin (`mesh_within_margin`: are the meshes within {MARGIN}? It stops at its first pair within it) and its time; FCL has no such query here (FCL's `collide` has no margin).

| placement | distance | tridist f32 ms | tridist f64 ms | FCL ms | FCL / tridist f32 | FCL / tridist f64 | intersect (tridist, FCL) | tridist f32 ms | tridist f64 ms | FCL ms | contacts | contacts f32 ms | contacts f64 ms | kernels alone f32 ms | within | within f32 ms | within f64 ms | agreement |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    );
    let mut sum = [0.0; 11];
    let mut no_slower = 0;
    for (k, r) in rows.iter().enumerate() {
        let diff = if r.fcl_d.is_nan() { 0.0 } else { (r.d - r.fcl_d).abs() };
        let agree = diff <= 1e-8
            && r.fcl_hit.is_none_or(|h| h == r.hit)
            && r.within == (r.contacts > 0)
            && r.floor_same;
        let times = [
            r.t_d32, r.t_d64, r.fcl_t_d, r.t_i32, r.t_i64, r.fcl_t_i, r.t_c32, r.t_c64, r.t_w32, r.t_w64,
            r.t_k32,
        ];
        for (x, v) in sum.iter_mut().zip(times) {
            *x += v;
        }
        // placements whose contact query took no longer than their distance query
        no_slower += usize::from(r.t_c32 <= r.t_d32 && r.t_c64 <= r.t_d64);
        let _ = writeln!(
            t,
            "| {k} | {:.6e} | {} | {} | {} | {} | {} | {}, {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.d,
            ms(r.t_d32),
            ms(r.t_d64),
            ms(r.fcl_t_d),
            ratio(r.fcl_t_d / r.t_d32, 2),
            ratio(r.fcl_t_d / r.t_d64, 2),
            if r.hit { "yes" } else { "no" },
            verdict(r.fcl_hit),
            ms(r.t_i32),
            ms(r.t_i64),
            ms(r.fcl_t_i),
            r.contacts,
            ms(r.t_c32),
            ms(r.t_c64),
            ms(r.t_k32),
            if r.within { "yes" } else { "no" },
            ms(r.t_w32),
            ms(r.t_w64),
            agreement(agree, diff)
        );
    }
    let n = rows.len().max(1) as f64;
    let m = sum.map(|x| x / n);
    let _ = writeln!(
        t,
        "\nMean time per placement: distance tridist f32 {} ms, f64 {} ms, FCL {} ms (FCL / tridist of the means **{} (f32)**, **{} (f64)**); intersect tridist f32 {} ms, f64 {} ms, FCL {} ms; contacts within {MARGIN} tridist f32 {} ms, f64 {} ms (contacts / distance of the means: {} (f32), {} (f64); the contact query no slower than the distance query in both precisions at {no_slower} of {} placements); the f32 kernels alone on the contacts' pairs {} ms, {} the f32 distance query's time: no contact query that runs them on every pair it returns can be faster than that; within {MARGIN} (the clearance check) tridist f32 {} ms, f64 {} ms (distance / within of the means: {} (f32), {} (f64)).\n",
        ms(m[0]),
        ms(m[1]),
        ms(m[2]),
        ratio(m[2] / m[0], 2),
        ratio(m[2] / m[1], 2),
        ms(m[3]),
        ms(m[4]),
        ms(m[5]),
        ms(m[6]),
        ms(m[7]),
        ratio(m[6] / m[0], 2),
        ratio(m[7] / m[1], 2),
        rows.len(),
        ms(m[10]),
        ratio(m[10] / m[0], 2),
        ms(m[8]),
        ms(m[9]),
        ratio(m[0] / m[8], 2),
        ratio(m[1] / m[9], 2)
    );
    format!(
        " Near contact ({} placements at random orientations, {NEAR_GAP} apart), mean per placement: distance tridist f32 {} ms, FCL {} ms (**{}**); intersect tridist f32 {} ms, FCL {} ms; the contacts within {MARGIN} (1 % of the scene's size) took {} (f32) the distance query's time (the kernels alone on the contacts' own triangle pairs, with no traversal, take {} of it), and the clearance check (are they within {MARGIN}?) answers in {} of it.",
        rows.len(),
        ms(m[0]),
        ms(m[2]),
        ratio(m[2] / m[0], 2),
        ms(m[3]),
        ms(m[5]),
        ratio(m[6] / m[0], 2),
        ratio(m[10] / m[0], 2),
        ratio(m[8] / m[0], 2)
    )
}

/// MESH.md, and its summary line for the README's results.
pub fn mesh_md(s: &Settings, seed: u64) -> Result<(String, String), String> {
    let (a, b) = (normalised("armadillo.off")?, normalised("fandisk_large.off")?);
    let mut t =
        header("Mesh queries: tridist, FCL and parry3d on the same meshes and poses", &s.command, seed);
    let _ = writeln!(
        t,
        "Armadillo ({} triangles) fixed at the origin, fandisk ({} triangles) moved along the seed's trajectory: {} poses from 3 units on one side through the armadillo to 3 units on the other, rotating once about (1, 2, 3); both meshes scaled to [-1, 1]^3. tridist: `Engine::auto()` ({}), a tree of {} children per node (see Tree width below) with an axis-aligned and an oriented box per node (pruning by the larger gap), {} triangles per leaf (see Leaf size below), the batch kernels at the leaves; distance with closest points (`mesh_distance`), `mesh_intersect`, `mesh_contacts`. FCL 0.7, double, the library as the distribution ships it (`libfcl-dev`; the shim's glue only is compiled here, so unlike the triangle peer it is not built with `-march=native`): `BVHModel<OBBRSS>`, `fcl::distance` with nearest points and `fcl::collide` (one contact), {}. parry3d / parry3d-f64 0.31: `TriMesh`, `query::distance` and `query::intersection_test`. Times: the median of repeated calls within {} ms per measurement, one thread (the contact query also on two), the same run; {FCL_TIMING}. Contacts: the triangle pairs within 0.02 (1 % of the scene's size) with their distances and closest points; FCL and parry have no such query here. Agreement: the distances of the three libraries (the poses are built from the same axis and angle: parry rotates by a quaternion, tridist and FCL by the same matrix, so they differ in rounding) and the intersection verdicts.\n",
        a.triangles.len(),
        b.triangles.len(),
        s.mesh_poses,
        Engine::auto().isa(),
        tridist::TreeShape::DEFAULT.width,
        tridist::TreeShape::DEFAULT.leaf,
        if MeshLib::Fcl.available() { "measured" } else { "**not measured: FCL was not found at build time** (`apt-get install libfcl-dev libeigen3-dev`, then rebuild)" },
        s.budget.as_millis()
    );
    // per precision: mean distance ms of tridist and FCL, mean intersect ms of both, parry ratio
    let (mut means, mut builds, mut ceilings) = (Vec::new(), Vec::new(), Vec::new());
    for p in ["f32", "f64"] {
        let m = if p == "f32" {
            rows::<f32>(&a, &b, s.budget, s.mesh_poses)?
        } else {
            rows::<f64>(&a, &b, s.budget, s.mesh_poses)?
        };
        let _ = writeln!(
            t,
            "## tridist {p}\n\nTree build of both meshes ({BUILD_TIMING}): tridist {} ms, FCL {} ms, parry3d {} ms (tridist takes {} parry3d's time).\n",
            ms(m.build),
            m.fcl_build.map_or("-".to_string(), ms),
            ms(m.parry_build),
            ratio(m.build / m.parry_build, 2)
        );
        builds.push((
            ms(m.build),
            ms(m.parry_build),
            m.fcl_build.map_or("-".to_string(), ms),
            ratio(m.build / m.parry_build, 2),
        ));
        let _ = writeln!(t, "| pose (x) | distance | tridist ms | FCL ms | parry3d ms | FCL / tridist | parry3d / tridist | intersect (tridist, FCL, parry3d) | tridist ms | FCL ms | parry3d ms | contacts | contacts ms | 2 threads ms | within | within ms | agreement |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
        let (mut parry_ratio, mut fcl_ratio, mut worst) = (0.0, 0.0, 0.0f64);
        let (mut sum_t, mut sum_fcl, mut sum_ti, mut sum_fcl_i, mut sum_tw) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for r in &m.rows {
            let tol = if p == "f32" { 1e-4 } else { 1e-8 };
            let diff =
                (r.d - r.parry_d).abs().max(if r.fcl_d.is_nan() { 0.0 } else { (r.d - r.fcl_d).abs() });
            // (and the clearance check says yes exactly where there are contacts)
            let agree = diff <= tol
                && r.parry_hit.is_none_or(|h| h == r.hit)
                && r.fcl_hit.is_none_or(|h| h == r.hit)
                && r.within == (r.contacts > 0);
            worst = worst.max(diff);
            parry_ratio += r.parry_t_d / r.t_d;
            fcl_ratio += r.fcl_t_d / r.t_d;
            sum_t += r.t_d;
            sum_fcl += r.fcl_t_d;
            sum_ti += r.t_i;
            sum_fcl_i += r.fcl_t_i;
            sum_tw += r.t_w;
            let _ = writeln!(
                t,
                "| {:+.2} | {:.6e} | {} | {} | {} | {} | {} | {}, {}, {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                r.x,
                r.d,
                ms(r.t_d),
                ms(r.fcl_t_d),
                ms(r.parry_t_d),
                ratio(r.fcl_t_d / r.t_d, 2),
                ratio(r.parry_t_d / r.t_d, 1),
                if r.hit { "yes" } else { "no" },
                verdict(r.fcl_hit),
                r.parry_hit.map_or("unsupported", |h| if h { "yes" } else { "no" }),
                ms(r.t_i),
                ms(r.fcl_t_i),
                ms(r.parry_t_i),
                r.contacts,
                ms(r.t_c),
                ms(r.t_c2),
                if r.within { "yes" } else { "no" },
                ms(r.t_w),
                agreement(agree, diff)
            );
        }
        let n = m.rows.len() as f64;
        // two threads on the contacts of the pose with the most of them (measured again)
        let (deep, ceiling) = m.scaling.map_or((f64::NAN, f64::NAN), |x| (x.two, x.apart));
        let _ = writeln!(
            t,
            "\nMean time per pose: distance tridist {} ms, FCL {} ms (FCL / tridist of the means **{}**; mean of the per-pose ratios {}); intersect tridist {} ms, FCL {} ms; within {MARGIN} (the clearance check) tridist {} ms. parry3d's distance time / tridist's, mean over the poses: **{:.1}x**. Largest distance difference {worst:.1e}. Contacts on two threads at the pose with the most contacts: **{}** one thread's speed (two independent one-thread workers: {}).\n",
            ms(sum_t / n),
            ms(sum_fcl / n),
            ratio(sum_fcl / sum_t, 2),
            ratio(fcl_ratio / n, 2),
            ms(sum_ti / n),
            ms(sum_fcl_i / n),
            ms(sum_tw / n),
            parry_ratio / n,
            ratio(deep, 2),
            ratio(ceiling, 2)
        );
        means.push((sum_t / n, sum_fcl / n, sum_ti / n, sum_fcl_i / n, parry_ratio / n, deep));
        ceilings.push(ratio(ceiling, 2));
    }
    let _ = writeln!(t, "Contacts on two threads: `Engine::threads(2)`, the traversal split into pieces walked in parallel and the contacts sorted in parallel (same contacts, same order); per pose, one and two threads measured alternately, three rounds, medians. The summary's figure at the pose with the most contacts is measured again in {SCALING_ROUNDS} rounds, each of one- and two-thread calls alternated call by call (at least 375 ms), then, as the machine's ceiling at that moment, two independent one-thread workers running the query at once for at least 250 ms (their combined speed over one thread's; this machine's two cores are shared, so that ceiling is below 2x when other work runs), medians.\n");
    let near = near_rows(&a, &b, s.budget, s.mesh_poses, seed)?;
    let near_summary = near_md(&mut t, &near);
    let mut protocol_summary = crate::meshprotocol::peers_md(&mut t, s, seed)?;
    protocol_summary += &crate::meshprotocol::protocol_md(&mut t, s, seed)?;
    protocol_summary += &crate::meshprotocol::scale_md(&mut t, s, seed)?;
    shapes_sections(&mut t, &a, &b, s, &near.iter().map(|r| r.pose).collect::<Vec<_>>())?;
    let (m32, m64) = (means[0], means[1]);
    let summary = format!(
        "- Mesh distance with closest points, Armadillo vs fandisk ({} poses through each other), one thread, mean per pose: tridist f32 {} ms, f64 {} ms; FCL (OBBRSS, double) {} ms: **{} (f32)** and **{} (f64)** FCL's speed; parry3d {:.1}x slower than tridist f32. Collision: tridist {} ms, FCL {} ms. Contacts within 1 % of the scene's size on two threads, at the pose with the most contacts: {} (f32) and {} (f64) one thread's speed (two independent one-thread workers at the same time: {} and {}).{near_summary}{protocol_summary} Tree build of both meshes ({BUILD_TIMING}): tridist f32 {} ms, f64 {} ms (axis-aligned and oriented boxes); parry3d f32 {} ms, f64 {} ms (axis-aligned boxes), so tridist takes {} (f32) and {} (f64) parry3d's time; FCL (OBBRSS) {} ms ([reports/MESH.md](reports/MESH.md)).",
        s.mesh_poses,
        ms(m32.0),
        ms(m64.0),
        ms(m64.1),
        ratio(m64.1 / m32.0, 2),
        ratio(m64.1 / m64.0, 2),
        m32.4,
        ms(m32.2),
        ms(m64.3),
        ratio(m32.5, 2),
        ratio(m64.5, 2),
        ceilings[0],
        ceilings[1],
        builds[0].0,
        builds[1].0,
        builds[0].1,
        builds[1].1,
        builds[0].3,
        builds[1].3,
        builds[1].2
    );
    Ok((t, summary))
}
