//! Named input families: seeded generators of triangle pairs (and, derived from them, segment
//! pairs and point-triangle pairs), one per kind of input that breaks distance kernels.
//!
//! Constructions that must be exact (touching, shared features, coplanar, parallel, near misses)
//! use only axis-aligned planes, coordinates with few significant bits, axis permutations, sign
//! flips and ulp steps, so they stay exact in f32 as well as f64. Every case records the family
//! and seed it came from.

use std::sync::OnceLock;

use tridist::Triangle;

use crate::float::Float;

use crate::mesh::Mesh;
use crate::rng::Rng;

/// An input family.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Family {
    /// Random triangles in the unit cube.
    Random,
    /// Unit-size triangles translated 1e3 .. 1e7 from the origin.
    Far,
    /// Whole pair scaled by 1e-30 .. 1e20 (past the f32 overflow of squares near 1.8e19).
    Scale,
    /// All coordinates subnormal.
    Subnormal,
    /// Point-like, segment-like, repeated vertex, slivers of aspect 1e4 .. 1e7.
    Degenerate,
    /// Parallel faces with overlapping projections, parallel closest edges, coplanar disjoint.
    Parallel,
    /// Closest edges at 1e-3 .. 1e-7 rad.
    NearParallel,
    /// Piercing and coplanar overlap.
    Intersecting,
    /// Vertex-face, edge-edge crossing, shared vertex, shared edge.
    Touching,
    /// Touching configurations moved a few ulps apart (or into each other).
    NearMiss,
    /// Triangles sharing a vertex in the Armadillo mesh.
    Mesh,
}

impl Family {
    /// Every family.
    pub const ALL: [Family; 11] = [
        Family::Random,
        Family::Far,
        Family::Scale,
        Family::Subnormal,
        Family::Degenerate,
        Family::Parallel,
        Family::NearParallel,
        Family::Intersecting,
        Family::Touching,
        Family::NearMiss,
        Family::Mesh,
    ];

    /// Short name (CLI, reports, failure messages).
    pub fn name(self) -> &'static str {
        match self {
            Family::Random => "random",
            Family::Far => "far",
            Family::Scale => "scale",
            Family::Subnormal => "subnormal",
            Family::Degenerate => "degenerate",
            Family::Parallel => "parallel",
            Family::NearParallel => "near_parallel",
            Family::Intersecting => "intersecting",
            Family::Touching => "touching",
            Family::NearMiss => "near_miss",
            Family::Mesh => "mesh",
        }
    }

    /// One line on what the family stresses (`tridist cases --list`).
    pub fn about(self) -> &'static str {
        match self {
            Family::Random => "random triangles in the unit cube: the generic case",
            Family::Far => "unit-size triangles translated 1e3 .. 1e7 from the origin: cancellation",
            Family::Scale => "the whole pair scaled by 1e-30 .. 1e20: underflow and overflow of squares",
            Family::Subnormal => "every coordinate subnormal: gradual underflow",
            Family::Degenerate => "point-like, segment-like, repeated vertex, slivers of aspect 1e4 .. 1e7",
            Family::Parallel => {
                "parallel faces, parallel closest edges, coplanar disjoint: ties and zero divisors"
            }
            Family::NearParallel => "closest edges at 1e-3 .. 1e-7 rad: ill-conditioned edge-edge solves",
            Family::Intersecting => "piercing and coplanar overlap: exact distance 0",
            Family::Touching => {
                "vertex-face, edge-edge crossing, shared vertex or edge: distance 0 on the boundary"
            }
            Family::NearMiss => {
                "touching configurations a few ulps apart or into each other: contact decisions"
            }
            Family::Mesh => "triangles sharing a vertex in the Armadillo mesh: what mesh queries ask",
        }
    }

    /// Parses [`Family::name`].
    pub fn parse(s: &str) -> Option<Family> {
        Family::ALL.into_iter().find(|f| f.name() == s)
    }
}

/// One generated triangle pair.
#[derive(Clone, Debug, PartialEq)]
pub struct Case<T> {
    /// `family/seed/index/variant-of-construction`, reproducible.
    pub label: String,
    /// First triangle.
    pub a: Triangle<T>,
    /// Second triangle.
    pub b: Triangle<T>,
}

impl<T: Float> Case<T> {
    /// Whether every coordinate is finite (the oracle judges finite input only).
    pub fn is_finite(&self) -> bool {
        self.a.iter().chain(self.b.iter()).flatten().all(|x| x.is_finite())
    }
}

type P = [f64; 3];
type Tri = [P; 3];

