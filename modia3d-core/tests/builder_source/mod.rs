//! Shared by `joint_table.rs` and `shape_table.rs`: the variants of a builder enum with their
//! fields, read from the crate's source, to hold against the table of kinds that `model!`
//! reads.

/// The variants of `decl` (e.g. `"pub enum JointKind {"`) in the file `path` (relative to the
/// crate), each with its field names in order. Variants sit at one indentation, their fields
/// at two; comment lines are skipped.
pub fn builder_variants(path: &str, decl: &str) -> Vec<(String, Vec<String>)> {
    let path = format!("{}/{path}", env!("CARGO_MANIFEST_DIR"));
    let src = std::fs::read_to_string(&path).unwrap();
    let body = src
        .split(decl)
        .nth(1)
        .unwrap_or_else(|| panic!("{path} declares `{decl}`"));
    let mut variants: Vec<(String, Vec<String>)> = vec![];
    for line in body.lines() {
        if line.starts_with('}') {
            break;
        }
        if line.trim_start().starts_with("//") {
            continue;
        }
        if let Some(v) = line.strip_prefix("    ").filter(|l| !l.starts_with(' ')) {
            let name: String = v.chars().take_while(|c| c.is_alphanumeric()).collect();
            if !name.is_empty() {
                variants.push((name, vec![]));
            }
        } else if let Some(f) = line
            .strip_prefix("        ")
            .filter(|l| !l.starts_with(' '))
        {
            if let (Some((field, _)), Some(last)) = (f.split_once(':'), variants.last_mut()) {
                last.1.push(field.trim().to_string());
            }
        }
    }
    variants
}
