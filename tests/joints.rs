//! The joints beyond Revolute/Prismatic/FreeMotion (Spherical, Universal, Cylindrical,
//! Planar), each against an independent closed form or a conservation law, through the
//! public API.

use modia3d::core::*;
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

const G: f64 = 9.81;

fn world(gravity: [f64; 3]) -> Object3D {
    Object3D::new("world").scene(SceneOptions {
        gravity: Vector3::from(gravity),
        ..Default::default()
    })
}

fn explicit(mass: f64, inertia: Matrix3<f64>) -> Solid {
    Solid::default().mass_properties(mass, Vector3::zeros(), inertia)
}

/// Kinetic plus potential energy of rigid parts `(object, mass, inertia about the object's
/// origin = its centre of mass, in its frame)` at every output point, gravity `g`; and the
/// largest kinetic energy (the scale of the exchange between the two, against which drift is
/// measured).
fn energy(
    res: &SimulationResult,
    parts: &[(&str, f64, Matrix3<f64>)],
    g: Vector3<f64>,
) -> (Vec<f64>, f64) {
    let mut e = vec![0.0; res.time().len()];
    let mut kin_max = 0.0f64;
    for (name, m, i) in parts {
        let r = res.signal(&format!("{name}.r_abs")).unwrap();
        let v = res.signal(&format!("{name}.v_abs")).unwrap();
        let w = res.signal(&format!("{name}.w_abs")).unwrap();
        let rot = res.signal(&format!("{name}.R_abs")).unwrap();
        for (k, ek) in e.iter_mut().enumerate() {
            let (r, v, w) = (
                Vector3::from_column_slice(r.at(k).unwrap()),
                Vector3::from_column_slice(v.at(k).unwrap()),
                Vector3::from_column_slice(w.at(k).unwrap()),
            );
            let rm = Matrix3::from_row_slice(rot.at(k).unwrap());
            let iw = rm * i * rm.transpose();
            let kin = 0.5 * m * v.norm_squared() + 0.5 * w.dot(&(iw * w));
            kin_max = kin_max.max(kin);
            *ek += kin - m * g.dot(&r);
        }
    }
    (e, kin_max)
}

/// Largest change of the energy, relative to the largest kinetic energy.
fn max_drift((e, scale): (Vec<f64>, f64)) -> f64 {
    e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max) / scale
}

/// A bob of mass `m` and inertia `inertia` about its centre, `l` below a Spherical joint at the
/// world origin, its rod tilted by `tilt` about y and turning with angular velocity `w_body`
/// (resolved in the tilted pivot frame), run for two periods of a steady orbit at `omega` at
/// rtol 1e-11. Returns the largest azimuth error (the bob starts at −x and should advance as
/// `Ω t`) in revolutions, the largest height error (it should stay at `−l cos tilt`) in `l`,
/// and the result.
fn steady_orbit(
    m: f64,
    inertia: Matrix3<f64>,
    l: f64,
    tilt: f64,
    w_body: Vector3<f64>,
    omega: f64,
) -> (f64, f64, SimulationResult) {
    let period = 2.0 * PI / omega;
    let mut s = SceneDesc::new();
    s.add(world([0.0, 0.0, -G]))
        .add(Object3D::new("pivot"))
        .add(
            Object3D::new("bob")
                .parent("pivot")
                .translation([0.0, 0.0, -l])
                .solid(explicit(m, inertia)),
        )
        .add_joint(Joint::new(
            "ball",
            "world",
            "pivot",
            JointKind::Spherical {
                rot: FreeRotation::Cardan([0.0, tilt, 0.0]),
                w: w_body,
            },
        ));
    let res = s
        .build()
        .unwrap()
        .simulate(
            &SimOptions::new(2.0 * period)
                .tolerance(1e-11)
                .atol(1e-12)
                .interval(period / 50.0)
                .progress(false),
        )
        .unwrap();
    let r = res.signal("bob.r_abs").unwrap();
    let (mut worst_angle, mut worst_height) = (0.0f64, 0.0f64);
    for (k, &t) in res.time().iter().enumerate() {
        let p = Vector3::from_column_slice(r.at(k).unwrap());
        // Azimuth of the bob, starting at π (it starts at −x), unwrapped by the expected one.
        let da = (p.y.atan2(p.x) - PI - omega * t + PI).rem_euclid(2.0 * PI) - PI;
        worst_angle = worst_angle.max(da.abs() / (2.0 * PI));
        worst_height = worst_height.max((p.z + l * tilt.cos()).abs() / l);
    }
    (worst_angle, worst_height, res)
}

