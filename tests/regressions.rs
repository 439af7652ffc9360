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

/// The scene of reproducer `tests/regressions/<file>`.
fn reproducer(file: &str) -> SceneSpec {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/regressions")
        .join(file);
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    SceneSpec::from_json(&v["scene"].to_string()).unwrap()
}

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

/// The reproducer `error_test_fails_under_contact_tightening.json` (a run that failed with
/// `IDA_ERR_FAIL` under the contact tightening and now goes on with it relaxed) checked against
/// the energy balance, an independent check for a chaotic scene: gravity and the spring are
/// conservative and every other force (the spring's damper, the contact's damping, friction,
/// rolling resistance) dissipates, and the contact's own elastic energy is ≥ 0, so the
/// mechanical energy (kinetic + gravity + spring) can only fall from one output point out of
/// contact to the next. Tolerance 1e-6 of the energy turned over (the largest kinetic energy): the soft clamp
/// of the damping (`contact/regularise.rs`) adds at most an impulse of order 1e-8 of the
/// contact's, and IDA's error at rtol 5e-10 is far below; a run whose relaxed restart lost
/// consistency (a jump of the state) would show as a rise of the energy.
#[test]
fn relaxed_contact_tightening_loses_no_energy() {
    use modia3d::prelude::*;
    let s = reproducer("error_test_fails_under_contact_tightening.json");
    let model = fuzz::build::scene(&s).build().unwrap();
    let opts = fuzz::build::options(&s)
        .interval(s.run.stop_time / 2000.0)
        .contact_results(true);
    let res = model.simulate(&opts).expect("the run ends");
    assert!(
        res.warnings
            .iter()
            .any(|w| matches!(w, SimWarning::ContactTighteningRelaxed { .. })),
        "the tightening was not relaxed (the reproducer no longer fails its error test): {:?}",
        res.warnings
    );
    let g = Vector3::from(s.gravity);
    let fuzz::ForceSpec::Spring {
        stiffness, length0, ..
    } = s.forces[0]
    else {
        panic!("the reproducer's force is its spring");
    };
    let length = res.signal("spring0.length").unwrap();
    let mut e = vec![0.0; res.time().len()];
    let mut kinetic_max: f64 = 0.0;
    for (k, b) in s.bodies.iter().enumerate() {
        let m = b.mass.expect("the reproducer's masses are given");
        // The body's inertia about its centre (its object origin) [kg·m²]: a solid sphere's
        // 2/5·m·r², a box's m/12·(l_j² + l_k²).
        let inertia = match b.shape {
            fuzz::ShapeSpec::Sphere(d) => Matrix3::from_diagonal_element(0.1 * m * d * d),
            fuzz::ShapeSpec::Box(l) => Matrix3::from_diagonal(&Vector3::new(
                m / 12.0 * (l[1] * l[1] + l[2] * l[2]),
                m / 12.0 * (l[0] * l[0] + l[2] * l[2]),
                m / 12.0 * (l[0] * l[0] + l[1] * l[1]),
            )),
            _ => panic!("the reproducer's bodies are a sphere and a box"),
        };
        let name = format!("b{k}");
        let r = res.signal(&format!("{name}.r_abs")).unwrap();
        let vel = res.signal(&format!("{name}.v_abs")).unwrap();
        let w = res.signal(&format!("{name}.w_abs")).unwrap();
        let rot = res.signal(&format!("{name}.R_abs")).unwrap();
        for (i, ei) in e.iter_mut().enumerate() {
            let rm = Matrix3::from_row_slice(rot.at(i).unwrap());
            let wv = Vector3::from_column_slice(w.at(i).unwrap());
            let vv = Vector3::from_column_slice(vel.at(i).unwrap());
            let rv = Vector3::from_column_slice(r.at(i).unwrap());
            let kin =
                0.5 * m * vv.norm_squared() + 0.5 * wv.dot(&(rm * inertia * rm.transpose() * wv));
            kinetic_max = kinetic_max.max(kin);
            *ei += -m * g.dot(&rv) + kin;
        }
    }
    for (i, ei) in e.iter_mut().enumerate() {
        let stretch = length.at(i).unwrap()[0] - length0;
        *ei += 0.5 * stiffness * stretch * stretch;
    }
    // Out of contact (no pair penetrating) the contact stores nothing: there the energy may
    // only fall from one such point to the next.
    let pairs = res.contact_pairs();
    let depths: Vec<_> = pairs
        .iter()
        .map(|p| res.signal(&format!("{p}.penetration")).unwrap())
        .collect();
    let free: Vec<usize> = (0..e.len())
        .filter(|&i| depths.iter().all(|d| d.at(i).unwrap()[0] <= 0.0))
        .collect();
    let rise = free
        .windows(2)
        .map(|w| e[w[1]] - e[w[0]])
        .fold(0.0f64, f64::max);
    let t_relaxed = res
        .warnings
        .iter()
        .find_map(|w| match w {
            SimWarning::ContactTighteningRelaxed { t, .. } => Some(*t),
            _ => None,
        })
        .unwrap();
    let after = free.iter().filter(|&&i| res.time()[i] > t_relaxed).count();
    println!(
        "energy: start {:.6e} J, end {:.6e} J; {} output points out of contact ({after} after the relaxation at {t_relaxed:.3e} s), largest rise between them {rise:.3e} J; largest kinetic {kinetic_max:.3e} J",
        e[0],
        e[e.len() - 1],
        free.len()
    );
    assert!(after >= 10, "too few output points out of contact: {after}");
    assert!(
        rise <= 1e-6 * kinetic_max,
        "the mechanical energy rose by {rise:e} J between two points out of contact (largest kinetic energy {kinetic_max:e} J)"
    );
}

