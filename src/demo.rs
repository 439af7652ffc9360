//! Ready-made contact scenes shared by the examples, the contact tests and the work-precision
//! benchmark (`examples/work_precision.rs`). Every scene is a `model!` type (one definition);
//! the functions return its [`SceneDesc`] for the tests and the benchmark. The builder helpers
//! ([`world`], [`fixed_box`], [`add_free_sphere`]) remain for tests that build scenes from
//! data. All lengths in \[m\], velocities in [m/s], angular velocities in [rad/s].

use crate::prelude::*;

/// Hertz stiffness `K = c_res · 4/3 · sqrt(R*)` [N/m^1.5] of a sphere of radius `r` \[m\] against a
/// flat body, both of the given solid materials (`c_i = E_i/(1 − ν_i²)`).
pub fn hertz_k_sphere_flat(r: f64, m1: &SolidMaterial, m2: &SolidMaterial) -> f64 {
    c_res(m1, m2) * 4.0 / 3.0 * r.sqrt()
}

/// `c_res = 1/(1/c_1 + 1/c_2)` [N/m²].
pub fn c_res(m1: &SolidMaterial, m2: &SolidMaterial) -> f64 {
    let c = |m: &SolidMaterial| m.young_modulus / (1.0 - m.poisson_ratio * m.poisson_ratio);
    1.0 / (1.0 / c(m1) + 1.0 / c(m2))
}

/// Static penetration \[m\] of a mass `m` \[kg\] resting on a Hertz contact of stiffness `k`
/// (`m g = k δ^{3/2}`), gravity `g` [m/s²].
pub fn static_penetration(m: f64, g: f64, k: f64) -> f64 {
    (m * g / k).powf(2.0 / 3.0)
}

/// Mass \[kg\] of a sphere of diameter `d` \[m\] and density `rho` [kg/m³].
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
        .solid_material(material)
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

/// A sphere (Ø `d` \[m\], solid material `mat`, contact material "Ball") flying at `v0` [m/s]
/// along −z towards a fixed 1 × 1 × 0.1 m steel box (top face at z = 0) from a gap of `gap` \[m\];
/// pair material `pair` for Ball–Steel; world options `options`.
pub fn sphere_on_plane(
    d: f64,
    mat: SolidMaterial,
    v0: f64,
    gap: f64,
    pair: ContactPairMaterial,
    options: SceneOptions,
) -> SceneDesc {
    let mut s = SceneDesc::new();
    s.add(world(options))
        .add(fixed_box(
            "plane",
            [1.0, 1.0, 0.1],
            [0.0, 0.0, -0.05],
            "Steel",
        ))
        .add(
            Object3D::new("ball").solid(
                Solid::new(Shape::Sphere { diameter: d })
                    .material_value(mat)
                    .contact_material("Ball")
                    .collision(true),
            ),
        )
        .add_joint(Joint::new(
            "free",
            "world",
            "ball",
            JointKind::FreeMotion {
                r: Vector3::new(0.0, 0.0, d / 2.0 + gap),
                rot: FreeRotation::Cardan([0.0; 3]),
                v: Vector3::new(0.0, 0.0, -v0),
                w: Vector3::zeros(),
            },
        ))
        .add_contact_pair("Ball", "Steel", pair);
    s
}

/// A steel ball `ball` (Ø `d` \[m\]) at rest with its lowest point `h` \[m\] above a fixed
/// 1 × 1 × 0.1 m steel `plate` (top face at z = 0), Steel–Steel pair with `cor`, no friction,
/// gravity on; `exact_restitution` as given (the bounce and steel-drop scenes of the Rapier
/// comparison, docs/rapier-comparison.md, and their tests).
pub fn steel_drop(d: f64, h: f64, cor: f64, exact_restitution: bool) -> SceneDesc {
    let mut s = SceneDesc::new();
    s.add(world(SceneOptions {
        exact_restitution,
        ..Default::default()
    }))
    .add(fixed_box(
        "plate",
        [1.0, 1.0, 0.1],
        [0.0, 0.0, -0.05],
        "Steel",
    ));
    add_free_sphere(
        &mut s,
        "ball",
        d,
        "Steel",
        None,
        [0.0, 0.0, d / 2.0 + h],
        [0.0; 3],
        [0.0; 3],
    );
    s.add_contact_pair("Steel", "Steel", ContactPairMaterial::new(cor, 0.0, 0.0));
    s
}

/// Rebound speed over impact speed of the free object `ball` of `model` that starts 1e-5 m
/// from a plane, moving at `v0` [m/s] towards it along −z without gravity (as
/// [`sphere_on_plane`] builds it): simulated for 1e-5/`v0` + 0.05 s at rtol 1e-9, the final
/// `ball.v_abs[2]` over `v0`. `Ok(None)` when no contact ended (the ball did not rebound).
pub fn rebound_ratio(model: &Model, v0: f64) -> Result<Option<f64>, SimError> {
    let res = model.simulate(
        &SimOptions::new(1e-5 / v0 + 0.05)
            .tolerance(1e-9)
            .interval(1e-3)
            .progress(false),
    )?;
    if !res.events.iter().any(|e| !e.ended.is_empty()) {
        return Ok(None);
    }
    let vz = res
        .signal("ball.v_abs[2]")
        .map(|s| s.values())
        .unwrap_or_default();
    Ok(vz.last().map(|v| v / v0))
}