/// Conical spherical pendulum. The bob is a solid sphere (isotropic inertia `J` about its
/// centre) at distance `L` below a Spherical joint, turning rigidly about the vertical at
/// `Ω`. Torque balance about the pivot: `Ω ẑ × (I_o Ω ẑ) = r_c × (−m g ẑ)`; with
/// `I_o = J·1 + m L² (1 − u uᵀ)` the isotropic `J` drops out of `ẑ × I_o ẑ`, leaving
/// `Ω² L cos θ = g`: the point-mass period `T = 2π sqrt(L cos θ / g)` holds exactly for the
/// rigid sphere. Checked: the azimuth of the bob grows as `Ω t` and its height stays
/// `−L cos θ`, both to 1e-8 relative over two periods at rtol 1e-11 (IDA's global error is a
/// few rtol per period here; the bound leaves two orders of margin). Precession: with the body
/// also spinning about the rod the orbit would precess; the rigid orbit has no precession, and
/// its absence (the orbit returns to its start after each period) is part of the check.
#[test]
fn spherical_pendulum_conical_orbit_has_the_closed_form_period() {
    let (m, l, d, theta) = (1.5, 0.8, 0.1, 0.6f64);
    let j = 0.4 * m * (d / 2.0) * (d / 2.0);
    let omega = (G / (l * theta.cos())).sqrt();
    // Rod tilted by θ about y: the bob at (−L sin θ, 0, −L cos θ); Ω ẑ resolved in the tilted
    // pivot frame.
    let w = Vector3::new(-theta.sin() * omega, 0.0, theta.cos() * omega);
    let (worst_angle, worst_height, res) =
        steady_orbit(m, Matrix3::identity() * j, l, theta, w, omega);
    println!("conical pendulum: azimuth error {worst_angle:.2e} rev, height {worst_height:.2e} L");
    assert!(
        worst_angle < 1e-8,
        "azimuth error {worst_angle:e} of a revolution"
    );
    assert!(worst_height < 1e-8, "height error {worst_height:e} L");
    // The quaternion stays unit (norm kept as for FreeMotion).
    let q = res.signal("ball.q").unwrap();
    let qn = (0..q.len())
        .map(|k| (q.at(k).unwrap().iter().map(|x| x * x).sum::<f64>().sqrt() - 1.0).abs())
        .fold(0.0, f64::max);
    assert!(qn < 1e-9, "quaternion norm error {qn:e}");
}

/// Steady precession of a spinning symmetric bob on a Spherical joint: inertia `diag(A, A, C)`
/// about its centre (symmetry axis = the rod), rod tilted by α from the vertical, the rod
/// precessing about the vertical at `Ω` while the bob spins about the rod. Torque balance about
/// the pivot for motion that is rigid in the precessing frame, `Ω ẑ × H = r_c × (−m g ẑ)` with
/// `H = A'(ω − ω₃ e₃) + C ω₃ e₃`, `A' = A + m L²`, gives `C ω₃ Ω − A' Ω² cos α = −m g L`
/// (with `C = A` and no spin this is the conical pendulum). For `Ω = 1.5 Ω_conical` the spin
/// component `ω₃ = (A' Ω² cos α − m g L)/(C Ω)` makes the orbit steady: the azimuth advances as
/// `Ω t` and the height stays `−L cos α`, to 1e-8 over two precession periods at rtol 1e-11.
#[test]
fn spinning_bob_on_a_spherical_joint_precesses_at_the_closed_form_rate() {
    let (m, l, a, c, alpha) = (1.5, 0.8, 0.03, 0.05, 0.6f64);
    let omega = 1.5 * (G / (l * alpha.cos())).sqrt();
    let a_pivot = a + m * l * l;
    let w3 = (a_pivot * omega * omega * alpha.cos() - m * G * l) / (c * omega);
    // ω = Ω ẑ + s e₃ with ω·e₃ = w3: s = w3 − Ω cos α; resolved in the tilted pivot frame.
    let spin = w3 - omega * alpha.cos();
    let w_body = Vector3::new(-alpha.sin() * omega, 0.0, alpha.cos() * omega + spin);
    let inertia = Matrix3::from_diagonal(&Vector3::new(a, a, c));
    let (worst_angle, worst_height, _) = steady_orbit(m, inertia, l, alpha, w_body, omega);
    println!("precession: azimuth error {worst_angle:.2e} rev, height {worst_height:.2e} L (spin {spin:.3} rad/s)");
    assert!(
        worst_angle < 1e-8,
        "azimuth error {worst_angle:e} of a revolution"
    );
    assert!(worst_height < 1e-8, "height error {worst_height:e} L");
}

