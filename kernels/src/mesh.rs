//! Mesh-vs-mesh queries: an indexed triangle mesh with a bounding-volume hierarchy built once,
//! queried in any rigid pose (the mesh is never rebuilt when it moves). Traversal gathers the
//! candidate triangle pairs into batches and the batch kernels ([`Engine`]) do all leaf work,
//! a vector of pairs at a time, so every mesh answer is a kernel answer with its guarantees.
//!
//! # Accuracy
//! A mesh answer is the kernels' answer on the triangles *as moved*: each vertex is moved by
//! [`Pose::apply`] in the working precision (within about `3 u` of its magnitude of the exact
//! motion), and those rounded triangles are what the kernels answer, within the engine's
//! [`crate::Tolerance`]. Pruning never changes an answer: a node pair is skipped only when the
//! bounding boxes (in f64, enlarged by the rounding of the motion) prove every triangle pair in
//! it farther than the answer so far (distance), than the margin (contacts) or apart
//! (intersection). So the distance is within the tolerance of the exact minimum over all
//! pairs of moved triangles, the contact set holds every pair within the margin (decided by the
//! kernels as [`Engine::within_margin_triangle_triangle`] does), and intersection is the
//! kernels' verdict on some pair or `None` when every pair is disjoint. The differential tests
//! (`scenes/tests/mesh.rs`) check this against an exact brute force over all pairs.
//!
//! # The tree
//! A binary tree of axis-aligned boxes in the mesh's own frame, split at the median centroid
//! along the widest axis, at most [`LEAF`] triangles per leaf. Boxes are moved with the pose
//! (centre moved, half-extent through `|R|`), which keeps them conservative for any rotation.

use crate::engine::Outputs;
use crate::{ClosestPoints, Engine, Error, Intersection, Point, Pose, Query, Real, Triangle};

/// Most triangles per leaf.
pub const LEAF: usize = 4;

/// Triangle pairs gathered before the kernels run on them.
const FLUSH: usize = 64;

