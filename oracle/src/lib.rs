//! # tridist-oracle: exact answers and the shared error metrics
//!
//! Every finite `f32`/`f64` is a dyadic rational, so the squared distance between two triangles
//! (segments, a point and a triangle) given in floats is a rational number. This crate computes
//! it exactly with GMP rationals (`rug`), with no tolerance anywhere, together with the exact
//! intersection predicate and one exact pair of closest points. It is the judge for tridist's
//! tests, fuzz targets and reports.
//!
//! Two independent formulations of the triangle-triangle distance are provided and cross-checked
//! by the tests:
//! * [`sqdist_triangle_triangle`]: the minimum over the 15 feature pairs (9 segment-segment,
//!   6 point-triangle, each solved exactly) and an exact intersection predicate built from
//!   orientation signs (an edge properly crossing the other triangle's plane inside it);
//! * [`sqdist_triangle_triangle_kkt`]: minimisation of the convex quadratic |x(a,b) - y(g,d)|^2
//!   over the product of the triangles by enumerating all 49 face pairs (vertex, edge or interior
//!   of each) and solving each pair's stationary system exactly.
//!
//! The error metrics of `ACCURACY.md` live in [`metrics`].

mod filter;
pub mod metrics;
pub mod round;

use rug::Rational;

/// An exact point.
pub type P3 = [Rational; 3];

/// An input coordinate was NaN or infinite.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NonFinite;

impl core::fmt::Display for NonFinite {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("non-finite coordinate")
    }
}
impl std::error::Error for NonFinite {}

/// A float type the oracle accepts: `f32` or `f64` (every finite value converts exactly).
pub trait Float: Copy + Into<f64> {}
impl Float for f32 {}
impl Float for f64 {}

/// Exact conversion of one coordinate.
pub fn exact<F: Float>(x: F) -> Result<Rational, NonFinite> {
    Rational::from_f64(x.into()).ok_or(NonFinite)
}

/// Exact conversion of a point.
pub fn exact_point<F: Float>(p: &[F; 3]) -> Result<P3, NonFinite> {
    Ok([exact(p[0])?, exact(p[1])?, exact(p[2])?])
}

/// Exact conversion of `K` points.
pub fn exact_points<F: Float, const K: usize>(p: &[[F; 3]; K]) -> Result<[P3; K], NonFinite> {
    let v: Vec<P3> = p.iter().map(exact_point).collect::<Result<_, _>>()?;
    Ok(v.try_into().unwrap_or_else(|_| unreachable!("K points in, K points out")))
}

/// An exact squared distance with one pair of closest points (`p` on the first primitive).
#[derive(Clone, Debug, PartialEq)]
pub struct Exact {
    /// The squared distance.
    pub d2: Rational,
    /// A closest point on the first primitive.
    pub p: P3,
    /// A closest point on the second primitive.
    pub q: P3,
}

impl Exact {
    fn swap(self) -> Exact {
        Exact { d2: self.d2, p: self.q, q: self.p }
    }
}

fn keep_min(best: &mut Option<Exact>, c: Exact) {
    if best.as_ref().is_none_or(|b| c.d2 < b.d2) {
        *best = Some(c);
    }
}

pub(crate) fn sub(a: &P3, b: &P3) -> P3 {
    [Rational::from(&a[0] - &b[0]), Rational::from(&a[1] - &b[1]), Rational::from(&a[2] - &b[2])]
}

pub(crate) fn dot(a: &P3, b: &P3) -> Rational {
    let mut r = Rational::from(&a[0] * &b[0]);
    r += Rational::from(&a[1] * &b[1]);
    r += Rational::from(&a[2] * &b[2]);
    r
}

pub(crate) fn cross(a: &P3, b: &P3) -> P3 {
    [
        Rational::from(&a[1] * &b[2]) - Rational::from(&a[2] * &b[1]),
        Rational::from(&a[2] * &b[0]) - Rational::from(&a[0] * &b[2]),
        Rational::from(&a[0] * &b[1]) - Rational::from(&a[1] * &b[0]),
    ]
}

