//! The fuzz targets' bodies, written once and run two ways: by libFuzzer (`fuzz/`, nightly,
//! `cargo +nightly fuzz run <name>`) and by a plain `cargo test` on stable, which replays every
//! committed finding in `fuzz/regressions/<name>/` and a seed corpus from the family generators
//! (`scenes/tests/fuzz_regressions.rs`). A target takes the raw input bytes and panics, with a
//! reproducible description, when it finds a violation.
//!
//! # Input format of the pair targets
//! * `b'F'`, a family byte, an 8-byte little-endian seed, then the target's extra bytes: the
//!   pair is [`generate`]d by that family (every family of the differential suite, so seed
//!   corpora come from the same generators; see [`seed_inputs`]).
//! * anything else: a [`PairInput`] decoded by `arbitrary` (a mode builds shared vertices,
//!   coplanar, parallel, touching or nearly parallel pairs, with ulp nudges, scale and offset),
//!   then the extra bytes.

use arbitrary::{Arbitrary, Unstructured};
use tridist::{Interval, Isa, Point, Query, Tolerance, Triangle};

use crate::bounds::violations_judged;
use crate::eval::{answer_in_interval, case_line, interval_contains, parse_case_line, truth, Variant};
use crate::families::{generate, ulp_step, Case, Family};
use crate::float::Float;
use crate::mesh::Mesh;

/// What a target body returns: `Err` with a reproducible description of the violation.
pub type Verdict = Result<(), String>;

/// One fuzz target: its name (the `fuzz/fuzz_targets/<name>.rs` binary and the
/// `fuzz/regressions/<name>/` folder) and its body.
#[derive(Clone, Copy)]
pub struct Target {
    /// Name of the target.
    pub name: &'static str,
    /// Runs one input, judging the variants `Judge` keeps.
    pub run: fn(&[u8], Judge) -> Verdict,
}

/// Which variants an input is judged on: every one (the replays of committed findings and
/// seeds by `cargo test`), or one per check, picked from the input's hash (libFuzzer, through
/// [`fuzz`]: an input costs one variant's run and exact judgement instead of every variant's,
/// and over a run every variant is judged on a share of the inputs). A finding is replayed on
/// every variant, so it reproduces whichever variant found it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Judge {
    /// Every available variant.
    All,
    /// One variant per check, from this hash.
    One(u64),
}

impl Judge {
    /// The sampling judge of an input: `One` of its FNV-1a hash.
    pub fn of(data: &[u8]) -> Judge {
        Judge::One(
            data.iter()
                .fold(0xcbf2_9ce4_8422_2325u64, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)),
        )
    }

    /// Is candidate `i` of `n` judged? `salt` tells the checks of one input apart (query,
    /// precision), so that they pick different variants.
    pub fn keeps(self, i: usize, n: usize, salt: u64) -> bool {
        match self {
            Judge::All => true,
            Judge::One(h) => {
                // a SplitMix64 finaliser: consecutive salts pick independently
                let mut z = h ^ salt.wrapping_mul(0x9e37_79b9_7f4a_7c15);
                z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
                z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
                z ^= z >> 31;
                n > 0 && (z % n as u64) as usize == i
            }
        }
    }
}

/// The available variants (with their engines) `judge` keeps for `q` in precision `T`.
fn judged_variants<T: Float>(q: Query, judge: Judge) -> Vec<(Variant, tridist::Engine)> {
    let all: Vec<_> = Variant::ALL.into_iter().filter_map(|v| Some((v, v.engine_or_skip()?))).collect();
    let (n, salt) = (all.len(), salt::<T>(q));
    all.into_iter().enumerate().filter(|&(k, _)| judge.keeps(k, n, salt)).map(|(_, x)| x).collect()
}

/// A salt per (query, precision) for [`Judge::keeps`].
fn salt<T: Float>(q: Query) -> u64 {
    let qi = Query::ALL.iter().position(|x| *x == q).unwrap_or(0) as u64;
    2 * qi + u64::from(T::NAME == "f64")
}

/// Every target.
pub const TARGETS: [Target; 11] = [
    Target { name: "tri_tri", run: tri_tri },
    Target { name: "seg_seg", run: seg_seg },
    Target { name: "point_tri", run: point_tri },
    Target { name: "intersect", run: intersect },
    Target { name: "within", run: within },
    Target { name: "cert", run: cert },
    Target { name: "rounded", run: rounded },
    Target { name: "raw_bits", run: raw_bits },
    Target { name: "parsers", run: parsers },
    Target { name: "oracle_filter", run: oracle_filter },
    Target { name: "mesh", run: mesh },
];

