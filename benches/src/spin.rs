//! Runs one query on one workload for a few seconds (for `perf record`):
//! `cargo run --release -p tridist-benches --bin spin -- tri_tri random f32 avx2fma 5 [pairs [threads [sqdist|points [quick|full]]]]`
//! (`full`: without the quick stage, `Engine::quick_stage(false)`),
//! or a mesh query on the mesh report's scene (Armadillo fixed, fandisk at trajectory pose
//! `k` of 12, or at near-contact placement `n<k>` of MESH.md, 0.001 apart):
//! `spin mesh contacts|distance|intersect|within|build <k>|n<k> f32|f64 <threads> <secs> [leaf]`.
use tridist::{Engine, Intersection, Isa, Query};
use tridist_scenes::workload::Workload;
use tridist_scenes::{families, Family};

const USAGE: &str = "usage: spin <query> <family|arm_nearby> f32|f64 <variant|fcl> <secs> [pairs [threads [sqdist|points [quick|full [default|correctly-rounded]]]]]
       spin mesh contacts|distance|intersect|within|build <pose 0-11 | near placement n0-n11> f32|f64 <threads> <secs> [leaf size]";

/// Bad arguments: the reason and the usage on stderr, exit status 2.
fn usage(why: &str) -> ! {
    eprintln!("spin: {why}\n{USAGE}");
    std::process::exit(2)
}

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    if a.first().is_some_and(|x| x == "mesh") {
        if !(6..=7).contains(&a.len()) {
            usage("a mesh query takes 5 arguments and an optional leaf size");
        }
        return match a[3].as_str() {
            "f32" => mesh::<f32>(&a),
            "f64" => mesh::<f64>(&a),
            _ => usage("the precision is f32 or f64"),
        };
    }
    if !(5..=10).contains(&a.len()) {
        usage("a batch query takes 5 to 10 arguments");
    }
    let q = Query::parse(&a[0]).unwrap_or_else(|| usage("unknown query"));
    let arm = || tridist_scenes::mesh::carried("armadillo.off").expect("armadillo");
    // (`fcl` times the peer; the engine is then unused)
    let isa = if a[3] == "fcl" {
        Isa::Scalar
    } else {
        Isa::parse(&a[3]).unwrap_or_else(|| usage("unknown variant"))
    };
    let secs: f64 = a[4].parse().unwrap_or_else(|_| usage("seconds must be a number"));
    // optional: the number of pairs (default 4096) and of threads (default 1)
    let count: usize = a
        .get(5)
        .map_or(Some(4096), |x| x.parse().ok().filter(|n| *n > 0))
        .unwrap_or_else(|| usage("pairs must be a positive number"));
    let threads: usize = a
        .get(6)
        .map_or(Some(1), |x| x.parse().ok().filter(|n| *n > 0))
        .unwrap_or_else(|| usage("threads must be a positive number"));
    // optional: the outputs, squared distances only (the default) or with closest points
    let points = match a.get(7).map(String::as_str) {
        None | Some("sqdist") => false,
        Some("points") => true,
        Some(_) => usage("the outputs are sqdist or points"),
    };
    if points && q.is_verdict() {
        usage("a verdict query has no closest points");
    }
    // optional: with the quick stage (the default) or straight to the full fast stage
    let quick = match a.get(8).map(String::as_str) {
        None | Some("quick") => true,
        Some("full") => false,
        Some(_) => usage("the stages are quick or full"),
    };
    // optional: the tolerance, the default or the correctly rounded mode
    let tol = match a.get(9).map(String::as_str) {
        None | Some("default") => tridist::Tolerance::DEFAULT,
        Some("correctly-rounded") => tridist::Tolerance::CORRECTLY_ROUNDED,
        Some(_) => usage("the tolerance is default or correctly-rounded"),
    };
    if a[2] != "f32" && a[2] != "f64" {
        usage("the precision is f32 or f64");
    }
    // a family name, or `arm_nearby` (nearby pairs of the Armadillo mesh)
    let pairs: Vec<_> = if a[1] == "arm_nearby" {
        tridist_scenes::protocol::nearby_pairs(&arm(), 3.0, count, 7)
    } else {
        let fam = Family::parse(&a[1]).unwrap_or_else(|| usage("unknown family"));
        families::generate::<f64>(fam, 7, count).into_iter().map(|c| (c.a, c.b)).collect()
    };
    let e = Engine::new(isa)
        .unwrap_or_else(|_| usage("variant not available on this CPU"))
        .threads(threads)
        .quick_stage(quick)
        .tolerance(tol);
    let t = std::time::Instant::now();
    let mut n = 0usize;
    macro_rules! go {
        ($t:ty) => {{
            let w = Workload::<$t>::new(&pairs, 0.02);
            let len = w.len(q);
            let (mut out, mut v) = (vec![0.0 as $t; len], vec![Intersection::Invalid; len]);
            let mut counts = tridist::PathCounts::default();
            let mut cp = vec![tridist::ClosestPoints::<$t>::default(); if points { len } else { 0 }];
            while t.elapsed().as_secs_f64() < secs {
                let c =
                    if points { w.run_points(q, e, &mut cp) } else { w.run(q, e, false, &mut out, &mut v) };
                counts.add(&c.expect("run"));
                n += len;
            }
            println!("{counts:?}");
        }};
    }
    if a[3] == "fcl" {
        // the peer on the same pairs: `spin tri_tri random f64 fcl 5`
        use tridist_scenes::peer::{Lib, Shapes};
        macro_rules! fcl {
            ($t:ty) => {{
                let c = |t: &tridist::Triangle<f64>| t.map(|p| p.map(|x| x as $t));
                let (ta, tb): (Vec<_>, Vec<_>) = pairs.iter().map(|(x, y)| (c(x), c(y))).unzip();
                let s = Shapes::for_lib(Lib::Fcl, &ta, &tb);
                let mut out = vec![0.0 as $t; ta.len()];
                while t.elapsed().as_secs_f64() < secs {
                    s.distances(&mut out);
                    n += ta.len();
                }
            }};
        }
        if a[2] == "f32" {
            fcl!(f32)
        } else {
            fcl!(f64)
        }
    } else if a[2] == "f32" {
        go!(f32)
    } else {
        go!(f64)
    }
    println!("{:.2} M/s", n as f64 / t.elapsed().as_secs_f64() / 1e6);
}

