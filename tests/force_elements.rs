//! Force elements after Modia3D (Bushing, SpringDamperPtP with force laws, WorldForce,
//! WorldTorque) and the gravity fields (none, point gravity), each against a closed form or a
//! conservation law through the public API.
//!
//! Tolerances: IDA's error control is local; over a run the global error grows with the number
//! of steps and the problem's stability. Every run below is at `rtol` 1e-11 or tighter with
//! `atol` well below the signal's size, so its global error is expected near 1e-10 of the
//! signal's scale; the bounds (1e-8 absolute on O(0.1) signals, 1e-9 relative on an orbit's
//! period) leave a factor of at least 10 and would fail for a wrong law, sign, unit or frame
//! (which all give errors of the signal's own size).

use modia3d::core::*;
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

/// A world without gravity.
fn world_no_gravity() -> Object3D {
    Object3D::new("world").scene(SceneOptions {
        gravity_field: Some(GravityField::None),
        ..Default::default()
    })
}

fn body(name: &str, mass: f64, inertia: Matrix3<f64>) -> Object3D {
    Object3D::new(name).solid(Solid::default().mass_properties(mass, Vector3::zeros(), inertia))
}

fn run(s: &SceneDesc, stop: f64, rtol: f64, atol: f64, dt: f64) -> SimulationResult {
    s.build()
        .unwrap()
        .simulate(
            &SimOptions::new(stop)
                .tolerance(rtol)
                .atol(atol)
                .interval(dt)
                .progress(false),
        )
        .unwrap()
}

/// The damped oscillator `m ẍ + d ẋ + k x = −F0` from `x0`, `ẋ0`: its solution at `t`.
fn damped(m: f64, d: f64, k: f64, f0: f64, x0: f64, v0: f64, t: f64) -> f64 {
    let xe = -f0 / k;
    let delta = d / (2.0 * m);
    let wd = (k / m - delta * delta).sqrt();
    let a = x0 - xe;
    let b = (v0 + delta * a) / wd;
    xe + (-delta * t).exp() * (a * (wd * t).cos() + b * (wd * t).sin())
}

/// Bushing on a prismatic mass, no gravity: translational spring k = 100 N/m, damper
/// d = 2 N·s/m, nominal force 5 N along x, m = 1 kg: `ẍ + 2ẋ + 100x = −5` (the nominal force
/// pushes obj1 along +x and obj2 back). The slider's other axes are locked, so the bushing's
/// y, z and rotational laws (also set) only load the joint.
#[test]
fn bushing_translational_oscillator_matches_closed_form() {
    let (m, k, d, f0, x0, v0) = (1.0, 100.0, 2.0, 5.0, 0.1, -0.3);
    let mut s = SceneDesc::new();
    s.add(world_no_gravity())
        .add(body("slider", m, Matrix3::identity() * 0.01))
        .add_joint(
            Joint::new("slide", "world", "slider", JointKind::prismatic(1))
                .init_position(x0)
                .init_velocity(v0),
        );
    let mut b = Bushing::new("mount", "world", "slider")
        .stiffness([k, 50.0, 50.0])
        .damping([d, 1.0, 1.0])
        .rot_stiffness([3.0; 3]);
    b.nominal_force = Vector3::new(f0, 0.0, 0.0);
    s.add_force(ForceElement::from(b));
    let res = run(&s, 5.0, 1e-12, 1e-14, 0.01);
    let x = res.signal("slide.s").unwrap();
    let mut worst = 0.0f64;
    for (k_, &t) in res.time().iter().enumerate() {
        let err = x.at(k_).unwrap()[0] - damped(m, d, k, f0, x0, v0, t);
        worst = worst.max(err.abs());
    }
    // The amplitude is 0.15 m: 1e-8 is ~1e-7 of it (see the module's header).
    assert!(worst < 1e-8, "largest error {worst:e} m");
    eprintln!("translational bushing: largest error {worst:e} m");
    // The signals: r is the slider's position in obj1 = world, the force on obj2 is
    // −(F0 + k x + d ẋ) along x and 0 in y, z.
    let (r, f) = (
        res.signal("mount.r").unwrap(),
        res.signal("mount.force").unwrap(),
    );
    let v = res.signal("slide.v").unwrap();
    let n = res.time().len() / 2;
    let (xn, vn) = (x.at(n).unwrap()[0], v.at(n).unwrap()[0]);
    assert!((r.at(n).unwrap()[0] - xn).abs() < 1e-15);
    assert!((f.at(n).unwrap()[0] + f0 + k * xn + d * vn).abs() < 1e-12);
    assert_eq!(f.unit, "N");
    assert!(res.signal_names().contains(&"mount.torque".to_string()));
}

