//! API behaviour that needs no oracle: bad input, lengths, lane positions and batch tails,
//! layouts, within-margin, power-of-two scaling. Every test runs on every available variant.

use tridist::{
    ClosestPoints, Engine, Error, Intersection, Interval, Isa, Outputs, PenaltyOptions, Prims, Proximity,
    Query, SegmentBatch, Tolerance, Triangle, TriangleBatch,
};

fn engines() -> Vec<Engine> {
    Isa::ALL.into_iter().filter_map(|i| Engine::new(i).ok()).collect()
}

struct Rng(u64);
impl Rng {
    fn f(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn tri<T: tridist::Real>(&mut self) -> Triangle<T> {
        [0; 3].map(|_| [0; 3].map(|_| T::from_f64(self.f() * 2.0 - 1.0)))
    }
}

/// A mix of ordinary and awkward pairs (degenerate, touching, parallel).
fn pairs<T: tridist::Real>(n: usize) -> Vec<(Triangle<T>, Triangle<T>)> {
    let mut r = Rng(5);
    (0..n)
        .map(|i| {
            let a = r.tri::<T>();
            let mut b = r.tri::<T>();
            match i % 5 {
                1 => b[1] = a[0],                                // shared vertex
                2 => b = [a[0], a[1], a[0]],                     // degenerate, touching
                3 => b = a.map(|p| [p[0], p[1], p[2] + T::ONE]), // parallel copy
                _ => {}
            }
            (a, b)
        })
        .collect()
}

#[test]
fn same_bits_in_every_lane_position_and_in_the_tail() {
    let ps = pairs::<f32>(40);
    // with and without the quick stage: either path is independent of the neighbours
    for e in engines().into_iter().flat_map(|e| [e, e.quick_stage(false)]) {
        // Reference: each pair alone (a batch of one goes through the padded tail path).
        let alone: Vec<(f32, [f32; 3], [f32; 3])> = ps
            .iter()
            .map(|(a, b)| {
                let mut cp = [ClosestPoints::default()];
                e.closest_points_triangle_triangle(&[*a][..], &[*b][..], &mut cp).unwrap();
                (cp[0].sqdist, cp[0].p, cp[0].q)
            })
            .collect();
        // Every batch length 1..=17 and every offset: the pair lands in every lane and the tail.
        for len in 1..=17 {
            for start in 0..(ps.len() - len) {
                let a: Vec<_> = ps[start..start + len].iter().map(|x| x.0).collect();
                let b: Vec<_> = ps[start..start + len].iter().map(|x| x.1).collect();
                let (ba, bb) = (TriangleBatch::from_slice(&a), TriangleBatch::from_slice(&b));
                let mut cp = vec![ClosestPoints::default(); len];
                e.closest_points_triangle_triangle(&ba, &bb, &mut cp).unwrap();
                for k in 0..len {
                    let (rd, rp, rq) = alone[start + k];
                    assert_eq!(
                        cp[k].sqdist.to_bits(),
                        rd.to_bits(),
                        "{:?} len {len} start {start} lane {k}",
                        e
                    );
                    assert_eq!(cp[k].p, rp);
                    assert_eq!(cp[k].q, rq);
                }
                let mut d2 = vec![0.0f32; len];
                e.sqdist_triangle_triangle(&ba, &bb, &mut d2).unwrap();
                let d: Vec<f32> = cp.iter().map(|c| c.sqdist).collect();
                assert_eq!(d, d2, "distance-only must equal the distance of the points query");
            }
        }
    }
}

/// A batch of several chunks (the driver's 256 pairs), SoA and AoS: every pair gets the bits it
/// gets alone, also the pairs the quick stage leaves open, which the full fast stage reads
/// packed by the quick stage (where the lanes have a register compress) or gathered.
fn multi_chunk_batches_give_each_pair_its_own_bits<T: tridist::Real>() {
    let ps = pairs::<T>(700);
    let a: Vec<_> = ps.iter().map(|x| x.0).collect();
    let b: Vec<_> = ps.iter().map(|x| x.1).collect();
    for e in engines() {
        let alone: Vec<ClosestPoints<T>> = ps
            .iter()
            .map(|(a, b)| {
                let mut cp = [ClosestPoints::default()];
                e.closest_points_triangle_triangle(&[*a][..], &[*b][..], &mut cp).unwrap();
                cp[0]
            })
            .collect();
        let (mut soa, mut aos) =
            (vec![ClosestPoints::default(); ps.len()], vec![ClosestPoints::default(); ps.len()]);
        let c = e
            .run(
                Query::TriTri,
                &TriangleBatch::from_slice(&a),
                &TriangleBatch::from_slice(&b),
                Outputs::new().closest_points(&mut soa),
            )
            .unwrap();
        assert!(c.refined > 100 && c.refined < c.pairs, "{:?}: {c:?}", e.isa());
        e.closest_points_triangle_triangle(&a, &b, &mut aos).unwrap();
        for k in 0..ps.len() {
            for got in [&soa[k], &aos[k]] {
                assert_eq!(
                    (
                        got.sqdist.to_f64().to_bits(),
                        got.p.map(|x| x.to_f64().to_bits()),
                        got.q.map(|x| x.to_f64().to_bits())
                    ),
                    (
                        alone[k].sqdist.to_f64().to_bits(),
                        alone[k].p.map(|x| x.to_f64().to_bits()),
                        alone[k].q.map(|x| x.to_f64().to_bits())
                    ),
                    "{:?} pair {k}",
                    e.isa()
                );
            }
        }
    }
}

#[test]
fn multi_chunk_batches_give_each_pair_its_own_bits_f32() {
    multi_chunk_batches_give_each_pair_its_own_bits::<f32>();
}

#[test]
fn multi_chunk_batches_give_each_pair_its_own_bits_f64() {
    multi_chunk_batches_give_each_pair_its_own_bits::<f64>();
}

#[test]
fn soa_aos_and_single_queries_agree_on_the_scalar_variant() {
    let ps = pairs::<f64>(64);
    let a: Vec<_> = ps.iter().map(|x| x.0).collect();
    let b: Vec<_> = ps.iter().map(|x| x.1).collect();
    let e = Engine::scalar();
    let (mut soa, mut aos) = (vec![0.0; 64], vec![0.0; 64]);
    e.sqdist_triangle_triangle(&TriangleBatch::from_slice(&a), &TriangleBatch::from_slice(&b), &mut soa)
        .unwrap();
    e.sqdist_triangle_triangle(&a, &b, &mut aos).unwrap();
    assert_eq!(soa, aos);
    for (i, (x, y)) in ps.iter().enumerate() {
        assert_eq!(tridist::sqdist_triangle_triangle(x, y).to_bits(), soa[i].to_bits());
    }
}

#[test]
fn one_against_many_equals_pairs() {
    let ps = pairs::<f32>(30);
    let one = ps[0].0;
    let b: Vec<_> = ps.iter().map(|x| x.1).collect();
    let a: Vec<_> = vec![one; b.len()];
    for e in engines() {
        let (mut x, mut y) = (vec![0.0f32; b.len()], vec![0.0f32; b.len()]);
        e.sqdist_triangle_triangle(&one, &TriangleBatch::from_slice(&b), &mut x).unwrap();
        e.sqdist_triangle_triangle(&TriangleBatch::from_slice(&a), &TriangleBatch::from_slice(&b), &mut y)
            .unwrap();
        assert_eq!(x, y, "{:?}", e.isa());
    }
}

#[test]
fn non_finite_input_gives_nan_and_none_without_touching_other_lanes() {
    let ps = pairs::<f64>(9);
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let mut a: Vec<_> = ps.iter().map(|x| x.0).collect();
        let b: Vec<_> = ps.iter().map(|x| x.1).collect();
        let clean = a.clone();
        a[4][2][1] = bad;
        for e in engines() {
            let mut reference = vec![0.0; 9];
            e.sqdist_triangle_triangle(&clean, &b, &mut reference).unwrap();
            let mut cp = vec![ClosestPoints::default(); 9];
            let mut iv = vec![Interval::default(); 9];
            let out = Outputs::new().closest_points(&mut cp).intervals(&mut iv);
            e.run(Query::TriTri, &TriangleBatch::from_slice(&a), &TriangleBatch::from_slice(&b), out)
                .unwrap();
            assert!(cp[4].sqdist.is_nan() && cp[4].p[0].is_nan() && cp[4].q[0].is_nan());
            assert!(iv[4].lo.is_nan() && iv[4].hi.is_nan());
            for k in (0..9).filter(|&k| k != 4) {
                assert_eq!(
                    cp[k].sqdist.to_bits(),
                    reference[k].to_bits(),
                    "{:?} lane {k} disturbed",
                    e.isa()
                );
            }
            let mut f = vec![Intersection::Disjoint; 9];
            e.intersect_triangle_triangle(&a, &b, &mut f).unwrap();
            assert_eq!(f[4], Intersection::Invalid);
            let mut w = vec![0.0; 9];
            e.within_margin_triangle_triangle(&a, &b, 1.0, &mut w).unwrap();
            assert!(w[4].is_nan());
        }
    }
    let s = [[0.0f32, 0.0, f32::NAN], [1.0, 0.0, 0.0]];
    assert!(tridist::sqdist_segment_segment(&s, &[[0.0; 3], [1.0, 1.0, 1.0]]).is_nan());
    assert!(tridist::sqdist_point_triangle(&[f32::INFINITY, 0.0, 0.0], &ps_f32()[0]).is_nan());
}

