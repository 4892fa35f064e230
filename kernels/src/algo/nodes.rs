//! The mesh traversal's node test ([`crate::mesh`]), written once over [`Lanes`] of f64 like
//! the triangle kernels: one node of one tree against the children of a node of the other
//! tree, a lane per child. The lower bound of the squared distance between two nodes is the
//! larger of their moved axis-aligned boxes' gap and their moved oriented boxes' gap (the
//! largest projection gap over the line through their centres and the six box axes, less
//! their balls and every rounding); a node pair is pruned when it exceeds the search's limit.
//!
//! Each node's moved bounds are a column of [`ROWS`] numbers (the row constants below);
//! the children of a node are stored as a group, row by row, `stride` numbers per row (a
//! structure of arrays), so one load fills a vector with one quantity of consecutive children.
//!
//! Every lane computes every axis (the early exits are per vector: when every lane is already
//! pruned by the boxes, or by the centre line). The rounding allowances are those the scalar
//! test had: each projection gap is lowered by the moved boxes' rounding (`ERR` times the
//! axis' 1-norm) and by a relative `1e-12`, far above what this arithmetic, fused or not, can
//! add; squares are lowered by `8 eps`.

use crate::lanes::{Lanes, Mask, V3};

/// Most triangles of a leaf a tree may hold ([`crate::TreeShape::MAX_LEAF`]): the leaf test's
/// rows are sized by it.
pub(crate) const MAX_LEAF: usize = 8;
/// Most children of a node ([`crate::TreeShape::MAX_WIDTH`]): a node test's lanes.
pub(crate) const MAX_WIDTH: usize = 8;

/// A pose in f64 with the relative slack that makes moved boxes contain the moved vertices.
#[derive(Clone, Copy)]
pub(crate) struct Moved {
    pub(crate) r: [[f64; 3]; 3],
    pub(crate) t: [f64; 3],
    pub(crate) rel: f64,
    /// The Frobenius norm of `r` rounded up: how much the rotation can stretch a ball.
    pub(crate) frob: f64,
}

impl Moved {
    pub(crate) fn of<T: crate::Real>(p: &crate::Pose<T>) -> Moved {
        let r = p.rotation.map(|row| row.map(crate::Real::to_f64));
        Moved {
            r,
            t: p.translation.map(crate::Real::to_f64),
            rel: 4.0 * T::UNIT_ROUNDOFF.to_f64() + 16.0 * f64::EPSILON,
            frob: r.iter().flatten().map(|x| x * x).sum::<f64>().sqrt() * (1.0 + 1e-12),
        }
    }
}

/// Row of the moved axis-aligned box's lower corner (3 rows).
pub(crate) const LO: usize = 0;
/// Row of its upper corner (3 rows).
pub(crate) const HI: usize = 3;
/// Row of the moved oriented box's centre (3 rows).
pub(crate) const C: usize = 6;
/// Row of its axes: `E + 3 i + k` is component `k` of axis `i` (9 rows).
pub(crate) const E: usize = 9;
/// Row of its half-extents along its axes (3 rows).
pub(crate) const H: usize = 18;
/// Row of the radius of its ball (the box is the parallelepiped enlarged by that ball).
pub(crate) const RHO: usize = 21;
/// Row of the rounding bound of its centre and weighted axes (1-norms).
pub(crate) const ERR: usize = 22;
/// Row of its radius along its own axis `k`, `sum_i h_i |e_i . e_k|` (3 rows).
pub(crate) const OWN: usize = 23;
/// Row of the length of its axis `i`, rounded up by a relative `1e-12` (3 rows).
pub(crate) const LEN: usize = 26;
/// Row of the 1-norm of its axis `i` (3 rows).
pub(crate) const N1: usize = 29;
/// Rows of a node's moved bounds.
pub(crate) const ROWS: usize = 32;

/// One node's moved bounds (the rows above).
#[cfg(test)]
pub(crate) type Column = [f64; ROWS];