/// Cardan shaft kinematics: input shaft about x at `ω1`, cross (Universal: axis1 = y in the
/// input shaft, axis2 = z in the output shaft), output shaft axis `e = (cos β, sin β, 0)`.
/// For input angle θ the joint angles that keep the output on `e` are
/// `phi2 = asin(sin β cos θ)`, `phi1 = atan2(sin β sin θ, cos β)`; their rates are the
/// derivatives of these closed forms. The output's angular velocity the library computes from
/// the joint's motion subspace must then be `ω1 cos β / (1 − sin²β cos²θ)` along `e` and zero
/// across it, to 1e-9 (relative to ω1): everything is closed form, so only round-off
/// (~1e-15) remains. This checks the joint's velocity map alone, at 24 input angles; the loop
/// test below runs the whole mechanism.
#[test]
fn universal_joint_reproduces_the_cardan_speed_ratio() {
    let (beta, w1) = (0.5f64, 3.0);
    let e = Vector3::new(beta.cos(), beta.sin(), 0.0);
    let mut worst = 0.0f64;
    for k in 0..24 {
        let theta = 2.0 * PI * k as f64 / 24.0 + 0.1;
        let (sb, cb) = beta.sin_cos();
        let (st, ct) = theta.sin_cos();
        let phi2 = (sb * ct).asin();
        let phi1 = (sb * st).atan2(cb);
        let dphi2 = -sb * st * w1 / phi2.cos();
        let dphi1 = sb * cb * ct * w1 / (cb * cb + sb * sb * st * st);
        let inertia = Matrix3::from_diagonal(&Vector3::new(0.1, 0.2, 0.3));
        let mut s = SceneDesc::new();
        s.add(world([0.0, 0.0, 0.0]))
            .add(Object3D::new("shaft1").solid(explicit(1.0, inertia)))
            .add(Object3D::new("shaft2").solid(explicit(1.0, inertia)))
            .add_joint(
                Joint::new("input", "world", "shaft1", JointKind::revolute(1))
                    .init_position(theta)
                    .init_velocity(w1),
            )
            .add_joint(Joint::new(
                "cross",
                "shaft1",
                "shaft2",
                JointKind::Universal {
                    axis1: Vector3::y(),
                    axis2: Vector3::z(),
                    phi1,
                    phi2,
                    w1: dphi1,
                    w2: dphi2,
                },
            ));
        let res = s
            .build()
            .unwrap()
            .simulate(&SimOptions::new(1e-6).progress(false))
            .unwrap();
        let w = Vector3::from_column_slice(res.signal("shaft2.w_abs").unwrap().first().unwrap());
        let ratio = cb / (1.0 - sb * sb * ct * ct);
        let along = w.dot(&e);
        let across = (w - e * along).norm();
        worst = worst.max((along - w1 * ratio).abs() / w1).max(across / w1);
    }
    println!("Cardan shaft: worst speed error {worst:.2e} (relative to ω1)");
    assert!(worst < 1e-9, "speed error {worst:e}");
}

