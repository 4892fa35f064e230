//! Mesh-vs-mesh queries: an indexed triangle mesh with a bounding-volume hierarchy built once,
//! queried in any rigid pose (the mesh is never rebuilt when it moves). Traversal gathers the
//! candidate triangle pairs into batches and the batch kernels ([`Engine`]) do all leaf work,
//! a vector of pairs at a time, so every mesh answer is a kernel answer with its guarantees.
//!
//! # Accuracy
//! A mesh answer is the kernels' answer on the triangles *as moved*: each vertex is moved by
//! [`Pose::apply`] in the working precision (within about `3 u` of its magnitude of the exact
//! motion), and those rounded triangles are what the kernels answer, within the engine's
//! [`crate::Tolerance`]. Pruning never loses an answer: a node pair is skipped only when the
//! bounding boxes (in f64, enlarged by the rounding of the motion) prove every triangle pair in
//! it farther than the margin (contacts), apart (intersection), or farther than the smallest
//! answer so far (distance; the search ends at an answer of 0). So the distance is within the
//! tolerance of the exact minimum over all pairs of moved triangles, the contact set holds
//! every pair within the margin (decided by the kernels as
//! [`Engine::within_margin_triangle_triangle`] does), and intersection is the kernels' verdict
//! on some pair or `None` when every pair is disjoint. The three queries share one traversal.
//! The differential tests (`scenes/tests/mesh.rs`) check this against an exact brute force over all pairs.
//!
//! # The tree
//! A binary tree split at the median centroid along the widest axis, at most [`LEAF`]
//! triangles per leaf. Each node has two bounds: an axis-aligned box in the mesh's own frame,
//! moved with the pose (centre moved, half-extent through `|R|`: conservative for any
//! rotation, but loose for rotated flat patches), and an oriented box on the principal axes
//! of its vertices (`Obb`: thin around a flat patch in any pose), certified to contain every
//! vertex exactly despite f64 rounding and moved exactly as a parallelepiped. A node pair's
//! lower bound is the larger of the boxes' gap and the oriented boxes' six-axis projection
//! gap; the oriented boxes are tried only when the boxes do not already prune. Each node's
//! moved bounds and each leaf's moved triangles are computed once per query.
//!
//! # The traversal
//! From each node pair taken, the walk dives to a leaf pair along the nearer child pairs and
//! leaves the farther ones for later. Contacts and intersection take them depth first (a
//! stack); the distance takes them best first (a heap by lower bound), so its first answers
//! come from the nearest candidates and the walk ends at the first pair whose lower bound
//! exceeds the best answer (issue #15: 43 % less time than depth first over the 12 poses of
//! `cargo bench -p tridist-benches --bench kernels -- 'mesh/arm_fandisk/.*/distance$'`).

use crate::engine::Outputs;
use crate::{ClosestPoints, Engine, Error, Intersection, Point, Pose, Query, Real, Triangle};

/// Most triangles per leaf.
pub const LEAF: usize = 4;

/// Triangle pairs gathered before the kernels run on them.
const FLUSH: usize = 64;

/// An indexed triangle mesh and its bounding-volume hierarchy.
///
/// Memory: besides the mesh and its tree, each thread that runs mesh-vs-mesh queries keeps a
/// scratch of 12 bytes per tree node (two per query, sized by the largest trees it met), so
/// that starting a query costs nothing whatever the meshes' sizes.
///
/// # Example (the README's)
/// ```
/// use tridist::{Engine, Mesh, Pose};
/// let tet = |o: f64| Mesh::new(
///     vec![[o, 0.0, 0.0], [o + 1.0, 0.0, 0.0], [o, 1.0, 0.0], [o, 0.0, 1.0]],
///     vec![[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]],
/// ).unwrap();
/// let (a, b) = (tet(0.0), tet(0.0));
/// let (e, here, there) = (Engine::auto(), Pose::identity(), Pose::translation([3.0, 0.0, 0.0]));
/// let d = e.mesh_distance(&a, &here, &b, &there)?.unwrap();        // closest pair, points
/// assert_eq!((d.sqdist, d.tri_a), (4.0, 0));
/// assert_eq!(e.mesh_intersect(&a, &here, &b, &there)?, None);      // first certified hit
/// let contacts = e.mesh_contacts(&a, &here, &b, &there, 2.5, None)?; // pairs within a margin
/// assert_eq!(contacts.len(), 12);
/// let p = e.mesh_closest_point(&b, &there, [5.0, 0.0, 0.0])?.unwrap(); // point to mesh
/// assert_eq!(p.sqdist, 1.0);
/// # Ok::<(), tridist::Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct Mesh<T> {
    vertices: Vec<Point<T>>,
    triangles: Vec<[u32; 3]>,
    nodes: Vec<Node>,
    /// Per node, an oriented box of its triangles (same index as `nodes`).
    obbs: Vec<Obb>,
    /// Triangle numbers in leaf order.
    order: Vec<u32>,
}

/// A node: a box in the mesh frame (f64) and either two children (`count == 0`: at `first`
/// and `first + 1`) or `count` triangles at `order[first..]`.
#[derive(Clone, Copy, Debug)]
struct Node {
    lo: [f64; 3],
    hi: [f64; 3],
    first: u32,
    count: u32,
}

/// The closest pair of two meshes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshDistance<T> {
    /// Squared distance.
    pub sqdist: T,
    /// Closest point on the first mesh (moved).
    pub p: Point<T>,
    /// Closest point on the second mesh (moved).
    pub q: Point<T>,
    /// The triangle of the first mesh that holds `p`.
    pub tri_a: usize,
    /// The triangle of the second mesh that holds `q`.
    pub tri_b: usize,
}

/// A triangle pair within the margin ([`Engine::mesh_contacts`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact<T> {
    /// Triangle of the first mesh.
    pub tri_a: usize,
    /// Triangle of the second mesh.
    pub tri_b: usize,
    /// Squared distance.
    pub sqdist: T,
    /// Closest point on `tri_a` (moved).
    pub p: Point<T>,
    /// Closest point on `tri_b` (moved).
    pub q: Point<T>,
}

/// The closest point of a mesh to a query point ([`Engine::mesh_closest_point`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshPoint<T> {
    /// Squared distance.
    pub sqdist: T,
    /// The closest point (moved).
    pub point: Point<T>,
    /// The triangle that holds it.
    pub tri: usize,
}

