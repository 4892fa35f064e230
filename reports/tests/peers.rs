//! The conformance corpus and `tridist peers` as a user runs them: the committed corpus is
//! exactly what `tridist cases` writes (so its exact answers are the oracle's and cannot drift),
//! PEERS.md gets a row per library and precision it offers (built or "not built"), tridist's
//! rows conform, and a wrong exact answer planted in a copy of the corpus is caught and named
//! by its file and line.

mod common;
use common::tridist;

use std::path::{Path, PathBuf};

use tridist_scenes::peer::Lib;

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../corpus/triangle")
}

#[test]
fn the_corpus_is_what_tridist_cases_writes() {
    for prec in ["f32", "f64"] {
        let (code, out, err) = tridist(
            &[
                "cases",
                "--family",
                "all",
                "--count",
                "150",
                "--precision",
                prec,
                "--exact",
                "--seed",
                "1898041687",
            ],
            "",
        );
        assert_eq!(code, 0, "{err}");
        let file = corpus().join(format!("tri_tri.{prec}.cases"));
        let committed = std::fs::read_to_string(&file).unwrap();
        assert!(
            out == committed,
            "{} differs from `tridist cases --family all --count 150 --precision {prec} --exact --seed 1898041687` \
             (regenerate it as corpus/README.md says, and say why in the commit)",
            file.display()
        );
    }
}

/// The table's rows: (library, precision, the rest of the cells).
fn rows(md: &str) -> Vec<(String, String, Vec<String>)> {
    let start = md.find("## Triangle level").expect("the triangle section");
    let end = md.find("## Mesh level").unwrap_or(md.len());
    md[start..end]
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| library"))
        .map(|l| {
            let c: Vec<String> = l.trim_matches('|').split(" | ").map(|s| s.trim().to_string()).collect();
            (c[0].clone(), c[3].clone(), c[4..].to_vec())
        })
        .collect()
}

fn peers(corpus: &Path, out: &Path) -> String {
    let (c, o) = (corpus.display().to_string(), out.display().to_string());
    let (code, stdout, err) = tridist(&["peers", "--level", "triangle", "--corpus", &c, "--out", &o], "");
    assert_eq!(code, 0, "{stdout}{err}");
    std::fs::read_to_string(out).unwrap()
}

