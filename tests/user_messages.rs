//! Issue 44, "the first hour of a new user": errors that read well through `main`'s
//! `Result` (point 2), a restitution only for impacts (point 7), warnings that reach the
//! user without a `tracing` subscriber (point 3), an initial-penetration error that names
//! the size slip behind it (point 8; the loop that cannot close is in `tests/loops.rs`),
//! and a user crate told how to build optimised (point 1).

use modia3d::demo;
use modia3d::prelude::*;
use std::process::Command;

fn steel() -> SolidMaterial {
    modia3d::core::scene::builtin_solid_material("Steel").unwrap()
}

/// A bouncing ball stopped by a budget of 50 steps: `{:?}` of the error (what `unwrap()` and
/// `fn main() -> Result<(), Box<dyn Error>>` print) is the message, the variant and one line
/// about the partial results, naming the last time reached; the results are still in
/// `e.partial`. Before, it was a dump of the whole partial result (model, statistics,
/// warnings): 1,500 characters that started with `SimError { kind: …`.
#[test]
fn debug_of_a_failed_run_is_the_message_and_a_summary() {
    let pair = ContactPairMaterial::new(0.7, 0.5, 0.001);
    let model = demo::bouncing_sphere(0.1, 0.55, pair).build().unwrap();
    let opts = SimOptions::new(1.0).max_steps(Some(50)).progress(false);
    let e = model.simulate(&opts).unwrap_err();
    assert!(matches!(e.kind, SimErrorKind::WorkBudget(_)), "{e}");
    let text = format!("{e:?}");
    // What the derived Debug printed.
    let dump = format!(
        "SimError {{ kind: {:?}, partial: {:?} }}",
        e.kind, e.partial
    );
    println!(
        "{} characters (the derived Debug: {}):\n{text}",
        text.len(),
        dump.len()
    );
    let message = e.to_string();
    assert!(text.starts_with(&message), "{text}");
    // What Debug adds to the message (itself ~500 characters: the diagnosis of the budget)
    // is one short line per field.
    assert!(text.len() < message.len() + 150, "{text}");
    assert!(text.len() < 700, "{} characters: {text}", text.len());
    assert!(text.contains("SimErrorKind::WorkBudget"), "{text}");
    // The partial results stay reachable, and Debug names how far they go.
    let time = e.partial.time();
    assert!(time.len() > 1, "{} points", time.len());
    let t_last = *time.last().unwrap();
    assert!(t_last > 0.0 && t_last < 1.0, "{t_last}");
    assert!(text.contains(&format!("{t_last} s")), "{text}");
    assert!(
        text.contains(&format!("output points: {},", time.len())),
        "{text}"
    );
    assert!(e.partial.signal("ball.r_abs").unwrap().len() == time.len());
}

/// `build()?` in `main` prints `{:?}` of `SceneErrors`: the message with its hint, then the
/// variants, not `SceneErrors([UnknownParent { … }])`.
#[test]
fn debug_of_scene_errors_is_the_message() {
    let mut s = SceneDesc::new();
    s.add(demo::world(SceneOptions::default()))
        .add(Object3D::new("bob").solid(Solid::new(Shape::Sphere { diameter: 0.1 })))
        .add(Object3D::new("pivot").parent("bobb"));
    let e = s.build().unwrap_err();
    let text = format!("{e:?}");
    println!("{text}");
    assert!(text.starts_with(&e.to_string()), "{text}");
    assert!(text.contains("did you mean `bob`"), "{text}");
    assert!(text.contains("SceneError::"), "{text}");
    assert!(!text.starts_with("SceneErrors("), "{text}");
}

/// Contact phases of the ball–plane pair of a steel ball (Ø 20 mm) dropped from 5 cm on a
/// steel table with restitution `cor` (the force law's exact rebound relation if `exact`),
/// over `stop` \[s\].
fn ball_drop(cor: f64, exact: bool, stop: f64) -> Vec<ContactPhase> {
    let pair = ContactPairMaterial::new(cor, 0.0, 0.0);
    let options = SceneOptions {
        exact_restitution: exact,
        ..SceneOptions::default()
    };
    let model = demo::sphere_on_plane(0.02, steel(), 0.0, 0.05, pair, options)
        .build()
        .unwrap();
    let opts = SimOptions::new(stop)
        .interval(0.01)
        .contact_results(true)
        .progress(false);
    let res = model.simulate(&opts).unwrap();
    res.contact_phases("ball|plane").unwrap()
}

