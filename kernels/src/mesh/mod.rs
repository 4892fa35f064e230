//! Mesh-vs-mesh queries: an indexed triangle mesh with a bounding-volume hierarchy built once,
//! queried in any pose (the mesh is never rebuilt when it moves). The traversal gathers the
//! candidate triangle pairs into batches and the batch kernels ([`Engine`]) do all leaf work,
//! a vector of pairs at a time, so every mesh answer is a kernel answer with its guarantees.
//!
//! # Accuracy
//! A mesh answer is the kernels' answer on the triangles *as moved*: each vertex is moved by
//! [`Pose::apply`] in the working precision, and those rounded triangles are what the kernels
//! answer, within the engine's [`crate::Tolerance`]. Pruning never loses an answer: a node
//! pair is skipped only when its bounds (in f64, enlarged by the rounding of the motion) prove
//! every triangle pair in it farther than the margin (contacts), apart (intersection), or
//! farther than the smallest answer so far less a slack of [`Engine::MESH_DISTANCE_SLACK`]
//! `u S`, capped by the tolerance and widened to the tolerance's width after
//! [`Engine::MESH_DISTANCE_WIDEN_AFTER`] pairs (distance; the search ends at an answer of 0).
//! So the distance is one pair's kernel answer, at most that slack above the smallest kernel
//! answer over all pairs of moved triangles; the contact set holds every pair within the
//! margin (decided by the kernels as [`Engine::within_margin_triangle_triangle`] does); and
//! intersection is the kernels' verdict on some pair, or `None` when every pair is disjoint.
//! The clearance check ([`Engine::mesh_within_margin`]) decides as the contact set does and
//! stops at its first pair within the margin. `scenes/tests/mesh.rs` checks all of this
//! against an exact brute force over all pairs.
//!
//! # Files
//! One concern a file, arrows pointing down this list:
//! - `queries.rs`: the [`Engine`] methods, each a [`traverse::search`] with one searcher;
//! - `distance.rs` ([`Engine::mesh_distance`], [`Engine::mesh_closest_point`]),
//!   `contacts.rs` ([`Engine::mesh_contacts`], its sorting and threads), `intersect.rs`
//!   ([`Engine::mesh_intersect`], [`Engine::mesh_within_margin`]): the searchers, each a
//!   [`traverse::Search`] deciding what a batch of leaf pairs means and what prunes;
//! - `traverse.rs`: the one walk every query shares, node pairs ordered depth first, overlap
//!   first or best first by the searcher;
//! - `scratch.rs`: what a query keeps per side (moved node bounds, moved leaves, candidate
//!   pairs), reused across queries of a thread;
//! - `bounds.rs`: boxes, oriented boxes and their certified fit, moved poses, the gaps that
//!   prune; the node test itself is lane-generic code in `crate::algo::nodes`;
//! - `build.rs`: the tree (binned surface-area splits collapsed to [`TreeShape::width`]
//!   children per node).
//!
//! # The tree
//! A binary tree of binned surface-area splits along the widest axis of the triangles' box
//! centres (the median where no such split leaves two triangles on each side), at most
//! [`TreeShape::leaf`] triangles per leaf, collapsed into a tree of up to
//! [`TreeShape::width`] children per node (a node's children are the binary descendants found
//! by opening the one of largest box area until there are that many: the same splits at every
//! width). Each node has two bounds: an axis-aligned box in the mesh frame, moved with the
//! pose (conservative for any linear map), and an oriented box on the principal axes of its
//! vertices, certified to contain every vertex exactly despite f64 rounding and moved exactly
//! as a parallelepiped. A node pair's lower bound is the larger of the two gaps.
//!
//! # The traversal
//! From each node pair taken, the walk splits the larger node (all its children against the
//! other node, one node test on the engine's lanes) and dives along the nearest child pairs.
//! Contacts take node pairs depth first; intersection too, but overlapping pairs before
//! apart ones (so that far from the origin a hit is still found at once); distance best
//! first (a heap by lower bound), ending at the first pair whose bound exceeds the best
//! answer less the slack. Overlapping pairs are taken deepest overlap first. A query first
//! tests the two roots' boxes alone and ends there when their gap exceeds its limit.
//!
//! Why these choices (split, width, leaf size, orders, slack), with the measurements and the
//! alternatives dropped: `docs/notes/mesh.md` in the repository.

