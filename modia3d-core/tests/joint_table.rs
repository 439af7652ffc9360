//! Every builder variant of `JointKind` (`src/scene/desc.rs`) has a row in the table of joint
//! kinds ([`modia3d_core::JOINT_KINDS`], issue 41), in the same order, whose keys are the
//! variant's fields in their order: the table is what `model!` checks and expands a joint
//! with. Reads the source, so a variant added without its row fails here (the generated
//! dispatch in `joints/mod.rs` does not compile without one either).

mod builder_source;

use modia3d_core::JOINT_KINDS;

/// The variants of `pub enum JointKind` with their fields, read from `desc.rs`.
fn builder_variants() -> Vec<(String, Vec<String>)> {
    builder_source::builder_variants("src/scene/desc.rs", "pub enum JointKind {")
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
