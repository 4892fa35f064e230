//! Hand-derived cases with known exact answers, the two formulations against each other, exact
//! invariances, and the rounding routine.

use proptest::prelude::*;
use rug::Rational;

use super::*;

type T3 = [[f64; 3]; 3];

fn q(x: f64) -> Rational {
    Rational::from_f64(x).unwrap()
}

fn tt(a: &T3, b: &T3) -> Rational {
    let r = sqdist_triangle_triangle(a, b).unwrap();
    let k = sqdist_triangle_triangle_kkt(a, b).unwrap();
    assert_eq!(r, k, "the two formulations disagree on {a:?} {b:?}");
    r
}

const A: T3 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

fn shift(t: &T3, d: [f64; 3]) -> T3 {
    t.map(|p| [p[0] + d[0], p[1] + d[1], p[2] + d[2]])
}

#[test]
fn parallel_planes_at_distance_h() {
    for h in [1.0, 0.1, 3.0e-5, 1e10] {
        let b = shift(&[[0.2, 0.2, 0.0], [2.0, 0.2, 0.0], [0.2, 2.0, 0.0]], [0.0, 0.0, h]);
        assert_eq!(tt(&A, &b), q(h) * q(h), "h = {h}");
    }
}

#[test]
fn coplanar_gap() {
    // b's left edge x = 1.5 faces a's hypotenuse-free vertex (1,0): gap 0.5.
    let b = [[1.5, -1.0, 0.0], [3.0, 0.0, 0.0], [1.5, 1.0, 0.0]];
    assert_eq!(tt(&A, &b), Rational::from((1, 4)));
}

#[test]
fn shared_vertex_shared_edge_and_piercing_are_zero() {
    let shared_v = [[1.0, 0.0, 0.0], [2.0, 1.0, 5.0], [2.0, -1.0, 3.0]];
    let shared_e = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.7]];
    let piercing = [[0.25, 0.25, -1.0], [0.25, 0.25, 1.0], [5.0, 5.0, 0.5]];
    let crossing = [[0.2, -1.0, 0.1], [0.2, 2.0, 0.1], [0.2, 0.5, -3.0]];
    for b in [shared_v, shared_e, piercing, crossing] {
        assert_eq!(tt(&A, &b), 0, "{b:?}");
        assert!(intersect_triangle_triangle(&exact_points(&A).unwrap(), &exact_points(&b).unwrap()));
    }
    // The piercing case has no zero feature distance (a's hypotenuse crosses b's face at
    // (0.5, 0.5, 0)): only the orientation test finds it.
    let (ea, eb) = (exact_points(&A).unwrap(), exact_points(&piercing).unwrap());
    assert!(min15(&ea, &eb).d2 > 0);
    let x = triangle_triangle(&ea, &eb);
    assert_eq!(x.p, x.q);
    assert_eq!(x.p, [q(0.5), q(0.5), q(0.0)]);
}

#[test]
fn point_like_and_segment_like_triangles() {
    let pt = [[0.25, 0.25, 2.0]; 3];
    assert_eq!(tt(&A, &pt), 4);
    let seg = [[2.0, 0.0, 1.0], [3.0, 0.0, 1.0], [2.5, 0.0, 1.0]]; // collinear, x in [2, 3]
    assert_eq!(tt(&A, &seg), 2); // (1,0,0) to (2,0,1)
    let seg_piercing = [[0.2, 0.2, -1.0], [0.2, 0.2, 1.0], [0.2, 0.2, 0.0]];
    assert_eq!(tt(&A, &seg_piercing), 0);
    // two point-like triangles
    assert_eq!(tt(&[[1.0, 2.0, 3.0]; 3], &[[1.0, 2.0, 5.0]; 3]), 4);
}