/// `a + d * t`.
pub(crate) fn lerp(a: &P3, d: &P3, t: &Rational) -> P3 {
    [Rational::from(&d[0] * t) + &a[0], Rational::from(&d[1] * t) + &a[1], Rational::from(&d[2] * t) + &a[2]]
}

fn dist2(a: &P3, b: &P3) -> Rational {
    let d = sub(a, b);
    dot(&d, &d)
}

fn clamp01(t: Rational) -> Rational {
    if t < 0 {
        Rational::new()
    } else if t > 1 {
        Rational::from(1)
    } else {
        t
    }
}

/// Exact closest point to `x` on segment `[a, b]` (a point when `a == b`).
pub fn closest_point_segment(x: &P3, a: &P3, b: &P3) -> P3 {
    let d = sub(b, a);
    let dd = dot(&d, &d);
    if dd == 0 {
        return a.clone();
    }
    let t = clamp01(dot(&sub(x, a), &d) / dd);
    lerp(a, &d, &t)
}

/// Exact squared distance and closest points of segments `a` and `b`.
///
/// Candidates: the stationary point of the two lines when it lies in both segments (then it is
/// the unique answer), else the four endpoint-to-segment distances (the minimum of a convex
/// quadratic over a square lies in its interior or on an edge of it).
pub fn segment_segment(a: &[P3; 2], b: &[P3; 2]) -> Exact {
    let mut best: Option<Exact> = None;
    let d1 = sub(&a[1], &a[0]);
    let d2 = sub(&b[1], &b[0]);
    let r = sub(&a[0], &b[0]);
    let aa = dot(&d1, &d1);
    let e = dot(&d2, &d2);
    let bb = dot(&d1, &d2);
    let c = dot(&d1, &r);
    let f = dot(&d2, &r);
    let denom = Rational::from(&aa * &e) - Rational::from(&bb * &bb);
    if denom != 0 {
        let s = (Rational::from(&bb * &f) - Rational::from(&c * &e)) / &denom;
        let t = (Rational::from(&aa * &f) - Rational::from(&bb * &c)) / &denom;
        let unit = |x: &Rational| *x >= 0 && *x <= 1;
        if unit(&s) && unit(&t) {
            // The quadratic is strictly convex (denom != 0) and its minimiser is feasible: it is
            // the unique closest pair, so no endpoint candidate can be better or tie elsewhere.
            let p = lerp(&a[0], &d1, &s);
            let q = lerp(&b[0], &d2, &t);
            return Exact { d2: dist2(&p, &q), p, q };
        }
    }
    for x in a {
        let q = closest_point_segment(x, &b[0], &b[1]);
        keep_min(&mut best, Exact { d2: dist2(x, &q), p: x.clone(), q });
    }
    for y in b {
        let p = closest_point_segment(y, &a[0], &a[1]);
        keep_min(&mut best, Exact { d2: dist2(&p, y), p, q: y.clone() });
    }
    best.unwrap_or_else(|| unreachable!("four endpoint candidates"))
}

