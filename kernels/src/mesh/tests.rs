//! Unit tests of the tree, the bounds and the traversal (the differential tests against an
//! exact brute force are `scenes/tests/mesh.rs`).

use super::{area_split, dot, principal_axes, Aabb, Item, Obb};

/// `area_split` cuts where the area estimate says, not at the median: 10 small boxes
/// around x = 0 and 30 around x = 100 (so the median would cut the second cluster) are
/// split into the two clusters; on random boxes every item put first has a smaller centre
/// than every item after, two at least on each side; and it declines (for the median)
/// where the centres do not spread or cannot leave two items on each side.
#[test]
fn area_splits_cut_between_clusters_and_partition_by_centre() {
    let mut rnd = uniform(0x2545_f491_4f6c_dd1d);
    let items_of = |boxes: &[Aabb]| -> Vec<Item> {
        let c = |(lo, hi): &Aabb| [0, 1, 2].map(|k| 0.5 * lo[k] + 0.5 * hi[k]);
        boxes.iter().enumerate().map(|(i, b)| Item { c: c(b), tri: i as u32 }).collect()
    };
    let range = |items: &[Item], k: usize| {
        items.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), it| (l.min(it.c[k]), h.max(it.c[k])))
    };
    let mut boxes: Vec<Aabb> = Vec::new();
    for (count, x) in [(10, 0.0), (30, 100.0)] {
        for _ in 0..count {
            let o = [x + rnd(), rnd(), rnd()];
            boxes.push((o, [0, 1, 2].map(|k| o[k] + 0.1 * (rnd() + 0.5))));
        }
    }
    let mut items = items_of(&boxes);
    let (lo, hi) = range(&items, 0);
    assert_eq!(area_split(&mut items, &boxes, 0, lo, hi), Some(10));
    assert!(items[..10].iter().all(|it| it.c[0] < 50.0));
    for n in [4, 5, 7, 16, 17, 100, 3000] {
        let boxes: Vec<Aabb> = (0..n)
            .map(|_| {
                let o = [0; 3].map(|_| 10.0 * rnd());
                (o, [0, 1, 2].map(|k| o[k] + rnd() + 0.5))
            })
            .collect();
        for k in 0..3 {
            let mut items = items_of(&boxes);
            let (lo, hi) = range(&items, k);
            // (small nodes may have no boundary with two on each side)
            let Some(first) = area_split(&mut items, &boxes, k, lo, hi) else {
                assert!(n < 16, "{n} random centres have a split");
                continue;
            };
            assert!(first >= 2 && n - first >= 2, "{n} items, {first} first");
            let before = items[..first].iter().fold(f64::NEG_INFINITY, |m, it| m.max(it.c[k]));
            let after = items[first..].iter().fold(f64::INFINITY, |m, it| m.min(it.c[k]));
            assert!(before < after, "{n} items, axis {k}: {before} put before {after}");
            let mut tris: Vec<u32> = items.iter().map(|it| it.tri).collect();
            tris.sort_unstable();
            assert!(tris.iter().copied().eq(0..n as u32), "a permutation");
        }
    }
    // no spread along the axis, or too few items to leave two on each side
    let same: Vec<Aabb> = (0..8).map(|_| ([1.0, rnd(), rnd()], [2.0, 3.0, 3.0])).collect();
    assert_eq!(area_split(&mut items_of(&same), &same, 0, 1.5, 1.5), None);
    let three = &boxes[..3];
    let mut items = items_of(three);
    let (lo, hi) = range(&items, 0);
    assert_eq!(area_split(&mut items, three, 0, lo, hi), None);
}