#[test]
fn smallest_gaps() {
    let tiny = f32::from_bits(1) as f64; // 2^-149
    let b = shift(&A, [0.0, 0.0, tiny]);
    let a32: [[f32; 3]; 3] = A.map(|p| p.map(|c| c as f32));
    let b32: [[f32; 3]; 3] = b.map(|p| p.map(|c| c as f32));
    let d = sqdist_triangle_triangle(&a32, &b32).unwrap();
    assert_eq!(d, q(tiny) * q(tiny));
    assert_eq!(tt(&A, &b), Rational::from(1) >> 298u32);
    let sub64 = f64::from_bits(1);
    assert_eq!(tt(&A, &shift(&A, [sub64, 0.0, 0.0])), 0); // overlapping, shifted a hair
    let b = [[0.0, 0.0, sub64], [1.0, 0.0, sub64], [0.0, 1.0, sub64]];
    assert_eq!(tt(&A, &b), q(sub64) * q(sub64));
}

#[test]
fn segment_segment_and_point_triangle_cases() {
    let e = |p: [[f64; 3]; 2]| exact_points(&p).unwrap();
    let r = segment_segment(&e([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]), &e([[0.5, 1.0, -1.0], [0.5, 1.0, 1.0]]));
    assert_eq!(r.d2, 1);
    // parallel overlapping segments
    let r = segment_segment(&e([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]]), &e([[1.0, 3.0, 0.0], [5.0, 3.0, 0.0]]));
    assert_eq!(r.d2, 9);
    // zero-length segment
    let r = segment_segment(&e([[1.0, 1.0, 1.0], [1.0, 1.0, 1.0]]), &e([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]]));
    assert_eq!(r.d2, 2);
    let t = exact_points(&A).unwrap();
    assert_eq!(point_triangle(&exact_point(&[0.25, 0.25, 2.0]).unwrap(), &t).d2, 4);
    assert_eq!(point_triangle(&exact_point(&[-1.0, -1.0, 0.0]).unwrap(), &t).d2, 2);
    assert_eq!(point_triangle(&exact_point(&[1.0, 1.0, 0.0]).unwrap(), &t).d2, Rational::from((1, 2)));
}

#[test]
fn non_finite_is_an_error() {
    let mut b = A;
    b[1][2] = f64::NAN;
    assert_eq!(sqdist_triangle_triangle(&A, &b), Err(NonFinite));
    b[1][2] = f64::INFINITY;
    assert_eq!(sqdist_triangle_triangle_kkt(&A, &b), Err(NonFinite));
}

// ---- rounding ----

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}

#[test]
fn rounding_to_f32_matches_the_hardware_cast() {
    // `f64 as f32` is round-to-nearest-even, an independent reference. Random bit patterns
    // cover normals, subnormals, overflow and the exact ties that f64 can hold.
    let mut rng = Rng(1);
    for _ in 0..200_000 {
        let x = f64::from_bits(rng.next());
        if !x.is_finite() {
            continue;
        }
        let r = round::to_f32(&q(x));
        assert_eq!(r.to_bits(), (x as f32).to_bits(), "x = {x:e}");
    }
    // exhaustive over the f32 neighbourhood of every binade boundary, midpoints included
    for e in -150i32..=128 {
        let base = 2f64.powi(e);
        for k in -4i32..=4 {
            let x = base * (1.0 + k as f64 * 2f64.powi(-25));
            assert_eq!(round::to_f32(&q(x)).to_bits(), (x as f32).to_bits(), "x = {x:e}");
        }
    }
}

