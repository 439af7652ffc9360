//! A satellite in Earth's point gravity (`GravityField::Point`, μ = 3.986004418e14 m³/s²):
//! a circular orbit 622 km up and an elliptic one with the same semi-major axis. Prints each
//! orbit's period, measured from the crossings of the equatorial x-z plane (bisection on IDA's
//! interpolating polynomial), beside Kepler's `2π sqrt(a³/μ)`.

use modia3d::prelude::*;

const MU: f64 = 3.986004418e14;

model! {
    /// A 500 kg satellite at perigee distance `rp` \[m\] with speed `vp` [m/s] (along y),
    /// Earth's centre at the world origin.
    pub Orbit(rp: f64 = 7.0e6, vp: f64 = 7546.0) {
        world = Object3D(feature = Scene(gravity_field = GravityField::Point { mu: MU, centre: Vector3::zeros() })),
        sat   = Object3D(feature = Solid(shape = Box(lengths = [1.0, 1.0, 2.0]),
                                         mass_properties = MassProperties(mass = 500.0))),
        free  = FreeMotion(obj1 = world, obj2 = sat, r = Var(init = [rp, 0, 0]), v = Var(init = [0, vp, 0])),
    }
}

/// Simulates `orbits` revolutions and returns the measured mean period \[s\].
fn period(orbit: Orbit, orbits: f64, kepler: f64) -> Result<f64, Box<dyn std::error::Error>> {
    let opts = SimOptions::new((orbits + 0.2) * kepler)
        .tolerance(1e-13)
        .atol(1e-6) // [m] and [m/s] on a 7e6 m orbit
        .interval(kepler / 100.0)
        .dense_output(true)
        .progress(false);
    let res = orbit.build()?.simulate(&opts)?;
    let y = |t: f64| res.signal_at("sat.r_abs[1]", t).map(|v| v[0]);
    // The upward crossing of y = 0 near the last full orbit, by bisection.
    let (mut a, mut b) = ((orbits - 0.1) * kepler, (orbits + 0.1) * kepler);
    for _ in 0..100 {
        let c = 0.5 * (a + b);
        if y(c)? < 0.0 {
            a = c;
        } else {
            b = c;
        }
    }
    Ok(0.5 * (a + b) / orbits)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let rp = 7.0e6;
    for (name, ra) in [("circular", rp), ("elliptic", 9.0e6)] {
        let a: f64 = 0.5 * (rp + ra);
        let vp = (MU * (2.0 / rp - 1.0 / a)).sqrt(); // vis-viva at perigee
        let kepler = 2.0 * std::f64::consts::PI * (a.powi(3) / MU).sqrt();
        let measured = period(Orbit { rp, vp }, 3.0, kepler)?;
        println!(
            "{name} orbit (a = {:.0} km): period {measured:.6} s, Kepler {kepler:.6} s, relative error {:.1e}",
            a / 1e3,
            (measured - kepler).abs() / kepler
        );
    }
    Ok(())
}