/// The closed-form axes are orthonormal eigenvectors: for `A = Q^T diag(l) Q` (Q a
/// rotation), `A x = l x` for every axis x within rounding, with distinct, repeated (then
/// any basis of the eigenspace is right) and zero eigenvalues; NaN gives the identity.
#[test]
fn principal_axes_are_orthonormal_eigenvectors() {
    let (c, s) = (0.6f64, 0.8f64);
    let (c2, s2) = (0.28f64, 0.96f64);
    // a rotation about z, then about x
    let q = [[c, -s * c2, s * s2], [s, c * c2, -c * s2], [0.0, s2, c2]];
    for l in [
        [3.0, 2.0, 1.0],
        [5.0, 5.0, 1.0],
        [1.0, 1e-3, 1e-3],
        [2.0, 0.0, 0.0],
        [1e-20, 1e-21, 0.0],
        [7.0, 7.0, 7.0],
        // scale-free: a cross product of rows of A - l I would underflow (or overflow)
        [3e-200, 2e-200, 1e-200],
        [3e100, 2e100, 1e100],
    ] {
        let a = [0, 1, 2].map(|i| [0, 1, 2].map(|j| (0..3).map(|k| q[k][i] * l[k] * q[k][j]).sum::<f64>()));
        let e = principal_axes(a);
        let big = l.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for (i, x) in e.iter().enumerate() {
            for (j, y) in e.iter().enumerate() {
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((dot(x, y) - want).abs() < 1e-12, "{l:?}: axes {i}, {j} not orthonormal: {e:?}");
            }
            let ax = [0, 1, 2].map(|r| dot(&a[r], x));
            let lam = dot(&ax, x);
            let res = [0, 1, 2].map(|r| ax[r] - lam * x[r]);
            // (the largest component: a sum of squares would underflow at 1e-200)
            let res = res.iter().fold(0.0f64, |m, r| m.max(r.abs()));
            assert!(res <= 1e-6 * big, "{l:?}: axis {i} {x:?} not an eigenvector");
        }
    }
    let nan = [[f64::NAN; 3]; 3];
    assert_eq!(principal_axes(nan), [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
}

/// `a + b` as an unevaluated sum (Knuth's two-sum: exact).
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// A double-double `(hi, lo)` times `x`, plus a double-double: about 2^-100 relative.
fn dd_mul_add(a: (f64, f64), x: f64, acc: (f64, f64)) -> (f64, f64) {
    let p = a.0 * x;
    let e = a.0.mul_add(x, -p) + a.1 * x;
    let (s, t) = two_sum(acc.0, p);
    two_sum(s, t + acc.1 + e)
}

/// Every point lies in its box (fitted, or from its axis-aligned box) as the type
/// promises: with `s_i = e_i . (v - c)` (computed in double-double, far below the box's
/// allowance), `|s_i| <= h_i` and `|v - c - sum s_i e_i|_1 <= rho`; and the box is tight
/// (its widths within a millionth of the point set's extent plus the allowance's order).
#[test]
fn oriented_boxes_contain_their_points() {
    let mut rnd = uniform(0x9e37_79b9_7f4a_7c15);
    let mut sets: Vec<Vec<[f64; 3]>> = Vec::new();
    for &(size, offset) in &[(1.0, 0.0), (1e-3, 1e3), (1e-6, 1e6), (1e3, -1e-3), (1e-9, 0.5)] {
        for n in [1, 2, 3, 7, 40] {
            // a blob, a flat patch (z exactly equal), a line, a thin slab
            sets.push((0..n).map(|_| [0; 3].map(|_| offset + size * rnd())).collect());
            let z = offset + size * rnd();
            sets.push((0..n).map(|_| [offset + size * rnd(), offset + size * rnd(), z]).collect());
            let (o, d) = ([0; 3].map(|_| offset + size * rnd()), [0; 3].map(|_| size * rnd()));
            sets.push(
                (0..n)
                    .map(|_| {
                        let t = rnd();
                        [0, 1, 2].map(|k| o[k] + t * d[k])
                    })
                    .collect(),
            );
            sets.push(
                (0..n)
                    .map(|_| [offset + size * rnd(), offset + size * rnd(), offset + 1e-12 * size * rnd()])
                    .collect(),
            );
        }
    }
    for (pts, b) in sets.iter().flat_map(|pts| {
        // fitted on the principal axes, and the box of a large node (its axis-aligned box)
        let mut bx = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        pts.iter().for_each(|p| super::unite(&mut bx, &(*p, *p)));
        [(pts, Obb::fit(pts)), (pts, Obb::of_box(&bx))]
    }) {
        for v in pts {
            let d = [0, 1, 2].map(|k| two_sum(v[k], -b.c[k]));
            let s = [0, 1, 2].map(|i| (0..3).fold((0.0, 0.0), |acc, k| dd_mul_add(d[k], b.e[i][k], acc)));
            for i in 0..3 {
                assert!(s[i].0.abs() + s[i].1.abs() <= b.h[i], "|s_{i}| = {:e} > h = {:e}", s[i].0, b.h[i]);
            }
            let mut r1 = 0.0;
            for k in 0..3 {
                let mut r = d[k];
                for i in 0..3 {
                    r = dd_mul_add(s[i], -b.e[i][k], r);
                }
                r1 += r.0.abs() + r.1.abs();
            }
            assert!(r1 <= b.rho, "|r|_1 = {r1:e} > rho = {:e}", b.rho);
        }
        // tight: the box's half-widths exceed the set's own (along its axes) by rounding only
        let m = pts.iter().map(|p| p[0].abs() + p[1].abs() + p[2].abs()).fold(0.0, f64::max);
        for i in 0..3 {
            let proj: Vec<f64> = pts.iter().map(|p| super::dot(&b.e[i], p)).collect();
            let half = 0.5
                * (proj.iter().copied().fold(f64::MIN, f64::max)
                    - proj.iter().copied().fold(f64::MAX, f64::min));
            assert!(b.h[i] - half <= 1e-12 * m, "h_{i} = {:e}, half-width {half:e}", b.h[i]);
        }
        assert!(b.rho <= 1e-12 * m, "rho = {:e}", b.rho);
    }
}

/// The leaf test keeps, on every instruction set, exactly the triangle pairs whose boxes
/// the scalar `box_gap2` does not put beyond the limit: leaves of 1 to 8 triangles with
/// random boxes (overlapping, touching and apart, at magnitudes from 1e-3 to 1e3, some
/// degenerate), limits of 0, exactly one pair's gap (kept) and the number below it, and
/// random ones; the numbers past the rows random too (the lanes past the last triangle
/// read them).
#[test]
fn leaf_pairs_keep_the_pairs_the_scalar_box_gap_keeps_on_every_isa() {
    use super::*;
    let isas: Vec<crate::Isa> = crate::Isa::ALL.into_iter().filter(|i| i.is_available()).collect();
    let mut rnd = uniform(0x9e37_79b9_7f4a_7c15);
    let (mut kept, mut dropped) = (0usize, 0usize);
    for case in 0..4000 {
        let scale = 10f64.powi((case % 7) as i32 - 3);
        let (na, nb) = (1 + case % MAX_LEAF, 1 + (case / MAX_LEAF) % MAX_LEAF);
        let mut boxes = |n: usize| -> Vec<Aabb> {
            (0..n)
                .map(|_| {
                    let o = [rnd(), rnd(), rnd()].map(|x| x * scale);
                    let flat = rnd() < -0.3;
                    let w = [rnd(), rnd(), rnd()].map(|x| if flat { 0.0 } else { (x + 0.5) * 0.3 * scale });
                    (o, [0, 1, 2].map(|k| o[k] + w[k]))
                })
                .collect()
        };
        let (ba, bb) = (boxes(na), boxes(nb));
        let mut rows = |b: &[Aabb]| -> Vec<f64> {
            let n = b.len();
            let mut r: Vec<f64> = (0..6 * n + MAX_LEAF).map(|_| rnd() * scale).collect();
            for (j, (lo, hi)) in b.iter().enumerate() {
                for q in 0..3 {
                    (r[q * n + j], r[(3 + q) * n + j]) = (lo[q], hi[q]);
                }
            }
            r
        };
        let (ra, rb) = (rows(&ba), rows(&bb));
        let one = box_gap2(&ba[case % na], &bb[(case / 3) % nb]);
        let limits = [0.0, one, one.next_down(), (rnd() + 0.5) * scale * scale * 0.1];
        for limit in limits {
            let mut want = 0u64;
            for (i, a) in ba.iter().enumerate() {
                for (j, b) in bb.iter().enumerate() {
                    // kept unless beyond the limit, as `push_leaves` kept them
                    if box_gap2(a, b).partial_cmp(&limit) != Some(core::cmp::Ordering::Greater) {
                        want |= 1 << (i * MAX_LEAF + j);
                    }
                }
            }
            kept += want.count_ones() as usize;
            dropped += na * nb - want.count_ones() as usize;
            let t = LeafTest { a: &ra, na, b: &rb, nb, limit };
            for &isa in &isas {
                let mut got = u64::MAX;
                crate::arch::leaf_pairs(isa, &t, &mut got);
                assert_eq!(got, want, "{isa}: case {case}, {na} x {nb} triangles, limit {limit:e}");
            }
        }
    }
    // both outcomes well represented
    assert!(kept > 20_000 && dropped > 20_000, "kept {kept}, dropped {dropped}");
}

/// One node test as `siblings` runs it, on `isa`, with the same limit for every child.
fn test_gaps(
    isa: crate::Isa,
    sa: &mut super::Side<'_, f64>,
    p: u32,
    sb: &mut super::Side<'_, f64>,
    f: u32,
    lim: f64,
) -> [f64; super::MAX_WIDTH] {
    let n = sa.mesh.nodes[p as usize].kids as usize;
    let (at, fixed_at) = (sa.group(p), sb.bounds_at(f));
    super::node_test(isa, (sa, at, n), (sb, fixed_at), super::Limit::Fixed(lim)).gap
}

/// Checks the moved bounds of every node of `m` in `pose` (see the test below); returns how
/// many vertices were checked.
fn check_columns<T: crate::Real>(m: &super::Mesh<T>, pose: &crate::Pose<T>) -> usize {
    use super::*;
    let isas: Vec<crate::Isa> = crate::Isa::ALL.into_iter().filter(|i| i.is_available()).collect();
    let mv = Moved::of(pose);
    let stride = m.shape.width.next_multiple_of(4);
    for p in (0..m.nodes.len()).filter(|&p| m.nodes[p].count == 0) {
        let first = m.nodes[p].first as usize;
        let mut want = vec![0.0; ROWS * stride];
        crate::arch::node_columns(crate::Isa::Scalar, &mut m.columns(&mv, first, stride, &mut want, stride));
        for &isa in &isas {
            let mut got = vec![0.0; ROWS * stride];
            crate::arch::node_columns(isa, &mut m.columns(&mv, first, stride, &mut got, stride));
            for (r, (g, w)) in got.iter().zip(&want).enumerate() {
                assert_eq!(
                    g.to_bits(),
                    w.to_bits(),
                    "{isa}: children of {p}, row {} lane {}",
                    r / stride,
                    r % stride
                );
            }
        }
        for j in 0..stride {
            let one = mv.column(m, first + j);
            for r in 0..ROWS {
                assert_eq!(one[r].to_bits(), want[r * stride + j].to_bits(), "node {} row {r}", first + j);
            }
        }
    }
    let mut checked = 0;
    for i in 0..m.nodes.len() {
        let col = mv.column(m, i);
        let (mut todo, mut tris) = (vec![i], Vec::new());
        while let Some(n) = todo.pop() {
            let node = m.nodes[n];
            if node.count > 0 {
                tris.extend_from_slice(&m.order[node.first as usize..(node.first + node.count) as usize]);
            } else {
                todo.extend(node.first as usize..(node.first + node.kids) as usize);
            }
        }
        for &t in &tris {
            for v in m.tri(t as usize).map(|v| pose.apply(v)) {
                for k in 0..3 {
                    let x = v[k].to_f64();
                    assert!(
                        col[LO + k] <= x && x <= col[HI + k],
                        "node {i}: moved vertex {x:e} outside [{:e}, {:e}]",
                        col[LO + k],
                        col[HI + k]
                    );
                    checked += 1;
                }
            }
        }
    }
    checked
}

/// The moved bounds of every node (`crate::algo::nodes::columns`) on every instruction
/// set this CPU runs are the portable code's, bit for bit (they are computed unfused), for
/// groups of children and single nodes alike; and every node's moved axis-aligned box
/// contains every vertex under it as `Pose::apply` moves it in the mesh's precision
/// (exact comparisons: the box's slack must cover the motion's rounding). Random meshes of
/// every tree width, near and far from the origin, f32 and f64, in rotated poses.
#[test]
fn moved_columns_agree_across_instruction_sets_and_contain_the_moved_vertices() {
    use super::*;
    let mut rnd = uniform(0x51_7cc1_b727_220a);
    let mut checked = 0;
    for &(size, offset) in &[(1.0, 0.0), (1e-3, 1e4), (1e3, -1e2)] {
        for w in [2, 3, 4, 8] {
            let (v, t) = soup(&mut rnd, 40, size, offset);
            let axis = [rnd(), rnd(), rnd()];
            let (angle, shift) = (7.0 * rnd(), [0, 1, 2].map(|_| size * rnd()));
            let m64 = Mesh::with_width(v.clone(), t.clone(), w).expect("mesh");
            checked += check_columns(&m64, &Pose::from_axis_angle(axis, angle, shift).unwrap());
            let v32: Vec<[f32; 3]> = v.iter().map(|p| p.map(|x| x as f32)).collect();
            let m32 = Mesh::with_width(v32, t, w).expect("mesh");
            let p32 = Pose::from_axis_angle(axis.map(|x| x as f32), angle, shift.map(|x| x as f32)).unwrap();
            checked += check_columns(&m32, &p32);
        }
    }
    assert!(checked > 10_000, "only {checked} coordinates checked");
}

/// `n` small random triangles (each within 0.15 of a centre in the unit cube), scaled by
/// `size` and moved by `offset` in every coordinate.
fn soup(rnd: &mut impl FnMut() -> f64, n: u32, size: f64, offset: f64) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let (mut v, mut t) = (Vec::new(), Vec::new());
    for k in 0..n {
        let c = [rnd(), rnd(), rnd()];
        for _ in 0..3 {
            v.push([0, 1, 2].map(|i| offset + size * (c[i] + 0.15 * rnd())));
        }
        t.push([3 * k, 3 * k + 1, 3 * k + 2]);
    }
    (v, t)
}

/// Every tree shape builds a tree of its shape over the same triangles: each triangle in
/// exactly one leaf, a leaf of 1 to `leaf` triangles, a node of 2 to `width` children,
/// every node's box holding its children's (or its triangles'), and a smaller leaf size
/// making more nodes.
#[test]
fn trees_have_their_shape() {
    use super::{tri_box, Mesh, TreeShape};
    let mut rnd = uniform(0x9e37_79b9_7f4a_7c15);
    let inside = |outer: ([f64; 3], [f64; 3]), inner: ([f64; 3], [f64; 3])| {
        (0..3).all(|k| outer.0[k] <= inner.0[k] && inner.1[k] <= outer.1[k])
    };
    for n in [1u32, 2, 3, 9, 17, 200] {
        let (v, t) = soup(&mut rnd, n, 10.0, 0.0);
        let mut last = usize::MAX;
        for leaf in [1, 2, 4, 8] {
            for width in [2, 3, 4, 8] {
                let m = Mesh::with_shape(v.clone(), t.clone(), TreeShape { width, leaf }).expect("mesh");
                let mut seen = vec![0u32; n as usize];
                for node in &m.nodes {
                    if node.count > 0 {
                        assert!(node.count as usize <= leaf, "{n} triangles, leaf {leaf}: {}", node.count);
                        for at in node.first..node.first + node.count {
                            let i = m.order[at as usize] as usize;
                            seen[i] += 1;
                            assert!(inside((node.lo, node.hi), tri_box(&m.tri(i))));
                        }
                    } else {
                        assert!((2..=width as u32).contains(&node.kids), "width {width}: {} kids", node.kids);
                        for c in &m.nodes[node.first as usize..(node.first + node.kids) as usize] {
                            assert!(inside((node.lo, node.hi), (c.lo, c.hi)));
                        }
                    }
                }
                assert!(seen.iter().all(|&k| k == 1), "{n} triangles, leaf {leaf}: {seen:?}");
                if width == 2 && n > 8 {
                    // a binary tree: 2 k - 1 nodes for k leaves, fewer leaves for larger ones
                    assert!(m.node_count() < last, "leaf {leaf}: {} nodes, not below {last}", m.node_count());
                    last = m.node_count();
                }
            }
        }
    }
}

/// Uniform numbers in [-0.5, 0.5) from a xorshift generator seeded with `seed`.
fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}

