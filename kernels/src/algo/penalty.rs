//! Krestenitis & Koziara's penalty method (*Calculating the minimum distance between two
//! triangles on SIMD hardware*): the distance as a constrained minimisation over the four
//! barycentric parameters, with a penalty on the violated constraints and a regularised Newton
//! step (Hessian + reg I, no line search), every lane iterating independently. An
//! approximation: its answer carries the same certificate as every other query, but is never
//! escalated (the caller chose speed).

use super::{finish, scale_pair, Kernel, Out, Params, PenaltyParams, Res};
use crate::lanes::{Cx, Lanes, Mask, V3};
use crate::real::Real;

/// The penalty-method query (registry entry `penalty`).
pub(crate) struct Penalty;

impl Kernel for Penalty {
    const KA: usize = 3;
    const KB: usize = 3;
    const WIDEN: bool = false;
    const RECERT: bool = false;
    #[inline(always)]
    fn stage<L: Lanes, const ST: u8>(a: &[V3<L>; 3], b: &[V3<L>; 3], prm: &Params<L::S>) -> Out<L> {
        let (sc, s, t) = scale_pair::<L, 3, 3>(a, b);
        let (r, it) = tri_tri_penalty(&s, &t, &prm.penalty);
        let mut out = finish::<L, 3, 3, false>(&sc, &s, &t, None, r, prm);
        out.ok = Cx::of(it).yes();
        out.it = it;
        out
    }
}

/// Krestenitis & Koziara's penalty method (seed 003, Algorithm 1): minimise
/// |x(a,b) - y(g,d)|^2 + rho * sum max(0, c_i)^2 over the barycentric parameters with a
/// regularised Newton step (Hessian + reg * I, no line search), every lane iterating
/// independently until its step, measured on the geometry, is below `tol` or `max_iter` is
/// reached. `rho` and `reg` are relative to the pair's own curvature (trace of the Hessian of
/// the distance term / 4), so the method behaves the same at every scale. Input must be
/// prescaled. Returns the result and the iterations each lane used.
#[inline(always)]
pub(crate) fn tri_tri_penalty<L: Lanes>(
    s: &[V3<L>; 3],
    t: &[V3<L>; 3],
    o: &PenaltyParams<L::S>,
) -> (Res<L>, L) {
    let ba = s[1].sub(s[0]);
    let ca = s[2].sub(s[0]);
    let ed = t[1].sub(t[0]);
    let fd = t[2].sub(t[0]);
    let k = Cx::of(ba.x);
    let two = k.c(2.0);
    // Hessian of |x - y|^2 (symmetric 4x4), upper triangle.
    let h00 = two.mul(ba.norm2());
    let h01 = two.mul(ba.dot(ca));
    let h02 = two.mul(ba.dot(ed)).neg();
    let h03 = two.mul(ba.dot(fd)).neg();
    let h11 = two.mul(ca.norm2());
    let h12 = two.mul(ca.dot(ed)).neg();
    let h13 = two.mul(ca.dot(fd)).neg();
    let h22 = two.mul(ed.norm2());
    let h23 = two.mul(ed.dot(fd));
    let h33 = two.mul(fd.norm2());
    let scale = h00.add(h11).add(h22).add(h33).mul(k.c(0.25)).max(k.splat(L::S::MIN_POSITIVE));
    let rho = k.splat(o.rho).mul(scale);
    let reg = k.splat(o.reg).mul(scale);
    let tol2 = k.splat(o.tol).mul(k.splat(o.tol));
    let mut x = [k.splat(o.start[0]), k.splat(o.start[1]), k.splat(o.start[2]), k.splat(o.start[3])];
    let mut done = k.no();
    let mut iters = k.zero();
    let z = k.zero();
    let one = k.one();
    for _ in 0..o.max_iter {
        let xp = s[0].add_scaled(ba, x[0]).add_scaled(ca, x[1]);
        let yp = t[0].add_scaled(ed, x[2]).add_scaled(fd, x[3]);
        let xy = xp.sub(yp);
        let mut g =
            [two.mul(xy.dot(ba)), two.mul(xy.dot(ca)), two.mul(xy.dot(ed)).neg(), two.mul(xy.dot(fd)).neg()];
        // constraints c_i <= 0: -a, -b, a+b-1, -g, -d, g+d-1; penalty on the violated ones
        let cs = [
            x[0].neg(),
            x[1].neg(),
            x[0].add(x[1]).sub(one),
            x[2].neg(),
            x[3].neg(),
            x[2].add(x[3]).sub(one),
        ];
        // (No closures or `array::map` here: they are compiled without the entry point's
        // target features and would call the intrinsics out of line.)
        let mut act = [z; 6];
        let mut pen = [z; 6];
        for k in 0..6 {
            act[k] = L::select(cs[k].ge(z), one, z);
            pen[k] = cs[k].max(z);
        }
        g[0] = g[0].add(rho.mul(pen[2].sub(pen[0])));
        g[1] = g[1].add(rho.mul(pen[2].sub(pen[1])));
        g[2] = g[2].add(rho.mul(pen[5].sub(pen[3])));
        g[3] = g[3].add(rho.mul(pen[5].sub(pen[4])));
        let m00 = h00.add(rho.mul(act[0].add(act[2]))).add(reg);
        let m01 = h01.add(rho.mul(act[2]));
        let m11 = h11.add(rho.mul(act[1].add(act[2]))).add(reg);
        let m22 = h22.add(rho.mul(act[3].add(act[5]))).add(reg);
        let m23 = h23.add(rho.mul(act[5]));
        let m33 = h33.add(rho.mul(act[4].add(act[5]))).add(reg);
        let dx = solve_spd4(
            [[m00, m01, h02, h03], [m01, m11, h12, h13], [h02, h12, m22, m23], [h03, h13, m23, m33]],
            g,
        );
        let step = ba.scale(dx[0]).add_scaled(ca, dx[1]);
        let stept = ed.scale(dx[2]).add_scaled(fd, dx[3]);
        let err2 = step.norm2().add(stept.norm2());
        let open = done.not();
        for k in 0..4 {
            x[k] = L::select(open, x[k].sub(dx[k]), x[k]);
        }
        iters = L::select(open, iters.add(one), iters);
        done = done.or(err2.lt(tol2));
        if done.all() {
            break;
        }
    }
    // The penalty solution lies outside the triangles by about 1/rho, and an iteration that
    // diverged may be anywhere: bring the parameters back into each triangle (clamp, then scale
    // onto a + b <= 1; NaN goes back to the start) so that the points are real points of the
    // triangles and the distance an upper bound. Not the exact projection: the gap to the true
    // distance is what the accuracy report measures.
    let (a0, b0) = feasible(x[0], x[1], k.splat(o.start[0]), k.splat(o.start[1]));
    let (g0, d0) = feasible(x[2], x[3], k.splat(o.start[2]), k.splat(o.start[3]));
    let p = s[0].add_scaled(ba, a0).add_scaled(ca, b0);
    let q = t[0].add_scaled(ed, g0).add_scaled(fd, d0);
    (Res { d: p.sub(q).norm2(), p, q }, iters)
}