#[test]
fn rounding_to_f64_edge_cases() {
    let mut rng = Rng(7);
    for _ in 0..50_000 {
        let a = f64::from_bits(rng.next() >> 1);
        if !a.is_finite() || a == f64::MAX {
            continue;
        }
        let b = f64::from_bits(a.to_bits() + 1);
        let mid = (q(a) + q(b)) / 2;
        let even = if a.to_bits().is_multiple_of(2) { a } else { b };
        assert_eq!(round::to_f64(&mid), even, "tie between {a:e} and {b:e}");
        let eps = Rational::from(&mid - &q(a)) / 1024;
        assert_eq!(round::to_f64(&(mid.clone() - &eps)), a);
        assert_eq!(round::to_f64(&(mid.clone() + &eps)), b);
        assert_eq!(round::to_f64(&-mid), -even);
        assert_eq!(round::to_f64(&q(a)), a);
    }
    // overflow: MAX + half an ulp ties to the even neighbour 2^1024, i.e. infinity
    let half_ulp = q(2f64.powi(970));
    assert_eq!(round::to_f64(&(q(f64::MAX) + &half_ulp)), f64::INFINITY);
    assert_eq!(round::to_f64(&(q(f64::MAX) + half_ulp / 2)), f64::MAX);
    // below half the smallest subnormal: 0; above: the smallest subnormal
    let tiny = q(f64::from_bits(1));
    assert_eq!(round::to_f64(&(tiny.clone() / 2)), 0.0);
    assert_eq!(round::to_f64(&(tiny.clone() * 3 / 4)), f64::from_bits(1));
    // rug's own conversion truncates; ours must not
    let third = Rational::from((1, 3));
    assert_eq!(round::to_f64(&third), 1.0 / 3.0);
}

#[test]
fn square_roots_round_as_the_hardware_sqrt() {
    // IEEE sqrt is correctly rounded: on floats (exact rationals) it is an independent
    // reference, subnormals and the largest values included.
    let mut rng = Rng(3);
    for _ in 0..100_000 {
        let x = f64::from_bits(rng.next() >> 1);
        if x.is_finite() {
            assert_eq!(round::sqrt_to_f64(&q(x)), Some(x.sqrt()), "x = {x:e}");
        }
        let y = f32::from_bits((rng.next() >> 33) as u32);
        if y.is_finite() {
            let r = round::sqrt_to_f32(&q(y as f64)).map(f32::to_bits);
            assert_eq!(r, Some(y.sqrt().to_bits()), "y = {y:e}");
        }
    }
    assert_eq!(round::sqrt_to_f64(&q(0.0)), Some(0.0));
    assert_eq!(round::sqrt_to_f64(&q(-1.0)), None);
    assert_eq!(round::sqrt_to_f32(&q(-1e-30)), None);
}

#[test]
fn square_roots_of_rationals_near_midpoints() {
    // Squares of the midpoint between neighbours a < b: exactly on it ties to the even one,
    // just below rounds to a and just above to b. No float is such a square, so these are
    // cases the hardware cannot check.
    let mut rng = Rng(5);
    for i in 0..20_000 {
        let a = f64::from_bits(rng.next() >> 2);
        if !a.is_finite() || a == 0.0 {
            continue;
        }
        let b = a.next_up();
        let mid = (q(a) + q(b)) / 2;
        let sq = Rational::from(&mid * &mid);
        let even = if a.to_bits().is_multiple_of(2) { a } else { b };
        assert_eq!(round::sqrt_to_f64(&sq), Some(even), "tie between {a:e} and {b:e}");
        let eps = Rational::from(&sq >> 140u32);
        assert_eq!(round::sqrt_to_f64(&(sq.clone() - &eps)), Some(a), "below {a:e}");
        assert_eq!(round::sqrt_to_f64(&(sq.clone() + &eps)), Some(b), "above {a:e}");
        // f32 the same way, on f32 neighbours
        let a32 = f32::from_bits((rng.next() >> 34) as u32 + i % 2);
        if a32.is_finite() && a32 > 0.0 && a32 < f32::MAX {
            let b32 = a32.next_up();
            let mid = (q(a32 as f64) + q(b32 as f64)) / 2;
            let sq = Rational::from(&mid * &mid);
            let even = if a32.to_bits().is_multiple_of(2) { a32 } else { b32 };
            assert_eq!(round::sqrt_to_f32(&sq), Some(even), "tie between {a32:e} and {b32:e}");
            let eps = Rational::from(&sq >> 80u32);
            assert_eq!(round::sqrt_to_f32(&(sq.clone() - &eps)), Some(a32));
            assert_eq!(round::sqrt_to_f32(&(sq + &eps)), Some(b32));
        }
    }
    // beyond the largest finite value: the midpoint above MAX ties to 2^1024, infinity
    let top = q(f64::MAX) + q(2f64.powi(970));
    assert_eq!(round::sqrt_to_f64(&Rational::from(&top * &top)), Some(f64::INFINITY));
    let big = q(f64::MAX) * q(f64::MAX);
    assert_eq!(round::sqrt_to_f64(&big), Some(f64::MAX));
    assert_eq!(round::sqrt_to_f32(&big), Some(f32::INFINITY));
    // a third: sqrt(1/3) rounded, against the f64 value (the hardware's sqrt of RN(1/3) is
    // within an ulp but need not be the same; the integer method is checked above)
    let third = round::sqrt_to_f64(&Rational::from((1, 3))).unwrap();
    assert!((third - (1.0f64 / 3.0).sqrt()).abs() <= f64::EPSILON);
}