/// The mesh queries (distance, contacts, intersection, closest point) on small fuzzed meshes
/// in fuzzed poses, every variant, against the exact brute force over all triangle pairs
/// ([`crate::mesh_scenes::check_scene`]; input: [`crate::mesh_scenes::fuzz_scene`]), held to
/// the kernels' loosest rows ([`crate::mesh_scenes::Limits::kernels`]) as fuzzed pairs are:
/// the generated families' measured mesh row is for the generated families. One precision
/// per input when the judge samples (each costs its own exact brute force over the meshes
/// rounded to it), both with [`Judge::All`].
pub fn mesh(data: &[u8], judge: Judge) -> Verdict {
    let Some(s) = crate::mesh_scenes::fuzz_scene(data) else { return Ok(()) };
    let mut w = crate::mesh_scenes::Worst::default();
    let lim = crate::mesh_scenes::Limits::kernels;
    if judge.keeps(0, 2, MESH_SALT) {
        crate::mesh_scenes::check_scene::<f32>(&s, 0, &lim("f32"), &mut w)
            .map_err(|e| format!("{e} in {s:?}"))?;
    }
    if judge.keeps(1, 2, MESH_SALT) {
        crate::mesh_scenes::check_scene::<f64>(&s, 0, &lim("f64"), &mut w)
            .map_err(|e| format!("{e} in {s:?}"))?;
    }
    Ok(())
}

/// The salt of the mesh target's choice of precision.
const MESH_SALT: u64 = 0x6d65_7368;

/// The libFuzzer entry: runs target `name` on `data`, judging one variant per check
/// ([`Judge::of`] the input), panicking with the violation (what libFuzzer records as a
/// finding).
pub fn fuzz(name: &str, data: &[u8]) {
    let t = TARGETS.iter().find(|t| t.name == name).unwrap_or_else(|| panic!("no fuzz target {name}"));
    if let Err(e) = (t.run)(data, Judge::of(data)) {
        panic!("{e}");
    }
}

/// First byte of a family-generated pair input.
pub const FAMILY_TAG: u8 = b'F';
/// First byte of a raw-coordinates input of `oracle_filter`.
pub const RAW_TAG: u8 = b'R';

/// Fuzzer-chosen construction of a triangle pair.
#[derive(Arbitrary, Debug, Clone)]
pub struct PairInput {
    mode: u8,
    coords: [i16; 18],
    picks: [u8; 4],
    nudges: [i8; 4],
    scale_exp: i8,
    offset: i16,
}

/// Where a pair comes from.
#[derive(Debug, Clone)]
pub enum PairSource {
    /// Case `0` of `generate(family, seed, 1)`.
    Family(Family, u64),
    /// A structured construction.
    Built(PairInput),
}

/// Splits an input into its pair and the target's extra bytes (`None`: not decodable, skip).
pub fn pair_source(data: &[u8]) -> Option<(PairSource, Unstructured<'_>)> {
    if data.len() >= 10 && data[0] == FAMILY_TAG {
        let family = Family::ALL[data[1] as usize % Family::ALL.len()];
        let seed = u64::from_le_bytes(data[2..10].try_into().ok()?);
        return Some((PairSource::Family(family, seed), Unstructured::new(&data[10..])));
    }
    let mut u = Unstructured::new(data);
    let p = PairInput::arbitrary(&mut u).ok()?;
    Some((PairSource::Built(p), u))
}

/// The family whose bound row judges a construction mode.
fn family_of(mode: u8) -> Family {
    match mode % 8 {
        1 | 2 | 5 => Family::Touching,
        3 | 4 => Family::Parallel,
        6 => Family::NearParallel,
        7 => Family::Degenerate,
        _ => Family::Random,
    }
}

impl PairSource {
    /// The pair in precision T and the family whose bounds judge it (`None` when scaling left
    /// the finite range).
    pub fn build<T: Float>(&self) -> Option<(Case<T>, Family)> {
        match self {
            PairSource::Family(f, seed) => generate::<T>(*f, *seed, 1).pop().map(|c| (c, *f)),
            PairSource::Built(p) => p.build(),
        }
    }
}