mod bounds;
mod build;
mod contacts;
mod distance;
mod intersect;
mod queries;
mod scratch;
#[cfg(test)]
mod tests;
mod traverse;

use crate::algo::nodes::{MAX_LEAF, MAX_WIDTH};
use crate::{Error, Point, Pose, Real, Triangle};
// The unit tests (`tests.rs`) see every item of the module's files, as they did in one file.
#[cfg(test)]
use {
    crate::algo::nodes::{LeafTest, Limit, Moved, HI, LO, ROWS},
    crate::{ClosestPoints, Engine, Intersection},
    bounds::*,
    build::*,
    contacts::*,
    distance::*,
    intersect::*,
    scratch::*,
    traverse::*,
};

/// The shape of a mesh's tree ([`Mesh::with_shape`]): how many children a node and how many
/// triangles a leaf holds at most. The splits are the same at every shape (a larger leaf
/// stops them earlier), and so are the answers, as far as the queries define them: the
/// contact set (each pair decided by the kernels alone), the intersection verdict, the
/// clearance check's yes or no and the closest point's distance are the same for every tree
/// (the pair an intersection or a clearance check names may differ: the first found); the
/// distance is within the search's slack ([`Engine::MESH_DISTANCE_SLACK`](crate::Engine::MESH_DISTANCE_SLACK)) of the same smallest
/// kernel answer, and where pairs tie within that slack another tree may answer another of
/// them. Only the time is meant to differ (the differential tests run leaves of 1 and 8 and
/// widths of 2 and 8).
///
/// The default ([`TreeShape::DEFAULT`]: 4 children, 4 triangles) is the fastest distance query
/// on the report's meshes (`docs/notes/mesh.md` in the repository says how it was chosen). Larger leaves trade the node tests a query makes for triangle pairs it hands the
/// kernels: they suit callers whose time goes into contact sets (`Engine::mesh_contacts`,
/// which walks every node pair within its margin) and into building trees. `reports/MESH.md`
/// ("Leaf size", regenerated by the report command) times leaves of 2, 4, 6 and 8 triangles
/// for every query and the build on the same meshes and poses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TreeShape {
    /// Most children of a node: 2 to [`TreeShape::MAX_WIDTH`].
    pub width: usize,
    /// Most triangles of a leaf: 1 to [`TreeShape::MAX_LEAF`].
    pub leaf: usize,
}

impl Default for TreeShape {
    /// [`TreeShape::DEFAULT`].
    fn default() -> Self {
        TreeShape::DEFAULT
    }
}

impl TreeShape {
    /// The shape of [`Mesh::new`]: 4 children per node, 4 triangles per leaf.
    pub const DEFAULT: TreeShape = TreeShape { width: 4, leaf: 4 };
    /// Most children of a node a tree may be asked for.
    pub const MAX_WIDTH: usize = MAX_WIDTH;
    /// Most triangles of a leaf a tree may be asked for.
    pub const MAX_LEAF: usize = MAX_LEAF;

    /// `Ok` for a shape [`Mesh::with_shape`] builds: [`Error::InvalidTreeWidth`] for a width
    /// outside `2..=8` (named first), [`Error::InvalidLeafSize`] for a leaf size outside
    /// `1..=8`.
    pub fn check(&self) -> Result<(), Error> {
        if !(2..=MAX_WIDTH).contains(&self.width) {
            return Err(Error::InvalidTreeWidth(self.width));
        }
        if !(1..=MAX_LEAF).contains(&self.leaf) {
            return Err(Error::InvalidLeafSize(self.leaf));
        }
        Ok(())
    }
}

/// Triangle pairs gathered before the kernels run on them ([`Search::batch`]'s default): few,
/// so that a distance query's first answers prune the rest.
const FLUSH: usize = 64;

