//! Every failure the random-scene fuzzer (`tests/fuzz_scenes.rs`) found, kept as a test forever
//! (issue 15, point 1): each `tests/regressions/*.json` holds the scene seed, the minimised
//! scene (`tests/fuzz/`'s `SceneSpec` as JSON), the cause in words and the outcome class the
//! scene must have now (`ok`, `build:<SceneError>`, `sim:<SimErrorKind>`). This test replays
//! every file and asserts that class, that the run ended within twice its wall budget
//! (`run.max_wall_time`; plus 1 s for the build and a loaded machine), and, where the file has
//! `detail_contains`, that the outcome's message contains it (the cause a diagnosis must name).
//!
//! Add a reproducer: `MODIA3D_FUZZ_SCENE=<scene seed> cargo test --test fuzz_scenes
//! replay_one_scene -- --nocapture` prints the minimised scene as such a JSON object; save it
//! with a `note` and set `expected` to the class of the fixed behaviour.

mod fuzz;

use fuzz::run::run_scene;
use fuzz::SceneSpec;

#[test]
fn every_recorded_failure_has_its_expected_outcome() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/regressions");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("tests/regressions exists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no reproducers in {dir:?}");
    let mut wrong = vec![];
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        let v: serde_json::Value = serde_json::from_str(&text)
            .unwrap_or_else(|e| panic!("{}: not JSON: {e}", f.display()));
        let expected = v["expected"].as_str().expect("`expected` is a string");
        // Optional: a phrase the outcome's message must contain (the diagnosis' cause).
        let phrase = v["detail_contains"].as_str();
        let scene = SceneSpec::from_json(&v["scene"].to_string())
            .unwrap_or_else(|e| panic!("{}: not a scene: {e}", f.display()));
        let o = run_scene(&scene);
        let late = o.wall > 2.0 * scene.run.max_wall_time + 1.0;
        println!(
            "{}: {} in {:.3} s (expected {expected}){}",
            f.file_name().unwrap().to_string_lossy(),
            o.class,
            o.wall,
            if o.detail.is_empty() {
                String::new()
            } else {
                format!(": {}", o.detail)
            }
        );
        let unnamed = phrase.is_some_and(|p| !o.detail.contains(p));
        if o.class != expected || late || unnamed {
            wrong.push(format!(
                "{}: {} after {:.2} s, expected {expected} within {} s{}",
                f.display(),
                o.class,
                o.wall,
                2.0 * scene.run.max_wall_time + 1.0,
                phrase.map_or(String::new(), |p| format!(" naming `{p}`: {}", o.detail))
            ));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}