/// The node test (`crate::algo::nodes`) on every instruction set this CPU runs, against
/// the portable one and against the triangles, on small random meshes of different tree
/// widths (so different group strides on the two sides) in rotated poses, near and far
/// from the origin: the lower bounds agree within `4 eps S` (unsquared; FMA rounds
/// differently; measured 0.8 eps S), the prunings at a finite limit agree, and no bound
/// exceeds the squared distance of a triangle pair under the two nodes (the f64 kernels'
/// answer).
#[test]
fn node_tests_agree_across_instruction_sets_and_bound_the_triangles() {
    use super::*;
    let mut rnd = uniform(0x2545_f491_4f6c_dd1d);
    let isas: Vec<crate::Isa> = crate::Isa::ALL.into_iter().filter(|i| i.is_available()).collect();
    let (mut worst, mut checked, mut overlapping) = (0.0f64, 0usize, 0usize);
    for &(size, offset, wa, wb) in &[(1.0, 0.0, 4, 4), (1.0, 0.0, 8, 2), (1e-3, 1e4, 2, 8), (1e-3, 1e4, 4, 3)]
    {
        let mut mesh = |w: usize| {
            let (v, t) = soup(&mut rnd, 48, size, offset);
            Mesh::with_width(v, t, w).expect("mesh")
        };
        let (a, b) = (mesh(wa), mesh(wb));
        let pa = Pose::from_axis_angle([1.0, 2.0, 3.0], 0.7, [0.1 * size, 0.0, 0.0]).unwrap();
        let pb = Pose::from_axis_angle([-2.0, 0.5, 1.0], 2.1, [0.0, 0.2 * size, 0.0]).unwrap();
        let (mut sa, mut sb) = (
            Side::new(&a, &pa, moved(&a, &pa).expect("pose"), crate::Isa::Scalar),
            Side::new(&b, &pb, moved(&b, &pb).expect("pose"), crate::Isa::Scalar),
        );
        let under = |m: &Mesh<f64>, pose: &Pose<f64>, i: u32| {
            let (mut out, mut todo) = (Vec::new(), vec![i]);
            while let Some(n) = todo.pop() {
                let node = m.nodes[n as usize];
                if node.count > 0 {
                    out.extend(
                        m.order[node.first as usize..(node.first + node.count) as usize]
                            .iter()
                            .map(|&t| m.tri(t as usize).map(|v| pose.apply(v))),
                    );
                } else {
                    todo.extend(node.first..node.first + node.kids);
                }
            }
            out
        };
        let scale = 4.0 * (offset + size);
        for p in (0..a.nodes.len() as u32).filter(|&p| a.nodes[p as usize].count == 0) {
            for f in 0..b.nodes.len() as u32 {
                let full = test_gaps(crate::Isa::Scalar, &mut sa, p, &mut sb, f, f64::INFINITY);
                let n = a.nodes[p as usize].kids as usize;
                let first = a.nodes[p as usize].first;
                // a limit between the children's bounds, so that some are pruned
                // (the bounds compared as distances: the overlapping ones as 0)
                let full0 = full.map(|x| x.max(0.0));
                let lim = full0[..n].iter().sum::<f64>() / n as f64;
                // overlapping nodes: minus the overlap of their moved boxes, a fraction
                let fb = sb.aabb(f);
                for j in 0..n {
                    let cb = sa.aabb(first + j as u32);
                    let frac = (0..3)
                        .map(|q| {
                            let sep = (fb.0[q] - cb.1[q]).max(cb.0[q] - fb.1[q]);
                            sep / ((cb.1[q] - cb.0[q]) + (fb.1[q] - fb.0[q])).max(f64::MIN_POSITIVE)
                        })
                        .fold(f64::NEG_INFINITY, f64::max);
                    assert!(
                        full[j] > 0.0 || (full[j] == frac.min(0.0) && full[j] >= -0.5),
                        "child {j} of {p} vs {f}: {:e} vs {frac:e}",
                        full[j]
                    );
                    overlapping += usize::from(full[j] < 0.0);
                }
                let cut = test_gaps(crate::Isa::Scalar, &mut sa, p, &mut sb, f, lim);
                for &isa in &isas {
                    let g = test_gaps(isa, &mut sa, p, &mut sb, f, f64::INFINITY);
                    let h = test_gaps(isa, &mut sa, p, &mut sb, f, lim);
                    for j in 0..n {
                        // (the bounds of overlapping nodes, minus their overlap as a
                        // fraction, are computed unfused: the same on every instruction set)
                        assert!(g[j] >= 0.0 || g[j] == full[j], "{isa} child {j} of {p} vs {f}");
                    }
                    let (g, full) = (g.map(|x| x.max(0.0)), full0);
                    for j in 0..n {
                        let diff = (g[j].sqrt() - full[j].sqrt()).abs() / scale;
                        worst = worst.max(diff);
                        assert!(
                            diff <= 4.0 * f64::EPSILON,
                            "{isa} child {j} of {p} vs {f}: {:e} vs {:e}",
                            g[j],
                            full[j]
                        );
                        let near = (lim.sqrt() - full[j].sqrt()).abs() <= 4.0 * f64::EPSILON * scale;
                        assert!(
                            near || (h[j] <= lim) == (cut[j] <= lim),
                            "{isa} child {j} of {p} vs {f}: pruned differently at {lim:e}"
                        );
                    }
                }
                let tb = under(&b, &pb, f);
                for j in 0..n {
                    for ta in under(&a, &pa, first + j as u32) {
                        for t in &tb {
                            let d: f64 = crate::sqdist_triangle_triangle(&ta, t);
                            checked += 1;
                            assert!(full[j] <= d, "child {j} of {p} vs {f}: bound {:e} > {d:e}", full[j]);
                        }
                    }
                }
            }
        }
    }
    assert!(checked > 50_000, "only {checked} triangle pairs checked");
    assert!(overlapping > 100, "only {overlapping} overlapping node pairs");
    eprintln!("largest difference between instruction sets: {worst:e} S over {checked} triangle pairs ({overlapping} overlapping node pairs)");
}