/// A body on a revolute joint about x (I = 0.5 kg·m²) held by a large-angle bushing with
/// torsional stiffness 8 N·m/rad and damping 0.4 N·m·s/rad, released at 1 rad: in the Cardan
/// formulation a rotation about obj1's x axis alone is α = φ exactly and the moment acts
/// about x, so `I φ̈ + 0.4 φ̇ + 8 φ = 0` holds at any amplitude.
#[test]
fn large_angle_bushing_torsional_oscillator_matches_closed_form() {
    let (i, k, d, phi0) = (0.5, 8.0, 0.4, 1.0);
    let mut s = SceneDesc::new();
    s.add(world_no_gravity())
        .add(body(
            "rotor",
            2.0,
            Matrix3::from_diagonal(&Vector3::new(i, 0.7, 0.9)),
        ))
        .add_joint(Joint::new("rev", "world", "rotor", JointKind::revolute(1)).init_position(phi0))
        .add_force(ForceElement::from(
            Bushing::new("tors", "world", "rotor")
                .rot_stiffness([k, 0.0, 0.0])
                .rot_damping([d, 0.0, 0.0])
                .large_angles(true),
        ));
    let res = run(&s, 6.0, 1e-12, 1e-14, 0.01);
    let phi = res.signal("rev.phi").unwrap();
    let angles = res.signal("tors.angles").unwrap();
    let mut worst = 0.0f64;
    for (n, &t) in res.time().iter().enumerate() {
        let exact = damped(i, d, k, 0.0, phi0, 0.0, t);
        worst = worst.max((phi.at(n).unwrap()[0] - exact).abs());
        assert!((angles.at(n).unwrap()[0] - phi.at(n).unwrap()[0]).abs() < 1e-12);
    }
    // Amplitude 1 rad: 1e-8 absolute (see the module's header).
    assert!(worst < 1e-8, "largest error {worst:e} rad");
    eprintln!("torsional bushing: largest error {worst:e} rad");
}

/// Small-angle bushing (Modia3D's default): the angle about x is `R[2,1] = sin φ` of the
/// relative rotation, so the torque is `−k sin φ` and `½ I φ̇² − k cos φ` is conserved without
/// damping, at 0.8 rad where `sin φ` and `φ` differ by 10 %.
#[test]
fn small_angle_bushing_conserves_its_energy() {
    let (i, k, phi0) = (0.5, 8.0, 0.8);
    let mut s = SceneDesc::new();
    s.add(world_no_gravity())
        .add(body("rotor", 1.0, Matrix3::identity() * i))
        .add_joint(Joint::new("rev", "world", "rotor", JointKind::revolute(1)).init_position(phi0))
        .add_force(ForceElement::from(
            Bushing::new("tors", "world", "rotor").rot_stiffness([k; 3]),
        ));
    let res = run(&s, 5.0, 1e-11, 1e-13, 0.01);
    let (phi, w) = (res.signal("rev.phi").unwrap(), res.signal("rev.w").unwrap());
    let energy = |n: usize| {
        let (p, w) = (phi.at(n).unwrap()[0], w.at(n).unwrap()[0]);
        0.5 * i * w * w - k * p.cos()
    };
    let e0 = energy(0);
    let scale = k * (1.0 - phi0.cos()); // the energy exchanged
    let drift = (0..res.time().len())
        .map(|n| (energy(n) - e0).abs())
        .fold(0.0, f64::max);
    assert!(
        drift < 1e-8 * scale,
        "energy drift {drift:e} J of {scale} J"
    );
    eprintln!(
        "small-angle bushing: energy drift {:e} relative",
        drift / scale
    );
    // The linear law would give a different period: the small-angle torque is k sin φ.
    let angle = res.signal("tors.angles").unwrap();
    assert!((angle.at(0).unwrap()[0] - phi0.sin()).abs() < 1e-15);
}