/// `spin mesh <query> <pose> <precision> <threads> <secs> [leaf]`: calls per second and the
/// answer's size (trees of `leaf` triangles per leaf, the default's when not given).
fn mesh<T: tridist::Real>(a: &[String]) {
    use tridist::{Mesh, Pose, TreeShape};
    let load = |f: &str| tridist_scenes::protocol::carried_normalised(f).expect("carried mesh");
    let (arm, fan) = (load("armadillo.off"), load("fandisk_large.off"));
    let shape = match a.get(6) {
        Some(l) => TreeShape {
            leaf: l.parse().unwrap_or_else(|_| usage("the leaf size is a number")),
            ..TreeShape::default()
        },
        None => TreeShape::default(),
    };
    let tm = |m: &tridist_scenes::mesh::Mesh| {
        let v = m.vertices.iter().map(|p| p.map(T::from_f64)).collect();
        Mesh::with_shape(v, m.triangles.clone(), shape).unwrap_or_else(|e| usage(&e.to_string()))
    };
    // a trajectory pose `k`, or a near-contact placement `n<k>`
    let (near, k) = match a[2].strip_prefix('n') {
        Some(k) => (true, k),
        None => (false, a[2].as_str()),
    };
    let k: usize =
        k.parse().ok().filter(|k| *k < 12).unwrap_or_else(|| usage("the pose is 0 to 11 or n0 to n11"));
    let threads: usize =
        a[4].parse().ok().filter(|n| *n > 0).unwrap_or_else(|| usage("threads must be a positive number"));
    let secs: f64 = a[5].parse().unwrap_or_else(|_| usage("seconds must be a number"));
    let p64 = if near {
        let m64 = |m: &tridist_scenes::mesh::Mesh| {
            Mesh::new(m.vertices.clone(), m.triangles.clone()).expect("mesh")
        };
        // MESH.md's gap and seed
        tridist_scenes::protocol::near_contact_pose(
            &m64(&arm),
            &m64(&fan),
            tridist_scenes::seed(),
            k as u64,
            tridist_scenes::protocol::NEAR_GAP,
        )
        .expect("placement")
    } else {
        tridist_scenes::protocol::trajectory_pose(k, 12).1
    };
    let pose = Pose {
        rotation: p64.rotation.map(|r| r.map(T::from_f64)),
        translation: p64.translation.map(T::from_f64),
    };
    let (ma, mb) = (tm(&arm), tm(&fan));
    let id = Pose::<T>::identity();
    let e = Engine::auto().threads(threads);
    let margin = T::from_f64(0.02);
    let t = std::time::Instant::now();
    let (mut calls, mut size) = (0usize, 0usize);
    while t.elapsed().as_secs_f64() < secs {
        size = match a[1].as_str() {
            "contacts" => e.mesh_contacts(&ma, &id, &mb, &pose, margin, None).expect("contacts").len(),
            "distance" => e.mesh_distance(&ma, &id, &mb, &pose).expect("distance").map_or(0, |d| d.tri_a),
            "intersect" => e.mesh_intersect(&ma, &id, &mb, &pose).expect("intersect").map_or(0, |h| h.0),
            "within" => {
                e.mesh_within_margin(&ma, &id, &mb, &pose, margin).expect("within").map_or(0, |h| h.0)
            }
            "build" => tm(&arm).len() + tm(&fan).len(),
            _ => usage("unknown mesh query"),
        };
        calls += 1;
    }
    let el = t.elapsed().as_secs_f64();
    println!("{} {}: {calls} calls, {:.3} ms per call, answer {size}", a[1], a[2], 1e3 * el / calls as f64);
}