fn ps_f32() -> Vec<Triangle<f32>> {
    pairs::<f32>(1).into_iter().map(|x| x.0).collect()
}

#[test]
fn misuse_is_an_error_not_a_panic() {
    let a = TriangleBatch::from_slice(&ps_f32().repeat(5));
    let b = TriangleBatch::from_slice(&ps_f32().repeat(4));
    for e in engines() {
        let mut out = vec![0.0f32; 5];
        assert!(matches!(
            e.sqdist_triangle_triangle(&a, &b, &mut out),
            Err(Error::LengthMismatch { what: "b", expected: 5, found: 4 })
        ));
        assert!(matches!(
            e.sqdist_triangle_triangle(&a, &a, &mut out[..2]),
            Err(Error::LengthMismatch { what: "sqdist", .. })
        ));
        let (mut p, mut q) = (vec![[0.0; 3]; 5], vec![[0.0; 3]; 4]);
        assert!(matches!(
            e.run(Query::TriTri, &a, &a, Outputs::new().sqdist(&mut out).points(&mut p, &mut q)),
            Err(Error::LengthMismatch { what: "q", .. })
        ));
        assert!(matches!(
            e.run(Query::SegSeg, &a, &a, Outputs::new().sqdist(&mut out)),
            Err(Error::Arity { query: Query::SegSeg, expected: (2, 2), found: (3, 3) })
        ));
        // the intersection test computes no distance: asking it for one is an error, each
        // distance output alike; its verdicts (and the zero iteration counts) are fine
        let mut iv = vec![Interval::default(); 5];
        let mut cp = vec![ClosestPoints::default(); 5];
        let (mut p5, mut q5) = (vec![[0.0; 3]; 5], vec![[0.0; 3]; 5]);
        let mut dist = vec![0.0f32; 5];
        assert!(matches!(
            e.run(Query::TriTri, &a, &a, Outputs::new().sqdist(&mut out).distances(&mut dist[..3])),
            Err(Error::LengthMismatch { what: "distances", expected: 5, found: 3 })
        ));
        // distances are the square roots of the squares (outside the correctly rounded mode)
        let moved: Vec<_> =
            ps_f32().repeat(5).iter().map(|t| t.map(|p| [p[0] + 3.0, p[1] * 0.5, p[2]])).collect();
        let moved = TriangleBatch::from_slice(&moved);
        e.run(Query::TriTri, &a, &moved, Outputs::new().sqdist(&mut out).distances(&mut dist)).unwrap();
        assert!(out.iter().any(|&d2| d2 > 0.0));
        assert!(out.iter().zip(&dist).all(|(d2, d)| d2.sqrt().to_bits() == d.to_bits()), "{out:?} {dist:?}");
        for (out, what) in [
            (Outputs::new().sqdist(&mut out), "sqdist"),
            (Outputs::new().distances(&mut dist), "distances"),
            (Outputs::new().intervals(&mut iv), "intervals"),
            (Outputs::new().closest_points(&mut cp), "closest_points"),
            (Outputs::new().points(&mut p5, &mut q5), "p"),
        ] {
            let r = e.run(Query::Intersect, &a, &a, out);
            assert_eq!(r, Err(Error::NoSuchOutput { query: Query::Intersect, output: what }));
            assert!(r.unwrap_err().to_string().contains("ask for verdicts"));
        }
        let (mut v, mut it) = (vec![Intersection::Invalid; 5], vec![7u32; 5]);
        e.run(Query::Intersect, &a, &a, Outputs::new().verdicts(&mut v).iterations(&mut it)).unwrap();
        assert!(v.iter().all(|&x| x == Intersection::Intersecting) && it == [0; 5]);
        assert_eq!(e.within_margin_triangle_triangle(&a, &a, -1.0, &mut out), Err(Error::InvalidMargin));
        assert_eq!(e.within_margin_triangle_triangle(&a, &a, f32::NAN, &mut out), Err(Error::InvalidMargin));
        assert_eq!(e.tolerance(Tolerance::scaled(-1.0)).check(), Err(Error::InvalidTolerance));
        assert_eq!(e.tolerance(Tolerance::relative(f64::NAN)).check(), Err(Error::InvalidTolerance));
        // empty batches are fine
        let empty = TriangleBatch::<f32>::from_slice(&[]);
        assert_eq!(e.sqdist_triangle_triangle(&empty, &empty, &mut []).map(|c| c.pairs), Ok(0));
        let segs = SegmentBatch::<f32>::from_slice(&[]);
        assert_eq!(e.sqdist_segment_segment(&segs, &segs, &mut []).map(|c| c.pairs), Ok(0));
    }
    assert!(matches!(
        tridist::within_margin_triangle_triangle(&ps_f32()[0], &ps_f32()[0], f32::INFINITY),
        Err(Error::InvalidMargin)
    ));
    assert_eq!(
        Engine::scalar().single::<f32, [f32; 3]>(Query::PointTri, &ps_f32()[0], &ps_f32()[0]).err(),
        Some(Error::Arity { query: Query::PointTri, expected: (1, 3), found: (3, 3) })
    );
    assert!(TriangleBatch::from_mesh(&[[0.0f32; 3]; 2], &[[0, 1, 2]]).is_err());
    assert_eq!(Isa::parse("avx1024"), None);
}