/// A large-angle bushing on a spherical joint with three different torsional stiffnesses,
/// no damping, deflected by tens of degrees about all three axes: the moments are the
/// generalised forces of the Cardan angles (τ = J⁻ᵀ m), so
/// `½ ωᵀ I ω + Σ ½ k_i angle_i²` is conserved. (Modia3D's τ = J m would not conserve it.)
#[test]
fn large_angle_bushing_conserves_energy_in_three_axes() {
    let inertia = Matrix3::from_diagonal(&Vector3::new(0.1, 0.2, 0.3));
    let k = [3.0, 5.0, 7.0];
    let mut s = SceneDesc::new();
    s.add(world_no_gravity())
        .add(body("gimbal", 1.0, inertia))
        .add_joint(Joint::new(
            "ball",
            "world",
            "gimbal",
            JointKind::Spherical {
                rot: FreeRotation::Cardan([0.5, 0.4, -0.3]),
                w: Vector3::new(0.3, -0.5, 0.8),
            },
        ))
        .add_force(ForceElement::from(
            Bushing::new("mount", "world", "gimbal")
                .rot_stiffness(k)
                .large_angles(true),
        ));
    let res = run(&s, 4.0, 1e-11, 1e-13, 0.01);
    let (w, rot) = (
        res.signal("gimbal.w_abs").unwrap(),
        res.signal("gimbal.R_abs").unwrap(),
    );
    let angles = res.signal("mount.angles").unwrap();
    let energy = |n: usize| {
        let rm = Matrix3::from_row_slice(rot.at(n).unwrap());
        let w = Vector3::from_column_slice(w.at(n).unwrap());
        let a = angles.at(n).unwrap();
        0.5 * w.dot(&(rm * inertia * rm.transpose() * w))
            + (0..3).map(|i| 0.5 * k[i] * a[i] * a[i]).sum::<f64>()
    };
    let e0 = energy(0);
    let drift = (0..res.time().len())
        .map(|n| (energy(n) - e0).abs())
        .fold(0.0, f64::max);
    assert!(drift < 1e-8 * e0, "energy drift {drift:e} J of {e0} J");
    eprintln!(
        "large-angle bushing: energy drift {:e} relative",
        drift / e0
    );
    // The motion reaches large angles, where J⁻ᵀ and J differ.
    let a_max = (0..res.time().len())
        .map(|n| angles.at(n).unwrap()[1].abs())
        .fold(0.0, f64::max);
    assert!(a_max > 0.3, "β reached only {a_max} rad");
}

/// At β = 90° the large-angle formulation is singular: the run stops with a typed error
/// naming the bushing (no NaN state).
#[test]
fn large_angle_bushing_at_gimbal_lock_is_a_typed_error() {
    let mut s = SceneDesc::new();
    s.add(world_no_gravity())
        .add(body("gimbal", 1.0, Matrix3::identity() * 0.1))
        .add_joint(Joint::new(
            "ball",
            "world",
            "gimbal",
            JointKind::Spherical {
                rot: FreeRotation::Cardan([0.0, PI / 2.0, 0.0]),
                w: Vector3::zeros(),
            },
        ))
        .add_force(ForceElement::from(
            Bushing::new("mount", "world", "gimbal")
                .rot_stiffness([1.0; 3])
                .large_angles(true),
        ));
    let err = s
        .build()
        .unwrap()
        .simulate(&SimOptions::new(1.0).progress(false))
        .unwrap_err();
    match &err.kind {
        SimErrorKind::ForceElement {
            element, reason, ..
        } => {
            assert!(element.contains("bushing `mount`"), "{element}");
            assert!(reason.contains("90°"), "{reason}");
        }
        other => panic!("expected a force-element error, got {other}"),
    }
}

