//! The slider-crank of SUNDIALS' `idaSlCrank_dns` example (Haug, *Intermediate Dynamics*, 1992,
//! example 6.1.8): a crank (length `a`, inertia `J1` about its pivot) and a connecting rod of
//! length 1 whose mass `m2` sits at the slider and whose inertia `J2` is about the slider,
//! joined by a spring-damper between their midpoints and pushed by a constant horizontal force
//! `f` at the rod's far end; no gravity. The crank pivots on the world, the slider runs on the
//! world's x axis, and the revolute `loop_joint` between the crank tip and the rod's end closes
//! the loop. Prints the state at t = 1 s (compare `scripts/slider_crank_reference.py`).

use modia3d::prelude::*;

model! {
    /// idaSlCrank_dns's data: `a` = 0.5 m, `J1` = 1, `m2` = 1, `J2` = 2, `k` = 1, `c` = 1,
    /// `l0` = 1, `f` = 1 (SI units), released at rest with the crank at π/2.
    pub SliderCrank(a: f64 = 0.5, j1: f64 = 1.0, m2: f64 = 1.0, j2: f64 = 2.0,
                    k: f64 = 1.0, c: f64 = 1.0, l0: f64 = 1.0, f: f64 = 1.0,
                    q0: f64 = std::f64::consts::FRAC_PI_2) {
        world     = Object3D(feature = Scene(gravity = [0.0, 0.0, 0.0])),
        crank     = Object3D(feature = Solid(mass_properties = MassProperties(mass = 1.0,
                                 inertia = [[j1, 0.0, 0.0], [0.0, j1, 0.0], [0.0, 0.0, j1]]))),
        crank_mid = Object3D(parent = crank, translation = [a / 2.0, 0.0, 0.0]),
        crank_tip = Object3D(parent = crank, translation = [a, 0.0, 0.0]),
        slider    = Object3D(),
        rod       = Object3D(feature = Solid(mass_properties = MassProperties(mass = m2,
                                 inertia = [[j2, 0.0, 0.0], [0.0, j2, 0.0], [0.0, 0.0, j2]]))),
        rod_mid   = Object3D(parent = rod, translation = [-0.5, 0.0, 0.0]),
        rod_end   = Object3D(parent = rod, translation = [-1.0, 0.0, 0.0]),
        rod_load  = Object3D(parent = rod, translation = [1.0, 0.0, 0.0]),
        crank_joint = Revolute(obj1 = world, obj2 = crank, axis = 3, phi = Var(init = q0)),
        // Rough guesses: the build moves them onto the loop (x = 0.866, p = −0.524).
        slide       = Prismatic(obj1 = world, obj2 = slider, axis = 1, s = Var(init = 0.9)),
        rod_joint   = Revolute(obj1 = slider, obj2 = rod, axis = 3, phi = Var(init = -0.5)),
        // Marked: without `cut` the tree search would reach the rod through this joint and cut
        // `rod_joint`, whose initial guess would then be ignored.
        loop_joint  = Revolute(obj1 = crank_tip, obj2 = rod_end, axis = 3, cut = true),
        spring      = SpringDamper(obj1 = crank_mid, obj2 = rod_mid, stiffness = k, damping = c,
                                   length0 = l0),
        push        = ObjectForce(object = rod_load,
                                  law = move |_t: f64, _m: &ObjectMotion| Wrench {
                                      force: Vector3::new(f, 0.0, 0.0),
                                      torque: Vector3::zeros(),
                                  }),
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let model = SliderCrank::default().build()?;
    println!(
        "independent coordinates: {:?}",
        model.independent_coordinates()
    );
    let result = model.simulate(&SimOptions::new(1.0).tolerance(1e-10))?;
    for name in [
        "crank_joint.phi",
        "slide.s",
        "rod_joint.phi",
        "crank_joint.w",
        "slide.v",
        "rod_joint.w",
    ] {
        println!(
            "{name:16} = {:.15e}",
            result.signal(name)?.last().unwrap_or(&[f64::NAN])[0]
        );
    }
    let f = result.signal("loop_joint.f")?;
    println!(
        "loop_joint.f at 1 s [N] (on the rod, in the crank tip's frame): {:?}",
        f.last()
    );
    Ok(())
}
