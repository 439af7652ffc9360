//! Ready-made contact scenes shared by the examples, the contact tests and the work-precision
//! benchmark (`examples/work_precision.rs`). Each function returns a plain [`SceneDesc`]; all
//! lengths in [m], velocities in [m/s], angular velocities in [rad/s].

use crate::prelude::*;

/// Hertz stiffness `K = c_res · 4/3 · sqrt(R*)` [N/m^1.5] of a sphere of radius `r` [m] against a
/// flat body, both of the given solid materials (`c_i = E_i/(1 − ν_i²)`).
pub fn hertz_k_sphere_flat(r: f64, m1: &SolidMaterial, m2: &SolidMaterial) -> f64 {
    c_res(m1, m2) * 4.0 / 3.0 * r.sqrt()
}

/// `c_res = 1/(1/c_1 + 1/c_2)` [N/m²].
pub fn c_res(m1: &SolidMaterial, m2: &SolidMaterial) -> f64 {
    let c = |m: &SolidMaterial| m.young_modulus / (1.0 - m.poisson_ratio * m.poisson_ratio);
    1.0 / (1.0 / c(m1) + 1.0 / c(m2))
}

/// Static penetration [m] of a mass `m` [kg] resting on a Hertz contact of stiffness `k`
/// (`m g = k δ^{3/2}`), gravity `g` [m/s²].
pub fn static_penetration(m: f64, g: f64, k: f64) -> f64 {
    (m * g / k).powf(2.0 / 3.0)
}

/// Mass [kg] of a sphere of diameter `d` [m] and density `rho` [kg/m³].
pub fn sphere_mass(d: f64, rho: f64) -> f64 {
    rho * std::f64::consts::PI * d * d * d / 6.0
}

/// The world object with these options.
pub fn world(options: SceneOptions) -> Object3D {
    Object3D::new("world").scene(options)
}

/// A fixed collision box `name` with edge lengths `lengths` centred at `centre`.
pub fn fixed_box(name: &str, lengths: [f64; 3], centre: [f64; 3], material: &str) -> Object3D {
    Object3D::new(name)
        .parent("world")
        .translation(centre)
        .solid(
            Solid::new(Shape::Box {
                lengths: Vector3::from(lengths),
            })
            .material(material)
            .collision(true),
        )
}

/// Adds a free collision sphere `name` (joint `"<name>.free"`), at `r` with velocity `v` and
/// angular velocity `w` (resolved in the ball frame, which starts aligned with world).
#[allow(clippy::too_many_arguments)]
pub fn add_free_sphere(
    scene: &mut SceneDesc,
    name: &str,
    diameter: f64,
    material: &str,
    contact_material: Option<&str>,
    r: [f64; 3],
    v: [f64; 3],
    w: [f64; 3],
) {
    let mut solid = Solid::new(Shape::Sphere { diameter })
        .material(material)
        .collision(true);
    if let Some(cm) = contact_material {
        solid = solid.contact_material(cm);
    }
    scene
        .add(Object3D::new(name).solid(solid))
        .add_joint(Joint::new(
            &format!("{name}.free"),
            "world",
            name,
            JointKind::FreeMotion {
                r: Vector3::from(r),
                rot: FreeRotation::Cardan([0.0; 3]),
                v: Vector3::from(v),
                w: Vector3::from(w),
            },
        ));
}

/// A steel sphere of diameter `diameter` dropped from centre height `h0` (above the top face
/// of a fixed 1 × 1 × 0.1 m steel box at z = 0), with contact pair material `pair` for
/// `Steel`–`Steel`.
pub fn bouncing_sphere(diameter: f64, h0: f64, pair: ContactPairMaterial) -> SceneDesc {
    let mut s = SceneDesc::new();
    s.add(world(SceneOptions::default()))
        .add(fixed_box(
            "table",
            [1.0, 1.0, 0.1],
            [0.0, 0.0, -0.05],
            "Steel",
        ))
        .add_contact_pair("Steel", "Steel", pair);
    add_free_sphere(
        &mut s,
        "ball",
        diameter,
        "Steel",
        None,
        [0.0, 0.0, h0],
        [0.0; 3],
        [0.0; 3],
    );
    s
}