/// The reproducer `conv_fail_is_diagnosed.json` (an ellipsoid starting 5.9 cm inside a fixed
/// sphere, which the contact law lets out no faster than its damping allows, until IDA's
/// corrector fails): the error is `SolverStalled` with `DampingLimited`, and its numbers are
/// checked against the run's own partial results, an independent measurement: the depth equals
/// the penetration at the last output point to 1e-5 of it (the failed step's attempts move it
/// by ~1e-9 m per 1.7e-9 s step), and the speed `1/d` equals the rate at which the penetration
/// fell over the last 20 ms to 1 % (the creep is steady there; the elastic force's small
/// change over 20 µm of 5.9 cm moves the balance speed by far less).
#[test]
fn a_damping_limited_contact_is_named_when_the_solver_fails() {
    use modia3d::prelude::*;
    let s = reproducer("conv_fail_is_diagnosed.json");
    let model = fuzz::build::scene(&s).build().unwrap();
    let opts = fuzz::build::options(&s)
        .output_steps(true)
        .contact_results(true);
    let e = model.simulate(&opts).expect_err("the corrector fails");
    let SimErrorKind::SolverStalled { error, cause, .. } = &e.kind else {
        panic!("{}", e.kind);
    };
    assert!(error.to_string().contains("IDA_CONV_FAIL"), "{error}");
    let modia3d::core::SlowCause::DampingLimited {
        pair, depth, speed, ..
    } = &**cause
    else {
        panic!("cause {cause:?}");
    };
    assert_eq!(pair, "b0|b1");
    let r = &e.partial;
    let t = r.time();
    let p = r.signal("b0|b1.penetration").unwrap();
    let n = t.len();
    let last = p.at(n - 1).unwrap()[0];
    assert!((depth - last).abs() < 1e-5 * last, "{depth} vs {last}");
    let k0 = t.iter().position(|&x| x >= t[n - 1] - 0.02).unwrap();
    let rate = (p.at(k0).unwrap()[0] - last) / (t[n - 1] - t[k0]);
    assert!((rate - speed).abs() < 1e-2 * speed, "{rate} vs {speed}");
}