/// The Cardan shaft as the mechanism it is, a closed loop: input shaft on a Revolute about x,
/// cross (Universal: axis1 = y in the input shaft, axis2 = z in the output shaft), output shaft
/// in a bearing (a Revolute about `e = (cos β, sin β, 0)`, the cut joint). The input turns at
/// constant `ω1` (prescribed acceleration 0); the output speed about `e` must follow
/// `ω1 cos β / (1 − sin²β cos²θ)` with `θ = ω1 t` over a revolution. The loop is held by the
/// stabilised constraints to the Newton tolerance of each step, the output speed is a function
/// of the state through the velocity constraints, so its error is of the order of the local
/// error at rtol 1e-11 (~1e-11 · ω1); 1e-9 relative to ω1 leaves two orders.
#[test]
fn cardan_shaft_loop_output_speed_follows_the_closed_form() {
    let (beta, w1) = (0.5f64, 3.0);
    let e = Vector3::new(beta.cos(), beta.sin(), 0.0);
    let inertia = Matrix3::from_diagonal(&Vector3::new(0.1, 0.2, 0.3));
    let mut s = SceneDesc::new();
    s.add(world([0.0, 0.0, -G]))
        .add(Object3D::new("shaft1").solid(explicit(1.0, inertia)))
        .add(Object3D::new("shaft2").solid(explicit(1.0, inertia)))
        .add(
            Object3D::new("mount")
                .parent("world")
                .rotation(Rotation::Cardan([0.0, 0.0, beta])),
        )
        .add_joint(Joint::new("input", "world", "shaft1", JointKind::revolute(1)).init_velocity(w1))
        .add_joint(Joint::new(
            "cross",
            "shaft1",
            "shaft2",
            JointKind::Universal {
                axis1: Vector3::y(),
                axis2: Vector3::z(),
                phi1: 0.0,
                phi2: beta,
                w1: 0.0,
                w2: 0.0,
            },
        ))
        .add_joint(Joint::new("bearing", "mount", "shaft2", JointKind::revolute(1)).cut(true))
        .add_input(Input::joint_acceleration("drive", "input"));
    let model = s.build().unwrap();
    let period = 2.0 * PI / w1;
    let res = model
        .simulate(
            &SimOptions::new(period)
                .tolerance(1e-11)
                .atol(1e-12)
                .interval(period / 100.0)
                .progress(false),
        )
        .unwrap();
    let theta = res.signal("input.phi").unwrap().values();
    let w = res.signal("shaft2.w_abs").unwrap();
    let (sb, cb) = beta.sin_cos();
    let mut worst = 0.0f64;
    for (k, th) in theta.iter().enumerate() {
        let wk = Vector3::from_column_slice(w.at(k).unwrap());
        let along = wk.dot(&e);
        let expected = w1 * cb / (1.0 - sb * sb * th.cos().powi(2));
        worst = worst
            .max((along - expected).abs() / w1)
            .max((wk - e * along).norm() / w1);
    }
    println!(
        "Cardan loop: worst output speed error {worst:.2e} (relative to ω1), input turned {:.4} rad",
        theta.last().unwrap() - theta[0]
    );
    assert!((theta.last().unwrap() - theta[0] - 2.0 * PI).abs() < 1e-9);
    assert!(worst < 1e-9, "speed error {worst:e}");
}

/// Body on a joint whose motion subspace depends on its coordinates (Universal: `S(phi2)`,
/// Planar: `S(phi)`) and on a Spherical joint, without friction or drive: energy is conserved
/// only if the bias `c_J = Ṡ q̇` is right (leaving it out changes the energy at first order).
/// 1e-8 relative to the largest kinetic energy over 3 s at rtol 1e-11 (the drift of a correct
/// model is a few rtol times the energy exchanged; a body falling in the plane exchanges
/// hundreds of joules between the two forms, hence that scale rather than the total).
#[test]
fn joints_with_configuration_dependent_subspace_conserve_energy() {
    let inertia = Matrix3::new(0.2, 0.01, 0.0, 0.01, 0.3, 0.02, 0.0, 0.02, 0.15);
    let g = Vector3::new(0.0, -G * 0.3, -G);
    let kinds = [
        (
            "universal",
            JointKind::Universal {
                axis1: Vector3::new(0.0, 0.0, 1.0),
                axis2: Vector3::new(1.0, 1.0, 0.0),
                phi1: 0.3,
                phi2: -0.4,
                w1: 2.0,
                w2: -1.5,
            },
        ),
        (
            "planar",
            JointKind::Planar {
                normal: Vector3::new(1.0, 0.0, 0.2),
                x: 0.1,
                y: -0.2,
                phi: 0.5,
                vx: 0.7,
                vy: 0.3,
                w: 4.0,
            },
        ),
        (
            "spherical",
            JointKind::Spherical {
                rot: FreeRotation::Cardan([0.3, -0.2, 0.1]),
                w: Vector3::new(1.0, -2.0, 3.0),
            },
        ),
        (
            "cylindrical",
            JointKind::Cylindrical {
                axis: Vector3::new(0.0, 1.0, 1.0),
                phi: 0.2,
                s: 0.1,
                w: 3.0,
                v: 0.5,
            },
        ),
    ];
    for (name, kind) in kinds {
        let mut s = SceneDesc::new();
        s.add(world([g.x, g.y, g.z]))
            .add(Object3D::new("link"))
            .add(
                Object3D::new("mass")
                    .parent("link")
                    .translation([0.3, -0.1, 0.2])
                    .solid(explicit(1.2, inertia)),
            )
            .add_joint(Joint::new("j", "world", "link", kind));
        let res = s
            .build()
            .unwrap()
            .simulate(
                &SimOptions::new(3.0)
                    .tolerance(1e-11)
                    .atol(1e-12)
                    .interval(0.01)
                    .progress(false),
            )
            .unwrap();
        let drift = max_drift(energy(&res, &[("mass", 1.2, inertia)], g));
        println!("{name}: energy drift {drift:.2e}");
        assert!(drift < 1e-8, "{name}: energy drift {drift:e}");
    }
}

