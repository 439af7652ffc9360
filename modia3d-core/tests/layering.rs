//! The crate's imports point down its layering (ARCHITECTURE.md, "Layers"; issue 41): every
//! `use crate::…`/`use super::…` and every `crate::…` path in the code of `src/**/*.rs` (comments
//! and `#[cfg(test)]` modules left out) names a file of the same or a lower layer. The imports
//! that still run up are listed in `KNOWN_UP`, each with the step that removes it: a new one
//! fails this test, and so does a listed one that is gone (delete its line), so the list only
//! shrinks.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// Layers from the bottom, by path prefix under `src/` (the longest prefix wins).
const LAYERS: &[(&str, u32)] = &[
    // Vocabulary that imports nothing of the crate.
    ("geometry/", 0),
    ("solver/", 0),
    ("spatial.rs", 0),
    ("joints/rows.rs", 0),
    ("scene/", 1),
    ("joints/", 2),
    ("dynamics/", 3),
    ("contact/", 4),
    ("dae/", 5),
    ("model.rs", 6),
    ("results/", 7),
    ("simulation.rs", 8),
    ("simulation/", 8),
    ("sweep/", 9),
    ("bench.rs", 9),
    ("lib.rs", 10),
];

/// Imports that still run up, `(from, to)`, and what removes them.
const KNOWN_UP: &[(&str, &str)] = &[
    // Validation asks the joint kinds' table, which takes validation's `Checker`: `Checker` and
    // the errors move to a leaf (`scene/error.rs`, issue 41 A).
    ("scene/topology.rs", "joints/mod.rs"),
    ("scene/validate/forces.rs", "joints/mod.rs"),
    ("scene/validate/joints.rs", "joints/mod.rs"),
    ("scene/validate/mod.rs", "joints/mod.rs"),
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

/// The code of a source file: comments and a trailing `#[cfg(test)]` module removed.
fn code_of(src: &str) -> String {
    let end = src.find("#[cfg(test)]\nmod tests").unwrap_or(src.len());
    src[..end]
        .lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
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

#[test]
fn imports_point_down_the_layers() {
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
    // The file a module path lands in: its longest prefix that is a file.
    let file_of = |path: &[String]| -> Option<String> {
        (1..=path.len()).rev().find_map(|k| {
            let p = path[..k].join("/");
            [format!("{p}.rs"), format!("{p}/mod.rs")]
                .into_iter()
                .find(|f| names.contains(f))
        })
    };
    let mut up = BTreeSet::new();
    for name in &names {
        let code = code_of(&std::fs::read_to_string(src.join(name)).unwrap());
        let me = module_of(name);
        let mut paths = vec![];
        for stmt in code.split(';') {
            let s = stmt.trim_start();
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
                    expand("", &tree, &mut paths);
                }
            }
        }
        for (i, _) in code.match_indices("crate::") {
            let rest: String = code[i..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                .collect();
            paths.push(rest);
        }
        for p in paths {
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
                _ => continue,
            };
            if let Some(to) = file_of(&target) {
                if to != *name && layer(&to) > layer(name) {
                    up.insert((name.clone(), to));
                }
            }
        }
    }
    let known: BTreeSet<(String, String)> = KNOWN_UP
        .iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect();
    let new: Vec<_> = up.difference(&known).collect();
    let gone: Vec<_> = known.difference(&up).collect();
    assert!(new.is_empty(), "imports that run up the layers: {new:?}");
    assert!(
        gone.is_empty(),
        "listed in KNOWN_UP but gone (delete them): {gone:?}"
    );
}