/// The builder convention: setters never fail, and every query on an engine with an invalid
/// setting returns that setting's error before it touches its outputs (batch, single and mesh
/// queries alike), as `Engine::check` does up front.
#[test]
fn an_invalid_setting_is_the_error_of_every_query() {
    let tet = tridist::Mesh::new(
        vec![[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        vec![[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]],
    )
    .unwrap();
    let (here, there) = (tridist::Pose::identity(), tridist::Pose::translation([3.0f32, 0.0, 0.0]));
    let a = ps_f32();
    for e in engines() {
        let big_rho = PenaltyOptions::<f64> { rho: 1e300, ..Default::default() };
        let bad = [
            (e.tolerance(Tolerance::scaled(-1.0)), Error::InvalidTolerance),
            (e.tolerance(Tolerance::absolute(f64::NAN)), Error::InvalidTolerance),
            (e.margin(-1.0), Error::InvalidMargin),
            (e.margin(f64::INFINITY), Error::InvalidMargin),
            (e.penalty(&PenaltyOptions::<f32> { max_iter: 0, ..Default::default() }), Error::InvalidOptions),
            (
                e.penalty(&PenaltyOptions::<f64> { reg: f64::NAN, ..Default::default() }),
                Error::InvalidOptions,
            ),
        ];
        for (b, err) in bad {
            assert_eq!(b.check(), Err(err.clone()), "{:?}", e.isa());
            let mut out = vec![7.0f32; a.len()];
            assert_eq!(b.sqdist_triangle_triangle(&a, &a, &mut out).err(), Some(err.clone()));
            assert!(out.iter().all(|&x| x == 7.0), "an invalid setting wrote outputs");
            let mut v = vec![Intersection::Invalid; a.len()];
            assert_eq!(b.intersect_triangle_triangle(&a, &a, &mut v).err(), Some(err.clone()));
            assert_eq!(b.single::<f32, _>(Query::TriTri, &a[0], &a[0]).err(), Some(err.clone()));
            assert_eq!(b.mesh_distance(&tet, &here, &tet, &there).err(), Some(err.clone()));
            assert_eq!(b.mesh_intersect(&tet, &here, &tet, &there).err(), Some(err.clone()));
            assert_eq!(b.mesh_closest_point(&tet, &here, [2.0, 0.0, 0.0]).err(), Some(err.clone()));
            // the settings the mesh clearance queries take as arguments replace the engine's
            let own = if err == Error::InvalidMargin { None } else { Some(err.clone()) };
            assert_eq!(b.mesh_within_margin(&tet, &here, &tet, &there, 0.5).err(), own);
            assert_eq!(b.mesh_contacts(&tet, &here, &tet, &there, 0.5, None).err(), own);
            // the threaded contact search too, also where the roots are apart
            let far = tridist::Pose::translation([300.0f32, 0.0, 0.0]);
            assert_eq!(b.threads(2).mesh_contacts(&tet, &here, &tet, &there, 0.5, None).err(), own);
            assert_eq!(b.threads(2).mesh_contacts(&tet, &here, &tet, &far, 0.5, None).err(), own);
            // a valid setting repairs the engine
            let fixed = match err {
                Error::InvalidTolerance => b.tolerance(Tolerance::DEFAULT),
                Error::InvalidMargin => b.margin(0.0),
                _ => b.penalty(&PenaltyOptions::<f64>::default()),
            };
            assert_eq!(fixed.check(), Ok(()));
            assert!(fixed.sqdist_triangle_triangle(&a, &a, &mut out).is_ok());
        }
        // a bad margin argument on a valid engine, threaded or not, near or with the roots apart
        let far = tridist::Pose::translation([300.0f32, 0.0, 0.0]);
        for (t, p) in [(1, &there), (2, &there), (1, &far), (2, &far)] {
            let r = e.threads(t).mesh_contacts(&tet, &here, &tet, p, f32::NAN, None);
            assert_eq!(r.err(), Some(Error::InvalidMargin), "threads {t}");
            let r = e.threads(t).mesh_within_margin(&tet, &here, &tet, p, -1.0);
            assert_eq!(r.err(), Some(Error::InvalidMargin), "threads {t}");
        }
        // options valid in f64 but not in f32 (rho beyond f32's range): f32 queries refuse them
        let b = e.penalty(&big_rho);
        assert_eq!(b.check(), Ok(()));
        let mut out = vec![0.0f32; a.len()];
        assert_eq!(b.sqdist_triangle_triangle(&a, &a, &mut out).err(), Some(Error::InvalidOptions));
        let a64: Vec<Triangle<f64>> = a.iter().map(|t| t.map(|p| p.map(f64::from))).collect();
        let mut out64 = vec![0.0f64; a.len()];
        assert!(b.sqdist_triangle_triangle(&a64, &a64, &mut out64).is_ok());
    }
}

#[test]
fn isa_selection() {
    assert!(Isa::Scalar.is_available());
    assert!(Isa::best().is_available());
    for i in Isa::ALL {
        assert_eq!(Isa::parse(i.name()), Some(i));
        match Engine::new(i) {
            Ok(e) => assert_eq!(e.isa(), i),
            Err(err) => assert_eq!(err, Error::Unavailable(i)),
        }
    }
    assert_eq!(Isa::Avx2Fma.lanes::<f32>(), 8);
    assert_eq!(Isa::Sse41.lanes::<f64>(), 2);
    assert_eq!(Isa::Avx512.lanes::<f32>(), 16);
    assert_eq!(Isa::Avx512.lanes::<f64>(), 8);
    assert_eq!(Isa::Avx512Vl.lanes::<f32>(), 8);
    assert_eq!(Isa::Avx512Vl.lanes::<f64>(), 4);
    // AVX-512 implies AVX2+FMA (its entry points enable them, and mesh queries hand their small
    // leaf batches to AVX-512VL, or to AVX2+FMA on a CPU without VL), and AVX-512VL implies both
    assert!(!Isa::Avx512.is_available() || Isa::Avx2Fma.is_available());
    assert!(!Isa::Avx512Vl.is_available() || (Isa::Avx512.is_available() && Isa::Avx2Fma.is_available()));
}

/// The AVX-without-FMA and AVX-512VL variants exist only with the `avx` and `avx512vl`
/// features (`cargo test -p tridist` builds without them, the workspace with them): without,
/// they are never picked and asking for one says which feature to enable.
#[test]
fn feature_gated_variants_follow_their_features() {
    assert_eq!(Isa::Avx.is_compiled(), cfg!(feature = "avx"));
    assert_eq!(Isa::Avx512Vl.is_compiled(), cfg!(feature = "avx512vl"));
    assert!(Isa::ALL.iter().all(|i| matches!(i, Isa::Avx | Isa::Avx512Vl) || i.is_compiled()));
    for isa in [Isa::Avx, Isa::Avx512Vl] {
        if !isa.is_compiled() {
            assert!(!isa.is_available());
            assert_ne!(Isa::best(), isa);
            let err = Engine::new(isa).unwrap_err();
            assert_eq!(err, Error::Unavailable(isa));
            assert!(err.to_string().contains(&format!("enable the `{}` feature", isa.name())), "{err}");
        }
    }
}

#[test]
fn within_margin_agrees_with_the_full_query() {
    let ps = pairs::<f32>(200);
    let a: Vec<_> = ps.iter().map(|x| x.0).collect();
    let b: Vec<_> = ps.iter().map(|x| x.1).collect();
    for e in engines() {
        let mut full = vec![0.0f32; ps.len()];
        e.sqdist_triangle_triangle(&a, &b, &mut full).unwrap();
        for margin in [0.0f32, 0.05, 0.3, 1.0, 10.0] {
            let mut w = vec![0.0f32; ps.len()];
            e.within_margin_triangle_triangle(&a, &b, margin, &mut w).unwrap();
            for k in 0..ps.len() {
                if full[k] <= margin * margin {
                    assert_eq!(w[k].to_bits(), full[k].to_bits(), "{:?} margin {margin} pair {k}", e.isa());
                } else {
                    assert_eq!(w[k], f32::INFINITY, "{:?} margin {margin} pair {k}: {}", e.isa(), full[k]);
                }
            }
        }
    }
}

#[test]
fn power_of_two_scaling_scales_the_result_exactly() {
    let ps = pairs::<f32>(100);
    for e in engines() {
        for k in [-60i32, -20, -1, 1, 7, 40] {
            let f = 2f32.powi(k);
            let a: Vec<_> = ps.iter().map(|x| x.0).collect();
            let b: Vec<_> = ps.iter().map(|x| x.1).collect();
            let sa: Vec<_> = a.iter().map(|t| t.map(|p| p.map(|c| c * f))).collect();
            let sb: Vec<_> = b.iter().map(|t| t.map(|p| p.map(|c| c * f))).collect();
            let (mut d, mut ds) = (vec![0.0f32; 100], vec![0.0f32; 100]);
            e.sqdist_triangle_triangle(&a, &b, &mut d).unwrap();
            e.sqdist_triangle_triangle(&sa, &sb, &mut ds).unwrap();
            for i in 0..100 {
                let want = d[i] * f * f;
                // exact unless the scaled square leaves the normal range
                if want == 0.0 || (want.abs() >= f32::MIN_POSITIVE && want.is_finite()) {
                    assert_eq!(ds[i], want, "{:?} k {k} pair {i}", e.isa());
                }
            }
            let segs_a: Vec<_> = a.iter().map(|t| [t[0], t[1]]).collect();
            let segs_b: Vec<_> = b.iter().map(|t| [t[0], t[2]]).collect();
            let sseg_a: Vec<_> = sa.iter().map(|t| [t[0], t[1]]).collect();
            let sseg_b: Vec<_> = sb.iter().map(|t| [t[0], t[2]]).collect();
            e.sqdist_segment_segment(&segs_a, &segs_b, &mut d).unwrap();
            e.sqdist_segment_segment(&sseg_a, &sseg_b, &mut ds).unwrap();
            for i in 0..100 {
                let want = d[i] * f * f;
                if want == 0.0 || (want.abs() >= f32::MIN_POSITIVE && want.is_finite()) {
                    assert_eq!(ds[i], want, "seg {:?} k {k} pair {i}", e.isa());
                }
            }
        }
    }
}

#[test]
fn overflowing_squares_give_infinity_with_finite_points() {
    let a = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]].map(|p| p.map(|c| c * 1e30));
    let b = a.map(|p| [p[0], p[1], p[2] + 3e30]);
    for e in engines() {
        let mut cp = [ClosestPoints::default()];
        e.closest_points_triangle_triangle(Prims::One(a), Prims::One(b), &mut cp).unwrap();
        assert_eq!(cp[0].sqdist, f32::INFINITY);
        assert!(cp[0].p.iter().chain(cp[0].q.iter()).all(|c| c.is_finite()));
        assert_eq!((cp[0].q[2] - cp[0].p[2]), 3e30);
    }
}

