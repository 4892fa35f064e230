//! Correctly rounded answers ([`Tolerance::CORRECTLY_ROUNDED`]): every returned squared
//! distance is `RN(D*)`, the exact squared distance rounded to nearest (ties to even) in the
//! input's precision, every returned distance `RN(sqrt(D*))`, or the pair is reported
//! undecided.
//!
//! A block of pairs runs in f64 (f32 input exactly widened) at the default tolerance, which
//! gives each pair a certified interval `[lo, hi]` of its distance. Rounding to nearest is
//! monotonic, so when the ends of `[lo^2, hi^2]` (bounded outward) round to the same value of
//! the input's precision, every square in between does, `D*` among them: that value is the
//! answer ([`decide`]); likewise the distance when `lo` and `hi` round to one value
//! ([`decide_distance`]). The distance is decided on its own: the square root of the rounded
//! square is rounded twice and can be an ulp off. The pairs this leaves undecided go to the
//! exact oracle (feature `exact`), whose square and distance are correctly rounded; without it
//! they are answered with their f64 answer rounded once and counted in
//! [`PathCounts::undecided`] (and `uncertified`), never passed off as correctly rounded.

use super::{Engine, Tolerance};
use crate::algo::Params;
use crate::drv::{beyond_margin, outward, post, Job, Lane, Sink, Src};
use crate::lanes::V3;
use crate::query::Query;
use crate::real::{Precision, Real};
use crate::types::{Interval, PathCounts, Point};

/// Pairs answered per block and thread: the f64 copies and answers of a block are held at
/// once (1,024 triangle pairs are 147 KB of f64 coordinates, which stay in the caches). A
/// block of several threads' share is at least [`Engine::MIN_PARALLEL`] pairs, so that its f64
/// pass is split over them.
const BLOCK: usize = 1024;

/// The value of `T` that every square in `[lo^2, hi^2]` rounds to (to nearest), when there is
/// one: `lo <= hi` bound a distance (f64, non-negative, certified).
#[inline(always)]
fn decide<T: Real>(lo: f64, hi: f64) -> Option<T> {
    if !(lo >= 0.0 && lo <= hi) {
        return None;
    }
    // `lo * lo` and `hi * hi` are the squares rounded to nearest in f64.
    let (a, b) = (lo * lo, hi * hi);
    match T::PRECISION {
        // RN(lo^2) = a and RN(hi^2) = b: equal ends decide every square between them.
        Precision::F64 => (a == b).then(|| T::from_f64(a)),
        // The exact squares lie within half an ulp of `a` and `b`, so in [pred(a), succ(b)];
        // f64 -> f32 conversion rounds to nearest, ties to even.
        Precision::F32 => {
            let (l, h) = (a.next_down().max(0.0) as f32, b.next_up() as f32);
            (l == h).then(|| T::from_f64(l as f64))
        }
    }
}

/// The value of `T` that every distance in `[lo, hi]` rounds to (to nearest), when there is
/// one: `lo <= hi` bound a distance (f64, non-negative, certified).
#[inline(always)]
fn decide_distance<T: Real>(lo: f64, hi: f64) -> Option<T> {
    if !(lo >= 0.0 && lo <= hi) {
        return None;
    }
    match T::PRECISION {
        // every f64 in between is a candidate: only a point interval decides
        Precision::F64 => (lo == hi).then(|| T::from_f64(lo)),
        // f64 -> f32 conversion rounds to nearest, ties to even, and is monotonic
        Precision::F32 => {
            let (l, h) = (lo as f32, hi as f32);
            (l == h).then(|| T::from_f64(l as f64))
        }
    }
}

/// One pair's answer in the mode: the lane (its square rounded) and its distance.
#[derive(Clone, Copy)]
struct Rounded<T> {
    lane: Lane<T>,
    dist: T,
}

/// The f64 answers of some pairs: squared distances, closest points (when asked for),
/// intervals; and the widened input they were computed from.
#[derive(Default)]
struct Answers64 {
    fa: Vec<f64>,
    fb: Vec<f64>,
    d: Vec<f64>,
    p: Vec<Point<f64>>,
    q: Vec<Point<f64>>,
    iv: Vec<Interval<f64>>,
    counts: PathCounts,
}

