//! Mesh-level conformance: `tridist mesh-cases` writes the corpus's mesh scenes (corpus/mesh:
//! the meshes as OFF, the placements with their exact answers), `tridist mesh-eval` answers a
//! mesh case file with tridist or a peer, and [`judge_mesh`] judges answers against the exact
//! ones (`tridist judge --mesh`, and the mesh table of `tridist peers`).
//!
//! Mesh case file: one placed pair per line, `LABEL MESH_A MESH_B` (OFF files, relative to the
//! case file), then pose A and pose B, each as a translation and the rotation's rows (12
//! numbers: a placed vertex is `R v + t`), then `exact=NUM/DEN` (the smallest exact squared
//! distance over all triangle pairs of the exactly placed meshes) and `pair=I,J` (a triangle
//! pair attaining it). Answer file: one line per case, an optional label, the squared
//! distance (`nan`, `inf`, `error` allowed), optionally the triangle pair `I J`.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;
use rug::Rational;
use tridist::{Engine, Isa, Pose};
use tridist_oracle::metrics::{contact_miss, excess, false_zero, Precision};
use tridist_scenes::mesh::Mesh;
use tridist_scenes::mesh_exact::{contacts_exact, mesh_exact, pair_d2, scene_magnitude};
use tridist_scenes::mesh_peer::{MeshLib, MeshPeer};
use tridist_scenes::peer::{Peer, PeerPose};
use tridist_scenes::protocol::{ball_placements, ball_radius, near_contact_pose, normalise};
use tridist_scenes::rng::Rng;

use crate::{Fail, Prec};

/// An answer farther than this from the exact distance (in `u S` of its precision) is a wrong
/// distance, and a reported pair whose exact distance is farther than this from the minimum a
/// wrong pair: MESH.md's wrong-distance threshold.
pub(crate) const WRONG: f64 = 64.0;

/// The contact classification's `c` (ACCURACY.md), in `u S`.
const CONTACT_C: f64 = 8.0;

/// The contact margin of the corpus's close scenes: 1 % of the normalised meshes' size (2), as
/// MESH.md's contact query.
const CONTACT_MARGIN: f64 = 0.02;

/// The corpus's mesh case file, in corpus/mesh.
pub(crate) const CASE_FILE: &str = "mesh.cases";

#[derive(Args, Debug)]
pub(crate) struct MeshCasesArgs {
    /// Write the meshes and the case file here [default: corpus/mesh].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub(crate) struct MeshEvalArgs {
    /// The mesh case file.
    #[arg(long, value_name = "FILE")]
    cases: PathBuf,
    /// Answer with this mesh peer instead of tridist: fcl, fcl-rss, fcl-kios, coal, coal-rss,
    /// coal-kios, trueform-obb-f64, trueform-aabb-f32, trueform-aabb-f64, trueform-obbrss-f64,
    /// parry3d.
    #[arg(long)]
    peer: Option<String>,
    /// tridist's (and parry's) precision.
    #[arg(long, value_enum, default_value = "f64")]
    precision: Prec,
}

/// One placed pair of a mesh case file.
pub(crate) struct MeshCase {
    pub label: String,
    pub a: String,
    pub b: String,
    pub pa: Pose<f64>,
    pub pb: Pose<f64>,
    pub exact: Option<Rational>,
    pub pair: Option<(usize, usize)>,
    /// The contact margin, and the exact contact set at it (sorted).
    pub margin: Option<f64>,
    pub contacts: Option<Vec<(usize, usize)>>,
    /// 1-based line.
    pub line: usize,
}

fn pose_from(v: &[f64]) -> Pose<f64> {
    Pose {
        translation: [v[0], v[1], v[2]],
        rotation: [[v[3], v[4], v[5]], [v[6], v[7], v[8]], [v[9], v[10], v[11]]],
    }
}