/// Triangles reaching from `-MAX/2` and `+MAX/2` outwards, whose closest points are their
/// tips: raw differences across the origin overflow (the local frame of triangle distance then
/// takes the scaled points' differences, `algo::local_pair`, whose unit test checks them; here
/// the answer is checked end to end, which PQP's stage would also recover, so this test alone
/// does not catch a missing fallback). The distance is `MAX`, so the squared distance is
/// `+inf` (documented), and the points are the tips exactly.
fn tips_near_max<T: tridist::Real>(engines: &[Engine]) {
    let h = T::MAX * T::from_f64(0.5);
    let (q1, q2) = (h * T::from_f64(0.25), h * T::from_f64(1.5));
    let z = T::from_f64(0.0);
    let a = [[z - h, z, z], [z - q2, q1, z], [z - q2, z - q1, q1]];
    let b = a.map(|p| [z - p[0], p[1], p[2]]);
    // a lane of ordinary magnitude beside it must keep its own answer
    let (sa, sb) =
        ([[z; 3], [T::from_f64(1.0), z, z], [z, T::from_f64(1.0), z]], [[z, z, T::from_f64(2.0)]; 3]);
    for e in engines.iter().flat_map(|e| [*e, e.quick_stage(false)]) {
        let mut cp = vec![ClosestPoints::default(); 9];
        let xa: Vec<_> = (0..9).map(|i| if i % 2 == 0 { a } else { sa }).collect();
        let xb: Vec<_> = (0..9).map(|i| if i % 2 == 0 { b } else { sb }).collect();
        e.closest_points_triangle_triangle(&xa[..], &xb[..], &mut cp).unwrap();
        for (i, c) in cp.iter().enumerate() {
            if i % 2 == 0 {
                assert_eq!(c.sqdist, T::INFINITY, "{:?} {i}", e.isa());
                assert_eq!((c.p, c.q), (a[0], b[0]), "{:?} {i}", e.isa());
            } else {
                assert_eq!(c.sqdist, T::from_f64(4.0), "{:?} {i}", e.isa());
            }
        }
    }
}

