//! The mesh queries against an exact brute force over all triangle pairs, on every family of
//! `mesh_scenes`, both precisions and every available instruction set.
//!
//! The reference moves the triangles exactly as the queries do ([`tridist::Mesh::triangle_at`],
//! the pose's rounding is the caller's input) and answers every pair with the exact oracle:
//! - distance: the excess `E = |d - d*| / (u S)` of the mesh distance over the exact minimum
//!   `d*` (S: the largest moved coordinate of both meshes), the reported pair's own exact
//!   distance, and the closest points lying on the reported triangles;
//! - contacts: every pair exactly within `margin - allow` is reported, none beyond
//!   `margin + allow` (`allow`: the verdict contract, 65 u S of the pair), each once, with
//!   its pair's distance and closest points on its triangles whose `|p - q|` is its pair's
//!   exact distance (within the measured E);
//! - intersection: `Some` when some pair exactly intersects, and a reported pair is within
//!   `allow` of touching; `None` only when every pair is exactly apart by more than 0;
//! - closest point: as distance, for query points around the first mesh.

use tridist_scenes::mesh_scenes::{check_scene, scene, Limits, Worst, FAMILIES, MEASURED_E, MEASURED_GAP};

/// Scenes per family and precision (blobs of 7 segments: 84 triangles, 7056 pairs).
const SCENES: u64 = 4;
const K: usize = 7;

/// One family, both precisions (one test per family: the harness runs them in parallel).
fn family(fam: &'static str) {
    let mut worst = Worst::default();
    for idx in 0..SCENES {
        let s = scene(fam, 1, idx, K);
        check_scene::<f32>(&s, idx, &Limits::MEASURED, &mut worst).unwrap();
        check_scene::<f64>(&s, idx, &Limits::MEASURED, &mut worst).unwrap();
    }
    println!(
        "{fam}: largest mesh E {:.3} at {} (measured over all families: {MEASURED_E}, contact points' distance {MEASURED_GAP})",
        worst.e, worst.what
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

family_tests!(separated, near_parallel, touching, interpenetrating, far, degenerate, needles);

/// Contacts on two threads (the traversal split into pieces walked in parallel) are exactly
/// the single-threaded contacts, on the report's interpenetrating poses of Armadillo and
/// fandisk (thousands of contacts) and on a separated one (none).
#[test]
fn threaded_contacts_are_the_single_threaded_ones() {
    use tridist_scenes::protocol::{carried_normalised, trajectory_pose};
    fn run<T: tridist::Real>() {
        let load = |n: &str| {
            let m = carried_normalised(n).unwrap();
            tridist::Mesh::new(m.vertices.iter().map(|p| p.map(T::from_f64)).collect(), m.triangles).unwrap()
        };
        let (a, b) = (load("armadillo.off"), load("fandisk_large.off"));
        let e = tridist::Engine::auto();
        let id = tridist::Pose::<T>::identity();
        for k in [0, 4, 5, 7] {
            let p = trajectory_pose(k, 12).1;
            let p = tridist::Pose {
                rotation: p.rotation.map(|r| r.map(T::from_f64)),
                translation: p.translation.map(T::from_f64),
            };
            let m = T::from_f64(0.02);
            let one = e.mesh_contacts(&a, &id, &b, &p, m, None).unwrap();
            let two = e.threads(2).mesh_contacts(&a, &id, &b, &p, m, None).unwrap();
            assert_eq!(one.len(), two.len(), "pose {k}");
            assert!(one == two, "pose {k}: threaded contacts differ");
            assert_eq!(one.is_empty(), k == 0, "pose {k}: {} contacts", one.len());
        }
    }
    run::<f32>();
    run::<f64>();
}