fn pose_text(p: &Pose<f64>) -> String {
    p.translation
        .iter()
        .chain(p.rotation.iter().flatten())
        .map(|x| format!("{x:?}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Triangle pairs as `i,j;i,j;...` (empty: none).
pub(crate) fn pairs_text(v: &[(usize, usize)]) -> String {
    v.iter().map(|(i, j)| format!("{i},{j}")).collect::<Vec<_>>().join(";")
}

/// Parses [`pairs_text`].
pub(crate) fn parse_pairs(s: &str) -> Result<Vec<(usize, usize)>, String> {
    s.split(';')
        .filter(|p| !p.is_empty())
        .map(|p| {
            let (i, j) = p.split_once(',').ok_or_else(|| format!("not a pair: {p:?}"))?;
            let n = |x: &str| x.parse::<usize>().map_err(|_| format!("not a triangle index: {x:?}"));
            Ok((n(i)?, n(j)?))
        })
        .collect()
}

/// Parses a mesh case file (errors name the line).
pub(crate) fn parse_cases(text: &str, name: &str) -> Result<Vec<MeshCase>, Fail> {
    let mut out = Vec::new();
    for (i, l) in text.lines().enumerate() {
        let l = l.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        let at = |e: String| Fail(format!("{name}: line {}: {e}", i + 1));
        let f: Vec<&str> = l.split_whitespace().collect();
        if f.len() < 27 {
            return Err(at(format!(
                "expected a label, two mesh files and 24 numbers, found {} fields",
                f.len()
            )));
        }
        let nums: Vec<f64> = f[3..27]
            .iter()
            .map(|s| s.parse::<f64>().map_err(|_| at(format!("not a number: {s:?}"))))
            .collect::<Result<_, _>>()?;
        let (mut exact, mut pair, mut margin, mut contacts) = (None, None, None, None);
        for extra in &f[27..] {
            if let Some(r) = extra.strip_prefix("exact=") {
                exact =
                    Some(r.parse::<Rational>().map_err(|_| at(format!("not an exact fraction: {extra:?}")))?);
            } else if let Some(p) = extra.strip_prefix("pair=") {
                let (x, y) = p.split_once(',').ok_or_else(|| at(format!("not a pair: {extra:?}")))?;
                let n = |s: &str| s.parse::<usize>().map_err(|_| at(format!("not a pair: {extra:?}")));
                pair = Some((n(x)?, n(y)?));
            } else if let Some(m) = extra.strip_prefix("margin=") {
                let m = m.parse::<f64>().ok().filter(|m| m.is_finite() && *m >= 0.0);
                margin = Some(m.ok_or_else(|| at(format!("not a margin: {extra:?}")))?);
            } else if let Some(list) = extra.strip_prefix("contacts=") {
                let mut v = parse_pairs(list).map_err(|e| at(format!("{e} in {extra:?}")))?;
                v.sort_unstable();
                contacts = Some(v);
            } else {
                return Err(at(format!("unexpected field {extra:?}")));
            }
        }
        out.push(MeshCase {
            label: f[0].to_string(),
            a: f[1].to_string(),
            b: f[2].to_string(),
            pa: pose_from(&nums[..12]),
            pb: pose_from(&nums[12..]),
            exact,
            pair,
            margin,
            contacts,
            line: i + 1,
        });
    }
    if out.is_empty() {
        return Err(Fail(format!("{name}: no cases")));
    }
    Ok(out)
}

/// The meshes a case file names, loaded once each (relative to the case file's folder).
pub(crate) fn load_meshes(cases: &[MeshCase], dir: &Path) -> Result<HashMap<String, Mesh>, Fail> {
    let mut m = HashMap::new();
    for c in cases {
        for name in [&c.a, &c.b] {
            if !m.contains_key(name) {
                let p = dir.join(name);
                let mesh = Mesh::load(&p).map_err(|e| Fail(format!("{}: {e}", p.display())))?;
                m.insert(name.clone(), mesh);
            }
        }
    }
    Ok(m)
}

// ---------------------------------------------------------------------------------------------
// the corpus's scenes

/// A unit cube [-1, 1]^3 as 12 triangles.
fn cube() -> Mesh {
    let vertices: Vec<[f64; 3]> =
        (0..8).map(|i| [0, 1, 2].map(|k| if (i >> k) & 1 == 1 { 1.0 } else { -1.0 })).collect();
    let q = |a: u32, b: u32, c: u32, d: u32| [[a, b, c], [a, c, d]];
    let triangles =
        [q(0, 2, 3, 1), q(4, 5, 7, 6), q(0, 1, 5, 4), q(2, 6, 7, 3), q(0, 4, 6, 2), q(1, 3, 7, 5)]
            .into_iter()
            .flatten()
            .collect();
    Mesh { vertices, triangles }
}

/// The mesh with degenerate triangles: every 7th a segment (a repeated vertex), every 7th
/// after the third a point (one vertex three times).
fn degenerate(m: &Mesh) -> Mesh {
    let mut d = m.clone();
    for (k, t) in d.triangles.iter_mut().enumerate() {
        match k % 7 {
            0 => t[2] = t[0],
            3 => *t = [t[0]; 3],
            _ => {}
        }
    }
    d
}

fn off_text(m: &Mesh) -> String {
    let mut s = format!("OFF\n{} {} 0\n", m.vertices.len(), m.triangles.len());
    for v in &m.vertices {
        let _ = writeln!(s, "{:?} {:?} {:?}", v[0], v[1], v[2]);
    }
    for t in &m.triangles {
        let _ = writeln!(s, "3 {} {} {}", t[0], t[1], t[2]);
    }
    s
}

/// A pose about the z axis by `angle`, then moved by `t` (rows exact in z).
fn about_z(angle: f64, t: [f64; 3]) -> Pose<f64> {
    let (s, c) = angle.sin_cos();
    Pose { rotation: [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]], translation: t }
}

/// The Armadillo as this repository carries it (raw coordinates), named from corpus/mesh.
const ARMADILLO: &str = "../../data/meshes/armadillo.off";

/// One scene of the corpus: label, mesh A, mesh B, pose A, pose B.
type Scene = (String, &'static str, &'static str, Pose<f64>, Pose<f64>);

/// The corpus's scenes.
fn scenes(part: &Mesh, degen: &Mesh, arm: &Mesh, seed: u64) -> Result<Vec<Scene>, Fail> {
    let id = Pose::identity();
    let tm = |m: &Mesh| {
        tridist::Mesh::<f64>::new(m.vertices.clone(), m.triangles.clone()).map_err(|e| Fail(e.to_string()))
    };
    let (tp, td) = (tm(part)?, tm(degen)?);
    let e = Engine::auto();
    let gap = |pb: &Pose<f64>| tridist_scenes::protocol::mesh_gap(&e, &tp, &tp, pb).map_err(Fail);
    let mut out = Vec::new();
    // separated random placements (TrueForm's protocol): the first 8 apart
    let ball = ball_placements(64, ball_radius(part), seed);
    for (k, p) in ball.iter().enumerate() {
        if out.len() < 8 && gap(p)? > 0.0 {
            out.push((format!("separated/{seed}/{k}"), "part.off", "part.off", id, *p));
        }
    }
    // through each other: placements within a tenth of the size, overlapping
    let mut k = 0;
    for (i, p) in ball_placements(64, 0.2, seed ^ 1).iter().enumerate() {
        if k < 4 && gap(p)? == 0.0 {
            out.push((format!("through/{seed}/{i}"), "part.off", "part.off", id, *p));
            k += 1;
        }
    }
    // near contact at gaps 1e-1 .. 1e-6 of the size (2)
    for (k, g) in [1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6].iter().enumerate() {
        let p = near_contact_pose(&tp, &tp, seed, k as u64, 2.0 * g).map_err(Fail)?;
        out.push((format!("near_contact/{seed}/{k}/gap_{g:e}"), "part.off", "part.off", id, p));
    }
    // far from the origin: separated placements, both moved 1e3 .. 1e7 along a random direction
    let mut rng = Rng::new(seed ^ 0x0066_6172);
    let seps: Vec<Pose<f64>> = out.iter().filter(|s| s.0.starts_with("separated")).map(|s| s.4).collect();
    for (k, off) in [1e3, 1e4, 1e5, 1e6, 1e7].iter().enumerate() {
        let d = rng.dir().map(|x| x * off);
        let p = seps[k % seps.len()];
        let pa = Pose { translation: d, ..id };
        let pb = Pose { translation: [0, 1, 2].map(|i| p.translation[i] + d[i]), ..p };
        out.push((format!("far/{seed}/{k}/offset_{off:e}"), "part.off", "part.off", pa, pb));
    }
    // degenerate triangles: the part with segments and points, near contact and apart
    for (k, g) in [1e-2, 1e-4, 1e-6].iter().enumerate() {
        let p = near_contact_pose(&td, &tp, seed ^ 2, k as u64, 2.0 * g).map_err(Fail)?;
        out.push((format!("degenerate/{seed}/{k}/gap_{g:e}"), "part_degenerate.off", "part.off", id, p));
    }
    out.push((format!("degenerate/{seed}/3/apart"), "part_degenerate.off", "part.off", id, seps[0]));
    // coplanar faces: a cube on a cube, turned about z by a non-axis angle, touching and at
    // gaps, and offset sideways
    for (k, (g, side)) in [(0.0, 0.0), (0.0, 0.7), (1e-3, 0.3), (1e-6, 1.2), (1e-9, 0.0)].iter().enumerate() {
        let p = about_z(0.3 + 0.4 * k as f64, [*side, 0.5 * side, 2.0 + g]);
        out.push((format!("coplanar/{seed}/{k}/gap_{g:e}"), "cube.off", "cube.off", id, p));
    }
    // TrueForm's protocol on two Armadillos (52,000 triangles each, as carried): the first 12
    // separated placements
    let ta = tm(arm)?;
    let mut k = 0;
    for (i, p) in ball_placements(64, ball_radius(arm), seed).iter().enumerate() {
        if k < 12 && tridist_scenes::protocol::mesh_gap(&e, &ta, &ta, p).map_err(Fail)? > 0.0 {
            out.push((format!("armadillo/{seed}/{i}"), ARMADILLO, ARMADILLO, id, *p));
            k += 1;
        }
    }
    Ok(out)
}

pub(crate) fn cmd_mesh_cases(a: &MeshCasesArgs) -> Result<ExitCode, Fail> {
    let dir = a.out.clone().unwrap_or_else(|| crate::root().join("corpus/mesh"));
    std::fs::create_dir_all(&dir).map_err(|e| Fail(format!("{}: {e}", dir.display())))?;
    let mut part = tridist_scenes::mesh::carried("mech-holes-shark.off")
        .map_err(|e| Fail(format!("mech-holes-shark.off: {e}")))?;
    normalise(&mut part);
    let degen = degenerate(&part);
    let seed = tridist_scenes::DEFAULT_SEED;
    let meshes = [("part.off", &part), ("part_degenerate.off", &degen), ("cube.off", &cube())];
    for (name, m) in meshes {
        let p = dir.join(name);
        std::fs::write(&p, off_text(m)).map_err(|e| Fail(format!("{}: {e}", p.display())))?;
    }
    // the meshes as the case file's readers get them (parsed back from the text written)
    let mut by_name: HashMap<&str, Mesh> = meshes
        .iter()
        .map(|(n, m)| Ok((*n, Mesh::parse_off(&off_text(m)).map_err(|e| Fail(format!("{n}: {e}")))?)))
        .collect::<Result<_, Fail>>()?;
    // the carried Armadillo, named from corpus/mesh; written beside the cases when they go
    // elsewhere (--out)
    let carried = tridist_scenes::mesh::data_dir().join("armadillo.off");
    let arm = Mesh::load(&carried).map_err(|e| Fail(format!("{}: {e}", carried.display())))?;
    by_name.insert(ARMADILLO, arm.clone());
    let in_repo = dir.join(ARMADILLO).canonicalize().ok() == carried.canonicalize().ok();
    let arm_name = if in_repo { ARMADILLO } else { "armadillo.off" };
    if !in_repo {
        std::fs::copy(&carried, dir.join(arm_name)).map_err(|e| Fail(format!("{}: {e}", dir.display())))?;
    }
    let file_name = |n: &'static str| if n == ARMADILLO { arm_name } else { n };
    if by_name["part.off"] != part {
        return Err(Fail("part.off does not parse back to the same values".into()));
    }
    let mut s = format!(
        "# tridist mesh cases (format 1, corpus/README.md), seed {seed}\n\
         # label, mesh A, mesh B, pose A (translation, rotation rows), pose B, then exact=NUM/DEN (the smallest\n\
         # squared distance of the exactly placed meshes) and pair=I,J (a triangle pair attaining it)\n"
    );
    for (label, ma, mb, pa, pb) in scenes(&part, &degen, &arm, seed)? {
        let x =
            mesh_exact(&by_name[ma], &pa, &by_name[mb], &pb).map_err(|e| Fail(format!("{label}: {e}")))?;
        let _ = writeln!(
            s,
            "{label} {} {} {} {} exact={}/{} pair={},{}",
            file_name(ma),
            file_name(mb),
            pose_text(&pa),
            pose_text(&pb),
            x.d2.numer(),
            x.d2.denom(),
            x.tri_a,
            x.tri_b
        );
        // contact sets at 1 % of the size (MESH.md's margin) where the meshes are close
        if ["near_contact/", "coplanar/", "degenerate/", "through/"].iter().any(|f| label.starts_with(f)) {
            let m = CONTACT_MARGIN;
            let cs = contacts_exact(&by_name[ma], &pa, &by_name[mb], &pb, m)
                .map_err(|e| Fail(format!("{label}: {e}")))?;
            s.pop();
            let _ = writeln!(s, " margin={m:?} contacts={}", pairs_text(&cs));
        }
        eprintln!("{label}: {} candidates, {} answered exactly", x.candidates.0, x.candidates.1);
    }
    let p = dir.join(CASE_FILE);
    std::fs::write(&p, s).map_err(|e| Fail(format!("{}: {e}", p.display())))?;
    eprintln!("wrote {}", dir.display());
    Ok(ExitCode::SUCCESS)
}

// ---------------------------------------------------------------------------------------------
// answering

/// A contender at the mesh level.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum MeshContender {
    /// tridist's `Engine::mesh_distance` with this instruction set, in this precision.
    Tridist(Isa, Prec),
    /// A C++ mesh peer.
    Peer(MeshLib),
    /// parry3d (`Prec::F32`) or parry3d-f64, `TriMesh` and `query::distance`.
    Parry(Prec),
}

impl MeshContender {
    /// The precision its answers are judged in.
    pub(crate) fn precision(self) -> Prec {
        match self {
            MeshContender::Tridist(_, p) | MeshContender::Parry(p) => p,
            MeshContender::Peer(MeshLib::TrueFormAabbF32) => Prec::F32,
            MeshContender::Peer(_) => Prec::F64,
        }
    }
}

/// An answer to a mesh case.
#[derive(Clone, Debug, Default)]
pub(crate) struct MeshAnswer {
    /// The squared distance (NaN: none).
    pub d2: f64,
    /// The closest triangle pair, when reported.
    pub pair: Option<(usize, usize)>,
    /// The triangle pairs within the case's margin, when reported.
    pub contacts: Option<Vec<(usize, usize)>>,
}

impl MeshAnswer {
    fn distance(d2: f64) -> MeshAnswer {
        MeshAnswer { d2, pair: None, contacts: None }
    }
}

/// The scaled axis (axis times angle) of a rotation matrix, for parry: through the unit
/// quaternion (Shepperd's method, stable at every angle).
fn scaled_axis(r: &[[f64; 3]; 3]) -> [f64; 3] {
    let tr = r[0][0] + r[1][1] + r[2][2];
    let q = if tr > 0.0 {
        let s = (tr + 1.0).sqrt() * 2.0;
        [(r[2][1] - r[1][2]) / s, (r[0][2] - r[2][0]) / s, (r[1][0] - r[0][1]) / s, 0.25 * s]
    } else if r[0][0] > r[1][1] && r[0][0] > r[2][2] {
        let s = (1.0 + r[0][0] - r[1][1] - r[2][2]).sqrt() * 2.0;
        [0.25 * s, (r[0][1] + r[1][0]) / s, (r[0][2] + r[2][0]) / s, (r[2][1] - r[1][2]) / s]
    } else if r[1][1] > r[2][2] {
        let s = (1.0 + r[1][1] - r[0][0] - r[2][2]).sqrt() * 2.0;
        [(r[0][1] + r[1][0]) / s, 0.25 * s, (r[1][2] + r[2][1]) / s, (r[0][2] - r[2][0]) / s]
    } else {
        let s = (1.0 + r[2][2] - r[0][0] - r[1][1]).sqrt() * 2.0;
        [(r[0][2] + r[2][0]) / s, (r[1][2] + r[2][1]) / s, 0.25 * s, (r[1][0] - r[0][1]) / s]
    };
    let (v, w) = ([q[0], q[1], q[2]], q[3]);
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if n == 0.0 {
        return [0.0; 3];
    }
    let angle = 2.0 * n.atan2(w);
    v.map(|x| x / n * angle)
}

/// parry's answers to the cases (distance squared in `T`, no pair).
fn parry_answers<T: Peer>(cases: &[MeshCase], meshes: &HashMap<String, Mesh>) -> Vec<MeshAnswer> {
    let mut built: HashMap<&str, Option<T::Mesh>> = HashMap::new();
    for c in cases {
        for n in [&c.a, &c.b] {
            built.entry(n.as_str()).or_insert_with(|| T::trimesh(&meshes[n].vertices, &meshes[n].triangles));
        }
    }
    cases
        .iter()
        .map(|c| {
            let pose = |p: &Pose<f64>| -> PeerPose { (p.translation, scaled_axis(&p.rotation)) };
            let d = match (&built[c.a.as_str()], &built[c.b.as_str()]) {
                (Some(a), Some(b)) => T::mesh_distance(a, &pose(&c.pa), b, &pose(&c.pb)),
                _ => f64::NAN,
            };
            // squared in T, as the triangle table squares the peers' distances
            let d = T::from_f64(d);
            MeshAnswer::distance((d * d).to_f64())
        })
        .collect()
}

fn tridist_answers<T: tridist::Real + Peer>(
    isa: Isa,
    cases: &[MeshCase],
    meshes: &HashMap<String, Mesh>,
) -> Result<Vec<MeshAnswer>, Fail> {
    let e = Engine::new(isa).map_err(|e| Fail(e.to_string()))?;
    let mut built: HashMap<&str, tridist::Mesh<T>> = HashMap::new();
    for c in cases {
        for n in [&c.a, &c.b] {
            if !built.contains_key(n.as_str()) {
                let m = &meshes[n];
                let v = m.vertices.iter().map(|p| p.map(T::from_f64)).collect();
                let tm = tridist::Mesh::new(v, m.triangles.clone()).map_err(|e| Fail(format!("{n}: {e}")))?;
                built.insert(n.as_str(), tm);
            }
        }
    }
    let pose = crate::meshreport::pose_in::<T>;
    cases
        .iter()
        .map(|c| {
            let r = e
                .mesh_distance(&built[c.a.as_str()], &pose(&c.pa), &built[c.b.as_str()], &pose(&c.pb))
                .map_err(|x| Fail(format!("{}: {x}", c.label)))?;
            let mut ans = r.map_or(MeshAnswer::distance(f64::NAN), |r| MeshAnswer {
                d2: r.sqdist.to_f64(),
                pair: Some((r.tri_a, r.tri_b)),
                contacts: None,
            });
            if let Some(m) = c.margin {
                let cs = e
                    .mesh_contacts(
                        &built[c.a.as_str()],
                        &pose(&c.pa),
                        &built[c.b.as_str()],
                        &pose(&c.pb),
                        T::from_f64(m),
                        None,
                    )
                    .map_err(|x| Fail(format!("{}: {x}", c.label)))?;
                let mut v: Vec<(usize, usize)> = cs.iter().map(|c| (c.tri_a, c.tri_b)).collect();
                v.sort_unstable();
                ans.contacts = Some(v);
            }
            Ok(ans)
        })
        .collect()
}

/// A contender's answers to the cases: the squared distance (NaN: none) and the pair when it
/// reports one; `Err` when it was not built in.
pub(crate) fn answers(
    who: MeshContender,
    cases: &[MeshCase],
    meshes: &HashMap<String, Mesh>,
) -> Result<Vec<MeshAnswer>, Fail> {
    match who {
        MeshContender::Tridist(isa, Prec::F32) => tridist_answers::<f32>(isa, cases, meshes),
        MeshContender::Tridist(isa, Prec::F64) => tridist_answers::<f64>(isa, cases, meshes),
        MeshContender::Parry(Prec::F32) => Ok(parry_answers::<f32>(cases, meshes)),
        MeshContender::Parry(Prec::F64) => Ok(parry_answers::<f64>(cases, meshes)),
        MeshContender::Peer(lib) => {
            if !lib.available() {
                return Err(Fail(format!("{} is not built in ({})", lib.name(), lib.how_to_get())));
            }
            let mut built: HashMap<&str, Option<MeshPeer>> = HashMap::new();
            for c in cases {
                for n in [&c.a, &c.b] {
                    built
                        .entry(n.as_str())
                        .or_insert_with(|| MeshPeer::new(lib, &meshes[n].vertices, &meshes[n].triangles));
                }
            }
            Ok(cases
                .iter()
                .map(|c| match (&built[c.a.as_str()], &built[c.b.as_str()]) {
                    (Some(a), Some(b)) => {
                        let d = a.distance(&c.pa, b, &c.pb);
                        MeshAnswer::distance(if lib == MeshLib::TrueFormAabbF32 {
                            f64::from((d as f32) * (d as f32))
                        } else {
                            d * d
                        })
                    }
                    _ => MeshAnswer::distance(f64::NAN),
                })
                .collect())
        }
    }
}

fn case_dir(path: &Path) -> PathBuf {
    path.parent().map_or_else(|| PathBuf::from("."), Path::to_path_buf)
}

pub(crate) fn cmd_mesh_eval(a: &MeshEvalArgs) -> Result<ExitCode, Fail> {
    let text = std::fs::read_to_string(&a.cases).map_err(|e| Fail(format!("{}: {e}", a.cases.display())))?;
    let cases = parse_cases(&text, &a.cases.display().to_string())?;
    let meshes = load_meshes(&cases, &case_dir(&a.cases))?;
    let who = match a.peer.as_deref() {
        None => MeshContender::Tridist(Engine::auto().isa(), a.precision),
        Some("parry3d") => MeshContender::Parry(a.precision),
        Some(p) => {
            MeshContender::Peer(MeshLib::JUDGED.into_iter().find(|l| l.cli_name() == p).ok_or_else(|| {
                Fail(format!(
                    "unknown mesh peer {p:?} (parry3d, {})",
                    MeshLib::JUDGED.map(MeshLib::cli_name).join(", ")
                ))
            })?)
        }
    };
    for (c, x) in cases.iter().zip(answers(who, &cases, &meshes)?) {
        let d = if x.d2.is_nan() { "error".to_string() } else { format!("{:?}", x.d2) };
        let pair = x.pair.map_or(String::new(), |(i, j)| format!(" {i} {j}"));
        let contacts = x.contacts.map_or(String::new(), |v| format!(" contacts={}", pairs_text(&v)));
        outln!("{} {d}{pair}{contacts}", c.label);
    }
    Ok(ExitCode::SUCCESS)
}

// ---------------------------------------------------------------------------------------------
// judging

/// The judgement of one mesh answer.
#[derive(Clone, Debug, Default)]
pub(crate) struct MeshJudged {
    pub excess: f64,
    pub wrong: bool,
    pub contact_miss: bool,
    pub false_zero: bool,
    pub nonfinite: bool,
    /// The reported pair's exact distance is farther than [`WRONG`] `u S` from the minimum.
    pub wrong_pair: bool,
    /// Contacts missed (exactly within the margin less [`WRONG`] `u S`, not reported) and
    /// extra (reported, exactly beyond the margin plus [`WRONG`] `u S`); None: not judged.
    pub contacts: Option<(usize, usize)>,
}

/// The contacts judged over some answers: missed and extra in all, and the cases judged
/// (None when no answer reported contacts).
pub(crate) fn contacts_total<'a>(js: impl Iterator<Item = &'a MeshJudged>) -> Option<(usize, usize, usize)> {
    let judged: Vec<(usize, usize)> = js.filter_map(|j| j.contacts).collect();
    (!judged.is_empty())
        .then(|| (judged.iter().map(|c| c.0).sum(), judged.iter().map(|c| c.1).sum(), judged.len()))
}

