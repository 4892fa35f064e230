//! The mesh queries against an exact brute force over all triangle pairs, on every family of
//! `mesh_scenes`, both precisions and every available instruction set.
//!
//! The reference moves the triangles exactly as the queries do ([`tridist::Mesh::triangle_at`],
//! the pose's rounding is the caller's input) and answers every pair with the exact oracle:
//! - distance: the excess `E = |d - d*| / (u S)` of the mesh distance over the exact minimum
//!   `d*` (S: the largest moved coordinate of both meshes), the reported pair's own exact
//!   distance, and the closest points lying on the reported triangles;
//! - contacts: every pair exactly within `margin - allow` is reported, none beyond
//!   `margin + allow` (`allow`: the verdict contract, the tolerance + 1 u S of the pair: 65
//!   by default, 2 in `contacts_under_a_tight_tolerance`), each once, with
//!   its pair's distance and closest points on its triangles whose `|p - q|` is its pair's
//!   exact distance (within the measured E);
//! - intersection: `Some` when some pair exactly intersects, and a reported pair is within
//!   `allow` of touching; `None` only when every pair is exactly apart by more than 0;
//! - closest point: as distance, for query points around the first mesh.

use tridist_scenes::mesh_scenes::{check_scene, scene, Limits, Worst, FAMILIES, MEASURED_E, MEASURED_GAP};

/// Scenes per family and precision (blobs of 7 segments: 84 triangles, 7056 pairs); with
/// `TRIDIST_EXTENSIVE=1`, [`EXTENSIVE_SCENES`] (use `--release`: 121 s on two cores with leaves of 1
/// and 8 added to the trees run, a fuzz run beside it; about 70 s before), the
/// run that measured `MEASURED_E` and `MEASURED_GAP`.
const SCENES: u64 = 4;
const EXTENSIVE_SCENES: u64 = 48;
const K: usize = 7;

fn scenes() -> u64 {
    if tridist_scenes::extensive() {
        EXTENSIVE_SCENES
    } else {
        SCENES
    }
}

/// One family, both precisions (one test per family: the harness runs them in parallel).
fn family(fam: &'static str) {
    let mut worst = Worst::default();
    for idx in 0..scenes() {
        let s = scene(fam, 1, idx, K);
        check_scene::<f32>(&s, idx, &Limits::MEASURED, &mut worst).unwrap();
        check_scene::<f64>(&s, idx, &Limits::MEASURED, &mut worst).unwrap();
    }
    println!(
        "{fam}: largest mesh E {:.3} at {}; contact points' distance {:.3} at {} (measured over all families: {MEASURED_E}, {MEASURED_GAP})",
        worst.e, worst.what, worst.gap, worst.gap_what
    );
}

macro_rules! family_tests {
    ($($name:ident),*) => {
        $(
            #[test]
            fn $name() {
                family(stringify!($name));
            }
        )*
        /// Every family of `mesh_scenes` has its test here.
        #[test]
        fn every_family_is_tested() {
            assert_eq!(FAMILIES, [$(stringify!($name)),*]);
        }
    };
}

family_tests!(separated, near_parallel, touching, interpenetrating, far, degenerate, needles, sheared);

/// Contact sets, the clearance check and the intersection pair under a tight tolerance
/// (`1 u S`, judged outside `2 u S` of a change of verdict instead of 65): two scenes of each
/// family where pairs sit near a margin or touch.
#[test]
fn contacts_under_a_tight_tolerance() {
    for fam in ["touching", "near_parallel", "interpenetrating", "degenerate"] {
        for idx in 0..2 {
            let s = scene(fam, 1, idx, K);
            check_scene::<f32>(&s, idx, &Limits::MEASURED.tight(1.0), &mut Worst::default()).unwrap();
            check_scene::<f64>(&s, idx, &Limits::MEASURED.tight(1.0), &mut Worst::default()).unwrap();
        }
    }
}

/// Scenes of the sheared family run by [`sheared_poses_lose_no_pair`].
const SHEARED_SCENES: u64 = 24;

