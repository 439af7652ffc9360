//! The block library (docs/drive-trains.md) against closed forms: sources at output points,
//! states integrated under the run's error control, limits located as zero crossings, a
//! sampled block's forward-Euler ticks, the typed errors of bad components and bad wiring.

use modia3d::core::blocks::{
    FirstOrder, Gain, Input, Integrator, LimPID, Limiter, PtpPath, Ramp, Sampled, Sine, Step,
    Table, PI,
};
use modia3d::core::{ComponentIo, OutputSpec, PortSpec, StateSpec};
use modia3d::prelude::*;
use std::f64::consts::TAU;

type Res = Result<(), Box<dyn std::error::Error>>;

/// A scene of components only (the world and no body).
fn components_only() -> SceneDesc {
    let mut scene = SceneDesc::new();
    scene.add(Object3D::new("world").scene(SceneOptions::default()));
    scene
}

fn value(r: &SimulationResult, name: &str, t: f64) -> Result<f64, Box<dyn std::error::Error>> {
    Ok(r.signal_at(name, t)?[0])
}

/// Sources at their kinks and in between, exactly (no state: the output is the formula).
#[test]
fn sources_give_their_formulas() -> Res {
    let mut scene = components_only();
    scene
        .add_component(ComponentDecl::new(
            "step",
            Step {
                height: 2.0,
                offset: 0.5,
                startTime: 0.3,
            },
        ))
        .add_component(ComponentDecl::new(
            "ramp",
            Ramp {
                height: 3.0,
                duration: 0.4,
                offset: -1.0,
                startTime: 0.2,
            },
        ))
        .add_component(ComponentDecl::new(
            "table",
            Table {
                table: vec![(0.0, 0.0), (0.5, 1.0), (0.5, 3.0), (1.0, 2.0)],
            },
        ))
        .add_component(ComponentDecl::new(
            "path",
            PtpPath {
                positions: vec![vec![0.0], vec![0.3], vec![0.0]],
                v_max: vec![2.68512],
                a_max: vec![1.5],
                startTime: 0.0,
            },
        ));
    let r = scene
        .build()?
        .simulate(&SimOptions::new(2.0).output_steps(true))?;
    for t in [0.1f64, 0.25, 0.35, 0.7, 0.95, 1.5] {
        let step = 0.5 + if t < 0.3 { 0.0 } else { 2.0 };
        let ramp = -1.0 + 3.0 * ((t - 0.2) / 0.4).clamp(0.0, 1.0);
        let table: f64 = if t < 0.5 {
            2.0 * t
        } else {
            3.0 - 2.0 * (t - 0.5)
        };
        let table = if t >= 1.0 { 2.0 } else { table };
        assert!(
            (value(&r, "step.y", t)? - step).abs() < 1e-12,
            "step at {t}: {} vs {step}; {:?}",
            value(&r, "step.y", t)?,
            r.signal("step.y")?
                .values()
                .iter()
                .take(5)
                .collect::<Vec<_>>()
        );
        assert!((value(&r, "ramp.y", t)? - ramp).abs() < 1e-9, "ramp at {t}");
        assert!(
            (value(&r, "table.y", t)? - table).abs() < 1e-9,
            "table at {t}"
        );
    }
    // The path 0 → 0.3 → 0 with a_max 1.5 never reaches v_max: two parabolas per segment,
    // each 1/√(1.5/0.3) s long (Modia3D's `PTP_path`).
    let ta = (0.3f64 / 1.5).sqrt();
    for (t, q) in [
        (0.5 * ta, 0.5 * 1.5 * (0.5 * ta).powi(2)),
        (ta, 0.15),
        (2.0 * ta, 0.3),
        (3.0 * ta, 0.15),
        (4.0 * ta + 0.1, 0.0),
    ] {
        assert!(
            (value(&r, "path.q", t)? - q).abs() < 1e-9,
            "path at {t}: {q}"
        );
    }
    Ok(())
}