/// A cubic spring `f(x) = k x + k3 x³` between the world origin and a slider on x (from its
/// unstretched length 0.5 m, stretched to 0.8 m), no damping: `½ m v² + ½ k x² + ¼ k3 x⁴` with
/// `x = L − L0` is conserved; the `tension` signal is the law.
#[test]
fn nonlinear_spring_damper_ptp_conserves_energy() {
    let (m, k, k3, l0, s0) = (2.0, 40.0, 2000.0, 0.5, 0.8);
    let mut s = SceneDesc::new();
    s.add(world_no_gravity())
        .add(body("mass", m, Matrix3::identity() * 0.01))
        .add_joint(Joint::new("slide", "world", "mass", JointKind::prismatic(1)).init_position(s0))
        .add_force(ForceElement::SpringDamperPtP {
            name: "cubic".into(),
            obj1: "world".into(),
            obj2: "mass".into(),
            length0: l0,
            spring: Law::new(move |x| k * x + k3 * x * x * x),
            damper: Law::Linear(0.0),
        });
    let res = run(&s, 3.0, 1e-11, 1e-13, 0.005);
    let (x, v) = (
        res.signal("slide.s").unwrap(),
        res.signal("slide.v").unwrap(),
    );
    let (len, tension) = (
        res.signal("cubic.length").unwrap(),
        res.signal("cubic.tension").unwrap(),
    );
    let energy = |n: usize| {
        let (x, v) = (x.at(n).unwrap()[0] - l0, v.at(n).unwrap()[0]);
        0.5 * m * v * v + 0.5 * k * x * x + 0.25 * k3 * x.powi(4)
    };
    let e0 = energy(0);
    let mut drift = 0.0f64;
    let mut x_min = f64::INFINITY;
    for n in 0..res.time().len() {
        drift = drift.max((energy(n) - e0).abs());
        let s_n = x.at(n).unwrap()[0];
        x_min = x_min.min(s_n);
        assert!((len.at(n).unwrap()[0] - s_n).abs() < 1e-14);
        let dx = s_n - l0;
        assert!((tension.at(n).unwrap()[0] - (k * dx + k3 * dx.powi(3))).abs() < 1e-10);
    }
    assert!(drift < 1e-8 * e0, "energy drift {drift:e} J of {e0} J");
    eprintln!("cubic spring: energy drift {:e} relative", drift / e0);
    // Symmetric potential: the slider swings to 0.5 − 0.3 m.
    assert!((x_min - (l0 - (s0 - l0))).abs() < 1e-6, "x_min {x_min}");
}

/// A nonlinear damper law `g(L̇) = c L̇ |L̇|` (quadratic damping) dissipates exactly the work it
/// does: `E(t) + ∫ g(L̇) L̇ dt` stays constant (trapezoidal sum on a fine grid, hence 1e-6).
#[test]
fn nonlinear_damper_law_dissipates_its_work() {
    let (m, k, c, l0, s0) = (1.0, 100.0, 3.0, 0.5, 0.7);
    let mut s = SceneDesc::new();
    s.add(world_no_gravity())
        .add(body("mass", m, Matrix3::identity() * 0.01))
        .add_joint(Joint::new("slide", "world", "mass", JointKind::prismatic(1)).init_position(s0))
        .add_force(ForceElement::SpringDamperPtP {
            name: "sd".into(),
            obj1: "world".into(),
            obj2: "mass".into(),
            length0: l0,
            spring: Law::Linear(k),
            damper: Law::new(move |v| c * v * v.abs()),
        });
    let dt = 1e-4;
    let res = run(&s, 2.0, 1e-11, 1e-13, dt);
    let (x, v) = (
        res.signal("slide.s").unwrap(),
        res.signal("slide.v").unwrap(),
    );
    let energy = |n: usize| {
        let (x, v) = (x.at(n).unwrap()[0] - l0, v.at(n).unwrap()[0]);
        0.5 * m * v * v + 0.5 * k * x * x
    };
    let power = |n: usize| {
        let v = v.at(n).unwrap()[0];
        c * v * v * v.abs()
    };
    let (e0, mut work, mut worst) = (energy(0), 0.0, 0.0f64);
    for n in 1..res.time().len() {
        let h = res.time()[n] - res.time()[n - 1];
        work += 0.5 * h * (power(n) + power(n - 1));
        worst = worst.max((energy(n) + work - e0).abs());
    }
    assert!(
        energy(res.time().len() - 1) < 0.5 * e0,
        "the damper dissipates"
    );
    assert!(
        worst < 1e-6 * e0,
        "energy balance off by {worst:e} J of {e0} J"
    );
    eprintln!("quadratic damper: energy balance {:e} relative", worst / e0);
}

