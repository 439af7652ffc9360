//! The crate's imports point down its layering (ARCHITECTURE.md, "Layers"; issue 41): every
//! `use crate::…`/`use super::…` and every `crate::…` path in the code of `src/**/*.rs` (comments
//! and `#[cfg(test)]` modules left out) names a file of the same or a lower layer; `crate::Item`
//! paths are followed through the crate root's re-exports. The layer table is the one of
//! ARCHITECTURE.md.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// Layers from the bottom, by path prefix under `src/` (the longest prefix wins).
const LAYERS: &[(&str, u32)] = &[
    // Vocabulary that imports nothing of the crate.
    ("geometry/", 0),
    ("solver/", 0),
    ("spatial.rs", 0),
    ("joints/rows.rs", 0),
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
    // The notice of an unoptimised build, printed by the driver's first run.
    ("build_profile.rs", 9),
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

/// The code of a source file: comments and a trailing `#[cfg(test)]` module removed.
fn code_of(src: &str) -> String {
    let end = src.find("#[cfg(test)]\nmod tests").unwrap_or(src.len());
    src[..end]
        .lines()
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
    let mut up = BTreeSet::new();
    for name in &names {
        let code = code_of(&std::fs::read_to_string(src.join(name)).unwrap());
        let me = module_of(name);
        let mut paths = vec![];
        for stmt in code.split(';') {
            let s = without_attributes(stmt);
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
    assert!(up.is_empty(), "imports that run up the layers: {up:?}");
}
