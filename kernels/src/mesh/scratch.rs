//! What a query keeps per side while it walks: the candidate pairs waiting for the kernels
//! ([`Pending`]), each side's moved node bounds and moved leaves ([`Side`]), and the per-thread
//! node-indexed stamps that make starting a query free ([`Slots`]).

use super::bounds::{tri_box, Aabb};
use super::{Mesh, FLUSH};
use crate::algo::nodes::LeafTest;
use crate::algo::nodes::Moved;
use crate::algo::nodes::HI;
use crate::algo::nodes::LO;
use crate::algo::nodes::MAX_LEAF;
use crate::algo::nodes::ROWS;
use crate::Pose;
use crate::Real;
use crate::Triangle;

/// Candidate triangle pairs, moved, waiting for the kernels.
pub(super) struct Pending<T> {
    pub(super) ids: Vec<(u32, u32)>,
    pub(super) a: Vec<Triangle<T>>,
    pub(super) b: Vec<Triangle<T>>,
}

impl<T: Real> Pending<T> {
    pub(super) fn new() -> Self {
        Pending { ids: Vec::with_capacity(FLUSH + MAX_LEAF * MAX_LEAF), a: Vec::new(), b: Vec::new() }
    }

    /// Gathers the triangle pairs of two moved leaves whose triangles' boxes are not farther
    /// apart (squared, a lower bound: [`box_gap2`]) than `limit`, tested on `isa`
    /// ([`crate::algo::nodes::leaf_pairs`]), but for those in `apart` (bit `i * MAX_LEAF + j`
    /// for triangle `i` of `la` and `j` of `lb`: pairs the searcher knows to be beyond it).
    pub(super) fn push_leaves(
        &mut self,
        isa: crate::Isa,
        la: Leaf<'_, T>,
        lb: Leaf<'_, T>,
        limit: f64,
        apart: u64,
    ) {
        let t = LeafTest { a: la.rows, na: la.ids.len(), b: lb.rows, nb: lb.ids.len(), limit };
        let mut near = 0;
        crate::arch::leaf_pairs(isa, &t, &mut near);
        near &= !apart;
        while near != 0 {
            let k = near.trailing_zeros() as usize;
            near &= near - 1;
            let (i, j) = (k / MAX_LEAF, k % MAX_LEAF);
            self.ids.push((la.ids[i], lb.ids[j]));
            self.a.push(la.tris[i]);
            self.b.push(lb.tris[j]);
        }
    }

    pub(super) fn clear(&mut self) {
        self.ids.clear();
        self.a.clear();
        self.b.clear();
    }
}

/// A leaf's triangle numbers and its triangles moved by the query's pose
/// ([`Mesh::leaf_triangle_at`]), with their boxes as rows ([`Side::leaf`]).
#[derive(Clone, Copy)]
pub(super) struct Leaf<'s, T> {
    pub(super) ids: &'s [u32],
    pub(super) tris: &'s [Triangle<T>],
    /// The triangles' boxes as [`LeafTest`] reads them: six rows of one number per triangle,
    /// then [`MAX_LEAF`] more.
    pub(super) rows: &'s [f64],
}

/// Node-indexed scratch of a [`Side`], reused by the queries of one thread: an entry counts
/// only when it carries the current query's stamp, so starting a query costs nothing whatever
/// the trees' sizes (two fresh `vec![u32::MAX; nodes]` per side were most of a collision
/// query's time on separated poses). Kept per thread, for each side alive at once (see
/// [`Mesh`] for the sizes).
#[derive(Default)]
pub(super) struct Slots {
    pub(super) stamp: u32,
    /// Per node: the stamp of the query that wrote it, the group and lane of its moved bounds
    /// in `groups`, where its moved triangles start in `Side::tris`, the group of its children (groups numbered
    /// from 0, at most one per node and the root's own; `u32::MAX`: not reached yet).
    pub(super) v: Vec<[u32; 5]>,
    /// The moved bounds of the nodes reached, in groups of siblings of `ROWS * stride` numbers
    /// ([`NodeTest`], [`Side::group`]). (Kept from query to query with the rest: allocated
    /// afresh, they were page faults for 19 % of a deep contact query's time.)
    pub(super) groups: Vec<f64>,
}

std::thread_local! {
    static SLOTS: core::cell::RefCell<Vec<Slots>> = const { core::cell::RefCell::new(Vec::new()) };
}

impl Slots {
    /// Scratch for a tree of `n` nodes, every entry unset.
    pub(super) fn take(n: usize) -> Slots {
        let mut s = SLOTS.with(|p| p.borrow_mut().pop()).unwrap_or_default();
        if s.v.len() < n {
            s.v.resize(n, [0; 5]);
        }
        s.groups.clear();
        s.stamp = s.stamp.wrapping_add(1);
        if s.stamp == 0 {
            // after 2^32 queries: forget every stamp (0 is never current)
            s.v.iter_mut().for_each(|e| e[0] = 0);
            s.stamp = 1;
        }
        s
    }

    /// Node `i`'s entry for this query: `[_, bounds group, bounds lane, leaf start, children's group]`.
    pub(super) fn entry(&mut self, i: u32) -> &mut [u32; 5] {
        let e = &mut self.v[i as usize];
        if e[0] != self.stamp {
            *e = [self.stamp, u32::MAX, 0, u32::MAX, u32::MAX];
        }
        e
    }
}