/// Rows of a node's bounds in its mesh's own frame, as the mesh keeps them (a structure of
/// arrays: a row per quantity, a number per node, so the consecutive children of a node fill
/// a vector with one load): its oriented box's centre (3 rows), axes (`SE + 3 i + k`:
/// component `k` of axis `i`), half-extents (3), ball radius, and its axis-aligned box's
/// corners (3 + 3).
pub(crate) const SC: usize = 0;
pub(crate) const SE: usize = 3;
pub(crate) const SH: usize = 12;
pub(crate) const SRHO: usize = 15;
pub(crate) const SLO: usize = 16;
pub(crate) const SHI: usize = 19;
/// Rows of a node's bounds in its mesh's frame.
pub(crate) const SROWS: usize = 22;

/// The moved bounds (columns of [`ROWS`] numbers) of `n` consecutive nodes, a lane per node.
pub(crate) struct Columns<'a> {
    pub mv: &'a Moved,
    /// The nodes' bounds in their mesh's frame: row `r` (the `S*` constants) of node `i` at
    /// `src[r * src_stride + i]`.
    pub src: &'a [f64],
    pub src_stride: usize,
    /// The first node and how many (a multiple of every f64 lane count; the source has them).
    pub first: usize,
    pub n: usize,
    /// Row `r` of node `first + j` goes to `out[r * out_stride + j]`.
    pub out: &'a mut [f64],
    pub out_stride: usize,
}

/// Fills `job.out` with the moved bounds of its nodes, a lane per node: the axis-aligned box
/// moved by [`moved_aabb`], and the oriented box moved exactly (see `Moved::column` for what
/// each row bounds). Plain multiplications and additions in a fixed order, never fused: every
/// instruction set computes the same numbers as the portable code (tested), and the rounding
/// bounds (`ERR`, `RHO`, the moved box's slack) are those of this arithmetic. (Computed one
/// node at a time in scalar code before, this was 16 % of a collision query's time at an
/// interpenetrating pose: `perf` of `spin mesh intersect 6 f32 1 3`.)
#[inline(always)]
pub(crate) fn columns<L: Lanes<S = f64>>(k: L::K, job: &mut Columns<'_>) {
    let c = |v: f64| L::splat(k, v);
    let mv = job.mv;
    let mut base = 0;
    while base < job.n {
        // (a loop, not a closure per row: closures compile without the instruction set's
        // features, and their loads stayed calls)
        let mut s = [c(0.0); SROWS];
        for (r, x) in s.iter_mut().enumerate() {
            *x = L::load(k, &job.src[r * job.src_stride + job.first + base..]);
        }
        let oc = [s[SC], s[SC + 1], s[SC + 2]];
        let oh = [s[SH], s[SH + 1], s[SH + 2]];
        let oe = [
            [s[SE], s[SE + 1], s[SE + 2]],
            [s[SE + 3], s[SE + 4], s[SE + 5]],
            [s[SE + 6], s[SE + 7], s[SE + 8]],
        ];
        let (nlo, nhi) = ([s[SLO], s[SLO + 1], s[SLO + 2]], [s[SHI], s[SHI + 1], s[SHI + 2]]);
        let mut col = [c(0.0); ROWS];
        let (mut big, mut slack) = (c(0.0), c(0.0));
        let mut e = [[c(0.0); 3]; 3];
        for r in 0..3 {
            let rr = [c(mv.r[r][0]), c(mv.r[r][1]), c(mv.r[r][2])];
            let ra = [rr[0].abs(), rr[1].abs(), rr[2].abs()];
            let tr = c(mv.t[r]);
            // the oriented box: centre and axes through the rotation
            col[C + r] = dot3(&rr, &oc).add(tr);
            for (i, ei) in e.iter_mut().enumerate() {
                ei[r] = dot3(&rr, &oe[i]);
            }
            // the rounding of both and of the vertices' motion in the working precision
            let (mut b, mut v) = (tr.abs(), tr.abs());
            for j in 0..3 {
                let w =
                    oh[0].mul(oe[0][j].abs()).add(oh[1].mul(oe[1][j].abs())).add(oh[2].mul(oe[2][j].abs()));
                b = b.add(ra[j].mul(oc[j].abs().add(w)));
                v = v.add(ra[j].mul(nlo[j].abs().max(nhi[j].abs())));
            }
            big = big.add(b);
            slack = slack.add(v.mul(c(mv.rel)));
        }
        let (lo, hi) = moved_aabb(k, mv, &nlo, &nhi);
        for r in 0..3 {
            (col[LO + r], col[HI + r]) = (lo[r], hi[r]);
        }
        // the moved axes' dot products, each once (the diagonal gives their lengths)
        let mut ee = [[c(0.0); 3]; 3];
        for (i, row) in ee.iter_mut().enumerate() {
            for (q, x) in row.iter_mut().enumerate() {
                *x = dot3(&e[i], &e[q]);
            }
        }
        for q in 0..3 {
            col[H + q] = oh[q];
            // its radius along its own axis q: sum_i h_i |e_i . e_q|
            col[OWN + q] =
                oh[0].mul(ee[0][q].abs()).add(oh[1].mul(ee[1][q].abs())).add(oh[2].mul(ee[2][q].abs()));
            col[LEN + q] = ee[q][q].sqrt().mul(c(1.0 + 1e-12));
            col[N1 + q] = e[q][0].abs().add(e[q][1].abs()).add(e[q][2].abs());
            for j in 0..3 {
                col[E + 3 * q + j] = e[q][j];
            }
        }
        col[RHO] = s[SRHO].mul(c(mv.frob)).add(slack);
        col[ERR] = c(32.0 * f64::EPSILON).mul(big);
        for (r, x) in col.iter().enumerate() {
            x.store(&mut job.out[r * job.out_stride + base..]);
        }
        base += L::N;
    }
}

