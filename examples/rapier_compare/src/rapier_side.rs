//! The Rapier side of each scene (docs/rapier-comparison.md): the same bodies, sizes, masses,
//! initial state and coefficients as the modia3d scene, with Rapier's rigid contacts (velocity
//! level, restitution as a velocity target, no compliance). One accuracy setting is a time
//! step `dt` \[s\] and a number of solver iterations (Rapier's substeps of one step); all other
//! integration parameters are Rapier's defaults. Bodies never sleep (a sleeping body would
//! stop a slow ball by a threshold, which is no part of either law).

use rapier3d_f64::prelude as rp;
use rp::{CoefficientCombineRule, ColliderBuilder, RigidBodyBuilder, RigidBodyHandle, Vector};
use std::time::Instant;

/// One accuracy setting of Rapier.
#[derive(Clone, Copy, Debug)]
pub struct Setting {
    /// Time step \[s\].
    pub dt: f64,
    /// `IntegrationParameters::num_solver_iterations` (substeps per step).
    pub iterations: usize,
}

impl Setting {
    /// "dt 1/960, it 4".
    pub fn label(&self) -> String {
        format!("dt 1/{:.0}, it {}", 1.0 / self.dt, self.iterations)
    }
}

/// A world with gravity `g` [m/s²] along z and the setting's step and iterations.
fn world(s: Setting, g: [f64; 3]) -> rp::PhysicsWorld {
    let mut w = rp::PhysicsWorld::new();
    w.gravity = Vector::new(g[0], g[1], g[2]);
    w.integration_parameters.dt = s.dt;
    w.integration_parameters.num_solver_iterations = s.iterations;
    w
}

/// A dynamic ball of radius `r` \[m\] and density `rho` [kg/m³] at `p` with velocity `v`.
fn ball(
    w: &mut rp::PhysicsWorld,
    r: f64,
    rho: f64,
    p: [f64; 3],
    v: [f64; 3],
    restitution: f64,
    friction: f64,
) -> RigidBodyHandle {
    w.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(p[0], p[1], p[2]))
            .linvel(Vector::new(v[0], v[1], v[2]))
            .can_sleep(false),
        coefficients(ColliderBuilder::ball(r).density(rho), restitution, friction),
    )
    .0
}

/// Restitution combined by `Min`, friction by `Max` (the rule of the pair is the larger of
/// the two colliders' rules, so every collider carries the same rules): with these a pair
/// gets the coefficients the modia3d scene gives it (see the billiards scene).
fn coefficients(c: ColliderBuilder, restitution: f64, friction: f64) -> ColliderBuilder {
    c.restitution(restitution)
        .friction(friction)
        .restitution_combine_rule(CoefficientCombineRule::Min)
        .friction_combine_rule(CoefficientCombineRule::Max)
}

/// A fixed box of half extents `h` centred at `p`.
fn fixed_box(w: &mut rp::PhysicsWorld, h: [f64; 3], p: [f64; 3], restitution: f64, friction: f64) {
    w.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(p[0], p[1], p[2])),
        coefficients(
            ColliderBuilder::cuboid(h[0], h[1], h[2]),
            restitution,
            friction,
        ),
    );
}

/// Position and velocity of one body after each step, with the time.
pub struct Samples {
    /// Times \[s\] (0 first).
    pub t: Vec<f64>,
    /// Positions \[m\] per sample.
    pub r: Vec<[f64; 3]>,
    /// Velocities [m/s] per sample.
    pub v: Vec<[f64; 3]>,
}

fn v3(x: Vector) -> [f64; 3] {
    [x.x, x.y, x.z]
}

/// Steps `w` for `stop` \[s\] (the whole number of steps that reaches it), recording body
/// `rec` (if any) after every step; returns the wall time of the stepping \[s\].
fn run(w: &mut rp::PhysicsWorld, stop: f64, rec: Option<RigidBodyHandle>) -> (f64, Samples) {
    let dt = w.integration_parameters.dt;
    let n = (stop / dt - 1e-9).ceil().max(1.0) as usize;
    let cap = if rec.is_some() { n + 1 } else { 0 };
    let mut s = Samples {
        t: Vec::with_capacity(cap),
        r: Vec::with_capacity(cap),
        v: Vec::with_capacity(cap),
    };
    let t0 = Instant::now();
    let push = |w: &rp::PhysicsWorld, k: usize, s: &mut Samples| {
        if let Some(h) = rec {
            let b = &w.bodies[h];
            s.t.push(k as f64 * dt);
            s.r.push(v3(b.translation()));
            s.v.push(v3(b.linvel()));
        }
    };
    push(w, 0, &mut s);
    for k in 1..=n {
        w.step();
        push(w, k, &mut s);
    }
    (t0.elapsed().as_secs_f64(), s)
}