/// A ball dropped on a table: its impacts have a restitution near the pair's cor. The paper's
/// damping gives less (0.894 for 0.9, README "Contacts"; measured here 0.6·cor at cor 0.02,
/// 0.69·cor at 0.1, 0.85·cor at 0.3); with `exact_restitution` the first impact rebounds with
/// the cor. Even the heavily damped impacts of cor 0.02 count as impacts.
#[test]
fn an_impact_has_a_restitution_near_the_cor() {
    for (cor, exact) in [
        (0.02, false),
        (0.1, false),
        (0.3, false),
        (0.8, false),
        (0.3, true),
    ] {
        let phases = ball_drop(cor, exact, 0.25);
        for ph in &phases {
            println!(
                "cor {cor}: {:.6} … {:?} s, in {:.4e} out {:?} m/s, δ_max {:.3e} m, δ_max/(v·T) {:.3}, e = {:?}",
                ph.start,
                ph.end,
                ph.impact_speed,
                ph.exit_speed,
                ph.max_penetration,
                ph.max_penetration / (ph.impact_speed * ph.duration().unwrap_or(f64::NAN)),
                ph.restitution()
            );
        }
        let first = phases.first().expect("an impact");
        let e = first.restitution().expect("an impact has a restitution");
        println!("cor {cor}, exact {exact}: e = {e}");
        assert!(e <= cor && e > 0.5 * cor, "cor {cor}: e = {e}");
        if exact {
            assert!((e - cor).abs() < 5e-3 * cor, "cor {cor}: e = {e}");
        }
        // Every phase that ended (the bounces) is an impact; one still open (the ball at
        // rest) has none.
        for ph in &phases {
            assert_eq!(ph.end.is_some(), ph.restitution().is_some(), "{ph:?}");
            assert!(ph.restitution().is_none_or(|e| e <= cor), "{ph:?}");
        }
    }
}

/// A wooden cube sliding off the edge of a table (the plank ends at x = 2 m): its sliding
/// phase ends by tipping over the edge, with an exit speed unrelated to the speed it touched
/// down with, which made a "restitution" of 7.33 (issue 44). Not an impact: `None`.
#[test]
fn a_block_sliding_off_an_edge_has_no_restitution() {
    let cube = Shape::Box {
        lengths: Vector3::repeat(0.1),
    };
    // Dropped from 0.1 mm, so that the sliding phase starts with a small impact speed.
    let scene = demo::on_incline(
        cube,
        0.0501,
        0.0,
        1.6,
        2.5,
        [0.0; 3],
        "DryWood",
        ContactPairMaterial::new(0.6, 0.3, 0.001),
        SceneOptions::default(),
    );
    let model = scene.build().unwrap();
    let opts = SimOptions::new(0.5)
        .interval(1e-3)
        .contact_results(true)
        .progress(false);
    let res = model.simulate(&opts).unwrap();
    let phases = res.contact_phases("plank|body").unwrap();
    for ph in &phases {
        println!(
            "{:.6} … {:?} s, in {:.4e} out {:?} m/s, δ_max {:.3e} m, δ_max/(v·T) {:.3e}, e = {:?}, ratio {:?}",
            ph.start,
            ph.end,
            ph.impact_speed,
            ph.exit_speed,
            ph.max_penetration,
            ph.max_penetration / (ph.impact_speed * ph.duration().unwrap_or(f64::NAN)),
            ph.restitution(),
            ph.exit_speed.map(|x| x / ph.impact_speed)
        );
    }
    let last = phases.last().expect("a phase");
    assert!(last.end.is_some(), "the block left the plank: {last:?}");
    let x = res.signal("body.r_abs").unwrap();
    assert!(x.last().unwrap()[2] < -0.1, "the block fell off");
    // The phase that ends by tipping over the edge is no impact, and no phase reports more
    // restitution than the pair's cor 0.6: the landings from 0.1 mm leave faster than they
    // came (the block lands tilted by the friction and one edge lifts: no restitution) or
    // rebound below cor (the second, at 0.02 m/s, with e ≈ 0.18 since Newton's test of
    // volume-law scenes is tighter, `simulation.rs` `VOLUME_NEWTON_COEFFICIENT`).
    assert_eq!(last.restitution(), None, "{last:?}");
    for ph in &phases {
        assert!(ph.restitution().is_none_or(|e| e <= 0.6), "{ph:?}");
    }
    assert!(
        last.exit_speed.unwrap() > 100.0 * last.impact_speed,
        "{last:?}"
    );
}