/// Exact squared distance from `x` to triangle `t` and the closest point (`q`; `p` is `x`).
///
/// Candidates: the orthogonal projection onto the plane when it lies inside the triangle
/// (barycentric coordinates from the exact 2x2 system; then it is the answer), else the three
/// edges. A degenerate
/// triangle (zero normal) is the union of its edges.
pub fn point_triangle(x: &P3, t: &[P3; 3]) -> Exact {
    let mut best: Option<Exact> = None;
    let e0 = sub(&t[1], &t[0]);
    let e1 = sub(&t[2], &t[0]);
    let n = cross(&e0, &e1);
    let nn = dot(&n, &n);
    if nn != 0 {
        let w = sub(x, &t[0]);
        let a00 = dot(&e0, &e0);
        let a01 = dot(&e0, &e1);
        let a11 = dot(&e1, &e1);
        let b0 = dot(&e0, &w);
        let b1 = dot(&e1, &w);
        // det = a00*a11 - a01^2 = |n|^2
        let u = (Rational::from(&a11 * &b0) - Rational::from(&a01 * &b1)) / &nn;
        let v = (Rational::from(&a00 * &b1) - Rational::from(&a01 * &b0)) / &nn;
        if u >= 0 && v >= 0 && Rational::from(&u + &v) <= 1 {
            // The projection lies in the triangle: it is the unique closest point.
            let q = lerp(&lerp(&t[0], &e0, &u), &e1, &v);
            return Exact { d2: dist2(x, &q), p: x.clone(), q };
        }
    }
    for k in 0..3 {
        let q = closest_point_segment(x, &t[k], &t[(k + 1) % 3]);
        keep_min(&mut best, Exact { d2: dist2(x, &q), p: x.clone(), q });
    }
    best.unwrap_or_else(|| unreachable!("three edge candidates"))
}

fn edge(t: &[P3; 3], k: usize) -> [P3; 2] {
    [t[k].clone(), t[(k + 1) % 3].clone()]
}

/// Minimum over the 15 feature pairs.
fn min15(s: &[P3; 3], t: &[P3; 3]) -> Exact {
    let mut best: Option<Exact> = None;
    for i in 0..3 {
        for j in 0..3 {
            keep_min(&mut best, segment_segment(&edge(s, i), &edge(t, j)));
        }
    }
    for k in 0..3 {
        keep_min(&mut best, point_triangle(&s[k], t));
        keep_min(&mut best, point_triangle(&t[k], s).swap());
    }
    best.unwrap_or_else(|| unreachable!("15 candidates"))
}

/// A point where an edge of `a` properly crosses the plane of non-degenerate `b` inside `b`.
fn piercing(a: &[P3; 3], b: &[P3; 3]) -> Option<P3> {
    let n = cross(&sub(&b[1], &b[0]), &sub(&b[2], &b[0]));
    if dot(&n, &n) == 0 {
        return None;
    }
    let h: Vec<Rational> = a.iter().map(|v| dot(&sub(v, &b[0]), &n)).collect();
    for k in 0..3 {
        let (h0, h1) = (&h[k], &h[(k + 1) % 3]);
        if (*h0 < 0 && *h1 > 0) || (*h0 > 0 && *h1 < 0) {
            let tpar = h0 / Rational::from(h0 - h1);
            let x = lerp(&a[k], &sub(&a[(k + 1) % 3], &a[k]), &tpar);
            // Inside test in the plane: x on the inner side of all three edges.
            let inside = (0..3).all(|m| {
                let ed = sub(&b[(m + 1) % 3], &b[m]);
                dot(&cross(&ed, &sub(&x, &b[m])), &n) >= 0
            });
            if inside {
                return Some(x);
            }
        }
    }
    None
}

/// Exact intersection predicate (touching counts): the 15-feature minimum is zero, or an edge of
/// one triangle properly crosses the other's plane at a point inside it.
pub fn intersect_triangle_triangle(s: &[P3; 3], t: &[P3; 3]) -> bool {
    triangle_triangle(s, t).d2 == 0
}

