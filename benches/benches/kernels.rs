//! Every query x variant x precision, in queries per second (`Throughput::Elements`), on the
//! standard workloads (`protocol::standard`: random unit-cube pairs, nearby Armadillo
//! triangles, and the paper's protocol: Armadillo vs Armadillo, CAD vs CAD, CAD vs Armadillo;
//! four triangles sharing a vertex, or four random ones, against one), plus the threaded batch
//! path, triangle distance without its quick stage (`<variant>-full`), and the mesh queries along the mesh report's trajectory (`mesh/`). Inputs come from the shared generators with fixed seeds; every
//! benchmark first checks its results against the scalar AoS variant. The triangle-distance
//! groups also time the peers on the same inputs in the same run: FCL's PQP `TriangleDistance`
//! (when its headers were installed at build time) and parry3d (f32) / parry3d-f64
//! `query::distance` on `Triangle` shapes, after checking that each agrees with tridist.
//!
//! `cargo bench -p tridist-benches` (all), `cargo bench -p tridist-benches -- tri_tri/random`
//! (a subset); `cargo test -p tridist-benches --benches` runs each once as a smoke test.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use tridist::{Engine, Intersection, Query};
use tridist_scenes::eval::Variant;
use tridist_scenes::mesh;
use tridist_scenes::peer::{self, Peer};
use tridist_scenes::protocol::{self, Grouping};
use tridist_scenes::workload::{check_engine, Workload};

type Pairs = Vec<(tridist::Triangle<f64>, tridist::Triangle<f64>)>;

fn workloads() -> Vec<(&'static str, Pairs)> {
    let w = protocol::standard(4096, 0x7121_d157).expect("data/meshes");
    w.into_iter().map(|n| (n.id, n.pairs)).collect()
}

/// Times the peer on the workload's triangle pairs after checking that it answers the same
/// question (`peer::agreement`); the disagreement is printed.
fn bench_peer<T: Peer>(
    g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    w: &Workload<T>,
    must_agree: bool,
) {
    let (ta, tb) = w.triangles();
    for lib in peer::Lib::ALL {
        if !lib.available() {
            eprintln!("{} not measured: {}", lib.name(), lib.missing_reason());
            continue;
        }
        // A harness error (wrong pose, unsquared distance) disagrees everywhere: the check must
        // pass on random pairs. Near contact a peer's own inaccuracy may exceed 1e-3 S (parry3d
        // f32 on nearby pairs): reported, and timed all the same.
        match peer::agreement(lib, ta, tb) {
            Ok((worst, beyond)) => eprintln!(
                "{} ({}) vs tridist: max |d - d'| / S = {worst:.2e}, {beyond} of {} pairs beyond 1e-3",
                lib.name(),
                T::NAME,
                ta.len()
            ),
            Err(e) if must_agree => panic!("{e}"),
            Err(e) => eprintln!("{e}"),
        }
        let shapes = peer::Shapes::for_lib(lib, ta, tb);
        let mut out = vec![T::ZERO; ta.len()];
        g.bench_function(BenchmarkId::from_parameter(lib.name()), |b| b.iter(|| shapes.distances(&mut out)));
    }
}

fn bench_precision<T: Peer>(c: &mut Criterion, name: &str, pairs: &Pairs) {
    let w = Workload::<T>::new(pairs, 0.02);
    for &q in Query::ALL {
        let mut g = c.benchmark_group(format!("{}/{name}/{}", q.name(), T::NAME));
        g.throughput(Throughput::Elements(w.len(q) as u64));
        g.sample_size(10);
        // every variant, then (triangle distance) the SIMD ones without the quick stage
        // (`Engine::quick_stage(false)`, named `<variant>-full`), each checked first
        let full = Variant::ALL.into_iter().filter(|v| q == Query::TriTri && *v != Variant::Scalar);
        for (v, quick) in Variant::ALL.into_iter().map(|v| (v, true)).chain(full.map(|v| (v, false))) {
            let Ok(e) = Engine::new(v.isa()).map(|e| e.quick_stage(quick)) else { continue };
            let id = if quick { v.name().to_string() } else { format!("{}-full", v.name()) };
            if let Some(Err(err)) = check_engine(&w, q, v, e) {
                panic!("{} {id} {}: {err}", q.name(), T::NAME);
            }
            let n = w.len(q);
            let (mut out, mut flags) = (vec![T::ZERO; n], vec![Intersection::Invalid; n]);
            g.bench_function(BenchmarkId::from_parameter(id), |b| {
                b.iter(|| w.run(q, e, v == Variant::Scalar, &mut out, &mut flags).expect("lengths match"))
            });
        }
        if q == Query::TriTri {
            bench_peer(&mut g, &w, name == "random");
        }
        g.finish();
    }
}