impl PairInput {
    /// Builds the pair in precision T (None when scaling left the finite range).
    pub fn build<T: Float>(&self) -> Option<(Case<T>, Family)> {
        let c = |k: usize| self.coords[k] as f64 / 256.0;
        let p = |k: usize| [c(3 * k), c(3 * k + 1), c(3 * k + 2)];
        let mut a = [p(0), p(1), p(2)];
        let mut b = [p(3), p(4), p(5)];
        let pick = |k: usize| self.picks[k] as usize % 3;
        match self.mode % 8 {
            1 => b[0] = a[pick(0)], // shared vertex
            2 => {
                b[0] = a[pick(0)]; // shared edge
                b[1] = a[(pick(0) + 1) % 3];
            }
            3 => {
                for v in a.iter_mut().chain(b.iter_mut()) {
                    // coplanar
                    v[2] = c(0);
                }
            }
            4 => b = a.map(|v| [v[0] + c(9), v[1] + c(10), v[2] + c(11)]), // parallel translate
            5 => {
                // vertex of b on a's face (dyadic barycentrics: exact in f64)
                let (u, w) = ((self.picks[1] % 64) as f64 / 256.0, (self.picks[2] % 64) as f64 / 256.0);
                b[0] = [0, 1, 2].map(|k| a[0][k] + u * (a[1][k] - a[0][k]) + w * (a[2][k] - a[0][k]));
            }
            6 => {
                // b's first edge nearly parallel to a's first edge
                let d = [0, 1, 2].map(|k| a[1][k] - a[0][k]);
                b[1] = [0, 1, 2].map(|k| b[0][k] + d[k] + c(12 + k) * 1e-6);
            }
            7 => a[2] = a[pick(1)], // degenerate (repeated vertex)
            _ => {}
        }
        let f = 2f64.powi((self.scale_exp as i32).clamp(-60, 60));
        let off = self.offset as f64 * 64.0;
        let conv = |t: &[[f64; 3]; 3]| -> Triangle<T> { t.map(|v| v.map(|x| T::from_f64(x * f + off))) };
        let (mut ta, mut tb) = (conv(&a), conv(&b));
        for k in 0..4 {
            let idx = self.picks[k] as usize % 18;
            let t = if idx < 9 { &mut ta } else { &mut tb };
            let (v, cc) = ((idx % 9) / 3, idx % 3);
            t[v][cc] = ulp_step(t[v][cc], self.nudges[k] as i32 % 8);
        }
        let finite = ta.iter().chain(tb.iter()).flatten().all(|x| x.is_finite());
        finite.then(|| {
            let family = family_of(self.mode);
            let label = format!("{}/fuzz/mode{}", family.name(), self.mode % 8);
            (Case { label, a: ta, b: tb }, family)
        })
    }
}

/// Runs `query` on every available variant for the case: `Err`, with a reproducible
/// description, when the bound table is exceeded (E, closest points, intervals that miss the
/// exact distance, verdicts wrong beyond their allowance: every construction mode, judged by
/// the same rules).
/// Fuzzed input is adversarial, so it is held to the loosest row over the families.
pub fn check<T: Float>(query: Query, case: Case<T>, judge: Judge) -> Verdict {
    let cases = vec![case];
    let salt = salt::<T>(query);
    let bad = violations_judged(query, None, &cases, &truth(query, &cases), |i, n| judge.keeps(i, n, salt));
    if bad.is_empty() {
        Ok(())
    } else {
        Err(bad.join("\n"))
    }
}

/// The differential check of `queries` in both precisions.
/// The differential check of `queries` in both precisions: every (query, precision) check, or
/// one of them picked from the input's hash when the judge samples (each check costs its own
/// exact truth, so one check per input keeps a fuzzer's input cheap; over a run every check
/// gets its share).
fn differential(data: &[u8], queries: &[Query], judge: Judge) -> Verdict {
    let Some((src, _)) = pair_source(data) else { return Ok(()) };
    let n = 2 * queries.len();
    for (k, &q) in queries.iter().enumerate() {
        if judge.keeps(2 * k, n, CHECK_SALT) {
            if let Some((c, _)) = src.build::<f32>() {
                check(q, c, judge)?;
            }
        }
        if judge.keeps(2 * k + 1, n, CHECK_SALT) {
            if let Some((c, _)) = src.build::<f64>() {
                check(q, c, judge)?;
            }
        }
    }
    Ok(())
}

/// The salt of the choice of a (query, precision) check (beside [`salt`]'s of the variants).
const CHECK_SALT: u64 = 0x5eed;

/// The distance targets and the queries each judges against the bound table: their committed
/// findings set the adversarial rows ([`crate::bounds::ADVERSARIAL`], [`measure`]).
pub const DISTANCE_TARGETS: [(&str, &[Query]); 3] = [
    ("tri_tri", &[Query::TriTri, Query::TriTriBrute]),
    ("seg_seg", &[Query::SegSeg]),
    ("point_tri", &[Query::PointTri]),
];

/// The queries a distance target judges (empty for the other targets).
fn distance_queries(target: &str) -> &'static [Query] {
    DISTANCE_TARGETS.iter().find(|t| t.0 == target).map_or(&[], |t| t.1)
}

/// One input of a distance target measured on every variant (both quick-stage settings for
/// triangle distance), as its checks would judge it: for each query and precision it checks,
/// the largest E and point error. What the adversarial rows are set from.
pub fn measure(target: &str, data: &[u8]) -> Vec<(Query, &'static str, [f64; 2])> {
    let Some((src, _)) = pair_source(data) else { return Vec::new() };
    let mut out = Vec::new();
    for &q in distance_queries(target) {
        if let Some((c, _)) = src.build::<f32>() {
            out.push((q, "f32", measure_case(q, c)));
        }
        if let Some((c, _)) = src.build::<f64>() {
            out.push((q, "f64", measure_case(q, c)));
        }
    }
    out
}