/// Is the triangles' overlap removable by a relative translation of length at most `delta`
/// (their penetration depth is at most `delta`)? True for disjoint or merely touching pairs.
///
/// For intersecting convex polytopes the penetration depth is the smallest overlap of their
/// projections over the facet normals of their Minkowski difference; for two triangles those
/// normals are among the two face normals and the nine edge-edge cross products (a flat
/// difference, as for coplanar triangles, has an axis with zero overlap). Decided exactly:
/// `overlap^2 <= delta^2 |a|^2` for some candidate axis `a`. The intersection verdict of a
/// floating-point kernel on a pair within rounding of touching is judged with this (bound table).
pub fn penetration_at_most(s: &[P3; 3], t: &[P3; 3], delta: &Rational) -> bool {
    if triangle_triangle(s, t).d2 != 0 {
        return true;
    }
    let es: Vec<P3> = (0..3).map(|k| sub(&s[(k + 1) % 3], &s[k])).collect();
    let et: Vec<P3> = (0..3).map(|k| sub(&t[(k + 1) % 3], &t[k])).collect();
    let mut axes = vec![cross(&es[0], &es[1]), cross(&et[0], &et[1])];
    for e in &es {
        for f in &et {
            axes.push(cross(e, f));
        }
    }
    let d2 = Rational::from(delta * delta);
    for a in &axes {
        let aa = dot(a, a);
        if aa == 0 {
            continue;
        }
        let ps: Vec<Rational> = s.iter().map(|x| dot(a, x)).collect();
        let pt: Vec<Rational> = t.iter().map(|x| dot(a, x)).collect();
        let (smin, smax) = min_max(&ps);
        let (tmin, tmax) = min_max(&pt);
        let ov = Rational::from(&smax - &tmin).min(Rational::from(&tmax - &smin));
        if ov <= 0 || Rational::from(&ov * &ov) <= Rational::from(&d2 * &aa) {
            return true;
        }
    }
    false
}

fn min_max(v: &[Rational]) -> (Rational, Rational) {
    let mut lo = v[0].clone();
    let mut hi = v[0].clone();
    for x in &v[1..] {
        if *x < lo {
            lo = x.clone();
        }
        if *x > hi {
            hi = x.clone();
        }
    }
    (lo, hi)
}

/// Exact squared distance and closest points of two triangles: the first (in a fixed order) of
/// the 15 feature pairs with the smallest distance, or, when that is positive, a point where an
/// edge of one triangle pierces the other. Intersecting pairs give 0 with `p == q` a common
/// point.
///
/// # Performance
/// When every coordinate is exactly an `f64` (always, for input converted from floats), a
/// certified floating-point filter skips the feature pairs that cannot be closest and the
/// piercing test for provably disjoint pairs; the result is bit-for-bit the unfiltered one (the
/// tests check this). Other exact coordinates take the unfiltered path.
pub fn triangle_triangle(s: &[P3; 3], t: &[P3; 3]) -> Exact {
    match (as_floats(s), as_floats(t)) {
        (Some(sf), Some(tf)) => filter::triangle_triangle(s, t, &sf, &tf),
        _ => triangle_triangle_unfiltered(s, t),
    }
}

/// The coordinates as `f64` when each one is exactly an `f64`.
fn as_floats(t: &[P3; 3]) -> Option<[[f64; 3]; 3]> {
    let mut out = [[0.0; 3]; 3];
    for (o, p) in out.iter_mut().zip(t) {
        for (o, x) in o.iter_mut().zip(p) {
            let f = x.to_f64();
            if *x != f {
                return None;
            }
            *o = f;
        }
    }
    Some(out)
}

/// The unfiltered computation: all 15 feature pairs exactly, then the piercing test. The same
/// [`Exact`] as [`triangle_triangle`], slower; public for cross-checks (tests, the
/// `oracle_filter` fuzz target) and the benchmark of the filter.
pub fn triangle_triangle_unfiltered(s: &[P3; 3], t: &[P3; 3]) -> Exact {
    pierce_or(min15(s, t), s, t)
}

/// `m` (the 15-feature minimum) unless it is positive and an edge of one triangle pierces the
/// other, which gives distance 0 at the piercing point.
pub(crate) fn pierce_or(m: Exact, s: &[P3; 3], t: &[P3; 3]) -> Exact {
    if m.d2 == 0 {
        return m;
    }
    if let Some(x) = piercing(s, t).or_else(|| piercing(t, s)) {
        return Exact { d2: Rational::new(), p: x.clone(), q: x };
    }
    m
}

/// Exact squared triangle distance from float input.
///
/// # Errors
/// [`NonFinite`] when a coordinate is NaN or infinite.
pub fn sqdist_triangle_triangle<F: Float>(a: &[[F; 3]; 3], b: &[[F; 3]; 3]) -> Result<Rational, NonFinite> {
    Ok(triangle_triangle(&exact_points(a)?, &exact_points(b)?).d2)
}

