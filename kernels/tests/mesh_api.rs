//! Mesh queries: misuse and bad input are errors with their documented outcome, never a panic;
//! empty meshes; a moved mesh gives the same answers as the same mesh built moved.

use tridist::{Engine, Error, Mesh, Pose};

fn tetra(o: [f64; 3]) -> Mesh<f64> {
    let v = vec![o, [o[0] + 1.0, o[1], o[2]], [o[0], o[1] + 1.0, o[2]], [o[0], o[1], o[2] + 1.0]];
    Mesh::new(v, vec![[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]]).unwrap()
}

#[test]
fn bad_meshes_and_poses_are_errors() {
    let v = vec![[0.0f32; 3]; 3];
    assert_eq!(
        Mesh::new(v.clone(), vec![[0, 1, 3]]).unwrap_err(),
        Error::IndexOutOfRange { triangle: 0, index: 3, vertices: 3 }
    );
    let mut nan = v.clone();
    nan[1][2] = f32::NAN;
    assert_eq!(Mesh::new(nan, vec![[0, 1, 2]]).unwrap_err(), Error::NonFiniteVertex { vertex: 1 });
    for w in [0, 1, tridist::TreeShape::MAX_WIDTH + 1, usize::MAX] {
        assert_eq!(Mesh::with_width(v.clone(), vec![[0, 1, 2]], w).unwrap_err(), Error::InvalidTreeWidth(w));
    }
    assert!(Error::InvalidTreeWidth(9).to_string().contains("2 to 8"));
    assert_eq!(Mesh::with_width(v.clone(), vec![[0, 1, 2]], 5).unwrap().width(), 5);
    assert_eq!(tetra([0.0; 3]).width(), tridist::TreeShape::DEFAULT.width);
    // leaf sizes: 1 to MAX_LEAF; a bad width is named before a bad leaf
    use tridist::TreeShape;
    let shaped = |width, leaf| Mesh::with_shape(v.clone(), vec![[0, 1, 2]], TreeShape { width, leaf });
    for n in [0, tridist::TreeShape::MAX_LEAF + 1, usize::MAX] {
        assert_eq!(shaped(4, n).unwrap_err(), Error::InvalidLeafSize(n));
    }
    assert_eq!(shaped(1, 0).unwrap_err(), Error::InvalidTreeWidth(1));
    // the same check, without a mesh (what the CLI validates its flags with)
    assert_eq!(TreeShape { width: 1, leaf: 0 }.check(), Err(Error::InvalidTreeWidth(1)));
    assert_eq!(TreeShape { width: 8, leaf: 9 }.check(), Err(Error::InvalidLeafSize(9)));
    assert_eq!(TreeShape::default().check(), Ok(()));
    assert!(Error::InvalidLeafSize(9).to_string().contains("1 to 8"));
    for n in [1, tridist::TreeShape::MAX_LEAF] {
        assert_eq!(shaped(3, n).unwrap().shape(), TreeShape { width: 3, leaf: n });
    }
    assert_eq!(
        tetra([0.0; 3]).shape(),
        TreeShape { width: tridist::TreeShape::DEFAULT.width, leaf: tridist::TreeShape::DEFAULT.leaf }
    );
    assert_eq!(TreeShape::default(), tetra([0.0; 3]).shape());
    // a triangle that is not there is `None`, not a panic
    let t = tetra([0.0; 3]);
    assert_eq!(t.triangle(3), Some([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]));
    assert_eq!(t.triangle(4), None);
    assert_eq!(t.triangle_at(usize::MAX, &Pose::identity()), None);
    assert_eq!(t.triangle_at(0, &Pose::translation([0.0, 0.0, 1.0])).map(|t| t[0]), Some([0.0, 0.0, 1.0]));
    let (a, b) = (tetra([0.0; 3]), tetra([3.0, 0.0, 0.0]));
    let e = Engine::auto();
    let id = Pose::identity();
    let bad = Pose::translation([f64::NAN, 0.0, 0.0]);
    assert_eq!(e.mesh_distance(&a, &bad, &b, &id).unwrap_err(), Error::InvalidPose);
    assert_eq!(e.mesh_intersect(&a, &id, &b, &bad).unwrap_err(), Error::InvalidPose);
    assert_eq!(e.mesh_contacts(&a, &id, &b, &id, -1.0, None).unwrap_err(), Error::InvalidMargin);
    assert_eq!(e.mesh_contacts(&a, &id, &b, &id, f64::NAN, None).unwrap_err(), Error::InvalidMargin);
    for m in [-1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(e.mesh_within_margin(&a, &id, &b, &id, m).unwrap_err(), Error::InvalidMargin);
    }
    assert_eq!(e.mesh_within_margin(&a, &bad, &b, &id, 1.0).unwrap_err(), Error::InvalidPose);
    assert_eq!(
        e.mesh_closest_point(&a, &id, [f64::INFINITY, 0.0, 0.0]).unwrap_err(),
        Error::NonFiniteCoordinate
    );
    // a moved coordinate that overflows
    let huge =
        Mesh::new(vec![[3e38f32, 0.0, 0.0], [3e38, 1.0, 0.0], [3e38, 0.0, 1.0]], vec![[0, 1, 2]]).unwrap();
    let push = Pose::translation([3e38f32, 0.0, 0.0]);
    let small = Mesh::new(vec![[0.0f32; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], vec![[0, 1, 2]]).unwrap();
    let idf = Pose::identity();
    assert_eq!(e.mesh_distance(&huge, &push, &small, &idf).unwrap_err(), Error::NonFiniteCoordinate);
    assert_eq!(e.mesh_intersect(&huge, &push, &small, &idf).unwrap_err(), Error::NonFiniteCoordinate);
    assert_eq!(
        e.mesh_within_margin(&huge, &push, &small, &idf, 1.0).unwrap_err(),
        Error::NonFiniteCoordinate
    );
    assert!(Error::NonFiniteCoordinate.to_string().contains("NaN or infinite"));
}

#[test]
fn empty_meshes_are_infinitely_far_and_touch_nothing() {
    let empty = Mesh::<f64>::new(vec![], vec![]).unwrap();
    let t = tetra([0.0; 3]);
    let (e, id) = (Engine::auto(), Pose::identity());
    assert!(empty.is_empty() && empty.node_count() == 0);
    assert_eq!(e.mesh_distance(&empty, &id, &t, &id).unwrap(), None);
    assert_eq!(e.mesh_intersect(&t, &id, &empty, &id).unwrap(), None);
    assert!(e.mesh_contacts(&t, &id, &empty, &id, 1.0, None).unwrap().is_empty());
    assert_eq!(e.mesh_within_margin(&empty, &id, &t, &id, 1.0).unwrap(), None);
    assert_eq!(e.mesh_closest_point(&empty, &id, [0.0; 3]).unwrap(), None);
}

#[test]
fn a_moved_mesh_answers_as_the_mesh_built_there() {
    // translations by integers are exact: moving the mesh or building it moved is the same input
    let (a, b) = (tetra([0.0; 3]), tetra([0.0; 3]));
    let e = Engine::auto();
    let pose = Pose::translation([2.0, 1.0, 0.5]);
    let moved = e.mesh_distance(&a, &Pose::identity(), &b, &pose).unwrap().unwrap();
    let built =
        e.mesh_distance(&a, &Pose::identity(), &tetra([2.0, 1.0, 0.5]), &Pose::identity()).unwrap().unwrap();
    assert_eq!(moved, built);
    // the smallest of the 16 pairs' answers, bit for bit
    let far = tetra([2.0, 1.0, 0.5]);
    let all = (0..4).flat_map(|i| (0..4).map(move |j| (i, j)));
    let min = all
        .map(|(i, j)| {
            tridist::sqdist_triangle_triangle(
                &a.triangle(i).expect("a triangle"),
                &far.triangle(j).expect("a triangle"),
            )
        })
        .fold(f64::INFINITY, f64::min);
    assert_eq!(moved.sqdist, min);
    assert_eq!(e.mesh_intersect(&a, &Pose::identity(), &b, &pose).unwrap(), None);
    assert!(e
        .mesh_intersect(&a, &Pose::identity(), &b, &Pose::translation([0.25, 0.25, 0.25]))
        .unwrap()
        .is_some());
    // the clearance check against the distance: within a margin just above it, not just below
    let d = moved.sqdist.sqrt();
    let within = |m: f64| e.mesh_within_margin(&a, &Pose::identity(), &b, &pose, m).unwrap();
    let (i, j) = within(d * 1.001).expect("within a margin above the distance");
    assert!(
        tridist::sqdist_triangle_triangle(
            &a.triangle(i).expect("a triangle"),
            &far.triangle(j).expect("a triangle")
        ) <= (d * 1.001).powi(2)
    );
    assert_eq!(within(d * 0.999), None);
}
