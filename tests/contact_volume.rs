//! The volume law of pairs without a sphere (docs/contact-model.md §3.2) at the DEFAULT scene
//! options, against rigid-body references: sliding on an incline and to rest, rolling, pivoting
//! on an edge (Housner), tipping, resting stacks. Each tolerance is argued where it is used; the
//! compliant law's own deviation from the rigid answer is of the order of the static
//! penetration over the body's size (~1e-7 for 0.1 m wooden bodies) plus the regularised
//! friction's creep below `v_min`.

use modia3d::demo::{box_stack, cube_on_edge, housner_fall_back_time, on_incline, INCLINE_NAMES};
use modia3d::prelude::*;

const G: f64 = 9.81;
/// The built-in DryWood self-pair: cor 0.6, μ_k 0.3, μ_r 0.001.
const WOOD: ContactPairMaterial = ContactPairMaterial::new(0.6, 0.3, 0.001);

fn cube(a: f64) -> Shape {
    Shape::Box {
        lengths: Vector3::new(a, a, a),
    }
}

/// Value of `signal` (component `c`) at time `t` (linear between output points).
fn at(res: &SimulationResult, signal: &str, c: usize, t: f64) -> f64 {
    res.signal_at(signal, t).unwrap()[c]
}

/// Speed along the downhill direction of the body at `t` [m/s].
fn downhill_speed(res: &SimulationResult, alpha: f64, t: f64) -> f64 {
    modia3d::demo::downhill_speed(res, alpha, t).unwrap()
}

fn pair_name() -> String {
    format!("{}|{}", INCLINE_NAMES.0, INCLINE_NAMES.1)
}

/// A 0.1 m wooden cube released on a 30° wooden incline (μ 0.3 < tan 30°): after the start
/// (the contact settles within ~1 ms, critically damped), the rigid answer is
/// a = g (sin α − μ cos α), N = m g cos α. The compliant law differs by the friction's
/// regularisation only while |v| < v_min (the first 4 ms) and by the tilt of the contact
/// normal under the friction moment (δ/size ~ 1e-7): 1e-3 is the bound, with margin.
#[test]
fn a_block_slides_down_an_incline_at_the_rigid_acceleration() {
    let alpha = 30f64.to_radians();
    let scene = on_incline(
        cube(0.1),
        0.05,
        alpha,
        -1.0,
        0.0,
        [0.0; 3],
        "DryWood",
        WOOD,
        SceneOptions::default(),
    );
    let model = scene.build().unwrap();
    let res = model
        .simulate(&SimOptions::new(0.5).interval(1e-3).contact_results(true))
        .unwrap();
    let a_rigid = G * (alpha.sin() - 0.3 * alpha.cos());
    let (t0, t1) = (0.1, 0.5);
    let a = (downhill_speed(&res, alpha, t1) - downhill_speed(&res, alpha, t0)) / (t1 - t0);
    let m = 700.0 * 1e-3;
    let f_n: Vec<f64> = (0..=40)
        .map(|k| {
            at(
                &res,
                &format!("{}.f_n", pair_name()),
                0,
                t0 + k as f64 * 0.01,
            )
        })
        .collect();
    let n_rigid = m * G * alpha.cos();
    println!(
        "a = {a:.7} (rigid {a_rigid:.7}), f_n in [{:.6}, {:.6}] (rigid {n_rigid:.6}); {}",
        f_n.iter().cloned().fold(f64::INFINITY, f64::min),
        f_n.iter().cloned().fold(0.0, f64::max),
        res.stats
    );
    assert!(
        ((a - a_rigid) / a_rigid).abs() < 1e-3,
        "a = {a}, rigid {a_rigid}"
    );
    for f in f_n {
        assert!(
            ((f - n_rigid) / n_rigid).abs() < 1e-3,
            "f_n = {f}, rigid {n_rigid}"
        );
    }
}

