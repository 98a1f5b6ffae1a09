//! No module of the crate imports one that imports it back (issue 15).
//!
//! Reads `src/**/*.rs` as text: each file is a module (`foo/mod.rs` is
//! `foo`), and every `crate::`, `super::` and `self::` path in its code
//! (comments left out; `use` trees such as `crate::{a, b::C}` expanded)
//! names the longest module it starts with. The crate root (`lib.rs`,
//! which re-exports everything) is left out of the graph. A cycle is a
//! strongly connected component of more than one module, reported with its
//! edges.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// Module path (`scene::parser`) → source text, for every file under `dir`.
fn modules(dir: &Path, prefix: &[String], out: &mut BTreeMap<String, String>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        if path.is_dir() {
            let mut p = prefix.to_vec();
            p.push(name);
            modules(&path, &p, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let mut p = prefix.to_vec();
            if name != "mod" && name != "lib" {
                p.push(name);
            }
            out.insert(p.join("::"), std::fs::read_to_string(&path).unwrap());
        }
    }
}

/// The text without `//` comments (doc links are not imports).
fn code(text: &str) -> String {
    text.lines()
        .map(|l| l.find("//").map_or(l, |i| &l[..i]))
        .collect::<Vec<_>>()
        .join("\n")
}

/// Every path that starts with `crate::`, `super::` or `self::` in `code`,
/// made absolute from `module`; a `{..}` group gives one path per item.
fn paths(module: &str, code: &str) -> Vec<String> {
    let mut out = Vec::new();
    let bytes = code.as_bytes();
    let is_ident = |b: u8| b.is_ascii_alphanumeric() || b == b'_';
    for base in ["crate::", "super::", "self::"] {
        let mut from = 0;
        while let Some(found) = code[from..].find(base) {
            let start = from + found;
            from = start + base.len();
            if start > 0 && (is_ident(bytes[start - 1]) || bytes[start - 1] == b':') {
                continue; // `foo::self::`, `my_crate::`
            }
            let mut prefix: Vec<&str> = match base {
                "crate::" => vec![],
                "super::" => module.split("::").filter(|s| !s.is_empty()).collect(),
                _ => module.split("::").filter(|s| !s.is_empty()).collect(),
            };
            if base == "super::" {
                prefix.pop();
            }
            let mut end = from;
            while end < bytes.len() && (is_ident(bytes[end]) || bytes[end] == b':') {
                end += 1;
            }
            let path = code[from..end].trim_end_matches(':');
            let mut full: Vec<&str> = prefix;
            full.extend(path.split("::").filter(|s| !s.is_empty()));
            if end < bytes.len() && bytes[end] == b'{' {
                // One level of a use tree: each item's leading segment.
                let close = code[end..].find('}').map_or(bytes.len(), |i| end + i);
                for item in code[end + 1..close].split(',') {
                    let head = item.trim().split("::").next().unwrap_or("");
                    let head = head.split_whitespace().next().unwrap_or("");
                    if !head.is_empty() && head != "self" && head.bytes().all(is_ident) {
                        let mut p = full.clone();
                        p.push(head);
                        out.push(p.join("::"));
                    }
                }
            }
            out.push(full.join("::"));
        }
    }
    out
}

/// The longest module of `known` that `path` starts with.
fn module_of<'k>(path: &str, known: &'k BTreeMap<String, String>) -> Option<&'k str> {
    let parts: Vec<&str> = path.split("::").collect();
    (1..=parts.len())
        .rev()
        .find_map(|n| known.get_key_value(&parts[..n].join("::")))
        .map(|(k, _)| k.as_str())
}

fn import_graph() -> BTreeMap<String, BTreeSet<String>> {
    let mut known = BTreeMap::new();
    modules(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &[],
        &mut known,
    );
    let mut graph = BTreeMap::new();
    for (module, text) in &known {
        if module.is_empty() {
            continue;
        }
        let targets: BTreeSet<String> = paths(module, &code(text))
            .iter()
            .filter_map(|p| module_of(p, &known))
            .filter(|t| !t.is_empty() && t != module)
            .map(str::to_owned)
            .collect();
        graph.insert(module.clone(), targets);
    }
    graph
}

/// Strongly connected components of more than one module (Tarjan).
fn cycles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct State<'g> {
        graph: &'g BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'g str, usize>,
        low: BTreeMap<&'g str, usize>,
        stack: Vec<&'g str>,
        found: Vec<Vec<String>>,
    }
    fn visit<'g>(s: &mut State<'g>, v: &'g str) {
        let i = s.index.len();
        s.index.insert(v, i);
        s.low.insert(v, i);
        s.stack.push(v);
        for w in &s.graph[v] {
            let w = w.as_str();
            if !s.index.contains_key(w) {
                visit(s, w);
                let lw = s.low[w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(lw);
            } else if s.stack.contains(&w) {
                let iw = s.index[w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(iw);
            }
        }
        if s.low[v] == s.index[v] {
            let mut component = Vec::new();
            loop {
                let w = s.stack.pop().unwrap();
                component.push(w.to_owned());
                if w == v {
                    break;
                }
            }
            if component.len() > 1 {
                component.sort();
                s.found.push(component);
            }
        }
    }
    let mut s = State {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        found: Vec::new(),
    };
    for v in graph.keys() {
        if !s.index.contains_key(v.as_str()) {
            visit(&mut s, v);
        }
    }
    s.found
}

/// Cycles known and left for now, each sorted (none: the walk and the
/// skip pyramid read a field through `traversal::WalkGrid` and
/// `skip::SampleGrid`, which `heightfield` implements).
const KNOWN: &[&[&str]] = &[];

#[test]
fn no_module_imports_one_that_imports_it_back() {
    let graph = import_graph();
    let mut report = String::new();
    for component in cycles(&graph) {
        if KNOWN.iter().any(|k| *k == component) {
            continue;
        }
        report += &format!("cycle among {}:\n", component.join(", "));
        for m in &component {
            let back: Vec<&str> = graph[m]
                .iter()
                .filter(|t| component.contains(t))
                .map(String::as_str)
                .collect();
            report += &format!("  {m} -> {}\n", back.join(", "));
        }
    }
    assert!(report.is_empty(), "{report}");
}

/// The graph is read as meant: known imports are edges, and a cycle made
/// for the test is found.
#[test]
fn the_import_graph_sees_use_trees_and_finds_a_planted_cycle() {
    let graph = import_graph();
    assert!(graph["render"].contains("shading"), "{:?}", graph["render"]);
    assert!(graph["scene::lexer"].contains("scene::error"));
    assert!(graph["scene::parser::object"].contains("scene::parser::pigment"));
    let mut planted = graph.clone();
    planted
        .get_mut("shading")
        .unwrap()
        .insert("render".to_owned());
    assert!(cycles(&planted).contains(&vec!["render".to_owned(), "shading".to_owned()]));
}