/// The limit the node test computes a lane per child ([`Limit::Reach`], the contact and
/// intersection searches') is, bit for bit, the scalar [`Limit::at`] of the child's and
/// the other node's moved boxes' [`magnitude`], on every instruction set, for every child of
/// every internal node against every node (near and far from the origin, different tree
/// widths, a margin and per-magnitude term of either size, with and without the relative
/// tolerance's division); lanes past the last child get `-inf`.
#[test]
fn lane_limits_are_the_scalar_limits_of_the_moved_boxes() {
    use super::*;
    let mut rnd = uniform(0x9e37_79b9_7f4a_7c15);
    let isas: Vec<crate::Isa> = crate::Isa::ALL.into_iter().filter(|i| i.is_available()).collect();
    let limits = [
        Limit::Reach { margin: 0.02, per: 72.0 * f64::EPSILON / 2.0, absolute: 0.0, keep: None },
        Limit::Reach { margin: 0.0, per: 1e-3, absolute: 1e-9, keep: Some(0.75) },
    ];
    let mut checked = 0usize;
    for &(size, offset, wa, wb) in &[(1.0, 0.0, 4, 4), (1.0, 0.0, 8, 2), (1e-3, 1e4, 2, 8)] {
        let mut mesh = |w: usize| {
            let (v, t) = soup(&mut rnd, 48, size, offset);
            Mesh::with_width(v, t, w).expect("mesh")
        };
        let (a, b) = (mesh(wa), mesh(wb));
        let pa = Pose::from_axis_angle([1.0, 2.0, 3.0], 0.7, [0.1 * size, 0.0, -offset]).unwrap();
        let pb = Pose::from_axis_angle([-2.0, 0.5, 1.0], 2.1, [0.0, 0.2 * size, 0.0]).unwrap();
        let (mut sa, mut sb) = (
            Side::new(&a, &pa, moved(&a, &pa).expect("pose"), crate::Isa::Scalar),
            Side::new(&b, &pb, moved(&b, &pb).expect("pose"), crate::Isa::Scalar),
        );
        for p in (0..a.nodes.len() as u32).filter(|&p| a.nodes[p as usize].count == 0) {
            let (n, first) = (a.nodes[p as usize].kids as usize, a.nodes[p as usize].first);
            for f in 0..b.nodes.len() as u32 {
                for &isa in &isas {
                    for limit in limits {
                        let (at, fixed_at) = (sa.group(p), sb.bounds_at(f));
                        let g = node_test(isa, (&sa, at, n), (&sb, fixed_at), limit);
                        let fb = sb.aabb(f);
                        for j in 0..MAX_WIDTH {
                            let want = if j < n {
                                limit.at(|| magnitude(&sa.aabb(first + j as u32), &fb))
                            } else {
                                f64::NEG_INFINITY
                            };
                            assert_eq!(g.lim[j].to_bits(), want.to_bits(), "{isa} child {j} of {p} vs {f}");
                            checked += 1;
                        }
                    }
                }
            }
        }
    }
    assert!(checked > 10_000, "only {checked} limits checked");
}