/// A wooden cube sliding on a wooden table from 1 m/s stops after d = v0²/(2 μ g). The
/// regularised friction lets it creep on below v_min with a time constant v_min/(3 μ g), which
/// adds ~v_min²/(3 μ g) = 1.1e-5 m (7e-5 relative); 5e-4 is the bound.
#[test]
fn a_block_slides_to_rest_after_the_rigid_distance() {
    let (v0, mu) = (1.0, 0.3);
    let scene = on_incline(
        cube(0.1),
        0.05,
        0.0,
        -1.0,
        v0,
        [0.0; 3],
        "DryWood",
        WOOD,
        SceneOptions::default(),
    );
    let model = scene.build().unwrap();
    let res = model
        .simulate(&SimOptions::new(0.6).interval(1e-3))
        .unwrap();
    let x = res.signal("body.r_abs").unwrap();
    let d = x.last().unwrap()[0] - (-1.0);
    let d_rigid = v0 * v0 / (2.0 * mu * G);
    println!("d = {d:.7} m (rigid {d_rigid:.7}); {}", res.stats);
    assert!(
        ((d - d_rigid) / d_rigid).abs() < 5e-4,
        "d = {d}, rigid {d_rigid}"
    );
}

/// A solid wooden cylinder (Ø 0.1 m × 0.2 m) rolling down a 20° incline without slipping
/// (μ 0.6 > tan 20°/3, μ_r 0) accelerates at (2/3) g sin α. The layer's damping sees no spin of
/// a body of revolution about its own axis (its surface does not move), so rolling adds no
/// damping torque; what remains is the lever of the normal force, R − δ instead of R
/// (δ/R ~ 2e-5), and the regularised friction's micro-slip. Measured: 7e-6; 5e-3 is the
/// issue's bound. (With the damping acting on the material points' spin, the strip ~2√(2Rδ)
/// wide gave a viscous rolling resistance of 1.2–1.4 % at d_max: why the spin is removed.)
#[test]
fn a_cylinder_rolls_down_an_incline_at_two_thirds_g_sin_alpha() {
    let alpha = 20f64.to_radians();
    let shape = Shape::Cylinder {
        axis: Axis::Y,
        diameter: 0.1,
        length: 0.2,
    };
    let scene = on_incline(
        shape,
        0.05,
        alpha,
        -1.0,
        0.0,
        [0.0; 3],
        "DryWood",
        ContactPairMaterial::new(0.6, 0.6, 0.0),
        SceneOptions::default(),
    );
    let model = scene.build().unwrap();
    let res = model
        .simulate(&SimOptions::new(0.5).interval(1e-3))
        .unwrap();
    let (t0, t1) = (0.1, 0.5);
    let a = (downhill_speed(&res, alpha, t1) - downhill_speed(&res, alpha, t0)) / (t1 - t0);
    let a_rigid = 2.0 / 3.0 * G * alpha.sin();
    println!("a = {a:.7} (rigid {a_rigid:.7}); {}", res.stats);
    assert!(
        ((a - a_rigid) / a_rigid).abs() < 5e-3,
        "a = {a}, rigid {a_rigid}"
    );
}

/// Housner's rigid block rocking on an edge: θ̈ = −p² sin(α − θ) for the angle θ of the block
/// away from flat (p² = 3g/(4R), R the half diagonal, α = atan(b/h)), released at θ0 from rest,
/// falls back to flat at the time the reference integrates (`demo::housner_fall_back_time`,
/// RK4 at 1e-6 s, error ~1e-12 s). 2 % is the bound: the compliant edge adds ~δ/R to
/// the lever. The pivot must not slide: μ 0.8 (|F_t/N| reaches ~0.5 for a cube).
#[test]
fn a_block_falls_back_from_its_edge_as_housners_rigid_block() {
    let (b, theta0) = (0.05, 0.3);
    let t_rigid = housner_fall_back_time(b, theta0);
    let model = cube_on_edge(b, theta0, ContactPairMaterial::new(0.6, 0.8, 0.0))
        .build()
        .unwrap();
    let res = model
        .simulate(&SimOptions::new(1.2 * t_rigid).interval(1e-4))
        .unwrap();
    let rot = res.signal("body.R_abs").unwrap();
    // sin θ = −(R e_x)_z: R_abs row-major 3×3, element (2, 0).
    let tilt: Vec<f64> = rot.component(6).iter().map(|r| (-r).asin()).collect();
    let time = res.time();
    let k = tilt.iter().position(|&th| th <= 0.0).expect("falls back");
    let t_hit = time[k - 1] + (time[k] - time[k - 1]) * tilt[k - 1] / (tilt[k - 1] - tilt[k]);
    println!(
        "falls back at {t_hit:.6} s (rigid {t_rigid:.6} s); {}",
        res.stats
    );
    assert!(
        ((t_hit - t_rigid) / t_rigid).abs() < 0.02,
        "{t_hit} vs {t_rigid}"
    );
}