fn measure_case<T: Float>(query: Query, case: Case<T>) -> [f64; 2] {
    let cases = vec![case];
    let t = truth(query, &cases);
    let settings: &[bool] = if query == Query::TriTri { &[true, false] } else { &[true] };
    let mut worst = [0.0f64; 2];
    for v in Variant::ALL {
        let Some(e) = v.engine_or_skip() else { continue };
        for &quick in settings {
            // an error is the checks' to report (`check` fails on it); nothing to measure
            let Ok(o) = crate::eval::run_with(e.quick_stage(quick), query, v, &cases, None) else { continue };
            let (st, _) = crate::eval::summarise(query, &cases, &t, &o, crate::bounds::VERDICT_ALLOW, None);
            worst = [worst[0].max(st.max_excess), worst[1].max(st.max_point_error)];
        }
    }
    worst
}

/// Triangle distance (fast stage + PQP, and brute force), every variant and precision,
/// against the oracle.
pub fn tri_tri(data: &[u8], judge: Judge) -> Verdict {
    differential(data, distance_queries("tri_tri"), judge)
}

/// Segment-segment distance against the oracle.
pub fn seg_seg(data: &[u8], judge: Judge) -> Verdict {
    differential(data, distance_queries("seg_seg"), judge)
}

/// Point-triangle distance against the oracle.
pub fn point_tri(data: &[u8], judge: Judge) -> Verdict {
    differential(data, distance_queries("point_tri"), judge)
}

/// The intersection predicate against the oracle.
pub fn intersect(data: &[u8], judge: Judge) -> Verdict {
    differential(data, &[Query::Intersect], judge)
}

/// Within-margin must agree exactly with the full query of the same variant (squared distance
/// when within the margin, +inf beyond), for every variant and both precisions; the margin is
/// the extra `u16 / 4096`.
pub fn within(data: &[u8], judge: Judge) -> Verdict {
    let Some((src, mut rest)) = pair_source(data) else { return Ok(()) };
    let margin = f64::from(u16::arbitrary(&mut rest).unwrap_or(0)) / 4096.0;
    if let Some((c, _)) = src.build::<f32>() {
        within_in(&c, margin as f32, judge)?;
    }
    if let Some((c, _)) = src.build::<f64>() {
        within_in(&c, margin, judge)?;
    }
    Ok(())
}

fn within_in<T: Float>(c: &Case<T>, margin: T, judge: Judge) -> Verdict {
    let engines: Vec<_> = Isa::ALL
        .into_iter()
        .filter_map(|isa| Some((isa, Variant::from_isa(isa).engine_or_skip()?)))
        .collect();
    let salt = salt::<T>(Query::Within);
    for (k, &(isa, e)) in engines.iter().enumerate() {
        if !judge.keeps(k, engines.len(), salt) {
            continue;
        }
        let (mut full, mut w) = ([T::ZERO], [T::ZERO]);
        e.sqdist_triangle_triangle(&c.a, &c.b, &mut full).map_err(|e| e.to_string())?;
        e.within_margin_triangle_triangle(&c.a, &c.b, margin, &mut w).map_err(|e| e.to_string())?;
        let expected = if full[0] <= margin * margin { full[0] } else { T::INFINITY };
        if w[0].to_bits_u64() != expected.to_bits_u64() {
            return Err(format!("{isa} {}: within {} full {} margin {margin} {c:?}", T::NAME, w[0], full[0]));
        }
    }
    Ok(())
}

/// The certificate of every distance query, under several tolerances (which send pairs down
/// different escalation paths): the interval contains the exact distance, the answer's
/// distance lies in it (up to its final rounding), and a pair reported certified has an
/// interval within the tolerance. The tolerance is the extra byte.
pub fn cert(data: &[u8], judge: Judge) -> Verdict {
    let Some((src, mut rest)) = pair_source(data) else { return Ok(()) };
    let t = u8::arbitrary(&mut rest).unwrap_or(0);
    // (4 mod 8 was the default tolerance before the correctly rounded mode took it)
    let tol = match (t % 8, t % 4) {
        (4, _) => Tolerance::CORRECTLY_ROUNDED,
        (_, 0) => Tolerance::DEFAULT,
        (_, 1) => Tolerance::EXACT,
        (_, 2) => Tolerance::scaled(1.0),
        _ => Tolerance::relative(1e-3),
    };
    if let Some((c, _)) = src.build::<f32>() {
        cert_in(&c, tol, judge)?;
    }
    if let Some((c, _)) = src.build::<f64>() {
        cert_in(&c, tol, judge)?;
    }
    Ok(())
}

