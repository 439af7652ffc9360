//! A brick (0.1 × 0.2 × 0.3 m, 2 kg) spinning in space. Spun about its intermediate principal
//! axis (y) with a tiny perturbation, it flips over and over (the tennis-racket effect); spun
//! about the largest or smallest axis it stays put.

use modia3d::prelude::*;

model! {
    /// A 2 kg brick in space, spun with angular velocity `w0` (resolved in the brick) [rad/s].
    pub SpinningBrick(w0: [f64; 3] = [0.0, 6.0, 0.0]) {
        world = Object3D(feature = Scene(gravity = [0.0, 0.0, 0.0])),
        brick = Object3D(feature = Solid(shape = Box(lengths = [0.1, 0.2, 0.3]),
                                         mass_properties = MassProperties(mass = 2.0))),
        free  = FreeMotion(obj1 = world, obj2 = brick, w = Var(init = w0)),
    }
}

fn run(label: &str, w0: [f64; 3], axis: usize) -> Result<(), Box<dyn std::error::Error>> {
    let model = SpinningBrick { w0 }.build()?;
    let result = model.simulate(&SimOptions::new(10.0).tolerance(1e-8).interval(0.01))?;
    let rot = result.signal("brick.R_abs")?;
    // Alignment of the spin axis with its initial direction; a flip shows as -1.
    let mut flips = 0;
    let mut sign = 1.0;
    let mut min = 1.0f64;
    for k in 0..result.time().len() {
        let a = rot.at(k).ok_or("no output point")?[3 * axis + axis]; // R[axis][axis]
        min = min.min(a);
        if a * sign < -0.5 {
            flips += 1;
            sign = -sign;
        }
    }
    println!("{label:>13}: min alignment {min:+.4}, flips in 10 s: {flips}");
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    run("largest (x)", [6.0, 0.01, 0.01], 0)?;
    run("intermediate (y)", [0.01, 6.0, 0.01], 1)?;
    run("smallest (z)", [0.01, 0.01, 6.0], 2)?;
    Ok(())
}