/// Two triangles for each of `rows x cols` quads, whose corner `(i, j)` is vertex `at(i, j)`.
fn quads(rows: u32, cols: u32, at: impl Fn(u32, u32) -> u32 + Copy) -> Vec<[u32; 3]> {
    (0..rows)
        .flat_map(|i| {
            (0..cols).flat_map(move |j| {
                [[at(i, j), at(i + 1, j), at(i, j + 1)], [at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]]
            })
        })
        .collect()
}

/// A grid of `n x n` squares (two triangles each) of side `h` in the plane x = 0.
fn wall(n: u32, h: f32) -> super::Mesh<f32> {
    let v = (0..=n).flat_map(|i| (0..=n).map(move |j| [0.0, i as f32 * h, j as f32 * h])).collect();
    super::Mesh::new(v, quads(n, n, |i, j| i * (n + 1) + j)).expect("mesh")
}

/// The kernels' squared distance of every pair of moved triangles, `i * b.len() + j`.
fn brute_force<T: crate::Real>(
    e: &crate::Engine,
    (a, pa): (&super::Mesh<T>, &crate::Pose<T>),
    (b, pb): (&super::Mesh<T>, &crate::Pose<T>),
) -> Vec<T> {
    let tb: Vec<_> = (0..b.len()).map(|j| b.tri(j).map(|v| pb.apply(v))).collect();
    let (mut xa, mut xb) = (Vec::new(), Vec::new());
    for i in 0..a.len() {
        let x = a.tri(i).map(|v| pa.apply(v));
        for y in &tb {
            xa.push(x);
            xb.push(*y);
        }
    }
    let mut d = vec![T::ZERO; xa.len()];
    e.sqdist_triangle_triangle(&xa, &xb, &mut d).expect("brute force");
    d
}