/// Cylindrical joint along the vertical under constant inputs on both coordinates: axial force
/// `F` (input on `s`) and torque `τ` (input on `phi`), gravity along the axis. Closed forms
/// `s = s0 + v0 t + (F/m − g) t²/2`, `phi = phi0 + w0 t + (τ/I_zz) t²/2`. Quadratics are
/// reproduced exactly by BDF of order ≥ 2: only Newton and round-off error remain, far below
/// the 1e-9 bound.
#[test]
fn cylindrical_joint_under_constant_force_and_torque() {
    let (m, izz, f, tau) = (2.0, 0.3, 30.0, 0.45);
    let mut s = SceneDesc::new();
    s.add(world([0.0, 0.0, -G]))
        .add(Object3D::new("body").solid(explicit(
            m,
            Matrix3::from_diagonal(&Vector3::new(0.2, 0.25, izz)),
        )))
        .add_joint(Joint::new(
            "cyl",
            "world",
            "body",
            JointKind::Cylindrical {
                axis: Vector3::z(),
                phi: 0.3,
                s: 0.1,
                w: 1.0,
                v: -0.5,
            },
        ))
        .add_input(Input::joint_force("push", "cyl").coordinate("s"))
        .add_input(Input::joint_force("turn", "cyl").coordinate("phi"));
    let model = s.build().unwrap();
    let mut sim = model
        .simulation(
            &SimOptions::new(2.0)
                .tolerance(1e-10)
                .interval(0.1)
                .progress(false),
        )
        .unwrap();
    sim.set_input("push", &[f]).unwrap();
    sim.set_input("turn", &[tau]).unwrap();
    sim.advance_to(2.0).unwrap();
    let res = sim.into_result();
    let (sv, phi) = (
        res.signal("cyl.s").unwrap().values(),
        res.signal("cyl.phi").unwrap().values(),
    );
    let mut worst = 0.0f64;
    for (k, &t) in res.time().iter().enumerate() {
        let se = 0.1 - 0.5 * t + 0.5 * (f / m - G) * t * t;
        let pe = 0.3 + t + 0.5 * tau / izz * t * t;
        worst = worst.max((sv[k] - se).abs()).max((phi[k] - pe).abs());
    }
    println!("cylindrical: max error {worst:.2e}");
    assert!(worst < 1e-9, "max error {worst:e}");
}