/// The oracle's answer for `q` on `c`, computed once per arity: queries on the same
/// primitives (triangle distance, its brute force, the penalty method) share it. The oracle is
/// nearly all of these targets' time.
fn truth_by_arity<T: Float>(
    q: Query,
    c: &Case<T>,
    memo: &mut Vec<((usize, usize), crate::eval::Truth)>,
) -> crate::eval::Truth {
    if let Some((_, t)) = memo.iter().find(|(k, _)| *k == q.arity()) {
        return t.clone();
    }
    let t = truth(q, std::slice::from_ref(c)).swap_remove(0);
    memo.push((q.arity(), t.clone()));
    t
}

fn cert_in<T: Float>(c: &Case<T>, tol: Tolerance, judge: Judge) -> Verdict {
    let cases = std::slice::from_ref(c);
    let mut memo = Vec::new();
    for &q in Query::ALL.iter().filter(|q| !q.is_verdict() && **q != Query::Within) {
        if tol.correctly_rounded && q.is_approximate() {
            // the penalty method refuses the mode (tested in kernels/tests/rounded.rs)
            continue;
        }
        let crate::eval::Truth { d2, s } = truth_by_arity(q, c, &mut memo);
        for (v, e) in judged_variants::<T>(q, judge) {
            let e = e.tolerance(tol);
            let o = crate::eval::run_with_distances(e, q, v, cases, None).map_err(|e| e.to_string())?;
            let iv: Interval<T> = o.iv[0];
            let where_ = || format!("{} {} {} tol {tol:?}: {}", q.name(), v.name(), T::NAME, case_line(c));
            if !interval_contains(&iv, &d2) {
                return Err(format!(
                    "interval {iv:?} misses the exact distance {:e}: {}",
                    d2.to_f64().sqrt(),
                    where_()
                ));
            }
            // The answer is the square of a distance in the interval, rounded once (and the
            // documented underflow of squares below the smallest subnormal).
            if !answer_in_interval(&iv, o.d[0]) {
                return Err(format!(
                    "answer {:e} outside its interval {iv:?}: {}",
                    o.d[0].to_f64().sqrt(),
                    where_()
                ));
            }
            let allowed = (tol.scaled * T::UNIT_ROUNDOFF.to_f64() * s)
                .max(tol.absolute)
                .max(tol.relative * iv.lo.to_f64());
            let certified = o.counts.uncertified == 0;
            let w = iv.hi.to_f64() - iv.lo.to_f64();
            // one final rounding of each end when an f64 answer is narrowed to f32
            let narrowing = 4.0 * T::UNIT_ROUNDOFF.to_f64() * iv.hi.to_f64();
            // and two subnormal steps at each end when the ends are subnormal (Tolerance docs)
            let subnormal = 4.0 * T::from_bits_u64(1).to_f64();
            // correctly rounded: a certified answer is RN(D*) bit for bit (its interval may be
            // as wide as the stage that decided it left it)
            if tol.correctly_rounded {
                if certified {
                    rounded_bits(o.d[0], o.dist[0], &d2).map_err(|e| format!("{e}: {}", where_()))?;
                }
                continue;
            }
            if certified && q != Query::Penalty && w.is_finite() && w > allowed + narrowing + subnormal {
                return Err(format!(
                    "certified with width {w:e} above the tolerance {allowed:e}: {}",
                    where_()
                ));
            }
        }
    }
    Ok(())
}

/// A certified answer of the correctly rounded mode: its square `RN(D*)` and its distance
/// `RN(sqrt(D*))`, bit for bit.
fn rounded_bits<T: Float>(d: T, dist: T, d2: &rug::Rational) -> Verdict {
    let (rn, rn_sqrt): (T, T) = (crate::eval::rn(d2), crate::eval::rn_sqrt(d2));
    if d.to_bits_u64() != rn.to_bits_u64() || dist.to_bits_u64() != rn_sqrt.to_bits_u64() {
        return Err(format!(
            "correctly rounded mode answered {:e} (distance {:e}), RN(D*) is {:e} (RN(sqrt(D*)) {:e})",
            d.to_f64(),
            dist.to_f64(),
            rn.to_f64(),
            rn_sqrt.to_f64()
        ));
    }
    Ok(())
}

/// The correctly rounded mode on its own ([`Tolerance::CORRECTLY_ROUNDED`]), on every variant
/// whatever the judge: the interval contains the exact distance; a certified pair's square is
/// `RN(D*)` and its distance `RN(sqrt(D*))` bit for bit (so the variants that certify it agree);
/// the single query and a batch of one give the same bits; a pair flagged uncertified is
/// counted undecided.
pub fn rounded(data: &[u8], _judge: Judge) -> Verdict {
    let Some((src, _)) = pair_source(data) else { return Ok(()) };
    if let Some((c, _)) = src.build::<f32>() {
        rounded_in(&c)?;
    }
    if let Some((c, _)) = src.build::<f64>() {
        rounded_in(&c)?;
    }
    Ok(())
}

