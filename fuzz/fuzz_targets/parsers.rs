//! The untrusted-text readers: OFF meshes and case lines. Never panic; what parses is valid.
#![no_main]
use libfuzzer_sys::fuzz_target;
use tridist_scenes::eval::parse_case_line;
use tridist_scenes::mesh::Mesh;

fuzz_target!(|text: &str| {
    if let Ok(m) = Mesh::parse_off(text) {
        for t in &m.triangles {
            assert!(t.iter().all(|&i| (i as usize) < m.vertices.len()));
        }
        if !m.triangles.is_empty() {
            let tris: Vec<[[f64; 3]; 3]> = (0..m.triangles.len()).map(|i| m.triangle(i)).collect();
            let _ = tridist::TriangleBatch::from_slice(&tris);
        }
    }
    for line in text.lines() {
        let _ = parse_case_line::<f32>(line);
        let _ = parse_case_line::<f64>(line);
    }
});
