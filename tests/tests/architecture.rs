//! The shape of the source tree, checked: no crate's modules import each other in a
//! circle, no source file grows past [`MAX_LINES`], and the product speaks of
//! techniques, files and commits, never of tracker numbers.
//!
//! The import graph is read from the `crate::`, `super::` and `self::` paths of each
//! file (`use` declarations and paths in code alike), outside its `#[cfg(test)]`
//! module: a unit test may build its inputs with a module above the one it tests.
//! A path names the longest module prefix it starts with; a module's own children and
//! parents count like any other module.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Longest source file allowed in the product's crates (runner/src, shared/src,
/// shaders-rs/src, runner/examples); a `tests.rs` that is a list of cases may be
/// longer.
const MAX_LINES: usize = 600;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Every `.rs` file under `dir`, recursively.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap_or_else(|e| panic!("{}: {e}", d.display())) {
            let path = entry.expect("directory entry").path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

type Module = Vec<String>;

/// The module path of `file` in the crate rooted at `src` (`lib.rs`, `main.rs` and
/// `mod.rs` name their folder).
fn module_of(src: &Path, file: &Path) -> Module {
    let rel = file.strip_prefix(src).expect("file under its crate");
    let mut parts: Module = rel
        .with_extension("")
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if matches!(
        parts.last().map(String::as_str),
        Some("lib" | "main" | "mod")
    ) {
        parts.pop();
    }
    parts
}

/// `text` without its comments and without its `#[cfg(test)] mod tests { … }`.
fn product_code(text: &str) -> String {
    let text = match text.find("#[cfg(test)]\nmod tests {") {
        Some(at) => &text[..at],
        None => text,
    };
    text.lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The paths `text` names from `crate::`, `super::` or `self::`, each as the
/// segments after that word (groups `a::{b, c::d}` expanded one level), with the
/// word.
fn named_paths(text: &str) -> Vec<(String, Vec<String>)> {
    let mut out = Vec::new();
    let bytes = text.as_bytes();
    for word in ["crate::", "super::", "self::"] {
        let mut from = 0;
        while let Some(at) = text[from..].find(word) {
            let start = from + at;
            from = start + word.len();
            let before = start.checked_sub(1).map(|i| bytes[i] as char);
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
                continue;
            }
            let rest = &text[from..];
            let end = rest
                .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':' || c == '{'))
                .unwrap_or(rest.len());
            let path = &rest[..end];
            let base = word.trim_end_matches("::").to_owned();
            match path.find("::{") {
                Some(brace) => {
                    let prefix: Vec<String> =
                        path[..brace].split("::").map(str::to_owned).collect();
                    let group_end = rest[brace..].find('}').map_or(rest.len(), |e| brace + e);
                    for item in rest[brace + 3..group_end].split(',') {
                        let item = item.split(" as ").next().unwrap_or("").trim();
                        if item.is_empty() || item == "self" || item.contains('{') {
                            continue;
                        }
                        let mut p = prefix.clone();
                        p.extend(item.split("::").map(|s| s.trim().to_owned()));
                        out.push((base.clone(), p));
                    }
                    out.push((base.clone(), prefix));
                }
                None => out.push((
                    base.clone(),
                    path.trim_end_matches([':', '{'])
                        .split("::")
                        .map(str::to_owned)
                        .collect(),
                )),
            }
        }
    }
    out
}

/// The import graph of the crate whose sources are under `src`: each module and
/// the modules its product code names.
fn import_graph(src: &Path) -> BTreeMap<Module, BTreeSet<Module>> {
    let files = rust_files(src);
    let modules: BTreeSet<Module> = files.iter().map(|f| module_of(src, f)).collect();
    let resolve = |path: &[String]| {
        (1..=path.len())
            .rev()
            .map(|n| path[..n].to_vec())
            .find(|m| modules.contains(m))
    };
    let mut graph = BTreeMap::new();
    for file in &files {
        let this = module_of(src, file);
        let text = std::fs::read_to_string(file).expect("read source");
        let mut edges = BTreeSet::new();
        for (base, rest) in named_paths(&product_code(&text)) {
            let mut path = match base.as_str() {
                "crate" => Vec::new(),
                "super" => this[..this.len().saturating_sub(1)].to_vec(),
                _ => this.clone(),
            };
            path.extend(rest);
            if let Some(m) = resolve(&path).filter(|m| *m != this) {
                edges.insert(m);
            }
        }
        graph.insert(this, edges);
    }
    graph
}

/// The circles of `graph` (strongly connected parts of more than one module),
/// each with its edges inside it.
fn circles(graph: &BTreeMap<Module, BTreeSet<Module>>) -> Vec<Vec<String>> {
    // Modules that reach each other both ways share a circle.
    let reach = |from: &Module| {
        let mut seen = BTreeSet::new();
        let mut stack = vec![from.clone()];
        while let Some(m) = stack.pop() {
            for n in graph.get(&m).into_iter().flatten() {
                if seen.insert(n.clone()) {
                    stack.push(n.clone());
                }
            }
        }
        seen
    };
    let reaches: BTreeMap<&Module, BTreeSet<Module>> =
        graph.keys().map(|m| (m, reach(m))).collect();
    let mut done = BTreeSet::new();
    let mut out = Vec::new();
    for m in graph.keys() {
        if done.contains(m) || !reaches[m].contains(m) {
            continue;
        }
        let part: BTreeSet<&Module> = graph
            .keys()
            .filter(|n| reaches[m].contains(*n) && reaches[*n].contains(m))
            .collect();
        let mut edges = Vec::new();
        for a in &part {
            for b in &graph[*a] {
                if part.contains(b) {
                    edges.push(format!("{} -> {}", a.join("::"), b.join("::")));
                }
            }
            done.insert((*a).clone());
        }
        out.push(edges);
    }
    out
}