/// Integrator, FirstOrder and PI states against their closed forms, to the run's tolerance.
#[test]
fn continuous_blocks_follow_their_solutions() -> Res {
    let (a, f) = (2.0, 1.5);
    let mut scene = components_only();
    scene
        .add_component(ComponentDecl::new(
            "sine",
            Sine {
                amplitude: a,
                f,
                ..Default::default()
            },
        ))
        .add_component(ComponentDecl::new("int", Integrator::default()).input("u", "sine.y"))
        .add_component(
            ComponentDecl::new(
                "lag",
                FirstOrder {
                    k: 3.0,
                    T: 0.2,
                    y_start: 0.0,
                },
            )
            .input("u", 1.0),
        )
        .add_component(ComponentDecl::new("pi", PI::new(2.0, 0.5)).input("u", "time"));
    let rtol = 1e-8;
    let r = scene
        .build()?
        .simulate(&SimOptions::new(2.0).tolerance(rtol))?;
    for k in 1..=8 {
        let t = 0.25 * k as f64;
        let int = a / (TAU * f) * (1.0 - (TAU * f * t).cos());
        let lag = 3.0 * (1.0 - (-t / 0.2).exp());
        // PI with u = t: x = t²/(2T), y = k(x + u).
        let pi = 2.0 * (t * t / 1.0 + t);
        // Global error of a variable-step BDF run: a few hundred times rtol on O(1) values
        // (the error test bounds the local error per step).
        let tol = 1e-5;
        assert!(
            (value(&r, "int.y", t)? - int).abs() < tol,
            "integrator at {t}"
        );
        assert!(
            (value(&r, "lag.y", t)? - lag).abs() < tol,
            "first order at {t}"
        );
        assert!((value(&r, "pi.y", t)? - pi).abs() < tol, "PI at {t}");
    }
    Ok(())
}

/// A limiter on a sine: its kinks are events at `asin(uMax/A)/(2πf)` and the integral of the
/// limited sine is the closed form's.
#[test]
fn limiter_kinks_are_located_as_events() -> Res {
    let (a, f, umax) = (1.0, 1.0, 0.5);
    let mut scene = components_only();
    scene
        .add_component(ComponentDecl::new(
            "sine",
            Sine {
                amplitude: a,
                f,
                ..Default::default()
            },
        ))
        .add_component(ComponentDecl::new("lim", Limiter::new(-umax, umax)).input("u", "sine.y"))
        .add_component(ComponentDecl::new("int", Integrator::default()).input("u", "lim.y"));
    let r = scene
        .build()?
        .simulate(&SimOptions::new(1.0).tolerance(1e-9))?;
    let t1 = (umax / a).asin() / (TAU * f);
    let expected = [t1, 0.5 - t1, 0.5 + t1, 1.0 - t1];
    let times: Vec<f64> = r.events.iter().map(|e| e.t).collect();
    assert_eq!(times.len(), 4, "events {times:?}");
    for (t, e) in times.iter().zip(expected) {
        // IDA locates a root to about 100 ulps of the step scale.
        assert!((t - e).abs() < 1e-9, "kink at {t}, expected {e}");
    }
    // ∫ clamp(sin) over [0, 1/2]: 2·(1 − cos(2π t1))/(2π) + umax·(1/2 − 2 t1), and the mirror
    // image over [1/2, 1]: zero over the whole period.
    let half = 2.0 * (1.0 - (TAU * t1).cos()) / TAU + umax * (0.5 - 2.0 * t1);
    assert!((value(&r, "int.y", 0.5)? - half).abs() < 1e-7);
    assert!(value(&r, "int.y", 1.0)?.abs() < 1e-7);
    Ok(())
}

