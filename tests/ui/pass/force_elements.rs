// The force elements after Modia3D in `model!`: a bushing with numbers and closures per axis,
// a point-to-point spring-damper with force laws, world forces and torques (constant, closure,
// resolved in an object) and a point gravity field; built and run for a few steps.
use modia3d::prelude::*;

model! {
    pub Elements(k: f64 = 100.0, laws: [f64; 3] = [1.0, 2.0, 3.0]) {
        world = Object3D(feature = Scene(gravity_field = GravityField::Point { mu: 4.0e5, centre: Vector3::new(0.0, 0.0, -100.0) })),
        block = Object3D(feature = Solid(shape = Box(lengths = [0.2, 0.1, 0.1]), solid_material = "Steel")),
        free = FreeMotion(obj1 = world, obj2 = block, r = Var(init = [0, 0, 0.01])),
        mount = Bushing(obj1 = world, obj2 = block, nominal_force = [0, 0, 1],
                        spring_law = [k, k, |x| 2.0 * k * x + 1e4 * x * x * x],
                        damper_law = [2, 2, 2], rot_spring_law = laws,
                        rot_damper_law = [0.1, 0.1, |w| 0.1 * w], large_angles = true),
        cubic = SpringDamper(obj1 = world, obj2 = block, length0 = 0.01,
                             spring_law = |x| 50.0 * x + 1e3 * x.powi(3), damping = 0.5),
        push = WorldForce(object = block, force = [1, 0, 0]),
        wind = WorldForce(object = block, force = |t, m| Vector3::new(0.0, t.sin(), -m.v_abs.z)),
        spin = WorldTorque(object = block, torque = [0, 0, 0.01], resolved_in = block),
    }
}

fn main() {
    let model = Elements::default().build().unwrap();
    let res = model
        .simulate(&SimOptions::new(0.01).progress(false))
        .unwrap();
    for s in ["mount.r", "mount.angles", "mount.force", "mount.torque", "cubic.length", "cubic.tension"] {
        res.signal(s).unwrap();
    }
}
