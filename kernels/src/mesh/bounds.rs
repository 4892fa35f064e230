//! The bounds the traversal prunes with: axis-aligned boxes, oriented boxes certified to hold
//! their vertices despite f64 rounding, a mesh's moved node boxes, and the squared gaps (each
//! rounded down: a lower bound of the exact one) that every pruning test compares with a
//! search's limit.

use super::Mesh;
#[cfg(test)]
use crate::algo::nodes::Column;
use crate::algo::nodes::Columns;
use crate::algo::nodes::Limit;
use crate::algo::nodes::Moved;
use crate::algo::nodes::DOWN;
#[cfg(test)]
use crate::algo::nodes::ROWS;
use crate::Error;
use crate::Real;
use crate::Triangle;

impl<T: Real> Mesh<T> {
    /// Node `i`'s box moved by `pose` ([`crate::algo::nodes::moved_aabb`], as the node tests'
    /// columns move it).
    pub(super) fn moved_box(&self, i: usize, pose: &Moved) -> ([f64; 3], [f64; 3]) {
        let n = &self.nodes[i];
        crate::algo::nodes::moved_aabb::<f64>(crate::lanes::Portable, pose, &n.lo, &n.hi)
    }

    /// The job of computing the moved bounds of nodes `first..first + n` into `out` (row `r`
    /// of node `first + j` at `r * out_stride + j`).
    pub(super) fn columns<'a>(
        &'a self,
        mv: &'a Moved,
        first: usize,
        n: usize,
        out: &'a mut [f64],
        out_stride: usize,
    ) -> Columns<'a> {
        Columns { mv, src: &self.bounds, src_stride: self.bounds_stride, first, n, out, out_stride }
    }
}

/// The box that holds nothing ([`unite`] starts from it).
pub(super) const EMPTY: Aabb = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);

/// Grows box `a` to hold box `b`.
pub(super) fn unite(a: &mut Aabb, b: &Aabb) {
    for q in 0..3 {
        a.0[q] = least(a.0[q], b.0[q]);
        a.1[q] = most(a.1[q], b.1[q]);
    }
}

/// The least of a running minimum `acc` (never NaN) and `x`, NaN `x` ignored as by
/// [`f64::min`], but in one instruction (`minsd`; `f64::min` also tests `acc` for NaN, three
/// instructions on the bounds' loop-carried chains).
pub(super) fn least(acc: f64, x: f64) -> f64 {
    if x < acc {
        x
    } else {
        acc
    }
}

/// The greatest of a running maximum `acc` (never NaN) and `x`, as [`least`].
pub(super) fn most(acc: f64, x: f64) -> f64 {
    if x > acc {
        x
    } else {
        acc
    }
}

/// Half a box's surface area (0 for an empty one; the tree's width collapse compares nodes by
/// it too).
pub(super) fn half_area(b: &Aabb) -> f64 {
    let d = [0, 1, 2].map(|k| (b.1[k] - b.0[k]).max(0.0));
    d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
}

/// An oriented box in the mesh frame, as a container that f64 rounding cannot break: the
/// points `c + sum_i s_i e_i` with `|s_i| <= h_i`, enlarged by the ball of radius `rho`. Every
/// vertex `v` of the node is in it *exactly*: with `s_i = e_i . (v - c)` and the residual
/// `r = v - c - sum_i s_i e_i` (an identity for any `e_i`), `h_i` and `rho` bound `|s_i|` and
/// `|r|` with a margin for the rounding of their computation, from the vertices' extents
/// along the axes and how far the computed axes are from orthonormal (`Obb::fit`; the unit
/// test checks it in double-double arithmetic on far-from-origin, flat and collinear sets).
/// The axes come from the
/// principal axes of the node's vertices, so a flat patch gets a thin box in any pose (the
/// axis-aligned boxes only in the mesh frame); a node of more than [`OBB_FIT_MAX`] triangles
/// takes the mesh frame's axes and its axis-aligned box ([`Obb::of_box`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct Obb {
    pub(super) c: [f64; 3],
    pub(super) e: [[f64; 3]; 3],
    pub(super) h: [f64; 3],
    pub(super) rho: f64,
}

pub(super) fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(super) fn norm1(a: &[f64; 3]) -> f64 {
    a[0].abs() + a[1].abs() + a[2].abs()
}