/// Two walls facing each other 1e8 apart in f32 (`u S` = 6, the walls 100 across): every
/// pair's distance ties within rounding. The distance search answers a few batches, not
/// every pair as it did with no slack (asserted too, as the cliff this guards against),
/// and its answer is at most the slack above the smallest of the kernels' answers over
/// all pairs, found by brute force.
#[test]
fn far_meshes_whose_pairs_tie_within_rounding_are_not_searched_pair_by_pair() {
    use super::*;
    let (a, b) = (wall(20, 5.0), wall(20, 5.0));
    let (pa, pb) = (Pose::identity(), Pose::translation([1e8f32, 0.0, 0.0]));
    let e = Engine::auto();
    let all = a.len() * b.len();
    let run = |tol: crate::Tolerance| {
        let mut s = Nearest::<f32>::new(tol);
        search(&e, &a, &pa, &b, &pb, &mut s).expect("search");
        (s.best.expect("an answer"), s.answered, s.slack)
    };
    let (exact, every, none) = run(crate::Tolerance::EXACT);
    assert_eq!(none, 0.0);
    assert!(every > all / 2, "with no slack {every} of {all} pairs answered");
    let (best, answered, slack) = run(e.current_tolerance());
    assert!(answered < all / 100, "{answered} of {all} pairs answered");
    // the slack is 4 u S: S = 1e8 + the walls' width (100), u = 2^-24
    let want = 4.0 * (1e8 + 100.0) / 16_777_216.0;
    assert!((slack - want).abs() < 1e-6 * want, "slack {slack}, not {want}");
    // brute force over every pair of moved triangles
    let d = brute_force(&e, (&a, &pa), (&b, &pb));
    let min = d.iter().fold(f64::INFINITY, |m, &x| m.min(x as f64));
    for m in [&best, &exact] {
        let got = m.sqdist as f64;
        assert_eq!(got, d[m.tri_a * b.len() + m.tri_b] as f64, "not its pair's answer");
        assert!(got >= min && got.sqrt() <= min.sqrt() + slack, "{got} against {min}, slack {slack}");
    }
    assert_eq!(exact.sqdist as f64, min, "no slack: the smallest answer");
}

/// A capped contact query answers the first `cap` contacts of the uncapped one, on one
/// thread and two, with ties in distance (two parallel walls: many pairs at the same
/// distance) ordered by triangle numbers; and its search holds about `2 cap` contacts,
/// not every one in reach.
#[test]
fn capped_contacts_are_the_first_of_all_and_held_in_bounded_memory() {
    use super::*;
    let (a, b) = (wall(16, 1.0), wall(16, 1.0));
    let (pa, pb) = (Pose::identity(), Pose::translation([0.5f32, 0.0, 0.0]));
    let margin = 3.0f32;
    for threads in [1, 2] {
        let e = Engine::auto().threads(threads);
        let all = e.mesh_contacts(&a, &pa, &b, &pb, margin, None).expect("contacts");
        assert!(all.len() > 20_000, "{} contacts", all.len());
        for cap in [0, 1, 7, 100, 1000, all.len(), all.len() + 5] {
            let got = e.mesh_contacts(&a, &pa, &b, &pb, margin, Some(cap)).expect("capped");
            assert_eq!(got[..], all[..cap.min(all.len())], "cap {cap} on {threads} threads");
        }
    }
    // one thread's search state: the contacts held at the end
    let e = Engine::auto().margin(margin as f64);
    let held = |cap: Option<usize>| {
        let mut s = Contacts::<f32>::new(margin as f64, e.current_tolerance(), cap);
        search(&e, &a, &pa, &b, &pb, &mut s).expect("search");
        s.found.len()
    };
    let (cap, batch) = (50, FLUSH + TreeShape::DEFAULT.leaf * TreeShape::DEFAULT.leaf);
    let (capped, uncapped) = (held(Some(cap)), held(None));
    assert!(capped < 2 * cap + batch, "{capped} contacts held for a cap of {cap}");
    assert!(uncapped > 100 * capped, "{uncapped} against {capped}");
}

/// The clearance check stops at its first hit: two parallel walls 0.5 apart, every one of
/// their pairs within a margin of 3, are found within it by the first leaf pair's
/// triangle pairs, where the contact query answers more than 20,000; the pair it names is
/// a contact; below the walls' distance there is none.
#[test]
fn the_clearance_check_stops_at_its_first_hit() {
    use super::*;
    let (a, b) = (wall(16, 1.0), wall(16, 1.0));
    let (pa, pb) = (Pose::identity(), Pose::translation([0.5f32, 0.0, 0.0]));
    let e = Engine::auto();
    let run = |margin: f32| {
        let mut s = FirstHit::<f32>::new(e.current_tolerance(), Some(margin as f64));
        search(&e, &a, &pa, &b, &pb, &mut s).expect("search");
        (s.hit, s.answered)
    };
    let (hit, answered) = run(3.0);
    let (i, j) = hit.expect("within 3");
    assert!(answered <= TreeShape::DEFAULT.leaf * TreeShape::DEFAULT.leaf, "{answered} pairs answered");
    let all = e.mesh_contacts(&a, &pa, &b, &pb, 3.0, None).expect("contacts");
    assert!(all.len() > 20_000, "{} contacts", all.len());
    assert!(all.iter().any(|c| (c.tri_a, c.tri_b) == (i, j)), "({i}, {j}) is not a contact");
    assert_eq!(e.mesh_within_margin(&a, &pa, &b, &pb, 3.0).expect("within"), Some((i, j)));
    assert_eq!(run(0.49).0, None);
    assert_eq!(e.mesh_within_margin(&a, &pa, &b, &pb, 0.49).expect("within"), None);
}