/// `tests/regressions/rolling_resistance_stalls_newton.json`: a 0.65 g steel cylinder rocking
/// on its side on a steel table under ~300 N (the non-spheres' linear law at `k_red = 1`).
/// IDA's corrector fails, and the diagnosis names the rolling resistance as the damper whose
/// time constant the steps fell to. Checked independently of the diagnosis' own numbers:
/// - its time constant is `I·w_min/(3 μ_r μ_geo f_n)` with the cylinder's smallest inertia from
///   its geometry (`m r²/2` about its axis, which is smaller than `m(3r² + L²)/12` here), the
///   Steel–Steel palette's `μ_r = 0.001`, `μ_geo = 1` m and `w_min = 0.01` rad/s (1e-9
///   relative: the same formula on independently computed inputs);
/// - the step IDA failed at (from its message) is within 1…100 time constants;
/// - with `μ_r = 0` and every other value the same, the run ends: the rolling resistance is
///   the cause, not a bystander.
#[test]
fn a_stiff_rolling_resistance_is_named_when_the_solver_fails() {
    use modia3d::prelude::*;
    let mut s = reproducer("rolling_resistance_stalls_newton.json");
    let model = fuzz::build::scene(&s).build().unwrap();
    let e = model
        .simulate(&fuzz::build::options(&s))
        .expect_err("the corrector fails");
    let SimErrorKind::SolverStalled { error, cause, .. } = &e.kind else {
        panic!("{}", e.kind);
    };
    let modia3d::core::SlowCause::StiffFriction {
        pair,
        law,
        object,
        time_constant,
        force,
    } = &**cause
    else {
        panic!("cause {cause:?}");
    };
    assert_eq!(
        (pair.as_str(), law.as_str(), object.as_str()),
        ("table|b0", "rolling resistance", "b0")
    );
    let fuzz::ShapeSpec::Cylinder(_, d, l) = s.bodies[0].shape else {
        panic!("the reproducer is a cylinder");
    };
    let (r, rho) = (0.5 * d, 8000.0); // Steel's density in the built-in palette
    let m = rho * std::f64::consts::PI * r * r * l;
    let i_min = (0.5 * m * r * r).min(m * (3.0 * r * r + l * l) / 12.0);
    let tau = i_min * 0.01 / (3.0 * 0.001 * 1.0 * force);
    println!("{error}\ntime constant {time_constant:.4e} s (from geometry {tau:.4e} s), normal force {force:.3e} N");
    assert!(
        (time_constant - tau).abs() < 1e-9 * tau,
        "{time_constant} vs {tau}"
    );
    let msg = error.to_string();
    let h: f64 = msg
        .split("h = ")
        .nth(1)
        .and_then(|x| x.split(',').next())
        .and_then(|x| x.trim().parse().ok())
        .unwrap_or_else(|| panic!("no step in {msg}"));
    assert!(
        h >= tau && h <= 100.0 * tau,
        "failed at h = {h:e} s, time constant {tau:e} s"
    );
    // The same scene without rolling resistance runs to the end.
    s.pairs = vec![("Steel".into(), "Steel".into(), [0.7, 0.5, 0.0])];
    let p = modia3d::core::scene::builtin_contact_pair("Steel", "Steel").unwrap();
    assert_eq!(
        (p.cor, p.mu_k),
        (0.7, 0.5),
        "the palette's Steel–Steel pair"
    );
    let model = fuzz::build::scene(&s).build().unwrap();
    // The reproducer's 10 s wall budget is what the failing run hit; this one only has to
    // end (it takes 7.5–8.4 s of it in the test profile on an idle 2-core machine, and failed
    // on a loaded one), so it gets a budget that load cannot reach.
    let r = model.simulate(&fuzz::build::options(&s).max_wall_time(120.0));
    assert!(
        r.is_ok(),
        "without rolling resistance: {:?}",
        r.err().map(|e| e.kind.to_string())
    );
}

/// A body sliding on one contact decelerates at `μ_k·g` (Coulomb: the normal force is its
/// weight once the bounces are over, the friction force `μ_k·f_n` above the regularisation
/// speed `v_min`, opposite to the contact point's velocity; the rocking damping of the patch
/// adds a torque, no force). Checked on the cylinder that lands on its side and slides
/// (`tests/regressions/cylinder_slides_on_its_side.json`), whose run stalled before the
/// quaternion increments of the pair-local quotients were capped: the deceleration of its centre of mass
/// over 10 ms windows of the sliding phase (after the last event, while it is faster than
/// `2·v_min`, so that the contact point, whose speed differs from the centre's by the yaw rate
/// times its distance, ≤ 6 mm/s, slides faster than `v_min`) within 1e-3 of `μ_k·g`. The bound:
/// the windowed secant of a deceleration whose direction turns with the yaw rate (~0.04 rad/s,
/// 4e-4 rad per window, a cosine error of 2e-8) and the velocities' error at rtol 3.7e-6
/// (~1e-7 m/s against the 2.6e-3 m/s change per window: 4e-5) are far below it.
#[test]
fn a_cylinder_sliding_on_its_side_decelerates_at_mu_g() {
    let s = reproducer("cylinder_slides_on_its_side.json");
    let mu_k = s.pairs[0].2[1];
    let g = -s.gravity[2];
    let model = fuzz::build::scene(&s).build().unwrap();
    let res = model.simulate(&fuzz::build::options(&s)).unwrap();
    let t_end = *res.time().last().unwrap();
    let t_last = res.events.last().expect("it lands").t;
    let v_at = |t: f64| {
        let v = res.signal_at("b0.v_abs", t).unwrap();
        nalgebra::Vector3::new(v[0], v[1], v[2])
    };
    let v_min = 0.01; // SceneOptions' default [m/s]: the scene sets none
    let (dt, mut windows) = (0.01, 0);
    let mut t = t_last + dt;
    while t + dt <= t_end {
        let (v0, v1) = (v_at(t), v_at(t + dt));
        if v1.xy().norm() < 2.0 * v_min {
            break;
        }
        let a = (v1 - v0) / dt;
        println!(
            "t {t:.3} s: speed {:.4e} m/s, deceleration {:.6e} m/s² (μ_k g = {:.6e})",
            v0.xy().norm(),
            a.norm(),
            mu_k * g
        );
        assert!(
            (a.norm() / (mu_k * g) - 1.0).abs() < 1e-3,
            "t = {t}: deceleration {} m/s², μ_k g = {} m/s²",
            a.norm(),
            mu_k * g
        );
        windows += 1;
        t += dt;
    }
    assert!(
        windows >= 5,
        "only {windows} sliding windows after t = {t_last} s"
    );
}