impl<T: Real> Mesh<T> {
    /// A mesh from vertices and triangles (vertex indices), with its tree.
    ///
    /// # Errors
    /// [`Error::IndexOutOfRange`] when an index names no vertex, [`Error::NonFiniteVertex`]
    /// when a coordinate is NaN or infinite. An empty mesh is fine: it is infinitely far from
    /// everything, intersects nothing and has no closest point.
    pub fn new(vertices: Vec<Point<T>>, triangles: Vec<[u32; 3]>) -> Result<Mesh<T>, Error> {
        if let Some(v) = vertices.iter().position(|v| v.iter().any(|x| !x.is_finite())) {
            return Err(Error::NonFiniteVertex { vertex: v });
        }
        for (t, tri) in triangles.iter().enumerate() {
            for &i in tri {
                if i as usize >= vertices.len() {
                    return Err(Error::IndexOutOfRange {
                        triangle: t,
                        index: i as usize,
                        vertices: vertices.len(),
                    });
                }
            }
        }
        let mut m = Mesh { vertices, triangles, nodes: Vec::new(), obbs: Vec::new(), order: Vec::new() };
        m.build();
        Ok(m)
    }

    /// Vertices.
    pub fn vertices(&self) -> &[Point<T>] {
        &self.vertices
    }

    /// Triangles (vertex indices).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.triangles.len()
    }

    /// No triangles?
    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    /// Number of tree nodes (leaves and internal).
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Triangle `i` in the mesh's own frame.
    pub fn triangle(&self, i: usize) -> Triangle<T> {
        self.triangles[i].map(|v| self.vertices[v as usize])
    }

    /// Triangle `i` moved by `pose`, exactly as the queries move it ([`Pose::apply`]).
    pub fn triangle_at(&self, i: usize, pose: &Pose<T>) -> Triangle<T> {
        self.triangle(i).map(|v| pose.apply(v))
    }

    fn build(&mut self) {
        let n = self.triangles.len();
        if n == 0 {
            return;
        }
        let verts: Vec<[f64; 3]> = self.vertices.iter().map(|v| v.map(Real::to_f64)).collect();
        // What the build reads of a triangle, in one place, moved with it by the splits (so
        // each node's pass reads its triangles in order, not scattered over four arrays).
        let mut items: Vec<Item> = (0..n)
            .map(|i| {
                let (lo, hi) = tri_box(&self.triangle(i));
                let c = [0, 1, 2].map(|k| 0.5 * lo[k] + 0.5 * hi[k]);
                Item { lo, hi, c, v: self.triangles[i], tri: i as u32 }
            })
            .collect();
        self.nodes.push(Node { lo: [0.0; 3], hi: [0.0; 3], first: 0, count: 0 });
        // The oriented boxes are fitted to each node's distinct vertices (a vertex is shared by
        // about six triangles): `seen[v]` is the last node that took vertex `v`.
        let mut seen = vec![u32::MAX; verts.len()];
        let mut pts: Vec<[f64; 3]> = Vec::new();
        // (node, range of `items`) still to be built
        let mut todo = vec![(0usize, 0usize, n)];
        while let Some((id, s, e)) = todo.pop() {
            let mut lo = [f64::INFINITY; 3];
            let mut hi = [f64::NEG_INFINITY; 3];
            let (mut clo, mut chi) = (lo, hi);
            pts.clear();
            for it in &items[s..e] {
                for k in 0..3 {
                    lo[k] = lo[k].min(it.lo[k]);
                    hi[k] = hi[k].max(it.hi[k]);
                    clo[k] = clo[k].min(it.c[k]);
                    chi[k] = chi[k].max(it.c[k]);
                }
                for &v in &it.v {
                    if seen[v as usize] != id as u32 {
                        seen[v as usize] = id as u32;
                        pts.push(verts[v as usize]);
                    }
                }
            }
            let obb = Obb::fit(&pts);
            self.obbs.resize(self.obbs.len().max(id + 1), obb);
            self.obbs[id] = obb;
            if e - s <= LEAF {
                self.nodes[id] = Node { lo, hi, first: s as u32, count: (e - s) as u32 };
                continue;
            }
            let axis = (0..3).max_by(|&a, &b| (chi[a] - clo[a]).total_cmp(&(chi[b] - clo[b]))).unwrap_or(0);
            let mid = s + (e - s) / 2;
            items[s..e].select_nth_unstable_by(mid - s, |a, b| a.c[axis].total_cmp(&b.c[axis]));
            let left = self.nodes.len();
            self.nodes.push(Node { lo: [0.0; 3], hi: [0.0; 3], first: 0, count: 0 });
            self.nodes.push(Node { lo: [0.0; 3], hi: [0.0; 3], first: 0, count: 0 });
            self.nodes[id] = Node { lo, hi, first: left as u32, count: 0 };
            todo.push((left, s, mid));
            todo.push((left + 1, mid, e));
        }
        self.order = items.iter().map(|it| it.tri).collect();
    }

    /// Node `i`'s box moved by `pose` (see [`Moved`]).
    fn moved_box(&self, i: usize, pose: &Moved) -> ([f64; 3], [f64; 3]) {
        let n = &self.nodes[i];
        let (mut c, mut h) = ([0.0; 3], [0.0; 3]);
        for k in 0..3 {
            (c[k], h[k]) = (0.5 * n.lo[k] + 0.5 * n.hi[k], 0.5 * n.hi[k] - 0.5 * n.lo[k]);
        }
        let mut lo = [0.0; 3];
        let mut hi = [0.0; 3];
        for r in 0..3 {
            let (mut cr, mut hr, mut mag) = (pose.t[r], 0.0, pose.t[r].abs());
            for k in 0..3 {
                cr += pose.r[r][k] * c[k];
                hr += pose.r[r][k].abs() * h[k];
                mag += pose.r[r][k].abs() * (c[k].abs() + h[k]);
            }
            // The motion in the working precision is within `3 u mag` of the exact one (Pose),
            // this f64 arithmetic within `8 eps64 mag`; the half-width is enlarged by both.
            let slack = mag * pose.rel;
            lo[r] = cr - hr - slack;
            hi[r] = cr + hr + slack;
        }
        (lo, hi)
    }
}

/// A triangle as the tree build reads it: its box, the box's centre, its vertices and number.
struct Item {
    lo: [f64; 3],
    hi: [f64; 3],
    c: [f64; 3],
    v: [u32; 3],
    tri: u32,
}

/// An oriented box in the mesh frame, as a container that f64 rounding cannot break: the
/// points `c + sum_i s_i e_i` with `|s_i| <= h_i`, enlarged by the ball of radius `rho`. Every
/// vertex `v` of the node is in it *exactly*: with `s_i = e_i . (v - c)` and the residual
/// `r = v - c - sum_i s_i e_i` (an identity for any `e_i`), `h_i` and `rho` bound `|s_i|` and
/// `|r|` with a margin for the rounding of their computation. The axes come from the
/// principal axes of the node's vertices, so a flat patch gets a thin box in any pose (the
/// axis-aligned boxes only in the mesh frame).
#[derive(Clone, Copy, Debug)]
struct Obb {
    c: [f64; 3],
    e: [[f64; 3]; 3],
    h: [f64; 3],
    rho: f64,
}

fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn norm1(a: &[f64; 3]) -> f64 {
    a[0].abs() + a[1].abs() + a[2].abs()
}

/// Orthonormal eigenvectors (rows) of a symmetric 3x3 matrix, by cyclic Jacobi rotations:
/// only their being a well-conditioned basis matters here (the box is certified afterwards).
fn principal_axes(mut a: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..12 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        let diag = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
        // converged (or NaN: the caller falls back to the identity); axes good to about the
        // square root of this are as good a box as exact ones (the rotations keep them
        // orthonormal whenever the loop stops)
        if off <= 1e-9 * diag || off.is_nan() {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let (c, s) = (1.0 / (t * t + 1.0).sqrt(), t / (t * t + 1.0).sqrt());
            // a <- J^T a J, v <- v J (columns p, q rotated)
            for k in 0..3 {
                let (akp, akq) = (a[k][p], a[k][q]);
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let (apk, aqk) = (a[p][k], a[q][k]);
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for row in v.iter_mut() {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    // columns of v are the eigenvectors
    let axes = [0, 1, 2].map(|i| [v[0][i], v[1][i], v[2][i]]);
    if axes.iter().flatten().all(|x| x.is_finite()) {
        axes
    } else {
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    }
}

impl Obb {
    /// The box of `points` (at least one), certified as the type says.
    fn fit(points: &[[f64; 3]]) -> Obb {
        // Mean and covariance in one pass, about the first point (only the axes depend on
        // them, and only their quality: the box is certified below whatever they are).
        let o = points[0];
        let (mut n, mut sum, mut sq) = (0.0, [0.0; 3], [[0.0; 3]; 3]);
        for p in points {
            let d = [p[0] - o[0], p[1] - o[1], p[2] - o[2]];
            n += 1.0;
            for i in 0..3 {
                sum[i] += d[i];
                for j in 0..3 {
                    sq[i][j] += d[i] * d[j];
                }
            }
        }
        let cov = [0, 1, 2].map(|i| [0, 1, 2].map(|j| sq[i][j] - sum[i] * sum[j] / n));
        let e = principal_axes(cov);
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for p in points {
            for i in 0..3 {
                let s = dot(&e[i], p);
                lo[i] = lo[i].min(s);
                hi[i] = hi[i].max(s);
            }
        }
        let mid = [0, 1, 2].map(|i| 0.5 * lo[i] + 0.5 * hi[i]);
        let c = [0, 1, 2].map(|k| (0..3).map(|i| mid[i] * e[i][k]).sum::<f64>());
        // the certificate: |s_i| and |r| as computed, plus their computation's rounding (a
        // few operations on numbers of magnitude at most `m`: 64 eps m is far above it)
        let (mut h, mut rho, mut m) = ([0.0f64; 3], 0.0f64, 0.0f64);
        // (written out: array `map`s here were left as calls, a tenth of the build)
        let resid = |d: &[f64; 3], sv: &[f64; 3], k: usize| {
            d[k] - sv[0] * e[0][k] - sv[1] * e[1][k] - sv[2] * e[2][k]
        };
        for p in points {
            let d = [p[0] - c[0], p[1] - c[1], p[2] - c[2]];
            let sv = [dot(&e[0], &d), dot(&e[1], &d), dot(&e[2], &d)];
            let r = [resid(&d, &sv, 0), resid(&d, &sv, 1), resid(&d, &sv, 2)];
            for i in 0..3 {
                h[i] = h[i].max(sv[i].abs());
            }
            rho = rho.max(norm1(&r));
            m = m.max(norm1(p) + norm1(&c) + norm1(&sv));
        }
        let slack = 64.0 * f64::EPSILON * m;
        Obb { c, e, h: h.map(|x| x + slack), rho: rho + slack }
    }
}

/// An oriented box moved by a pose (exactly: the linear map takes the box to the
/// parallelepiped `c' + sum s_i e_i'`, `|s_i| <= h_i`, and the ball into a ball `|R|_F` times
/// larger), with `err`, a bound of the rounding of the computed `c'`, `e_i'` (1-norms, the
/// `e_i'` weighted by `h_i`), and `rho` grown by the ball's growth and the rounding of the
/// vertices' motion in the working precision.
#[derive(Clone, Copy, Debug)]
struct MovedObb {
    b: Obb,
    err: f64,
}

/// A lower bound of the distance between two moved oriented boxes: the largest gap of their
/// projections on the six box axes and the line through their centres (the good axis for
/// boxes apart along a diagonal), less the balls and every rounding; `None` as soon as one
/// axis shows that its square (rounded down by [`down`]) exceeds `lim`.
fn obb_gap(ma: &MovedObb, mb: &MovedObb, lim: f64) -> Option<f64> {
    let (a, b) = (&ma.b, &mb.b);
    let dc = [b.c[0] - a.c[0], b.c[1] - a.c[1], b.c[2] - a.c[2]];
    // The axes' dot products, each computed once (`dot` is symmetric bit for bit, so the
    // projections are the ones computed axis by axis): rows 0-2 the axes of `a`, 3-5 of `b`,
    // 6 the centre line; `pa[n][i] = |a.e_i . n|`, `pb[n][i] = |b.e_i . n|`.
    let axes = [a.e[0], a.e[1], a.e[2], b.e[0], b.e[1], b.e[2], dc];
    let mut pa = [[0.0f64; 3]; 7];
    let mut pb = [[0.0f64; 3]; 7];
    for i in 0..3 {
        for j in i..3 {
            let (x, y) = (dot(&a.e[i], &a.e[j]).abs(), dot(&b.e[i], &b.e[j]).abs());
            (pa[j][i], pa[i][j]) = (x, x);
            (pb[3 + j][i], pb[3 + i][j]) = (y, y);
        }
        for j in 0..3 {
            let x = dot(&a.e[i], &b.e[j]).abs();
            (pa[3 + j][i], pb[i][j]) = (x, x);
        }
        (pa[6][i], pb[6][i]) = (dot(&a.e[i], &dc).abs(), dot(&b.e[i], &dc).abs());
    }
    let mut best = 0.0f64;
    for (k, n) in axes.iter().enumerate() {
        let ra = a.h[0] * pa[k][0] + a.h[1] * pa[k][1] + a.h[2] * pa[k][2];
        let rb = b.h[0] * pb[k][0] + b.h[1] * pb[k][1] + b.h[2] * pb[k][2];
        let g = dot(&dc, n).abs() - ra - rb;
        if g > 0.0 {
            // the computed projections are within (err_a + err_b) |n|_1 of the exact ones,
            // and this arithmetic within far less than its 1e-12 relative margin
            let len = dot(n, n).sqrt() * (1.0 + 1e-12);
            let g = (g - (ma.err + mb.err) * norm1(n)) * (1.0 - 1e-12) / len;
            best = best.max(g);
            // one axis that prunes is enough (the gap is at least its bound)
            let o = (best - a.rho - b.rho).max(0.0);
            if down(o * o) > lim {
                return None;
            }
        }
    }
    Some((best - a.rho - b.rho).max(0.0))
}

/// A pose in f64 with the relative slack that makes moved boxes contain the moved vertices.
struct Moved {
    r: [[f64; 3]; 3],
    t: [f64; 3],
    rel: f64,
    /// The Frobenius norm of `r` rounded up: how much the rotation can stretch a ball.
    frob: f64,
}

impl Moved {
    fn of<T: Real>(p: &Pose<T>) -> Moved {
        let r = p.rotation.map(|row| row.map(Real::to_f64));
        Moved {
            r,
            t: p.translation.map(Real::to_f64),
            rel: 4.0 * T::UNIT_ROUNDOFF.to_f64() + 16.0 * f64::EPSILON,
            frob: r.iter().flatten().map(|x| x * x).sum::<f64>().sqrt() * (1.0 + 1e-12),
        }
    }

    /// Node `i`'s oriented box moved (see [`MovedObb`]).
    fn obb<T: Real>(&self, mesh: &Mesh<T>, i: usize) -> MovedObb {
        let (o, n) = (&mesh.obbs[i], &mesh.nodes[i]);
        let r = &self.r;
        // (loops, not array maps: those were left as calls on this hot path)
        let (mut c, mut e) = ([0.0; 3], [[0.0; 3]; 3]);
        for k in 0..3 {
            c[k] = dot(&r[k], &o.c) + self.t[k];
            for i in 0..3 {
                e[i][k] = dot(&r[k], &o.e[i]);
            }
        }
        let (mut big, mut slack) = (0.0, 0.0);
        for k in 0..3 {
            let (mut b, mut v) = (self.t[k].abs(), self.t[k].abs());
            for j in 0..3 {
                let w = o.h[0] * o.e[0][j].abs() + o.h[1] * o.e[1][j].abs() + o.h[2] * o.e[2][j].abs();
                b += r[k][j].abs() * (o.c[j].abs() + w);
                v += r[k][j].abs() * n.lo[j].abs().max(n.hi[j].abs());
            }
            big += b;
            // the vertices' motion in the working precision (as in `moved_box`)
            slack += v * self.rel;
        }
        MovedObb { b: Obb { c, e, h: o.h, rho: o.rho * self.frob + slack }, err: 32.0 * f64::EPSILON * big }
    }

    /// `Ok` unless `mesh`'s moved root box leaves the range of `T` (a moved vertex could
    /// overflow): then [`Error::NonFiniteCoordinate`].
    fn fits<T: Real>(&self, mesh: &Mesh<T>) -> Result<(), Error> {
        let b = mesh.moved_box(0, self);
        if b.0.iter().chain(&b.1).all(|x| x.abs() <= T::MAX.to_f64()) {
            Ok(())
        } else {
            Err(Error::NonFiniteCoordinate)
        }
    }
}

/// A squared gap computed in f64 (a few roundings), lowered past them: a lower bound of the
/// exact square. Every pruning test compares such a bound with the search's limit.
fn down(s: f64) -> f64 {
    s * (1.0 - 8.0 * f64::EPSILON)
}

/// Squared distance between two boxes, rounded down (a lower bound of the exact one).
fn box_gap2(a: &Aabb, b: &Aabb) -> f64 {
    let mut s = 0.0;
    for k in 0..3 {
        let g = (b.0[k] - a.1[k]).max(a.0[k] - b.1[k]).max(0.0);
        s += g * g;
    }
    down(s)
}

/// Squared distance from a point to a box, rounded down.
fn point_gap2(x: &[f64; 3], b: &([f64; 3], [f64; 3])) -> f64 {
    let mut s = 0.0;
    for k in 0..3 {
        let g = (b.0[k] - x[k]).max(x[k] - b.1[k]).max(0.0);
        s += g * g;
    }
    down(s)
}

/// The largest absolute coordinate of two boxes: a bound of the magnitude `S` of every
/// triangle pair in them.
fn magnitude(a: &Aabb, b: &Aabb) -> f64 {
    let mut m = 0.0f64;
    for k in 0..3 {
        m = m.max(a.0[k].abs()).max(a.1[k].abs()).max(b.0[k].abs()).max(b.1[k].abs());
    }
    m
}

/// How far apart (exactly) two triangles of magnitude at most `mag` may be and still be
/// answered within `margin` by the kernels: an answer is at least its certified lower bound,
/// which is at least the exact distance less the tolerance width
/// `max(scaled u S, absolute, relative lo)`, plus a little for the rounding of the box tests
/// (`8 u S`, far above it). Uncertified pairs (counted by the batch, rare) are outside this
/// guarantee. Infinite when the relative tolerance is 1 or more.
fn reach<T: Real>(tol: &crate::Tolerance, mag: f64, margin: f64) -> f64 {
    let u = T::UNIT_ROUNDOFF.to_f64();
    let width = (margin + (tol.scaled + 8.0) * u * mag + tol.absolute) / (1.0 - tol.relative);
    if tol.relative < 1.0 {
        width
    } else {
        f64::INFINITY
    }
}

/// An axis-aligned box (lower and upper corner) in f64.
type Aabb = ([f64; 3], [f64; 3]);

/// The box of a triangle, in f64 (exact: every `T` converts exactly).
fn tri_box<T: Real>(t: &Triangle<T>) -> Aabb {
    let (mut lo, mut hi) = ([0.0; 3], [0.0; 3]);
    for k in 0..3 {
        let x = [t[0][k].to_f64(), t[1][k].to_f64(), t[2][k].to_f64()];
        (lo[k], hi[k]) = (x[0].min(x[1]).min(x[2]), x[0].max(x[1]).max(x[2]));
    }
    (lo, hi)
}

/// Candidate triangle pairs, moved, waiting for the kernels.
struct Pending<T> {
    ids: Vec<(u32, u32)>,
    a: Vec<Triangle<T>>,
    b: Vec<Triangle<T>>,
}

impl<T: Real> Pending<T> {
    fn new() -> Self {
        Pending { ids: Vec::with_capacity(FLUSH + LEAF * LEAF), a: Vec::new(), b: Vec::new() }
    }

    /// Gathers the triangle pairs of two moved leaves whose triangles' boxes are not farther
    /// apart (squared, a lower bound) than `limit`.
    fn push_leaves(&mut self, la: &Leaf<T>, lb: &Leaf<T>, limit: f64) {
        for ka in 0..la.n {
            for kb in 0..lb.n {
                if box_gap2(&la.boxes[ka], &lb.boxes[kb]) > limit {
                    continue;
                }
                self.ids.push((la.ids[ka], lb.ids[kb]));
                self.a.push(la.tris[ka]);
                self.b.push(lb.tris[kb]);
            }
        }
    }

    fn clear(&mut self) {
        self.ids.clear();
        self.a.clear();
        self.b.clear();
    }
}

/// A leaf's triangles moved by the query's pose ([`Mesh::triangle_at`]), with their boxes.
struct Leaf<T> {
    n: usize,
    ids: [u32; LEAF],
    tris: [Triangle<T>; LEAF],
    boxes: [Aabb; LEAF],
}

/// Node-indexed scratch of a [`Side`], reused by the queries of one thread: an entry counts
/// only when it carries the current query's stamp, so starting a query costs nothing whatever
/// the trees' sizes (two fresh `vec![u32::MAX; nodes]` per side were most of a collision
/// query's time on separated poses). Kept per thread: 12 bytes per node of the largest tree
/// met, for each side alive at once.
#[derive(Default)]
struct Slots {
    stamp: u32,
    /// Per node: the stamp of the query that wrote it, its index in `Side::bounds`, its index
    /// in `Side::leaves` (`u32::MAX`: not reached yet).
    v: Vec<[u32; 3]>,
}

std::thread_local! {
    static SLOTS: core::cell::RefCell<Vec<Slots>> = const { core::cell::RefCell::new(Vec::new()) };
}

impl Slots {
    /// Scratch for a tree of `n` nodes, every entry unset.
    fn take(n: usize) -> Slots {
        let mut s = SLOTS.with(|p| p.borrow_mut().pop()).unwrap_or_default();
        if s.v.len() < n {
            s.v.resize(n, [0; 3]);
        }
        s.stamp = s.stamp.wrapping_add(1);
        if s.stamp == 0 {
            // after 2^32 queries: forget every stamp (0 is never current)
            s.v.iter_mut().for_each(|e| e[0] = 0);
            s.stamp = 1;
        }
        s
    }

    /// Node `i`'s entry for this query: `[_, bounds index, leaf index]`.
    fn entry(&mut self, i: u32) -> &mut [u32; 3] {
        let e = &mut self.v[i as usize];
        if e[0] != self.stamp {
            *e = [self.stamp, u32::MAX, u32::MAX];
        }
        e
    }
}

/// One mesh of a query in its pose, with what the traversal has moved so far: each node's
/// bounds and each leaf's triangles are moved once per query (a node meets many nodes of the
/// other mesh).
struct Side<'m, T> {
    mesh: &'m Mesh<T>,
    pose: &'m Pose<T>,
    mv: Moved,
    slots: Slots,
    bounds: Vec<(Aabb, MovedObb)>,
    leaves: Vec<Leaf<T>>,
}

impl<T> Drop for Side<'_, T> {
    fn drop(&mut self) {
        let s = core::mem::take(&mut self.slots);
        // a thread keeps as many as it had sides alive at once (two per query)
        let _ = SLOTS.try_with(|p| p.borrow_mut().push(s));
    }
}

impl<'m, T: Real> Side<'m, T> {
    /// The side, or [`Error::NonFiniteCoordinate`] when the moved mesh leaves the range of `T`.
    fn new(mesh: &'m Mesh<T>, pose: &'m Pose<T>) -> Result<Self, Error> {
        let mv = Moved::of(pose);
        mv.fits(mesh)?;
        let slots = Slots::take(mesh.nodes.len());
        Ok(Side { mesh, pose, mv, slots, bounds: Vec::new(), leaves: Vec::new() })
    }

    /// Node `i`'s moved box and oriented box.
    fn bounds(&mut self, i: u32) -> &(Aabb, MovedObb) {
        let k = self.slots.entry(i)[1];
        if k != u32::MAX {
            return &self.bounds[k as usize];
        }
        self.slots.entry(i)[1] = self.bounds.len() as u32;
        self.bounds.push((self.mesh.moved_box(i as usize, &self.mv), self.mv.obb(self.mesh, i as usize)));
        &self.bounds[self.bounds.len() - 1]
    }

    /// Leaf node `i`, moved.
    fn leaf(&mut self, i: u32) -> &Leaf<T> {
        let k = self.slots.entry(i)[2];
        if k != u32::MAX {
            return &self.leaves[k as usize];
        }
        let node = &self.mesh.nodes[i as usize];
        let mut l = Leaf {
            n: node.count as usize,
            ids: [0; LEAF],
            tris: [[[T::ZERO; 3]; 3]; LEAF],
            boxes: [([0.0; 3], [0.0; 3]); LEAF],
        };
        for (k, &t) in
            self.mesh.order[node.first as usize..(node.first + node.count) as usize].iter().enumerate()
        {
            l.ids[k] = t;
            l.tris[k] = self.mesh.triangle_at(t as usize, self.pose);
            l.boxes[k] = tri_box(&l.tris[k]);
        }
        self.slots.entry(i)[2] = self.leaves.len() as u32;
        self.leaves.push(l);
        &self.leaves[self.leaves.len() - 1]
    }
}

/// The lower bound of the squared distance between two nodes (moved bounds): the larger of
/// their boxes' and their oriented boxes' gaps; `None` when it exceeds the search's limit
/// (the oriented boxes, dearer, are tried only when the boxes do not already prune).
fn node_gap2<T: Real>(x: &(Aabb, MovedObb), y: &(Aabb, MovedObb), s: &impl Search<T>) -> Option<f64> {
    let lim = s.limit(&x.0, &y.0);
    let g = box_gap2(&x.0, &y.0);
    if g > lim {
        return None;
    }
    let o = obb_gap(&x.1, &y.1, lim)?;
    let g = g.max(down(o * o));
    (g <= lim).then_some(g)
}

/// What one mesh-vs-mesh query does on the one traversal they share ([`search`]).
trait Search<T: Real> {
    /// The squared distance beyond which the triangle pairs in the boxes `bx`, `by` are not
    /// needed.
    fn limit(&self, bx: &Aabb, by: &Aabb) -> f64;
    /// Whether to run the kernels on the first pairs gathered, not waiting for [`FLUSH`] of
    /// them (distance: their answer prunes the rest).
    fn eager(&self) -> bool {
        false
    }
    /// Runs the kernels on the gathered pairs; `true` ends the search.
    fn flush(&mut self, e: &Engine, pend: &Pending<T>) -> Result<bool, Error>;
    /// Visit node pairs best first (smallest lower bound next) instead of depth first. Only for
    /// a search whose limit does not depend on the boxes: the first pair beyond it ends the
    /// search.
    fn best_first(&self) -> bool {
        false
    }
}

/// The node pairs waiting for a visit: a stack (depth first, the nearer child pair on top) or a
/// heap (best first: the pair of smallest lower bound next).
enum Frontier {
    Depth(Vec<Visit>),
    Best(std::collections::BinaryHeap<Nearer>),
}

/// A visit ordered for a max-heap by its lower bound, smallest first (ties: smaller nodes).
struct Nearer(Visit);

impl Ord for Nearer {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        let (a, b) = (self.0, o.0);
        b.0.total_cmp(&a.0).then((b.1, b.2).cmp(&(a.1, a.2)))
    }
}
impl PartialOrd for Nearer {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl PartialEq for Nearer {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o).is_eq()
    }
}
impl Eq for Nearer {}

