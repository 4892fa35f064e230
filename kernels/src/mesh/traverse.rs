//! The one traversal every mesh-vs-mesh query shares: node pairs taken depth first, overlap
//! first or best first as the searcher ([`Search`]) asks, split at the larger node, pruned by
//! the lane-wide node test, leaf pairs gathered into batches for the kernels.

use super::bounds::{box_gap2, magnitude};
use super::scratch::{Pending, Side};
use super::{Mesh, Node, FLUSH};
use crate::algo::nodes::Gaps;
use crate::algo::nodes::Limit;
use crate::algo::nodes::Moved;
use crate::algo::nodes::NodeTest;
use crate::algo::nodes::MAX_LEAF;
use crate::algo::nodes::MAX_WIDTH;
use crate::algo::nodes::ROWS;
use crate::Engine;
use crate::Error;
use crate::Pose;
use crate::Real;
use crate::Triangle;

/// The children of internal node `p` of `side` against node `f` of `other`: the pairs not
/// pruned (`pair(child)` names them), into `out` with their lower bounds, by the node test of
/// `isa` ([`crate::algo::nodes`]).
pub(super) fn siblings<T: Real>(
    isa: crate::Isa,
    (side, p): (&mut Side<'_, T>, u32),
    (other, f): (&mut Side<'_, T>, u32),
    s: &impl Search<T>,
    pair: impl Fn(u32) -> (u32, u32),
    out: &mut Vec<Visit>,
) {
    let (n, first) = (side.mesh.nodes[p as usize].kids as usize, side.mesh.nodes[p as usize].first);
    let (at, fixed_at) = (side.group(p), other.bounds_at(f));
    let g = node_test(isa, (side, at, n), (other, fixed_at), s.limit());
    for j in 0..n {
        if g.gap[j] <= g.lim[j] {
            let (x, y) = pair(first + j as u32);
            out.push((g.gap[j], x, y, g.lim[j]));
        }
    }
}

/// The node test of `isa` ([`crate::algo::nodes`]): the first `n` lanes of the group at `at`
/// in `side` against the node whose bounds are at `fixed_at` in `other`, each lane with its
/// limit from the two moved boxes; the lanes' lower bounds and limits.
pub(super) fn node_test<T: Real>(
    isa: crate::Isa,
    (side, at, n): (&Side<'_, T>, usize, usize),
    (other, fixed_at): (&Side<'_, T>, usize),
    limit: Limit,
) -> Gaps {
    let t = NodeTest {
        group: &side.slots.groups[at..at + ROWS * side.stride],
        stride: side.stride,
        n,
        fixed: &other.slots.groups[fixed_at..],
        fixed_stride: other.stride,
        limit,
    };
    let mut g = Gaps::new();
    crate::arch::node_gaps(isa, &t, &mut g);
    g
}

/// What one mesh-vs-mesh query does on the one traversal they share ([`search`]).
pub(super) trait Search<T: Real> {
    /// The squared distance beyond which the triangle pairs in two boxes are not needed (fixed,
    /// or growing with the boxes' magnitude).
    fn limit(&self) -> Limit;
    /// Whether to run the kernels on the pairs gathered so far at once, not waiting for
    /// [`FLUSH`] of them (distance: the first answer prunes the rest). `overlap`: the boxes of
    /// the leaf pair just gathered overlap (its lower bound is negative, [`Visit`]).
    fn eager(&self, _overlap: bool) -> bool {
        false
    }
    /// How many pairs to gather before the kernels run on them (at least; a leaf pair's are
    /// gathered together).
    fn batch(&self) -> usize {
        FLUSH
    }
    /// Runs the kernels on the gathered pairs; `true` ends the search.
    fn flush(&mut self, e: &Engine, pend: &Pending<T>) -> Result<bool, Error>;
    /// Visit node pairs best first (smallest lower bound next) instead of depth first. Only for
    /// a search whose limit does not depend on the boxes: the first pair beyond it ends the
    /// search.
    fn best_first(&self) -> bool {
        false
    }
    /// Visit node pairs whose boxes overlap (lower bound at most 0) before any whose boxes are
    /// apart, each class depth first. For a search that ends at its first hit among pairs that
    /// must all be visited otherwise (intersection): far from the origin its limit, the
    /// tolerance's width, can exceed the triangles' size, and plain depth first then walks
    /// every apart pair of a subtree before it reaches the next overlapping one.
    fn overlap_first(&self) -> bool {
        false
    }
    /// Called once the roots are moved, with the largest absolute coordinate of their boxes
    /// (a bound of every moved coordinate).
    fn start(&mut self, _mag: f64) {}
    /// A direction to prune along ([`AxisCut`]): a leaf pair's triangle pairs whose projections
    /// on it are farther apart than the limit are not answered. The nearest-pair search gives the direction
    /// of its best answer so far (from its point on the first mesh to the one on the second),
    /// numbered so that the walk recomputes its projections only when it changes.
    fn axis(&self) -> Option<Axis> {
        None
    }
}

/// A direction to prune along and its version ([`Search::axis`]).
#[derive(Clone, Copy, PartialEq)]
pub(super) struct Axis {
    pub(super) dir: [f64; 3],
    pub(super) version: usize,
    /// The scene's magnitude ([`Search::start`]).
    pub(super) mag: f64,
}

/// Pruning along one direction `n`: for any `n`, the gap between two triangles' projections on
/// it, over `|n|`, is a lower bound of their distance, and along the direction between the
/// nearest points found so far, the triangles near them project behind the two points (for a
/// locally convex pair of surfaces the planes through those points across `n` separate them),
/// so a pair that the box tests keep is often beyond the limit along `n`. The leaf pairs'
/// triangles are tested, not the nodes: a node's box, axis-aligned or oriented, is wider
/// along `n` than the slab between the nearest points, and cut 1 to 4 % of the node pairs
/// visited at TrueForm's random placements of two Armadillos (`tridist poses --protocol
/// ball`), where this cut 79 % of the triangle pairs the kernels answered (643 to 133 per
/// query, throwaway counters; docs/notes/mesh.md).
pub(super) struct AxisCut {
    version: usize,
    n: [f64; 3],
    /// `|n|`, and the projections' rounding bound in units of it.
    len: f64,
    tri_slack: f64,
}

impl AxisCut {
    /// No direction yet.
    pub(super) const NONE: AxisCut = AxisCut { version: usize::MAX, n: [0.0; 3], len: 0.0, tri_slack: 0.0 };

    fn new(axis: Axis) -> AxisCut {
        let n = axis.dir;
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        let n1 = n[0].abs() + n[1].abs() + n[2].abs();
        AxisCut { version: axis.version, n, len, tri_slack: 16.0 * f64::EPSILON * axis.mag * n1 }
    }

    /// The triangle pairs of two moved leaves whose projections are farther apart than `lim`
    /// (squared): bit `i * MAX_LEAF + j` for triangle `i` of `a` and `j` of `b`. The triangles
    /// are the moved ones the kernels answer, exact in `f64`; the projections' own rounding is
    /// within `16 eps S |n|_1` (S the magnitude, every moved coordinate within it).
    fn apart<T: Real>(&self, a: &[Triangle<T>], b: &[Triangle<T>], lim: f64) -> u64 {
        if self.len.is_nan() || self.len <= 0.0 {
            return 0;
        }
        let span = |t: &Triangle<T>| {
            let p =
                t.map(|v| v[0].to_f64() * self.n[0] + v[1].to_f64() * self.n[1] + v[2].to_f64() * self.n[2]);
            (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]))
        };
        let sb: [(f64, f64); MAX_LEAF] = core::array::from_fn(|j| b.get(j).map_or((0.0, 0.0), span));
        let mut out = 0u64;
        for (i, ta) in a.iter().enumerate() {
            let (lo, hi) = span(ta);
            for (j, &(blo, bhi)) in sb.iter().enumerate().take(b.len()) {
                let apart = ((blo - hi).max(lo - bhi) - self.tri_slack) / self.len;
                if apart > 0.0 && apart * apart * (1.0 - 1e-12) > lim {
                    out |= 1 << (i * MAX_LEAF + j);
                }
            }
        }
        out
    }
}

/// The node pairs waiting for a visit: a stack (depth first, the nearer child pair on top), two
/// stacks (overlapping boxes first, then apart ones; [`Search::overlap_first`]) or a heap (best
/// first: the pair of smallest lower bound next).
pub(super) enum Frontier {
    Depth(Vec<Visit>),
    OverlapFirst(Vec<Visit>, Vec<Visit>),
    Best(std::collections::BinaryHeap<Nearer>),
}

/// A visit ordered for a max-heap by its lower bound, smallest first (ties: smaller nodes).
pub(super) struct Nearer(Visit);

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
    pub(super) fn push(&mut self, v: Visit) {
        match self {
            Frontier::Depth(s) => s.push(v),
            Frontier::OverlapFirst(now, _) if v.0 <= 0.0 => now.push(v),
            Frontier::OverlapFirst(_, later) => later.push(v),
            Frontier::Best(h) => h.push(Nearer(v)),
        }
    }
    pub(super) fn pop(&mut self) -> Option<Visit> {
        match self {
            Frontier::Depth(s) => s.pop(),
            Frontier::OverlapFirst(now, later) => now.pop().or_else(|| later.pop()),
            Frontier::Best(h) => h.pop().map(|n| n.0),
        }
    }
}

/// A node pair to visit: (lower bound of the squared gap, node of a, node of b, the search's
/// limit as the node test found it). The bound is negative where the node test found the
/// nodes' boxes overlapping: minus their overlap as a fraction of their extents, so that both
/// orders (the depth-first children's and the best-first heap's) take the deepest overlaps
/// first ([`crate::algo::nodes::gaps`]). The limit is taken again when the visit comes unless
/// the search's limit is the one the walk started with and grows with the boxes' magnitude
/// ([`walk`]).
pub(super) type Visit = (f64, u32, u32, f64);

/// The root pair of two sides, unless pruned.
pub(super) fn root_visit<T: Real>(
    isa: crate::Isa,
    sa: &mut Side<'_, T>,
    sb: &mut Side<'_, T>,
    s: &impl Search<T>,
) -> Option<Visit> {
    // the root of a has a group of its own, every lane a copy ([`Side::bounds_at`])
    let (at, fixed_at) = (sa.bounds_at(0), sb.bounds_at(0));
    let g = node_test(isa, (sa, at, 1), (sb, fixed_at), s.limit());
    (g.gap[0] <= g.lim[0]).then_some((g.gap[0], 0, 0, g.lim[0]))
}

/// The child pairs of the internal pair (x, y) not pruned, into `out`, nearest last: the
/// larger internal node is split.
pub(super) fn children<T: Real>(
    isa: crate::Isa,
    sa: &mut Side<'_, T>,
    sb: &mut Side<'_, T>,
    (x, y): (u32, u32),
    s: &impl Search<T>,
    out: &mut Vec<Visit>,
) {
    out.clear();
    let (nx, ny) = (sa.mesh.nodes[x as usize], sb.mesh.nodes[y as usize]);
    let extent = |n: &Node| (0..3).map(|k| n.hi[k] - n.lo[k]).fold(0.0, f64::max);
    let split_a = ny.count > 0 || (nx.count == 0 && extent(&nx) >= extent(&ny));
    if split_a {
        siblings(isa, (sa, x), (sb, y), s, |c| (c, y), out);
    } else {
        siblings(isa, (sb, y), (sa, x), s, |c| (x, c), out);
    }
    // farthest first, so the nearest is popped first (reversed, then a stable sort: of equal
    // gaps the earlier child is taken first)
    out.reverse();
    out.sort_by(|p, q| q.0.total_cmp(&p.0));
}

/// The traversal of two trees every mesh-vs-mesh query runs, from the node pairs on `stack`:
/// node pairs nearest first (depth first, the nearer child pair on top; or best first when the
/// search asks), pruned by `s.limit`, leaf pairs gathered into batches for the kernels.
pub(super) fn walk<T: Real, S: Search<T>>(
    e: &Engine,
    sa: &mut Side<'_, T>,
    sb: &mut Side<'_, T>,
    stack: Vec<Visit>,
    s: &mut S,
) -> Result<(), Error> {
    let mut pend = Pending::new();
    let mut kids = Vec::with_capacity(MAX_WIDTH);
    let best_first = s.best_first();
    // A visit's limit is the one its node test found (the same number: see the test
    // `lane_limits_are_the_scalar_limits_of_the_moved_boxes`) while the search's limit is the
    // one it started with and grows with the magnitude; it is taken again otherwise (a fixed
    // limit costs nothing; a contact search with a cap narrows its limit as it goes). Taken
    // again for every visit, with the boxes read back for their magnitude, it held 10 % of
    // the contact query's samples at near-contact placement 3 (`perf record` of `spin mesh
    // contacts n3 f32 1 3`); kept, contacts over the 12 near-contact placements 3.35 -> 3.05
    // ms and intersection over the 24 poses 0.452 -> 0.415 ms (f32, two builds alternated,
    // `spin mesh <query> <pose> f32 1 <0.3|0.15 s>`'s mean time per call summed over the
    // poses, the median of 4 rounds, faster in each, 2026-11-28).
    let start = s.limit();
    let mut cut = AxisCut::NONE;
    let mut todo = if best_first {
        Frontier::Best(stack.into_iter().map(Nearer).collect())
    } else if s.overlap_first() {
        let mut f = Frontier::OverlapFirst(Vec::new(), Vec::new());
        stack.into_iter().for_each(|v| f.push(v));
        f
    } else {
        Frontier::Depth(stack)
    };
    'visits: while let Some(mut v) = todo.pop() {
        // From each pair taken, dive to a leaf pair along the nearer child pairs, leaving the
        // farther ones for later: leaves are reached (and their answers prune) early in either
        // order.
        loop {
            let (gap, x, y, found) = v;
            let lim = match s.limit() {
                now @ Limit::Reach { .. } if now == start => found,
                now => now.at(|| magnitude(&sa.aabb(x), &sb.aabb(y))),
            };
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
                if let Some(axis) = s.axis().filter(|a| a.version != cut.version) {
                    cut = AxisCut::new(axis);
                }
                let isa = sa.isa;
                let (la, lb) = (sa.leaf(x), sb.leaf(y));
                let apart = cut.apart(la.tris, lb.tris, lim);
                pend.push_leaves(isa, la, lb, lim, apart);
                if pend.ids.len() >= s.batch() || (s.eager(gap < 0.0) && !pend.ids.is_empty()) {
                    let stop = s.flush(e, &pend)?;
                    pend.clear();
                    if stop {
                        return Ok(());
                    }
                }
                continue 'visits;
            }
            children(e.isa(), sa, sb, (x, y), s, &mut kids);
            let Some(near) = kids.pop() else { continue 'visits };
            for f in kids.drain(..) {
                todo.push(f);
            }
            v = near;
        }
    }
    if !pend.ids.is_empty() {
        s.flush(e, &pend)?;
    }
    Ok(())
}