/// The fall-back time of [`a_block_falls_back_from_its_edge_as_housners_rigid_block`]'s cube
/// with the volume law's friction regularised at `v_min_volume` \[m/s\], at the default rtol,
/// relative to Housner's: the crossing θ = 0 located by bisection on the dense output (the
/// output grid's linear interpolation would be off by up to 1e-3 here: the far edge meets the
/// table ~4e-5 s before the crossing and brakes the fall).
fn pivot_error(v_min_volume: f64) -> f64 {
    let (b, theta0) = (0.05, 0.3);
    let t_rigid = housner_fall_back_time(b, theta0);
    let mut scene = cube_on_edge(b, theta0, ContactPairMaterial::new(0.6, 0.8, 0.0));
    scene.objects[0] = modia3d::demo::world(SceneOptions {
        v_min_volume,
        ..Default::default()
    });
    let res = scene
        .build()
        .unwrap()
        .simulate(
            &SimOptions::new(1.2 * t_rigid)
                .interval(1e-3)
                .dense_output(true),
        )
        .unwrap();
    // The tilt about y from the free joint's quaternion (w, x, y, z).
    let tilt = |t: f64| {
        let q = res.signal_at("body.free.q", t).unwrap();
        2.0 * q[2].atan2(q[0])
    };
    let (mut lo, mut hi) = (0.5 * t_rigid, 1.2 * t_rigid);
    assert!(
        tilt(lo) > 0.0 && tilt(hi) < 0.0,
        "no crossing in [{lo}, {hi}]"
    );
    for _ in 0..60 {
        let m = 0.5 * (lo + hi);
        if tilt(m) > 0.0 {
            lo = m;
        } else {
            hi = m;
        }
    }
    (0.5 * (lo + hi) - t_rigid) / t_rigid
}

/// A contact that friction holds creeps at `v_slip·|F_t/f_n|/(3 μ_k)` under the regularised
/// friction (docs/contact-model.md §3.2), and the pivoting edge's creep makes the cube fall
/// back early by an error proportional to `v_slip`, down to the compliant edge's ~7e-6. At the
/// default `v_min_volume` (1e-4 m/s) the fall-back time is within 1e-4 of Housner's
/// (measured 3.8e-5: 2.6× margin for the rest of the compliant edge and the platform's
/// rounding); at 1e-3 m/s, the default before, the same run is more than 1e-4 off (3.4e-4),
/// which is what the default changed.
#[test]
fn the_pivoting_edge_creeps_within_1e_4_of_housner_at_the_default_regularisation() {
    let default = SceneOptions::default().v_min_volume;
    let (e_default, e_before) = (pivot_error(default), pivot_error(1e-3));
    println!(
        "fall-back time error: {e_default:.2e} at {default:e} m/s, {e_before:.2e} at 1e-3 m/s"
    );
    assert!(e_default.abs() < 1e-4, "{e_default:e}");
    assert!(e_before.abs() > 1e-4, "{e_before:e}");
}