/// Triangle pairs the contact query gathers before the kernels run on them where no cap
/// narrows it (with a cap, the cap's size within [`FLUSH`] and this: the search narrows only
/// after a batch, and holds up to `2 cap` contacts and a batch meanwhile). It visits every
/// node pair within its margin whatever the kernels answer, so a batch prunes nothing, and
/// larger ones run the kernels in fuller vectors: the pairs of a chunk that the quick stage
/// leaves open (18 % of the candidates at near contact, docs/notes/kernel-speed.md) fill a mostly empty
/// vector of the full stage. `spin mesh contacts n3|5 f32 1 1`, against batches of 64, two
/// copies alternated three rounds: 256, 0.717-0.767 against 0.772-0.791 ms at n3 and
/// 10.45-11.19 against 10.84-11.40 at pose 5; 1024, 0.708-0.751 and 10.36-10.47.
const CONTACT_FLUSH: usize = 1024;

/// An indexed triangle mesh and its bounding-volume hierarchy.
///
/// Memory: besides the mesh (its vertices, and its triangles' vertex numbers twice: as given,
/// and in the tree's leaf order for the queries) and its tree, each thread that runs
/// mesh-vs-mesh queries keeps a scratch (two per query, sized by the largest trees and queries
/// it met) of 20 bytes per tree node, and the moved bounds of the nodes a query reached: 256
/// bytes per node, and 256 bytes times the width rounded up to 4 per node whose children were
/// tested (at most about 9 MB per side for the 52,000 triangles of the Armadillo, when a query
/// reaches every node). So starting a query costs nothing whatever the meshes' sizes.
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
/// assert!(e.mesh_within_margin(&a, &here, &b, &there, 2.5)?.is_some()); // clearance check
/// assert_eq!(e.mesh_within_margin(&a, &here, &b, &there, 1.5)?, None);
/// let p = e.mesh_closest_point(&b, &there, [5.0, 0.0, 0.0])?.unwrap(); // point to mesh
/// assert_eq!(p.sqdist, 1.0);
/// # Ok::<(), tridist::Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct Mesh<T> {
    vertices: Vec<Point<T>>,
    triangles: Vec<[u32; 3]>,
    nodes: Vec<Node>,
    /// Per node, its oriented box (an `Obb` fitted to its vertices) and its axis-aligned box,
    /// as rows ([`crate::algo::nodes::SROWS`]; row `r` of node `i` at `r * bounds_stride + i`,
    /// the nodes past the last copies of it).
    bounds: Vec<f64>,
    bounds_stride: usize,
    /// Triangle numbers in leaf order.
    order: Vec<u32>,
    /// The triangles' vertex numbers in leaf order (`triangles[order[k]]`), read in sequence
    /// when a query moves a leaf's triangles.
    leaf_tris: Vec<[u32; 3]>,
    /// Most children of a node and most triangles of a leaf.
    shape: TreeShape,
}

/// A node: a box in the mesh frame (f64) and either `kids` children (`count == 0`: at
/// `first..first + kids`) or `count` triangles at `order[first..]`.
#[derive(Clone, Copy, Debug)]
struct Node {
    lo: [f64; 3],
    hi: [f64; 3],
    first: u32,
    count: u32,
    kids: u32,
}

/// A node of the binary tree every tree is collapsed from: its box, its triangles
/// (`items[s..e]`) and its children.
#[derive(Clone, Copy)]
struct Bin {
    lo: [f64; 3],
    hi: [f64; 3],
    s: usize,
    e: usize,
    kids: Option<[usize; 2]>,
}

/// The closest pair of two meshes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshDistance<T> {
    /// Squared distance.
    pub sqdist: T,
    /// The distance: `Some(sqdist.sqrt())` (one more rounding; `+inf` where the square
    /// overflows), except under [`Tolerance::CORRECTLY_ROUNDED`](crate::Tolerance::CORRECTLY_ROUNDED),
    /// where it is the smallest exact distance over all triangle pairs correctly rounded,
    /// `RN(sqrt(D*))`, decided on its own (not the root of the rounded square, which can be an
    /// ulp off), or `None` when it could not be decided without the exact oracle (feature
    /// `exact`): the square is then still correctly rounded.
    pub distance: Option<T>,
    /// Closest point on the first mesh (moved).
    pub p: Point<T>,
    /// Closest point on the second mesh (moved).
    pub q: Point<T>,
    /// The triangle of the first mesh that holds `p`.
    pub tri_a: usize,
    /// The triangle of the second mesh that holds `q`.
    pub tri_b: usize,
}

/// A triangle pair within the margin ([`Engine::mesh_contacts`](crate::Engine::mesh_contacts)).
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