/// One ball (Ø `d`, density `rho`) at height `z0` with velocity `v0` over a fixed steel plate
/// (top face at z = 0, `plate` half extents), gravity 9.81 m/s² along −z: bounce, steel drop,
/// slide-to-roll. Returns the wall time and the ball's samples.
#[allow(clippy::too_many_arguments)]
pub fn ball_on_plate(
    s: Setting,
    d: f64,
    rho: f64,
    z0: f64,
    v0: [f64; 3],
    plate: ([f64; 3], [f64; 3]),
    restitution: f64,
    friction: f64,
    stop: f64,
) -> (f64, Samples) {
    let mut w = world(s, [0.0, 0.0, -9.81]);
    fixed_box(&mut w, plate.0, plate.1, restitution, friction);
    let h = ball(
        &mut w,
        d / 2.0,
        rho,
        [0.0, 0.0, z0],
        v0,
        restitution,
        friction,
    );
    run(&mut w, stop, Some(h))
}

/// Balls (Ø `d`, density `rho`) at `p` with velocities `v`, no gravity, no other body,
/// restitution `e`, no friction: the cradle. Returns the wall time and the final velocities.
pub fn free_balls(
    s: Setting,
    d: f64,
    rho: f64,
    p: &[[f64; 3]],
    v: &[[f64; 3]],
    e: f64,
    stop: f64,
) -> (f64, Vec<[f64; 3]>) {
    let mut w = world(s, [0.0; 3]);
    let hs: Vec<_> = p
        .iter()
        .zip(v)
        .map(|(p, v)| ball(&mut w, d / 2.0, rho, *p, *v, e, 0.0))
        .collect();
    let (wall, _) = run(&mut w, stop, None);
    (wall, hs.iter().map(|h| v3(w.bodies[*h].linvel())).collect())
}

/// The 16-ball break (modia3d's `demo::billiards16` geometry): table top, four capsule
/// cushions, 15 racked balls and the cue ball with velocity `cue_v`; per pair the coefficients
/// of modia3d's palette (ball–ball restitution 1, no friction; ball–table restitution 0,
/// friction 0.8; ball–cushion restitution 0.98, no friction; Rapier has no rolling
/// resistance). `rack` gives the 15 ball centres, the cue ball last. Returns the wall time and
/// the 16 final positions (rack order, cue last).
pub fn billiards(
    s: Setting,
    rho: f64,
    balls: &[[f64; 3]],
    cue_v: [f64; 3],
    stop: f64,
) -> (f64, Vec<[f64; 3]>) {
    use modia3d::demo::{BALL_DIAMETER, CUSHION_HEIGHT, CUSHION_RADIUS, TABLE};
    let mut w = world(s, [0.0, 0.0, -9.81]);
    // Table: restitution 0 (min with the ball's 1), friction 0.8 (max with the ball's 0).
    fixed_box(
        &mut w,
        [TABLE[0] / 2.0, TABLE[1] / 2.0, 0.025],
        [0.0, 0.0, -0.025],
        0.0,
        0.8,
    );
    // Cushions: restitution 0.98, no friction. Capsules of length `TABLE[k]` along x (north,
    // south) and y (east, west), half height = half length.
    for (p, along_x) in [
        ([0.0, 0.5 * TABLE[1], CUSHION_HEIGHT], true),
        ([0.0, -0.5 * TABLE[1], CUSHION_HEIGHT], true),
        ([0.5 * TABLE[0], 0.0, CUSHION_HEIGHT], false),
        ([-0.5 * TABLE[0], 0.0, CUSHION_HEIGHT], false),
    ] {
        let c = if along_x {
            ColliderBuilder::capsule_x(TABLE[0] / 2.0, CUSHION_RADIUS)
        } else {
            ColliderBuilder::capsule_y(TABLE[1] / 2.0, CUSHION_RADIUS)
        };
        w.insert(
            RigidBodyBuilder::fixed().translation(Vector::new(p[0], p[1], p[2])),
            coefficients(c, 0.98, 0.0),
        );
    }
    let n = balls.len();
    let hs: Vec<_> = balls
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let v = if k + 1 == n { cue_v } else { [0.0; 3] };
            ball(&mut w, BALL_DIAMETER / 2.0, rho, *p, v, 1.0, 0.0)
        })
        .collect();
    let (wall, _) = run(&mut w, stop, None);
    (
        wall,
        hs.iter().map(|h| v3(w.bodies[*h].translation())).collect(),
    )
}