/// A UV sphere of radius `r` centred at the origin: `m` rings of `2 m` quads (two triangles
/// each, the poles' fans degenerate).
fn sphere<T: crate::Real>(m: u32, r: f64) -> super::Mesh<T> {
    let k = 2 * m;
    let mut v = Vec::new();
    for i in 0..=m {
        let th = core::f64::consts::PI * i as f64 / m as f64;
        for j in 0..k {
            let ph = core::f64::consts::TAU * j as f64 / k as f64;
            v.push([r * th.sin() * ph.cos(), r * th.sin() * ph.sin(), r * th.cos()].map(T::from_f64));
        }
    }
    super::Mesh::new(v, quads(m, k, |i, j| i * k + j % k)).expect("mesh")
}

/// Two interpenetrating spheres of 5,000 triangles 1e6 from the origin in f32: the
/// intersection search's limit, the tolerance's width (72 `u S`, 4.3), exceeds the spheres
/// (radius 1), so no node pair apart is pruned. Overlapping pairs first, the search answers
/// under 0.6 % of the pairs before its hit (5,332 measured); plain depth first, as before,
/// walked every apart pair of a subtree before the next overlapping one (732,506 measured;
/// asserted too, as the cliff this guards against: one call of `tridist mesh` took 54-70 ms
/// for the Armadillo and fandisk interpenetrating at 1e6, 1.7-1.8 s at 1e9, against
/// 1.4-2.2 ms and 0.05-0.13 ms now). Both hits are pairs the kernels call intersecting.
#[test]
fn far_intersecting_meshes_are_searched_overlapping_pairs_first() {
    use super::*;
    let e = Engine::auto();
    let (a, b) = (sphere::<f32>(50, 1.0), sphere::<f32>(50, 1.0));
    let pa = Pose::translation([1e6f32, 0.0, 0.0]);
    let pb = Pose::from_axis_angle([1.0f32, 2.0, 3.0], 0.5, [1e6, 0.0, 0.5]).unwrap();
    let all = a.len() * b.len();
    let run = |overlap_first: bool| {
        let mut s = FirstHit::<f32>::new(e.current_tolerance(), None);
        s.overlap_first = overlap_first;
        search(&e, &a, &pa, &b, &pb, &mut s).expect("search");
        let (i, j) = s.hit.expect("a hit");
        let mut v = [Intersection::Invalid];
        e.intersect_triangle_triangle(
            &[a.tri(i).map(|v| pa.apply(v))][..],
            &[b.tri(j).map(|v| pb.apply(v))][..],
            &mut v,
        )
        .unwrap();
        assert_eq!(v[0], Intersection::Intersecting, "pair {i} {j}");
        s.answered
    };
    let (first, plain) = (run(true), run(false));
    assert!(first < all * 6 / 1000, "{first} of {all} pairs answered");
    assert!(plain > 20 * first, "plain depth first: {plain} pairs, overlapping first: {first}");
    assert!(e.mesh_intersect(&a, &pa, &b, &pb).unwrap().is_some());
}

/// Two f64 spheres of 1,600 triangles, radius 5, 1e16 apart (`u S` = 1.1): the pruning
/// tests' own rounding exceeds the slack of 4 `u S`, so without widening the search
/// answered 1,694,924 of the 2,560,000 pairs (measured; asserted, as the cliff this guards
/// against). Widened after [`Engine::MESH_DISTANCE_WIDEN_AFTER`] pairs it answers 65,553, and its
/// answer is its pair's kernel answer within the tolerance's width of the smallest kernel
/// answer over all pairs (brute force).
#[test]
fn far_apart_f64_meshes_widen_the_slack_after_many_pairs() {
    use super::*;
    let e = Engine::auto();
    let (a, b) = (sphere::<f64>(20, 5.0), sphere::<f64>(20, 5.0));
    let pa = Pose::identity();
    let pb = Pose::from_axis_angle([1.0, 2.0, 3.0], 0.5, [1e16, 0.0, 0.0]).unwrap();
    let all = a.len() * b.len();
    let run = |widen_after: usize| {
        let mut s = Nearest::<f64>::new(e.current_tolerance());
        s.widen_after = widen_after;
        search(&e, &a, &pa, &b, &pb, &mut s).expect("search");
        (s.best.expect("an answer"), s.answered, s.wide)
    };
    let (_, never, _) = run(usize::MAX);
    assert!(never > all / 2, "never widened: {never} of {all} pairs answered");
    let (best, answered, wide) = run(Engine::MESH_DISTANCE_WIDEN_AFTER.max(a.len() + b.len()));
    assert!(answered < 2 * Engine::MESH_DISTANCE_WIDEN_AFTER, "{answered} of {all} pairs answered");
    // the width is 64 u S: S = 1e16 + the sphere's radius and rounding
    let want = 64.0 * 1e16 * f64::EPSILON / 2.0;
    assert!(wide >= want && wide < want * (1.0 + 1e-9), "width {wide}, not {want}");
    assert_eq!(e.mesh_distance(&a, &pa, &b, &pb).unwrap().map(|d| d.sqdist), Some(best.sqdist));
    let d = brute_force(&e, (&a, &pa), (&b, &pb));
    let min = d.iter().fold(f64::INFINITY, |m, &x| m.min(x));
    assert_eq!(best.sqdist, d[best.tri_a * b.len() + best.tri_b], "not its pair's answer");
    assert!(best.sqdist >= min && best.sqdist.sqrt() <= min.sqrt() + wide, "{} against {min}", best.sqdist);
}