impl Frontier {
    fn push(&mut self, v: Visit) {
        match self {
            Frontier::Depth(s) => s.push(v),
            Frontier::Best(h) => h.push(Nearer(v)),
        }
    }
    fn pop(&mut self) -> Option<Visit> {
        match self {
            Frontier::Depth(s) => s.pop(),
            Frontier::Best(h) => h.pop().map(|n| n.0),
        }
    }
}

/// A node pair to visit: (lower bound of the squared gap, node of a, node of b).
type Visit = (f64, u32, u32);

/// The root pair of two sides, unless pruned.
fn root_visit<T: Real>(sa: &mut Side<'_, T>, sb: &mut Side<'_, T>, s: &impl Search<T>) -> Option<Visit> {
    node_gap2(sa.bounds(0), sb.bounds(0), s).map(|g| (g, 0, 0))
}

/// The child pairs of the internal pair (x, y), not pruned, the nearer last: the larger
/// internal node is split.
fn children<T: Real>(
    sa: &mut Side<'_, T>,
    sb: &mut Side<'_, T>,
    (x, y): (u32, u32),
    s: &impl Search<T>,
) -> [Option<Visit>; 2] {
    let (nx, ny) = (&sa.mesh.nodes[x as usize], &sb.mesh.nodes[y as usize]);
    let extent = |n: &Node| (0..3).map(|k| n.hi[k] - n.lo[k]).fold(0.0, f64::max);
    let split_a = ny.count > 0 || (nx.count == 0 && extent(nx) >= extent(ny));
    let mut kids = if split_a {
        let (c, by) = (nx.first, *sb.bounds(y));
        let g0 = node_gap2(sa.bounds(c), &by, s).map(|g| (g, c, y));
        [g0, node_gap2(sa.bounds(c + 1), &by, s).map(|g| (g, c + 1, y))]
    } else {
        let (c, bx) = (ny.first, *sa.bounds(x));
        let g0 = node_gap2(&bx, sb.bounds(c), s).map(|g| (g, x, c));
        [g0, node_gap2(&bx, sb.bounds(c + 1), s).map(|g| (g, x, c + 1))]
    };
    if kids[0].map_or(f64::INFINITY, |k| k.0) < kids[1].map_or(f64::INFINITY, |k| k.0) {
        kids.swap(0, 1);
    }
    kids
}

