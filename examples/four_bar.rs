//! A planar crank-rocker four-bar linkage (crank 0.1 m, coupler 0.3 m, rocker 0.25 m, ground
//! 0.3 m: Grashof, the crank turns fully) of steel bars, its crank driven at a constant speed
//! by a prescribed acceleration of zero. The loop is closed by the revolute `loop_joint`
//! between the coupler's and the rocker's tips, which the library cuts and turns into
//! constraints; the initial coupler and rocker angles are rough guesses that the build corrects.
//! Prints the rocker angle against Freudenstein's equation over one crank revolution and the
//! constraint force in the cut joint.

use modia3d::prelude::*;

model! {
    /// Crank `a`, coupler `b`, rocker `c`, ground `d` [m]: steel bars `w` × `w` in cross-section,
    /// turning about z in the x-y plane (gravity along −y). `theta2` [rad] and `omega` [rad/s]:
    /// the crank's initial angle and speed; `phi3`, `phi4`: rough initial coupler (relative to
    /// the crank) and rocker angles [rad].
    pub FourBar(a: f64 = 0.1, b: f64 = 0.3, c: f64 = 0.25, d: f64 = 0.3, w: f64 = 0.01,
                theta2: f64 = 0.5, omega: f64 = std::f64::consts::TAU,
                phi3: f64 = 0.2, phi4: f64 = 1.5) {
        world       = Object3D(feature = Scene(gravity = [0.0, -9.81, 0.0])),
        ground_b    = Object3D(parent = world, translation = [d, 0.0, 0.0]),
        crank       = Object3D(),
        crank_bar   = Object3D(parent = crank, translation = [a / 2.0, 0.0, 0.0],
                               feature = Solid(shape = Box(lengths = [a, w, w]), solid_material = "Steel")),
        crank_tip   = Object3D(parent = crank, translation = [a, 0.0, 0.0]),
        coupler     = Object3D(),
        coupler_bar = Object3D(parent = coupler, translation = [b / 2.0, 0.0, 0.0],
                               feature = Solid(shape = Box(lengths = [b, w, w]), solid_material = "Steel")),
        coupler_tip = Object3D(parent = coupler, translation = [b, 0.0, 0.0]),
        rocker      = Object3D(),
        rocker_bar  = Object3D(parent = rocker, translation = [c / 2.0, 0.0, 0.0],
                               feature = Solid(shape = Box(lengths = [c, w, w]), solid_material = "Steel")),
        rocker_tip  = Object3D(parent = rocker, translation = [c, 0.0, 0.0]),
        crank_joint   = Revolute(obj1 = world, obj2 = crank, axis = 3,
                                 phi = Var(init = theta2), w = Var(init = omega)),
        coupler_joint = Revolute(obj1 = crank_tip, obj2 = coupler, axis = 3, phi = Var(init = phi3)),
        rocker_joint  = Revolute(obj1 = ground_b, obj2 = rocker, axis = 3, phi = Var(init = phi4)),
        // Closes the loop: cut by the library (the last joint reached), enforced by constraints.
        loop_joint    = Revolute(obj1 = coupler_tip, obj2 = rocker_tip, axis = 3),
        // Constant crank speed: zero crank acceleration (inputs are 0 until set).
        drive         = JointAcceleration(joint = crank_joint),
    }
}

/// The rocker angle [rad] of the open branch for crank angle `theta2` [rad], from
/// Freudenstein's equation `K1 cos θ4 − K2 cos θ2 + K3 = cos(θ2 − θ4)` solved in closed form
/// (`A tan²(θ4/2) + B tan(θ4/2) + C = 0`).
pub fn freudenstein(a: f64, b: f64, c: f64, d: f64, theta2: f64) -> f64 {
    let (k1, k2, k3) = (
        d / a,
        d / c,
        (a * a - b * b + c * c + d * d) / (2.0 * a * c),
    );
    let (s, co) = theta2.sin_cos();
    let big_a = co - k1 - k2 * co + k3;
    let big_b = -2.0 * s;
    let big_c = k1 - (k2 + 1.0) * co + k3;
    let disc = (big_b * big_b - 4.0 * big_a * big_c).sqrt();
    2.0 * ((-big_b - disc) / (2.0 * big_a)).atan()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let fb = FourBar::default();
    let model = fb.build()?;
    println!("cut joints: {:?}", model.loops());
    let result = model.simulate(&SimOptions::new(1.0).tolerance(1e-8).interval(0.1))?;
    let theta2 = result.signal("crank_joint.phi")?.values();
    let theta4 = result.signal("rocker_joint.phi")?.values();
    let force = result.signal("loop_joint.f")?;
    println!("   t [s]  crank [rad]  rocker [rad]  Freudenstein [rad]  |f| [N]");
    for (k, t) in result.time().iter().enumerate() {
        let reference = freudenstein(fb.a, fb.b, fb.c, fb.d, theta2[k]);
        let f = force.at(k).unwrap_or(&[0.0; 3]);
        let fnorm = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
        println!(
            "{t:8.3} {:12.6} {:13.9} {:19.9} {fnorm:8.3}",
            theta2[k], theta4[k], reference
        );
    }
    let s = &result.stats.solver;
    println!(
        "steps {}, residual evaluations {}, wall time {:.3} s",
        s.steps, s.residual_evals, result.stats.wall_time
    );
    Ok(())
}