/// The mesh frame's axes.
pub(super) const ID: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// Orthonormal axes (rows) along the eigenvectors of a symmetric 3x3 matrix, in closed form
/// (the eigenvalues from the characteristic cubic by the trigonometric method; the vector of
/// the best separated one as the longest cross product of two rows of `A - l I`, the vector
/// of the other extreme one likewise, made orthogonal to it, the third their cross product).
/// Only their being a well-conditioned basis matters here (the box is certified afterwards):
/// where eigenvalues coincide any basis of their eigenspace is as good, and a matrix with no
/// direction preferred (or NaN) gets the identity. (Cyclic Jacobi rotations, 12 sweeps to
/// 1e-9, took about 270 ns per leaf, a quarter of the build: `spin mesh build 0 f32 1 2`.
/// Written as straight-line code, this and the smaller split items of `build` took the
/// same command from 32.5 to 26.8 ms, the eigenvector's rows and longest cross product
/// having been picked through arrays and closures before.)
pub(super) fn principal_axes(a: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    // Scaled to entries of order 1 (the same eigenvectors): no square below underflows or
    // overflows, whatever the coordinates' magnitude.
    let big = a.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    if !(big > 0.0 && big.is_finite()) {
        return ID;
    }
    let a = a.map(|r| r.map(|x| x / big));
    let p1 = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    let q = (a[0][0] + a[1][1] + a[2][2]) / 3.0;
    let d = [a[0][0] - q, a[1][1] - q, a[2][2] - q];
    let p2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + 2.0 * p1;
    if !(p2 > 0.0 && p2.is_finite()) {
        return ID;
    }
    let p = (p2 / 6.0).sqrt();
    // r = det(B) / 2 in [-1, 1] with B = (A - q I) / p
    let ip = 1.0 / p;
    let b = [
        [d[0] * ip, a[0][1] * ip, a[0][2] * ip],
        [a[0][1] * ip, d[1] * ip, a[1][2] * ip],
        [a[0][2] * ip, a[1][2] * ip, d[2] * ip],
    ];
    let det = b[0][0] * (b[1][1] * b[2][2] - b[1][2] * b[1][2])
        - b[0][1] * (b[0][1] * b[2][2] - b[1][2] * b[0][2])
        + b[0][2] * (b[0][1] * b[1][2] - b[1][1] * b[0][2]);
    let phi = (0.5 * det).clamp(-1.0, 1.0).acos() / 3.0;
    // The eigenvalues of B (trace 0; those of A are q + p m), B's eigenvectors A's, and B's
    // entries of order 1 whatever A's scale: cos(phi + 2 pi / 3) = -cos(phi) / 2 -
    // sin(phi) sqrt(3) / 2.
    let (sin, cos) = phi.sin_cos();
    let m1 = 2.0 * cos;
    let m3 = -cos - 3f64.sqrt() * sin;
    let m2 = -m1 - m3;
    let (first, second) = if m1 - m2 >= m2 - m3 { (m1, m3) } else { (m3, m1) };
    let Some(x) = eigenvector(&b, first) else { return ID };
    let y = eigenvector(&b, second)
        .and_then(|y| {
            let c = dot(&y, &x);
            unit([y[0] - c * x[0], y[1] - c * x[1], y[2] - c * x[2]])
        })
        .or_else(|| {
            // any direction normal to x: across its smallest component
            let k = (0..3).min_by(|&i, &j| x[i].abs().total_cmp(&x[j].abs())).unwrap_or(0);
            let mut ek = [0.0; 3];
            ek[k] = 1.0;
            unit(cross(&x, &ek))
        });
    let Some(y) = y else { return ID };
    // (finite: `unit` returns only finite unit vectors)
    [x, y, cross(&x, &y)]
}

/// A unit eigenvector of the symmetric `a` for its eigenvalue `l`: the longest cross product
/// of two rows of `a - l I` (they span the normal space of the eigenvector), `None` when all
/// vanish.
pub(super) fn eigenvector(a: &[[f64; 3]; 3], l: f64) -> Option<[f64; 3]> {
    let r0 = [a[0][0] - l, a[0][1], a[0][2]];
    let r1 = [a[1][0], a[1][1] - l, a[1][2]];
    let r2 = [a[2][0], a[2][1], a[2][2] - l];
    let (c0, c1, c2) = (cross(&r0, &r1), cross(&r0, &r2), cross(&r1, &r2));
    let (n0, n1, n2) = (dot(&c0, &c0), dot(&c1, &c1), dot(&c2, &c2));
    let (c, n) = if n0 >= n1 { (c0, n0) } else { (c1, n1) };
    let (c, n) = if n >= n2 { (c, n) } else { (c2, n2) };
    unit_of(c, n)
}

pub(super) fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// `a / |a|`, or `None` for a zero or non-finite length.
pub(super) fn unit(a: [f64; 3]) -> Option<[f64; 3]> {
    unit_of(a, dot(&a, &a))
}