/// The traversal of two trees every mesh-vs-mesh query runs, from the node pairs on `stack`:
/// node pairs nearest first (depth first, the nearer child pair on top; or best first when the
/// search asks), pruned by `s.limit`, leaf pairs gathered into batches for the kernels.
fn walk<T: Real, S: Search<T>>(
    e: &Engine,
    sa: &mut Side<'_, T>,
    sb: &mut Side<'_, T>,
    stack: Vec<Visit>,
    s: &mut S,
) -> Result<(), Error> {
    let mut pend = Pending::new();
    let best_first = s.best_first();
    let mut todo = if best_first {
        Frontier::Best(stack.into_iter().map(Nearer).collect())
    } else {
        Frontier::Depth(stack)
    };
    'visits: while let Some(mut v) = todo.pop() {
        // From each pair taken, dive to a leaf pair along the nearer child pairs, leaving the
        // farther ones for later: leaves are reached (and their answers prune) early in either
        // order.
        loop {
            let (gap, x, y) = v;
            let lim = s.limit(&sa.bounds(x).0, &sb.bounds(y).0);
            if gap > lim {
                if best_first {
                    // Only the pair just taken from the heap can be beyond the limit here (a
                    // dive's children passed the same limit in `children`, and the limit
                    // changes only at a flush, which ends the dive): it is the nearest left,
                    // so every pair left is at least as far (the limit is the same for all).
                    break 'visits;
                }
                continue 'visits;
            }
            if sa.mesh.nodes[x as usize].count > 0 && sb.mesh.nodes[y as usize].count > 0 {
                pend.push_leaves(sa.leaf(x), sb.leaf(y), lim);
                if pend.ids.len() >= FLUSH || (s.eager() && !pend.ids.is_empty()) {
                    let stop = s.flush(e, &pend)?;
                    pend.clear();
                    if stop {
                        return Ok(());
                    }
                }
                continue 'visits;
            }
            let [far, near] = children(sa, sb, (x, y), s);
            if let Some(f) = far {
                todo.push(f);
            }
            match near {
                Some(n) => v = n,
                None => continue 'visits,
            }
        }
    }
    if !pend.ids.is_empty() {
        s.flush(e, &pend)?;
    }
    Ok(())
}