pub(crate) fn metrics_precision(p: Prec) -> Precision {
    match p {
        Prec::F32 => tridist_scenes::eval::prec::<f32>(),
        Prec::F64 => tridist_scenes::eval::prec::<f64>(),
    }
}

/// Judges answers `(d2, pair)` to cases (each with its exact answer) in precision `prec`.
pub(crate) fn judge_mesh(
    cases: &[MeshCase],
    meshes: &HashMap<String, Mesh>,
    answers: &[MeshAnswer],
    prec: Prec,
) -> Result<Vec<MeshJudged>, Fail> {
    let pr = metrics_precision(prec);
    cases
        .iter()
        .zip(answers)
        .map(|(c, x)| {
            let (d2, pair) = (x.d2, x.pair);
            let exact = c.exact.as_ref().ok_or_else(|| Fail(format!("line {}: no exact answer", c.line)))?;
            let (a, b) = (&meshes[&c.a], &meshes[&c.b]);
            let s = scene_magnitude(a, &c.pa, b, &c.pb).map_err(|e| Fail(format!("line {}: {e}", c.line)))?;
            let us = pr.u * s;
            if let Some((i, j)) = c.pair {
                // the case's own pair must attain its exact answer (a corrupted corpus is an error)
                if pair_d2(a, &c.pa, b, &c.pb, i, j).ok().as_ref() != Some(exact) {
                    return Err(Fail(format!("line {}: pair={i},{j} does not attain exact=", c.line)));
                }
            }
            let e = excess(d2, exact, s, pr);
            let nonfinite = !d2.is_finite();
            let wrong_pair = match pair {
                Some((i, j)) => match pair_d2(a, &c.pa, b, &c.pb, i, j) {
                    Ok(p) => p.to_f64().sqrt() - exact.to_f64().sqrt() > WRONG * us * (1.0 + 1e-9),
                    Err(_) => true,
                },
                None => false,
            };
            let contacts = match (&c.contacts, &x.contacts, c.margin) {
                (Some(truth), Some(got), Some(m)) => {
                    let d = |i: usize, j: usize| {
                        pair_d2(a, &c.pa, b, &c.pb, i, j).map(|r| r.to_f64().sqrt()).unwrap_or(f64::INFINITY)
                    };
                    let missed = truth
                        .iter()
                        .filter(|p| got.binary_search(p).is_err() && d(p.0, p.1) <= m - WRONG * us)
                        .count();
                    let extra = got
                        .iter()
                        .filter(|p| truth.binary_search(p).is_err() && d(p.0, p.1) > m + WRONG * us)
                        .count();
                    Some((missed, extra))
                }
                _ => None,
            };
            Ok(MeshJudged {
                contacts,
                excess: if e.is_nan() { f64::INFINITY } else { e },
                wrong: nonfinite || e.is_nan() || e > WRONG,
                contact_miss: contact_miss(d2, exact, s, pr, CONTACT_C),
                false_zero: false_zero(d2, exact, s, pr, CONTACT_C),
                nonfinite,
                wrong_pair,
            })
        })
        .collect()
}