/// A cube whose centre of mass overhangs the plank's edge (at x = 2 m) by 1 cm tips off; one
/// whose centre is 1 cm inside stays. The rigid answer is a switch at zero overhang; the
/// compliant law moves it by ~δ (nanometres), so ±1 cm decides either way. The one that stays
/// rests on a 6 cm strip whose area centroid is 2 cm from its centre of mass, so the layer
/// carries it with a wedge of pressure: a tilt θ ≈ 12·δ̄·e/w² ≈ 6e-7 rad (mean depth
/// δ̄ = 8.7e-9 m, e = 0.02 m, w = 0.06 m), the compliant law's own; the bound 1e-5 rad is 15× that
/// and 1e4× below the tipping one.
#[test]
fn a_block_overhanging_an_edge_tips_and_one_inside_stays() {
    for (overhang, tips) in [(0.01, true), (-0.01, false)] {
        let scene = on_incline(
            cube(0.1),
            0.05,
            0.0,
            2.0 + overhang,
            0.0,
            [0.0; 3],
            "DryWood",
            WOOD,
            SceneOptions::default(),
        );
        let res = scene
            .build()
            .unwrap()
            .simulate(&SimOptions::new(0.4).interval(1e-3))
            .unwrap();
        let tilt = (-res.signal("body.R_abs").unwrap().last().unwrap()[6]).asin();
        println!("overhang {overhang}: tilt {tilt:.3e} rad; {}", res.stats);
        if tips {
            assert!(tilt > 0.1, "it should tip, tilt {tilt}");
        } else {
            assert!(tilt.abs() < 1e-5, "it should stay, tilt {tilt}");
        }
    }
}

/// On a 25° incline with μ 0.8 > tan 25° = 0.47 (no sliding), a box 0.05 m deep and 0.15 m
/// tall (b/h = 0.33 < tan α) tips over, and a 0.1 m cube (b/h = 1) stays put (rigid statics:
/// the weight's line leaves the support face iff tan α > b/h).
#[test]
fn a_tall_box_tips_on_an_incline_and_a_cube_stays() {
    let alpha = 25f64.to_radians();
    for (lengths, tips) in [([0.05, 0.1, 0.15], true), ([0.1, 0.1, 0.1], false)] {
        let scene = on_incline(
            Shape::Box {
                lengths: Vector3::from(lengths),
            },
            0.5 * lengths[2],
            alpha,
            -1.0,
            0.0,
            [0.0; 3],
            "DryWood",
            ContactPairMaterial::new(0.6, 0.8, 0.001),
            SceneOptions::default(),
        );
        let res = scene
            .build()
            .unwrap()
            .simulate(&SimOptions::new(0.6).interval(1e-3))
            .unwrap();
        let r = res.signal("body.R_abs").unwrap();
        let r = r.last().unwrap();
        // Tilt relative to the incline: the body's z axis against the incline's normal.
        let normal = Vector3::new(alpha.sin(), 0.0, alpha.cos());
        let z_axis = Vector3::new(r[2], r[5], r[8]);
        let tilt = z_axis.dot(&normal).clamp(-1.0, 1.0).acos();
        let x = res.signal("body.r_abs").unwrap().last().unwrap()[0];
        println!("{lengths:?}: tilt {tilt:.3e} rad, x {x:.6}; {}", res.stats);
        if tips {
            assert!(tilt > 0.3, "it should tip, tilt {tilt}");
        } else {
            assert!(tilt < 1e-5, "it should stay, tilt {tilt}");
        }
    }
}

/// Three wooden cubes stacked on a table at rest: every interface carries the weight above it
/// (f_n = k·m·g for k boxes above, within 1e-4: the settling transient is critically damped and
/// over within milliseconds), no box tilts, and no contact event happens after the start.
#[test]
fn a_stack_of_boxes_rests_with_each_interface_carrying_the_weight_above() {
    let n = 3;
    let res = box_stack([0.1, 0.1, 0.1], n, 0.0, SceneOptions::default())
        .build()
        .unwrap()
        .simulate(&SimOptions::new(0.5).interval(1e-3).contact_results(true))
        .unwrap();
    let w = 700.0 * 1e-3 * G;
    let pairs = ["table|b0", "b0|b1", "b1|b2"];
    for (k, p) in pairs.iter().enumerate() {
        let f = res.signal(&format!("{p}.f_n")).unwrap();
        let f = f.last().unwrap()[0];
        let expected = (n - k) as f64 * w;
        println!("{p}: f_n {f:.8} N (weight above {expected:.8} N)");
        assert!(
            ((f - expected) / expected).abs() < 1e-4,
            "{p}: {f} vs {expected}"
        );
    }
    for i in 0..n {
        let r = res.signal(&format!("b{i}.R_abs")).unwrap();
        let r = r.last().unwrap();
        let tilt = (r[2] * r[2] + r[5] * r[5]).sqrt();
        assert!(tilt < 1e-6, "b{i} tilts by {tilt}");
    }
    let late: Vec<_> = res.events.iter().filter(|e| e.t > 0.01).collect();
    println!(
        "{} events, {} after 0.01 s; {}",
        res.events.len(),
        late.len(),
        res.stats
    );
    assert!(late.is_empty(), "events after settling: {late:?}");
}