/// [`unit()`] with `|a|^2` already computed as `n2`.
pub(super) fn unit_of(a: [f64; 3], n2: f64) -> Option<[f64; 3]> {
    let n = n2.sqrt();
    let inv = 1.0 / n;
    (n > 0.0 && n.is_finite()).then(|| a.map(|x| x * inv))
}

impl Obb {
    /// The box of the points in the axis-aligned box `b` on the mesh frame's axes (the
    /// projections are the coordinates themselves, exactly), certified as the type says.
    pub(super) fn of_box(b: &Aabb) -> Obb {
        let big = norm1(&[0, 1, 2].map(|k| b.0[k].abs().max(b.1[k].abs()))) * (1.0 + 4.0 * f64::EPSILON);
        Obb::certify(ID, b.0, b.1, big)
    }

    /// The box of `points` (at least one), certified as the type says.
    pub(super) fn fit(points: &[[f64; 3]]) -> Obb {
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
        // The extents along the axes and the largest 1-norm, in the same pass.
        let (mut lo, mut hi, mut big) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3], 0.0f64);
        for p in points {
            for i in 0..3 {
                let s = dot(&e[i], p);
                lo[i] = least(lo[i], s);
                hi[i] = most(hi[i], s);
            }
            big = most(big, norm1(p));
        }
        Obb::certify(e, lo, hi, big)
    }

    /// The box on the axes `e` (rows, near orthonormal: the certificate allows for how far)
    /// of the points whose computed projections `e_i . v` lie in `[lo_i, hi_i]` and whose
    /// 1-norms are at most `big`, certified as the type says.
    pub(super) fn certify(e: [[f64; 3]; 3], lo: [f64; 3], hi: [f64; 3], big: f64) -> Obb {
        let mid = [0, 1, 2].map(|i| 0.5 * lo[i] + 0.5 * hi[i]);
        let c = [0, 1, 2].map(|k| (0..3).map(|i| mid[i] * e[i][k]).sum::<f64>());
        // The certificate, from those alone (no pass over the points again). For a vertex `v`,
        // exactly: `s_i = e_i . v - e_i . c`, where the computed `e_i . v` lies in
        // [lo_i, hi_i] and each dot product is within `2 eps w |x|_1` of the exact one (`w` the
        // largest axis entry, about 1), so `|s_i| <= max(hi_i - e_i . c, e_i . c - lo_i)` plus
        // `6 eps w m` with `m = |v|_1 + |c|_1` and the subtraction's rounding; and
        // `r = (I - E^T E)(v - c)` (E the axes as rows), so `|r| <= |r|_1 <= |G|_1 m` with
        // `|G|_1` the largest column sum of `G = I - E^T E`, each entry computed within
        // `8 eps (1 + 3 w^2)`. `slack` is far above both allowances.
        let w = e.iter().flatten().fold(1.0f64, |a, x| a.max(x.abs()));
        let m = (big + norm1(&c)) * (1.0 + 8.0 * f64::EPSILON);
        let slack = 64.0 * f64::EPSILON * w * m;
        let h = [0, 1, 2].map(|i| {
            let ec = dot(&e[i], &c);
            (hi[i] - ec).max(ec - lo[i]) + slack
        });
        let mut g = 0.0f64;
        for j in 0..3 {
            let mut col = 0.0;
            for i in 0..3 {
                let id = if i == j { 1.0 } else { 0.0 };
                col += (id - (e[0][i] * e[0][j] + e[1][i] * e[1][j] + e[2][i] * e[2][j])).abs();
            }
            g = g.max(col);
        }
        let g = (g + 32.0 * f64::EPSILON * (1.0 + 3.0 * w * w)) * (1.0 + 8.0 * f64::EPSILON);
        Obb { c, e, h, rho: g * m + slack }
    }
}

impl Moved {
    /// Node `i`'s moved bounds ([`Column`]): its box moved as [`Mesh::moved_box`] moves it, and
    /// its oriented box moved exactly (the linear map takes the box to the parallelepiped
    /// `c' + sum s_i e_i'`, `|s_i| <= h_i`, and the ball into a ball `|R|_F` times larger),
    /// with `ERR`, a bound of the rounding of the computed `c'`, `e_i'` (1-norms, the `e_i'`
    /// weighted by `h_i`), and `RHO` grown by the ball's growth and the rounding of the
    /// vertices' motion in the working precision; `OWN`, `LEN`, `N1`: the box's radius along,
    /// and the length and 1-norm of, each of its own axes, computed once per moved box. One
    /// node in the portable code ([`crate::algo::nodes::columns`]): the tests' reference. The
    /// queries compute groups on the engine's lanes ([`Side::group`], [`Side::bounds_at`]),
    /// to the same numbers.
    #[cfg(test)]
    pub(super) fn column<T: Real>(&self, mesh: &Mesh<T>, i: usize) -> Column {
        let mut col = [0.0; ROWS];
        let mut job = mesh.columns(self, i, 1, &mut col, 1);
        crate::arch::node_columns(crate::Isa::Scalar, &mut job);
        col
    }