impl Engine {
    /// [`Engine::run`] for a distance query under [`Tolerance::CORRECTLY_ROUNDED`]: `job` is
    /// validated; its `prm` holds the margin of [`Query::Within`].
    ///
    /// Per block: every pair in f64 at the default tolerance (the cheapest certified pass);
    /// for f32 input, the pairs its interval does not decide (nor a proof of contact) once
    /// more in f64 at [`Tolerance::EXACT`], whose accurate stages give the tightest intervals
    /// the precision can certify (pairs far closer than their size, where the first interval
    /// is too wide for one rounding cell of the square); what is left to the exact oracle, or
    /// undecided.
    pub(super) fn run_rounded<T: Real>(&self, mut job: Job<'_, T>) -> PathCounts {
        // Within-margin is triangle-triangle distance, thresholded on the rounded square.
        let query = if job.query == Query::Within { Query::TriTri } else { job.query };
        let loose = Engine { tol: Tolerance::DEFAULT, exact: false, ..*self };
        let tight = Engine { tol: Tolerance::EXACT, exact: false, ..*self };
        let mut counts = PathCounts::default();
        let (mut first, mut second) = (Answers64::default(), Answers64::default());
        let (mut ids, mut open) = (Vec::new(), Vec::new());
        let block = if self.threads > 1 { (BLOCK * self.threads).max(Engine::MIN_PARALLEL) } else { BLOCK };
        let mut start = 0;
        while start < job.n {
            let end = (start + block).min(job.n);
            ids.clear();
            ids.extend(start..end);
            loose.answers64(&job, query, &ids, &mut first);
            counts.add(&PathCounts { pairs: 0, uncertified: 0, ..first.counts });
            counts.pairs += ids.len() as u64;
            if T::PRECISION == Precision::F32 {
                counts.widened += ids.len() as u64;
            }
            open.clear();
            for (m, &i) in ids.iter().enumerate() {
                match rounded_lane(&job, i, &first, m, &mut counts) {
                    Ok(lane) => put(&mut job, i, lane),
                    Err(lane) => open.push((i, lane)),
                }
            }
            // The tight pass decides f32 input only: an f64 interval, however tight, is wider
            // than one rounding cell of an f64 square unless it is exact (measured: it decided
            // none of the f64 pairs the first pass left, at the cost of the accurate stages on
            // all of them).
            if T::PRECISION == Precision::F32 && !open.is_empty() {
                ids.clear();
                ids.extend(open.iter().map(|x| x.0));
                tight.answers64(&job, query, &ids, &mut second);
                counts.add(&PathCounts { pairs: 0, uncertified: 0, ..second.counts });
                let mut still = Vec::new();
                for (m, &(i, _)) in open.iter().enumerate() {
                    match rounded_lane(&job, i, &second, m, &mut counts) {
                        Ok(lane) => put(&mut job, i, lane),
                        Err(lane) => still.push((i, lane)),
                    }
                }
                open = still;
            }
            for (i, r) in open.drain(..) {
                let r = match exact_lane(self, &job, i) {
                    Some(x) => {
                        counts.exact += 1;
                        x
                    }
                    None => {
                        counts.undecided += 1;
                        counts.uncertified += 1;
                        r
                    }
                };
                put(&mut job, i, r);
            }
            start = end;
        }
        counts
    }