#[test]
fn triangles_near_plus_and_minus_half_max_give_their_tips() {
    tips_near_max::<f32>(&engines());
    tips_near_max::<f64>(&engines());
}

#[test]
fn threaded_batches_give_the_same_bits() {
    let ps = pairs::<f32>(3001);
    let a: Vec<_> = ps.iter().map(|x| x.0).collect();
    let b: Vec<_> = ps.iter().map(|x| x.1).collect();
    let (ba, bb) = (TriangleBatch::from_slice(&a), TriangleBatch::from_slice(&b));
    for e in engines().into_iter().flat_map(|e| [e, e.quick_stage(false)]) {
        let (mut one, mut two) =
            (vec![ClosestPoints::default(); ps.len()], vec![ClosestPoints::default(); ps.len()]);
        let c1 = e.closest_points_triangle_triangle(&ba, &bb, &mut one).unwrap();
        let c2 = e.threads(3).closest_points_triangle_triangle(&ba, &bb, &mut two).unwrap();
        assert_eq!(one, two);
        assert_eq!(c1, c2, "the same paths, counted once each");
        assert_eq!(c1.pairs, ps.len() as u64);
        let mut aos = vec![0.0f32; ps.len()];
        e.threads(2).sqdist_triangle_triangle(&a, &b, &mut aos).unwrap();
        assert_eq!(one.iter().map(|c| c.sqdist).collect::<Vec<_>>(), aos);
        let (mut f1, mut f2) = (vec![Intersection::Invalid; ps.len()], vec![Intersection::Invalid; ps.len()]);
        e.intersect_triangle_triangle(&ba, &bb, &mut f1).unwrap();
        e.threads(0).intersect_triangle_triangle(&ba, &bb, &mut f2).unwrap();
        assert_eq!(f1, f2);
    }
}

/// A touching pair far from the origin (exactly 3.67e-4 apart at `u S` = 0.14), found by
/// `cargo fuzz run within`.
const TOUCHING_FAR: (Triangle<f64>, Triangle<f64>) = (
    [
        [-783424.0, -1266637395981376.0, -140737489138752.0],
        [140187731758016.1, -783424.0000000001, -549756597312.0],
        [-549756597312.0, -549756597312.0, -783424.0],
    ],
    [
        [140187731758016.0, -783424.0, -549756597312.0],
        [-783424.0, -783424.0, 280925220113344.0],
        [-783423.9999999993, -783424.0, -783424.0],
    ],
);

#[test]
fn within_margin_zero_agrees_for_touching_pairs_far_from_origin() {
    // Found by `cargo fuzz run within`: margin 0 on a pair the full query puts at distance 0;
    // the box test rejected it on a rounding-level gap. Fixed: absolute slack of 64 u S.
    let (a, b) = TOUCHING_FAR;
    // The exact distance of this pair is 3.67e-4 at S = 1.27e15 (u S = 0.14): 0.0026 u S, far
    // inside the default tolerance (64 u S), where the contract lets margin 0 go either way.
    // What is pinned, per variant:
    // - the full query's distance is within E <= 8 of the exact one;
    // - within-margin is the full query's answer decided against the margin, bit for bit (at
    //   margin 0, and at 66 u S, beyond the tolerance's reach, where it must be "within");
    // - with the `exact` feature and `Tolerance::EXACT`, margin 0 is decided exactly: beyond
    //   (`the_exact_step_decides_margin_zero_far_from_the_origin`).
    let exact = tridist_oracle::sqdist_triangle_triangle(&a, &b).unwrap().to_f64().sqrt();
    assert!((exact - 3.6696e-4).abs() < 1e-7, "{exact}");
    let us = f64::EPSILON / 2.0 * 1_266_637_395_981_376.0;
    for e in engines() {
        let mut full = [1.0f64];
        e.sqdist_triangle_triangle(Prims::One(a), Prims::One(b), &mut full).unwrap();
        assert!((full[0].sqrt() - exact).abs() <= 8.0 * us, "{:?}: {} vs {exact}", e.isa(), full[0].sqrt());
        for margin in [0.0, 66.0 * us] {
            let mut w = [1.0f64];
            e.within_margin_triangle_triangle(Prims::One(a), Prims::One(b), margin, &mut w).unwrap();
            let decided = if full[0] <= margin * margin { full[0] } else { f64::INFINITY };
            assert_eq!(
                w[0].to_bits(),
                decided.to_bits(),
                "{:?} margin {margin}: {} vs {}",
                e.isa(),
                w[0],
                full[0]
            );
        }
        let mut w = [1.0f64];
        e.within_margin_triangle_triangle(Prims::One(a), Prims::One(b), 66.0 * us, &mut w).unwrap();
        assert!(w[0].is_finite(), "{:?}: beyond a margin 66 u S above a pair {exact} apart", e.isa());
    }
    let single = tridist::within_margin_triangle_triangle(&a, &b, 0.0).unwrap();
    let full = tridist::closest_points_triangle_triangle(&a, &b).sqdist;
    let decided = if full == 0.0 { Proximity::Within(0.0) } else { Proximity::Beyond };
    assert_eq!(single, decided, "the single-pair function decides as the full query");
}

/// With the `exact` feature and `Tolerance::EXACT`, the touching pair far from the origin of
/// `within_margin_zero_agrees_for_touching_pairs_far_from_origin` (exactly 3.67e-4 apart, at
/// `u S` = 0.14) is beyond margin 0 on every variant, and within a margin of twice its distance.
#[cfg(feature = "exact")]
#[test]
fn the_exact_step_decides_margin_zero_far_from_the_origin() {
    let (a, b) = TOUCHING_FAR;
    for e in engines() {
        let e = e.tolerance(Tolerance::EXACT);
        let (mut w0, mut w1) = ([0.0f64], [0.0f64]);
        e.within_margin_triangle_triangle(Prims::One(a), Prims::One(b), 0.0, &mut w0).unwrap();
        e.within_margin_triangle_triangle(Prims::One(a), Prims::One(b), 7.4e-4, &mut w1).unwrap();
        assert_eq!(w0[0], f64::INFINITY, "{:?}: within margin 0 at exact distance 3.67e-4", e.isa());
        assert!((w1[0].sqrt() - 3.6696e-4).abs() < 1e-7, "{:?}: {}", e.isa(), w1[0].sqrt());
    }
}