#[test]
fn metrics_behave() {
    use metrics::*;
    let exact = Rational::from(4); // d* = 2
    assert_eq!(scaled_error(4.0, &exact, 1.0, F64), 0.0);
    // next_up(4) = 4 + 8u: sqrt = 2 + 2u (to first order), so E = 2 with S = 1.
    let e = scaled_error(f64::from_bits(4f64.to_bits() + 1), &exact, 1.0, F64);
    assert!((e - 2.0).abs() < 1e-6, "{e}");
    assert!(scaled_error(f64::NAN, &exact, 1.0, F64).is_nan());
    assert_eq!(scaled_error(f64::INFINITY, &exact, 1.0, F64), f64::INFINITY);
    assert_eq!(floor_error(&exact, 1.0, F64), 0.0);
    assert!(contact_miss(1.0, &Rational::new(), 1.0, F32, 8.0));
    assert!(!contact_miss(0.0, &Rational::new(), 1.0, F32, 8.0));
    assert!(false_zero_strict(0.0, &Rational::from((1, 1000)), F32));
    assert!(!false_zero_strict(0.0, &(Rational::from(1) >> 400u32), F32)); // rounds to 0 in f32
    assert!(false_zero(0.0, &Rational::from((1, 1000)), 1.0, F32, 8.0));
    assert!(!false_zero(0.0, &(Rational::from(1) >> 60u32), 1.0, F32, 8.0)); // within 8 u S

    // The thresholds in units of u S are exact where f64 arithmetic underflows: S the
    // smallest normal (an all-subnormal f64 input), 65 u S = 65 * 2^-1075, which the plain
    // product rounds to 0 (65 * u first) or to a multiple of the smallest subnormal.
    let tiny_s = f64::MIN_POSITIVE;
    assert_eq!(c_us(65.0, tiny_s, F64), Rational::from(65) >> 1075u32);
    assert_eq!(65.0 * (F64.u * tiny_s), 0.0);
    assert_eq!(c_us(8.0, f64::INFINITY, F64), 0);
    // A contact miss is decided on the squares, exactly: with S = 2^500 (8 u S = 2^450), an
    // answer just above (8 u S)^2 is a miss, one at it is not.
    let big_s = 2f64.powi(500);
    let thr2 = 2f64.powi(900);
    assert!(contact_miss(f64::from_bits(thr2.to_bits() + 1), &Rational::new(), big_s, F64, 8.0));
    assert!(!contact_miss(thr2, &Rational::new(), big_s, F64, 8.0));
    assert!(contact_miss(f64::NAN, &Rational::new(), big_s, F64, 8.0));
    let t = exact_points(&A).unwrap();
    assert_eq!(point_offset([0.25, 0.25, 0.0], &t, 1.0, F64), 0.0);
    assert!(point_offset([0.25, 0.25, 1e-10], &t, 1.0, F64) > 1e5);
    // overflow: +inf is the right answer when the exact value exceeds f32; a finite answer
    // far below it is judged by its error, far beyond any bound
    let huge = q(1e39);
    assert_eq!(excess(f64::INFINITY, &huge, 1e19, F32), 0.0);
    assert!(excess(3e38, &huge, 1e19, F32) > 1e6);
}