    /// `Ok` unless `mesh`'s moved root box leaves the range of `T` (a moved vertex could
    /// overflow): then [`Error::NonFiniteCoordinate`].
    pub(super) fn fits<T: Real>(&self, mesh: &Mesh<T>) -> Result<(), Error> {
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
pub(super) fn down(s: f64) -> f64 {
    s * DOWN
}

/// Squared distance between two boxes, rounded down (a lower bound of the exact one).
pub(super) fn box_gap2(a: &Aabb, b: &Aabb) -> f64 {
    let mut s = 0.0;
    for k in 0..3 {
        let g = (b.0[k] - a.1[k]).max(a.0[k] - b.1[k]).max(0.0);
        s += g * g;
    }
    down(s)
}

/// Squared distance from a point to a box, rounded down.
pub(super) fn point_gap2(x: &[f64; 3], b: &([f64; 3], [f64; 3])) -> f64 {
    let mut s = 0.0;
    for k in 0..3 {
        let g = (b.0[k] - x[k]).max(x[k] - b.1[k]).max(0.0);
        s += g * g;
    }
    down(s)
}

/// The largest absolute coordinate of two boxes (NaN ignored, as by
/// [`f64::max`]): a bound of the magnitude `S` of every triangle pair in them. A tree of
/// compare-and-selects ([`most`]): as a chain of twelve `f64::max` (three instructions each,
/// one after the other) it and the line waiting on it held 28 % of `children`'s samples when
/// it fed every child's limit in every node test (`perf record` of `spin mesh contacts 5 f32 1
/// 4`, `perf annotate`). The node test now computes those limits itself, a lane per child
/// ([`Limit::Reach`]); this one serves the pair a visit takes ([`walk`]) and the roots.
pub(super) fn magnitude(a: &Aabb, b: &Aabb) -> f64 {
    // per axis, the pairs from 0 (never NaN), then the tree of those
    let mut m = [0.0f64; 6];
    for k in 0..3 {
        m[2 * k] = most(most(0.0, a.0[k].abs()), a.1[k].abs());
        m[2 * k + 1] = most(most(0.0, b.0[k].abs()), b.1[k].abs());
    }
    most(most(most(m[0], m[1]), most(m[2], m[3])), most(m[4], m[5]))
}

/// How far apart (exactly) two triangles of magnitude at most `S` may be and still be
/// answered within `margin` by the kernels, squared, as a search's limit ([`Limit::Reach`],
/// taken at each node pair's magnitude): an answer is at least its certified lower bound,
/// which is at least the exact distance less the tolerance width
/// `max(scaled u S, absolute, relative lo)`, plus a little for the rounding of the box tests
/// (`8 u S`, far above it). Uncertified pairs (counted by the batch, rare) are outside this
/// guarantee. Infinite when the relative tolerance is 1 or more.
pub(super) fn reach<T: Real>(tol: &crate::Tolerance, margin: f64) -> Limit {
    let per = (tol.scaled + 8.0) * T::UNIT_ROUNDOFF.to_f64();
    let absolute = tol.absolute;
    if tol.relative == 0.0 {
        // (the default: the same number without a division; in perf of `spin mesh intersect 6
        // f32 1 3` the instructions waiting on it held about 12 % of `search`'s samples, this
        // being every node pair's limit)
        Limit::Reach { margin, per, absolute, keep: None }
    } else if tol.relative < 1.0 {
        Limit::Reach { margin, per, absolute, keep: Some(1.0 - tol.relative) }
    } else {
        Limit::Fixed(f64::INFINITY)
    }
}

/// An axis-aligned box (lower and upper corner) in f64.
pub(super) type Aabb = ([f64; 3], [f64; 3]);

/// The box of a triangle, in f64 (exact: every `T` converts exactly).
pub(super) fn tri_box<T: Real>(t: &Triangle<T>) -> Aabb {
    let (mut lo, mut hi) = ([0.0; 3], [0.0; 3]);
    for k in 0..3 {
        let x = [t[0][k].to_f64(), t[1][k].to_f64(), t[2][k].to_f64()];
        (lo[k], hi[k]) = (x[0].min(x[1]).min(x[2]), x[0].max(x[1]).max(x[2]));
    }
    (lo, hi)
}
