//! Writes seed corpora for the fuzz targets from the family generators:
//! `cargo run -p tridist-scenes --example fuzz_seeds [-- <corpus dir>]` (default `fuzz/corpus`).
//! Pair targets get family-mode inputs (every family, 4 seeds); `raw_bits` the same pairs as raw
//! f64 and f32 bits; `parsers` the pairs as case lines and a small OFF mesh; `mesh` also 16
//! strings of 256 bytes from a fixed stream (whole meshes and poses).

use std::path::PathBuf;

use tridist_scenes::eval::case_line;
use tridist_scenes::families::generate;
use tridist_scenes::fuzzing::{mesh_seed_inputs, seed_inputs, TARGETS};
use tridist_scenes::Family;

fn main() -> std::io::Result<()> {
    let root = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fuzz/corpus"));
    let mut written = 0;
    let mut put = |target: &str, name: String, data: &[u8]| -> std::io::Result<()> {
        let dir = root.join(target);
        std::fs::create_dir_all(&dir)?;
        std::fs::write(dir.join(name), data)?;
        written += 1;
        Ok(())
    };
    let pairs = seed_inputs(4, &[0x40, 0x01]);
    for t in TARGETS.iter().filter(|t| !matches!(t.name, "raw_bits" | "parsers")) {
        for (i, v) in pairs.iter().enumerate() {
            put(t.name, format!("seed-family-{i}"), v)?;
        }
    }
    for (i, v) in mesh_seed_inputs(16).iter().enumerate() {
        put("mesh", format!("seed-mesh-{i}"), v)?;
    }
    for f in Family::ALL {
        for (i, c) in generate::<f64>(f, tridist_scenes::DEFAULT_SEED, 4).iter().enumerate() {
            let coords = c.a.iter().chain(c.b.iter()).flatten();
            let b64: Vec<u8> = coords.clone().flat_map(|x| x.to_le_bytes()).collect();
            let b32: Vec<u8> = coords.flat_map(|x| (*x as f32).to_le_bytes()).collect();
            put("raw_bits", format!("seed-{}-{i}-f64", f.name()), &b64)?;
            put("raw_bits", format!("seed-{}-{i}-f32", f.name()), &b32)?;
            put("parsers", format!("seed-{}-{i}", f.name()), case_line(c).as_bytes())?;
        }
    }
    let off = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n3 0 2 3\n3 1 2 3\n";
    put("parsers", "seed-tetrahedron.off".to_string(), off.as_bytes())?;
    println!("wrote {written} seed inputs under {}", root.display());
    Ok(())
}