// ---- the two formulations, and exact invariances ----

fn coord() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => (-8i32..8).prop_map(|k| k as f64 * 0.25),     // lattice: coplanar, parallel, touching
        4 => -1.0f64..1.0,
        1 => (-1.0f64..1.0).prop_map(|x| x * 1e-20),
        1 => (-1.0f64..1.0).prop_map(|x| x * 1e20),
    ]
}

fn tri() -> impl Strategy<Value = T3> {
    let p = || [coord(), coord(), coord()];
    prop_oneof![
        6 => [p(), p(), p()],
        1 => p().prop_map(|a| [a, a, a]),                               // point-like
        1 => (p(), p()).prop_map(|(a, b)| [a, b, a]),                  // repeated vertex
        1 => (p(), p()).prop_map(|(a, b)| [a, b, [(a[0] + b[0]) * 0.5, (a[1] + b[1]) * 0.5, (a[2] + b[2]) * 0.5]]),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn formulations_agree(a in tri(), b in tri()) {
        let ea = exact_points(&a).unwrap();
        let eb = exact_points(&b).unwrap();
        let f = triangle_triangle(&ea, &eb);
        let k = triangle_triangle_kkt(&ea, &eb);
        prop_assert_eq!(&f.d2, &k.d2);
        // the closest points realise the distance and lie on their triangles
        prop_assert_eq!(dist2(&f.p, &f.q), f.d2.clone());
        prop_assert_eq!(point_triangle(&f.p, &ea).d2, 0);
        prop_assert_eq!(point_triangle(&f.q, &eb).d2, 0);
        prop_assert_eq!(intersect_triangle_triangle(&ea, &eb), f.d2 == 0);
    }

    #[test]
    fn exact_invariances(a in tri(), b in tri(), perm in 0usize..6, k in -3i32..3, off in prop::sample::select(vec![0.0, 1.0, -64.0, 1024.0])) {
        let d = tt(&a, &b);
        // swap
        prop_assert_eq!(&tt(&b, &a), &d);
        // vertex permutations
        let ps = [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]][perm];
        let pa = [a[ps[0]], a[ps[1]], a[ps[2]]];
        prop_assert_eq!(&sqdist_triangle_triangle(&pa, &b).unwrap(), &d);
        // power-of-two scaling (exact in f64 for these magnitudes)
        let f = 2f64.powi(k);
        let sa = a.map(|p| p.map(|c| c * f));
        let sb = b.map(|p| p.map(|c| c * f));
        prop_assert_eq!(sqdist_triangle_triangle(&sa, &sb).unwrap(), d.clone() * q(f) * q(f));
        // translation, where every sum is exact
        let ta = a.map(|p| p.map(|c| c + off));
        let tb = b.map(|p| p.map(|c| c + off));
        let exact_sums = ta.iter().chain(tb.iter()).flatten().zip(a.iter().chain(b.iter()).flatten())
            .all(|(t, c)| t - off == *c && q(*t) == q(*c) + q(off));
        if exact_sums {
            prop_assert_eq!(sqdist_triangle_triangle(&ta, &tb).unwrap(), d);
        }
    }
}

// ---- the filter changes nothing ----