fn rounded_in<T: Float>(c: &Case<T>) -> Verdict {
    let cases = std::slice::from_ref(c);
    let mut memo = Vec::new();
    for &q in Query::ALL.iter().filter(|q| !q.is_verdict() && **q != Query::Within && !q.is_approximate()) {
        let d2 = truth_by_arity(q, c, &mut memo).d2;
        for (v, e) in judged_variants::<T>(q, Judge::All) {
            let e = e.tolerance(Tolerance::CORRECTLY_ROUNDED);
            let where_ = || format!("{} {} {}: {}", q.name(), v.name(), T::NAME, case_line(c));
            let o = crate::eval::run_with_distances(e, q, v, cases, None)
                .map_err(|e| format!("{e}: {}", where_()))?;
            if !interval_contains(&o.iv[0], &d2) {
                return Err(format!("interval {:?} misses the exact distance: {}", o.iv[0], where_()));
            }
            if o.certified[0] == (o.counts.undecided == 1) {
                return Err(format!(
                    "certified {} but {} undecided: {}",
                    o.certified[0],
                    o.counts.undecided,
                    where_()
                ));
            }
            if o.certified[0] {
                rounded_bits(o.d[0], o.dist[0], &d2).map_err(|e| format!("{e}: {}", where_()))?;
            }
            let (pa, pb) = crate::eval::prims(q, c);
            let (ka, kb) = q.arity();
            let one = e.single(q, &pa[..ka], &pb[..kb]).map_err(|e| format!("{e}: {}", where_()))?;
            let same = one.certified == o.certified[0]
                && one.closest.sqdist.to_bits_u64() == o.d[0].to_bits_u64()
                && one.distance.to_bits_u64() == o.dist[0].to_bits_u64();
            if !same {
                return Err(format!(
                    "the single query ({:e}, {:e}, certified {}) is not the batch's ({:e}, {:e}, {}): {}",
                    one.closest.sqdist.to_f64(),
                    one.distance.to_f64(),
                    one.certified,
                    o.d[0].to_f64(),
                    o.dist[0].to_f64(),
                    o.certified[0],
                    where_()
                ));
            }
        }
    }
    Ok(())
}

fn raw_bits_in<T: Float>(words: &[u64], judge: Judge) -> Verdict {
    let coords: Vec<T> = words.iter().map(|&w| T::from_bits_u64(w)).collect();
    for &q in Query::ALL {
        let (ka, kb) = q.arity();
        let per = 3 * (ka + kb);
        let n = coords.len() / per;
        if n == 0 {
            continue;
        }
        let pt = |k: usize| -> Point<T> { [coords[3 * k], coords[3 * k + 1], coords[3 * k + 2]] };
        let pair = |i: usize| -> (Triangle<T>, Triangle<T>) {
            let base = i * (ka + kb);
            let a = [0, 1, 2].map(|v| pt(base + v.min(ka - 1)));
            let b = [0, 1, 2].map(|v| pt(base + ka + v.min(kb - 1)));
            (a, b)
        };
        let cases: Vec<Case<T>> = (0..n)
            .map(|i| {
                let (a, b) = pair(i);
                Case { label: format!("raw/{i}"), a, b }
            })
            .collect();
        // a fixed margin: the default one (a fraction of the largest coordinate) is infinite
        // for infinite input, which `margin` rightly refuses
        let margins = vec![T::from_f64(0.5); n];
        for (v, e) in judged_variants::<T>(q, judge) {
            let o = crate::eval::run_with(e, q, v, &cases, Some(&margins))
                .map_err(|e| format!("{} {}: {e}", q.name(), v.name()))?;
            for (i, c) in cases.iter().enumerate() {
                let (pa, pb) = crate::eval::prims(q, c);
                let finite = pa[..ka].iter().chain(pb[..kb].iter()).flatten().all(|x| x.is_finite());
                let at = || format!("{} {} {} pair {i}: {}", q.name(), v.name(), T::NAME, case_line(c));
                let d = o.d[i];
                if !finite {
                    if !(d.to_f64().is_nan() && o.verdict[i] == tridist::Intersection::Invalid) {
                        return Err(format!(
                            "non-finite input must give NaN/Invalid, got {d:?} {:?}: {}",
                            o.verdict[i],
                            at()
                        ));
                    }
                    continue;
                }
                if q.is_verdict() {
                    if o.verdict[i] == tridist::Intersection::Invalid {
                        return Err(format!("finite input, no verdict: {}", at()));
                    }
                    continue;
                }
                if d.is_nan() || d < T::ZERO {
                    return Err(format!("squared distance {d:?} for finite input: {}", at()));
                }
                if d.is_finite() && !o.p[i].iter().chain(o.q[i].iter()).all(|x| x.is_finite()) {
                    return Err(format!("non-finite points: {}", at()));
                }
                if !(o.iv[i].lo >= T::ZERO && o.iv[i].lo <= o.iv[i].hi) {
                    return Err(format!("bad interval {:?}: {}", o.iv[i], at()));
                }
            }
        }
    }
    Ok(())
}