/// The node pairs under the roots' pair `root`, split breadth first until there are at least
/// `want` (where the trees allow): leaf pairs are kept whole, internal pairs are replaced by
/// their children not pruned by `s`'s limit. Pieces for threads, each walked on its own.
pub(super) fn split<T: Real>(
    isa: crate::Isa,
    sa: &mut Side<'_, T>,
    sb: &mut Side<'_, T>,
    root: Option<Visit>,
    s: &impl Search<T>,
    want: usize,
) -> Vec<Visit> {
    let mut queue: std::collections::VecDeque<Visit> = root.into_iter().collect();
    let (mut pieces, mut kids) = (Vec::new(), Vec::new());
    while pieces.len() + queue.len() < want {
        let Some(v @ (_, x, y, _)) = queue.pop_front() else { break };
        if sa.mesh.nodes[x as usize].count > 0 && sb.mesh.nodes[y as usize].count > 0 {
            pieces.push(v);
        } else {
            children(isa, sa, sb, (x, y), s, &mut kids);
            queue.extend(kids.drain(..).rev());
        }
    }
    pieces.extend(queue);
    pieces
}

/// [`walk`] from the roots of two meshes in their poses.
pub(super) fn search<T: Real, S: Search<T>>(
    e: &Engine,
    a: &Mesh<T>,
    pa: &Pose<T>,
    b: &Mesh<T>,
    pb: &Pose<T>,
    s: &mut S,
) -> Result<(), Error> {
    e.params::<T>()?;
    let e = &e.for_small_batches();
    pa.check()?;
    pb.check()?;
    if a.is_empty() || b.is_empty() {
        return Ok(());
    }
    let (ma, mb) = (moved(a, pa)?, moved(b, pb)?);
    if roots_apart((a, &ma), (b, &mb), s) {
        return Ok(());
    }
    let (mut sa, mut sb) = (Side::new(a, pa, ma, e.isa()), Side::new(b, pb, mb, e.isa()));
    let stack = root_visit(e.isa(), &mut sa, &mut sb, s).into_iter().collect();
    walk(e, &mut sa, &mut sb, stack, s)
}