#[test]
fn penalty_method_returns_feasible_points_and_honours_its_options() {
    let ps = pairs::<f64>(100);
    let a: Vec<_> = ps.iter().map(|x| x.0).collect();
    let b: Vec<_> = ps.iter().map(|x| x.1).collect();
    let n = ps.len();
    for e in engines() {
        let opts = PenaltyOptions { max_iter: 5, ..Default::default() };
        let (mut cp, mut it) = (vec![ClosestPoints::default(); n], vec![0u32; n]);
        e.penalty_triangle_triangle(&a, &b, &opts, &mut cp, &mut it).unwrap();
        let mut exact = vec![0.0; n];
        e.sqdist_triangle_triangle(&a, &b, &mut exact).unwrap();
        for i in 0..n {
            assert!((1..=5).contains(&it[i]), "{:?}: {} iterations", e.isa(), it[i]);
            // the points are projected into their triangles: an upper bound of the distance
            assert!(
                cp[i].sqdist >= exact[i] * (1.0 - 1e-9) - 1e-12,
                "{:?} pair {i}: {} < {}",
                e.isa(),
                cp[i].sqdist,
                exact[i]
            );
            let dd: f64 = (0..3).map(|k| (cp[i].p[k] - cp[i].q[k]).powi(2)).sum();
            assert!((dd - cp[i].sqdist).abs() <= 1e-12 * (1.0 + dd), "the distance is that of the points");
        }
        let bad = PenaltyOptions { rho: -1.0, ..opts };
        assert_eq!(e.penalty_triangle_triangle(&a, &b, &bad, &mut cp, &mut it), Err(Error::InvalidOptions));
        let zero = PenaltyOptions { max_iter: 0, ..opts };
        assert_eq!(e.penalty_triangle_triangle(&a, &b, &zero, &mut cp, &mut it), Err(Error::InvalidOptions));
        assert!(matches!(
            e.penalty_triangle_triangle(&a, &b, &opts, &mut cp, &mut it[..3]),
            Err(Error::LengthMismatch { what: "iterations", .. })
        ));
    }
}

#[test]
fn single_queries_equal_a_batch_of_one_and_certify() {
    let ps = pairs::<f64>(60);
    for (a, b) in &ps {
        let mut d = [0.0];
        Engine::scalar().sqdist_triangle_triangle(&[*a][..], &[*b][..], &mut d).unwrap();
        assert_eq!(tridist::sqdist_triangle_triangle(a, b).to_bits(), d[0].to_bits());
        let r = Engine::scalar().single(Query::TriTri, a, b).unwrap();
        assert_eq!(r.closest.sqdist.to_bits(), d[0].to_bits());
        assert!(r.certified && r.interval.contains(r.closest.sqdist.sqrt()), "{r:?}");
        assert!(
            r.interval.width() <= 64.0 * f64::EPSILON / 2.0 * 2.0,
            "default tolerance 64 u S, S <= 1 here: {r:?}"
        );
        assert_eq!(
            tridist::intersect_triangle_triangle(a, b).as_bool(),
            Some(r.verdict == Intersection::Intersecting)
        );
    }
}

#[test]
fn outputs_in_any_combination_agree() {
    let ps = pairs::<f32>(37);
    let a: Vec<_> = ps.iter().map(|x| x.0).collect();
    let b: Vec<_> = ps.iter().map(|x| x.1).collect();
    let n = a.len();
    for e in engines() {
        let mut cp = vec![ClosestPoints::default(); n];
        e.closest_points_triangle_triangle(&a, &b, &mut cp).unwrap();
        let (mut d, mut p, mut q, mut iv, mut v) = (
            vec![0.0f32; n],
            vec![[0.0f32; 3]; n],
            vec![[0.0f32; 3]; n],
            vec![Interval::default(); n],
            vec![Intersection::Invalid; n],
        );
        let out = Outputs::new().sqdist(&mut d).points(&mut p, &mut q).intervals(&mut iv).verdicts(&mut v);
        let counts = e.run(Query::TriTri, &a, &b, out).unwrap();
        assert_eq!(counts.pairs, n as u64);
        for i in 0..n {
            assert_eq!((cp[i].sqdist, cp[i].p, cp[i].q), (d[i], p[i], q[i]));
            assert!(iv[i].lo <= iv[i].hi && iv[i].lo >= 0.0);
            // every pair's distance lies in its interval up to its final rounding
            let dist = d[i].sqrt();
            assert!(
                dist >= iv[i].lo * (1.0 - 1e-6) && dist <= iv[i].hi * (1.0 + 1e-6),
                "{i}: {dist} {:?}",
                iv[i]
            );
            assert_eq!(
                v[i] == Intersection::Intersecting,
                d[i] == 0.0 || iv[i].lo == 0.0 && iv[i].hi <= 64.0 * 6e-8 * 2.0
            );
        }
    }
}

#[test]
fn tolerances_trade_work_for_width() {
    let ps = pairs::<f32>(400);
    let a: Vec<_> = ps.iter().map(|x| x.0).collect();
    let b: Vec<_> = ps.iter().map(|x| x.1).collect();
    let n = a.len();
    for e in engines() {
        let mut widths = Vec::new();
        for tol in [Tolerance::DEFAULT, Tolerance::scaled(4.0), Tolerance::absolute(1e-9), Tolerance::EXACT] {
            let (mut d, mut iv) = (vec![0.0f32; n], vec![Interval::default(); n]);
            let c = e
                .tolerance(tol)
                .run(Query::TriTri, &a, &b, Outputs::new().sqdist(&mut d).intervals(&mut iv))
                .unwrap();
            let w = iv.iter().map(|i| i.width()).fold(0.0f32, f32::max);
            widths.push((tol, w, c));
        }
        // a tighter tolerance sends more pairs down the pipeline and narrows the intervals
        assert!(
            widths[1].2.recertified + widths[1].2.widened >= widths[0].2.recertified + widths[0].2.widened
        );
        assert!(widths[1].1 <= widths[0].1, "{widths:?}");
        // f32 pairs the f32 stages cannot certify to 1e-9 go to f64, whose intervals are that tight
        assert!(widths[2].2.widened > 0 && widths[2].1 <= 1e-6, "{widths:?}");
    }
}