/// LimPID with anti-windup holding an integrator plant at a set point it cannot reach
/// quickly: the output sits at its limit, then leaves it when the error turns.
#[test]
fn limpid_saturates_and_recovers() -> Res {
    let mut scene = components_only();
    scene
        .add_component(
            ComponentDecl::new(
                "ctrl",
                LimPID {
                    k: 10.0,
                    Ti: 0.5,
                    Td: 0.1,
                    yMax: 1.0,
                    yMin: -1.0,
                    ..Default::default()
                },
            )
            .input("u_s", 1.0)
            .input("u_m", "plant.y"),
        )
        .add_component(ComponentDecl::new("plant", Integrator::default()).input("u", "ctrl.y"));
    let r = scene
        .build()?
        .simulate(&SimOptions::new(5.0).tolerance(1e-8))?;
    // Saturated from the start: the plant rises at exactly 1 per second.
    assert!((value(&r, "plant.y", 0.5)? - 0.5).abs() < 1e-7);
    assert!((value(&r, "ctrl.y", 0.5)? - 1.0).abs() < 1e-12);
    // Leaves the limit (an event) and settles on the set point. With the anti-windup
    // (Ni = 0.9) the PI part's overshoot after saturation is smaller than without it
    // (Ni = 1e6: the integrator winds up for the whole saturated second).
    assert!(!r.events.is_empty());
    let peak = |r: &SimulationResult| -> Result<f64, Box<dyn std::error::Error>> {
        Ok(r.signal("plant.y")?
            .values()
            .into_iter()
            .fold(f64::MIN, f64::max))
    };
    let mut windup = components_only();
    windup
        .add_component(
            ComponentDecl::new(
                "ctrl",
                LimPID {
                    k: 10.0,
                    Ti: 0.5,
                    Td: 0.1,
                    yMax: 1.0,
                    yMin: -1.0,
                    Ni: 1e6,
                    ..Default::default()
                },
            )
            .input("u_s", 1.0)
            .input("u_m", "plant.y"),
        )
        .add_component(ComponentDecl::new("plant", Integrator::default()).input("u", "ctrl.y"));
    let rw = windup
        .build()?
        .simulate(&SimOptions::new(5.0).tolerance(1e-8))?;
    let (with, without) = (peak(&r)?, peak(&rw)?);
    assert!(
        with < without - 0.05,
        "anti-windup peak {with}, without {without}"
    );
    assert!((value(&r, "plant.y", 5.0)? - 1.0).abs() < 1e-2);
    Ok(())
}

/// A sampled integrator of `u = t` at 0.1 s: forward Euler from tick to tick,
/// `x_{k+1} = x_k + 0.1·t_k`, its output held between ticks.
#[test]
fn sampled_block_ticks_by_forward_euler() -> Res {
    let mut scene = components_only();
    scene.add_component(
        ComponentDecl::new("dig", Sampled::new(0.1, Integrator::default())).input("u", "time"),
    );
    let r = scene
        .build()?
        .simulate(&SimOptions::new(1.0).output_steps(true))?;
    for k in 1..10 {
        let t = 0.1 * k as f64 + 0.05;
        // Output at tick k is x_k = 0.1·Σ_{i<k} 0.1·i.
        let xk: f64 = (0..k).map(|i| 0.1 * 0.1 * i as f64).sum();
        assert!(
            (value(&r, "dig.y", t)? - xk).abs() < 1e-12,
            "tick {k}: {} vs {xk}; times {:?}",
            value(&r, "dig.y", t)?,
            r.time().iter().take(8).collect::<Vec<_>>()
        );
    }
    Ok(())
}

