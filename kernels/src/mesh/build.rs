//! The tree build: binned surface-area splits along the widest axis of the triangles' box
//! centres, collapsed to the shape's width, with each node's axis-aligned and oriented box laid
//! out as rows for the lane-wide node test.

use super::bounds::{half_area, least, most, tri_box, unite, Aabb, Obb, EMPTY};
use super::{Bin, Mesh, Node};
use crate::algo::nodes::MAX_WIDTH;
use crate::algo::nodes::SC;
use crate::algo::nodes::SE;
use crate::algo::nodes::SH;
use crate::algo::nodes::SHI;
use crate::algo::nodes::SLO;
use crate::algo::nodes::SRHO;
use crate::algo::nodes::SROWS;
use crate::Real;

impl<T: Real> Mesh<T> {
    pub(super) fn build(&mut self) {
        let n = self.triangles.len();
        if n == 0 {
            return;
        }
        let boxes: Vec<Aabb> = (0..n).map(|i| tri_box(&self.tri(i))).collect();
        // What the splits move: a triangle's box centre and number (small, so that the splits
        // move little; the boxes are read by number).
        let mut items: Vec<Item> = boxes
            .iter()
            .enumerate()
            .map(|(i, (lo, hi))| Item { c: [0, 1, 2].map(|k| 0.5 * lo[k] + 0.5 * hi[k]), tri: i as u32 })
            .collect();
        // 1. The binary tree: binned surface-area splits along the widest axis of the boxes'
        // centres ([`area_split`]), or the median where no such split leaves two triangles on
        // each side; a node's triangles stay `items[s..e]` (later splits only permute within a
        // node's range). (At most `2 n - 1` nodes; fewer than `n` once most leaves hold two
        // triangles or more.)
        let mut bins = Vec::with_capacity(n);
        bins.push(Bin { lo: [0.0; 3], hi: [0.0; 3], s: 0, e: n, kids: None });
        let mut todo = vec![(0usize, 0usize, n)];
        while let Some((id, s, e)) = todo.pop() {
            if e - s <= self.shape.leaf {
                continue;
            }
            let (mut clo, mut chi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            for it in &items[s..e] {
                for k in 0..3 {
                    clo[k] = least(clo[k], it.c[k]);
                    chi[k] = most(chi[k], it.c[k]);
                }
            }
            let axis = (0..3).max_by(|&a, &b| (chi[a] - clo[a]).total_cmp(&(chi[b] - clo[b]))).unwrap_or(0);
            let mid = match area_split(&mut items[s..e], &boxes, axis, clo[axis], chi[axis]) {
                Some(left) => s + left,
                None => {
                    let mid = s + (e - s) / 2;
                    items[s..e].select_nth_unstable_by(mid - s, |a, b| a.c[axis].total_cmp(&b.c[axis]));
                    mid
                }
            };
            let left = bins.len();
            bins.push(Bin { lo: [0.0; 3], hi: [0.0; 3], s, e: mid, kids: None });
            bins.push(Bin { lo: [0.0; 3], hi: [0.0; 3], s: mid, e, kids: None });
            bins[id].kids = Some([left, left + 1]);
            todo.push((left, s, mid));
            todo.push((left + 1, mid, e));
        }
        // The boxes bottom up (children come after their parent): a leaf's from its
        // triangles', a node's the union of its children's.
        for id in (0..bins.len()).rev() {
            let mut acc = EMPTY;
            match bins[id].kids {
                Some(k) => k.iter().for_each(|&c| unite(&mut acc, &(bins[c].lo, bins[c].hi))),
                None => items[bins[id].s..bins[id].e]
                    .iter()
                    .for_each(|it| unite(&mut acc, &boxes[it.tri as usize])),
            }
            (bins[id].lo, bins[id].hi) = acc;
        }
        // The triangles' vertices in leaf order, for the oriented boxes' pass.
        let tv: Vec<[u32; 3]> = items.iter().map(|it| self.triangles[it.tri as usize]).collect();
        // 2. The tree of `width`: the binary tree collapsed (the same splits, so the same tree
        // quality at every width): a node's children are binary descendants, found by opening
        // the internal one of largest box area until there are `width` (or only leaves).
        let area = |b: &Bin| half_area(&(b.lo, b.hi));
        // (every node is a binary node: `bins.len()` bounds their number)
        let mut of = Vec::with_capacity(bins.len()); // the binary node of each node
        of.push(0usize);
        self.nodes = Vec::with_capacity(bins.len());
        self.nodes.push(Node { lo: bins[0].lo, hi: bins[0].hi, first: 0, count: 0, kids: 0 });
        let mut todo = vec![0usize];
        let mut set = Vec::with_capacity(MAX_WIDTH);
        while let Some(id) = todo.pop() {
            let b = &bins[of[id]];
            let Some(k) = b.kids else {
                self.nodes[id].first = b.s as u32;
                self.nodes[id].count = (b.e - b.s) as u32;
                continue;
            };
            set.clear();
            set.extend(k);
            while set.len() < self.shape.width {
                let open = (0..set.len())
                    .filter(|&i| bins[set[i]].kids.is_some())
                    .max_by(|&i, &j| area(&bins[set[i]]).total_cmp(&area(&bins[set[j]])));
                let Some(i) = open else { break };
                let [c0, c1] = bins[set[i]].kids.unwrap_or_default();
                // (in place: the children stay in the binary tree's order)
                set[i] = c0;
                set.insert(i + 1, c1);
            }
            let first = self.nodes.len();
            self.nodes[id].first = first as u32;
            self.nodes[id].kids = set.len() as u32;
            for &c in &set {
                todo.push(self.nodes.len());
                of.push(c);
                self.nodes.push(Node { lo: bins[c].lo, hi: bins[c].hi, first: 0, count: 0, kids: 0 });
            }
        }
        // 3. Both bounds of every node as rows ([`crate::algo::nodes::SROWS`]), padded with
        // copies of the last node so that a group's lanes past the children read real nodes.
        // The oriented boxes are fitted to each node's distinct vertices (a vertex is shared
        // by about six triangles): `seen[v]` is the last node that took vertex `v`.
        let stride = self.nodes.len() + MAX_WIDTH;
        let mut rows = vec![0.0; SROWS * stride];
        let mut seen = vec![u32::MAX; self.vertices.len()];
        let mut pts = vec![[0.0; 3]; 3 * OBB_FIT_MAX];
        for id in 0..self.nodes.len() {
            let b = &bins[of[id]];
            let o = if b.e - b.s > OBB_FIT_MAX {
                Obb::of_box(&(b.lo, b.hi))
            } else {
                // (every vertex written, counted only when new: no branch on whether it is,
                // which is as good as random to the branch predictor)
                let mut len = 0;
                for tri in &tv[b.s..b.e] {
                    for &v in tri {
                        let new = seen[v as usize] != id as u32;
                        seen[v as usize] = id as u32;
                        pts[len] = self.vertices[v as usize].map(Real::to_f64);
                        len += usize::from(new);
                    }
                }
                Obb::fit(&pts[..len])
            };
            let n = &self.nodes[id];
            let mut put = |r: usize, x: f64| rows[r * stride + id] = x;
            for k in 0..3 {
                put(SC + k, o.c[k]);
                put(SH + k, o.h[k]);
                put(SLO + k, n.lo[k]);
                put(SHI + k, n.hi[k]);
                for q in 0..3 {
                    put(SE + 3 * k + q, o.e[k][q]);
                }
            }
            put(SRHO, o.rho);
        }
        for row in rows.chunks_exact_mut(stride) {
            let last = row[self.nodes.len() - 1];
            row[self.nodes.len()..].fill(last);
        }
        self.order = items.iter().map(|it| it.tri).collect();
        self.leaf_tris = self.order.iter().map(|&t| self.triangles[t as usize]).collect();
        (self.bounds, self.bounds_stride) = (rows, stride);
    }
}

/// A triangle as the tree's splits move it: its box's centre and its number.
pub(super) struct Item {
    pub(super) c: [f64; 3],
    pub(super) tri: u32,
}

/// Bins of [`area_split`].
pub(super) const SPLIT_BINS: usize = 16;

/// Most items [`area_split`] bins (a regular sample of larger nodes).
pub(super) const SPLIT_SAMPLE: usize = 1024;

/// Most triangles of a node whose oriented box is fitted on its vertices' principal axes;
/// a larger node's is its axis-aligned box, on the mesh frame's axes (no pass over its
/// vertices). Why: the `mesh` module's docs.
pub(super) const OBB_FIT_MAX: usize = 256;

/// A binned surface-area split of `items` along axis `k` (their box centres from `lo` to `hi`
/// along it; `boxes` the triangles' boxes by number): the centres' range cut into
/// [`SPLIT_BINS`] equal bins (as many as items in smaller nodes), and the items split at the
/// bin boundary that minimises the two sides' box areas times their triangle counts, the
/// usual estimate of how often a query opens them, counted on a regular sample of at most
/// [`SPLIT_SAMPLE`] items. Returns how many items it put first (every one of them with a
/// smaller centre than every one after), or `None` where no boundary leaves two on each side
/// (the caller takes the median). Why this split: the `mesh` module's docs.
pub(super) fn area_split(items: &mut [Item], boxes: &[Aabb], k: usize, lo: f64, hi: f64) -> Option<usize> {
    // (no spread, or NaN)
    if hi - lo <= 0.0 || (hi - lo).is_nan() {
        return None;
    }
    // (as many bins as items in small nodes: the cost of the sweeps below follows the items)
    let nb = items.len().min(SPLIT_BINS);
    let scale = nb as f64 / (hi - lo);
    // (the float-to-integer cast saturates: NaN and negatives go to bin 0)
    let bin = |it: &Item| (((it.c[k] - lo) * scale) as usize).min(nb - 1);
    let mut count = [0usize; SPLIT_BINS];
    let mut bins = [EMPTY; SPLIT_BINS];
    let step = items.len().div_ceil(SPLIT_SAMPLE);
    for it in items.iter().step_by(step) {
        let b = bin(it);
        count[b] += 1;
        unite(&mut bins[b], &boxes[it.tri as usize]);
    }
    // the area and count of every suffix of bins, then the cost at each boundary
    let mut right = [(0.0, 0usize); SPLIT_BINS];
    let (mut acc, mut m) = (EMPTY, 0);
    for b in (1..nb).rev() {
        unite(&mut acc, &bins[b]);
        m += count[b];
        right[b] = (half_area(&acc), m);
    }
    let mut best: Option<(f64, usize)> = None;
    let (mut acc, mut m) = (EMPTY, 0);
    for b in 0..nb - 1 {
        unite(&mut acc, &bins[b]);
        m += count[b];
        let (area_r, m_r) = right[b + 1];
        let cost = half_area(&acc) * m as f64 + area_r * m_r as f64;
        if m >= 2 && m_r >= 2 && best.is_none_or(|(c, _)| cost < c) {
            best = Some((cost, b));
        }
    }
    let (_, cut) = best?;
    // The items of bins up to `cut` first. (An item is in such a bin exactly when its scaled
    // offset is below `cut + 1`: the same test as `bin`'s without the conversion, `cut + 1`
    // being below the last bin's saturation.) Without a branch on the side (Lomuto's
    // partition: every item swapped with the first of the right side), whose outcome is as
    // good as random to the branch predictor.
    let cut = (cut + 1) as f64;
    let mut first = 0;
    for i in 0..items.len() {
        let left = (items[i].c[k] - lo) * scale < cut;
        items.swap(first, i);
        first += usize::from(left);
    }
    // (the sample saw two on each side; the whole may not)
    (first >= 2 && items.len() - first >= 2).then_some(first)
}