    /// The f64 answers of pairs `ids` of `job` to `query` on this engine (its tolerance), into
    /// `r` (its buffers reused from block to block); closest points only when `job` writes them.
    fn answers64<T: Real>(&self, job: &Job<'_, T>, query: Query, ids: &[usize], r: &mut Answers64) {
        let (ka, kb) = (job.a.k(), job.b.k());
        let n = ids.len();
        let a = widen(&job.a, ka, ids, &mut r.fa);
        let b = widen(&job.b, kb, ids, &mut r.fb);
        r.d.resize(n, 0.0);
        r.iv.resize(n, Interval::default());
        let points = job.sink.cp.is_some() || job.sink.p.is_some() || job.sink.q.is_some();
        r.p.resize(if points { n } else { 0 }, [0.0; 3]);
        r.q.resize(if points { n } else { 0 }, [0.0; 3]);
        let sub = Job {
            query,
            a,
            b,
            n,
            // (shared vertices proven by the pass itself, with an exact interval)
            prm: Params { exact_contacts: true, ..self.params_of_checked::<f64>() },
            sink: Sink {
                d: Some(&mut r.d[..n]),
                p: if points { Some(&mut r.p[..n]) } else { None },
                q: if points { Some(&mut r.q[..n]) } else { None },
                iv: Some(&mut r.iv[..n]),
                ..Sink::default()
            },
            counts: PathCounts::default(),
            widen: false,
            exact: false,
        };
        r.counts = self.exec(sub);
    }
}

/// Writes pair `i`'s answer (within-margin: `+inf` beyond the margin, on the rounded square,
/// for the distance too).
#[inline(always)]
fn put<T: Real>(job: &mut Job<'_, T>, i: usize, r: Rounded<T>) {
    let lane = post(job.query, job.prm.margin, r.lane);
    job.sink.put(i, &lane);
    if let Some(s) = job.sink.dist.as_deref_mut() {
        // (on the square: one beyond `T`'s range is beyond a finite margin, though its
        // distance is finite)
        s[i] = if beyond_margin(job.query, job.prm.margin, r.lane.d) { T::INFINITY } else { r.dist };
    }
}

/// Pair `i`'s answer from its f64 answer (number `m` of `r`): `Ok` with the decided square
/// and (when the job writes distances) distance, or NaN for non-finite input; `Err` with the
/// f64 answer rounded once when undecided.
#[inline(always)]
fn rounded_lane<T: Real>(
    job: &Job<'_, T>,
    i: usize,
    r: &Answers64,
    m: usize,
    counts: &mut PathCounts,
) -> Result<Rounded<T>, Rounded<T>> {
    let (d, iv) = (r.d[m], r.iv[m]);
    let cv = |x: f64| T::from_f64(x);
    // (the interval, closest points and distance only when the job writes them)
    let (lo, hi) = if job.sink.iv.is_some() { outward::<T, f64>(iv) } else { (T::ZERO, T::ZERO) };
    let (p, q) =
        (r.p.get(m).map_or([T::ZERO; 3], |x| x.map(cv)), r.q.get(m).map_or([T::ZERO; 3], |x| x.map(cv)));
    let lane = Lane { d: cv(d), p, q, lo, hi, ok: true, it: 0 };
    let dist = if job.sink.dist.is_some() { cv(d.sqrt()) } else { T::ZERO };
    if d.is_nan() {
        // non-finite input: NaN, as in every mode
        return Ok(Rounded { lane: Lane { ok: false, ..lane }, dist });
    }
    let distance = if job.sink.dist.is_some() { decide_distance::<T>(iv.lo, iv.hi) } else { Some(dist) };
    if let (Some(v), Some(dist)) = (decide::<T>(iv.lo, iv.hi), distance) {
        return Ok(Rounded { lane: Lane { d: v, ..lane }, dist });
    }
    // A contact: an interval from 0 decides nothing, a proof that the distance is 0 does: a
    // point the primitives share (mesh neighbours), or an edge crossing a triangle.
    if iv.lo == 0.0 && contact(job, i) {
        counts.crossed += 1;
        return Ok(Rounded { lane: Lane { d: T::ZERO, ..lane }, dist: T::ZERO });
    }
    Err(Rounded { lane: Lane { ok: false, ..lane }, dist })
}

/// Is pair `i` of `job` provably in contact: a point the primitives share, or an edge crossing
/// a triangle? (Out of line: the f64 pass proves the shared vertices and most crossings of
/// triangle pairs itself, with an exact interval, so this runs for the crossings it leaves and
/// for the other queries' contacts.)
#[inline(never)]
fn contact<T: Real>(job: &Job<'_, T>, i: usize) -> bool {
    let (a, b) = (prim64(&job.a, i), prim64(&job.b, i));
    let (ka, kb) = (job.a.k(), job.b.k());
    a[..ka].iter().any(|p| b[..kb].contains(p)) || (ka == 3 && kb == 3 && crossing(&a, &b))
}