/// An `Input` component set between steps by the host.
#[test]
fn input_component_is_set_by_the_host() -> Res {
    let mut scene = components_only();
    scene
        .add_component(ComponentDecl::new("cmd", Input { start: 1.0 }))
        .add_component(ComponentDecl::new("int", Integrator::default()).input("u", "cmd.y"));
    let model = scene.build()?;
    let mut sim = model.simulation(&SimOptions::new(2.0))?;
    sim.advance_to(1.0)?;
    sim.set_input("cmd", &[-3.0])?;
    sim.advance_to(2.0)?;
    let r = sim.into_result();
    // 1·1 s, then −3·1 s.
    assert!((value(&r, "int.y", 2.0)? + 2.0).abs() < 1e-9);
    // The components' signals are exported like the others.
    let path = std::env::temp_dir().join(format!("blocks_input_{}.csv", std::process::id()));
    r.write_csv(&path)?;
    let header = std::fs::read_to_string(&path)?
        .lines()
        .next()
        .unwrap_or_default()
        .to_string();
    std::fs::remove_file(&path)?;
    assert!(
        header.contains("int.y") && header.contains("int.x") && header.contains("cmd.y"),
        "{header}"
    );
    Ok(())
}

/// A user component whose output turns NaN at t > 0.5 s.
#[derive(Debug)]
struct Breaks;

impl Component for Breaks {
    fn kind(&self) -> &'static str {
        "Breaks"
    }
    fn inputs(&self) -> Vec<PortSpec> {
        vec![]
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        vec![OutputSpec::new("y", "1", false)]
    }
    fn states(&self) -> Vec<StateSpec> {
        vec![StateSpec::new("x", "1", 0.0, 1.0)]
    }
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]) {
        y[0] = if io.t > 0.5 { f64::NAN } else { io.x[0] };
    }
    fn derivatives(&self, _io: &ComponentIo<'_>, xdot: &mut [f64], _f: &mut [f64]) {
        xdot[0] = 1.0;
    }
}

/// A user component that panics at t > 0.5 s.
#[derive(Debug)]
struct Panics;

impl Component for Panics {
    fn kind(&self) -> &'static str {
        "Panics"
    }
    fn inputs(&self) -> Vec<PortSpec> {
        vec![]
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        vec![OutputSpec::new("y", "1", false)]
    }
    fn states(&self) -> Vec<StateSpec> {
        vec![StateSpec::new("x", "1", 0.0, 1.0)]
    }
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]) {
        assert!(io.t <= 0.5, "the component gave up");
        y[0] = io.x[0];
    }
    fn derivatives(&self, _io: &ComponentIo<'_>, xdot: &mut [f64], _f: &mut [f64]) {
        xdot[0] = 1.0;
    }
}

#[test]
fn a_failing_component_ends_the_run_with_its_name_and_time() -> Res {
    for (decl, what) in [
        (ComponentDecl::new("bad", Breaks), "NaN"),
        (ComponentDecl::new("bad", Panics), "gave up"),
    ] {
        let mut scene = components_only();
        scene.add_component(decl);
        let err = scene
            .build()?
            .simulate(&SimOptions::new(1.0))
            .expect_err("the component fails after 0.5 s");
        let text = err.to_string();
        assert!(text.contains("`bad`") && text.contains(what), "{text}");
        // Results up to the failure (the last accepted step before 0.5 s; the component's
        // state is linear, so the steps are long).
        let t_last = *err.partial.time().last().ok_or("no points")?;
        assert!(t_last > 0.0 && t_last <= 0.5, "{t_last}");
    }
    Ok(())
}