/// Meshes so far apart that squared distances overflow (the kernels' documented `+inf`):
/// every search still prunes, instead of answering every pair because `+inf` pruned
/// nothing (the Armadillo against fandisk ran for minutes: `tridist mesh ... --pose-b
/// 1e155,0,0`, and `1e200,0,0` in the intersection query). f32 spheres 1e20 apart: the
/// distance and the closest point are `+inf`, still for the closest pair (its points'
/// squared distance in f64 within the slack of the smallest over all pairs, brute
/// force) and point; f64 spheres 1e155 and 1e200 apart (squared gaps overflow f64 too):
/// `+inf` after a batch or two; at 1e200 the intersection query's reach (72 `u S`,
/// 2.4e186) squared overflows as well, and it answers no pair either. Measured: 9 pairs
/// answered by each distance query, 0 by the intersection queries. Broken on purpose, each
/// caught: `prune_beyond` made the identity, the f64 distance at 1e155 answered all
/// 160,000 pairs; `square_cap` always `+inf`, the intersection at 1e200 all 160,000;
/// `rank` the squared distance alone, the f32 distance all 160,000.
#[test]
fn searches_prune_where_squared_distances_overflow() {
    use super::*;
    let e = Engine::auto();
    // f32: the closest pair and point, ranked by their points in f64
    let (a, b) = (sphere::<f32>(10, 1.0), sphere::<f32>(10, 1.0));
    let all = a.len() * b.len();
    let (pa, pb) =
        (Pose::identity(), Pose::from_axis_angle([1.0f32, 2.0, 3.0], 0.5, [1e20, 3e19, 0.0]).unwrap());
    let mut s = Nearest::<f32>::new(e.current_tolerance());
    search(&e, &a, &pa, &b, &pb, &mut s).expect("search");
    let best = s.best.expect("an answer");
    assert_eq!(best.sqdist, f32::INFINITY);
    assert!(s.answered < all / 100, "{} of {all} pairs answered", s.answered);
    let (ta, tb): (Vec<_>, Vec<_>) = (0..a.len())
        .flat_map(|i| (0..b.len()).map(move |j| (i, j)))
        .map(|(i, j)| (a.tri(i).map(|v| pa.apply(v)), b.tri(j).map(|v| pb.apply(v))))
        .unzip();
    let mut cp = vec![ClosestPoints::default(); all];
    e.closest_points_triangle_triangle(&ta, &tb, &mut cp).expect("brute force");
    assert!(cp.iter().all(|c| c.sqdist == f32::INFINITY));
    let min = cp.iter().map(rank).fold(f64::INFINITY, f64::min);
    let got = rank(&cp[best.tri_a * b.len() + best.tri_b]);
    assert!(got.sqrt() <= min.sqrt() + s.slack, "{got} against {min}, slack {}", s.slack);
    let x = [-1e20f32, 0.0, 0.0];
    let near = e.mesh_closest_point(&b, &pb, x).expect("closest point").expect("a point");
    assert_eq!(near.sqdist, f32::INFINITY);
    let far = |t: &Triangle<f32>| {
        let mut c = [ClosestPoints::default()];
        e.closest_point_point_triangle(&[x], &[*t][..], &mut c).expect("point");
        rank(&c[0])
    };
    let min = tb[..b.len()].iter().map(far).fold(f64::INFINITY, f64::min);
    let got = far(&tb[near.tri]);
    assert!(got.sqrt() <= min.sqrt() * (1.0 + 1e-6), "{got} against {min}");
    // f64: squared gaps overflow too
    let (a, b) = (sphere::<f64>(10, 1.0), sphere::<f64>(10, 1.0));
    for dx in [1e155, 1e200] {
        let pb = Pose::from_axis_angle([1.0, 2.0, 3.0], 0.5, [dx, 0.3 * dx, 0.0]).unwrap();
        let mut s = Nearest::<f64>::new(e.current_tolerance());
        search(&e, &a, &Pose::identity(), &b, &pb, &mut s).expect("search");
        assert_eq!(s.best.expect("an answer").sqdist, f64::INFINITY);
        assert!(s.answered < all / 100, "{dx:e}: {} of {all} pairs answered", s.answered);
        let mut h = FirstHit::<f64>::new(e.current_tolerance(), None);
        search(&e, &a, &Pose::identity(), &b, &pb, &mut h).expect("intersection");
        assert_eq!(h.hit, None);
        assert!(h.answered < all / 100, "{dx:e}: intersection: {} of {all} pairs answered", h.answered);
        let near = e.mesh_closest_point(&b, &pb, [-dx, 0.0, 0.0]).expect("closest point");
        assert_eq!(near.map(|m| m.sqdist), Some(f64::INFINITY));
    }
}

/// The README states the mesh distance's constants as the code has them.
#[test]
fn the_readme_states_the_distance_search_constants() {
    use crate::Engine;
    let readme = include_str!("../../../README.md").split_whitespace().collect::<Vec<_>>().join(" ");
    let group = |n: usize| {
        let s = n.to_string();
        let mut out = String::new();
        for (i, c) in s.chars().enumerate() {
            if i > 0 && (s.len() - i).is_multiple_of(3) {
                out.push(',');
            }
            out.push(c);
        }
        out
    };
    for want in [
        format!("`Engine::MESH_DISTANCE_SLACK` ({}) `u S`", Engine::MESH_DISTANCE_SLACK),
        format!("`Engine::MESH_DISTANCE_WIDEN_AFTER` ({}) pairs", group(Engine::MESH_DISTANCE_WIDEN_AFTER)),
    ] {
        assert!(readme.contains(&want), "the README does not say {want:?}");
    }
}

/// The correctly rounded mesh distance's last step: the smallest decided distance among the
/// candidates that reach the minimum's pair, unless an undecided one may round to it or below.
#[test]
fn the_rounded_minimum_distance_waits_for_undecided_candidates() {
    use super::queries::{reaching, rounded_min_distance};
    use crate::Interval;
    let iv = |lo: f32, hi: f32| Interval { lo, hi };
    // the candidates reaching the decided pair 1 ([2, 2]): those starting at or below 2
    let ivs = [iv(0.9, 1.1), iv(2.0, 2.0), iv(2.0000002, 3.0), iv(2.5, 3.0)];
    assert_eq!(reaching(&ivs, 1), vec![0, 1]);
    assert_eq!(reaching(&ivs, 0), vec![0]);
    // an undecided candidate below the smallest decided one: undecided
    assert_eq!(rounded_min_distance(&[1.0f32, 2.0], &[false, true], &ivs[..2]), None);
    // an undecided candidate within rounding of it: undecided (it may round to 2 or below)
    assert_eq!(rounded_min_distance(&[2.0f32, 2.0], &[true, false], &[iv(2.0, 2.0), ivs[2]]), None);
    // an undecided candidate beyond it: the smallest decided one
    assert_eq!(rounded_min_distance(&[2.0f32, 3.0], &[true, false], &[iv(2.0, 2.0), ivs[3]]), Some(2.0));
    assert_eq!(rounded_min_distance(&[1.0f32, 2.0], &[true, true], &ivs[..2]), Some(1.0));
    // nothing decided: undecided
    assert_eq!(rounded_min_distance::<f32>(&[1.0], &[false], &ivs[..1]), None);
}
