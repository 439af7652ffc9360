//! Every builder variant of `Shape` (`src/geometry/shapes.rs`) has a row in the table of shape
//! kinds ([`modia3d_core::SHAPE_KINDS`], issue 41), in the same order, whose parameters are the
//! variant's fields in their order: the table is what `model!` checks and expands a shape
//! with. Reads the source, so a variant added without its row fails here (the generated
//! dispatch `Shape::spec` does not compile without one either).

mod builder_source;

use modia3d_core::{ShapeValue, SHAPE_KINDS};

/// The variants of `pub enum Shape` with their fields, read from `shapes.rs`.
fn builder_variants() -> Vec<(String, Vec<String>)> {
    builder_source::builder_variants("src/geometry/shapes.rs", "pub enum Shape {")
}

#[test]
fn every_builder_variant_has_a_table_row() {
    let variants = builder_variants();
    assert!(variants.len() >= 10, "read {variants:?}");
    let rows: Vec<&str> = SHAPE_KINDS.iter().map(|k| k.name).collect();
    let missing: Vec<&str> = variants
        .iter()
        .map(|(n, _)| n.as_str())
        .filter(|n| !rows.contains(n))
        .collect();
    assert!(
        missing.is_empty(),
        "Shape variants without a row in geometry/shape_kind.rs's table: {missing:?}"
    );
    let names: Vec<&str> = variants.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, rows, "the table's order is the builder's");
    for ((name, fields), row) in variants.iter().zip(SHAPE_KINDS) {
        let row_fields: Vec<&str> = row.fields().collect();
        assert_eq!(
            row_fields, *fields,
            "{name}: the row's parameters are the variant's fields"
        );
    }
}

/// A `model!` constructor's row builds its own variant from stand-in values, and takes only
/// values `model!` can write.
#[test]
fn stand_ins_are_their_variants() {
    struct StandIns;
    impl modia3d_core::ShapeValues for StandIns {
        fn length(&mut self, _: &'static str) -> f64 {
            0.5
        }
        fn vector(&mut self, _: &'static str) -> nalgebra::Vector3<f64> {
            nalgebra::Vector3::repeat(0.5)
        }
        fn axis(&mut self, _: &'static str) -> modia3d_core::Axis {
            modia3d_core::Axis::Z
        }
        fn stand_in(&self) -> f64 {
            0.5
        }
    }
    for row in SHAPE_KINDS {
        let Some(stand_in) = row.stand_in else {
            continue;
        };
        assert!(
            row.params.iter().all(|p| p.value != ShapeValue::LoadedMesh),
            "{}",
            row.name
        );
        let shape = stand_in(&mut StandIns);
        // Points and files stand in as a hull; every other row builds its own variant.
        if !row
            .params
            .iter()
            .any(|p| matches!(p.value, ShapeValue::Vertices | ShapeValue::File))
        {
            assert_eq!(shape.spec().name, row.name);
            assert_eq!(shape.kind(), row.kind, "{}", row.name);
        }
    }
}