#[test]
fn wiring_errors_are_named() -> Res {
    let mut scene = components_only();
    scene
        .add_component(ComponentDecl::new("a", Gain { k: 2.0 }).input("u", "b.y"))
        .add_component(ComponentDecl::new("b", Gain { k: 2.0 }).input("u", "a.y"))
        .add_component(ComponentDecl::new("c", Gain { k: 1.0 }).input("u", "a.yy"))
        .add_component(ComponentDecl::new("d", Gain { k: 1.0 }))
        .add_component(
            ComponentDecl::new("e", Gain { k: 1.0 })
                .input("v", 1.0)
                .input("u", 1.0),
        );
    let errs = scene.build().expect_err("bad wiring").0;
    let text: Vec<String> = errs.iter().map(|e| e.to_string()).collect();
    let has = |s: &str| text.iter().any(|t| t.contains(s));
    assert!(
        has("algebraic loop through components `a`, `b`")
            || has("algebraic loop through components `b`, `a`"),
        "{text:?}"
    );
    assert!(
        has("unknown signal `a.yy`") && has("did you mean `a.y`"),
        "{text:?}"
    );
    assert!(
        has("component `d` (Gain): input `u` is not wired"),
        "{text:?}"
    );
    assert!(has("component `e` (Gain) has no input `v`"), "{text:?}");
    // A state in the loop breaks it.
    let mut ok = components_only();
    ok.add_component(ComponentDecl::new("a", Gain { k: -2.0 }).input("u", "b.y"))
        .add_component(ComponentDecl::new("b", Integrator::default()).input("u", "a.y"));
    ok.build()?;
    Ok(())
}

/// An added mass `k` on a flange: the force `−k·a` of the flange's own acceleration.
#[derive(Debug)]
struct AddedMass {
    k: f64,
}

impl Component for AddedMass {
    fn kind(&self) -> &'static str {
        "AddedMass"
    }
    fn inputs(&self) -> Vec<PortSpec> {
        vec![]
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        vec![]
    }
    fn flanges(&self) -> Vec<modia3d::core::FlangeSpec> {
        vec![modia3d::core::FlangeSpec {
            joint: "slide".into(),
            coordinate: None,
            inertia: 0.0,
        }]
    }
    fn reads_flange_acceleration(&self) -> bool {
        true
    }
    fn outputs_at(&self, _io: &ComponentIo<'_>, _y: &mut [f64]) {}
    fn derivatives(&self, io: &ComponentIo<'_>, _xdot: &mut [f64], f: &mut [f64]) {
        f[0] = -self.k * io.flanges[0].acceleration;
    }
}

/// Accelerations as signals: a mass `m` falling along a vertical slide reads `der(slide.v)`
/// = −g; with an added mass `k` on its flange (a force `−k·a` of the acceleration it reads,
/// part of the implicit equations) it falls at `−m·g/(m + k)`. An added mass larger than the
/// mass makes the start's fixed point diverge: a typed error naming the cure.
#[test]
fn accelerations_are_readable() -> Res {
    let (m, g) = (2.0, 9.81);
    let scene = |k: Option<f64>| {
        let mut scene = components_only();
        scene
            .add(Object3D::new("mass").solid(
                Solid::new(Shape::Sphere { diameter: 0.1 }).mass_properties(
                    m,
                    Vector3::zeros(),
                    Matrix3::from_diagonal_element(0.01),
                ),
            ))
            .add_joint(Joint::new(
                "slide",
                "world",
                "mass",
                JointKind::prismatic(3),
            ))
            .add_component(ComponentDecl::new("acc", Gain { k: 1.0 }).input("u", "der(slide.v)"));
        if let Some(k) = k {
            scene.add_component(ComponentDecl::new("added", AddedMass { k }));
        }
        scene
    };
    let r = scene(None)
        .build()?
        .simulate(&SimOptions::new(0.5).quiet(true))?;
    for a in r.signal("acc.y")?.values() {
        assert!((a + g).abs() < 1e-9, "{a}");
    }
    let k = 1.0;
    let r = scene(Some(k))
        .build()?
        .simulate(&SimOptions::new(0.5).tolerance(1e-8).quiet(true))?;
    let expected = -m * g / (m + k);
    // At output points the accelerations come from the consistent derivatives (fixed point
    // to 1e-12); the fall's position follows to the run's tolerance.
    for a in r.signal("acc.y")?.values() {
        assert!((a - expected).abs() < 1e-9, "{a} vs {expected}");
    }
    let z = value(&r, "slide.s", 0.5)?;
    assert!((z - 0.5 * expected * 0.25).abs() < 1e-7, "{z}");
    let err = scene(Some(3.0 * m))
        .build()?
        .simulate(&SimOptions::new(0.5).quiet(true))
        .expect_err("the fixed point diverges");
    assert!(
        matches!(err.kind, SimErrorKind::AccelerationLoop { .. }),
        "{err}"
    );
    // An unknown derivative is a build error naming it.
    let mut bad = components_only();
    bad.add_component(ComponentDecl::new("acc", Gain { k: 1.0 }).input("u", "der(slide.vv)"));
    let text = bad.build().expect_err("unknown").to_string();
    assert!(text.contains("der(slide.vv)"), "{text}");
    Ok(())
}