/// A wooden cube dropped from 5 cm onto a wooden table edge first and corner first comes to
/// rest on a face: at 1.5 s it is still (speed < 1e-6 m/s), one of its axes is vertical to
/// 1e-6 rad (the rest tilt of a symmetric face is zero; 1e-6 is ~100 static depths over the
/// edge), the table carries its weight to 1e-4, and no contact event happens in the last
/// 0.5 s (settled contacts stay closed).
#[test]
fn edge_first_and_corner_first_drops_come_to_rest_on_a_face() {
    for (name, angles) in [
        ("edge first", [0.0, 0.5, 0.0]),
        ("corner first", [0.4, 0.5, 0.0]),
    ] {
        let a = 0.1;
        let mut scene = on_incline(
            cube(a),
            0.0,
            0.0,
            0.0,
            0.0,
            [0.0; 3],
            "DryWood",
            WOOD,
            SceneOptions::default(),
        );
        scene.joints[0].kind = JointKind::FreeMotion {
            r: Vector3::new(0.0, 0.0, 0.5 * a * 3f64.sqrt() + 0.05),
            rot: FreeRotation::Cardan(angles),
            v: Vector3::zeros(),
            w: Vector3::zeros(),
        };
        let res = scene
            .build()
            .unwrap()
            .simulate(&SimOptions::new(1.5).interval(1e-2).contact_results(true))
            .unwrap();
        assert_rests_on_a_face(name, &res, 700.0 * a * a * a * G, 1.0);
    }
}

/// The drops' rest: at the end of `res` the body is still (< 1e-6 m/s), one of its axes is
/// vertical to 1e-6 rad, the plank carries `weight` \[N\] to 1e-4 and no contact event
/// happened after `t_late` \[s\] (the tolerances are argued at the tests).
fn assert_rests_on_a_face(name: &str, res: &SimulationResult, weight: f64, t_late: f64) {
    let r = res.signal("body.R_abs").unwrap();
    let r = r.last().unwrap();
    // The largest vertical component of a body axis: 1 when a face is down.
    let up = [r[6], r[7], r[8]]
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let v = res.signal("body.v_abs").unwrap();
    let v = v.last().unwrap();
    let speed = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let f = res.signal(&format!("{}.f_n", pair_name())).unwrap();
    let f = f.last().unwrap()[0];
    let late = res.events.iter().filter(|e| e.t > t_late).count();
    println!(
        "{name}: tilt {:.2e}, speed {speed:.2e}, f_n {f:.7} (m g {weight:.7}), {} events ({late} late); {}",
        (2.0 * (1.0 - up)).sqrt(),
        res.events.len(),
        res.stats
    );
    assert!(
        (2.0 * (1.0 - up)).sqrt() < 1e-6,
        "{name}: not on a face, up {up}"
    );
    assert!(speed < 1e-6, "{name}: speed {speed}");
    assert!(
        ((f - weight) / weight).abs() < 1e-4,
        "{name}: f_n {f} vs {weight}"
    );
    assert_eq!(late, 0, "{name}: events after settling");
}