fn conv<T: Float>(t: &Tri) -> Triangle<T> {
    t.map(|p| p.map(T::from_f64))
}

/// Steps `x` by `k` ulps (toward +inf for k > 0) in precision T.
pub fn ulp_step<T: Float>(x: T, k: i32) -> T {
    let mut v = x;
    for _ in 0..k.unsigned_abs() {
        let up = k > 0;
        let b = v.to_bits_u64();
        v = if v == T::ZERO {
            let tiny = T::from_bits_u64(1);
            if up {
                tiny
            } else {
                -tiny
            }
        } else if (v > T::ZERO) == up {
            T::from_bits_u64(b + 1)
        } else {
            T::from_bits_u64(b - 1)
        };
    }
    v
}

fn rot(r: &mut Rng) -> [[f64; 3]; 3] {
    // a random rotation from two random directions (Gram-Schmidt)
    let a = r.dir();
    let mut b = r.dir();
    let d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    for k in 0..3 {
        b[k] -= d * a[k];
    }
    let n = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt().max(1e-12);
    b = b.map(|x| x / n);
    let c = [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
    [a, b, c]
}

fn apply(m: &[[f64; 3]; 3], p: P) -> P {
    [0, 1, 2].map(|i| m[0][i] * p[0] + m[1][i] * p[1] + m[2][i] * p[2])
}

fn rand_tri(r: &mut Rng, lo: f64, hi: f64) -> Tri {
    [0; 3].map(|_| [r.range(lo, hi), r.range(lo, hi), r.range(lo, hi)])
}

/// A dyadic value with at most 10 significant bits in [-1, 1): exact in f32.
fn dy(r: &mut Rng) -> f64 {
    (r.below(2048) as f64 - 1024.0) / 1024.0
}

/// Exact symmetries: permute axes and flip signs (keeps every coordinate exact).
fn symm(r: &mut Rng, a: &mut Tri, b: &mut Tri) {
    let perms = [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]];
    let p = perms[r.below(6)];
    let s = [0; 3].map(|_| if r.below(2) == 0 { 1.0 } else { -1.0 });
    for t in [a, b] {
        for v in t.iter_mut() {
            *v = [0, 1, 2].map(|i| v[p[i]] * s[i]);
        }
    }
}

/// The exactly touching constructions (also the starting point of the near misses). Returns
/// the pair and the name of the construction.
fn touching(r: &mut Rng) -> (Tri, Tri, &'static str) {
    let c = dy(r) * 0.5;
    match r.below(4) {
        0 => {
            // vertex of b on the interior of a (a in plane z = c), b above.
            let a = [[-0.5, -0.5, c], [0.5, -0.5, c], [-0.5, 0.5, c]];
            let v = [dy(r) * 0.2 - 0.2, dy(r) * 0.2 - 0.2, c];
            let b =
                [v, [v[0] + 0.5, v[1] + dy(r) * 0.3, c + 0.5], [v[0] + dy(r) * 0.3, v[1] + 0.5, c + 0.25]];
            (a, b, "vertex_face")
        }
        1 => {
            // a's edge along x at y = yy, b's edge along y at x = xx, both in z = c; a below, b above.
            let (xx, yy) = (dy(r) * 0.25, dy(r) * 0.25);
            let a = [[-0.5, yy, c], [0.5, yy, c], [dy(r) * 0.5, yy + dy(r) * 0.5, c - 0.5]];
            let b = [[xx, -0.5, c], [xx, 0.5, c], [xx + dy(r) * 0.5, dy(r) * 0.5, c + 0.5]];
            (a, b, "edge_edge")
        }
        2 => {
            // shared vertex, otherwise apart
            let v = [dy(r), dy(r), c];
            let a = [v, [v[0] + 0.5, v[1] + 0.125, c - 0.5], [v[0] + 0.25, v[1] - 0.5, c - 0.25]];
            let b = [v, [v[0] - 0.5, v[1] + 0.25, c + 0.5], [v[0] - 0.125, v[1] - 0.5, c + 0.75]];
            (a, b, "shared_vertex")
        }
        _ => {
            // shared edge (neighbouring mesh triangles), random dihedral
            let p = [dy(r), dy(r), c];
            let q = [p[0] + 0.5, p[1] + dy(r) * 0.25, c];
            let a = [p, q, [p[0] + dy(r) * 0.5, p[1] + 0.5, c + dy(r) * 0.5]];
            let b = [q, p, [p[0] + dy(r) * 0.5, p[1] - 0.5, c + dy(r) * 0.5]];
            (a, b, "shared_edge")
        }
    }
}

