//! Andrews' squeezing mechanism (Hairer & Wanner, *Solving Ordinary Differential Equations II*,
//! §VII.7; the index-3 problem of the Bari test set for IVP solvers): seven planar bodies on
//! revolute joints, driven by a constant torque on the crank and loaded by a stiff spring,
//! simulated for 0.03 s. The bodies 2, 3, 4 and 6 meet at one point E; the library closes the
//! three loops with the cut revolutes `e23`, `e24`, `e26` (marked `cut`). Coordinates as in the
//! test set: β (crank), Θ (body 2 on the crank), γ (body 3), Φ (body 4 on body 5), δ (body 5),
//! Ω (body 6 on body 7), ε (body 7). Prints the angles at 0.03 s next to the test set's
//! reference solution.

use modia3d::prelude::*;

/// The test set's reference solution at t = 0.03 s: β, Θ, γ, Φ, δ, Ω, ε [rad].
pub const REFERENCE_003: [f64; 7] = [
    15.81077119629904,
    -15.75637105984298,
    0.04082224013073101,
    -0.5347301163226948,
    0.5244099658805304,
    0.5347301163226948,
    1.048080741042263,
];

/// The joints of the seven coordinates, in the test set's order.
pub const JOINTS: [&str; 7] = ["beta", "theta", "gamma", "phi", "delta", "omega", "epsilon"];