/// Primitive `i` of `s` in f64 (exact; points beyond its arity repeat the first).
fn prim64<T: Real>(s: &Src<'_, T>, i: usize) -> [[f64; 3]; 3] {
    s.prim(i).map(|p| p.map(|x| x.to_f64()))
}

/// Primitives `ids` of `s` (`k` points each, `ids` increasing) widened to f64 in `out` (its
/// buffer reused from block to block), as the source the f64 pass reads. A run of consecutive
/// pairs (the first pass of a block) is widened a column (SoA) or a slice (AoS) at a time, as
/// vectors: per pair and coordinate, the copy took a third of the mode's time on mesh
/// neighbours. SoA columns are padded to whole vectors with copies of the last primitive, as
/// a batch's are.
fn widen<'o, T: Real>(s: &Src<'_, T>, k: usize, ids: &[usize], out: &'o mut Vec<f64>) -> Src<'o, f64> {
    out.clear();
    let n = ids.len();
    let run = n > 0 && ids[n - 1] - ids[0] + 1 == n;
    match *s {
        Src::Soa { data, cap, base, .. } if run => {
            let wide = n.next_multiple_of(crate::batch::PAD);
            out.reserve(3 * k * wide);
            for j in 0..3 * k {
                let from = &data[j * cap + base + ids[0]..][..n];
                out.extend(from.iter().map(|x| x.to_f64()));
                let last = from[n - 1].to_f64();
                out.extend(std::iter::repeat_n(last, wide - n));
            }
            Src::Soa { data: out, cap: wide, base: 0, k }
        }
        Src::Aos { flat, .. } if run => {
            out.extend(flat[ids[0] * 3 * k..(ids[0] + n) * 3 * k].iter().map(|x| x.to_f64()));
            Src::Aos { flat: out, k }
        }
        Src::One { flat, .. } => {
            // one primitive against every one of the other side: widened once
            out.extend(flat[..3 * k].iter().map(|x| x.to_f64()));
            Src::One { flat: out, k }
        }
        _ => {
            out.reserve(n * 3 * k);
            for &i in ids {
                out.extend((0..3 * k).map(|j| s.at(i, j).to_f64()));
            }
            Src::Aos { flat: out, k }
        }
    }
}