#[test]
fn no_crate_s_modules_import_each_other_in_a_circle() {
    let mut found = Vec::new();
    for src in ["shared/src", "shaders-rs/src", "runner/src"] {
        let graph = import_graph(&root().join(src));
        let edges: usize = graph.values().map(BTreeSet::len).sum();
        println!("{src}: {} modules, {edges} imports", graph.len());
        for circle in circles(&graph) {
            found.push(format!("{src}: {}", circle.join(", ")));
        }
    }
    assert!(
        found.is_empty(),
        "modules in a circle:\n{}",
        found.join("\n")
    );
}

/// The reader's check that the graph is read at all: a planted circle is found.
#[test]
fn a_circle_is_found() {
    let module = |s: &str| s.split("::").map(str::to_owned).collect::<Module>();
    let text = "use crate::b::thing;\nfn f() { super::c::g(); }\n#[cfg(test)]\nmod tests {\n use crate::d::x;\n}\n";
    let paths: Vec<Module> = named_paths(&product_code(text))
        .into_iter()
        .map(|(_, p)| p)
        .collect();
    assert_eq!(paths, [module("b::thing"), module("c::g")]);
    let graph: BTreeMap<Module, BTreeSet<Module>> = [
        (module("a"), [module("b")].into()),
        (module("b"), [module("c")].into()),
        (module("c"), [module("a")].into()),
        (module("d"), [module("a")].into()),
    ]
    .into();
    assert_eq!(circles(&graph), [vec!["a -> b", "b -> c", "c -> a"]]);
}

#[test]
fn no_source_file_is_over_the_limit() {
    let mut long = Vec::new();
    for dir in [
        "shared/src",
        "shaders-rs/src",
        "runner/src",
        "runner/examples",
    ] {
        for file in rust_files(&root().join(dir)) {
            let lines = std::fs::read_to_string(&file)
                .expect("read")
                .lines()
                .count();
            let cases = file.file_name().is_some_and(|n| n == "tests.rs");
            if lines > MAX_LINES && !cases {
                let name = file
                    .strip_prefix(root())
                    .unwrap_or(&file)
                    .display()
                    .to_string();
                long.push(format!("{name}: {lines} lines"));
            }
        }
    }
    assert!(
        long.is_empty(),
        "over {MAX_LINES} lines:\n{}",
        long.join("\n")
    );
}

/// Files the product is read through: sources, manifests, scripts and docs.
fn product_files() -> Vec<PathBuf> {
    let mut out = vec![root().join("README.md"), root().join(".ci/run")];
    for dir in ["shared", "shaders-rs", "runner", "tests", "docs"] {
        let mut stack = vec![root().join(dir)];
        while let Some(d) = stack.pop() {
            for entry in std::fs::read_dir(&d).expect("read dir") {
                let path = entry.expect("entry").path();
                if path.is_dir() {
                    stack.push(path);
                } else if path
                    .extension()
                    .is_some_and(|e| ["rs", "md", "toml", "sh"].iter().any(|x| e == *x))
                {
                    out.push(path);
                }
            }
        }
    }
    out
}

/// A tracker's word followed by a number (with an `s`, a space, `#` or `-` between):
/// numbers that mean nothing to a reader.
fn tracker_numbers(text: &str) -> Vec<String> {
    let lower = text.to_lowercase();
    let mut out = Vec::new();
    for (at, _) in lower.match_indices("issue") {
        let rest = lower[at + 5..]
            .trim_start_matches('s')
            .trim_start_matches([' ', '#', '-']);
        if rest.starts_with(|c: char| c.is_ascii_digit()) {
            let end = (at + 20).min(text.len());
            out.push(text[at..text.floor_char_boundary(end)].to_owned());
        }
    }
    out
}

#[test]
fn the_product_cites_no_tracker_numbers() {
    assert_eq!(
        tracker_numbers(&"see T 16, Ts #19 and the T-3 tT".replace('T', "issue")),
        ["T 16, Ts #19", "Ts #19 and the i", "T-3 tissue"].map(|e| e.replace('T', "issue"))
    );
    let mut found = Vec::new();
    for file in product_files() {
        let Ok(text) = std::fs::read_to_string(&file) else {
            continue;
        };
        let name = file
            .strip_prefix(root())
            .unwrap_or(&file)
            .display()
            .to_string();
        if name.ends_with("architecture.rs") {
            continue;
        }
        for hit in tracker_numbers(&text) {
            found.push(format!("{name}: {hit:?}"));
        }
    }
    assert!(found.is_empty(), "tracker numbers:\n{}", found.join("\n"));
}