/// A steel ball (Ø `diameter`) resting on a steel table at its static penetration, launched
/// sliding along x at `v0` without spin; pair material `pair` (friction, rolling resistance,
/// `v_min`).
pub fn sliding_ball(diameter: f64, v0: f64, spin: f64, pair: ContactPairMaterial) -> SceneDesc {
    let steel = builtin_steel();
    let r = 0.5 * diameter;
    let k = hertz_k_sphere_flat(r, &steel, &steel);
    let delta = static_penetration(sphere_mass(diameter, steel.density), 9.81, k);
    let mut s = SceneDesc::new();
    s.add(world(SceneOptions::default()))
        .add(fixed_box(
            "table",
            [40.0, 2.0, 0.1],
            [15.0, 0.0, -0.05],
            "Steel",
        ))
        .add_contact_pair("Steel", "Steel", pair);
    add_free_sphere(
        &mut s,
        "ball",
        diameter,
        "Steel",
        None,
        [0.0, 0.0, r - delta],
        [v0, 0.0, 0.0],
        [0.0, spin, 0.0],
    );
    s
}

fn builtin_steel() -> SolidMaterial {
    modia3d_core::scene::builtin_solid_material("Steel").expect("built-in")
}

/// Billiard ball diameter [m].
pub const BALL_DIAMETER: f64 = 0.06;

/// Height [m] of the centre of a billiard ball resting on the table (static penetration
/// subtracted, so the balls start in equilibrium) for contact reduction `k_red`.
pub fn billiard_ball_height(k_red: f64) -> f64 {
    let ball = modia3d_core::scene::builtin_solid_material("BilliardBall").expect("built-in");
    let table = modia3d_core::scene::builtin_solid_material("BilliardTable").expect("built-in");
    let r = 0.5 * BALL_DIAMETER;
    let k = k_red * hertz_k_sphere_flat(r, &ball, &table);
    r - static_penetration(sphere_mass(BALL_DIAMETER, ball.density), 9.81, k)
}

/// The billiard table (box 2.24 × 1.12 × 0.05 m, top face at z = 0) and four cushions:
/// capsules of radius 1 cm along the edges, placed so that a ball touches them at height
/// 7/5·r above the table top.
pub fn add_billiard_table(scene: &mut SceneDesc) {
    let (lx, ly) = (2.24, 1.12);
    scene.add(fixed_box(
        "table",
        [lx, ly, 0.05],
        [0.0, 0.0, -0.025],
        "BilliardTable",
    ));
    let r = 0.5 * BALL_DIAMETER;
    let rho = 0.01;
    let h = r + 0.4 * (r + rho); // contact point at r + r·(h − r)/(r + ρ) = 7/5·r
    let cushion = |name: &str, axis: Axis, length: f64, pos: [f64; 3]| {
        Object3D::new(name).parent("world").translation(pos).solid(
            Solid::new(Shape::Capsule {
                axis,
                diameter: 2.0 * rho,
                length,
            })
            .material("BilliardCushion")
            .collision(true),
        )
    };
    scene
        .add(cushion("cushion_n", Axis::X, lx, [0.0, 0.5 * ly, h]))
        .add(cushion("cushion_s", Axis::X, lx, [0.0, -0.5 * ly, h]))
        .add(cushion("cushion_e", Axis::Y, ly, [0.5 * lx, 0.0, h]))
        .add(cushion("cushion_w", Axis::Y, ly, [-0.5 * lx, 0.0, h]));
}

/// Modia3D's 16-ball billiards: the rack of 15 balls (touching distance plus 0.1 mm, apex at
/// x = 0.56 m on the x axis) and the cue ball at x = −0.56 m with velocity `cue_v`, on the
/// table with cushions; `k_red` scales the contact stiffness.
pub fn billiards16(cue_v: [f64; 3], k_red: f64) -> SceneDesc {
    let mut s = SceneDesc::new();
    s.add(world(SceneOptions {
        k_red,
        ..Default::default()
    }));
    add_billiard_table(&mut s);
    let z = billiard_ball_height(k_red);
    let d = BALL_DIAMETER + 1e-4;
    let row = 3f64.sqrt() / 2.0 * d;
    let mut k = 1;
    for i in 0..5 {
        for j in 0..=i {
            let x = 0.56 + i as f64 * row;
            let y = (j as f64 - 0.5 * i as f64) * d;
            add_free_sphere(
                &mut s,
                &format!("ball{k}"),
                BALL_DIAMETER,
                "BilliardBall",
                None,
                [x, y, z],
                [0.0; 3],
                [0.0; 3],
            );
            k += 1;
        }
    }
    add_free_sphere(
        &mut s,
        "cue",
        BALL_DIAMETER,
        "BilliardBall",
        None,
        [-0.56, 0.0, z],
        cue_v,
        [0.0; 3],
    );
    s
}