/// The sign of `det[a - d, b - d, c - d]` (positive: `d` below the plane of `a, b, c` seen
/// counter-clockwise), when the floating-point value proves it: the f64 pass's lane form
/// ([`crate::algo::fast::orient3d`], Shewchuk's static bound on differences in `[1e-80,
/// 1e80]` or zero) on one lane. `None`: not proven.
fn orient3d(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> Option<i8> {
    let v = |p: &[f64; 3]| V3::new(p[0], p[1], p[2]);
    match crate::algo::fast::orient3d::<f64>(v(a), v(b), v(c), v(d)) {
        (true, _) => Some(1),
        (_, true) => Some(-1),
        _ => None,
    }
}

/// The proven sides of `t`'s three vertices relative to the plane of `u` (`None`: not proven).
fn sides(u: &[[f64; 3]; 3], t: &[[f64; 3]; 3]) -> [Option<i8>; 3] {
    t.map(|x| orient3d(&u[0], &u[1], &u[2], &x))
}

/// Does an edge of `t` provably cross the interior of triangle `u` (its ends strictly on
/// either side of `u`'s plane, `side` their proven sides, its line strictly inside `u`'s three
/// edges)?
fn pierces(t: &[[f64; 3]; 3], side: &[Option<i8>; 3], u: &[[f64; 3]; 3]) -> bool {
    (0..3).any(|i| {
        let j = (i + 1) % 3;
        let (Some(sp), Some(sq)) = (side[i], side[j]) else { return false };
        if sp == sq {
            return false;
        }
        let (p, q) = (&t[i], &t[j]);
        let e0 = orient3d(p, q, &u[0], &u[1]);
        e0.is_some() && e0 == orient3d(p, q, &u[1], &u[2]) && e0 == orient3d(p, q, &u[2], &u[0])
    })
}

/// Do two triangles provably intersect: an edge of one crossing the other's interior? (Every
/// pair of intersecting triangles in general position has one; a touching or coplanar pair is
/// left to the oracle.) Then the distance is exactly 0.
fn crossing(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> bool {
    let sb = sides(a, b);
    // b strictly on one side of a's plane: no edge crosses (and the triangles do not meet)
    if sb.iter().all(|x| *x == Some(1)) || sb.iter().all(|x| *x == Some(-1)) {
        return false;
    }
    pierces(b, &sb, a) || pierces(a, &sides(b, a), b)
}

/// The exact oracle's answer for pair `i` (feature `exact`, when the engine uses it).
#[cfg(feature = "exact")]
fn exact_lane<T: Real>(e: &Engine, job: &Job<'_, T>, i: usize) -> Option<Rounded<T>> {
    if !e.uses_exact() {
        return None;
    }
    let x = crate::exact::answer(job.a.k(), &job.a.prim(i), job.b.k(), &job.b.prim(i))?;
    let lane = Lane { d: x.d, p: x.p, q: x.q, lo: x.lo, hi: x.hi, ok: true, it: 0 };
    Some(Rounded { lane, dist: x.dist })
}

#[cfg(not(feature = "exact"))]
fn exact_lane<T: Real>(_: &Engine, _: &Job<'_, T>, _: usize) -> Option<Rounded<T>> {
    None
}

#[cfg(test)]
mod tests {
    use super::{crossing, decide, orient3d};

    #[test]
    fn crossings_are_proven_and_near_misses_are_not() {
        let a = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        // an edge of b through a's interior
        assert!(crossing(&a, &[[0.2, 0.2, -1.0], [0.2, 0.2, 1.0], [5.0, 5.0, 0.5]]));
        // the same edge just beside a's hypotenuse: no crossing
        assert!(!crossing(&a, &[[0.5, 0.5000001, -1.0], [0.5, 0.5000001, 1.0], [5.0, 5.0, 0.5]]));
        // touching at a vertex, and coplanar: not proven (the oracle decides those)
        assert!(!crossing(&a, &[[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]]));
        assert!(!crossing(&a, &[[0.1, 0.1, 0.0], [0.5, 0.1, 0.0], [0.1, 0.5, 0.0]]));
        // a point 1e-17 off a plane through the origin is proven below, one exactly on it is not
        let (p, q, r) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]);
        assert_eq!(orient3d(&p, &q, &r, &[0.3, 0.3, 1e-17]).map(i8::signum), Some(-1));
        assert_eq!(orient3d(&p, &q, &r, &[0.3, 0.3, 0.0]), None);
        // differences beyond the safe range are not judged
        assert_eq!(orient3d(&p, &q, &r, &[0.3, 0.3, 1e-90]), None);
    }

    #[test]
    fn decides_only_inside_one_rounding_cell() {
        // exact ends
        assert_eq!(decide::<f64>(3.0, 3.0), Some(9.0));
        assert_eq!(decide::<f32>(0.0, 0.0), Some(0.0));
        // f64: the squares of two neighbours differ
        assert_eq!(decide::<f64>(3.0, 3.0f64.next_up()), None);
        // f32: an f64 interval far inside one f32 cell decides; one across a midpoint does not
        let x = 1.5f64;
        assert_eq!(decide::<f32>(x, x.next_up()), Some(2.25f32));
        let one_up = 1.0f32.next_up() as f64; // 1 + 2^-23
        let m = (1.0 + one_up) / 2.0; // the f32 midpoint above 1 (exact in f64)
        let (lo, hi) = (m.sqrt().next_down(), m.sqrt().next_up());
        assert_eq!(decide::<f32>(lo, hi), None);
        // nonsense intervals decide nothing
        assert_eq!(decide::<f32>(f64::NAN, 1.0), None);
        assert_eq!(decide::<f64>(2.0, 1.0), None);
        // beyond f32's range: +inf is the correctly rounded square
        assert_eq!(decide::<f32>(1e30, 1e30f64.next_up()), Some(f32::INFINITY));
    }
}