/// Flanges on every scalar coordinate of multi-coordinate joints: a planar joint (`x`, `y`,
/// `phi`) and a cylindrical one (`phi`, `s`), each coordinate driven by its own force source
/// (a `Drive` with ratio 1 and no rotor). A body with its centre of mass at its origin then
/// accelerates along each coordinate as `F/m` or `T/I` on its own: `q = ½·(F/m)·t²`
/// (closed form; the run's error, rtol 1e-9, is far below the 1e-7 asked), and
/// `der(<joint>.<velocity>)` reads the same acceleration.
#[test]
fn flanges_drive_each_coordinate_of_multi_coordinate_joints() -> Res {
    let (m, i_zz) = (2.0, 0.05);
    let body = |name: &str| {
        Object3D::new(name).solid(Solid::new(Shape::Sphere { diameter: 0.1 }).mass_properties(
            m,
            Vector3::zeros(),
            Matrix3::from_diagonal_element(i_zz),
        ))
    };
    let mut scene = SceneDesc::new();
    scene
        .add(Object3D::new("world").scene(SceneOptions {
            gravity: Vector3::zeros(),
            ..Default::default()
        }))
        .add(body("puck"))
        .add(body("sleeve"))
        .add_joint(Joint::new("plane", "world", "puck", JointKind::planar(3)))
        .add_joint(Joint::new(
            "cyl",
            "world",
            "sleeve",
            JointKind::cylindrical(1),
        ));
    let drives = [
        ("plane", "x", 1.0),
        ("plane", "y", -2.0),
        ("plane", "phi", 0.3),
        ("cyl", "phi", -0.2),
        ("cyl", "s", 4.0),
    ];
    for (j, c, f) in drives {
        let name = format!("{j}_{c}");
        scene.add_component(
            ComponentDecl::new(
                &name,
                modia3d::core::blocks::Drive::rigid(j, 1.0, 0.0).coordinate(c),
            )
            .input("tau", f),
        );
    }
    scene.add_component(ComponentDecl::new("ay", Gain { k: 1.0 }).input("u", "der(plane.vy)"));
    let r = scene
        .build()?
        .simulate(&SimOptions::new(1.0).tolerance(1e-9).quiet(true))?;
    let t = 1.0;
    for (j, c, f) in drives {
        let inertia = if c == "phi" { i_zz } else { m };
        let expected = 0.5 * f / inertia * t * t;
        let got = value(&r, &format!("{j}.{c}"), t)?;
        assert!(
            (got - expected).abs() < 1e-7,
            "{j}.{c}: {got} vs {expected}"
        );
    }
    assert!((value(&r, "ay.y", 0.5)? + 2.0 / m).abs() < 1e-9);
    // A coordinate the joint lacks is a build error naming the flange.
    let mut bad = SceneDesc::new();
    bad.add(Object3D::new("world").scene(SceneOptions::default()))
        .add(body("puck"))
        .add_joint(Joint::new("plane", "world", "puck", JointKind::planar(3)))
        .add_component(
            ComponentDecl::new(
                "d",
                modia3d::core::blocks::Drive::rigid("plane", 1.0, 0.0).coordinate("z"),
            )
            .input("tau", 1.0),
        );
    let text = bad.build().expect_err("no coordinate z").to_string();
    assert!(text.contains("`d`") && text.contains("z"), "{text}");
    Ok(())
}