/// Constant world force on a free body: `r(t) = r0 + v0 t + F/(2m) t²` (a quadratic, which
/// IDA's BDF integrates without truncation error: 1e-9 is roundoff with margin), and the
/// rotation stays still.
#[test]
fn constant_world_force_on_a_free_body() {
    let (m, f) = (2.0, Vector3::new(1.0, -2.0, 3.0));
    let (r0, v0) = (Vector3::new(0.1, 0.2, 0.3), Vector3::new(0.5, 0.0, -0.4));
    let mut s = SceneDesc::new();
    s.add(world_no_gravity())
        .add(body("puck", m, Matrix3::identity() * 0.1))
        .add_joint(Joint::new(
            "free",
            "world",
            "puck",
            JointKind::FreeMotion {
                r: r0,
                rot: FreeRotation::Cardan([0.2, 0.0, 0.0]),
                v: v0,
                w: Vector3::zeros(),
            },
        ))
        .add_force(ForceElement::WorldForce {
            name: "push".into(),
            object: "puck".into(),
            force: VectorLaw::Constant(f),
            resolved_in: None,
        });
    let res = run(&s, 2.0, 1e-10, 1e-12, 0.1);
    let r = res.signal("puck.r_abs").unwrap();
    let w = res.signal("puck.w_abs").unwrap();
    for (n, &t) in res.time().iter().enumerate() {
        let exact = r0 + v0 * t + f / (2.0 * m) * t * t;
        let got = Vector3::from_column_slice(r.at(n).unwrap());
        assert!((got - exact).norm() < 1e-9, "t = {t}: {got} vs {exact}");
        assert!(Vector3::from_column_slice(w.at(n).unwrap()).norm() < 1e-12);
    }
}

/// A world force given by a closure of time, `F = (F0 sin ωt, 0, 0)`, on a body at rest:
/// `x(t) = F0/(m ω²) (ωt − sin ωt)`.
#[test]
fn world_force_closure_of_time() {
    let (m, f0, om) = (0.5, 2.0, 3.0);
    let mut s = SceneDesc::new();
    s.add(world_no_gravity())
        .add(body("puck", m, Matrix3::identity() * 0.1))
        .add_joint(Joint::new("free", "world", "puck", JointKind::free()))
        .add_force(ForceElement::WorldForce {
            name: "push".into(),
            object: "puck".into(),
            force: VectorLaw::new(move |t, _| Vector3::new(f0 * (om * t).sin(), 0.0, 0.0)),
            resolved_in: None,
        });
    let res = run(&s, 3.0, 1e-12, 1e-14, 0.05);
    let r = res.signal("puck.r_abs").unwrap();
    // The element's signal: the force at each output time, resolved in world [N].
    let push = res.signal("push.force").unwrap();
    assert_eq!(push.unit, "N");
    let mut worst = 0.0f64;
    for (n, &t) in res.time().iter().enumerate() {
        let exact = f0 / (m * om * om) * (om * t - (om * t).sin());
        worst = worst.max((r.at(n).unwrap()[0] - exact).abs());
        let f = push.at(n).unwrap();
        assert!((f[0] - f0 * (om * t).sin()).abs() < 1e-15 && f[1] == 0.0 && f[2] == 0.0);
    }
    // x reaches 1.3 m: 1e-8 absolute (see the module's header).
    assert!(worst < 1e-8, "largest error {worst:e} m");
    eprintln!("world force closure: largest error {worst:e} m");
}

