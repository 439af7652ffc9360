//! Every builder variant of `JointKind` (`src/scene/desc.rs`) has a row in the table of joint
//! kinds ([`modia3d_core::JOINT_KINDS`], issue 41), in the same order, whose keys are the
//! variant's fields in their order: the table is what `model!` checks and expands a joint
//! with. Reads the source, so a variant added without its row fails here (the generated
//! dispatch in `joints/mod.rs` does not compile without one either).

use modia3d_core::JOINT_KINDS;

/// The variants of `pub enum JointKind` with their fields, read from `desc.rs`.
fn builder_variants() -> Vec<(String, Vec<String>)> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/src/scene/desc.rs");
    let src = std::fs::read_to_string(path).unwrap();
    let body = src
        .split("pub enum JointKind {")
        .nth(1)
        .expect("desc.rs declares `pub enum JointKind`");
    let mut variants: Vec<(String, Vec<String>)> = vec![];
    for line in body.lines() {
        if line.starts_with('}') {
            break;
        }
        if line.trim_start().starts_with("//") {
            continue;
        }
        // Variants at one indentation, their fields at two.
        if let Some(v) = line.strip_prefix("    ").filter(|l| !l.starts_with(' ')) {
            let name: String = v.chars().take_while(|c| c.is_alphanumeric()).collect();
            if !name.is_empty() {
                variants.push((name, vec![]));
            }
        } else if let Some(f) = line
            .strip_prefix("        ")
            .filter(|l| !l.starts_with(' '))
        {
            if let Some((field, _)) = f.split_once(':') {
                variants
                    .last_mut()
                    .unwrap()
                    .1
                    .push(field.trim().to_string());
            }
        }
    }
    variants
}

#[test]
fn every_builder_variant_has_a_table_row() {
    let variants = builder_variants();
    assert!(variants.len() >= 8, "read {variants:?}");
    let rows: Vec<&str> = JOINT_KINDS.iter().map(|k| k.name).collect();
    let missing: Vec<&str> = variants
        .iter()
        .map(|(n, _)| n.as_str())
        .filter(|n| !rows.contains(n))
        .collect();
    assert!(
        missing.is_empty(),
        "JointKind variants without a row in joints/mod.rs's table: {missing:?}"
    );
    let names: Vec<&str> = variants.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, rows, "the table's order is the builder's");
    for ((name, fields), row) in variants.iter().zip(JOINT_KINDS) {
        let keys: Vec<&str> = row.keys().collect();
        assert_eq!(
            keys, *fields,
            "{name}: the row's keys are the variant's fields"
        );
    }
}

#[test]
fn rows_at_rest_are_their_variants_at_rest() {
    for row in JOINT_KINDS {
        let kind = (row.at_rest)(&|_| None);
        assert_eq!(kind.name(), row.name);
        for c in row.coordinates {
            assert!(
                row.initial.iter().any(|p| p.key == c.name),
                "{}: coordinate `{}` is an initial value",
                row.name,
                c.name
            );
        }
    }
}