/// Coordinates that stress the filter's error bounds: lattice ties, tiny (underflowing
/// products), huge (overflowing products), far from the origin, and nearly equal values.
fn stress_coord() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => (-4i32..4).prop_map(|k| k as f64 * 0.5),
        2 => -1.0f64..1.0,
        1 => (-1.0f64..1.0).prop_map(|x| x * 1e-160),
        1 => (-1.0f64..1.0).prop_map(|x| x * 1e-300),
        1 => (-1.0f64..1.0).prop_map(|x| x * 1e160),
        1 => (-1.0f64..1.0).prop_map(|x| x * 1e300),
        1 => (-1.0f64..1.0).prop_map(|x| 1e12 + x),
        1 => (0i64..4).prop_map(|k| f64::from_bits(1.0f64.to_bits() + k as u64)),
    ]
}

fn stress_tri() -> impl Strategy<Value = T3> {
    let p = || [stress_coord(), stress_coord(), stress_coord()];
    prop_oneof![
        6 => [p(), p(), p()],
        1 => (p(), p()).prop_map(|(a, b)| [a, b, a]),
        1 => (p(), -1.0f64..1.0).prop_map(|(a, s)| [a, a.map(|c| c + s), a.map(|c| c - 2.0 * s)]),
    ]
}

/// The filtered answer, bit for bit the reference one (distance and closest points).
fn same_as_reference(a: &T3, b: &T3) -> Result<(), TestCaseError> {
    let (ea, eb) = (exact_points(a).unwrap(), exact_points(b).unwrap());
    let f = triangle_triangle(&ea, &eb);
    let r = triangle_triangle_unfiltered(&ea, &eb);
    prop_assert_eq!(&f, &r, "{:?} {:?}", a, b);
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 750, ..ProptestConfig::default() })]

    // 1500 cases in all, as two tests of 750 that the harness runs in parallel (the unfiltered
    // reference on 1e300-scale coordinates is slow: 12 s as one test).
    #[test]
    fn filter_matches_reference(a in stress_tri(), b in stress_tri()) {
        same_as_reference(&a, &b)?;
    }

    #[test]
    fn filter_matches_reference_other_order(a in stress_tri(), b in stress_tri()) {
        same_as_reference(&b, &a)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1500, ..ProptestConfig::default() })]

    #[test]
    fn filter_matches_reference_near_contact(a in tri(), n in [-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0], h in prop_oneof![Just(0.0), Just(1e-300), -1e-9f64..1e-9, -1.0f64..1.0]) {
        // b: a translated along n by h (parallel, touching, nearly touching, crossing)
        let b = a.map(|p| [p[0] + n[0] * h, p[1] + n[1] * h, p[2] + n[2] * h]);
        same_as_reference(&a, &b)?;
        let rot = [b[1], b[2], b[0]];
        same_as_reference(&rot, &a)?;
    }
}

#[test]
fn rational_input_that_is_not_a_float_takes_the_reference_path() {
    let third = Rational::from((1, 3));
    let a = exact_points(&A).unwrap();
    let mut b = exact_points(&[[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]]).unwrap();
    b[0][2] = third.clone();
    assert!(as_floats(&b).is_none());
    let x = triangle_triangle(&a, &b);
    assert_eq!(x.d2, Rational::from(&third * &third));
}