fn armadillo() -> &'static Mesh {
    static M: OnceLock<Mesh> = OnceLock::new();
    M.get_or_init(|| {
        crate::mesh::carried("armadillo.off").expect("data/meshes/armadillo.off is part of the repository")
    })
}

fn armadillo_pairs() -> &'static Vec<(usize, usize)> {
    static P: OnceLock<Vec<(usize, usize)>> = OnceLock::new();
    P.get_or_init(|| armadillo().neighbour_pairs())
}

/// Generates `n` cases of `family` in precision `T` from `seed`.
pub fn generate<T: Float>(family: Family, seed: u64, n: usize) -> Vec<Case<T>> {
    let mut r = Rng::new(seed ^ (family as u64).wrapping_mul(0x100_0000_01B3));
    (0..n)
        .map(|i| {
            let (a, b, how) = gen_one::<T>(family, &mut r);
            Case { label: format!("{}/{seed}/{i}/{how}", family.name()), a, b }
        })
        .collect()
}

fn gen_one<T: Float>(family: Family, r: &mut Rng) -> (Triangle<T>, Triangle<T>, &'static str) {
    let f32_prec = T::NAME == "f32";
    let (a, b, how): (Tri, Tri, &str) = match family {
        Family::Random => (rand_tri(r, 0.0, 1.0), rand_tri(r, 0.0, 1.0), "unit_cube"),
        Family::Far => {
            let d = r.dir();
            let off = r.log_range(1e3, 1e7);
            let o = d.map(|x| x * off);
            let sh = |t: Tri| t.map(|p| [p[0] + o[0], p[1] + o[1], p[2] + o[2]]);
            (sh(rand_tri(r, 0.0, 1.0)), sh(rand_tri(r, 0.0, 1.0)), "offset")
        }
        Family::Scale => {
            let k = r.range(-30.0, 20.0);
            let s = 10f64.powf(k);
            let (a, b) = (rand_tri(r, -1.0, 1.0), rand_tri(r, -1.0, 1.0));
            let sc = |t: Tri| t.map(|p| p.map(|x| x * s));
            (sc(a), sc(b), "scaled")
        }
        Family::Subnormal => {
            let s = if f32_prec { f32::MIN_POSITIVE as f64 / 8.0 } else { f64::MIN_POSITIVE / 8.0 };
            let (a, b) = (rand_tri(r, -1.0, 1.0), rand_tri(r, -1.0, 1.0));
            let sc = |t: Tri| t.map(|p| p.map(|x| x * s));
            (sc(a), sc(b), "subnormal")
        }
        Family::Degenerate => {
            let other = rand_tri(r, -1.0, 1.0);
            let p = [r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0)];
            let q = [r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0)];
            match r.below(5) {
                0 => ([p; 3], other, "point_like"),
                1 => {
                    let m = [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0, (p[2] + q[2]) / 2.0];
                    ([p, q, m], other, "segment_like")
                }
                2 => ([p, q, p], other, "repeated_vertex"),
                3 => ([p; 3], [q, q, [q[0] + 0.5, q[1], q[2]]], "point_vs_segment"),
                _ => {
                    let aspect = r.log_range(1e4, 1e7);
                    let m = rot(r);
                    let len = r.range(0.5, 2.0);
                    let t = r.range(0.1, 0.9);
                    let sl = [[0.0, 0.0, 0.0], [len, 0.0, 0.0], [len * t, len / aspect, 0.0]]
                        .map(|v| apply(&m, v));
                    let sl = sl.map(|v| [v[0] + p[0], v[1] + p[1], v[2] + p[2]]);
                    // the other triangle near the sliver: within about its length
                    let near = rand_tri(r, -1.0, 1.0)
                        .map(|v| [v[0] * 0.5 + p[0], v[1] * 0.5 + p[1], v[2] * 0.5 + p[2]]);
                    (sl, near, "sliver")
                }
            }
        }
        Family::Parallel => {
            let h = dy(r) * 0.5;
            let mut pair = match r.below(3) {
                0 => {
                    let a = [[dy(r), dy(r), 0.0], [dy(r), dy(r), 0.0], [dy(r), dy(r), 0.0]];
                    let b = [[dy(r), dy(r), h], [dy(r), dy(r), h], [dy(r), dy(r), h]];
                    (a, b, "parallel_faces")
                }
                1 => {
                    // parallel edges along x at different y, z; faces tilted away from each other
                    let (y0, z0) = (dy(r), dy(r));
                    let a = [[-0.5, 0.0, 0.0], [0.5, 0.0, 0.0], [dy(r), -0.5, -0.5]];
                    let b = [
                        [dy(r) * 0.5, y0 + 0.125 * y0.signum(), z0],
                        [dy(r) * 0.5 + 0.75, y0 + 0.125 * y0.signum(), z0],
                        [dy(r), y0 + 0.5 * y0.signum(), z0 + 0.5],
                    ];
                    (a, b, "parallel_edges")
                }
                _ => {
                    let a = [[0.0, 0.0, h], [0.5, 0.0, h], [0.0, 0.5, h]];
                    let dx = 0.5 + (r.below(64) as f64 + 1.0) / 128.0;
                    let b = [[dx, 0.0, h], [dx + 0.5, 0.25, h], [dx + 0.25, 0.5, h]];
                    (a, b, "coplanar_disjoint")
                }
            };
            symm(r, &mut pair.0, &mut pair.1);
            pair
        }
        Family::NearParallel => {
            let theta = r.log_range(1e-7, 1e-3);
            let gap = if r.below(4) == 0 { 0.0 } else { r.range(0.0, 0.1) };
            let m = rot(r);
            let s0 = r.range(-0.3, 0.3);
            let a = [[-0.5, 0.0, 0.0], [0.5, 0.0, 0.0], [0.0, -0.5, -0.5]];
            let (c, s) = (theta.cos(), theta.sin());
            let b = [[s0 - 0.5 * c, -0.5 * s, gap], [s0 + 0.5 * c, 0.5 * s, gap], [s0, 0.5, gap + 0.5]];
            (a.map(|v| apply(&m, v)), b.map(|v| apply(&m, v)), "near_parallel_edges")
        }
        Family::Intersecting => {
            if r.below(2) == 0 {
                let a = rand_tri(r, -1.0, 1.0);
                // a segment through a point of a's interior, then a third vertex
                let (u, v) = (r.range(0.1, 0.45), r.range(0.1, 0.45));
                let x = [0, 1, 2].map(|k| a[0][k] + u * (a[1][k] - a[0][k]) + v * (a[2][k] - a[0][k]));
                let d = r.dir();
                let b = [
                    [x[0] + d[0], x[1] + d[1], x[2] + d[2]],
                    [x[0] - d[0], x[1] - d[1], x[2] - d[2]],
                    [x[0] + r.range(-1.0, 1.0), x[1] + r.range(-1.0, 1.0), x[2] + r.range(-1.0, 1.0)],
                ];
                (a, b, "piercing")
            } else {
                let z = dy(r);
                let mut a = [[0.0, 0.0, z], [0.5, 0.0, z], [0.0, 0.5, z]];
                let mut b = [[0.125, 0.125, z], [dy(r), dy(r), z], [dy(r), dy(r), z]];
                symm(r, &mut a, &mut b);
                (a, b, "coplanar_overlap")
            }
        }
        Family::Touching => {
            let (mut a, mut b, how) = touching(r);
            symm(r, &mut a, &mut b);
            (a, b, how)
        }
        Family::NearMiss => {
            // Build in T directly: move b's on-plane vertices k ulps along z (before symmetry).
            let (a, b, how) = touching(r);
            let c = a[0][2];
            let k = [1, 2, 4, -1, -2, -4][r.below(6)];
            let mut ta: Triangle<T> = conv(&a);
            let mut tb: Triangle<T> = conv(&b);
            let ct = T::from_f64(c);
            for v in tb.iter_mut() {
                if v[2] == ct {
                    v[2] = ulp_step(v[2], k);
                }
            }
            let perms = [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]];
            let p = perms[r.below(6)];
            for t in [&mut ta, &mut tb] {
                for v in t.iter_mut() {
                    *v = [v[p[0]], v[p[1]], v[p[2]]];
                }
            }
            return (ta, tb, how);
        }
        Family::Mesh => {
            let m = armadillo();
            let pairs = armadillo_pairs();
            let (i, j) = pairs[r.below(pairs.len())];
            (m.triangle(i), m.triangle(j), "armadillo_neighbours")
        }
    };
    (conv(&a), conv(&b), how)
}

/// The segment pair derived from a triangle case: edge 0 of each triangle (the constructions
/// put their interesting feature there).
pub fn segments<T: Float>(c: &Case<T>) -> ([[T; 3]; 2], [[T; 3]; 2]) {
    ([c.a[0], c.a[1]], [c.b[0], c.b[1]])
}

/// The point-triangle pair derived from a triangle case: vertex 0 of `b` against `a`.
pub fn point_triangle<T: Float>(c: &Case<T>) -> ([T; 3], Triangle<T>) {
    (c.b[0], c.a)
}
