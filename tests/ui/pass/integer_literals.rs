//! Integer literals where a float is expected: vectors, matrices, scalars, `Var` initial
//! values and `f64` parameter defaults (issue 12). `axis = 2` stays an axis index.
use modia3d::prelude::*;

model! {
    pub Ints(h: f64 = 1) {
        world = Object3D(feature = Scene(gravity = [0, 0, -10], k_red = 1)),
        table = Object3D(parent = world, translation = [0, 0, -1],
                         feature = Solid(shape = Box(lengths = [4, 4, 2]), solid_material = "Steel",
                                         collision = true)),
        ball = Object3D(feature = Solid(shape = Sphere(diameter = 1), solid_material = "Steel",
                                        mass_properties = MassProperties(mass = 2, com = [0, 0, 0],
                                            inertia = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]),
                                        collision = true)),
        fall = FreeMotion(obj1 = world, obj2 = ball, r = Var(init = [0, 0, h]), v = Var(init = [1, 0, -2])),
        arm = Object3D(feature = Solid(shape = Cylinder(diameter = 1, length = 3), solid_material = "Steel")),
        hinge = Revolute(obj1 = world, obj2 = arm, axis = 2, phi = Var(init = 1)),
    }
}

fn main() {
    let m = Ints::default();
    assert_eq!(m.h, 1.0);
    let _ = m.build().unwrap();
}