/// A node's axis-aligned box (corners `lo`, `hi` in its mesh's frame) moved by `mv`: the
/// centre through the rotation, the half-extents through `|R|`, widened by the motion's
/// rounding (in the working precision, within `3 u mag` of the exact motion, `Pose`; this f64
/// arithmetic within `8 eps64 mag`: `mv.rel` covers both). Unfused, as [`columns`].
#[inline(always)]
pub(crate) fn moved_aabb<L: Lanes<S = f64>>(
    k: L::K,
    mv: &Moved,
    lo: &[L; 3],
    hi: &[L; 3],
) -> ([L; 3], [L; 3]) {
    let c = |v: f64| L::splat(k, v);
    let half = c(0.5);
    let mut bc = [c(0.0); 3];
    let mut bh = [c(0.0); 3];
    for q in 0..3 {
        (bc[q], bh[q]) = (half.mul(lo[q]).add(half.mul(hi[q])), half.mul(hi[q]).sub(half.mul(lo[q])));
    }
    let (mut out_lo, mut out_hi) = ([c(0.0); 3], [c(0.0); 3]);
    for r in 0..3 {
        let tr = c(mv.t[r]);
        let (mut cr, mut hr, mut mag) = (tr, c(0.0), tr.abs());
        for q in 0..3 {
            let rq = c(mv.r[r][q]);
            cr = cr.add(rq.mul(bc[q]));
            hr = hr.add(rq.abs().mul(bh[q]));
            mag = mag.add(rq.abs().mul(bc[q].abs().add(bh[q])));
        }
        let slack = mag.mul(c(mv.rel));
        out_lo[r] = cr.sub(hr).sub(slack);
        out_hi[r] = cr.add(hr).add(slack);
    }
    (out_lo, out_hi)
}

/// `a . b` as `(a0 b0 + a1 b1) + a2 b2`, unfused.
#[inline(always)]
fn dot3<L: Lanes>(a: &[L; 3], b: &[L; 3]) -> L {
    a[0].mul(b[0]).add(a[1].mul(b[1])).add(a[2].mul(b[2]))
}

/// A squared gap computed in f64 (a few roundings), lowered past them: a lower bound of the
/// exact square.
pub(crate) const DOWN: f64 = 1.0 - 8.0 * f64::EPSILON;