/// [`walk`] from the roots of two meshes in their poses.
fn search<T: Real, S: Search<T>>(
    e: &Engine,
    a: &Mesh<T>,
    pa: &Pose<T>,
    b: &Mesh<T>,
    pb: &Pose<T>,
    s: &mut S,
) -> Result<(), Error> {
    pa.check()?;
    pb.check()?;
    if a.is_empty() || b.is_empty() {
        return Ok(());
    }
    let (mut sa, mut sb) = (Side::new(a, pa)?, Side::new(b, pb)?);
    let stack = root_visit(&mut sa, &mut sb, s).into_iter().collect();
    walk(e, &mut sa, &mut sb, stack, s)
}

fn check_finite<T: Real>(d: T) -> Result<(), Error> {
    if d.is_nan() {
        Err(Error::NonFiniteCoordinate)
    } else {
        Ok(())
    }
}

/// [`Engine::mesh_distance`]: the smallest answer so far prunes.
struct Nearest<T> {
    best: Option<MeshDistance<T>>,
    best_d: f64,
    out: Vec<ClosestPoints<T>>,
}

impl<T: Real> Search<T> for Nearest<T> {
    fn limit(&self, _bx: &Aabb, _by: &Aabb) -> f64 {
        self.best_d
    }
    fn eager(&self) -> bool {
        self.best.is_none()
    }
    fn best_first(&self) -> bool {
        true
    }
    fn flush(&mut self, e: &Engine, pend: &Pending<T>) -> Result<bool, Error> {
        self.out.clear();
        self.out.resize(pend.ids.len(), ClosestPoints::default());
        e.closest_points_triangle_triangle(&pend.a, &pend.b, &mut self.out)?;
        for (cp, &(i, j)) in self.out.iter().zip(&pend.ids) {
            check_finite(cp.sqdist)?;
            let d = cp.sqdist.to_f64();
            // ties among the pairs answered go to the smaller triangle numbers
            let better = match self.best {
                None => true,
                Some(m) => {
                    d < self.best_d || (d == self.best_d && (i as usize, j as usize) < (m.tri_a, m.tri_b))
                }
            };
            if better {
                self.best_d = d;
                self.best = Some(MeshDistance {
                    sqdist: cp.sqdist,
                    p: cp.p,
                    q: cp.q,
                    tri_a: i as usize,
                    tri_b: j as usize,
                });
            }
        }
        // nothing is nearer than touching: the search ends at the first batch that touches
        Ok(self.best_d == 0.0)
    }
}