#[test]
fn peers_table_has_every_library_and_tridist_conforms() {
    let d = std::env::temp_dir().join(format!("tridist-peers-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let md = peers(&corpus(), &d.join("PEERS.md"));
    let rows = rows(&md);
    for prec in ["f32", "f64"] {
        let ours: Vec<_> = rows.iter().filter(|r| r.0 == "tridist" && r.1 == prec).collect();
        assert!(ours.len() >= 2, "{prec}: {rows:?}");
        for r in ours {
            // families, cases, worst E, p99 E, over 8, false zeros, misses, non-finite, bad input
            let c = &r.2;
            assert_eq!((c[0].as_str(), c[1].as_str()), ("11", "1650"), "{r:?}");
            let worst: f64 = c[2].parse().unwrap();
            assert!(worst <= 8.0, "{r:?}");
            assert_eq!(&c[4..8], ["0", "0", "0", "0"], "{r:?}");
            assert_eq!(c[8], "0 of 8", "{r:?}");
        }
    }
    for lib in Lib::JUDGED {
        for (prec, offered) in [("f32", lib.offers::<f32>()), ("f64", lib.offers::<f64>())] {
            let r: Vec<_> = rows.iter().filter(|r| r.0 == lib.name() && r.1 == prec).collect();
            assert_eq!(r.len(), usize::from(offered), "{} {prec}", lib.name());
            if let Some(r) = r.first() {
                assert_eq!(r.2[0].starts_with("not built"), !lib.available(), "{r:?}");
            }
        }
    }
}

/// The judge behind the table can fail: a copy of the corpus with one exact answer made wrong
/// (the squared distance of a random pair quadrupled) gives tridist's rows a worst E far
/// beyond 8, named at exactly that file and line.
#[test]
fn a_wrong_exact_answer_is_caught_at_its_line() {
    let d = std::env::temp_dir().join(format!("tridist-peers-planted-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    for f in ["tri_tri.f32.cases", "bad_input.cases"] {
        std::fs::copy(corpus().join(f), d.join(f)).unwrap();
    }
    let text = std::fs::read_to_string(corpus().join("tri_tri.f64.cases")).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let k = (0..lines.len())
        .filter(|&i| lines[i].starts_with("random/") && !lines[i].contains("exact=0/1"))
        .nth(5)
        .unwrap();
    let (body, exact) = lines[k].rsplit_once(" exact=").unwrap();
    let (num, den) = exact.split_once('/').unwrap();
    let num: rug::Integer = num.parse().unwrap();
    lines[k] = format!("{body} exact={}/{den}", num * 4u32);
    std::fs::write(d.join("tri_tri.f64.cases"), lines.join("\n") + "\n").unwrap();
    let md = peers(&d, &d.join("PEERS.md"));
    let at = format!("{}:{}", d.join("tri_tri.f64.cases").display(), k + 1);
    let ours: Vec<_> = rows(&md).into_iter().filter(|r| r.0 == "tridist" && r.1 == "f64").collect();
    assert!(!ours.is_empty());
    for r in &ours {
        assert!(r.2[2].parse::<f64>().unwrap() > 1e10, "{r:?}");
        assert_eq!(r.2[4], "1", "{r:?}");
    }
    let bullets: Vec<&str> =
        md.lines().filter(|l| l.starts_with("- **tridist") && l.contains(", f64)**")).collect();
    assert_eq!(bullets.len(), ours.len());
    for b in bullets {
        assert!(
            b.contains("worst E ") && b.contains(&format!(" at {at}; random: E ")),
            "{at} not named: {b}"
        );
    }
}

fn mesh_corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../corpus/mesh")
}

/// The mesh corpus's exact answers are mesh_exact's, recomputed for one case of each family
/// (all of them take about 20 s: `tridist mesh-cases` regenerates the corpus), and its part
/// is the carried mesh normalised as the generator writes it.
#[test]
fn the_mesh_corpus_answers_are_exact() {
    use tridist::Pose;
    use tridist_scenes::mesh::Mesh;
    let dir = mesh_corpus();
    let text = std::fs::read_to_string(dir.join("mesh.cases")).unwrap();
    let mut part = tridist_scenes::mesh::carried("mech-holes-shark.off").unwrap();
    tridist_scenes::protocol::normalise(&mut part);
    assert!(Mesh::load(&dir.join("part.off")).unwrap() == part, "part.off is not the normalised part");
    let mut seen: Vec<String> = Vec::new();
    let mut checked = 0;
    for l in text.lines().filter(|l| !l.starts_with('#') && !l.trim().is_empty()) {
        let f: Vec<&str> = l.split_whitespace().collect();
        let family = f[0].split('/').next().unwrap().to_string();
        if seen.contains(&family) {
            continue;
        }
        seen.push(family);
        let n: Vec<f64> = f[3..27].iter().map(|s| s.parse().unwrap()).collect();
        let pose = |v: &[f64]| Pose {
            translation: [v[0], v[1], v[2]],
            rotation: [[v[3], v[4], v[5]], [v[6], v[7], v[8]], [v[9], v[10], v[11]]],
        };
        let (a, b) = (Mesh::load(&dir.join(f[1])).unwrap(), Mesh::load(&dir.join(f[2])).unwrap());
        let x = tridist_scenes::mesh_exact::mesh_exact(&a, &pose(&n[..12]), &b, &pose(&n[12..])).unwrap();
        assert_eq!(f[27], format!("exact={}/{}", x.d2.numer(), x.d2.denom()), "{}", f[0]);
        if x.d2 != 0 {
            assert_eq!(f[28], format!("pair={},{}", x.tri_a, x.tri_b), "{}", f[0]);
        }
        if let Some(list) = f.iter().find_map(|x| x.strip_prefix("contacts=")) {
            let margin: f64 = f.iter().find_map(|x| x.strip_prefix("margin=")).unwrap().parse().unwrap();
            let got =
                tridist_scenes::mesh_exact::contacts_exact(&a, &pose(&n[..12]), &b, &pose(&n[12..]), margin)
                    .unwrap();
            let text: Vec<String> = got.iter().map(|(i, j)| format!("{i},{j}")).collect();
            assert_eq!(list, text.join(";"), "{}", f[0]);
        }
        checked += 1;
    }
    assert!(checked >= 7, "{seen:?}");
}

/// The corpus's cube and part scenes (not the Armadillo's, which names a file outside its
/// folder) in a folder of their own: the folder and the case lines.
fn mesh_subset(name: &str) -> (PathBuf, Vec<String>) {
    let d = std::env::temp_dir().join(format!("tridist-mesh-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    for f in ["cube.off", "part.off", "part_degenerate.off"] {
        std::fs::copy(mesh_corpus().join(f), d.join(f)).unwrap();
    }
    let text = std::fs::read_to_string(mesh_corpus().join("mesh.cases")).unwrap();
    let keep: Vec<String> = text
        .lines()
        .filter(|l| {
            ["coplanar/", "through/", "near_contact/", "degenerate/"].iter().any(|p| l.starts_with(p))
        })
        .map(String::from)
        .collect();
    assert!(keep.len() >= 15);
    std::fs::write(d.join("mesh.cases"), keep.join("\n") + "\n").unwrap();
    (d, keep)
}

/// PEERS.md's mesh table: a row per mesh contender and precision (built or "not built"),
/// tridist's with no failure and its worst E within the triangle target.
#[test]
fn mesh_table_has_every_library_and_tridist_conforms() {
    let (d, keep) = mesh_subset("table");
    let out = d.join("PEERS.md");
    let (c, o) = (d.display().to_string(), out.display().to_string());
    let (code, stdout, err) = tridist(&["peers", "--level", "mesh", "--corpus-mesh", &c, "--out", &o], "");
    assert_eq!(code, 0, "{stdout}{err}");
    let md = std::fs::read_to_string(&out).unwrap();
    assert!(!md.contains("## Triangle level"));
    let start = md.find("## Mesh level").expect("the mesh section");
    let rows: Vec<Vec<String>> = md[start..]
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| library"))
        .map(|l| l.trim_matches('|').split(" | ").map(|s| s.trim().to_string()).collect())
        .collect();
    let ours: Vec<_> = rows.iter().filter(|r| r[0] == "tridist").collect();
    assert!(ours.len() >= 2, "{rows:?}");
    for r in ours {
        assert_eq!(r[5], keep.len().to_string(), "{r:?}");
        assert!(r[6].parse::<f64>().unwrap() <= 8.0, "{r:?}");
        assert_eq!(&r[7..12], ["0", "0", "0", "0", "0"], "{r:?}");
        assert!(r[12].starts_with("0 / 0 (") && !r[12].starts_with("0 / 0 (0 "), "{r:?}");
    }
    assert_eq!(rows.iter().filter(|r| r[0] == "parry3d").count(), 2);
    for lib in tridist_scenes::mesh_peer::MeshLib::JUDGED {
        let r: Vec<_> = rows.iter().filter(|r| r[2] == lib.name()).collect();
        assert_eq!(r.len(), 1, "{}", lib.name());
        assert_eq!(r[0][4].starts_with("not built"), !lib.available(), "{:?}", r[0]);
    }
}

/// `tridist mesh-eval` answers a mesh case file and `tridist judge --mesh` judges it: tridist
/// passes; a planted wrong distance, a swapped triangle pair, a dropped contact, an extra
/// contact and a dropped answer are each caught (the first four named by their case-file line,
/// the last an error).
#[test]
fn mesh_answers_are_judged_and_faults_caught() {
    let (d, keep) = mesh_subset("judge");
    let cases = d.join("mesh.cases");
    let c = cases.display().to_string();
    let (code, answers, err) = tridist(&["mesh-eval", "--cases", &c, "--precision", "f64"], "");
    assert_eq!(code, 0, "{err}");
    let judge = |answers: &str| {
        let a = d.join("answers.txt");
        std::fs::write(&a, answers).unwrap();
        let a = a.display().to_string();
        tridist(&["judge", "--mesh", "--cases", &c, "--answers", &a, "--precision", "f64"], "")
    };
    let (code, out, err) = judge(&answers);
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("PASS"), "{out}");
    let lines: Vec<String> = answers.lines().map(String::from).collect();
    // a wrong distance: the squared distance of a positive case quadrupled
    let k = keep.iter().position(|l| l.starts_with("coplanar/") && !l.contains("exact=0/1")).unwrap();
    let mut wrong = lines.clone();
    let f: Vec<&str> = wrong[k].split(' ').collect();
    wrong[k] = format!("{} {:?} {} {}", f[0], f[1].parse::<f64>().unwrap() * 4.0, f[2], f[3]);
    let (code, out, _) = judge(&(wrong.join("\n") + "\n"));
    assert_eq!(code, 1, "{out}");
    assert!(out.contains(&format!(" lines {}\n", k + 1)), "{out}");
    // a swapped pair: the first mesh's triangle given as the second's
    let j = keep.iter().position(|l| l.starts_with("near_contact/")).unwrap();
    let mut swapped = lines.clone();
    let f: Vec<&str> = swapped[j].split(' ').collect();
    swapped[j] = format!("{} {} {} {}", f[0], f[1], f[3], f[2]);
    let (code, out, _) = judge(&(swapped.join("\n") + "\n"));
    assert_eq!(code, 1, "{out}");
    assert!(out.contains(&format!(" lines {}\n", j + 1)), "{out}");
    // a dropped contact and an extra one, in a case with contacts
    let c = lines.iter().position(|l| l.contains("contacts=") && l.matches(';').count() >= 3).unwrap();
    let (head, list) = lines[c].split_once(" contacts=").unwrap();
    let pairs: Vec<&str> = list.split(';').collect();
    for (what, list) in [("dropped", pairs[1..].join(";")), ("extra", format!("{list};999,999"))] {
        let mut planted = lines.clone();
        planted[c] = format!("{head} contacts={list}");
        let (code, out, err) = judge(&(planted.join("\n") + "\n"));
        // (an index beyond the mesh is no pair at all: an extra contact)
        assert_eq!(code, 1, "{what}: {out}{err}");
        assert!(out.contains(&format!(" lines {}\n", c + 1)), "{what}: {out}");
    }
    // a dropped answer
    let (code, _, err) = judge(&(lines[..lines.len() - 1].join("\n") + "\n"));
    assert_eq!(code, 3);
    assert!(err.contains("answers for"), "{err}");
}

/// Every adapter, as a user runs it: `tridist eval --peer NAME` answers a tiny case file (two
/// parallel triangles 2 apart: 4) in each precision the library offers, and says what is
/// missing otherwise (exit 3); `tridist mesh-eval --peer NAME` answers the mesh cases or says
/// the peer is not built.
#[test]
fn every_adapter_answers_a_tiny_case_file_or_says_why_not() {
    let case = "pair 0 0 0 1 0 0 0 1 0 0 0 2 1 0 2 0 1 2\n";
    for lib in Lib::JUDGED {
        for (prec, offered) in [("f32", lib.offers::<f32>()), ("f64", lib.offers::<f64>())] {
            let (code, out, err) = tridist(&["eval", "--peer", lib.name(), "--precision", prec], case);
            if lib.available() && offered {
                assert_eq!((code, out.as_str()), (0, "pair 4.0\n"), "{} {prec}: {err}", lib.name());
            } else {
                assert_eq!(code, 3, "{} {prec}: {out}", lib.name());
                assert!(err.contains("not built in") || err.contains("does not compute in"), "{err}");
            }
        }
    }
    let (d, keep) = mesh_subset("adapters");
    let c = d.join("mesh.cases").display().to_string();
    use tridist_scenes::mesh_peer::MeshLib;
    for (name, lib) in [
        ("fcl", MeshLib::Fcl),
        ("fcl-rss", MeshLib::FclRss),
        ("fcl-kios", MeshLib::FclKios),
        ("coal", MeshLib::Coal),
        ("coal-rss", MeshLib::CoalRss),
        ("coal-kios", MeshLib::CoalKios),
        ("trueform-aabb-f32", MeshLib::TrueFormAabbF32),
        ("trueform-aabb-f64", MeshLib::TrueFormAabbF64),
        ("trueform-obbrss-f64", MeshLib::TrueFormObbrssF64),
        ("trueform-obb-f64", MeshLib::TrueFormObbF64),
    ] {
        let (code, out, err) = tridist(&["mesh-eval", "--cases", &c, "--peer", name], "");
        if lib.available() {
            assert_eq!(code, 0, "{name}: {err}");
            assert_eq!(out.lines().count(), keep.len(), "{name}");
            assert!(
                out.lines().all(|l| l.split(' ').nth(1).is_some_and(|d| d.parse::<f64>().is_ok())),
                "{out}"
            );
        } else {
            assert_eq!(code, 3, "{name}: {out}");
            assert!(err.contains("not built in"), "{err}");
        }
    }
    let (code, _, err) = tridist(&["mesh-eval", "--cases", &c, "--peer", "nonsense"], "");
    assert_eq!(code, 3);
    assert!(err.contains("unknown mesh peer"), "{err}");
}
