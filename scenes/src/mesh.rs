//! A loader for OFF triangle meshes, with clear errors on malformed files, and the meshes this
//! repository carries.

use std::path::{Path, PathBuf};

/// An indexed triangle mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles as vertex indices (validated: every index names a vertex).
    pub triangles: Vec<[u32; 3]>,
}

/// Why an OFF file could not be read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OffError {
    /// 1-based line number (0 when the problem is the file as a whole).
    pub line: usize,
    /// What is wrong.
    pub msg: String,
}

impl core::fmt::Display for OffError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        if self.line == 0 {
            write!(f, "OFF: {}", self.msg)
        } else {
            write!(f, "OFF line {}: {}", self.line, self.msg)
        }
    }
}
impl std::error::Error for OffError {}

fn err<T>(line: usize, msg: impl Into<String>) -> Result<T, OffError> {
    Err(OffError { line, msg: msg.into() })
}

/// Upper bound on counts, so a corrupt header cannot make us allocate without limit.
const MAX_COUNT: usize = 50_000_000;

impl Mesh {
    /// Parses OFF text. Comments (`#`) and blank lines are skipped; faces with more than three
    /// vertices are fan-triangulated; coordinates must be finite.
    ///
    /// # Errors
    /// A missing `OFF` header, bad or missing counts, a non-numeric or non-finite coordinate, a
    /// face with fewer than 3 vertices or an index out of range, or a truncated file.
    pub fn parse_off(text: &str) -> Result<Mesh, OffError> {
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.split('#').next().unwrap_or("").trim()))
            .filter(|(_, l)| !l.is_empty());
        let Some((ln, head)) = lines.next() else { return err(0, "empty file") };
        let Some(rest) = head.strip_prefix("OFF") else {
            return err(ln, format!("expected the header `OFF`, found {head:?}"));
        };
        let head_rest = rest.trim();
        let (ln, counts) = if head_rest.is_empty() {
            match lines.next() {
                Some(x) => x,
                None => return err(0, "missing the counts line `V F E`"),
            }
        } else {
            (ln, head_rest)
        };
        let nums: Vec<&str> = counts.split_whitespace().collect();
        if nums.len() < 2 {
            return err(ln, format!("expected `V F E` counts, found {counts:?}"));
        }
        let parse_count = |s: &str| -> Result<usize, OffError> {
            match s.parse::<usize>() {
                Ok(n) if n <= MAX_COUNT => Ok(n),
                Ok(n) => err(ln, format!("count {n} is larger than {MAX_COUNT}")),
                Err(_) => err(ln, format!("bad count {s:?}")),
            }
        };
        let nv = parse_count(nums[0])?;
        let nf = parse_count(nums[1])?;
        let mut vertices = Vec::with_capacity(nv.min(1 << 20));
        for k in 0..nv {
            let Some((ln, l)) = lines.next() else {
                return err(0, format!("truncated: {k} of {nv} vertices"));
            };
            let c: Vec<&str> = l.split_whitespace().collect();
            if c.len() < 3 {
                return err(ln, format!("a vertex needs 3 coordinates, found {l:?}"));
            }
            let mut v = [0.0; 3];
            for (slot, s) in v.iter_mut().zip(&c) {
                match s.parse::<f64>() {
                    Ok(x) if x.is_finite() => *slot = x,
                    _ => return err(ln, format!("bad coordinate {s:?}")),
                }
            }
            vertices.push(v);
        }
        let mut triangles = Vec::with_capacity(nf.min(1 << 20));
        for k in 0..nf {
            let Some((ln, l)) = lines.next() else {
                return err(0, format!("truncated: {k} of {nf} faces"));
            };
            let c: Vec<&str> = l.split_whitespace().collect();
            let n: usize = match c.first().map(|s| s.parse()) {
                Some(Ok(n)) => n,
                _ => return err(ln, format!("bad face {l:?}")),
            };
            if n < 3 || c.len() - 1 < n {
                return err(ln, format!("a face needs at least 3 vertex indices, found {l:?}"));
            }
            let mut idx = Vec::with_capacity(n);
            for s in &c[1..=n] {
                match s.parse::<u32>() {
                    Ok(i) if (i as usize) < nv => idx.push(i),
                    Ok(i) => return err(ln, format!("index {i} out of range (0..{nv})")),
                    Err(_) => return err(ln, format!("bad index {s:?}")),
                }
            }
            for j in 1..n - 1 {
                triangles.push([idx[0], idx[j], idx[j + 1]]);
            }
        }
        Ok(Mesh { vertices, triangles })
    }

    /// Reads an OFF file.
    ///
    /// # Errors
    /// I/O errors and [`Mesh::parse_off`]'s.
    pub fn load(path: &Path) -> Result<Mesh, Box<dyn std::error::Error + Send + Sync>> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(Mesh::parse_off(&text).map_err(|e| format!("{}: {e}", path.display()))?)
    }

    /// Triangle `i` as points.
    pub fn triangle(&self, i: usize) -> [[f64; 3]; 3] {
        self.triangles[i].map(|k| self.vertices[k as usize])
    }

    /// Pairs of triangles that share at least one vertex (the touching pairs of a mesh).
    pub fn neighbour_pairs(&self) -> Vec<(usize, usize)> {
        let mut by_vertex: Vec<Vec<usize>> = vec![Vec::new(); self.vertices.len()];
        for (t, tri) in self.triangles.iter().enumerate() {
            for &v in tri {
                by_vertex[v as usize].push(t);
            }
        }
        let mut out = Vec::new();
        for (t, tri) in self.triangles.iter().enumerate() {
            let mut seen: Vec<usize> =
                tri.iter().flat_map(|&v| by_vertex[v as usize].iter().copied()).filter(|&u| u > t).collect();
            seen.sort_unstable();
            seen.dedup();
            out.extend(seen.into_iter().map(|u| (t, u)));
        }
        out
    }

    /// The mesh with every triangle split into four at its edges' midpoints, `levels` times
    /// (a level multiplies the triangles by 4): the same surface, finer, for timing trees at
    /// sizes the carried meshes do not reach (the Armadillo's 52,000 triangles become 208,000
    /// and 832,000). An edge shared by two triangles gets one midpoint, so the result is as
    /// connected as the input; the corners keep their numbers.
    pub fn subdivided(&self, levels: u32) -> Mesh {
        let mut m = self.clone();
        for _ in 0..levels {
            let mut mid: std::collections::HashMap<(u32, u32), u32> = std::collections::HashMap::new();
            let mut tris = Vec::with_capacity(4 * m.triangles.len());
            for t in &m.triangles {
                let mut at = |a: u32, b: u32| {
                    *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                        let (p, q) = (m.vertices[a as usize], m.vertices[b as usize]);
                        m.vertices.push([0, 1, 2].map(|k| 0.5 * (p[k] + q[k])));
                        (m.vertices.len() - 1) as u32
                    })
                };
                let (ab, bc, ca) = (at(t[0], t[1]), at(t[1], t[2]), at(t[2], t[0]));
                tris.extend([[t[0], ab, ca], [ab, t[1], bc], [ca, bc, t[2]], [ab, bc, ca]]);
            }
            m.triangles = tris;
        }
        m
    }

    /// Largest absolute coordinate.
    pub fn extent(&self) -> f64 {
        self.vertices.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()))
    }
}