model! {
    /// The squeezer with the test set's data (SI units; no gravity): masses `m1`…`m7` [kg],
    /// inertias `i1`…`i7` about the centres of mass [kg·m²], pivots A, B and the spring's anchor
    /// C [m], link dimensions [m], spring stiffness `c0` [N/m] and free length `l0` [m], drive
    /// torque `mom` [N·m]; the consistent initial angles of the test set.
    pub AndrewsSqueezer(
        m1: f64 = 0.04325, m2: f64 = 0.00365, m3: f64 = 0.02373, m4: f64 = 0.00706,
        m5: f64 = 0.07050, m6: f64 = 0.00706, m7: f64 = 0.05498,
        i1: f64 = 2.194e-6, i2: f64 = 4.410e-7, i3: f64 = 5.255e-6, i4: f64 = 5.667e-7,
        i5: f64 = 1.169e-5, i6: f64 = 5.667e-7, i7: f64 = 1.912e-5,
        xa: f64 = -0.06934, ya: f64 = -0.00227, xb: f64 = -0.03635, yb: f64 = 0.03273,
        xc: f64 = 0.014, yc: f64 = 0.072,
        d: f64 = 0.028, da: f64 = 0.0115, e: f64 = 0.02, ea: f64 = 0.01421,
        rr: f64 = 0.007, ra: f64 = 0.00092, ss: f64 = 0.035, sa: f64 = 0.01874,
        sb: f64 = 0.01043, sc: f64 = 0.018, sd: f64 = 0.02, ta: f64 = 0.02308,
        tb: f64 = 0.00916, u: f64 = 0.04, ua: f64 = 0.01228, ub: f64 = 0.00449,
        zf: f64 = 0.02, zt: f64 = 0.04, fa: f64 = 0.01421,
        c0: f64 = 4530.0, l0: f64 = 0.07785, mom: f64 = 0.033,
        beta0: f64 = -0.0617138900142764496358948458001,
        theta0: f64 = 0.0,
        gamma0: f64 = 0.455279819163070380255912382449,
        phi0: f64 = 0.222668390165885884674473185609,
        delta0: f64 = 0.487364979543842550225598953530,
        omega0: f64 = -0.222668390165885884674473185609,
        epsilon0: f64 = 1.23054744454982119249735015568
    ) {
        world  = Object3D(feature = Scene(gravity = [0.0, 0.0, 0.0])),
        pivot_a = Object3D(parent = world, translation = [xa, ya, 0.0]),
        pivot_b = Object3D(parent = world, translation = [xb, yb, 0.0]),
        anchor_c = Object3D(parent = world, translation = [xc, yc, 0.0]),
        // Body 1, the crank, about the origin O.
        body1  = Object3D(feature = Solid(mass_properties = MassProperties(mass = m1,
                     com = [ra, 0.0, 0.0], inertia = [[i1, 0.0, 0.0], [0.0, i1, 0.0], [0.0, 0.0, i1]]))),
        p1     = Object3D(parent = body1, translation = [rr, 0.0, 0.0]),
        // Body 2 at P; E at −d along its axis.
        body2  = Object3D(feature = Solid(mass_properties = MassProperties(mass = m2,
                     com = [-da, 0.0, 0.0], inertia = [[i2, 0.0, 0.0], [0.0, i2, 0.0], [0.0, 0.0, i2]]))),
        e2     = Object3D(parent = body2, translation = [-d, 0.0, 0.0]),
        // Body 3 about B; E at (0, −ss), the spring's end D at (sd, −sc).
        body3  = Object3D(feature = Solid(mass_properties = MassProperties(mass = m3,
                     com = [sa, sb, 0.0], inertia = [[i3, 0.0, 0.0], [0.0, i3, 0.0], [0.0, 0.0, i3]]))),
        e3     = Object3D(parent = body3, translation = [0.0, -ss, 0.0]),
        d3     = Object3D(parent = body3, translation = [sd, -sc, 0.0]),
        // Body 5 about A; body 4 at its point (zt, 0); E at (0, −e) on body 4.
        body5  = Object3D(feature = Solid(mass_properties = MassProperties(mass = m5,
                     com = [ta, tb, 0.0], inertia = [[i5, 0.0, 0.0], [0.0, i5, 0.0], [0.0, 0.0, i5]]))),
        z5     = Object3D(parent = body5, translation = [zt, 0.0, 0.0]),
        body4  = Object3D(feature = Solid(mass_properties = MassProperties(mass = m4,
                     com = [0.0, ea - e, 0.0], inertia = [[i4, 0.0, 0.0], [0.0, i4, 0.0], [0.0, 0.0, i4]]))),
        e4     = Object3D(parent = body4, translation = [0.0, -e, 0.0]),
        // Body 7 about A; body 6 at its point (0, −u); E at (zf, 0) on body 6.
        body7  = Object3D(feature = Solid(mass_properties = MassProperties(mass = m7,
                     com = [ua, ub, 0.0], inertia = [[i7, 0.0, 0.0], [0.0, i7, 0.0], [0.0, 0.0, i7]]))),
        u7     = Object3D(parent = body7, translation = [0.0, -u, 0.0]),
        body6  = Object3D(feature = Solid(mass_properties = MassProperties(mass = m6,
                     com = [zf - fa, 0.0, 0.0], inertia = [[i6, 0.0, 0.0], [0.0, i6, 0.0], [0.0, 0.0, i6]]))),
        e6     = Object3D(parent = body6, translation = [zf, 0.0, 0.0]),
        beta    = Revolute(obj1 = world, obj2 = body1, axis = 3, phi = Var(init = beta0)),
        theta   = Revolute(obj1 = p1, obj2 = body2, axis = 3, phi = Var(init = theta0)),
        gamma   = Revolute(obj1 = pivot_b, obj2 = body3, axis = 3, phi = Var(init = gamma0)),
        phi     = Revolute(obj1 = z5, obj2 = body4, axis = 3, phi = Var(init = phi0)),
        delta   = Revolute(obj1 = pivot_a, obj2 = body5, axis = 3, phi = Var(init = delta0)),
        omega   = Revolute(obj1 = u7, obj2 = body6, axis = 3, phi = Var(init = omega0)),
        epsilon = Revolute(obj1 = pivot_a, obj2 = body7, axis = 3, phi = Var(init = epsilon0)),
        // The three loops close at E.
        e23 = Revolute(obj1 = e2, obj2 = e3, axis = 3, cut = true),
        e24 = Revolute(obj1 = e2, obj2 = e4, axis = 3, cut = true),
        e26 = Revolute(obj1 = e2, obj2 = e6, axis = 3, cut = true),
        spring = SpringDamper(obj1 = anchor_c, obj2 = d3, stiffness = c0, length0 = l0),
        drive  = ObjectForce(object = body1, law = move |_t: f64, _m: &ObjectMotion| Wrench {
                     force: Vector3::zeros(),
                     torque: Vector3::new(0.0, 0.0, mom),
                 }),
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let model = AndrewsSqueezer::default().build()?;
    println!(
        "independent coordinates: {:?}",
        model.independent_coordinates()
    );
    let result = model.simulate(&SimOptions::new(0.03).tolerance(1e-10).interval(0.001))?;
    println!("joint      t = 0.03 s              reference               relative error");
    for (j, reference) in JOINTS.iter().zip(REFERENCE_003) {
        let got = result
            .signal(&format!("{j}.phi"))?
            .last()
            .unwrap_or(&[f64::NAN])[0];
        let rel = ((got - reference) / reference).abs();
        println!("{j:8} {got:22.15e} {reference:22.15e} {rel:10.2e}");
    }
    let s = &result.stats.solver;
    println!(
        "steps {}, residual evaluations {}, wall time {:.3} s",
        s.steps, s.residual_evals, result.stats.wall_time
    );
    Ok(())
}