/// Shapes that lie flat on a table, for the resting-contact scenes: `(name, shape, height when
/// resting [m], volume [m³])` of a 0.1 m cube, a cylinder Ø 0.1 × 0.2 m on its side and an
/// ellipsoid 0.1 × 0.06 × 0.04 m lying on its smallest axis.
pub fn lying_shapes() -> [(&'static str, Shape, f64, f64); 3] {
    [
        (
            "cube",
            Shape::Box {
                lengths: Vector3::new(0.1, 0.1, 0.1),
            },
            0.1,
            1e-3,
        ),
        (
            "cylinder",
            Shape::Cylinder {
                axis: Axis::X,
                diameter: 0.1,
                length: 0.2,
            },
            0.1,
            std::f64::consts::PI * 0.05 * 0.05 * 0.2,
        ),
        (
            "ellipsoid",
            Shape::Ellipsoid {
                lengths: Vector3::new(0.1, 0.06, 0.04),
            },
            0.04,
            std::f64::consts::PI / 6.0 * 0.1 * 0.06 * 0.04,
        ),
    ]
}

/// A steel table (top at z = 0) and `n` free bodies of `shape` (height `h` \[m\] when resting,
/// orientation `angles`) stacked, each touching the one below (gap 0), at rest.
pub fn stack(shape: Shape, h: f64, angles: [f64; 3], n: usize, k_red: f64) -> SceneDesc {
    let mut s = world_and_table(k_red, [1.0, 1.0, 0.1], "Steel");
    for i in 0..n {
        let name = format!("b{i}");
        s.add(
            Object3D::new(&name).solid(Solid::new(shape.clone()).material("Steel").collision(true)),
        )
        .add_joint(Joint::new(
            &format!("{name}.free"),
            "world",
            &name,
            JointKind::FreeMotion {
                r: Vector3::new(0.0, 0.0, h / 2.0 + i as f64 * h),
                rot: FreeRotation::Cardan(angles),
                v: Vector3::zeros(),
                w: Vector3::zeros(),
            },
        ));
    }
    s
}

/// The built-in Steel–Steel pair material (`builtin_contact_pair("Steel", "Steel")`): cor 0.7, μ_k 0.5,
/// μ_r 0.001.
pub const STEEL_STEEL: ContactPairMaterial = ContactPairMaterial::new(0.7, 0.5, 0.001);

model! {
    /// A steel sphere of diameter `diameter` dropped from centre height `h0` (above the top face
    /// of a fixed 1 × 1 × 0.1 m steel box at z = 0), with contact pair material `pair` for
    /// `Steel`–`Steel`.
    pub BouncingSphere(diameter: f64 = 0.1, h0: f64 = 0.55, pair: ContactPairMaterial = STEEL_STEEL) {
        world = Object3D(feature = Scene()),
        table = Object3D(parent = world, translation = [0.0, 0.0, -0.05],
                         feature = Solid(shape = Box(lengths = [1.0, 1.0, 0.1]), solid_material = "Steel", collision = true)),
        steel = ContactPair(material1 = "Steel", material2 = "Steel", cor = pair.cor, mu_k = pair.mu_k,
                            mu_r = pair.mu_r, v_min = pair.v_min, w_min = pair.w_min),
        ball  = Object3D(feature = Solid(shape = Sphere(diameter = diameter), solid_material = "Steel", collision = true)),
        ball_free = FreeMotion(obj1 = world, obj2 = ball, r = Var(init = [0.0, 0.0, h0])),
    }
}

/// [`BouncingSphere`] as a scene description.
pub fn bouncing_sphere(diameter: f64, h0: f64, pair: ContactPairMaterial) -> SceneDesc {
    BouncingSphere { diameter, h0, pair }.scene()
}

/// Centre height \[m\] of a steel ball of diameter `diameter` resting on a steel table at its
/// static penetration.
pub fn resting_steel_ball_height(diameter: f64) -> f64 {
    let steel = builtin_steel();
    let r = 0.5 * diameter;
    let k = hertz_k_sphere_flat(r, &steel, &steel);
    r - static_penetration(sphere_mass(diameter, steel.density), 9.81, k)
}

model! {
    /// A steel ball (Ø `diameter`) resting on a steel table at its static penetration, launched
    /// sliding along x at `v0` with spin `spin` about y; pair material `pair` (friction,
    /// rolling resistance, `v_min`).
    pub SlidingBall(diameter: f64 = 0.1, v0: f64 = 4.0, spin: f64 = 0.0,
                    pair: ContactPairMaterial = ContactPairMaterial::new(0.7, 0.5, 0.0)) {
        world = Object3D(feature = Scene()),
        table = Object3D(parent = world, translation = [15.0, 0.0, -0.05],
                         feature = Solid(shape = Box(lengths = [40.0, 2.0, 0.1]), solid_material = "Steel", collision = true)),
        steel = ContactPair(material1 = "Steel", material2 = "Steel", cor = pair.cor, mu_k = pair.mu_k,
                            mu_r = pair.mu_r, v_min = pair.v_min, w_min = pair.w_min),
        ball  = Object3D(feature = Solid(shape = Sphere(diameter = diameter), solid_material = "Steel", collision = true)),
        ball_free = FreeMotion(obj1 = world, obj2 = ball, r = Var(init = [0.0, 0.0, resting_steel_ball_height(diameter)]),
                               v = Var(init = [v0, 0.0, 0.0]), w = Var(init = [0.0, spin, 0.0])),
    }
}

/// [`SlidingBall`] as a scene description.
pub fn sliding_ball(diameter: f64, v0: f64, spin: f64, pair: ContactPairMaterial) -> SceneDesc {
    SlidingBall {
        diameter,
        v0,
        spin,
        pair,
    }
    .scene()
}

fn builtin_steel() -> SolidMaterial {
    modia3d_core::scene::builtin_solid_material("Steel").expect("built-in")
}

/// Billiard ball diameter \[m\].
pub const BALL_DIAMETER: f64 = 0.06;

/// Height \[m\] of the centre of a billiard ball resting on the table (static penetration
/// subtracted, so the balls start in equilibrium) for contact reduction `k_red`.
pub fn billiard_ball_height(k_red: f64) -> f64 {
    let ball = modia3d_core::scene::builtin_solid_material("BilliardBall").expect("built-in");
    let table = modia3d_core::scene::builtin_solid_material("BilliardTable").expect("built-in");
    let r = 0.5 * BALL_DIAMETER;
    let k = k_red * hertz_k_sphere_flat(r, &ball, &table);
    r - static_penetration(sphere_mass(BALL_DIAMETER, ball.density), 9.81, k)
}

/// Billiard table length along x and width along y \[m\] (box 2.24 × 1.12 × 0.05 m, top face at
/// z = 0).
pub const TABLE: [f64; 2] = [2.24, 1.12];

/// Cushion radius \[m\]: the cushions are capsules of this radius along the table's edges.
pub const CUSHION_RADIUS: f64 = 0.01;

/// Height \[m\] of the cushions' axes, placed so that a ball touches them at 7/5·r above the
/// table top (contact point at r + r·(h − r)/(r + ρ) = 7/5·r).
pub const CUSHION_HEIGHT: f64 = 0.5 * BALL_DIAMETER + 0.4 * (0.5 * BALL_DIAMETER + CUSHION_RADIUS);

/// Initial position \[m\] of the ball in row `i` (0..5, away from the cue), place `j` (0..=i)
/// of Modia3D's rack: touching distance plus 0.1 mm, apex at x = 0.56 m, centre height `z`.
pub fn rack(i: usize, j: usize, z: f64) -> [f64; 3] {
    let d = BALL_DIAMETER + 1e-4;
    let row = 3f64.sqrt() / 2.0 * d;
    let x = 0.56 + i as f64 * row;
    let y = (j as f64 - 0.5 * i as f64) * d;
    [x, y, z]
}

model! {
    /// The billiard table of docs/reference/materials.md: a 2.24 × 1.12 m top (`top`, its upper face at z = 0)
    /// and four cushions (`cushion_n`, `_s`, `_e`, `_w`) whose contact line lies 7/5·r above it.
    pub assembly BilliardTable {
        top       = Object3D(translation = [0.0, 0.0, -0.025],
                             feature = Solid(shape = Box(lengths = [TABLE[0], TABLE[1], 0.05]),
                                             solid_material = "BilliardTable", collision = true)),
        cushion_n = Object3D(translation = [0.0, 0.5 * TABLE[1], CUSHION_HEIGHT],
                             feature = Solid(shape = Capsule(axis = 1, diameter = 2.0 * CUSHION_RADIUS, length = TABLE[0]),
                                             solid_material = "BilliardCushion", collision = true)),
        cushion_s = Object3D(translation = [0.0, -0.5 * TABLE[1], CUSHION_HEIGHT],
                             feature = Solid(shape = Capsule(axis = 1, diameter = 2.0 * CUSHION_RADIUS, length = TABLE[0]),
                                             solid_material = "BilliardCushion", collision = true)),
        cushion_e = Object3D(translation = [0.5 * TABLE[0], 0.0, CUSHION_HEIGHT],
                             feature = Solid(shape = Capsule(axis = 2, diameter = 2.0 * CUSHION_RADIUS, length = TABLE[1]),
                                             solid_material = "BilliardCushion", collision = true)),
        cushion_w = Object3D(translation = [-0.5 * TABLE[0], 0.0, CUSHION_HEIGHT],
                             feature = Solid(shape = Capsule(axis = 2, diameter = 2.0 * CUSHION_RADIUS, length = TABLE[1]),
                                             solid_material = "BilliardCushion", collision = true)),
    }
}

model! {
    /// Modia3D's 16-ball billiards: the rack of 15 balls ([`rack`]) and the cue ball at
    /// x = −0.56 m with velocity `cue_v`, on the table with cushions; `k_red` scales the contact
    /// stiffness.
    pub Billiards16(cue_v: [f64; 3] = [3.0, 0.1, 0.0], k_red: f64 = 1.0) {
        world     = Object3D(feature = Scene(k_red = k_red)),
        table     = BilliardTable(parent = world),
        ball1     = Object3D(feature = Solid(shape = Sphere(diameter = BALL_DIAMETER), solid_material = "BilliardBall", collision = true)),
        ball1_free = FreeMotion(obj1 = world, obj2 = ball1, r = Var(init = rack(0, 0, billiard_ball_height(k_red)))),
        ball2     = Object3D(feature = Solid(shape = Sphere(diameter = BALL_DIAMETER), solid_material = "BilliardBall", collision = true)),
        ball2_free = FreeMotion(obj1 = world, obj2 = ball2, r = Var(init = rack(1, 0, billiard_ball_height(k_red)))),
        ball3     = Object3D(feature = Solid(shape = Sphere(diameter = BALL_DIAMETER), solid_material = "BilliardBall", collision = true)),
        ball3_free = FreeMotion(obj1 = world, obj2 = ball3, r = Var(init = rack(1, 1, billiard_ball_height(k_red)))),
        ball4     = Object3D(feature = Solid(shape = Sphere(diameter = BALL_DIAMETER), solid_material = "BilliardBall", collision = true)),
        ball4_free = FreeMotion(obj1 = world, obj2 = ball4, r = Var(init = rack(2, 0, billiard_ball_height(k_red)))),
        ball5     = Object3D(feature = Solid(shape = Sphere(diameter = BALL_DIAMETER), solid_material = "BilliardBall", collision = true)),
        ball5_free = FreeMotion(obj1 = world, obj2 = ball5, r = Var(init = rack(2, 1, billiard_ball_height(k_red)))),
        ball6     = Object3D(feature = Solid(shape = Sphere(diameter = BALL_DIAMETER), solid_material = "BilliardBall", collision = true)),
        ball6_free = FreeMotion(obj1 = world, obj2 = ball6, r = Var(init = rack(2, 2, billiard_ball_height(k_red)))),
        ball7     = Object3D(feature = Solid(shape = Sphere(diameter = BALL_DIAMETER), solid_material = "BilliardBall", collision = true)),
        ball7_free = FreeMotion(obj1 = world, obj2 = ball7, r = Var(init = rack(3, 0, billiard_ball_height(k_red)))),
        ball8     = Object3D(feature = Solid(shape = Sphere(diameter = BALL_DIAMETER), solid_material = "BilliardBall", collision = true)),
        ball8_free = FreeMotion(obj1 = world, obj2 = ball8, r = Var(init = rack(3, 1, billiard_ball_height(k_red)))),
        ball9     = Object3D(feature = Solid(shape = Sphere(diameter = BALL_DIAMETER), solid_material = "BilliardBall", collision = true)),
        ball9_free = FreeMotion(obj1 = world, obj2 = ball9, r = Var(init = rack(3, 2, billiard_ball_height(k_red)))),
        ball10    = Object3D(feature = Solid(shape = Sphere(diameter = BALL_DIAMETER), solid_material = "BilliardBall", collision = true)),
        ball10_free = FreeMotion(obj1 = world, obj2 = ball10, r = Var(init = rack(3, 3, billiard_ball_height(k_red)))),
        ball11    = Object3D(feature = Solid(shape = Sphere(diameter = BALL_DIAMETER), solid_material = "BilliardBall", collision = true)),
        ball11_free = FreeMotion(obj1 = world, obj2 = ball11, r = Var(init = rack(4, 0, billiard_ball_height(k_red)))),
        ball12    = Object3D(feature = Solid(shape = Sphere(diameter = BALL_DIAMETER), solid_material = "BilliardBall", collision = true)),
        ball12_free = FreeMotion(obj1 = world, obj2 = ball12, r = Var(init = rack(4, 1, billiard_ball_height(k_red)))),
        ball13    = Object3D(feature = Solid(shape = Sphere(diameter = BALL_DIAMETER), solid_material = "BilliardBall", collision = true)),
        ball13_free = FreeMotion(obj1 = world, obj2 = ball13, r = Var(init = rack(4, 2, billiard_ball_height(k_red)))),
        ball14    = Object3D(feature = Solid(shape = Sphere(diameter = BALL_DIAMETER), solid_material = "BilliardBall", collision = true)),
        ball14_free = FreeMotion(obj1 = world, obj2 = ball14, r = Var(init = rack(4, 3, billiard_ball_height(k_red)))),
        ball15    = Object3D(feature = Solid(shape = Sphere(diameter = BALL_DIAMETER), solid_material = "BilliardBall", collision = true)),
        ball15_free = FreeMotion(obj1 = world, obj2 = ball15, r = Var(init = rack(4, 4, billiard_ball_height(k_red)))),
        cue       = Object3D(feature = Solid(shape = Sphere(diameter = BALL_DIAMETER), solid_material = "BilliardBall", collision = true)),
        cue_free  = FreeMotion(obj1 = world, obj2 = cue, r = Var(init = [-0.56, 0.0, billiard_ball_height(k_red)]), v = Var(init = cue_v)),
    }
}

/// [`Billiards16`] as a scene description.
pub fn billiards16(cue_v: [f64; 3], k_red: f64) -> SceneDesc {
    Billiards16 { cue_v, k_red }.scene()
}

model! {
    /// A billiard cue ball rolling (v = ω r) along x at `v` from x = −0.9 m towards a resting
    /// ball at x = −0.4 m.
    pub TwoBalls(v: f64 = 2.0) {
        world     = Object3D(feature = Scene()),
        table     = BilliardTable(parent = world),
        cue       = Object3D(feature = Solid(shape = Sphere(diameter = BALL_DIAMETER), solid_material = "BilliardBall", collision = true)),
        cue_free  = FreeMotion(obj1 = world, obj2 = cue, r = Var(init = [-0.9, 0.0, billiard_ball_height(1.0)]),
                               v = Var(init = [v, 0.0, 0.0]), w = Var(init = [0.0, v / (0.5 * BALL_DIAMETER), 0.0])),
        ball      = Object3D(feature = Solid(shape = Sphere(diameter = BALL_DIAMETER), solid_material = "BilliardBall", collision = true)),
        ball_free = FreeMotion(obj1 = world, obj2 = ball, r = Var(init = [-0.4, 0.0, billiard_ball_height(1.0)])),
    }
}

/// [`TwoBalls`] as a scene description.
pub fn two_balls(v: f64) -> SceneDesc {
    TwoBalls { v }.scene()
}

model! {
    /// A billiard ball rolling (v = ω r) along x at `v` towards the east cushion.
    pub BallCushion(v: f64 = 1.0) {
        world     = Object3D(feature = Scene()),
        table     = BilliardTable(parent = world),
        ball      = Object3D(feature = Solid(shape = Sphere(diameter = BALL_DIAMETER), solid_material = "BilliardBall", collision = true)),
        ball_free = FreeMotion(obj1 = world, obj2 = ball, r = Var(init = [0.8, 0.0, billiard_ball_height(1.0)]),
                               v = Var(init = [v, 0.0, 0.0]), w = Var(init = [0.0, v / (0.5 * BALL_DIAMETER), 0.0])),
    }
}

/// [`BallCushion`] as a scene description.
pub fn ball_cushion(v: f64) -> SceneDesc {
    BallCushion { v }.scene()
}

/// Pendulum length \[m\] of Newton's cradle.
pub const CRADLE_LENGTH: f64 = 0.5;

model! {
    /// Newton's cradle: 5 steel balls (Ø `diameter`) on 0.5 m pendulums (Revolute joints with
    /// `can_collide = true`), neighbouring balls `gap` apart; the first ball starts with speed
    /// `v0` towards the others. Contact material `CradleSteel` (elasticity of Steel) with the
    /// pair material `pair`.
    pub NewtonsCradle(diameter: f64 = 0.05, gap: f64 = 1e-3, v0: f64 = 0.5,
                      pair: ContactPairMaterial = ContactPairMaterial::new(1.0, 0.0, 0.0)) {
        world  = Object3D(feature = Scene()),
        cradle = ContactPair(material1 = "CradleSteel", material2 = "CradleSteel", cor = pair.cor, mu_k = pair.mu_k,
                             mu_r = pair.mu_r, v_min = pair.v_min, w_min = pair.w_min),
        hook0  = Object3D(parent = world, translation = [0.0 * (diameter + gap), 0.0, CRADLE_LENGTH]),
        ball0  = Object3D(feature = Solid(shape = Sphere(diameter = diameter), solid_material = "Steel",
                                            contact_material = "CradleSteel", collision = true)),
        pivot0 = Object3D(parent = ball0, translation = [0.0, 0.0, CRADLE_LENGTH]),
        rev0   = Revolute(obj1 = hook0, obj2 = pivot0, axis = -2, can_collide = true, w = Var(init = v0 / CRADLE_LENGTH)),
        hook1  = Object3D(parent = world, translation = [1.0 * (diameter + gap), 0.0, CRADLE_LENGTH]),
        ball1  = Object3D(feature = Solid(shape = Sphere(diameter = diameter), solid_material = "Steel",
                                            contact_material = "CradleSteel", collision = true)),
        pivot1 = Object3D(parent = ball1, translation = [0.0, 0.0, CRADLE_LENGTH]),
        rev1   = Revolute(obj1 = hook1, obj2 = pivot1, axis = -2, can_collide = true),
        hook2  = Object3D(parent = world, translation = [2.0 * (diameter + gap), 0.0, CRADLE_LENGTH]),
        ball2  = Object3D(feature = Solid(shape = Sphere(diameter = diameter), solid_material = "Steel",
                                            contact_material = "CradleSteel", collision = true)),
        pivot2 = Object3D(parent = ball2, translation = [0.0, 0.0, CRADLE_LENGTH]),
        rev2   = Revolute(obj1 = hook2, obj2 = pivot2, axis = -2, can_collide = true),
        hook3  = Object3D(parent = world, translation = [3.0 * (diameter + gap), 0.0, CRADLE_LENGTH]),
        ball3  = Object3D(feature = Solid(shape = Sphere(diameter = diameter), solid_material = "Steel",
                                            contact_material = "CradleSteel", collision = true)),
        pivot3 = Object3D(parent = ball3, translation = [0.0, 0.0, CRADLE_LENGTH]),
        rev3   = Revolute(obj1 = hook3, obj2 = pivot3, axis = -2, can_collide = true),
        hook4  = Object3D(parent = world, translation = [4.0 * (diameter + gap), 0.0, CRADLE_LENGTH]),
        ball4  = Object3D(feature = Solid(shape = Sphere(diameter = diameter), solid_material = "Steel",
                                            contact_material = "CradleSteel", collision = true)),
        pivot4 = Object3D(parent = ball4, translation = [0.0, 0.0, CRADLE_LENGTH]),
        rev4   = Revolute(obj1 = hook4, obj2 = pivot4, axis = -2, can_collide = true),
    }
}

/// [`NewtonsCradle`] as a scene description.
pub fn newtons_cradle(diameter: f64, gap: f64, v0: f64, pair: ContactPairMaterial) -> SceneDesc {
    NewtonsCradle {
        diameter,
        gap,
        v0,
        pair,
    }
    .scene()
}

model! {
    /// Boxes and cylinders (DryWood) dropped onto a fixed wooden table; `k_red` scales the
    /// contact stiffness.
    pub FallingBoxes(k_red: f64 = 1e-3) {
        world = Object3D(feature = Scene(k_red = k_red)),
        table = Object3D(parent = world, translation = [0.0, 0.0, -0.05],
                         feature = Solid(shape = Box(lengths = [2.0, 2.0, 0.1]), solid_material = "DryWood", collision = true)),
        box1  = Object3D(feature = Solid(shape = Box(lengths = [0.2, 0.1, 0.05]), solid_material = "DryWood", collision = true)),
        box1_free = FreeMotion(obj1 = world, obj2 = box1, r = Var(init = [-0.4, 0.0, 0.2]), rot = Var(init = [0.3, 0.2, 0.0])),
        box2  = Object3D(feature = Solid(shape = Box(lengths = [0.1, 0.1, 0.1]), solid_material = "DryWood", collision = true)),
        box2_free = FreeMotion(obj1 = world, obj2 = box2, r = Var(init = [0.0, 0.3, 0.3]), rot = Var(init = [0.0, 0.5, 0.1])),
        cyl1  = Object3D(feature = Solid(shape = Cylinder(axis = 3, diameter = 0.1, length = 0.1), solid_material = "DryWood",
                                         collision = true)),
        cyl1_free = FreeMotion(obj1 = world, obj2 = cyl1, r = Var(init = [0.3, -0.2, 0.25]), rot = Var(init = [0.2, 0.0, 0.4])),
        cyl2  = Object3D(feature = Solid(shape = Cylinder(axis = 1, diameter = 0.08, length = 0.2), solid_material = "DryWood",
                                         collision = true)),
        cyl2_free = FreeMotion(obj1 = world, obj2 = cyl2, r = Var(init = [0.0, -0.5, 0.4]), rot = Var(init = [0.0, 0.4, 0.3])),
    }
}

/// The world (options default but `k_red`) and the fixed DryWood table of [`FallingBoxes`]
/// (2 × 2 × 0.1 m, top face at z = 0), for scenes that put bodies on it.
pub fn wooden_table(k_red: f64) -> SceneDesc {
    world_and_table(k_red, [2.0, 2.0, 0.1], "DryWood")
}

/// The world (options default but `k_red`) and a fixed table `table` of `lengths` \[m\] and
/// `material`, its top face at z = 0.
fn world_and_table(k_red: f64, lengths: [f64; 3], material: &str) -> SceneDesc {
    let mut s = SceneDesc::new();
    s.add(world(SceneOptions {
        k_red,
        ..Default::default()
    }))
    .add(fixed_box(
        "table",
        lengths,
        [0.0, 0.0, -lengths[2] / 2.0],
        material,
    ));
    s
}

/// [`FallingBoxes`] as a scene description.
pub fn falling_boxes(k_red: f64) -> SceneDesc {
    FallingBoxes { k_red }.scene()
}

/// Inner width \[m\] of the open steel box of [`ball_pile`].
pub const PILE_BOX_WIDTH: f64 = 0.16;
/// Diameter \[m\] of the balls of [`ball_pile`].
pub const PILE_BALL_DIAMETER: f64 = 0.05;
/// Number of balls of [`ball_pile`] (`b0` … `b11`).
pub const PILE_BALLS: usize = 12;

/// A stress scene: twelve steel balls (Ø 5 cm, three layers of 2 × 2, each ball slightly
/// offset) dropped into an open steel box 16 cm wide (floor `floor`, walls `wx0`, `wx1`, `wy0`,
/// `wy1`), so they hit the floor, the walls and each other in clusters. `pair` is the
/// Steel–Steel pair material; `options` the scene options.
pub fn ball_pile(options: SceneOptions, pair: ContactPairMaterial) -> SceneDesc {
    let mut s = SceneDesc::new();
    s.add(world(options))
        .add_contact_pair("Steel", "Steel", pair);
    add_open_box(&mut s, PILE_BOX_WIDTH, 0.05, 0.3);
    for k in 0..PILE_BALLS {
        let (layer, i, j) = (k / 4, (k / 2) % 2, k % 2);
        let jitter = 0.004 * ((k * 7 % 5) as f64 - 2.0);
        let r = [
            -0.03 + 0.06 * i as f64 + jitter,
            -0.03 + 0.06 * j as f64 - 0.5 * jitter,
            0.05 + 0.07 * layer as f64,
        ];
        let name = format!("b{k}");
        add_free_sphere(
            &mut s,
            &name,
            PILE_BALL_DIAMETER,
            "Steel",
            None,
            r,
            [0.0; 3],
            [0.0; 3],
        );
    }
    s
}

/// Adds an open steel box with a square inner width `w` \[m\], floor and walls `t` \[m\]
/// thick, walls `h` \[m\] high, its floor's top face at z = 0 (objects `floor`, `wx0`, `wx1`,
/// `wy0`, `wy1`).
fn add_open_box(s: &mut SceneDesc, w: f64, t: f64, h: f64) {
    s.add(fixed_box(
        "floor",
        [w + 2.0 * t, w + 2.0 * t, t],
        [0.0, 0.0, -t / 2.0],
        "Steel",
    ))
    .add(fixed_box(
        "wx0",
        [t, w, h],
        [-(w + t) / 2.0, 0.0, h / 2.0],
        "Steel",
    ))
    .add(fixed_box(
        "wx1",
        [t, w, h],
        [(w + t) / 2.0, 0.0, h / 2.0],
        "Steel",
    ))
    .add(fixed_box(
        "wy0",
        [w + 2.0 * t, t, h],
        [0.0, -(w + t) / 2.0, h / 2.0],
        "Steel",
    ))
    .add(fixed_box(
        "wy1",
        [w + 2.0 * t, t, h],
        [0.0, (w + t) / 2.0, h / 2.0],
        "Steel",
    ));
}

/// A ball pit for the linear algebra (`examples/ball_pit.rs`): `n` steel balls Ø 5 cm in
/// layers of `side × side` (`side = ⌈∛n⌉`), 5 mm apart with a few millimetres of jitter,
/// dropped into an open steel box just wide enough for one layer, `k_red = 1e-3`. Once they
/// settle every ball touches its neighbours, so the iteration matrix is one component of
/// `13·n` unknowns in which each ball couples with a handful of others.
pub fn ball_pit(n: usize) -> SceneDesc {
    let side = (n as f64).cbrt().ceil().max(1.0) as usize;
    let pitch = 0.055;
    let w = side as f64 * pitch;
    let mut s = SceneDesc::new();
    s.add(world(SceneOptions {
        k_red: 1e-3,
        ..Default::default()
    }))
    .add_contact_pair("Steel", "Steel", STEEL_STEEL);
    add_open_box(&mut s, w, 0.05, 0.06 * (n / (side * side) + 2) as f64);
    for k in 0..n {
        let (layer, i, j) = (k / (side * side), (k / side) % side, k % side);
        let jitter = 0.003 * ((k * 7 % 5) as f64 - 2.0);
        let r = [
            (i as f64 + 0.5) * pitch - w / 2.0 + jitter,
            (j as f64 + 0.5) * pitch - w / 2.0 - 0.5 * jitter,
            0.03 + 0.06 * layer as f64,
        ];
        add_free_sphere(
            &mut s,
            &format!("b{k}"),
            0.05,
            "Steel",
            None,
            r,
            [0.0; 3],
            [0.0; 3],
        );
    }
    s
}

/// The scaling scene (`examples/scaling.rs`): `n` steel balls Ø 5 cm on a square grid 0.1 m
/// apart, 2.5–8.5 cm above a steel table (top face at z = 0), sideways speeds of ±0.1 m/s,
/// `k_red = 1e-3`. No ball touches another; N²/2 shape pairs for the broad phase.
pub fn balls_on_table(n: usize) -> SceneDesc {
    let side = (n as f64).sqrt().ceil() as usize;
    let width = side as f64 * 0.1 + 0.2;
    let mut s = SceneDesc::new();
    s.add(world(SceneOptions {
        k_red: 1e-3,
        ..Default::default()
    }))
    .add(fixed_box(
        "table",
        [width, width, 0.05],
        [0.0, 0.0, -0.025],
        "Steel",
    ));
    for k in 0..n {
        let (i, j) = (k / side, k % side);
        let r = [
            0.1 * i as f64 - 0.05 * side as f64,
            0.1 * j as f64 - 0.05 * side as f64,
            0.05 + 0.01 * (k % 7) as f64,
        ];
        let v = [0.1 * ((k % 3) as f64 - 1.0), 0.0, 0.0];
        add_free_sphere(
            &mut s,
            &format!("b{k}"),
            0.05,
            "Steel",
            None,
            r,
            v,
            [0.0; 3],
        );
    }
    s
}

/// The sweep template of [`BouncingSphere`] that `examples/sweep_shard.rs` registers and
/// `tests/sweep.rs` checks: parameters `h0` (drop height of the centre \[m\], default 0.55),
/// `cor` (Steel–Steel coefficient of restitution \[1\], default 0.7) and `diameter` \[m\]
/// (default 0.1), each optional in a sweep file; runs of 1 s at rtol 1e-6 with output every
/// 10 ms (a sweep file may override these); metric `events`: the number of events of the run
/// \[1\].
pub fn bouncing_sphere_sweep() -> Sweep {
    Sweep::new(|p| {
        let pair = ContactPairMaterial::new(p.get_or("cor", STEEL_STEEL.cor), 0.5, 0.001);
        Ok(BouncingSphere {
            diameter: p.get_or("diameter", 0.1),
            h0: p.get_or("h0", 0.55),
            pair,
        }
        .build()?)
    })
    .options(SimOptions::new(1.0).tolerance(1e-6).interval(0.01))
    .metric("events", "", |res| Ok(res.events.len() as f64))
}

/// The models sweep files may name in `examples/sweep_shard.rs`: `bouncing_sphere`
/// ([`bouncing_sphere_sweep`]).
pub fn sweep_registry() -> SweepRegistry {
    SweepRegistry::new().add("bouncing_sphere", bouncing_sphere_sweep())
}

/// Name of the fixed plank and of the free body of [`on_incline`].
pub const INCLINE_NAMES: (&str, &str) = ("plank", "body");

/// A fixed plank (box 4 × 1 × 0.1 m, DryWood unless `material` names another) tilted by
/// `alpha` \[rad\] about the world y axis, its top face through the world origin, and a free
/// body `body` of `shape` (the same material) lying on it: the body's frame is turned like
/// the plank (so a shape's local z is the plank's normal), its origin `height` \[m\] above the
/// face (the shape's half height: touching, no penetration) at `s0` \[m\] along the downhill
/// direction `(cos α, 0, −sin α)`, moving downhill at `v0` [m/s] and spinning at `w` [rad/s]
/// (resolved in the body frame). `pair` is the material's self-pair; `options` the scene's.
/// With `alpha = 0` the plank is a table.
#[allow(clippy::too_many_arguments)]
pub fn on_incline(
    shape: Shape,
    height: f64,
    alpha: f64,
    s0: f64,
    v0: f64,
    w: [f64; 3],
    material: &str,
    pair: ContactPairMaterial,
    options: SceneOptions,
) -> SceneDesc {
    let rot = nalgebra::Rotation3::from_axis_angle(&Vector3::y_axis(), alpha);
    let (plank, body) = INCLINE_NAMES;
    let mut s = SceneDesc::new();
    s.add(world(options))
        .add_contact_pair(material, material, pair)
        .add(
            Object3D::new(plank)
                .parent("world")
                .translation((rot * Vector3::new(0.0, 0.0, -0.05)).into())
                .rotation(Rotation::Matrix(*rot.matrix()))
                .solid(
                    Solid::new(Shape::Box {
                        lengths: Vector3::new(4.0, 1.0, 0.1),
                    })
                    .material(material)
                    .collision(true),
                ),
        )
        .add(Object3D::new(body).solid(Solid::new(shape).material(material).collision(true)))
        .add_joint(Joint::new(
            "body.free",
            "world",
            body,
            JointKind::FreeMotion {
                r: rot * Vector3::new(s0, 0.0, height),
                rot: FreeRotation::Cardan([0.0, alpha, 0.0]),
                v: rot * Vector3::new(v0, 0.0, 0.0),
                w: Vector3::from(w),
            },
        ));
    s
}

/// A fixed DryWood table (2 × 2 × 0.1 m, top face at z = 0) and `n` DryWood boxes of
/// `lengths` \[m\] stacked on it, `b0` at the bottom, each touching the one below, at rest;
/// box `i` shifted by `i·shift` \[m\] along x. `options` are the scene's.
pub fn box_stack(lengths: [f64; 3], n: usize, shift: f64, options: SceneOptions) -> SceneDesc {
    let mut s = SceneDesc::new();
    s.add(world(options)).add(fixed_box(
        "table",
        [2.0, 2.0, 0.1],
        [0.0, 0.0, -0.05],
        "DryWood",
    ));
    for i in 0..n {
        let name = format!("b{i}");
        s.add(
            Object3D::new(&name).solid(
                Solid::new(Shape::Box {
                    lengths: Vector3::from(lengths),
                })
                .material("DryWood")
                .collision(true),
            ),
        )
        .add_joint(Joint::new(
            &format!("{name}.free"),
            "world",
            &name,
            JointKind::FreeMotion {
                r: Vector3::new(i as f64 * shift, 0.0, lengths[2] * (i as f64 + 0.5)),
                rot: FreeRotation::Cardan([0.0; 3]),
                v: Vector3::zeros(),
                w: Vector3::zeros(),
            },
        ));
    }
    s
}

/// `scene` with its world's contact profile set to `profile` (for tests and benchmarks that
/// pin a law: the paper's scenes pin [`ContactProfile::Paper2019`]).
pub fn with_profile(mut scene: SceneDesc, profile: ContactProfile) -> SceneDesc {
    for o in &mut scene.objects {
        if let Feature::Scene(opts) = &mut o.feature {
            opts.contact_profile = profile;
        }
    }
    scene
}

/// Housner's rigid block rocking on an edge, the reference of [`cube_on_edge`]: the time \[s\] a
/// cube of half edge `b` \[m\] released from rest at the angle `theta0` \[rad\] away from flat
/// falls back to flat, from `θ̈ = −p² sin(α − θ)` (`p² = 3g/(4R)`, `R = b√2` the half
/// diagonal, `α = π/4`, g = 9.81 m/s²) integrated by classical RK4 at 1e-6 s (error ~1e-12 s).
pub fn housner_fall_back_time(b: f64, theta0: f64) -> f64 {
    let p2 = 3.0 * 9.81 / (4.0 * b * 2f64.sqrt());
    let f = |th: f64| -p2 * (std::f64::consts::FRAC_PI_4 - th).sin();
    let (mut th, mut om, mut t, h) = (theta0, 0.0f64, 0.0, 1e-6);
    loop {
        let (k1, l1) = (om, f(th));
        let (k2, l2) = (om + 0.5 * h * l1, f(th + 0.5 * h * k1));
        let (k3, l3) = (om + 0.5 * h * l2, f(th + 0.5 * h * k2));
        let (k4, l4) = (om + h * l3, f(th + h * k3));
        let next = th + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        om += h / 6.0 * (l1 + 2.0 * l2 + 2.0 * l3 + l4);
        if next <= 0.0 || t > 100.0 {
            return t + h * th / (th - next);
        }
        th = next;
        t += h;
    }
}

/// A DryWood cube of half edge `b` \[m\] on a flat DryWood plank ([`on_incline`] at `α = 0`)
/// turned by `theta0` \[rad\] about y so that its edge `(b, ·, −b)` rests on the plank at the
/// origin, released from rest; `pair` is the DryWood self-pair.
pub fn cube_on_edge(b: f64, theta0: f64, pair: ContactPairMaterial) -> SceneDesc {
    let cube = Shape::Box {
        lengths: Vector3::repeat(2.0 * b),
    };
    let mut s = on_incline(
        cube,
        0.0,
        0.0,
        0.0,
        0.0,
        [0.0; 3],
        "DryWood",
        pair,
        SceneOptions::default(),
    );
    s.joints[0].kind = JointKind::FreeMotion {
        r: Vector3::new(
            -b * (theta0.cos() - theta0.sin()),
            0.0,
            b * (theta0.sin() + theta0.cos()),
        ),
        rot: FreeRotation::Cardan([0.0, theta0, 0.0]),
        v: Vector3::zeros(),
        w: Vector3::zeros(),
    };
    s
}

/// The speed \[m/s\] of [`on_incline`]'s body along the downhill direction `(cos α, 0, −sin α)`
/// at time `t` \[s\] of `res`.
pub fn downhill_speed(res: &SimulationResult, alpha: f64, t: f64) -> Result<f64, ResultError> {
    let v = res.signal_at("body.v_abs", t)?;
    Ok(v[0] * alpha.cos() - v[2] * alpha.sin())
}

/// A steel ball (Ø 0.02 m) on a Prismatic joint `slide` along z from the world (0.1 m up) above
/// a fixed 1 × 1 × 0.1 m steel `table` (top face at z = 0), the joint's `can_collide` as given:
/// with `false` (the default) the two can never touch, which a run warns about
/// (`SimWarning::NeverCollide`); with `true` they form a collision pair.
pub fn ball_on_a_slide(can_collide: bool) -> SceneDesc {
    let mut s = SceneDesc::new();
    s.add(world(SceneOptions::default()))
        .add(fixed_box(
            "table",
            [1.0, 1.0, 0.1],
            [0.0, 0.0, -0.05],
            "Steel",
        ))
        .add(
            Object3D::new("ball").solid(
                Solid::new(Shape::Sphere { diameter: 0.02 })
                    .material("Steel")
                    .collision(true),
            ),
        )
        .add_joint(
            Joint::new(
                "slide",
                "world",
                "ball",
                JointKind::Prismatic {
                    axis: Vector3::z(),
                    s: 0.1,
                    v: 0.0,
                },
            )
            .can_collide(can_collide),
        );
    s
}