/// A torque resolved in the body itself, along its z axis (the largest principal axis), on a
/// body spinning about that axis and tilted in world: the spin axis stays fixed in world and
/// `ω(t) = (ω0 + T t / I_zz) · R e_z`. Resolving the torque in world instead would tilt it.
#[test]
fn world_torque_resolved_in_the_body_spins_it_up() {
    let (izz, tq, w0) = (0.3, 0.6, 2.0);
    let inertia = Matrix3::from_diagonal(&Vector3::new(0.1, 0.2, izz));
    let tilt = [0.3, -0.2, 0.0];
    let mut s = SceneDesc::new();
    s.add(world_no_gravity())
        .add(body("top", 1.0, inertia))
        .add_joint(Joint::new(
            "free",
            "world",
            "top",
            JointKind::FreeMotion {
                r: Vector3::zeros(),
                rot: FreeRotation::Cardan(tilt),
                v: Vector3::zeros(),
                w: Vector3::new(0.0, 0.0, w0), // resolved in the body
            },
        ))
        .add_force(ForceElement::WorldTorque {
            name: "spin".into(),
            object: "top".into(),
            torque: VectorLaw::from([0.0, 0.0, tq]),
            resolved_in: Some("top".into()),
        });
    let res = run(&s, 2.0, 1e-11, 1e-13, 0.1);
    let w = res.signal("top.w_abs").unwrap();
    // The torque's signal is resolved in world: along the fixed spin axis (the body's z axis
    // stays there), as accurate as the body's orientation.
    let spin = res.signal("spin.torque").unwrap();
    let axis = Rotation::Cardan(tilt).to_matrix() * Vector3::z();
    for (n, &t) in res.time().iter().enumerate() {
        let exact = axis * (w0 + tq * t / izz);
        let got = Vector3::from_column_slice(w.at(n).unwrap());
        assert!((got - exact).norm() < 1e-8, "t = {t}: {got} vs {exact}");
        let torque = Vector3::from_column_slice(spin.at(n).unwrap());
        assert!(
            (torque - axis * tq).norm() < 1e-8,
            "t = {t}: {torque} vs {}",
            axis * tq
        );
    }
}

/// Point gravity, μ = 1 m³/s², a body on a circular orbit of radius 1 m about a centre away
/// from the world origin: the period is `2π sqrt(r³/μ)`. The period is measured over 10 orbits
/// from upward zero crossings of y − y_c, located by bisection on IDA's own interpolating
/// polynomial (`dense_output`), to 1e-9 relative.
#[test]
fn point_gravity_circular_orbit_period() {
    let (mu, radius): (f64, f64) = (1.0, 1.0);
    let centre = Vector3::new(0.5, -0.25, 2.0);
    let v = (mu / radius).sqrt();
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions {
        gravity_field: Some(GravityField::Point { mu, centre }),
        ..Default::default()
    }))
    .add(body("sat", 10.0, Matrix3::identity()))
    .add_joint(Joint::new(
        "free",
        "world",
        "sat",
        JointKind::FreeMotion {
            r: centre + Vector3::new(radius, 0.0, 0.0),
            rot: FreeRotation::Cardan([0.0; 3]),
            v: Vector3::new(0.0, v, 0.0),
            w: Vector3::zeros(),
        },
    ));
    let period = 2.0 * PI * (radius.powi(3) / mu).sqrt();
    let opts = SimOptions::new(10.2 * period)
        .tolerance(1e-14)
        .atol(1e-14)
        .interval(period / 50.0)
        .dense_output(true)
        .max_steps(None)
        .progress(false);
    let res = s.build().unwrap().simulate(&opts).unwrap();
    let y = |t: f64| res.signal_at("sat.r_abs[1]", t).unwrap()[0] - centre.y;
    // Upward crossings of y = y_c: at t = 0 and near every period.
    let crossing = |mut a: f64, mut b: f64| {
        for _ in 0..80 {
            let c = 0.5 * (a + b);
            if y(c) < 0.0 {
                a = c;
            } else {
                b = c;
            }
        }
        0.5 * (a + b)
    };
    let t10 = crossing(9.9 * period, 10.1 * period);
    let measured = t10 / 10.0;
    let err = (measured - period).abs() / period;
    assert!(
        err < 1e-9,
        "period {measured} vs {period}: relative error {err:e}"
    );
    // The radius stays 1 m (a circular orbit): 1e-8.
    let r = res.signal("sat.r_abs").unwrap();
    for n in 0..res.time().len() {
        let d = (Vector3::from_column_slice(r.at(n).unwrap()) - centre).norm();
        assert!((d - radius).abs() < 1e-8, "radius {d}");
    }
    eprintln!("orbit period relative error {err:e}");
}