/// One mesh of a query in its pose, with what the traversal has moved so far: each node's
/// bounds and each leaf's triangles are moved once per query (a node meets many nodes of the
/// other mesh).
pub(super) struct Side<'m, T> {
    pub(super) mesh: &'m Mesh<T>,
    pub(super) pose: &'m Pose<T>,
    /// The instruction set of the query's node tests, which also moves the bounds.
    pub(super) isa: crate::Isa,
    pub(super) mv: Moved,
    pub(super) slots: Slots,
    /// Numbers per row of a group of children (`Slots::groups`).
    pub(super) stride: usize,
    /// The moved triangles of the leaves reached, each leaf's together, and their boxes: the
    /// leaf whose triangles start at `k` in `tris` has its boxes' rows ([`Leaf::rows`]) at
    /// `6 k` in `rows`.
    pub(super) tris: Vec<Triangle<T>>,
    pub(super) rows: Vec<f64>,
}

impl<T> Drop for Side<'_, T> {
    fn drop(&mut self) {
        let s = core::mem::take(&mut self.slots);
        // a thread keeps as many as it had sides alive at once (two per query)
        let _ = SLOTS.try_with(|p| p.borrow_mut().push(s));
    }
}

impl<'m, T: Real> Side<'m, T> {
    /// The side of `mesh` in `pose`, moved by `mv` (`pose` as [`moved`] checks it).
    pub(super) fn new(mesh: &'m Mesh<T>, pose: &'m Pose<T>, mv: Moved, isa: crate::Isa) -> Self {
        let slots = Slots::take(mesh.nodes.len());
        // a multiple of every f64 lane count, at least the width
        let stride = mesh.shape.width.next_multiple_of(4);
        Side { mesh, pose, isa, mv, slots, stride, tris: Vec::new(), rows: Vec::new() }
    }

    /// Where node `i`'s moved bounds are in `Slots::groups`: row `r` at `pos + r * stride`.
    /// A node gets them with its siblings ([`Side::group`] of its parent); one not reached that
    /// way (the root, or where a piece of a threaded query starts) gets a group of its own,
    /// computed like a group of children from it (the lanes past it hold the next nodes'
    /// bounds: real nodes, the mesh pads its rows) on the side's instruction set. (Computed
    /// one column in the portable code and copied to every lane before, this was half the
    /// time of a collision query at a separated pose: see the module's docs.)
    pub(super) fn bounds_at(&mut self, i: u32) -> usize {
        let size = ROWS * self.stride;
        let e = *self.slots.entry(i);
        if e[1] != u32::MAX {
            return e[1] as usize * size + e[2] as usize;
        }
        let at = self.new_group();
        let out = &mut self.slots.groups[at..at + size];
        let mut job = self.mesh.columns(&self.mv, i as usize, self.stride, out, self.stride);
        crate::arch::node_columns(self.isa, &mut job);
        self.slots.entry(i)[1] = (at / size) as u32;
        at
    }

    /// Node `i`'s moved box.
    pub(super) fn aabb(&mut self, i: u32) -> Aabb {
        let at = self.bounds_at(i);
        boxed(&self.slots.groups, at, self.stride)
    }

    /// Room for one more group in `Slots::groups`: its offset.
    pub(super) fn new_group(&mut self) -> usize {
        let at = self.slots.groups.len();
        self.slots.groups.resize(at + ROWS * self.stride, 0.0);
        at
    }

    /// The moved bounds of internal node `i`'s children as a group ([`NodeTest::group`]): its
    /// offset in `Slots::groups`, computed on first use by the node columns of the side's
    /// instruction set ([`crate::algo::nodes::columns`], a lane per child). The lanes past the
    /// last child hold the next nodes' bounds (real nodes: the mesh pads its rows).
    pub(super) fn group(&mut self, i: u32) -> usize {
        let size = ROWS * self.stride;
        let k = self.slots.entry(i)[4];
        if k != u32::MAX {
            return k as usize * size;
        }
        let node = self.mesh.nodes[i as usize];
        let at = self.new_group();
        self.slots.entry(i)[4] = (at / size) as u32;
        let out = &mut self.slots.groups[at..at + size];
        let mut job = self.mesh.columns(&self.mv, node.first as usize, self.stride, out, self.stride);
        crate::arch::node_columns(self.isa, &mut job);
        for j in 0..node.kids {
            let e = self.slots.entry(node.first + j);
            if e[1] == u32::MAX {
                (e[1], e[2]) = ((at / size) as u32, j);
            }
        }
        at
    }

    /// Leaf node `i`, moved (on first use).
    pub(super) fn leaf(&mut self, i: u32) -> Leaf<'_, T> {
        let node = &self.mesh.nodes[i as usize];
        let (first, n) = (node.first as usize, node.count as usize);
        let mut k = self.slots.entry(i)[3] as usize;
        if k == u32::MAX as usize {
            k = self.tris.len();
            // (the numbers past the rows: the next leaf's rows overwrite them)
            self.rows.resize(6 * (k + n) + MAX_LEAF, 0.0);
            for (j, at) in (first..first + n).enumerate() {
                let t = self.mesh.leaf_triangle_at(at, self.pose);
                self.tris.push(t);
                let (lo, hi) = tri_box(&t);
                for q in 0..3 {
                    self.rows[6 * k + q * n + j] = lo[q];
                    self.rows[6 * k + (3 + q) * n + j] = hi[q];
                }
            }
            self.slots.entry(i)[3] = k as u32;
        }
        Leaf {
            ids: &self.mesh.order[first..first + n],
            tris: &self.tris[k..k + n],
            rows: &self.rows[6 * k..6 * (k + n) + MAX_LEAF],
        }
    }
}

/// The moved box in `groups` at `pos` (row `r` at `pos + r * stride`).
pub(super) fn boxed(groups: &[f64], pos: usize, stride: usize) -> Aabb {
    let row = |r: usize| groups[pos + r * stride];
    ([row(LO), row(LO + 1), row(LO + 2)], [row(HI), row(HI + 1), row(HI + 2)])
}