/// The children of one node against one node of the other tree.
pub(crate) struct NodeTest<'a> {
    /// The children's columns, row by row: row `r` of child `j` at `r * stride + j`. `stride`
    /// is a multiple of every f64 lane count (4) and at least the number of children; the
    /// lanes past `n` hold the bounds of the next nodes (real ones: finite numbers).
    pub group: &'a [f64],
    pub stride: usize,
    /// How many children.
    pub n: usize,
    /// The other node: row `r` at `r * fixed_stride`.
    pub fixed: &'a [f64],
    pub fixed_stride: usize,
    /// The search's limit on the squared gap ([`Limit`]).
    pub limit: Limit,
}

/// A search's limit on the squared gap of a node pair: beyond it the pair is pruned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Limit {
    /// The same for every pair.
    Fixed(f64),
    /// `w^2` with `w = (margin + per S) + absolute`, divided by `keep` when given, `S` the
    /// largest absolute coordinate of the pair's two moved boxes (a bound of every triangle
    /// pair's magnitude in them), at most [`square_cap`]: the reach of the contact and
    /// intersection searches (`crate::mesh`'s `reach`). The node test computes it a lane per child, the same
    /// operations in the same order as [`Limit::at`] (exact maxima, then plain roundings),
    /// so the same number.
    Reach { margin: f64, per: f64, absolute: f64, keep: Option<f64> },
}

impl Limit {
    /// The limit of a pair whose boxes' magnitude `mag` gives (asked only when needed).
    pub(crate) fn at(self, mag: impl FnOnce() -> f64) -> f64 {
        match self {
            Limit::Fixed(x) => x,
            Limit::Reach { margin, per, absolute, keep } => {
                let w = margin + per * mag() + absolute;
                let w = match keep {
                    Some(k) => w / k,
                    None => w,
                };
                (w * w).min(square_cap(margin))
            }
        }
    }
}

/// The largest a [`Limit::Reach`] may be: the largest `f64` unless the margin's own square
/// overflows. Where only the tolerance's part overflows (`per S` beyond about 1.3e154: f64
/// coordinates beyond about 1e168), a node pair whose squared gap overflows too is then
/// pruned: its gap, beyond 1.3e154 and a rigorous lower bound, proves it apart, though a
/// tolerance that wide would let the kernels call it within. Without the cap `+inf` pruned
/// nothing, and the intersection query answered every pair (minutes for the Armadillo
/// against fandisk, `tridist mesh ... --pose-b 1e200,0,0`). A margin whose square overflows
/// asks for the pairs within it, every one of them: no cap.
#[inline(always)]
pub(crate) fn square_cap(margin: f64) -> f64 {
    if (margin * margin).is_finite() {
        f64::MAX
    } else {
        f64::INFINITY
    }
}

/// Two leaves' triangles, each leaf's moved triangles' boxes as six rows of one number per
/// triangle (the lower corner's three coordinates, then the upper corner's): row `r` of
/// triangle `j` at `r * n + j`, followed by at least [`MAX_LEAF`] numbers, finite, that the
/// last vector's lanes past `n` read and never use.
pub(crate) struct LeafTest<'a> {
    pub a: &'a [f64],
    pub na: usize,
    pub b: &'a [f64],
    pub nb: usize,
    /// The search's limit on the squared gap.
    pub limit: f64,
}