/// `demo::FallingBoxes` (two boxes and two cylinders dropped onto a wooden table, at rtol 1e-5
/// as its example) at the wood's own stiffness (`k_red = 1`) under the default volume law:
/// every body at rest at 3 s (speed < 1e-6 m/s, angular speed < 1e-5 rad/s: a settled contact
/// is critically damped, so what is left after 2 s of rest is rounding), the table carrying the
/// weight of all four to 1e-4, and no contact event in the last 2 s.
#[test]
fn falling_boxes_at_full_stiffness_come_to_rest_without_late_events() {
    let model = modia3d::demo::FallingBoxes { k_red: 1.0 }.build().unwrap();
    let res = model
        .simulate(
            &SimOptions::new(3.0)
                .tolerance(1e-5)
                .interval(0.01)
                .contact_results(true),
        )
        .unwrap();
    let mut weight = 0.0;
    let mut carried = 0.0;
    for (name, b) in ["box1", "box2", "cyl1", "cyl2"].iter().zip(model.bodies()) {
        let v = res.signal(&format!("{name}.v_abs")).unwrap();
        let w = res.signal(&format!("{name}.w_abs")).unwrap();
        let norm = |x: &[f64]| (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
        let (v, w) = (norm(v.last().unwrap()), norm(w.last().unwrap()));
        println!("{name}: speed {v:.1e} m/s, angular speed {w:.1e} rad/s");
        assert!(v < 1e-6 && w < 1e-5, "{name} still moves: {v}, {w}");
        weight += b.mass * G;
        let f = res.signal(&format!("table|{name}.f_n")).unwrap();
        carried += f.last().unwrap()[0];
    }
    let late = res.events.iter().filter(|e| e.t > 1.0).count();
    println!(
        "table carries {carried:.6} N of {weight:.6} N; {} events, {late} after 1 s; {}",
        res.events.len(),
        res.stats
    );
    assert!(((carried - weight) / weight).abs() < 1e-4);
    assert_eq!(late, 0, "events after the bodies rest");
}

modia3d::model! {
    /// A wooden cube on a wooden table whose elastic layers are set by hand.
    pub LayeredCube(h_cube: f64 = 0.01) {
        world = Object3D(feature = Scene(profile = Volume)),
        table = Object3D(parent = world, translation = [0.0, 0.0, -0.05],
                         feature = Solid(shape = Box(lengths = [1.0, 1.0, 0.1]), solid_material = "DryWood",
                                         collision = true, layer_depth = 0.02)),
        cube  = Object3D(feature = Solid(shape = Box(lengths = [0.1, 0.1, 0.1]), solid_material = "DryWood",
                                         collision = true, layer_depth = h_cube)),
        free  = FreeMotion(obj1 = world, obj2 = cube, r = Var(init = [0.0, 0.0, 0.05])),
    }
}

/// The layer depth of each solid sets its stiffness per volume `E/((1 − ν²) H)`, in series
/// (`model!`'s `layer_depth` and `Solid::layer_depth`); without it a box's is half its smallest
/// edge. A depth that is not finite and positive is a scene error naming the solid.
#[test]
fn layer_depths_set_the_stiffness_per_volume_and_bad_ones_are_named() {
    let wood = modia3d::core::scene::builtin_solid_material("DryWood").unwrap();
    let c = wood.young_modulus / (1.0 - wood.poisson_ratio * wood.poisson_ratio);
    let series = |h1: f64, h2: f64| 1.0 / (h1 / c + h2 / c);
    let kappa = |m: &Model| m.contact_pairs()[0].volume_stiffness.expect("volume law");
    let m = LayeredCube { h_cube: 0.01 }.build().unwrap();
    let k = kappa(&m);
    assert!((k - series(0.02, 0.01)).abs() < 1e-12 * k, "{k}");
    // The defaults: half the smallest edges (0.05 m both).
    let mut s = LayeredCube::default().scene();
    for o in &mut s.objects {
        if let Feature::Solid(solid) = &mut o.feature {
            solid.layer_depth = None;
        }
    }
    let k = kappa(&s.clone().build().unwrap());
    assert!((k - series(0.05, 0.05)).abs() < 1e-12 * k, "{k}");
    for bad in [0.0, -0.01, f64::NAN, f64::INFINITY] {
        let err = LayeredCube { h_cube: bad }.build().unwrap_err().to_string();
        assert!(
            err.contains("cube") && err.contains("layer depth"),
            "{bad}: {err}"
        );
    }
    // The paper's profile has no volume law.
    let mut s = LayeredCube::default().scene();
    if let Feature::Scene(o) = &mut s.objects[0].feature {
        o.contact_profile = ContactProfile::Paper2019;
    }
    assert_eq!(s.build().unwrap().contact_pairs()[0].volume_stiffness, None);
}

/// A wooden beam (Modia3D's `Beam`: straight part 0.2 m, width 0.05 m, thickness 0.02 m)
/// lying flat on a 30° wooden incline slides at the rigid a = g (sin α − μ cos α) with
/// N = m g cos α, as the cube does (same bounds and reasons: 1e-3): the volume law sees the
/// beam as the polytope of `geometry::overlap::polytope::beam_points` (its face 0.64 % short of
/// the ends' area), which changes the static depth, not the forces. Its mass is the exact
/// beam's.
#[test]
fn a_beam_slides_down_an_incline_at_the_rigid_acceleration() {
    let (l, w, t) = (0.2, 0.05, 0.02);
    let alpha = 30f64.to_radians();
    let beam = Shape::Beam {
        axis: Axis::X,
        length: l,
        width: w,
        thickness: t,
    };
    let res = on_incline(
        beam,
        0.5 * t,
        alpha,
        -1.0,
        0.0,
        [0.0; 3],
        "DryWood",
        WOOD,
        SceneOptions::default(),
    )
    .build()
    .unwrap()
    .simulate(&SimOptions::new(0.5).interval(1e-3).contact_results(true))
    .unwrap();
    let m = 700.0 * t * (l * w + std::f64::consts::PI * 0.25 * w * w);
    let a_rigid = G * (alpha.sin() - 0.3 * alpha.cos());
    let a = (downhill_speed(&res, alpha, 0.5) - downhill_speed(&res, alpha, 0.1)) / 0.4;
    let f = at(&res, &format!("{}.f_n", pair_name()), 0, 0.3);
    let n_rigid = m * G * alpha.cos();
    println!(
        "a = {a:.7} (rigid {a_rigid:.7}), f_n {f:.7} (rigid {n_rigid:.7}); {}",
        res.stats
    );
    assert!(
        ((a - a_rigid) / a_rigid).abs() < 1e-3,
        "a = {a}, rigid {a_rigid}"
    );
    assert!(
        ((f - n_rigid) / n_rigid).abs() < 1e-3,
        "f_n = {f}, rigid {n_rigid}"
    );
}

/// The same beam dropped from 3 cm, tilted about two axes, onto a wooden table comes to rest
/// on a flat side (the face or a long side: a body axis vertical to 1e-6 rad, as the cube's
/// drops), still (< 1e-6 m/s), the table carrying its weight to 1e-4, with no contact event in
/// the last 0.5 s. Before the beam had the volume law its single-point linear law rocked on the
/// rounded ends; the test fails if a beam pair falls back to it.
#[test]
fn a_dropped_beam_comes_to_rest_on_a_flat_side() {
    let (l, w, t) = (0.2, 0.05, 0.02);
    let beam = Shape::Beam {
        axis: Axis::X,
        length: l,
        width: w,
        thickness: t,
    };
    let mut scene = on_incline(
        beam,
        0.0,
        0.0,
        0.0,
        0.0,
        [0.0; 3],
        "DryWood",
        WOOD,
        SceneOptions::default(),
    );
    scene.joints[0].kind = JointKind::FreeMotion {
        r: Vector3::new(0.0, 0.0, 0.5 * (l + w) + 0.03),
        rot: FreeRotation::Cardan([0.3, 0.2, 0.0]),
        v: Vector3::zeros(),
        w: Vector3::zeros(),
    };
    let model = scene.build().unwrap();
    let pair = model
        .contact_pairs()
        .into_iter()
        .find(|p| p.name == pair_name())
        .expect("the beam–plank pair");
    assert!(
        pair.volume_stiffness.is_some(),
        "the beam's pair has the volume law"
    );
    let res = model
        .simulate(&SimOptions::new(2.0).interval(1e-2).contact_results(true))
        .unwrap();
    let weight = 700.0 * t * (l * w + std::f64::consts::PI * 0.25 * w * w) * G;
    assert_rests_on_a_face("beam", &res, weight, 1.5);
}