/// A billiard cue ball rolling (v = ω r) along x at `v` from x = −0.9 m towards a resting ball
/// at x = −0.4 m.
pub fn two_balls(v: f64) -> SceneDesc {
    let mut s = SceneDesc::new();
    s.add(world(SceneOptions::default()));
    add_billiard_table(&mut s);
    let z = billiard_ball_height(1.0);
    let r = 0.5 * BALL_DIAMETER;
    add_free_sphere(
        &mut s,
        "cue",
        BALL_DIAMETER,
        "BilliardBall",
        None,
        [-0.9, 0.0, z],
        [v, 0.0, 0.0],
        [0.0, v / r, 0.0],
    );
    add_free_sphere(
        &mut s,
        "ball",
        BALL_DIAMETER,
        "BilliardBall",
        None,
        [-0.4, 0.0, z],
        [0.0; 3],
        [0.0; 3],
    );
    s
}

/// A billiard ball rolling (v = ω r) along x at `v` towards the east cushion.
pub fn ball_cushion(v: f64) -> SceneDesc {
    let mut s = SceneDesc::new();
    s.add(world(SceneOptions::default()));
    add_billiard_table(&mut s);
    let z = billiard_ball_height(1.0);
    let r = 0.5 * BALL_DIAMETER;
    add_free_sphere(
        &mut s,
        "ball",
        BALL_DIAMETER,
        "BilliardBall",
        None,
        [0.8, 0.0, z],
        [v, 0.0, 0.0],
        [0.0, v / r, 0.0],
    );
    s
}

/// Newton's cradle: 5 steel balls (Ø `diameter`) on 0.5 m pendulums (Revolute joints with
/// `can_collide = true`), neighbouring balls `gap` apart; the first ball starts with speed
/// `v0` towards the others. Contact material `CradleSteel` (elasticity of Steel) with the
/// pair material `pair`.
pub fn newtons_cradle(diameter: f64, gap: f64, v0: f64, pair: ContactPairMaterial) -> SceneDesc {
    let l = 0.5;
    let mut s = SceneDesc::new();
    s.add(world(SceneOptions::default()))
        .add_contact_pair("CradleSteel", "CradleSteel", pair);
    for i in 0..5 {
        let x = i as f64 * (diameter + gap);
        let (hook, ball, pivot) = (format!("hook{i}"), format!("ball{i}"), format!("pivot{i}"));
        s.add(
            Object3D::new(&hook)
                .parent("world")
                .translation([x, 0.0, l]),
        )
        .add(
            Object3D::new(&ball).solid(
                Solid::new(Shape::Sphere { diameter })
                    .material("Steel")
                    .contact_material("CradleSteel")
                    .collision(true),
            ),
        )
        .add(
            Object3D::new(&pivot)
                .parent(&ball)
                .translation([0.0, 0.0, l]),
        );
        let mut j = Joint::new(&format!("rev{i}"), &hook, &pivot, JointKind::revolute(-2))
            .can_collide(true);
        if i == 0 {
            j = j.init_velocity(v0 / l);
        }
        s.add_joint(j);
    }
    s
}

/// Boxes and cylinders (DryWood) dropped onto a fixed wooden table; `k_red` scales the contact
/// stiffness.
pub fn falling_boxes(k_red: f64) -> SceneDesc {
    let mut s = SceneDesc::new();
    s.add(world(SceneOptions {
        k_red,
        ..Default::default()
    }))
    .add(fixed_box(
        "table",
        [2.0, 2.0, 0.1],
        [0.0, 0.0, -0.05],
        "DryWood",
    ));
    let parts: [(&str, Shape, [f64; 3], [f64; 3]); 4] = [
        (
            "box1",
            Shape::Box {
                lengths: Vector3::new(0.2, 0.1, 0.05),
            },
            [-0.4, 0.0, 0.2],
            [0.3, 0.2, 0.0],
        ),
        (
            "box2",
            Shape::Box {
                lengths: Vector3::new(0.1, 0.1, 0.1),
            },
            [0.0, 0.3, 0.3],
            [0.0, 0.5, 0.1],
        ),
        (
            "cyl1",
            Shape::Cylinder {
                axis: Axis::Z,
                diameter: 0.1,
                length: 0.1,
            },
            [0.3, -0.2, 0.25],
            [0.2, 0.0, 0.4],
        ),
        (
            "cyl2",
            Shape::Cylinder {
                axis: Axis::X,
                diameter: 0.08,
                length: 0.2,
            },
            [0.0, -0.5, 0.4],
            [0.0, 0.4, 0.3],
        ),
    ];
    for (name, shape, r, angles) in parts {
        s.add(Object3D::new(name).solid(Solid::new(shape).material("DryWood").collision(true)))
            .add_joint(Joint::new(
                &format!("{name}.free"),
                "world",
                name,
                JointKind::FreeMotion {
                    r: Vector3::from(r),
                    rot: FreeRotation::Cardan(angles),
                    v: Vector3::zeros(),
                    w: Vector3::zeros(),
                },
            ));
    }
    s
}