/// The never-colliding solids of `tests/warnings.rs` (`demo::ball_on_a_slide`): one
/// `NeverCollide` warning.
fn never_colliding() -> Model {
    demo::ball_on_a_slide(false).build().unwrap()
}

/// Env var that makes [`warning_worker`] run its scenario: `default`, `quiet` or `subscriber`.
const WORKER: &str = "MODIA3D_FIRST_HOUR_WORKER";

// A `tracing` subscriber that prints nothing (it keeps the messages): installed, it takes the
// warnings through `tracing::warn!`.
mod recorder;
use recorder::Recorder;

/// Helper of [`warnings_reach_standard_error_once`], run in a child process (this test binary
/// re-invoked with [`WORKER`] set): one run of the never-colliding scene. Does nothing in a
/// normal test run.
#[test]
fn warning_worker() {
    let Ok(mode) = std::env::var(WORKER) else {
        return;
    };
    let model = never_colliding();
    let opts = SimOptions::new(0.01).quiet(mode == "quiet");
    let run = || model.simulate(&opts).unwrap();
    let res = if mode == "subscriber" {
        tracing::subscriber::with_default(Recorder(std::sync::Mutex::new(vec![])), run)
    } else {
        run()
    };
    // Warnings are kept in the result whatever is printed.
    assert_eq!(res.warnings.len(), 1, "{:?}", res.warnings);
}

/// The standard error of [`warning_worker`] in `mode`.
fn worker_stderr(mode: &str) -> String {
    let out = Command::new(std::env::current_exe().expect("test binary"))
        .args([
            "warning_worker",
            "--exact",
            "--nocapture",
            "--test-threads=1",
        ])
        .env(WORKER, mode)
        .output()
        .expect("run the worker");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{mode}: {stderr}");
    stderr
}

/// Without a `tracing` subscriber, a run prints its warnings to standard error, once, naming
/// the culprit; `SimOptions::quiet(true)` silences it, and so does an installed subscriber
/// (it gets them through `tracing::warn!`).
#[test]
fn warnings_reach_standard_error_once() {
    let text = worker_stderr("default");
    println!("default:\n{text}");
    assert_eq!(text.matches("can never touch").count(), 1, "{text}");
    assert!(
        text.contains("modia3d: the run found 1 warning ")
            && text.contains("`table` and `ball`")
            && text.contains("quiet(true)"),
        "{text}"
    );
    // This workspace compiles modia3d-core at opt-level 2 (its `[profile.dev]`): no notice of
    // an unoptimised build.
    assert!(!text.contains("without optimisation"), "{text}");
    for mode in ["quiet", "subscriber"] {
        let text = worker_stderr(mode);
        assert!(!text.contains("warning"), "{mode}: {text}");
    }
}

/// `result.summary()`: points, span, the statistics, and the warnings' headlines.
#[test]
fn summary_lists_the_warnings() {
    let res = never_colliding()
        .simulate(&SimOptions::new(0.01).progress(false).quiet(true))
        .unwrap();
    let s = res.summary();
    println!("{s}");
    assert!(s.starts_with(&format!(
        "output points: {}, t = 0 … 0.01 s, events: 0\n",
        res.time().len()
    )));
    assert!(s.contains(&res.stats.to_string()), "{s}");
    assert!(
        s.contains("warnings: 1 ")
            && s.contains("\n  - `table` and `ball` can never touch (joint `slide`"),
        "{s}"
    );
}

/// `restitution()`'s criterion on phases made by hand: an impact of 1 m/s that ends at
/// 0.5 m/s after 0.1 ms with 20 µm of penetration has e = 0.5; the same speeds after 0.2 s of
/// resting at 1 µm (the exit is then not the rebound of the impact), or an exit faster than
/// the impact, or a phase still open, have none.
#[test]
fn restitution_is_defined_for_impacts_only() {
    let impact = ContactPhase {
        pair: "a|b".into(),
        start: 1.0,
        end: Some(1.0001),
        impact_speed: 1.0,
        exit_speed: Some(0.5),
        max_penetration: 2e-5,
        max_normal_force: 100.0,
        t_max_normal_force: 1.00005,
        normal_impulse: 0.015,
        tangential_impulse: Vector3::zeros(),
        impulse: Vector3::new(0.0, 0.0, -0.015),
    };
    assert_eq!(impact.restitution(), Some(0.5));
    let resting = ContactPhase {
        end: Some(1.2),
        max_penetration: 1e-6,
        ..impact.clone()
    };
    assert_eq!(resting.restitution(), None);
    let pushed_off = ContactPhase {
        exit_speed: Some(1.5),
        ..impact.clone()
    };
    assert_eq!(pushed_off.restitution(), None);
    let elastic = ContactPhase {
        exit_speed: Some(1.0 + 1e-5),
        ..impact.clone()
    };
    assert_eq!(elastic.restitution(), Some(1.0 + 1e-5));
    let open = ContactPhase {
        end: None,
        exit_speed: None,
        ..impact.clone()
    };
    assert_eq!(open.restitution(), None);
    let grazing = ContactPhase {
        impact_speed: 0.0,
        ..impact
    };
    assert_eq!(grazing.restitution(), None);
}