/// The second, independent formulation: enumerate the 7 faces of each triangle (3 vertices,
/// 3 edges, the interior), solve each face pair's stationary system of |x - y|^2 exactly, keep
/// solutions inside both faces. A singular system is skipped (its minimum also lies on a smaller
/// face pair).
pub fn triangle_triangle_kkt(s: &[P3; 3], t: &[P3; 3]) -> Exact {
    let faces = |tri: &[P3; 3]| -> Vec<(P3, Vec<P3>)> {
        let mut f = Vec::new();
        for k in 0..3 {
            f.push((tri[k].clone(), vec![]));
        }
        for k in 0..3 {
            f.push((tri[k].clone(), vec![sub(&tri[(k + 1) % 3], &tri[k])]));
        }
        f.push((tri[0].clone(), vec![sub(&tri[1], &tri[0]), sub(&tri[2], &tri[0])]));
        f
    };
    let mut best: Option<Exact> = None;
    for (of, df) in faces(s) {
        for (og, dg) in faces(t) {
            // x - y = w + D theta, D = [df.., -dg..]
            let w = sub(&of, &og);
            let mut dirs: Vec<P3> = df.clone();
            for g in &dg {
                dirs.push([Rational::from(-&g[0]), Rational::from(-&g[1]), Rational::from(-&g[2])]);
            }
            let k = dirs.len();
            let theta = if k == 0 {
                Some(vec![])
            } else {
                let m: Vec<Vec<Rational>> =
                    (0..k).map(|i| (0..k).map(|j| dot(&dirs[i], &dirs[j])).collect()).collect();
                let rhs: Vec<Rational> = (0..k).map(|i| -dot(&dirs[i], &w)).collect();
                solve(m, rhs)
            };
            let Some(theta) = theta else { continue };
            let (tf, tg) = theta.split_at(df.len());
            let ok = |p: &[Rational]| {
                p.iter().all(|x| *x >= 0) && p.iter().fold(Rational::new(), |a, x| a + x) <= 1
            };
            if !ok(tf) || !ok(tg) {
                continue;
            }
            let mut x = of.clone();
            for (d, l) in df.iter().zip(tf) {
                x = lerp(&x, d, l);
            }
            let mut y = og.clone();
            for (d, l) in dg.iter().zip(tg) {
                y = lerp(&y, d, l);
            }
            keep_min(&mut best, Exact { d2: dist2(&x, &y), p: x, q: y });
        }
    }
    best.unwrap_or_else(|| unreachable!("vertex-vertex pairs always qualify"))
}

/// Squared triangle distance by the face-pair formulation, from float input.
///
/// # Errors
/// [`NonFinite`] when a coordinate is NaN or infinite.
pub fn sqdist_triangle_triangle_kkt<F: Float>(
    a: &[[F; 3]; 3],
    b: &[[F; 3]; 3],
) -> Result<Rational, NonFinite> {
    Ok(triangle_triangle_kkt(&exact_points(a)?, &exact_points(b)?).d2)
}

/// Exact Gaussian elimination; `None` when singular.
fn solve(mut m: Vec<Vec<Rational>>, mut r: Vec<Rational>) -> Option<Vec<Rational>> {
    let k = r.len();
    for col in 0..k {
        let piv = (col..k).find(|&i| m[i][col] != 0)?;
        m.swap(col, piv);
        r.swap(col, piv);
        for i in 0..k {
            if i != col && m[i][col] != 0 {
                let f = Rational::from(&m[i][col] / &m[col][col]);
                for j in col..k {
                    let v = Rational::from(&f * &m[col][j]);
                    m[i][j] -= v;
                }
                let v = Rational::from(&f * &r[col]);
                r[i] -= v;
            }
        }
    }
    Some((0..k).map(|i| Rational::from(&r[i] / &m[i][i])).collect())
}

#[cfg(test)]
mod tests;