/// An indexed triangle mesh and its bounding-volume hierarchy.
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
        let mut m = Mesh { vertices, triangles, nodes: Vec::new(), order: Vec::new() };
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
        let tri_f64 = |i: usize| self.triangle(i).map(|v| v.map(Real::to_f64));
        let boxes: Vec<([f64; 3], [f64; 3])> = (0..n)
            .map(|i| {
                let t = tri_f64(i);
                let mut lo = t[0];
                let mut hi = t[0];
                for v in &t[1..] {
                    for k in 0..3 {
                        lo[k] = lo[k].min(v[k]);
                        hi[k] = hi[k].max(v[k]);
                    }
                }
                (lo, hi)
            })
            .collect();
        let centroid = |i: u32| {
            let (lo, hi) = boxes[i as usize];
            [0, 1, 2].map(|k| 0.5 * lo[k] + 0.5 * hi[k])
        };
        self.order = (0..n as u32).collect();
        self.nodes.push(Node { lo: [0.0; 3], hi: [0.0; 3], first: 0, count: 0 });
        // (node, range of `order`) still to be built
        let mut todo = vec![(0usize, 0usize, n)];
        while let Some((id, s, e)) = todo.pop() {
            let mut lo = [f64::INFINITY; 3];
            let mut hi = [f64::NEG_INFINITY; 3];
            let (mut clo, mut chi) = (lo, hi);
            for &t in &self.order[s..e] {
                let (a, b) = boxes[t as usize];
                let c = centroid(t);
                for k in 0..3 {
                    lo[k] = lo[k].min(a[k]);
                    hi[k] = hi[k].max(b[k]);
                    clo[k] = clo[k].min(c[k]);
                    chi[k] = chi[k].max(c[k]);
                }
            }
            if e - s <= LEAF {
                self.nodes[id] = Node { lo, hi, first: s as u32, count: (e - s) as u32 };
                continue;
            }
            let axis = (0..3).max_by(|&a, &b| (chi[a] - clo[a]).total_cmp(&(chi[b] - clo[b]))).unwrap_or(0);
            let mid = s + (e - s) / 2;
            self.order[s..e]
                .select_nth_unstable_by(mid - s, |&a, &b| centroid(a)[axis].total_cmp(&centroid(b)[axis]));
            let left = self.nodes.len();
            self.nodes.push(Node { lo: [0.0; 3], hi: [0.0; 3], first: 0, count: 0 });
            self.nodes.push(Node { lo: [0.0; 3], hi: [0.0; 3], first: 0, count: 0 });
            self.nodes[id] = Node { lo, hi, first: left as u32, count: 0 };
            todo.push((left, s, mid));
            todo.push((left + 1, mid, e));
        }
    }

    /// Node `i`'s box moved by `pose` (see [`Moved`]).
    fn moved_box(&self, i: usize, pose: &Moved) -> ([f64; 3], [f64; 3]) {
        let n = &self.nodes[i];
        let c = [0, 1, 2].map(|k| 0.5 * n.lo[k] + 0.5 * n.hi[k]);
        let h = [0, 1, 2].map(|k| 0.5 * n.hi[k] - 0.5 * n.lo[k]);
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

/// A pose in f64 with the relative slack that makes moved boxes contain the moved vertices.
struct Moved {
    r: [[f64; 3]; 3],
    t: [f64; 3],
    rel: f64,
}

impl Moved {
    fn of<T: Real>(p: &Pose<T>) -> Moved {
        Moved {
            r: p.rotation.map(|row| row.map(Real::to_f64)),
            t: p.translation.map(Real::to_f64),
            rel: 4.0 * T::UNIT_ROUNDOFF.to_f64() + 16.0 * f64::EPSILON,
        }
    }

    /// `mesh`'s moved root box, or [`Error::NonFiniteCoordinate`] when it leaves the range of
    /// `T` (a moved vertex could overflow).
    fn root<T: Real>(&self, mesh: &Mesh<T>) -> Result<([f64; 3], [f64; 3]), Error> {
        let b = mesh.moved_box(0, self);
        if b.0.iter().chain(&b.1).all(|x| x.abs() <= T::MAX.to_f64()) {
            Ok(b)
        } else {
            Err(Error::NonFiniteCoordinate)
        }
    }
}

/// Squared distance between two boxes, rounded down (a lower bound of the exact one).
fn box_gap2(a: &([f64; 3], [f64; 3]), b: &([f64; 3], [f64; 3])) -> f64 {
    let mut s = 0.0;
    for k in 0..3 {
        let g = (b.0[k] - a.1[k]).max(a.0[k] - b.1[k]).max(0.0);
        s += g * g;
    }
    s * (1.0 - 8.0 * f64::EPSILON)
}

/// Squared distance from a point to a box, rounded down.
fn point_gap2(x: &[f64; 3], b: &([f64; 3], [f64; 3])) -> f64 {
    let mut s = 0.0;
    for k in 0..3 {
        let g = (b.0[k] - x[k]).max(x[k] - b.1[k]).max(0.0);
        s += g * g;
    }
    s * (1.0 - 8.0 * f64::EPSILON)
}

/// The largest absolute coordinate of two boxes: a bound of the magnitude `S` of every
/// triangle pair in them.
fn magnitude(a: &([f64; 3], [f64; 3]), b: &([f64; 3], [f64; 3])) -> f64 {
    a.0.iter().chain(&a.1).chain(&b.0).chain(&b.1).fold(0.0f64, |s, v| s.max(v.abs()))
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

    /// Gathers the triangle pairs of two leaves, moved; with `limit`, only the pairs whose
    /// moved triangles' boxes are not farther apart (squared, a lower bound) than `limit`.
    #[allow(clippy::too_many_arguments)]
    fn push_leaves(
        &mut self,
        ma: &Mesh<T>,
        pa: &Pose<T>,
        la: &Node,
        mb: &Mesh<T>,
        pb: &Pose<T>,
        lb: &Node,
        limit: Option<f64>,
    ) {
        let bx = |t: &Triangle<T>| {
            let f = t.map(|v| v.map(Real::to_f64));
            let lo = [0, 1, 2].map(|k| f[0][k].min(f[1][k]).min(f[2][k]));
            let hi = [0, 1, 2].map(|k| f[0][k].max(f[1][k]).max(f[2][k]));
            (lo, hi)
        };
        let mut tb = [[[T::ZERO; 3]; 3]; LEAF];
        let mut bb = [([0.0; 3], [0.0; 3]); LEAF];
        let js = &mb.order[lb.first as usize..(lb.first + lb.count) as usize];
        for (k, &j) in js.iter().enumerate() {
            tb[k] = mb.triangle_at(j as usize, pb);
            bb[k] = bx(&tb[k]);
        }
        for &i in &ma.order[la.first as usize..(la.first + la.count) as usize] {
            let ta = ma.triangle_at(i as usize, pa);
            let ba = bx(&ta);
            for (k, &j) in js.iter().enumerate() {
                if limit.is_some_and(|l| box_gap2(&ba, &bb[k]) > l) {
                    continue;
                }
                self.ids.push((i, j));
                self.a.push(ta);
                self.b.push(tb[k]);
            }
        }
    }

    fn clear(&mut self) {
        self.ids.clear();
        self.a.clear();
        self.b.clear();
    }
}

/// Node pairs in traversal order: the pairs on top of the stack are visited first.
type Stack = Vec<(f64, u32, u32)>;

/// Pushes the children pairs of (a, b), splitting the larger internal node, nearest last so
/// that it is visited first.
fn descend<T: Real>(
    ma: &Mesh<T>,
    mva: &Moved,
    mb: &Mesh<T>,
    mvb: &Moved,
    (a, b): (u32, u32),
    stack: &mut Stack,
) {
    let (na, nb) = (&ma.nodes[a as usize], &mb.nodes[b as usize]);
    let extent = |n: &Node| (0..3).map(|k| n.hi[k] - n.lo[k]).fold(0.0, f64::max);
    let split_a = nb.count > 0 || (na.count == 0 && extent(na) >= extent(nb));
    let pairs = if split_a { [(na.first, b), (na.first + 1, b)] } else { [(a, nb.first), (a, nb.first + 1)] };
    let mut gaps = pairs.map(|(x, y)| {
        let g = box_gap2(&ma.moved_box(x as usize, mva), &mb.moved_box(y as usize, mvb));
        (g, x, y)
    });
    if gaps[0].0 < gaps[1].0 {
        gaps.swap(0, 1);
    }
    stack.extend(gaps);
}

fn check_finite<T: Real>(d: T) -> Result<(), Error> {
    if d.is_nan() {
        Err(Error::NonFiniteCoordinate)
    } else {
        Ok(())
    }
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
        pose_a.check()?;
        pose_b.check()?;
        if a.is_empty() || b.is_empty() {
            return Ok(None);
        }
        let (mva, mvb) = (Moved::of(pose_a), Moved::of(pose_b));
        let (ra, rb) = (mva.root(a)?, mvb.root(b)?);
        let mut best: Option<MeshDistance<T>> = None;
        let mut best_d = f64::INFINITY;
        let mut pend = Pending::new();
        let mut out = Vec::new();
        let mut flush = |pend: &mut Pending<T>, best: &mut Option<MeshDistance<T>>, best_d: &mut f64| {
            out.clear();
            out.resize(pend.ids.len(), ClosestPoints::default());
            self.closest_points_triangle_triangle(&pend.a, &pend.b, &mut out)?;
            for (k, cp) in out.iter().enumerate() {
                check_finite(cp.sqdist)?;
                let d = cp.sqdist.to_f64();
                // ties among the pairs answered go to the smaller triangle numbers (pairs at
                // exactly the best distance are never pruned: box gaps are lower bounds)
                let (i, j) = pend.ids[k];
                let better = match best {
                    None => true,
                    Some(m) => d < *best_d || (d == *best_d && (i as usize, j as usize) < (m.tri_a, m.tri_b)),
                };
                if better {
                    *best_d = d;
                    *best = Some(MeshDistance {
                        sqdist: cp.sqdist,
                        p: cp.p,
                        q: cp.q,
                        tri_a: i as usize,
                        tri_b: j as usize,
                    });
                }
            }
            pend.clear();
            Ok::<(), Error>(())
        };
        let root = box_gap2(&ra, &rb);
        let mut stack: Stack = vec![(root, 0, 0)];
        while let Some((gap, x, y)) = stack.pop() {
            // `<=`: pairs at the best distance are still visited, for the tie rule
            if gap > best_d {
                continue;
            }
            let (nx, ny) = (&a.nodes[x as usize], &b.nodes[y as usize]);
            if nx.count > 0 && ny.count > 0 {
                pend.push_leaves(a, pose_a, nx, b, pose_b, ny, Some(best_d));
                // the first pairs (nearest first) run at once: their answer prunes the rest
                if pend.ids.len() >= FLUSH || (best.is_none() && !pend.ids.is_empty()) {
                    flush(&mut pend, &mut best, &mut best_d)?;
                }
            } else {
                descend(a, &mva, b, &mvb, (x, y), &mut stack);
            }
        }
        if !pend.ids.is_empty() {
            flush(&mut pend, &mut best, &mut best_d)?;
        }
        Ok(best)
    }

    /// Every triangle pair of two meshes in their poses whose distance is at most `margin`
    /// (contact generation), each with its squared distance and closest points, ordered by
    /// squared distance then triangle numbers; with `cap`, the first `cap` of that order.
    ///
    /// Within the margin is decided as [`Engine::within_margin_triangle_triangle`] decides it
    /// (the full triangle-triangle answer, thresholded), pair by pair.
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
        pose_a.check()?;
        pose_b.check()?;
        let e = self.margin(margin.to_f64())?;
        let mut found = Vec::new();
        if a.is_empty() || b.is_empty() {
            return Ok(found);
        }
        let (mva, mvb) = (Moved::of(pose_a), Moved::of(pose_b));
        mva.root(a)?;
        mvb.root(b)?;
        let (m, tol) = (margin.to_f64(), e.current_tolerance());
        let mut pend = Pending::new();
        let mut d = Vec::new();
        let mut cp = Vec::new();
        let mut flush = |pend: &mut Pending<T>, found: &mut Vec<Contact<T>>| {
            d.clear();
            d.resize(pend.ids.len(), T::ZERO);
            e.run(Query::Within, &pend.a, &pend.b, Outputs::new().sqdist(&mut d))?;
            // closest points for the pairs within the margin
            let (mut wa, mut wb, mut wid) = (Vec::new(), Vec::new(), Vec::new());
            for (k, &dk) in d.iter().enumerate() {
                check_finite(dk)?;
                if dk.is_finite() {
                    wa.push(pend.a[k]);
                    wb.push(pend.b[k]);
                    wid.push(pend.ids[k]);
                }
            }
            cp.clear();
            cp.resize(wa.len(), ClosestPoints::default());
            self.closest_points_triangle_triangle(&wa, &wb, &mut cp)?;
            for (c, &(i, j)) in cp.iter().zip(&wid) {
                found.push(Contact {
                    tri_a: i as usize,
                    tri_b: j as usize,
                    sqdist: c.sqdist,
                    p: c.p,
                    q: c.q,
                });
            }
            pend.clear();
            Ok::<(), Error>(())
        };
        let mut stack: Stack = vec![(0.0, 0, 0)];
        while let Some((_, x, y)) = stack.pop() {
            let (bx, by) = (a.moved_box(x as usize, &mva), b.moved_box(y as usize, &mvb));
            let lim = reach::<T>(&tol, magnitude(&bx, &by), m);
            if box_gap2(&bx, &by) > lim * lim {
                continue;
            }
            let (nx, ny) = (&a.nodes[x as usize], &b.nodes[y as usize]);
            if nx.count > 0 && ny.count > 0 {
                pend.push_leaves(a, pose_a, nx, b, pose_b, ny, Some(lim * lim));
                if pend.ids.len() >= FLUSH {
                    flush(&mut pend, &mut found)?;
                }
            } else {
                descend(a, &mva, b, &mvb, (x, y), &mut stack);
            }
        }
        if !pend.ids.is_empty() {
            flush(&mut pend, &mut found)?;
        }
        found.sort_by(|p, q| {
            p.sqdist.to_f64().total_cmp(&q.sqdist.to_f64()).then((p.tri_a, p.tri_b).cmp(&(q.tri_a, q.tri_b)))
        });
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
        pose_a.check()?;
        pose_b.check()?;
        if a.is_empty() || b.is_empty() {
            return Ok(None);
        }
        let (mva, mvb) = (Moved::of(pose_a), Moved::of(pose_b));
        mva.root(a)?;
        mvb.root(b)?;
        let mut pend = Pending::new();
        let mut v = Vec::new();
        let mut flush = |pend: &mut Pending<T>| {
            v.clear();
            v.resize(pend.ids.len(), Intersection::Invalid);
            self.intersect_triangle_triangle(&pend.a, &pend.b, &mut v)?;
            let mut hit: Option<(usize, usize)> = None;
            for (k, r) in v.iter().enumerate() {
                match r {
                    Intersection::Invalid => return Err(Error::NonFiniteCoordinate),
                    Intersection::Intersecting => {
                        let (i, j) = pend.ids[k];
                        let p = (i as usize, j as usize);
                        hit = Some(hit.map_or(p, |h| h.min(p)));
                    }
                    Intersection::Disjoint => {}
                }
            }
            pend.clear();
            Ok::<_, Error>(hit)
        };
        // "Intersecting" is said of pairs within the tolerance of touching: boxes that far
        // apart are kept.
        let tol = self.current_tolerance();
        let mut stack: Stack = vec![(0.0, 0, 0)];
        while let Some((_, x, y)) = stack.pop() {
            let (bx, by) = (a.moved_box(x as usize, &mva), b.moved_box(y as usize, &mvb));
            let lim = reach::<T>(&tol, magnitude(&bx, &by), 0.0);
            if box_gap2(&bx, &by) > lim * lim {
                continue;
            }
            let (nx, ny) = (&a.nodes[x as usize], &b.nodes[y as usize]);
            if nx.count > 0 && ny.count > 0 {
                pend.push_leaves(a, pose_a, nx, b, pose_b, ny, Some(lim * lim));
                if pend.ids.len() >= FLUSH {
                    if let Some(h) = flush(&mut pend)? {
                        return Ok(Some(h));
                    }
                }
            } else {
                descend(a, &mva, b, &mvb, (x, y), &mut stack);
            }
        }
        if !pend.ids.is_empty() {
            return flush(&mut pend);
        }
        Ok(None)
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
        mv.root(m)?;
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