/// `pose` in f64 ([`Moved`]), or [`Error::NonFiniteCoordinate`] when `mesh` moved by it leaves
/// the range of `T`.
pub(super) fn moved<T: Real>(mesh: &Mesh<T>, pose: &Pose<T>) -> Result<Moved, Error> {
    let mv = Moved::of(pose);
    mv.fits(mesh)?;
    Ok(mv)
}

/// Moves the roots' boxes, starts the search with their magnitude ([`Search::start`]) and
/// answers whether their gap alone exceeds the search's limit: then no triangle pair is
/// within it, and the query is answered before any scratch is taken or any oriented box
/// moved (the same lower bound as the node test's, less fused: both are below the exact
/// gap). (A collision query at a separated pose took about 500 ns, most of it in taking the
/// scratch and moving both roots' bounds, and about 125 ns with this test first: `spin mesh
/// intersect 0 f32 1 1`, see the module's docs.)
pub(super) fn roots_apart<T: Real, S: Search<T>>(
    (a, ma): (&Mesh<T>, &Moved),
    (b, mb): (&Mesh<T>, &Moved),
    s: &mut S,
) -> bool {
    let (ba, bb) = (a.moved_box(0, ma), b.moved_box(0, mb));
    let mag = magnitude(&ba, &bb);
    s.start(mag);
    box_gap2(&ba, &bb) > s.limit().at(|| mag)
}

pub(super) fn check_finite<T: Real>(d: T) -> Result<(), Error> {
    if d.is_nan() {
        Err(Error::NonFiniteCoordinate)
    } else {
        Ok(())
    }
}
