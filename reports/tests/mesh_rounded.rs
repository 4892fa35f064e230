//! `tridist mesh --tolerance correctly-rounded` end to end, judged by the exact oracle.

mod common;
use common::{number_after, tetrahedron, tmp, tridist};

/// `tridist mesh --tolerance correctly-rounded` as a user runs it, on a pose and a point found
/// where the two roundings differ (the root of the correctly rounded square is not the
/// correctly rounded distance): the distance and the closest point's distance printed are the
/// exact minimum's correctly rounded, judged by the oracle over every triangle of the moved
/// tetrahedra (f32, decided in f64), and each square is the exact minimum's rounded. f64
/// without the oracle: the mesh's square is undecided, an error that says so; a bad tolerance
/// is a usage error.
#[test]
fn mesh_correctly_rounded_distances() {
    use tridist::{Mesh, Pose};
    use tridist_oracle::{exact_point, point_triangle, round, triangle_triangle, P3};
    let a = tetrahedron("mesh_rounded");
    let a = a.as_str();
    let ex = |p: [f32; 3]| exact_point(&p.map(f64::from)).expect("finite");
    let tet = |pose: &Pose<f32>| {
        let v = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let m = Mesh::new(v, vec![[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]]).expect("a mesh");
        (0..4).map(|i| m.triangle_at(i, pose).expect("finite").map(ex)).collect::<Vec<[P3; 3]>>()
    };
    // (RN(D*), RN(sqrt(D*))) in f32 of the smallest exact square, and whether they round twice
    let rounded = |d2: rug::Rational| {
        let (sq, dist) = (round::to_f32(&d2), round::sqrt_to_f32(&d2).expect("a square"));
        (sq, dist, sq.sqrt() != dist)
    };
    let min = |v: Vec<rug::Rational>| v.into_iter().reduce(|m, d| if d < m { d } else { m }).expect("pairs");
    let ta = tet(&Pose::identity());
    // the second copy along x, turned about (1, 2, 3) by 40 degrees, as the CLI builds it
    let found = (0..400).find_map(|k| {
        let t = [1.7 + 0.001 * k as f64, 0.3, 0.1];
        let pose = Pose::from_axis_angle([1.0f32, 2.0, 3.0], 40f64.to_radians(), t.map(|x| x as f32)).ok()?;
        let tb = tet(&pose);
        let d2 = min(ta.iter().flat_map(|x| tb.iter().map(move |y| triangle_triangle(x, y).d2)).collect());
        let (sq, dist, twice) = rounded(d2);
        twice.then_some((t, pose, tb, sq, dist))
    });
    let (t, pose_b, tb, sq, dist) = found.expect("a pose whose distance rounds twice");
    let x = (0..400)
        .map(|k| [2.2 + 0.001 * k as f64, 0.4, -0.3])
        .find(|x| {
            let p = ex(x.map(|c| c as f32));
            rounded(min(tb.iter().map(|y| point_triangle(&p, y).d2).collect())).2
        })
        .expect("a point whose distance rounds twice");
    let pd = rounded(min(tb.iter().map(|y| point_triangle(&ex(x.map(|c| c as f32)), y).d2).collect()));
    let pose = format!("{},{},{},1,2,3,40", t[0], t[1], t[2]);
    let point = format!("{},{},{}", x[0], x[1], x[2]);
    let args = ["mesh", a, a, "--pose-b", &pose, "--point", &point, "--precision", "f32"];
    let (code, out, err) = tridist(&[&args[..], &["--tolerance", "correctly-rounded"]].concat(), "");
    assert_eq!(code, 0, "{err}");
    assert_eq!(number_after(&out, "distance: "), f64::from(dist), "{out}");
    let squared = out.split("(squared ").nth(1).and_then(|r| r.split(')').next()).expect("a square");
    assert_eq!(squared.parse::<f64>().expect("a number"), f64::from(sq), "{out}");
    let at = out.split("closest point of the second mesh: ").nth(1).and_then(|r| r.split(" at ").nth(1));
    let at = at.and_then(|r| r.split_whitespace().next()).expect("a closest point line");
    assert_eq!(at.parse::<f64>().expect("a number"), f64::from(pd.1), "{out}");
    // a poses file with that pose (its rotation's f32 numbers exactly): the same distance
    let file = tmp("mesh_rounded").join("poses.txt");
    let nums = pose_b.translation.iter().chain(pose_b.rotation.iter().flatten()).map(|x| format!("{x}"));
    std::fs::write(&file, format!("twice {}\n", nums.collect::<Vec<_>>().join(" "))).unwrap();
    let f = file.to_str().unwrap();
    let (code, out, err) = tridist(
        &[
            "mesh",
            a,
            a,
            "--poses",
            f,
            "--precision",
            "f32",
            "--tolerance",
            "correctly-rounded",
            "--budget-ms",
            "1",
        ],
        "",
    );
    assert_eq!(code, 0, "{err}");
    assert_eq!(number_after(&out, "twice "), f64::from(dist), "{out}");
    // the default tolerance prints the root of its square: not that value here
    let (code, out, err) = tridist(&args, "");
    assert_eq!(code, 0, "{err}");
    assert_ne!(number_after(&out, "distance: "), f64::from(dist), "{out}");
    // f64 without the oracle: the square is undecided (an error, exit 3)
    let (code, _, err) = tridist(&["mesh", a, a, "--pose-b", &pose, "--tolerance", "correctly-rounded"], "");
    assert_eq!(code, 3, "{err}");
    assert!(err.contains("needs the exact oracle"), "{err}");
    let (code, _, err) = tridist(&["mesh", a, a, "--tolerance", "nearest"], "");
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--tolerance"), "{err}");
}