/// The closest point of a mesh to a query point ([`Engine::mesh_closest_point`](crate::Engine::mesh_closest_point)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshPoint<T> {
    /// Squared distance.
    pub sqdist: T,
    /// The distance, as [`MeshDistance::distance`] gives it: `Some(sqdist.sqrt())`, or under
    /// [`Tolerance::CORRECTLY_ROUNDED`](crate::Tolerance::CORRECTLY_ROUNDED) the exact
    /// minimum's correctly rounded, `None` when that is undecided.
    pub distance: Option<T>,
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
        Self::with_shape(vertices, triangles, TreeShape::default())
    }

    /// [`Mesh::new`] with a tree of `width` children per node (2 to [`TreeShape::MAX_WIDTH`]): the same
    /// binary splits collapsed, so every width has the same tree quality; the answers
    /// are the same at every width as [`TreeShape`] says (only the time is meant to differ;
    /// the module's documentation says which width is the default, and why).
    ///
    /// # Errors
    /// As [`Mesh::new`], and [`Error::InvalidTreeWidth`] for a width outside `2..=8`.
    pub fn with_width(
        vertices: Vec<Point<T>>,
        triangles: Vec<[u32; 3]>,
        width: usize,
    ) -> Result<Mesh<T>, Error> {
        Self::with_shape(vertices, triangles, TreeShape { width, ..TreeShape::default() })
    }

    /// [`Mesh::new`] with a tree of the given shape ([`TreeShape`]: children per node and
    /// triangles per leaf). Every shape gives the same answers, as [`TreeShape`] says; the
    /// time differs.
    ///
    /// # Errors
    /// As [`Mesh::new`], and those of [`TreeShape::check`]: [`Error::InvalidTreeWidth`] for
    /// a width outside `2..=8`, [`Error::InvalidLeafSize`] for a leaf size outside `1..=8`.
    pub fn with_shape(
        vertices: Vec<Point<T>>,
        triangles: Vec<[u32; 3]>,
        shape: TreeShape,
    ) -> Result<Mesh<T>, Error> {
        shape.check()?;
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
        let mut m = Mesh {
            vertices,
            triangles,
            nodes: Vec::new(),
            bounds: Vec::new(),
            bounds_stride: 0,
            order: Vec::new(),
            leaf_tris: Vec::new(),
            shape,
        };
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

    /// Most children of a tree node ([`Mesh::with_width`]).
    pub fn width(&self) -> usize {
        self.shape.width
    }

    /// The tree's shape: most children of a node and most triangles of a leaf
    /// ([`Mesh::with_shape`]).
    pub fn shape(&self) -> TreeShape {
        self.shape
    }

    /// Triangle `i` in the mesh's own frame; `None` when the mesh has no triangle `i`.
    pub fn triangle(&self, i: usize) -> Option<Triangle<T>> {
        (i < self.triangles.len()).then(|| self.tri(i))
    }

    /// Triangle `i` moved by `pose`, exactly as the queries move it ([`Pose::apply`]); `None`
    /// when the mesh has no triangle `i`.
    pub fn triangle_at(&self, i: usize, pose: &Pose<T>) -> Option<Triangle<T>> {
        (i < self.triangles.len()).then(|| self.tri(i).map(|v| pose.apply(v)))
    }

    /// Triangle `i` (below [`Mesh::len`]: the index checks of [`Mesh::new`] hold).
    pub(crate) fn tri(&self, i: usize) -> Triangle<T> {
        self.triangles[i].map(|v| self.vertices[v as usize])
    }

    /// The triangle at position `k` of the leaf order (number `order[k]`) moved by `pose`, as
    /// [`Mesh::triangle_at`] moves it: its vertex numbers read from `leaf_tris`, in sequence
    /// along a leaf, not from `triangles` in the order of the triangle numbers (there the
    /// load of the numbers missed the cache, and moving the leaves took 9 % of a deep contact
    /// query's time: `perf` of `spin mesh contacts 5 f32 1 4`).
    fn leaf_triangle_at(&self, k: usize, pose: &Pose<T>) -> Triangle<T> {
        self.leaf_tris[k].map(|v| pose.apply(self.vertices[v as usize]))
    }
}