/// [`Engine::mesh_contacts`]: every pair within reach of the margin, answered by
/// [`Query::Within`] (distance and closest points in one run).
struct Contacts<T> {
    margin: f64,
    tol: crate::Tolerance,
    found: Vec<Contact<T>>,
    d: Vec<T>,
    p: Vec<Point<T>>,
    q: Vec<Point<T>>,
}

impl<T: Real> Search<T> for Contacts<T> {
    fn limit(&self, bx: &Aabb, by: &Aabb) -> f64 {
        let r = reach::<T>(&self.tol, magnitude(bx, by), self.margin);
        r * r
    }
    fn flush(&mut self, e: &Engine, pend: &Pending<T>) -> Result<bool, Error> {
        let n = pend.ids.len();
        self.d.clear();
        self.d.resize(n, T::ZERO);
        self.p.clear();
        self.p.resize(n, [T::ZERO; 3]);
        self.q.clear();
        self.q.resize(n, [T::ZERO; 3]);
        e.run(
            Query::Within,
            &pend.a,
            &pend.b,
            Outputs::new().sqdist(&mut self.d).points(&mut self.p, &mut self.q),
        )?;
        for k in 0..n {
            check_finite(self.d[k])?;
            if self.d[k].is_finite() {
                let (i, j) = pend.ids[k];
                self.found.push(Contact {
                    tri_a: i as usize,
                    tri_b: j as usize,
                    sqdist: self.d[k],
                    p: self.p[k],
                    q: self.q[k],
                });
            }
        }
        Ok(false)
    }
}

/// [`Engine::mesh_intersect`]: stops at the first batch with an intersecting pair.
struct FirstHit {
    tol: crate::Tolerance,
    hit: Option<(usize, usize)>,
    v: Vec<Intersection>,
}

impl<T: Real> Search<T> for FirstHit {
    fn limit(&self, bx: &Aabb, by: &Aabb) -> f64 {
        // "Intersecting" is said of pairs within the tolerance of touching: boxes that far
        // apart are kept.
        let r = reach::<T>(&self.tol, magnitude(bx, by), 0.0);
        r * r
    }
    fn eager(&self) -> bool {
        true
    }
    fn flush(&mut self, e: &Engine, pend: &Pending<T>) -> Result<bool, Error> {
        self.v.clear();
        self.v.resize(pend.ids.len(), Intersection::Invalid);
        e.intersect_triangle_triangle(&pend.a, &pend.b, &mut self.v)?;
        for (r, &(i, j)) in self.v.iter().zip(&pend.ids) {
            match r {
                Intersection::Invalid => return Err(Error::NonFiniteCoordinate),
                Intersection::Intersecting => {
                    let p = (i as usize, j as usize);
                    self.hit = Some(self.hit.map_or(p, |h| h.min(p)));
                }
                Intersection::Disjoint => {}
            }
        }
        Ok(self.hit.is_some())
    }
}

/// The order of [`Engine::mesh_contacts`]: squared distance, then triangle numbers.
fn contact_order<T: Real>(p: &Contact<T>, q: &Contact<T>) -> std::cmp::Ordering {
    p.sqdist.to_f64().total_cmp(&q.sqdist.to_f64()).then((p.tri_a, p.tri_b).cmp(&(q.tri_a, q.tri_b)))
}

/// [`Engine::mesh_contacts`] on the engine's threads: the node pairs are split breadth first
/// into pieces (at least 32 per thread where the trees allow), each walked on its own by a
/// thread with its own moved bounds and leaves; the pieces' contacts are merged (the caller
/// sorts them, so the answer is the single-threaded one).
fn contacts_threaded<T: Real>(
    e: &Engine,
    a: &Mesh<T>,
    pa: &Pose<T>,
    b: &Mesh<T>,
    pb: &Pose<T>,
    state: &(impl Fn() -> Contacts<T> + Sync),
) -> Result<Vec<Contact<T>>, Error> {
    pa.check()?;
    pb.check()?;
    if a.is_empty() || b.is_empty() {
        return Ok(Vec::new());
    }
    let (mut sa, mut sb) = (Side::new(a, pa)?, Side::new(b, pb)?);
    let probe = state();
    let want = 32 * e.thread_count();
    let mut queue: std::collections::VecDeque<Visit> =
        root_visit(&mut sa, &mut sb, &probe).into_iter().collect();
    let mut pieces = Vec::new();
    while pieces.len() + queue.len() < want {
        let Some((g, x, y)) = queue.pop_front() else { break };
        if sa.mesh.nodes[x as usize].count > 0 && sb.mesh.nodes[y as usize].count > 0 {
            pieces.push((g, x, y));
        } else {
            queue.extend(children(&mut sa, &mut sb, (x, y), &probe).into_iter().flatten());
        }
    }
    pieces.extend(queue);
    if pieces.is_empty() {
        // pruned at the root: no thread to wake
        return Ok(Vec::new());
    }
    let single = e.threads(1);
    let found = crate::engine::par_map_init(
        e.thread_count(),
        &pieces,
        || Side::new(a, pa).and_then(|sa| Ok((sa, Side::new(b, pb)?))),
        |sides, &v| {
            let (sa, sb) = sides.as_mut().map_err(|err| err.clone())?;
            let mut s = state();
            walk(&single, sa, sb, vec![v], &mut s)?;
            s.found.sort_unstable_by(contact_order);
            Ok(s.found)
        },
    );
    let mut all = Vec::new();
    for f in found {
        all.extend(f?);
    }
    Ok(all)
}