/// The repository's `data/meshes` folder.
pub fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/meshes")
}

/// Loads one of the carried meshes by file name (`armadillo.off`, `fandisk_large.off`,
/// `mech-holes-shark.off`).
///
/// # Errors
/// As [`Mesh::load`].
pub fn carried(name: &str) -> Result<Mesh, Box<dyn std::error::Error + Send + Sync>> {
    Mesh::load(&data_dir().join(name))
}

#[cfg(test)]
mod tests {

    /// Subdividing keeps a closed surface closed (Euler: V - E + F = 2, every edge in two
    /// triangles) and its area, and multiplies the triangles by 4 a level.
    #[test]
    fn subdivision_keeps_the_surface() {
        let tet =
            Mesh::parse_off("OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n3 0 2 3\n3 1 2 3\n")
                .unwrap();
        let area = |m: &Mesh| -> f64 {
            (0..m.triangles.len())
                .map(|i| {
                    let [a, b, c] = m.triangle(i);
                    let (u, v) = ([0, 1, 2].map(|k| b[k] - a[k]), [0, 1, 2].map(|k| c[k] - a[k]));
                    let x = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
                    0.5 * x.iter().map(|y| y * y).sum::<f64>().sqrt()
                })
                .sum()
        };
        for (levels, v, f) in [(0, 4, 4), (1, 10, 16), (2, 34, 64)] {
            let m = tet.subdivided(levels);
            assert_eq!((m.vertices.len(), m.triangles.len()), (v, f));
            let mut edges = std::collections::HashMap::new();
            for t in &m.triangles {
                for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                    *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
                }
            }
            assert!(edges.values().all(|&n| n == 2));
            assert_eq!(v as i64 - edges.len() as i64 + f as i64, 2);
            assert!((area(&m) - area(&tet)).abs() < 1e-12);
        }
    }

    use super::Mesh;

    #[test]
    fn malformed_off_files_are_errors_with_line_numbers() {
        let bad = [
            ("", "empty"),
            ("PLY\n", "header"),
            ("OFF\n", "counts"),
            ("OFF\n3 1 0\n0 0 0\n1 0 0\n", "truncated"),
            ("OFF\n3 1 0\n0 0 0\n1 0 x\n0 1 0\n3 0 1 2\n", "bad coordinate"),
            ("OFF\n3 1 0\n0 0 0\n1 0 inf\n0 1 0\n3 0 1 2\n", "bad coordinate"),
            ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", "out of range"),
            ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "at least 3"),
            // found by `cargo fuzz run parsers`: a huge vertex count in a face overflowed `n + 1`
            ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n18446744073709551615 0 1 2\n", "at least 3"),
            ("OFF\n99999999999 1 0\n", "count"),
        ];
        for (text, what) in bad {
            let e = Mesh::parse_off(text).expect_err(what);
            assert!(e.to_string().contains(what) || e.msg.contains(what), "{what}: {e}");
        }
        let ok = Mesh::parse_off("OFF\n# a quad\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n").unwrap();
        assert_eq!(ok.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(ok.neighbour_pairs(), vec![(0, 1)]);
    }

    #[test]
    fn carried_meshes_load() {
        let m = super::carried("armadillo.off").unwrap();
        assert_eq!(m.triangles.len(), 52_000);
        assert!(m.extent() > 0.0);
    }
}