/// Which triangle pairs of two leaves have boxes not beyond `t.limit` apart: bit
/// `i * MAX_LEAF + j` of `out` for triangle `i` of `a` and `j` of `b`, a lane per triangle of
/// `b`. The squared gap is `crate::mesh`'s `box_gap2`, the same operations in the same order
/// (plain, never fused; the maxima of finite numbers), so every instruction set keeps the
/// same pairs as that scalar test (tested). A NaN limit keeps every pair, as there. (The
/// scalar test with a branch per pair, half of which a contact query keeps, unpredictably,
/// was 14 % of the contact query's time at near contact, `perf` of `spin mesh contacts n3
/// f32 1 4`.)
#[inline(always)]
pub(crate) fn leaf_pairs<L: Lanes<S = f64>>(k: L::K, t: &LeafTest<'_>, out: &mut u64) {
    let c = |v: f64| L::splat(k, v);
    let (z, down, lim) = (c(0.0), c(DOWN), c(t.limit));
    let lanes = (1u32 << L::N) - 1;
    let mut near = 0u64;
    let mut base = 0;
    while base < t.nb {
        let (mut lo, mut hi) = ([z; 3], [z; 3]);
        for q in 0..3 {
            lo[q] = L::load(k, &t.b[q * t.nb + base..]);
            hi[q] = L::load(k, &t.b[(3 + q) * t.nb + base..]);
        }
        for i in 0..t.na {
            let mut s = z;
            for q in 0..3 {
                let (alo, ahi) = (c(t.a[q * t.na + i]), c(t.a[(3 + q) * t.na + i]));
                let g = lo[q].sub(ahi).max(alo.sub(hi[q])).max(z);
                s = s.add(g.mul(g));
            }
            let far = s.mul(down).gt(lim);
            near |= u64::from(!far.bits() & lanes) << (i * MAX_LEAF + base);
        }
        base += L::N;
    }
    // the lanes past the last triangle of `b`, in every row
    let row = (1u64 << t.nb) - 1;
    *out = (0..t.na).fold(0, |m, i| m | row << (i * MAX_LEAF)) & near;
}

/// The node test's answer per child: the lower bound of the squared gap and the limit it was
/// held against.
pub(crate) struct Gaps {
    pub gap: [f64; MAX_WIDTH],
    pub lim: [f64; MAX_WIDTH],
}

impl Gaps {
    pub(crate) fn new() -> Self {
        Gaps { gap: [0.0; MAX_WIDTH], lim: [f64::NEG_INFINITY; MAX_WIDTH] }
    }
}

/// Lane numbers, for the lanes past the last child.
const LANE: [f64; MAX_WIDTH] = {
    let mut x = [0.0; MAX_WIDTH];
    let mut i = 0;
    while i < MAX_WIDTH {
        x[i] = i as f64;
        i += 1;
    }
    x
};