/// Non-rigid poses ([`tridist::Pose`] applies any matrix): [`SHEARED_SCENES`] scenes of the
/// sheared family, held to the kernels' own bounds as the fuzz target holds its scenes
/// (`Limits::kernels`), since what they test is that no pair within reach is lost to a bound
/// that assumes a rotation. With every moved axis' length taken as 1 (`LEN` in
/// `kernels/src/algo/nodes.rs`, as a rotation keeps it), this test failed at scene 6 (a
/// contact missed) and every other mesh test passed, the four scenes of `sheared` included.
#[test]
fn sheared_poses_lose_no_pair() {
    for idx in 0..SHEARED_SCENES {
        let s = scene("sheared", 1, idx, K);
        check_scene::<f32>(&s, idx, &Limits::kernels("f32"), &mut Worst::default()).unwrap();
        check_scene::<f64>(&s, idx, &Limits::kernels("f64"), &mut Worst::default()).unwrap();
    }
}

/// Contacts on two threads (the traversal split into pieces walked in parallel) are exactly
/// the single-threaded contacts, and every tree shape (width, leaf size) gives the same
/// answers (distance, intersection verdict, contacts), on the report's interpenetrating
/// poses of Armadillo and fandisk (thousands of contacts) and on a separated one (none).
#[test]
fn threaded_contacts_and_tree_shapes_give_the_same_answers() {
    use tridist::TreeShape;
    use tridist_scenes::protocol::{carried_normalised, trajectory_pose};
    fn run<T: tridist::Real>() {
        let load = |n: &str, s: TreeShape| {
            let m = carried_normalised(n).unwrap();
            let v = m.vertices.iter().map(|p| p.map(T::from_f64)).collect();
            tridist::Mesh::with_shape(v, m.triangles, s).unwrap()
        };
        // the default first
        let trees: Vec<_> = tridist_scenes::mesh_scenes::test_shapes()
            .into_iter()
            .map(|s| (s, load("armadillo.off", s), load("fandisk_large.off", s)))
            .collect();
        let (def, nodes) = (trees[0].0, trees[0].1.node_count());
        assert_eq!(def, TreeShape::default());
        for (s, a, _) in &trees {
            assert_eq!(a.shape(), *s);
            // the same splits: a wider tree or larger leaves have fewer nodes
            if s.width > def.width || s.leaf > def.leaf {
                assert!(a.node_count() < nodes, "{s:?}: {} nodes, not fewer than {nodes}", a.node_count());
            } else if s != &def {
                assert!(a.node_count() > nodes, "{s:?}: {} nodes, not more than {nodes}", a.node_count());
            }
        }
        let e = tridist::Engine::auto();
        let id = tridist::Pose::<T>::identity();
        for k in [0, 4, 5, 7] {
            let p = trajectory_pose(k, 12).1;
            let p = tridist::Pose {
                rotation: p.rotation.map(|r| r.map(T::from_f64)),
                translation: p.translation.map(T::from_f64),
            };
            let m = T::from_f64(0.02);
            let (_, a, b) = &trees[0];
            let one = e.mesh_contacts(a, &id, b, &p, m, None).unwrap();
            // two threads, and three (more sorted ranges than this machine's cores)
            for threads in [2, 3] {
                let many = e.threads(threads).mesh_contacts(a, &id, b, &p, m, None).unwrap();
                assert_eq!(one.len(), many.len(), "pose {k}, {threads} threads");
                assert!(one == many, "pose {k}: contacts on {threads} threads differ");
            }
            // the documented order: squared distance, then triangle numbers (strictly: no pair twice)
            let key = |c: &tridist::Contact<T>| (c.sqdist, c.tri_a, c.tri_b);
            assert!(one.windows(2).all(|w| key(&w[0]) < key(&w[1])), "pose {k}: contacts out of order");
            assert_eq!(one.is_empty(), k == 0, "pose {k}: {} contacts", one.len());
            let d = e.mesh_distance(a, &id, b, &p).unwrap().unwrap().sqdist;
            let hit = e.mesh_intersect(a, &id, b, &p).unwrap().is_some();
            assert_eq!(hit, k != 0, "pose {k}");
            for (w, a, b) in &trees[1..] {
                let c = e.mesh_contacts(a, &id, b, &p, m, None).unwrap();
                assert!(c == one, "pose {k}, {w:?}: contacts differ");
                assert_eq!(e.mesh_distance(a, &id, b, &p).unwrap().unwrap().sqdist, d, "pose {k}, {w:?}");
                assert_eq!(e.mesh_intersect(a, &id, b, &p).unwrap().is_some(), hit, "pose {k}, {w:?}");
            }
        }
    }
    run::<f32>();
    run::<f64>();
}