/// Every mesh contender the table judges (built or not) with its library name, version and
/// configuration.
pub(crate) fn contenders() -> Vec<(MeshContender, String, String, String)> {
    let mut v = Vec::new();
    let best = Engine::auto().isa();
    let mut isas = vec![Isa::Avx2Fma, best];
    isas.retain(|i| i.is_available());
    isas.dedup();
    for p in [Prec::F32, Prec::F64] {
        for &isa in &isas {
            v.push((
                MeshContender::Tridist(isa, p),
                "tridist".to_string(),
                env!("CARGO_PKG_VERSION").to_string(),
                format!("`Engine::mesh_distance`, {} variant, default tree", isa.name()),
            ));
        }
        v.push((
            MeshContender::Parry(p),
            "parry3d".into(),
            tridist_scenes::peer::Lib::Parry.version().into(),
            format!(
                "{} `query::distance`, two `TriMesh`",
                if p == Prec::F32 { "parry3d" } else { "parry3d-f64" }
            ),
        ));
    }
    for lib in MeshLib::JUDGED {
        let (name, version) = match lib {
            MeshLib::Fcl | MeshLib::FclRss | MeshLib::FclKios => {
                ("fcl", tridist_scenes::peer::Lib::Fcl.version())
            }
            MeshLib::Coal | MeshLib::CoalRss | MeshLib::CoalKios => {
                ("coal", tridist_scenes::peer::Lib::Coal.version())
            }
            _ => ("trueform", tridist_scenes::peer::Lib::TrueForm.version()),
        };
        v.push((MeshContender::Peer(lib), name.into(), version.into(), lib.name().to_string()));
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scaled_axis_round_trips_every_angle() {
        for (axis, angle) in [
            ([1.0, 2.0, 3.0], 0.3),
            ([0.0, 0.0, 1.0], 3.1),
            ([1.0, -1.0, 0.5], std::f64::consts::PI - 1e-5),
            ([0.2, 1.0, 0.0], 1e-9),
        ] {
            let p = Pose::from_axis_angle(axis, angle, [0.0; 3]).unwrap();
            let v = scaled_axis(&p.rotation);
            let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            let q = Pose::from_axis_angle(if n > 0.0 { v } else { [0.0, 0.0, 1.0] }, n, [0.0; 3]).unwrap();
            for i in 0..3 {
                for j in 0..3 {
                    assert!((p.rotation[i][j] - q.rotation[i][j]).abs() < 1e-12, "{axis:?} {angle}");
                }
            }
        }
        assert_eq!(scaled_axis(&Pose::<f64>::identity().rotation), [0.0; 3]);
    }

    #[test]
    fn the_cube_is_closed_and_outward() {
        let c = cube();
        assert_eq!(c.triangles.len(), 12);
        // every edge is shared by exactly two triangles, in opposite directions
        let mut edges = std::collections::HashMap::new();
        for t in &c.triangles {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        for (&(a, b), &n) in &edges {
            assert_eq!(n, 1);
            assert_eq!(edges.get(&(b, a)), Some(&1));
        }
    }
}