#[test]
fn batches_update_in_place_and_queries_see_it() {
    let ps = pairs::<f64>(20);
    let a: Vec<_> = ps.iter().map(|x| x.0).collect();
    let local = TriangleBatch::from_slice(&a);
    let mut world = TriangleBatch::default();
    let far = tridist::Pose::translation([100.0, 0.0, 0.0]);
    world.transform_from(&local, &far).unwrap();
    let mut d = vec![0.0; 20];
    let e = Engine::auto();
    e.sqdist_triangle_triangle(&world, &local, &mut d).unwrap();
    assert!(d.iter().all(|&x| x > 90.0 * 90.0), "moved 100 away");
    world.transform_from(&local, &tridist::Pose::identity()).unwrap();
    e.sqdist_triangle_triangle(&world, &local, &mut d).unwrap();
    assert!(d.iter().all(|&x| x == 0.0), "the same triangles: {d:?}");
}

#[cfg(feature = "glam")]
#[test]
fn glam_vectors_are_points() {
    let a = [glam::Vec3::new(0.0, 0.0, 0.0), glam::Vec3::new(1.0, 0.0, 0.0), glam::Vec3::new(0.0, 1.0, 0.0)];
    let b = a.map(|v| v + glam::Vec3::Z * 2.0);
    assert_eq!(tridist::sqdist_triangle_triangle(&a, &b), 4.0f32);
    let da = a.map(|v| v.as_dvec3());
    let db = b.map(|v| v.as_dvec3());
    assert_eq!(tridist::sqdist_triangle_triangle(&da, &db), 4.0f64);
    let batch = TriangleBatch::from_points([a, b]);
    assert_eq!(batch.get(1), Some(b.map(|v| v.to_array())));
}

#[cfg(feature = "mint")]
#[test]
fn mint_points_are_points() {
    let p = |x: f32, y: f32, z: f32| mint::Point3 { x, y, z };
    let a = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(0.0, 1.0, 0.0)];
    assert_eq!(tridist::sqdist_point_triangle(&p(0.25, 0.25, 3.0), &a), 9.0);
}

/// `Engine::quick_stage(false)` sends every triangle pair to the full fast stage: a pair the
/// quick stage leaves open gets the same bits either way (the same stage and escalation), and
/// a pair it answers gets an answer whose certified interval meets the quick one's (both hold
/// the exact distance). Pairs one at a time, so the counts say which path each took.
#[test]
fn without_the_quick_stage_every_pair_takes_the_full_stage() {
    let mut ps = pairs::<f32>(300);
    // nearby pairs of a fine mesh, which the quick stage answers: a sheet of small triangles
    let mut r = Rng(9);
    for _ in 0..100 {
        let (x, y) = (r.f(), r.f());
        let h = 0.01;
        let a = [[x, y, 0.0], [x + h, y, 0.0], [x, y + h, 0.0]];
        let b =
            [[x + 2.5 * h, y, 0.3 * h], [x + 3.5 * h, y + 0.2 * h, 0.2 * h], [x + 2.5 * h, y + h, 0.1 * h]];
        ps.push((a.map(|p| p.map(|c| c as f32)), b.map(|p| p.map(|c| c as f32))));
    }
    for e in engines() {
        let off = e.quick_stage(false);
        assert!(e.uses_quick_stage() && !off.uses_quick_stage());
        let (mut quick_apart, mut both_refined) = (0, 0);
        for (a, b) in &ps {
            let mut got =
                [(ClosestPoints::default(), Interval::default(), tridist::PathCounts::default()); 2];
            for (eng, g) in [e, off].into_iter().zip(&mut got) {
                let (mut cp, mut iv) = ([ClosestPoints::default()], [Interval::default()]);
                let out = Outputs::new().closest_points(&mut cp).intervals(&mut iv);
                let c = eng.run(Query::TriTri, &[*a][..], &[*b][..], out).unwrap();
                *g = (cp[0], iv[0], c);
            }
            let [(c1, i1, k1), (c2, i2, k2)] = got;
            assert_eq!((k2.pairs, k2.refined), (1, 1), "{:?}: {a:?} {b:?} not sent to the full stage", off);
            if k1.refined == 1 {
                both_refined += 1;
                assert_eq!(
                    (c1, i1, k1),
                    (c2, i2, k2),
                    "{:?}: the same path must give the same bits",
                    e.isa()
                );
            } else {
                quick_apart += usize::from(c1.sqdist > 0.0);
                assert!(
                    i1.lo <= i2.hi && i2.lo <= i1.hi,
                    "{:?}: disjoint certified intervals {i1:?} {i2:?} for {a:?} {b:?}",
                    e.isa()
                );
            }
        }
        assert!(
            quick_apart >= 100 && both_refined >= 100,
            "{quick_apart} answered apart by the quick stage, {both_refined} refined"
        );
    }
}

/// A distance so small against the coordinates that its prescaled square underflows (f32:
/// segments and triangles spanning `±big`, 1 apart): the squared distance is still the square
/// of a distance in its certified interval, rounded once (`Tolerance`'s guarantee), not 0 below
/// an interval that starts near 1.
fn squares_within_their_intervals<T: tridist::Real>(engines: &[Engine], big: f64) {
    let c = |x: f64| T::from_f64(x);
    let a: Triangle<T> = [[c(big), c(0.0), c(0.0)], [c(-big), c(0.0), c(0.0)], [c(0.0), c(1.0), c(0.0)]];
    let b: Triangle<T> = [[c(0.0), c(0.0), c(1.0)], [c(1.0), c(0.0), c(1.0)], [c(0.0), c(1.0), c(1.0)]];
    let u = T::UNIT_ROUNDOFF.to_f64();
    for e in engines {
        for q in [Query::TriTri, Query::SegSeg, Query::PointTri] {
            let (mut d, mut iv) = ([T::ZERO], [Interval::default()]);
            let out = Outputs::new().sqdist(&mut d).intervals(&mut iv);
            let r = match q {
                Query::TriTri => e.run(q, &[a][..], &[b][..], out),
                Query::SegSeg => e.run(q, &[[a[0], a[1]]][..], &[[b[0], b[1]]][..], out),
                _ => e.run(q, &[[b[0]]][..], &[a][..], out),
            };
            r.unwrap();
            let (d, lo, hi) = (d[0].to_f64(), iv[0].lo.to_f64(), iv[0].hi.to_f64());
            assert!(
                lo <= 1.0 && 1.0 <= hi,
                "{:?} {q:?}: the exact distance 1 is not in [{lo}, {hi}]",
                e.isa()
            );
            assert!(
                lo * lo * (1.0 - 2.0 * u) <= d && d <= hi * hi * (1.0 + 2.0 * u),
                "{:?} {q:?} {}: squared distance {d} outside [{lo}, {hi}] squared",
                e.isa(),
                T::PRECISION.name()
            );
        }
    }
}

#[test]
fn tiny_distances_far_from_the_origin_square_within_their_intervals() {
    let e = engines();
    squares_within_their_intervals::<f32>(&e, 3e38);
    squares_within_their_intervals::<f32>(&e, 1e30);
    squares_within_their_intervals::<f64>(&e, 1e300);
    squares_within_their_intervals::<f64>(&e, 1e200);
}