/// Arbitrary f32/f64 bit patterns (NaN, inf, subnormals, huge values) through the batch API of
/// every query and variant: no panic, no UB (run it with the address sanitizer), and the
/// documented outcome: NaN (`Invalid` for intersection) exactly for pairs with a non-finite
/// coordinate, otherwise a non-negative squared distance or +inf (overflow) with finite closest
/// points and an ordered, non-negative interval.
pub fn raw_bits(data: &[u8], judge: Judge) -> Verdict {
    let w64: Vec<u64> = data
        .chunks_exact(8)
        .map(|c| u64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
        .collect();
    raw_bits_in::<f64>(&w64, judge)?;
    let w32: Vec<u64> =
        data.chunks_exact(4).map(|c| u64::from(u32::from_le_bytes([c[0], c[1], c[2], c[3]]))).collect();
    raw_bits_in::<f32>(&w32, judge)
}

/// The untrusted-text readers (OFF meshes, case lines): never panic; what parses is valid (face
/// indices in range; case lines round-trip).
pub fn parsers(data: &[u8], _judge: Judge) -> Verdict {
    let Ok(text) = std::str::from_utf8(data) else { return Ok(()) };
    if let Ok(m) = Mesh::parse_off(text) {
        for t in &m.triangles {
            if !t.iter().all(|&i| (i as usize) < m.vertices.len()) {
                return Err(format!("face index out of range accepted: {t:?}"));
            }
        }
        if !m.triangles.is_empty() {
            let tris: Vec<[[f64; 3]; 3]> = (0..m.triangles.len()).map(|i| m.triangle(i)).collect();
            let _ = tridist::TriangleBatch::from_slice(&tris);
        }
    }
    for line in text.lines() {
        // what parses prints back to a line that parses to the same values (any NaN is NaN)
        if let Ok(c) = parse_case_line::<f64>(line) {
            let again = parse_case_line::<f64>(&case_line(&c))
                .map_err(|e| format!("a printed case does not parse: {e}"))?;
            let bits = |c: &Case<f64>| {
                let b = |x: &f64| if x.is_nan() { u64::MAX } else { x.to_bits() };
                c.a.iter().chain(c.b.iter()).flatten().map(b).collect::<Vec<_>>()
            };
            if !(again.label == c.label && bits(&again) == bits(&c)) {
                return Err(format!("case line does not round-trip: {line}"));
            }
        }
        let _ = parse_case_line::<f32>(line);
    }
    Ok(())
}

/// The oracle's floating-point filter against its unfiltered computation: the same exact
/// distance and closest points, bit for bit. Pairs are structured (or family) pairs rescaled by
/// `2^e` across the whole f64 exponent range (the extra `i16`), or, after [`RAW_TAG`], 18 raw
/// finite bit patterns (non-finite ones become 0).
pub fn oracle_filter(data: &[u8], _judge: Judge) -> Verdict {
    let (a, b) = if data.len() > 144 && data[0] == RAW_TAG {
        let x = |k: usize| {
            let w = u64::from_le_bytes(data[1 + 8 * k..9 + 8 * k].try_into().unwrap_or([0; 8]));
            Some(f64::from_bits(w)).filter(|x| x.is_finite()).unwrap_or(0.0)
        };
        let p = |k: usize| [x(3 * k), x(3 * k + 1), x(3 * k + 2)];
        ([p(0), p(1), p(2)], [p(3), p(4), p(5)])
    } else {
        let Some((src, mut rest)) = pair_source(data) else { return Ok(()) };
        let Some((c, _)) = src.build::<f64>() else { return Ok(()) };
        let f = 2f64.powi(i32::from(i16::arbitrary(&mut rest).unwrap_or(0) % 1100));
        (c.a.map(|v| v.map(|x| x * f)), c.b.map(|v| v.map(|x| x * f)))
    };
    if !a.iter().chain(b.iter()).flatten().all(|x| x.is_finite()) {
        return Ok(());
    }
    let exact =
        |t: &[[f64; 3]; 3]| tridist_oracle::exact_points(t).unwrap_or_else(|_| unreachable!("finite"));
    let (ea, eb) = (exact(&a), exact(&b));
    for (x, y) in [(&ea, &eb), (&eb, &ea)] {
        let f = tridist_oracle::triangle_triangle(x, y);
        let u = tridist_oracle::triangle_triangle_unfiltered(x, y);
        if f != u {
            return Err(format!("filtered and unfiltered oracle differ on {a:?} {b:?}"));
        }
    }
    Ok(())
}

/// Seed inputs from the family generators: `per_family` family-mode inputs for every family,
/// with `extra` bytes appended (a margin, an exponent).
pub fn seed_inputs(per_family: u64, extra: &[u8]) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    for (i, _) in Family::ALL.iter().enumerate() {
        for k in 0..per_family {
            let mut v = vec![FAMILY_TAG, i as u8];
            v.extend_from_slice(&(crate::DEFAULT_SEED + k).to_le_bytes());
            v.extend_from_slice(extra);
            out.push(v);
        }
    }
    out
}

