//! Every block of `scene/blocks.rs` (each `impl Component for X`) has a row in the table of
//! block kinds ([`modia3d_core::BLOCK_KINDS`]), in the same order; each row's parameters are
//! the struct's public fields in order, and its ports, outputs (with feedthrough) and states
//! are those its example block reports. Reads the source, so a block added without its row,
//! or a field added without its key, fails here: the table is what `model!` checks and expands
//! a component entry with.

use modia3d_core::BLOCK_KINDS;

/// The source of `blocks.rs`.
fn blocks_source() -> String {
    let path = format!("{}/src/scene/blocks.rs", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap()
}

/// The blocks: `impl Component for X` in source order.
fn blocks() -> Vec<String> {
    blocks_source()
        .lines()
        .filter_map(|l| l.strip_prefix("impl Component for "))
        .map(|l| l.trim_end_matches(" {").to_string())
        .collect()
}

/// The public fields of `pub struct name {` in order (empty for a unit struct).
fn fields(name: &str) -> Vec<String> {
    let src = blocks_source();
    let Some(body) = src.split(&format!("pub struct {name} {{")).nth(1) else {
        assert!(
            src.contains(&format!("pub struct {name};")),
            "blocks.rs declares `pub struct {name}`"
        );
        return vec![];
    };
    body.lines()
        .take_while(|l| !l.starts_with('}'))
        .filter_map(|l| l.trim().strip_prefix("pub "))
        .filter_map(|l| l.split_once(':').map(|(f, _)| f.trim().to_string()))
        .collect()
}

#[test]
fn every_block_has_a_row_in_order() {
    let blocks = blocks();
    assert!(blocks.len() >= 18, "read {blocks:?}");
    let rows: Vec<&str> = BLOCK_KINDS.iter().map(|k| k.name).collect();
    let missing: Vec<&str> = blocks
        .iter()
        .map(String::as_str)
        .filter(|b| !rows.contains(b))
        .collect();
    assert!(
        missing.is_empty(),
        "blocks without a row in scene/block_table.rs: {missing:?}"
    );
    assert_eq!(blocks, rows, "the table's order is blocks.rs's");
}

#[test]
fn rows_keys_are_the_structs_fields() {
    for row in BLOCK_KINDS {
        let keys: Vec<&str> = row.params.iter().map(|p| p.key).collect();
        assert_eq!(keys, fields(row.name), "{}: parameters", row.name);
        for p in row.params {
            if let Some(d) = p.default.and_then(|d| d.strip_prefix('-')) {
                assert!(
                    d.parse::<f64>().is_ok() || row.param(d).is_some(),
                    "{}: default of {} is another key or a number",
                    row.name,
                    p.key
                );
            }
        }
        let mut all: Vec<&str> = row.keys().collect();
        all.sort_unstable();
        all.dedup();
        assert_eq!(
            all.len(),
            row.keys().count(),
            "{}: keys are unique",
            row.name
        );
    }
}

#[test]
fn rows_ports_are_their_example_blocks() {
    for row in BLOCK_KINDS {
        let b = (row.example)(&|_| None);
        assert_eq!(b.kind(), row.name);
        let inputs: Vec<String> = b.inputs().into_iter().map(|p| p.name).collect();
        assert_eq!(inputs, row.inputs, "{}: inputs", row.name);
        let outputs: Vec<(String, bool)> = b
            .outputs()
            .into_iter()
            .map(|o| (o.name, o.feedthrough))
            .collect();
        let want: Vec<(String, bool)> = row
            .outputs
            .iter()
            .map(|o| (o.name.to_string(), o.feedthrough))
            .collect();
        assert_eq!(outputs, want, "{}: outputs", row.name);
        let states: Vec<String> = b.states().into_iter().map(|s| s.name).collect();
        assert_eq!(states, row.states, "{}: states", row.name);
        let discrete: Vec<String> = b.discrete_states().into_iter().map(|s| s.name).collect();
        assert_eq!(
            discrete, row.discrete_states,
            "{}: discrete states",
            row.name
        );
    }
}

/// A path of several axes numbers its outputs per axis (the row lists one axis).
#[test]
fn numbered_outputs_are_per_axis() {
    use modia3d_core::blocks::PtpPath;
    use modia3d_core::Component;
    let p = PtpPath {
        positions: vec![vec![0.0, 0.0], vec![1.0, 2.0]],
        v_max: vec![1.0, 1.0],
        a_max: vec![1.0, 1.0],
        startTime: 0.0,
    };
    let names: Vec<String> = p.outputs().into_iter().map(|o| o.name).collect();
    assert_eq!(names, ["q1", "qd1", "qdd1", "q2", "qd2", "qdd2"]);
    let row = modia3d_core::block_kind("PtpPath").unwrap();
    assert!(row.numbered_outputs);
}

/// Every variant of an enum-valued parameter makes a valid block of the kind; the `Drive`'s
/// change its ports as its docs say.
#[test]
fn variants_make_valid_blocks() {
    use modia3d_core::BlockValue;
    for row in BLOCK_KINDS {
        for p in row.params {
            let BlockValue::Variant(vs) = p.value else {
                continue;
            };
            assert_eq!(
                p.default,
                Some(vs[0].name),
                "{}: the default is the first",
                row.name
            );
            for v in vs {
                let b = (row.example)(&|k| (k == p.key).then_some(v.name));
                assert_eq!(b.kind(), row.name);
                assert_eq!(
                    b.check(),
                    Ok(()),
                    "{} with {} = {}",
                    row.name,
                    p.key,
                    v.name
                );
            }
        }
    }
    // A sampled block takes its inner block's ports (every kind as `inner`).
    let sampled = modia3d_core::block_kind("Sampled").unwrap();
    for row in BLOCK_KINDS {
        let s = (sampled.example)(&|k| (k == "inner").then_some(row.name));
        let inner = (row.example)(&|_| None);
        assert_eq!(s.kind(), "Sampled");
        assert_eq!(s.inputs(), inner.inputs(), "Sampled with {}", row.name);
        assert_eq!(s.outputs().len(), inner.outputs().len());
        assert!(s.outputs().iter().all(|o| !o.feedthrough));
    }
    let drive = modia3d_core::block_kind("Drive").unwrap();
    let dc = (drive.example)(&|k| (k == "motor").then_some("Dc"));
    let inputs: Vec<String> = dc.inputs().into_iter().map(|p| p.name).collect();
    assert_eq!(inputs, ["v"]);
    let elastic = (drive.example)(&|k| (k == "gear").then_some("Elastic"));
    let states: Vec<String> = elastic.states().into_iter().map(|s| s.name).collect();
    assert_eq!(states, ["phi_gear", "motor_w"]);
}