/// `linear_law_at_touch.json` ([`SlowCause::LinearLawAtTouch`](modia3d::core::SlowCause)):
/// the diagnosis' stiffness and period follow from the pair's constants — steel on steel,
/// `c = E/(1 − ν²)` per body (E = 2e11 Pa, ν = 0.3 in the built-in palette), `c_res = c/2`,
/// `k = k_red·c_res` with `k_red = 1`, the period `2π sqrt(m/k)` with the tetrahedron's mass
/// (the table is fixed) — to 1e-12 relative (the same formulas on independently computed
/// inputs); and the remedy it names works: the same scene with the later profile (Hertz for
/// every pair, smooth at the touch) runs to its end within 80,000 steps (it takes ~45,000),
/// where the paper's law reaches only t = 0.17 s of 0.94 s in 25,000.
#[test]
fn a_linear_law_at_its_touch_is_named_and_the_later_profile_ends_the_run() {
    use modia3d::prelude::*;
    let mut s = reproducer("linear_law_at_touch.json");
    let model = fuzz::build::scene(&s).build().unwrap();
    let e = model
        .simulate(&fuzz::build::options(&s))
        .expect_err("the run reaches its step budget");
    let SimErrorKind::WorkBudget(d) = &e.kind else {
        panic!("{}", e.kind);
    };
    let modia3d::core::SlowCause::LinearLawAtTouch {
        pair,
        stiffness,
        period,
        ..
    } = &d.cause
    else {
        panic!("cause {:?}", d.cause);
    };
    assert_eq!(pair, "table|b0");
    let c = 2e11 / (1.0 - 0.3 * 0.3);
    let k = 0.5 * c;
    let m = s.bodies[0].mass.expect("the reproducer's mass is given");
    let t = 2.0 * std::f64::consts::PI * (m / k).sqrt();
    println!("{}\nstiffness {stiffness:.6e} N/m (from the palette {k:.6e}), period {period:.6e} s ({t:.6e})", e.kind);
    assert!((stiffness - k).abs() <= 1e-12 * k, "{stiffness} vs {k}");
    assert!((period - t).abs() <= 1e-12 * t, "{period} vs {t}");
    assert!(d.t < 0.5 * s.run.stop_time, "stalled at t = {}", d.t);
    s.later_profile = true;
    s.run.max_steps = Some(80_000);
    let r = fuzz::build::scene(&s)
        .build()
        .unwrap()
        .simulate(&fuzz::build::options(&s))
        .expect("the later profile runs to the end");
    println!("later profile: {} steps", r.stats.solver.steps);
    assert_eq!(r.time().last().copied(), Some(s.run.stop_time));
}

/// `tests/regressions/contact_results_steered_the_step_guard.json`: observing a run must not
/// change it. The same scene with contact results, without them, and with a 100 times finer
/// output grid takes the same steps, evaluates the residual and the root functions the same
/// number of times and ends in the same state, to the bit (the runs are the same sequence of
/// floating-point operations but for the outputs). Before the step guard followed each step
/// directly, the first two took 2,116 and 2,112 steps.
#[test]
fn contact_results_and_the_grid_do_not_steer_the_steps() {
    let s = reproducer("contact_results_steered_the_step_guard.json");
    assert!(s.run.contact_results);
    let run = |contacts: bool, interval: Option<f64>| {
        let mut s = s.clone();
        s.run.contact_results = contacts;
        s.run.interval = interval;
        let r = fuzz::build::scene(&s)
            .build()
            .unwrap()
            .simulate(&fuzz::build::options(&s))
            .expect("the scene runs to its end");
        let st = &r.stats.solver;
        let last: Vec<u64> = r
            .signal_names()
            .iter()
            .filter(|n| n.ends_with(".r_abs") || n.ends_with(".v_abs"))
            .flat_map(|n| {
                let sig = r.signal(n).unwrap();
                sig.last()
                    .unwrap()
                    .iter()
                    .map(|x| x.to_bits())
                    .collect::<Vec<_>>()
            })
            .collect();
        assert!(!last.is_empty());
        (
            st.steps,
            st.residual_evals,
            st.root_evals,
            r.events.len(),
            last,
        )
    };
    let with = run(true, None);
    let without = run(false, None);
    let fine = run(true, Some(s.run.stop_time / 50_000.0));
    println!(
        "{} steps, {} residuals, {} root evaluations, {} events",
        with.0, with.1, with.2, with.3
    );
    assert!(with.0 > 1000, "the guard is at work over many steps");
    assert_eq!(with, without, "contact results steered the steps");
    assert_eq!(with, fine, "the output grid steered the steps");
}