/// For each child `j < t.n`: a lower bound of the squared distance between it and the fixed
/// node, exact when it is at most `t.lim[j]` (then every axis was tried), and otherwise only
/// known to exceed it (the node pair is pruned). Where that bound is 0 (the boxes overlap and
/// no oriented-box axis separates the nodes), the child gets instead minus the moved boxes'
/// overlap as a fraction of their extents ([`overlap`]): a number in [-1/2, 0], still a
/// lower bound, never pruned (every search's limit is at least 0), that makes the traversal
/// visit the most deeply overlapping node pairs first. (The order the traversal takes among
/// overlapping nodes decides how soon a collision query meets an intersecting triangle pair,
/// and a distance query a touching one: at the report's interpenetrating poses, the order of
/// node numbers visited 8 leaf pairs and made 127 node tests before the first hit at pose 6;
/// the overlap's depth, not as a fraction, reached it at the first leaf pair but after 81
/// node tests: calls per query in callgrind of `spin mesh intersect 6 f32 1 0.5`. Times in
/// `crate::mesh`'s docs.)
#[inline(always)]
pub(crate) fn gaps<L: Lanes<S = f64>>(k: L::K, t: &NodeTest<'_>, out: &mut Gaps) {
    let c = |v: f64| L::splat(k, v);
    let z = c(0.0);
    // The other node's rows are read where they are used, not all copied first: a vector the
    // boxes prune reads 6 of its 32 rows (3 of the 16 cache lines they span at width 4). The
    // distance query summed over the report's 24 poses (`spin mesh distance <pose> f32 1
    // 0.2`, the 12 trajectory poses and the 12 near-contact placements, two builds alternated
    // 16 times, 2026-11-27, the machine noisy): 3.36 -> 3.14 ms, medians, faster in 11 of the
    // 16 rounds; 3.5 % fewer instructions in the node test at pose 9 (`TRIDIST_ISA=avx2fma
    // valgrind --tool=callgrind spin mesh distance 9 f32 1 0.001`).
    let fixed = &t.fixed[..(ROWS - 1) * t.fixed_stride + 1];
    let b = |r: usize| c(fixed[r * t.fixed_stride]);
    // the other node's magnitude, for a limit that grows with it (only then)
    let mut fixed_mag = 0.0f64;
    if let Limit::Reach { .. } = t.limit {
        for r in LO..HI + 3 {
            fixed_mag = fixed_mag.max(fixed[r * t.fixed_stride].abs());
        }
    }
    // (the reach's cap depends on the search's margin alone: once per node test)
    let cap = match t.limit {
        Limit::Reach { margin, .. } => square_cap(margin),
        Limit::Fixed(_) => f64::INFINITY,
    };
    let mut base = 0;
    while base < t.n {
        let a = |r: usize| L::load(k, &t.group[r * t.stride + base..]);
        let lim = match t.limit {
            Limit::Fixed(x) => c(x),
            Limit::Reach { margin, per, absolute, keep } => {
                // (a lane per child here, not child by child in scalar code before the test,
                // where the limit and the boxes it read took 7 % of the contact query's
                // samples at near-contact placement 3: `perf record` of `spin mesh contacts
                // n3 f32 1 3`. Two builds alternated, 2026-11-28: `spin mesh <query> <pose>
                // f32|f64 1 <0.15-0.3 s>`'s mean time per call, summed over the report's
                // poses, the median of the rounds: contacts f32 over the 12 near-contact
                // placements 3.73 -> 3.36 ms, faster in 4 of 4 rounds, f64 4.21 -> 3.82 ms,
                // 3 of 3; intersection over all 24 poses 0.503 -> 0.448 ms, 4 of 4; and the
                // distance query, whose limit is fixed but whose children's boxes were read
                // for it all the same, 2.11 -> 1.88 ms, 3 of 3.)
                let mut mag = c(fixed_mag);
                for r in LO..HI + 3 {
                    mag = mag.max(a(r).abs());
                }
                let w = c(margin).add(c(per).mul(mag)).add(c(absolute));
                let w = match keep {
                    Some(x) => w.div(c(x)),
                    None => w,
                };
                w.mul(w).min(c(cap))
            }
        };
        // lanes past the last child: never below their limit
        let lim = L::select(L::load(k, &LANE[base..]).lt(c(t.n as f64)), lim, c(f64::NEG_INFINITY));
        lim.store(&mut out.lim[base..]);
        // the boxes' separation along each axis (negative where they overlap)
        let (mut box2, mut sep) = (z, [z; 3]);
        for (q, s) in sep.iter_mut().enumerate() {
            *s = b(LO + q).sub(a(HI + q)).max(a(LO + q).sub(b(HI + q)));
            let g = s.max(z);
            box2 = g.mul_add(g, box2);
        }
        let mut gap = box2.mul(c(DOWN));
        if gap.le(lim).any() {
            gap = gap.max(obb_gap2(k, &a, &b, gap, lim));
        }
        let touch = gap.le(z);
        if touch.any() {
            // where no bound separates the nodes, minus the boxes' overlap (see the doc)
            gap = L::select(touch, overlap(k, &a, &b, &sep), gap);
        }
        gap.store(&mut out.gap[base..]);
        base += L::N;
    }
}

/// Minus the overlap of the moved boxes of children `a` (lanes) and the fixed node `b`, as a
/// fraction: along each axis, their separation `sep` (negative where they overlap) over the
/// sum of their extents; the largest of the three, at most 0 (from -1/2, one box centred in
/// the other and as wide, to 0, touching). Subtractions, additions, divisions and maxima: the
/// same on every instruction set.
#[inline(always)]
fn overlap<L: Lanes<S = f64>>(k: L::K, a: &impl Fn(usize) -> L, b: &impl Fn(usize) -> L, sep: &[L; 3]) -> L {
    let c = |v: f64| L::splat(k, v);
    let mut key = c(f64::NEG_INFINITY);
    for (q, s) in sep.iter().enumerate() {
        let ext = a(HI + q).sub(a(LO + q)).add(b(HI + q).sub(b(LO + q)));
        key = key.max(s.div(ext.max(c(f64::MIN_POSITIVE))));
    }
    key.min(c(0.0))
}