/// A ball given diameter 100 where 0.1 (m) was meant, placed 1.3 m above the table as for
/// the 0.1 m ball: it starts 48.7 m deep in the table. The initial-penetration error names the
/// likely cause that the run's unit check (`SimWarning::ScaleOutlier`) would find: the ball is
/// 100 times the size of the scene's other collision solid (the 1 m table). Before, the error
/// said only "start 4.870e1 m inside each other".
#[test]
fn initial_penetration_names_a_size_slip() {
    let pair = ContactPairMaterial::new(0.7, 0.5, 0.001);
    let d = 100.0;
    let scene = demo::sphere_on_plane(
        d,
        steel(),
        0.0,
        1.3 - d / 2.0,
        pair,
        SceneOptions::default(),
    );
    let errors = scene.build().unwrap_err();
    let text = errors.to_string();
    println!("{text}");
    let [SceneError::InitialPenetration {
        depth, size_slip, ..
    }] = &errors.0[..]
    else {
        panic!("{errors:?}");
    };
    // The ball's lowest point is 50 − 1.3 m below the table's top face.
    assert!((depth - 48.7).abs() < 1e-6, "{depth}");
    let slip = size_slip.as_ref().expect("the size slip is named");
    // Sizes are the largest extents: the ball's diameter, the table's 1 m edge.
    assert_eq!(slip.object, "ball");
    assert_eq!((slip.size, slip.median), (100.0, 1.0));
    assert!(
        text.contains("likely cause: `ball` is 1.000e2 m across, 100 times the median")
            && text.contains("wrong unit"),
        "{text}"
    );
    // A penetration of a ball of the right size is reported without a cause it does not have.
    let scene = demo::sphere_on_plane(0.1, steel(), 0.0, -0.08, pair, SceneOptions::default());
    let errors = scene.build().unwrap_err();
    assert!(
        matches!(
            &errors.0[..],
            [SceneError::InitialPenetration {
                size_slip: None,
                ..
            }]
        ),
        "{errors:?}"
    );
    assert!(!errors.to_string().contains("likely cause"), "{errors}");
}

/// Point 1: a crate that depends on modia3d compiles it at opt-level 0 in `cargo run` unless
/// its `Cargo.toml` says otherwise. The README's section on depending on the crate gives the
/// lines ([`build_profile::CARGO_TOML_FIX`]) in a `toml` block with the measured dev/release
/// ratio, the notice of an unoptimised build names the same lines, and this workspace's own
/// builds are optimised, so its tests never see the notice.
#[test]
fn a_user_crate_is_told_how_to_build_optimised() {
    use modia3d::core::build_profile;
    let readme = include_str!("../README.md");
    let section = readme
        .split("\n## ")
        .find(|s| s.starts_with("Using modia3d in your own crate"))
        .expect("the README's section on depending on modia3d");
    let toml = section
        .split("```toml\n")
        .nth(1)
        .and_then(|s| s.split("```").next())
        .expect("a toml block");
    assert!(toml.contains(build_profile::CARGO_TOML_FIX), "{toml}");
    assert!(toml.contains("modia3d = {"), "{toml}");
    assert!(
        section.contains("median of 3"),
        "the measured ratio: {section}"
    );
    let notice = build_profile::unoptimised_notice();
    for line in build_profile::CARGO_TOML_FIX.lines() {
        assert!(notice.contains(line), "{notice}");
    }
    assert!(notice.contains("Cargo.toml"), "{notice}");
    assert!(
        !build_profile::unoptimised(),
        "{}",
        build_profile::OPT_LEVEL
    );
}