/// Barycentric parameters brought into the triangle: NaN or infinite back to the start
/// `(u0, v0)`, clamp at 0, then scale onto `u + v <= 1`. (An iteration that diverged to
/// infinity made `inf / inf` here: NaN closest points for finite f32 input, found by the
/// extensive differential run on parallel faces.)
#[inline(always)]
fn feasible<L: Lanes>(u: L, v: L, u0: L, v0: L) -> (L, L) {
    let k = Cx::of(u);
    let big = k.splat(L::S::MAX);
    let ok = u.abs().le(big).and(v.abs().le(big));
    let u = L::select(ok, u, u0).max(k.zero());
    let v = L::select(ok, v, v0).max(k.zero());
    let sum = u.add(v);
    let over = sum.gt(k.one());
    (L::select(over, u.safe_div(sum), u), L::select(over, v.safe_div(sum), v))
}

/// Solves a symmetric positive definite 4x4 system by Gaussian elimination without pivoting,
/// fused and unrolled (no allocation, four divisions).
#[inline(always)]
fn solve_spd4<L: Lanes>(mut m: [[L; 4]; 4], mut r: [L; 4]) -> [L; 4] {
    let one = Cx::of(r[0]).one();
    for k in 0..4 {
        let inv = one.safe_div(m[k][k]);
        for i in (k + 1)..4 {
            let f = m[i][k].mul(inv);
            for j in (k + 1)..4 {
                m[i][j] = m[i][j].sub(f.mul(m[k][j]));
            }
            r[i] = r[i].sub(f.mul(r[k]));
        }
    }
    let mut x = [Cx::of(r[0]).zero(); 4];
    for k in (0..4).rev() {
        let mut acc = r[k];
        for j in (k + 1)..4 {
            acc = acc.sub(m[k][j].mul(x[j]));
        }
        x[k] = acc.safe_div(m[k][k]);
    }
    x
}