fn kernels(c: &mut Criterion) {
    for (name, pairs) in workloads() {
        bench_precision::<f32>(c, name, &pairs);
        bench_precision::<f64>(c, name, &pairs);
    }
}

fn threads(c: &mut Criterion) {
    let pairs = protocol::pairs(
        &mesh::carried("armadillo.off").expect("mesh"),
        &mesh::carried("armadillo.off").expect("mesh"),
        Grouping::Random,
        40_000,
        1,
    );
    let a: Vec<_> = pairs.iter().map(|p| p.0.map(|v| v.map(|x| x as f32))).collect();
    let b: Vec<_> = pairs.iter().map(|p| p.1.map(|v| v.map(|x| x as f32))).collect();
    let (ba, bb) = (tridist::TriangleBatch::from_slice(&a), tridist::TriangleBatch::from_slice(&b));
    let mut g = c.benchmark_group("threads/tri_tri/arm_arm_random/f32");
    g.throughput(Throughput::Elements(a.len() as u64));
    g.sample_size(10);
    let mut out = vec![0.0f32; a.len()];
    let e = Engine::auto();
    let mut reference = vec![0.0f32; a.len()];
    e.sqdist_triangle_triangle(&ba, &bb, &mut reference).expect("lengths");
    for t in [1usize, 2] {
        e.threads(t).sqdist_triangle_triangle(&ba, &bb, &mut out).expect("lengths");
        assert_eq!(out, reference, "threaded results differ");
        g.bench_function(BenchmarkId::from_parameter(format!("{}x{t}", e.isa().name())), |bch| {
            bch.iter(|| e.threads(t).sqdist_triangle_triangle(&ba, &bb, &mut out).expect("lengths"))
        });
    }
    g.finish();
}

/// The mesh queries along the seed's trajectory (the mesh report's 12 poses: Armadillo fixed,
/// fandisk moved from 3 units on one side through it to the other, both scaled to
/// [-1, 1]^3): one iteration answers all poses, so the time per pose is the time / 12.
fn meshes(c: &mut Criterion) {
    fn run<T: tridist::Real>(c: &mut Criterion, name: &str) {
        let load = |n: &str| {
            let m = protocol::carried_normalised(n).expect("data/meshes");
            tridist::Mesh::new(m.vertices.iter().map(|p| p.map(T::from_f64)).collect(), m.triangles)
                .expect("finite mesh")
        };
        let (a, b) = (load("armadillo.off"), load("fandisk_large.off"));
        const POSES: usize = 12;
        let poses: Vec<tridist::Pose<T>> = (0..POSES)
            .map(|k| {
                let p = protocol::trajectory_pose(k, POSES).1;
                tridist::Pose {
                    rotation: p.rotation.map(|r| r.map(T::from_f64)),
                    translation: p.translation.map(T::from_f64),
                }
            })
            .collect();
        let (e, id, margin) = (Engine::auto(), tridist::Pose::<T>::identity(), T::from_f64(0.02));
        let mut g = c.benchmark_group(format!("mesh/arm_fandisk/{name}"));
        g.throughput(Throughput::Elements(POSES as u64));
        g.sample_size(10);
        g.bench_function("distance", |bch| {
            bch.iter(|| {
                poses
                    .iter()
                    .map(|p| e.mesh_distance(&a, &id, &b, p).expect("finite").is_some() as usize)
                    .sum::<usize>()
            })
        });
        // the contact query on one thread and on two (Engine::threads): its scaling on 2 cores
        for (id_, eng) in [("contacts_0.02", e), ("contacts_0.02/2_threads", e.threads(2))] {
            g.bench_function(id_, |bch| {
                bch.iter(|| {
                    poses
                        .iter()
                        .map(|p| eng.mesh_contacts(&a, &id, &b, p, margin, None).expect("finite").len())
                        .sum::<usize>()
                })
            });
        }
        g.bench_function("intersect", |bch| {
            bch.iter(|| {
                poses.iter().filter(|p| e.mesh_intersect(&a, &id, &b, p).expect("finite").is_some()).count()
            })
        });
        // the clearance check at the contacts' margin
        g.bench_function("within_0.02", |bch| {
            bch.iter(|| {
                let within = |p| e.mesh_within_margin(&a, &id, &b, p, margin).expect("finite");
                poses.iter().filter(|p| within(p).is_some()).count()
            })
        });
        g.finish();
    }
    run::<f32>(c, "f32");
    run::<f64>(c, "f64");
}

criterion_group!(benches, kernels, threads, meshes);
criterion_main!(benches);
