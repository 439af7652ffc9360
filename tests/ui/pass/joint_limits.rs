// Joint limits in `model!`: both bounds, one side open, per-limit stiffness and cor, on a
// joint with several coordinates; built and run for a few steps.
use modia3d::prelude::*;

model! {
    pub Stops {
        world = Object3D(feature = Scene(gravity = [0.0, 0.0, -9.81])),
        arm = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        hinge = Revolute(obj1 = world, obj2 = arm, axis = 2, phi = Var(init = 0.5), phi_limits = [-1.2, 1.2], phi_limit_cor = 0.3),
        shaft = Object3D(feature = Solid(shape = Box(lengths = [0.1, 0.2, 0.3]), solid_material = "Steel")),
        uj = Universal(obj1 = world, obj2 = shaft, axis1 = 3, axis2 = 1, phi2_limits = [-1, f64::INFINITY], phi2_limit_stiffness = 1e5),
    }
}

fn main() {
    let model = Stops::default().build().unwrap();
    let res = model
        .simulate(&SimOptions::new(0.01).progress(false))
        .unwrap();
    for s in ["hinge.limit_f", "uj.limit_f_phi2"] {
        res.signal(s).unwrap();
    }
}