/// A body's centre of mass at the centre of point gravity is a scene error, not a NaN.
#[test]
fn body_at_the_point_gravity_centre_is_a_scene_error() {
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions {
        gravity_field: Some(GravityField::Point {
            mu: 1.0,
            centre: Vector3::new(0.0, 0.0, 1.0),
        }),
        ..Default::default()
    }))
    .add(body("sat", 1.0, Matrix3::identity()))
    .add_joint(Joint::new(
        "free",
        "world",
        "sat",
        JointKind::FreeMotion {
            r: Vector3::new(0.0, 0.0, 1.0),
            rot: FreeRotation::Cardan([0.0; 3]),
            v: Vector3::zeros(),
            w: Vector3::zeros(),
        },
    ));
    let errs = s.build().unwrap_err();
    assert!(
        matches!(&errs.0[..], [SceneError::AtGravityCentre { object, .. }] if object == "sat"),
        "{errs}"
    );
}

/// Scene checks of the new elements and options, all in one round: unknown objects with a
/// hint, negative coefficients, a non-positive μ, `gravity` and `gravity_field` both set.
#[test]
fn new_elements_are_validated_in_one_round() {
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions {
        gravity: Vector3::new(0.0, 0.0, -1.0),
        gravity_field: Some(GravityField::Point {
            mu: -1.0,
            centre: Vector3::zeros(),
        }),
        ..Default::default()
    }))
    .add(body("block", 1.0, Matrix3::identity()))
    .add_joint(Joint::new("free", "world", "block", JointKind::free()))
    .add_force(ForceElement::from(
        Bushing::new("mount", "world", "blok").stiffness([1.0, -2.0, 1.0]),
    ))
    .add_force(ForceElement::WorldTorque {
        name: "twist".into(),
        object: "block".into(),
        torque: VectorLaw::from([0.0, f64::NAN, 0.0]),
        resolved_in: Some("wrld".into()),
    });
    let text = s.build().unwrap_err().to_string();
    for needle in [
        "sets both `gravity` and `gravity_field`",
        "bushing `mount`'s obj2 names unknown object `blok`",
        "did you mean `block`",
        "stiffness [N/m] along y",
        "WorldTorque on `block`'s resolved_in names unknown object `wrld`",
        "WorldTorque on `block`: value [N·m]",
    ] {
        assert!(text.contains(needle), "missing `{needle}` in:\n{text}");
    }
    // μ is checked when the field is the only gravity given.
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions {
        gravity_field: Some(GravityField::Point {
            mu: 0.0,
            centre: Vector3::zeros(),
        }),
        ..Default::default()
    }));
    let text = s.build().unwrap_err().to_string();
    assert!(text.contains("point gravity's mu"), "{text}");
}

/// A law closure that panics or returns NaN ends the run with a typed error naming the element
/// (the panic caught at the call), with the results up to the failure.
#[test]
fn failing_law_closures_are_typed_errors_naming_the_element() {
    let scene = |spring: Law| {
        let mut s = SceneDesc::new();
        s.add(world_no_gravity())
            .add(body("slider", 1.0, Matrix3::identity()))
            .add_joint(
                Joint::new("slide", "world", "slider", JointKind::prismatic(1)).init_velocity(1.0),
            )
            .add_force(ForceElement::SpringDamperPtP {
                name: "sd".into(),
                obj1: "world".into(),
                obj2: "slider".into(),
                length0: 0.0,
                spring,
                damper: Law::Linear(0.0),
            });
        s.build()
            .unwrap()
            .simulate(&SimOptions::new(1.0).progress(false))
            .unwrap_err()
    };
    let err = scene(Law::new(|x| if x < 0.5 { x } else { panic!("too far") }));
    match &err.kind {
        SimErrorKind::UserPanic {
            element, message, ..
        } => {
            assert!(element.contains("spring-damper `sd`"), "{element}");
            assert_eq!(message, "too far");
        }
        other => panic!("expected a panic error, got {other}"),
    }
    // Up to the failure at x = sin t = 0.5, t = π/6 (the last output point is before it).
    assert!(err
        .partial
        .time()
        .last()
        .is_some_and(|&t| t > 0.4 && t <= PI / 6.0));
    let err = scene(Law::new(|x| if x < 0.5 { x } else { f64::NAN }));
    match &err.kind {
        SimErrorKind::ForceElement {
            element, reason, ..
        } => {
            assert!(element.contains("spring-damper `sd`"), "{element}");
            assert!(reason.contains("spring law returned NaN"), "{reason}");
        }
        other => panic!("expected a force-element error, got {other}"),
    }
}
