//! The kernels crate's layout, read from its source: the module graph has no cycle but the
//! documented one (the driver's escalation re-entering dispatch), ARCHITECTURE.md shows the
//! graph as it is, and no source file exceeds the size a reader can hold.
//!
//! `cargo test -p tridist --test layout -- --nocapture` prints the graph (the block that
//! ARCHITECTURE.md's "Modules" section holds between its markers).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The one strongly connected set of modules allowed: the driver's escalation steps rerun open
/// pairs through the dispatch, which instantiates the driver.
const ALLOWED_CYCLE: [&str; 3] = ["arch/dispatch", "drv", "drv/escalate"];

/// Lines per source file, tests included.
const MAX_LINES: usize = 1000;

fn src_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

fn rs_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> =
        std::fs::read_dir(dir).expect("read src").map(|e| e.expect("entry").path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rs_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// `algo/nodes.rs` -> `algo/nodes`, `mesh/mod.rs` -> `mesh`, `lib.rs` -> `lib`.
fn module_of(rel: &str) -> String {
    let m = rel.trim_end_matches(".rs");
    m.strip_suffix("/mod").unwrap_or(m).to_string()
}

/// The code of a file without comments and without test-only items (`#[cfg(test)]` items,
/// `mod tests` blocks): what the library itself imports. In macro bodies `super::` is
/// relative to the expansion, not to this file, so it is dropped there.
fn library_code(text: &str) -> String {
    let mut out = String::new();
    let lines: Vec<&str> = text.lines().collect();
    let mut i = 0;
    let mut macro_depth = 0i32;
    while i < lines.len() {
        if macro_depth > 0 || lines[i].trim_start().starts_with("macro_rules!") {
            let code = lines[i].split("//").next().unwrap_or("");
            macro_depth += code.matches('{').count() as i32 - code.matches('}').count() as i32;
            out.push_str(&code.replace("super::", ""));
            out.push('\n');
            i += 1;
            continue;
        }
        let t = lines[i].trim_start();
        if t.starts_with("//") {
            i += 1;
            continue;
        }
        if t.starts_with("#[cfg(test)]") {
            // skip the next item: to its `;` if it has no body, else to its balanced braces
            let (mut depth, mut opened) = (0i32, false);
            i += 1;
            while i < lines.len() {
                let l = lines[i].split("//").next().unwrap_or("");
                for c in l.chars() {
                    match c {
                        '{' => {
                            depth += 1;
                            opened = true
                        }
                        '}' => depth -= 1,
                        _ => {}
                    }
                }
                let ends = (opened && depth == 0) || (!opened && l.trim_end().ends_with(';'));
                i += 1;
                if ends {
                    break;
                }
            }
            continue;
        }
        let code = lines[i].split("//").next().unwrap_or("");
        out.push_str(code);
        out.push('\n');
        i += 1;
    }
    out
}

/// Identifiers and `::` of `code`, as tokens.
fn tokens(code: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let cs: Vec<char> = code.chars().collect();
    let mut i = 0;
    while i < cs.len() {
        let c = cs[i];
        if c.is_alphanumeric() || c == '_' {
            cur.push(c);
        } else {
            if !cur.is_empty() {
                out.push(std::mem::take(&mut cur));
            }
            if c == ':' && cs.get(i + 1) == Some(&':') {
                out.push("::".into());
                i += 1;
            } else if "{},;*".contains(c) {
                out.push(c.to_string());
            } else if !c.is_whitespace() {
                out.push(" ".into());
            }
        }
        i += 1;
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

struct Crate {
    modules: BTreeSet<String>,
    /// Names the crate root re-exports, and the module each comes from.
    root: BTreeMap<String, String>,
}

impl Crate {
    /// The module a path names (segments after `crate::`, or resolved from a module): the
    /// longest prefix that is a module, or, for one segment, a root re-export.
    fn resolve(&self, segs: &[String]) -> Option<String> {
        for n in (1..=segs.len()).rev() {
            let m = segs[..n].join("/");
            if self.modules.contains(&m) {
                return Some(m);
            }
        }
        segs.first().and_then(|s| self.root.get(s).cloned())
    }
}

/// Every path of `code` as segments after its anchor (`crate`, `super`, `self` or a child
/// module of `here`), with `use` groups expanded: `use crate::{a::B, C}` gives `a::B` and `C`.
fn paths(code: &str) -> Vec<(String, Vec<String>)> {
    let t = tokens(code);
    let mut out = Vec::new();
    let mut i = 0;
    while i < t.len() {
        let anchor = t[i].as_str();
        let is_path_start = (i == 0 || t[i - 1] != "::") && t.get(i + 1).is_some_and(|x| x == "::");
        if !is_path_start {
            i += 1;
            continue;
        }
        let mut segs = vec![];
        let mut j = i + 2;
        while j < t.len() {
            if t[j] == "{" {
                // a use group: each member from this prefix
                let mut depth = 1;
                let mut member: Vec<String> = vec![];
                j += 1;
                while j < t.len() && depth > 0 {
                    match t[j].as_str() {
                        "{" => depth += 1,
                        "}" => depth -= 1,
                        "," if depth == 1 => {
                            let mut s = segs.clone();
                            s.extend(member.drain(..).filter(|x| x != "::"));
                            out.push((anchor.to_string(), s));
                        }
                        x if depth == 1 => member.push(x.to_string()),
                        _ => {}
                    }
                    j += 1;
                }
                let mut s = segs.clone();
                s.extend(member.drain(..).filter(|x| x != "::"));
                out.push((anchor.to_string(), s));
                segs.clear();
                break;
            }
            if t[j] == "::" {
                j += 1;
                continue;
            }
            if t[j].chars().all(|c| c.is_alphanumeric() || c == '_') {
                segs.push(t[j].clone());
                j += 1;
                if t.get(j).is_some_and(|x| x == "::") {
                    continue;
                }
            }
            break;
        }
        if !segs.is_empty() {
            out.push((anchor.to_string(), segs));
        }
        i = j.max(i + 1);
    }
    out
}

/// Each module and the modules it imports.
type Graph = BTreeMap<String, BTreeSet<String>>;

/// The graph, and every source file with its line count.
fn graph() -> (Graph, Vec<(String, usize)>) {
    let dir = src_dir();
    let mut files = vec![];
    rs_files(&dir, &mut files);
    let rel = |p: &Path| p.strip_prefix(&dir).expect("under src").to_string_lossy().replace('\\', "/");
    let mut texts = BTreeMap::new();
    let mut sizes = vec![];
    for p in &files {
        let text = std::fs::read_to_string(p).expect("read a source file");
        sizes.push((rel(p), text.lines().count()));
        // the unit tests' own files are not the library's modules
        if rel(p).ends_with("tests.rs") {
            continue;
        }
        texts.insert(module_of(&rel(p)), text);
    }
    let modules: BTreeSet<String> = texts.keys().cloned().collect();
    // the root's re-exports: `pub use m::{A, B}` and `pub use m::*` (the module's pub items)
    let mut root = BTreeMap::new();
    for (anchor, segs) in paths(&library_code(&texts["lib"])) {
        if let Some((name, path)) = segs.split_last() {
            let mut full = vec![anchor.clone()];
            full.extend(path.iter().cloned());
            if modules.contains(&full.join("/")) {
                root.insert(name.clone(), full.join("/"));
            }
        }
    }
    for line in texts["lib"].lines() {
        if let Some(m) = line.strip_prefix("pub use ").and_then(|l| l.strip_suffix("::*;")) {
            for l in texts[m].lines() {
                let l = l.trim_start();
                for kw in ["pub fn ", "pub struct ", "pub enum ", "pub type ", "pub trait ", "pub const "] {
                    if let Some(rest) = l.strip_prefix(kw) {
                        let name: String =
                            rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
                        root.insert(name, m.to_string());
                    }
                }
            }
        }
    }
    let krate = Crate { modules: modules.clone(), root };
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (m, text) in &texts {
        let set = edges.entry(m.clone()).or_default();
        let parent: Vec<String> = m.split('/').map(String::from).collect();
        let parent = &parent[..parent.len() - 1];
        for (anchor, segs) in paths(&library_code(text)) {
            let target = match anchor.as_str() {
                "crate" => krate.resolve(&segs),
                "super" => {
                    let mut full = parent.to_vec();
                    full.extend(segs.iter().cloned());
                    krate
                        .resolve(&full)
                        .or_else(|| Some(if parent.is_empty() { "lib".into() } else { parent.join("/") }))
                }
                "self" | "Self" => None,
                child => {
                    // a child module of a `mod.rs`/`lib.rs` module, named without `self::`
                    let base =
                        if m == "lib" { vec![] } else { m.split('/').map(String::from).collect::<Vec<_>>() };
                    let mut full = base;
                    full.push(child.to_string());
                    full.extend(segs.iter().cloned());
                    let own = if m == "lib" { child.to_string() } else { format!("{m}/{child}") };
                    krate.modules.contains(&own).then(|| krate.resolve(&full)).flatten()
                }
            };
            if let Some(t) = target {
                if &t != m && t != "lib" {
                    set.insert(t);
                }
            }
        }
    }
    (edges, sizes)
}

/// Strongly connected sets of more than one module (Tarjan's algorithm).
fn cycles(edges: &BTreeMap<String, BTreeSet<String>>) -> Vec<BTreeSet<String>> {
    struct St<'a> {
        e: &'a BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on: BTreeSet<&'a str>,
        out: Vec<BTreeSet<String>>,
    }
    fn visit<'a>(s: &mut St<'a>, v: &'a str) {
        let i = s.index.len();
        s.index.insert(v, i);
        s.low.insert(v, i);
        s.stack.push(v);
        s.on.insert(v);
        for w in s.e.get(v).into_iter().flatten() {
            let w = w.as_str();
            if !s.index.contains_key(w) {
                visit(s, w);
                let l = s.low[w].min(s.low[v]);
                s.low.insert(v, l);
            } else if s.on.contains(w) {
                let l = s.index[w].min(s.low[v]);
                s.low.insert(v, l);
            }
        }
        if s.low[v] == s.index[v] {
            let mut set = BTreeSet::new();
            while let Some(w) = s.stack.pop() {
                s.on.remove(w);
                set.insert(w.to_string());
                if w == v {
                    break;
                }
            }
            if set.len() > 1 {
                s.out.push(set);
            }
        }
    }
    let mut s = St {
        e: edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: vec![],
        on: BTreeSet::new(),
        out: vec![],
    };
    for v in edges.keys() {
        if !s.index.contains_key(v.as_str()) {
            visit(&mut s, v);
        }
    }
    s.out
}

/// The graph as ARCHITECTURE.md shows it: a line per module, what it imports.
fn render(edges: &BTreeMap<String, BTreeSet<String>>) -> String {
    let width = edges.keys().map(|k| k.len()).max().unwrap_or(0);
    let mut s = String::new();
    for (m, to) in edges {
        let to: Vec<&str> = to.iter().map(String::as_str).collect();
        let to = if to.is_empty() { "(nothing of the crate)".to_string() } else { to.join(", ") };
        s.push_str(&format!("{m:width$} -> {to}\n"));
    }
    s
}

#[test]
fn the_module_graph_has_no_cycle_but_the_escalation_one() {
    let (edges, _) = graph();
    print!("{}", render(&edges));
    let allowed: BTreeSet<String> = ALLOWED_CYCLE.iter().map(|s| s.to_string()).collect();
    for c in cycles(&edges) {
        assert_eq!(
            c, allowed,
            "a cycle in the kernels crate's module graph: {c:?} (only {allowed:?} may form one)"
        );
    }
}

#[test]
fn architecture_md_shows_the_module_graph_as_it_is() {
    let (edges, _) = graph();
    let doc = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../ARCHITECTURE.md"))
        .expect("ARCHITECTURE.md");
    let (begin, end) = ("<!-- modules:begin -->\n```text\n", "```\n<!-- modules:end -->");
    let a = doc.find(begin).expect("ARCHITECTURE.md has the modules markers") + begin.len();
    let b = doc[a..].find(end).expect("the end marker") + a;
    let want = render(&edges);
    assert!(doc[a..b] == want, "ARCHITECTURE.md's module graph is stale; the graph now:\n{want}");
}

#[test]
fn no_source_file_is_longer_than_a_reader_can_hold() {
    let (_, sizes) = graph();
    let mut tests = vec![];
    rs_files(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests"), &mut tests);
    let long: Vec<_> =
        sizes
            .into_iter()
            .chain(tests.iter().map(|p| {
                (p.display().to_string(), std::fs::read_to_string(p).map_or(0, |t| t.lines().count()))
            }))
            .filter(|(_, n)| *n > MAX_LINES)
            .collect();
    assert!(long.is_empty(), "files over {MAX_LINES} lines: {long:?}");
}

/// The checker sees what it should: a planted import from a low module to a high one closes a
/// cycle it reports, and a test-only import does not count.
#[test]
fn the_checker_finds_a_planted_cycle() {
    let mut edges = BTreeMap::new();
    let code = "use crate::engine::Engine;\n#[cfg(test)]\nuse crate::mesh::Mesh;\n";
    let found: Vec<_> =
        paths(&library_code(code)).into_iter().map(|(a, s)| format!("{a}::{}", s.join("::"))).collect();
    assert_eq!(found, ["crate::engine::Engine"]);
    edges.insert("real".to_string(), BTreeSet::from(["engine".to_string()]));
    edges.insert("engine".to_string(), BTreeSet::from(["real".to_string()]));
    assert_eq!(cycles(&edges), vec![BTreeSet::from(["engine".to_string(), "real".to_string()])]);
}