/// Planar joint with normal x (plane axes e1 = y, e2 = z, fixed in obj1 = the world), gravity
/// in the plane, a constant world force and a torque about the normal on the body's centre
/// of mass (its origin). The translations are resolved in obj1, so while the body turns,
/// `x(t) = x0 + vx0 t + (F_y/m) t²/2`, `y(t) = y0 + vy0 t + ((F_z − m g)/m) t²/2` and
/// `phi = phi0 + w0 t + (τ_x/I_xx) t²/2`; had they been resolved in the turning obj2, the
/// force would not be constant in their frame. Bound 1e-9 as for the cylindrical joint.
#[test]
fn planar_joint_under_constant_force_and_torque() {
    let (m, ixx) = (2.0, 0.3);
    let (f, tau) = (Vector3::new(5.0, 3.0, -1.0), 0.45);
    let mut s = SceneDesc::new();
    s.add(world([0.0, 0.0, -G]))
        .add(Object3D::new("body").solid(explicit(
            m,
            Matrix3::from_diagonal(&Vector3::new(ixx, 0.25, 0.2)),
        )))
        .add_joint(Joint::new(
            "pl",
            "world",
            "body",
            JointKind::Planar {
                normal: Vector3::x(),
                x: 0.2,
                y: -0.1,
                phi: 0.3,
                vx: 0.5,
                vy: -0.2,
                w: 2.0,
            },
        ))
        .add_force(ForceElement::ObjectForce {
            object: "body".into(),
            law: ForceFn::new(move |_t, _m| Wrench {
                force: f,
                torque: Vector3::new(tau, 0.0, 0.0),
            }),
        });
    let res = s
        .build()
        .unwrap()
        .simulate(
            &SimOptions::new(2.0)
                .tolerance(1e-10)
                .interval(0.1)
                .progress(false),
        )
        .unwrap();
    let x = res.signal("pl.x").unwrap().values();
    let y = res.signal("pl.y").unwrap().values();
    let phi = res.signal("pl.phi").unwrap().values();
    let r = res.signal("body.r_abs").unwrap();
    let mut worst = 0.0f64;
    for (k, &t) in res.time().iter().enumerate() {
        let xe = 0.2 + 0.5 * t + 0.5 * f.y / m * t * t;
        let ye = -0.1 - 0.2 * t + 0.5 * (f.z / m - G) * t * t;
        let pe = 0.3 + 2.0 * t + 0.5 * tau / ixx * t * t;
        let p = r.at(k).unwrap();
        worst = worst
            .max((x[k] - xe).abs())
            .max((y[k] - ye).abs())
            .max((phi[k] - pe).abs())
            // Plane axes y, z: the body's origin in world is (0, x, y).
            .max(p[0].abs())
            .max((p[1] - xe).abs())
            .max((p[2] - ye).abs());
    }
    println!("planar: max error {worst:.2e}");
    assert!(worst < 1e-9, "max error {worst:e}");
}

/// Spring-dampers on every coordinate: a Universal joint with a spring on `phi2` only and no
/// gravity keeps `phi1` at rest while `phi2` oscillates as `phi2(t) = A cos(√(c/I) t)` when the
/// body's inertia about axis2 is `I` and `phi1` starts at rest with `w1 = 0` (then the coupling
/// terms, all ∝ `w1`, vanish). 1e-8 rad at rtol 1e-11.
#[test]
fn spring_on_one_coordinate_of_a_universal_joint() {
    let (i2, c, a) = (0.25, 4.0, 0.3);
    let mut s = SceneDesc::new();
    s.add(world([0.0, 0.0, 0.0]))
        .add(Object3D::new("body").solid(explicit(
            1.0,
            Matrix3::from_diagonal(&Vector3::new(i2, 0.4, 0.5)),
        )))
        .add_joint(Joint::new(
            "uj",
            "world",
            "body",
            JointKind::Universal {
                axis1: Vector3::z(),
                axis2: Vector3::x(),
                phi1: 0.0,
                phi2: a,
                w1: 0.0,
                w2: 0.0,
            },
        ))
        .add_force(ForceElement::JointSpringDamper {
            joint: "uj".into(),
            coordinate: Some("phi2".into()),
            stiffness: c,
            damping: 0.0,
            offset: 0.0,
        });
    let res = s
        .build()
        .unwrap()
        .simulate(
            &SimOptions::new(3.0)
                .tolerance(1e-11)
                .atol(1e-12)
                .interval(0.05)
                .progress(false),
        )
        .unwrap();
    let p1 = res.signal("uj.phi1").unwrap().values();
    let p2 = res.signal("uj.phi2").unwrap().values();
    let wn = (c / i2).sqrt();
    let mut worst = 0.0f64;
    for (k, &t) in res.time().iter().enumerate() {
        worst = worst
            .max(p1[k].abs())
            .max((p2[k] - a * (wn * t).cos()).abs());
    }
    println!("universal spring: max error {worst:.2e} rad");
    assert!(worst < 1e-8, "max error {worst:e}");
}