/// Seed inputs of the `mesh` target: `n` strings of 256 bytes from a fixed stream. Family-mode
/// pair inputs are short, and the mesh decoding reads exhausted bytes as zeros, so those decode
/// to meshes of coincident zero vertices in rigid poses; these are long enough to decode both
/// meshes, both poses and their linear parts from their own bytes.
pub fn mesh_seed_inputs(n: u64) -> Vec<Vec<u8>> {
    let mut rng = crate::rng::Rng::new(crate::DEFAULT_SEED);
    (0..n).map(|_| (0..256).map(|_| rng.next_u64() as u8).collect()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn family_inputs_decode_to_their_family() {
        for (i, f) in Family::ALL.iter().enumerate() {
            let v = &seed_inputs(1, &[])[i];
            let Some((PairSource::Family(g, seed), _)) = pair_source(v) else { panic!("{f:?} not decoded") };
            assert_eq!((*f, seed), (g, crate::DEFAULT_SEED));
            let (c, fam) = PairSource::Family(g, seed).build::<f64>().expect("families are finite in f64");
            assert_eq!((fam, c.label.split('/').next()), (*f, Some(f.name())));
        }
    }

    /// The mesh seeds decode to whole meshes from their own bytes, in rigid, scaled and other
    /// (sheared or any) poses, and pass the target.
    #[test]
    fn mesh_seeds_cover_every_pose_kind() {
        let (mut rigid, mut scaled, mut other) = (0, 0, 0);
        for (i, v) in mesh_seed_inputs(16).iter().enumerate() {
            let s = crate::mesh_scenes::fuzz_scene(v).expect("256 bytes decode");
            for m in [&s.a, &s.b] {
                assert!(m.vertices.iter().any(|x| *x != m.vertices[0]), "seed {i}: coincident vertices");
            }
            for p in [&s.pose_a, &s.pose_b] {
                let r = p.rotation;
                // the Gram matrix M^T M: the identity for a rotation, diagonal for scaled axes
                let g = |a: usize, b: usize| (0..3).map(|k| r[k][a] * r[k][b]).sum::<f64>();
                let diagonal = (0..3).all(|a| (0..3).all(|b| a == b || g(a, b).abs() < 1e-9));
                let unit = (0..3).all(|a| (g(a, a) - 1.0).abs() < 1e-9);
                match (diagonal, unit) {
                    (true, true) => rigid += 1,
                    (true, false) => scaled += 1,
                    _ => other += 1,
                }
            }
            assert_eq!(mesh(v, Judge::All), Ok(()), "seed {i}");
        }
        assert!(rigid > 0 && scaled > 0 && other > 0, "rigid {rigid}, scaled {scaled}, other {other}");
    }

    #[test]
    fn structured_inputs_decode() {
        let data: Vec<u8> = (0..80u8).collect();
        let (src, _) = pair_source(&data).expect("80 bytes decode");
        assert!(matches!(src, PairSource::Built(_)));
        assert!(src.build::<f32>().is_some());
    }

    /// A sampling judge keeps exactly one of `n` candidates per check, and over many inputs
    /// every candidate about equally often, for every salt; `All` keeps every one.
    #[test]
    fn a_sampling_judge_keeps_one_and_covers_all() {
        for n in [1usize, 2, 7, 14] {
            for salt in 0..16u64 {
                let mut seen = vec![0usize; n];
                for k in 0..2000u32 {
                    let j = Judge::of(&k.to_le_bytes());
                    let kept: Vec<usize> = (0..n).filter(|&i| j.keeps(i, n, salt)).collect();
                    assert_eq!(kept.len(), 1, "n {n} salt {salt} input {k}: {kept:?}");
                    seen[kept[0]] += 1;
                }
                let (lo, hi) = (seen.iter().min().unwrap(), seen.iter().max().unwrap());
                assert!(*lo * 2 > 2000 / n && *hi < 2 * 2000 / n + 1, "n {n} salt {salt}: {seen:?}");
                assert!((0..n).all(|i| Judge::All.keeps(i, n, salt)));
            }
        }
    }
}