impl Engine {
    /// The closest pair of triangles of two meshes in their poses: squared distance, closest
    /// points and the triangles that hold them (`None` when a mesh is empty). Touching or
    /// intersecting meshes give 0 (at some touching pair).
    ///
    /// # Errors
    /// [`Error::InvalidPose`] for a non-finite pose, [`Error::NonFiniteCoordinate`] when a
    /// moved coordinate overflows.
    pub fn mesh_distance<T: Real>(
        &self,
        a: &Mesh<T>,
        pose_a: &Pose<T>,
        b: &Mesh<T>,
        pose_b: &Pose<T>,
    ) -> Result<Option<MeshDistance<T>>, Error> {
        let mut s = Nearest { best: None, best_d: f64::INFINITY, out: Vec::new() };
        search(self, a, pose_a, b, pose_b, &mut s)?;
        Ok(s.best)
    }

    /// Every triangle pair of two meshes in their poses whose distance is at most `margin`
    /// (contact generation), each with its squared distance and closest points, ordered by
    /// squared distance then triangle numbers; with `cap`, the first `cap` of that order.
    ///
    /// Within the margin is decided as [`Engine::within_margin_triangle_triangle`] decides it
    /// (the full triangle-triangle answer, thresholded), pair by pair. With
    /// [`Engine::threads`] above 1 the traversal is split into pieces walked in parallel; the
    /// answer is the same.
    ///
    /// # Errors
    /// [`Error::InvalidMargin`], [`Error::InvalidPose`], [`Error::NonFiniteCoordinate`].
    pub fn mesh_contacts<T: Real>(
        &self,
        a: &Mesh<T>,
        pose_a: &Pose<T>,
        b: &Mesh<T>,
        pose_b: &Pose<T>,
        margin: T,
        cap: Option<usize>,
    ) -> Result<Vec<Contact<T>>, Error> {
        let e = self.margin(margin.to_f64())?;
        let state = || Contacts {
            margin: margin.to_f64(),
            tol: e.current_tolerance(),
            found: Vec::new(),
            d: Vec::new(),
            p: Vec::new(),
            q: Vec::new(),
        };
        let mut found = if self.thread_count() > 1 {
            contacts_threaded(&e, a, pose_a, b, pose_b, &state)?
        } else {
            let mut s = state();
            search(&e, a, pose_a, b, pose_b, &mut s)?;
            s.found
        };
        // deterministic either way: no two contacts share their triangle pair; the threaded
        // pieces come sorted, and the stable sort merges such runs
        if self.thread_count() > 1 {
            found.sort_by(contact_order);
        } else {
            found.sort_unstable_by(contact_order);
        }
        if let Some(c) = cap {
            found.truncate(c);
        }
        Ok(found)
    }

    /// Do two meshes in their poses intersect (touch or overlap)? `Some((tri_a, tri_b))`: a
    /// pair the kernels call intersecting ([`Engine::intersect_triangle_triangle`]; the
    /// search stops at the first batch that holds one, and reports its smallest pair), `None`
    /// when every pair is disjoint.
    ///
    /// # Errors
    /// [`Error::InvalidPose`], [`Error::NonFiniteCoordinate`].
    pub fn mesh_intersect<T: Real>(
        &self,
        a: &Mesh<T>,
        pose_a: &Pose<T>,
        b: &Mesh<T>,
        pose_b: &Pose<T>,
    ) -> Result<Option<(usize, usize)>, Error> {
        let mut s = FirstHit { tol: self.current_tolerance(), hit: None, v: Vec::new() };
        search::<T, _>(self, a, pose_a, b, pose_b, &mut s)?;
        Ok(s.hit)
    }

    /// The closest point of a mesh in its pose to `x`: squared distance, the point and its
    /// triangle (`None` for an empty mesh).
    ///
    /// # Errors
    /// [`Error::InvalidPose`], [`Error::NonFiniteCoordinate`] (also for a non-finite `x`).
    pub fn mesh_closest_point<T: Real>(
        &self,
        m: &Mesh<T>,
        pose: &Pose<T>,
        x: Point<T>,
    ) -> Result<Option<MeshPoint<T>>, Error> {
        pose.check()?;
        if x.iter().any(|c| !c.is_finite()) {
            return Err(Error::NonFiniteCoordinate);
        }
        if m.is_empty() {
            return Ok(None);
        }
        let mv = Moved::of(pose);
        mv.fits(m)?;
        let xf = x.map(Real::to_f64);
        let mut best: Option<MeshPoint<T>> = None;
        let mut best_d = f64::INFINITY;
        let (mut ids, mut tris) = (Vec::new(), Vec::new());
        let mut out = Vec::new();
        let mut flush = |ids: &mut Vec<u32>,
                         tris: &mut Vec<Triangle<T>>,
                         best: &mut Option<MeshPoint<T>>,
                         best_d: &mut f64| {
            out.clear();
            out.resize(ids.len(), ClosestPoints::default());
            self.closest_point_point_triangle(&[x], &tris[..], &mut out)?;
            for (cp, &i) in out.iter().zip(ids.iter()) {
                check_finite(cp.sqdist)?;
                let d = cp.sqdist.to_f64();
                if best.is_none_or(|b| d < *best_d || (d == *best_d && (i as usize) < b.tri)) {
                    *best_d = d;
                    *best = Some(MeshPoint { sqdist: cp.sqdist, point: cp.q, tri: i as usize });
                }
            }
            ids.clear();
            tris.clear();
            Ok::<(), Error>(())
        };
        let mut stack = vec![(point_gap2(&xf, &m.moved_box(0, &mv)), 0u32)];
        while let Some((gap, n)) = stack.pop() {
            if gap > best_d {
                continue;
            }
            let node = &m.nodes[n as usize];
            if node.count > 0 {
                for &i in &m.order[node.first as usize..(node.first + node.count) as usize] {
                    ids.push(i);
                    tris.push(m.triangle_at(i as usize, pose));
                }
                if ids.len() >= FLUSH {
                    flush(&mut ids, &mut tris, &mut best, &mut best_d)?;
                }
            } else {
                let mut c =
                    [node.first, node.first + 1].map(|k| (point_gap2(&xf, &m.moved_box(k as usize, &mv)), k));
                if c[0].0 < c[1].0 {
                    c.swap(0, 1);
                }
                stack.extend(c);
            }
        }
        if !ids.is_empty() {
            flush(&mut ids, &mut tris, &mut best, &mut best_d)?;
        }
        Ok(best)
    }
}