#[test]
fn overflow_is_allowed_just_above_the_largest_finite_value() {
    // Found by fuzzing (point_tri, f32): D* a hair above f32::MAX rounds down to it, and the
    // kernel's +inf is a documented answer.
    let d = Rational::from((
        "47115985318142507038151203899944013361106124800".parse::<rug::Integer>().unwrap(),
        rug::Integer::from(138461441),
    ));
    let max = q(f32::MAX as f64);
    assert!(d > max && round::to_f32(&d) == f32::MAX);
    let s = 7.493539419981768e19;
    assert!(metrics::overflow_allowed(&d, s, metrics::F32, metrics::OVERFLOW_REACH));
    assert_eq!(metrics::excess(f64::INFINITY, &d, s, metrics::F32), 0.0);
    assert_eq!(metrics::excess(f32::MAX as f64, &d, s, metrics::F32), 0.0);
    // well below the edge +inf is still a defect; just below it, within 8 u S, it is allowed
    let below = q(1e38);
    assert!(!metrics::overflow_allowed(&below, s, metrics::F32, metrics::OVERFLOW_REACH));
    assert_eq!(metrics::excess(f64::INFINITY, &below, s, metrics::F32), f64::INFINITY);
    let dmax = (f32::MAX as f64).sqrt();
    let near = q(dmax - 4.0 * metrics::F32.u * s) * q(dmax - 4.0 * metrics::F32.u * s);
    assert!(near < max && metrics::overflow_allowed(&near, s, metrics::F32, metrics::OVERFLOW_REACH));
    let far = q(dmax - 16.0 * metrics::F32.u * s) * q(dmax - 16.0 * metrics::F32.u * s);
    assert!(!metrics::overflow_allowed(&far, s, metrics::F32, metrics::OVERFLOW_REACH));
}

#[test]
fn a_finite_answer_just_below_an_overflowing_square_is_judged_by_its_error() {
    // Found by fuzzing (point_tri, f32, `fuzz/regressions/point_tri/square-rounding-up-to-inf`):
    // D* lies 0.955 ulp above f32::MAX (beyond the half ulp that rounds it to +inf) and the
    // kernel answered f32::MAX, an answer whose distance is within rounding of the exact one.
    // +inf is the correctly rounded answer; f32::MAX is judged by its error (E 0.11), as is any
    // other finite answer: one far below is still an excess far beyond the E target.
    let d = Rational::from((
        "6630985635732362137101743224038672230540867419946963607654400".parse::<rug::Integer>().unwrap(),
        "19486715440399434907657".parse::<rug::Integer>().unwrap(),
    ));
    assert!(round::to_f32(&d).is_infinite());
    let s = 7.493539419981768e19;
    assert_eq!(metrics::excess(f64::INFINITY, &d, s, metrics::F32), 0.0);
    let e = metrics::excess(f32::MAX as f64, &d, s, metrics::F32);
    assert!(e > 0.0 && e < 0.25, "{e}");
    assert!(metrics::excess(1e38, &d, s, metrics::F32) > 1e6);
    assert!(metrics::excess(f64::NAN, &d, s, metrics::F32).is_nan());
}

#[test]
fn penetration_depth_is_decided_exactly() {
    let ex = |t: &T3| exact_points(t).unwrap();
    let a = ex(&A);
    let zero = Rational::new();
    // shared vertex, shared edge, vertex on the face, apart: nothing to remove
    for b in [
        [[1.0, 0.0, 0.0], [2.0, 1.0, 5.0], [2.0, -1.0, 3.0]],
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.7]],
        [[0.25, 0.25, 0.0], [0.25, 0.25, 1.0], [1.0, 1.0, 1.0]],
        [[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]],
    ] {
        assert!(penetration_at_most(&a, &ex(&b), &zero), "{b:?}");
    }
    // coplanar overlap: a translation along the normal by any amount separates them
    let cop = ex(&[[0.1, 0.1, 0.0], [0.9, 0.0, 0.0], [0.0, 0.9, 0.0]]);
    assert!(penetration_at_most(&a, &cop, &zero));
    // a vertical fin in x = 0.3 through the triangle: moving it by 0.3 along -x removes the
    // overlap (it then touches the edge x = 0), nothing shorter does
    let fin = ex(&[[0.3, -1.0, -1.0], [0.3, -1.0, 1.0], [0.3, 1.0, 0.0]]);
    let r = |x: f64| Rational::from_f64(x).unwrap();
    assert!(penetration_at_most(&a, &fin, &r(0.3)));
    assert!(!penetration_at_most(&a, &fin, &r(0.29)));
    assert!(!penetration_at_most(&a, &fin, &zero));
}
