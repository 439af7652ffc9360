//! The crate's imports point down its layering (ARCHITECTURE.md, "Invariants", layers; issue 41): every
//! `use crate::…`/`use super::…` and every `crate::…` path in the code of `src/**/*.rs` (comments
//! and `#[cfg(test)]` modules left out) names a file of the same or a lower layer; `crate::Item`
//! paths are followed through the crate root's re-exports. The layer table is the one of
//! ARCHITECTURE.md. And no files import each other, directly or round a circle, but the ones
//! listed with what breaks them. A parent's re-exports of its children (`pub use child::X;`,
//! its export map) are not imports; a child's `use super::X` is.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// Layers from the bottom, by path prefix under `src/` (the longest prefix wins).
const LAYERS: &[(&str, u32)] = &[
    // Vocabulary that imports nothing of the crate.
    ("geometry/", 0),
    ("solver/", 0),
    ("spatial.rs", 0),
    ("joints/rows.rs", 0),
    ("build_profile.rs", 0),
    // The description (builder data, materials, force laws) and validation's errors.
    ("scene/", 1),
    // The joint kinds: each checks its own parameters with validation's `Checker`.
    ("joints/", 2),
    // Validation, the tree search and the contact rules of a validated scene ask the joint
    // kinds.
    ("scene/validate/", 3),
    ("scene/validate/error.rs", 1),
    ("scene/topology.rs", 3),
    ("scene/contact_rules.rs", 3),
    ("dynamics/", 4),
    ("contact/", 5),
    ("dae/", 6),
    ("model.rs", 7),
    ("results/", 8),
    ("simulation.rs", 9),
    ("simulation/", 9),
    ("sweep/", 10),
    ("bench.rs", 10),
    ("lib.rs", 11),
];

fn layer(file: &str) -> u32 {
    LAYERS
        .iter()
        .filter(|(p, _)| file.starts_with(p))
        .max_by_key(|(p, _)| p.len())
        .map(|(_, l)| *l)
        .unwrap_or_else(|| panic!("{file}: no layer in LAYERS"))
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The module path of a file (`dynamics/loops.rs` → `[dynamics, loops]`).
fn module_of(file: &str) -> Vec<String> {
    let mut m: Vec<String> = file
        .trim_end_matches(".rs")
        .split('/')
        .map(String::from)
        .collect();
    if matches!(m.last().map(String::as_str), Some("mod" | "lib")) {
        m.pop();
    }
    m
}

/// The code of a source file: comments and a trailing `#[cfg(test)]` module (its attributes
/// and comments between them allowed) removed.
fn code_of(src: &str) -> String {
    let lines: Vec<&str> = src.lines().collect();
    let end = (0..lines.len())
        .find(|&i| {
            lines[i].trim() == "#[cfg(test)]"
                && lines[i + 1..]
                    .iter()
                    .map(|l| l.trim())
                    .find(|l| !l.starts_with("#[") && !l.starts_with("//"))
                    .is_some_and(|l| l.starts_with("mod ") && l.ends_with('{'))
        })
        .unwrap_or(lines.len());
    lines[..end]
        .iter()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// A statement without its leading attributes (`#[cfg(…)]`) and whitespace.
fn without_attributes(stmt: &str) -> &str {
    let mut s = stmt.trim_start();
    while s.starts_with("#[") {
        match s.find(']') {
            Some(end) => s = s[end + 1..].trim_start(),
            None => break,
        }
    }
    s
}

/// The paths a `use` tree names, braces expanded (`a::{b, c::{d}}` → `a::b`, `a::c::d`).
fn expand(prefix: &str, tree: &str, out: &mut Vec<String>) {
    let tree = tree.trim();
    let Some(open) = tree.find('{') else {
        let path = tree.split('#').next().unwrap_or(tree);
        out.push(format!("{prefix}{path}"));
        return;
    };
    let (head, body) = (&tree[..open], &tree[open + 1..tree.rfind('}').unwrap()]);
    let (mut depth, mut start) = (0, 0);
    for (i, c) in body.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                expand(&format!("{prefix}{head}"), &body[start..i], out);
                start = i + 1;
            }
            _ => {}
        }
    }
    if !body[start..].trim().is_empty() {
        expand(&format!("{prefix}{head}"), &body[start..], out);
    }
}