/// The exact oracle as the last escalation step (feature `exact`), as [`Tolerance::EXACT`]'s
/// docs promise: every pair no floating-point stage answers exactly is answered by the oracle,
/// so every squared distance is the exact one correctly rounded and every interval holds the
/// exact distance; with the step switched off, those pairs stay uncertified instead.
#[cfg(feature = "exact")]
#[test]
fn the_exact_step_answers_what_no_float_stage_can() {
    fn check<T: tridist::Real + tridist_oracle::Float>(round: fn(&rug::Rational) -> f64) {
        use rug::Rational;
        let ps = pairs::<T>(60);
        let a: Vec<_> = ps.iter().map(|x| x.0).collect();
        let b: Vec<_> = ps.iter().map(|x| x.1).collect();
        let n = a.len();
        let truth: Vec<Rational> =
            ps.iter().map(|(a, b)| tridist_oracle::sqdist_triangle_triangle(a, b).unwrap()).collect();
        for e in engines() {
            let e = e.tolerance(Tolerance::EXACT);
            let (mut d, mut iv) = (vec![T::ZERO; n], vec![Interval::<T>::default(); n]);
            let c = e
                .exact(true)
                .run(Query::TriTri, &a, &b, Outputs::new().sqdist(&mut d).intervals(&mut iv))
                .unwrap();
            assert!(c.exact > 0 && c.uncertified == 0, "{:?}: {c:?}", e.isa());
            for i in 0..n {
                assert_eq!(d[i].to_f64(), round(&truth[i]), "{:?} pair {i}", e.isa());
                let (lo, hi) = (
                    Rational::from_f64(iv[i].lo.to_f64()).unwrap(),
                    Rational::from_f64(iv[i].hi.to_f64()).unwrap(),
                );
                assert!(
                    lo.clone() * &lo <= truth[i] && truth[i] <= hi.clone() * &hi,
                    "{:?} pair {i}: {:?}",
                    e.isa(),
                    iv[i]
                );
            }
            let c = e.exact(false).run(Query::TriTri, &a, &b, Outputs::new().sqdist(&mut d)).unwrap();
            assert!(c.exact == 0 && c.uncertified > 0, "{:?}: {c:?}", e.isa());
        }
    }
    check::<f32>(|q| tridist_oracle::round::to_f32(q) as f64);
    check::<f64>(tridist_oracle::round::to_f64);
}

/// The closest-point queries of segments, points and the brute-force triangle kernel, each by
/// its free function and its engine method on every variant, on pairs whose answer is exact in
/// binary (so every variant must give it exactly): which point lies on which primitive
/// included.
#[test]
fn closest_points_of_segments_points_and_brute_triangles_by_name() {
    type C = ([f64; 3], [f64; 3], f64);
    type Seg = [[f64; 3]; 2];
    fn check<T: tridist::Real>(what: &str, got: ClosestPoints<T>, want: C) {
        let t = |p: [f64; 3]| p.map(T::from_f64);
        assert_eq!((got.sqdist, got.p, got.q), (T::from_f64(want.2), t(want.0), t(want.1)), "{what}");
    }
    fn run<T: tridist::Real>() {
        let v = |p: [f64; 3]| p.map(T::from_f64);
        let x = [0.0, 0.0, 0.0];
        let tri = [x, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]].map(v);
        // (segment, segment, closest point on the first, on the second, squared distance)
        let segs: [(Seg, Seg, C); 3] = [
            (
                [x, [1.0, 0.0, 0.0]],
                [[0.5, 1.0, -1.0], [0.5, 1.0, 1.0]],
                ([0.5, 0.0, 0.0], [0.5, 1.0, 0.0], 1.0),
            ),
            (
                [x, [1.0, 0.0, 0.0]],
                [[2.0, 1.0, 0.0], [3.0, 1.0, 0.0]],
                ([1.0, 0.0, 0.0], [2.0, 1.0, 0.0], 2.0),
            ),
            ([x, [1.0, 0.0, 0.0]], [[0.25, 2.0, 0.0]; 2], ([0.25, 0.0, 0.0], [0.25, 2.0, 0.0], 4.0)),
        ];
        // (point, closest point of `tri`, squared distance): above the face, beyond a vertex,
        // beyond the long edge, beyond a short edge
        let pts: [([f64; 3], [f64; 3], f64); 4] = [
            ([0.25, 0.25, 2.0], [0.25, 0.25, 0.0], 4.0),
            ([2.0, -1.0, 0.0], [1.0, 0.0, 0.0], 2.0),
            ([1.0, 1.0, 0.0], [0.5, 0.5, 0.0], 0.5),
            ([-1.0, 0.5, 3.0], [0.0, 0.5, 0.0], 10.0),
        ];
        // a triangle whose lowest vertex is over the face of `tri`, and one swapped
        let over = [[0.25, 0.25, 2.0], [3.0, 0.25, 5.0], [0.25, 3.0, 5.0]].map(v);
        for e in engines() {
            for (a, b, want) in segs {
                let (a, b) = (a.map(v), b.map(v));
                check(
                    &format!("segments {a:?} {b:?}"),
                    tridist::closest_points_segment_segment(&a, &b),
                    want,
                );
                let mut out = [ClosestPoints::default()];
                e.closest_points_segment_segment(&[a][..], &[b][..], &mut out).unwrap();
                check(&format!("{e:?} segments {a:?} {b:?}"), out[0], want);
            }
            for (p, q, d) in pts {
                let p = v(p);
                let want = (p.map(|c| c.to_f64()), q, d);
                check(&format!("point {p:?}"), tridist::closest_point_point_triangle(&p, &tri), want);
                let mut out = [ClosestPoints::default()];
                e.closest_point_point_triangle(&[[p]][..], &[tri][..], &mut out).unwrap();
                check(&format!("{e:?} point {p:?}"), out[0], want);
            }
            for (a, b, want) in [
                (tri, over, ([0.25, 0.25, 0.0], [0.25, 0.25, 2.0], 4.0)),
                (over, tri, ([0.25, 0.25, 2.0], [0.25, 0.25, 0.0], 4.0)),
            ] {
                check("brute", tridist::closest_points_triangle_triangle_brute(&a, &b), want);
                let mut out = [ClosestPoints::default()];
                e.closest_points_triangle_triangle_brute(&[a][..], &[b][..], &mut out).unwrap();
                check(&format!("{e:?} brute"), out[0], want);
                let mut d = [T::ZERO];
                e.sqdist_triangle_triangle_brute(&[a][..], &[b][..], &mut d).unwrap();
                assert_eq!(d[0], T::from_f64(want.2), "{e:?} brute squared distance");
            }
        }
    }
    run::<f32>();
    run::<f64>();
}