/// The oriented boxes' squared gap lower bound of children `a` (lanes) and the fixed node `b`
/// (rows given by the two closures), stopping after the centre line when every lane's gap
/// (with `box2`, the boxes' one) already exceeds `lim`.
#[inline(always)]
fn obb_gap2<L: Lanes<S = f64>>(
    k: L::K,
    a: &impl Fn(usize) -> L,
    b: &impl Fn(usize) -> L,
    box2: L,
    lim: L,
) -> L {
    let c = |v: f64| L::splat(k, v);
    let z = c(0.0);
    // (no array maps in this file: they stay calls without the instruction set's features,
    // and so do the vector operations inside them)
    let ae = [v3(a, E), v3(a, E + 3), v3(a, E + 6)];
    let be = [v3(b, E), v3(b, E + 3), v3(b, E + 6)];
    let dc = v3(b, C).sub(v3(a, C));
    let rho = a(RHO).add(b(RHO));
    let errs = a(ERR).add(b(ERR));
    let (up, shrink) = (c(1.0 + 1e-12), c(1.0 - 1e-12));
    // The gap along an axis from the centres' projection `proj`, the boxes' radii `ra`, `rb`
    // (all times the axis' length) and the axis' length and 1-norm, lowered past rounding;
    // 0 where the projections overlap.
    let axis = |proj: L, ra: L, rb: L, len: L, n1: L| {
        let g = proj.sub(ra).sub(rb);
        let lowered = g.sub(errs.mul(n1)).mul(shrink).div(len);
        L::select(g.gt(z), lowered, z)
    };
    let squared = |best: L| {
        let o = best.sub(rho).max(z);
        o.mul(o).mul(c(DOWN))
    };
    // The centre line first: it prunes most often, and needs none of the nine cross dots.
    let da = [ae[0].dot(dc), ae[1].dot(dc), ae[2].dot(dc)];
    let db = [be[0].dot(dc), be[1].dot(dc), be[2].dot(dc)];
    let pc = dc.dot(dc);
    let mut best = axis(pc, radius(a, &da), radius(b, &db), pc.sqrt().mul(up), dc.norm1());
    if box2.max(squared(best)).gt(lim).all() {
        return squared(best);
    }
    // x[i][j] = a.e_i . b.e_j: row q holds b's axes' dots with a's axis q, column q a's
    // with b's axis q
    let mut x = [[z; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            x[i][j] = ae[i].dot(be[j]);
        }
    }
    for q in 0..3 {
        let rb = radius(b, &x[q]);
        best = best.max(axis(da[q].abs(), a(OWN + q), rb, a(LEN + q), a(N1 + q)));
    }
    for q in 0..3 {
        let ra = radius(a, &[x[0][q], x[1][q], x[2][q]]);
        best = best.max(axis(db[q].abs(), ra, b(OWN + q), b(LEN + q), b(N1 + q)));
    }
    squared(best)
}

/// Rows `r..r + 3` as a vector.
#[inline(always)]
fn v3<L: Lanes>(f: &impl Fn(usize) -> L, r: usize) -> V3<L> {
    V3::new(f(r), f(r + 1), f(r + 2))
}

/// A box's radius along an axis from its axes' dot products `d` with it: `sum_i h_i |d_i|`.
#[inline(always)]
fn radius<L: Lanes>(f: &impl Fn(usize) -> L, d: &[L; 3]) -> L {
    f(H).mul_add(d[0].abs(), f(H + 1).mul_add(d[1].abs(), f(H + 2).mul(d[2].abs())))
}