/// Every import of one file by another, `(from, to)`, paths relative to `src/`.
fn imports() -> BTreeSet<(String, String)> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = vec![];
    rust_files(&src, &mut files);
    let names: BTreeSet<String> = files
        .iter()
        .map(|p| {
            p.strip_prefix(&src)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/")
        })
        .collect();
    // The crate root's re-exports (`crate::Model` is `crate::model::Model`).
    let mut reexports = vec![];
    for stmt in code_of(&std::fs::read_to_string(src.join("lib.rs")).unwrap()).split(';') {
        if let Some(tree) = without_attributes(stmt).strip_prefix("pub use ") {
            expand(
                "",
                &tree.split_whitespace().collect::<String>(),
                &mut reexports,
            );
        }
    }
    // The file a module path lands in: its longest prefix that is a file, through the root's
    // re-exports for `crate::Item`.
    let longest = |path: &[&str]| -> Option<String> {
        (1..=path.len()).rev().find_map(|k| {
            let p = path[..k].join("/");
            [format!("{p}.rs"), format!("{p}/mod.rs")]
                .into_iter()
                .find(|f| names.contains(f))
        })
    };
    let file_of = |path: &[String]| -> Option<String> {
        let path: Vec<&str> = path.iter().map(String::as_str).collect();
        longest(&path).or_else(|| {
            let full = reexports
                .iter()
                .find(|r| r.rsplit("::").next() == path.first().copied())?;
            longest(&full.split("::").collect::<Vec<_>>())
        })
    };
    let mut edges = BTreeSet::new();
    for name in &names {
        let code = code_of(&std::fs::read_to_string(src.join(name)).unwrap());
        let me = module_of(name);
        let mut paths = vec![];
        for stmt in code.split(';') {
            let s = without_attributes(stmt);
            let re_export = s.starts_with("pub");
            let s = s
                .strip_prefix("pub(crate) ")
                .or(s.strip_prefix("pub "))
                .unwrap_or(s);
            if let Some(tree) = s.strip_prefix("use ") {
                // `a as b` keeps its path `a`; anything but a use tree (prose in a string) is
                // skipped.
                let tree = tree
                    .replace(" as ", "#")
                    .split_whitespace()
                    .collect::<String>();
                if tree
                    .chars()
                    .all(|c| c.is_alphanumeric() || "_:{},*#".contains(c))
                {
                    let mut found = vec![];
                    expand("", &tree, &mut found);
                    paths.extend(found.into_iter().map(|p| (p, re_export)));
                }
            }
        }
        for (i, _) in code.match_indices("crate::") {
            let rest: String = code[i..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                .collect();
            paths.push((rest, false));
        }
        for (p, re_export) in paths {
            let segs: Vec<String> = p
                .split("::")
                .filter(|s| !s.is_empty())
                .map(String::from)
                .collect();
            let target = match segs.first().map(String::as_str) {
                Some("crate") => segs[1..].to_vec(),
                Some("super") => {
                    // `super` of `a/b.rs` and of `a/b/mod.rs` (module `a::b`) is `a`.
                    let mut base = me.clone();
                    let mut rest = &segs[..];
                    while rest.first().map(String::as_str) == Some("super") {
                        base.pop();
                        rest = &rest[1..];
                    }
                    base.extend(rest.iter().cloned());
                    base
                }
                // A child module's path (`use plan::Plan;` in `dynamics/mod.rs`); a parent's
                // re-export of its children (`pub use plan::Plan;`) is its export map, not a
                // dependency of its code.
                Some(_) if re_export => continue,
                Some(first) => {
                    let mut child = me.clone();
                    child.push(first.to_string());
                    let c = child.join("/");
                    if !names.contains(&format!("{c}.rs"))
                        && !names.contains(&format!("{c}/mod.rs"))
                    {
                        continue;
                    }
                    child.extend(segs[1..].iter().cloned());
                    child
                }
                None => continue,
            };
            if let Some(to) = file_of(&target) {
                if to != *name {
                    edges.insert((name.clone(), to));
                }
            }
        }
    }
    edges
}

#[test]
fn imports_point_down_the_layers() {
    let up: Vec<_> = imports()
        .into_iter()
        .filter(|(from, to)| layer(to) > layer(from))
        .collect();
    assert!(up.is_empty(), "imports that run up the layers: {up:?}");
}

/// Files that import each other, directly or through others (the strongly connected components
/// of the import graph with more than one file), each sorted.
fn circles(edges: &BTreeSet<(String, String)>) -> Vec<Vec<String>> {
    let reach = |from: &str| {
        let mut seen = BTreeSet::from([from.to_string()]);
        let mut stack = vec![from.to_string()];
        while let Some(f) = stack.pop() {
            for (_, to) in edges
                .range((f.clone(), String::new())..)
                .take_while(|(a, _)| *a == f)
            {
                if seen.insert(to.clone()) {
                    stack.push(to.clone());
                }
            }
        }
        seen
    };
    let files: BTreeSet<&String> = edges.iter().map(|(a, _)| a).collect();
    let mut out: Vec<Vec<String>> = vec![];
    for f in files {
        if out.iter().any(|c| c.contains(f)) {
            continue;
        }
        let mine = reach(f);
        let circle: Vec<String> = mine
            .iter()
            .filter(|g| reach(g).contains(f.as_str()))
            .cloned()
            .collect();
        if circle.len() > 1 {
            out.push(circle);
        }
    }
    out
}

/// Circles of files still to break (issue 41), each with what breaks it: the test fails on a
/// new circle and on a listed one that is gone (delete its line), so the list only shrinks.
const KNOWN_CIRCLES: &[&[&str]] = &[
    // The FFI callbacks use the wrapper's types (`use super::*`): its shared types into a leaf.
    &["solver/ida.rs", "solver/ida/callbacks.rs"],
];

#[test]
fn no_new_circles_of_files() {
    let found = circles(&imports());
    let known: Vec<Vec<String>> = KNOWN_CIRCLES
        .iter()
        .map(|c| c.iter().map(|f| f.to_string()).collect())
        .collect();
    let new: Vec<_> = found.iter().filter(|c| !known.contains(c)).collect();
    let gone: Vec<_> = known.iter().filter(|c| !found.contains(c)).collect();
    assert!(new.is_empty(), "files that import each other: {new:?}");
    assert!(
        gone.is_empty(),
        "listed in KNOWN_CIRCLES but gone (delete them): {gone:?}"
    );
}
