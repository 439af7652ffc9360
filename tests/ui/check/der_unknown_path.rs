use modia3d::prelude::*;

model! {
    pub M(k: f64 = 1.0) {
        world = Object3D(feature = Scene()),
        load  = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        slide = Prismatic(obj1 = world, obj2 = load),
        a1    = Gain(k = 1.0, u = der(slid.v)),
        a2    = Gain(k = 1.0, u = k * der(motor.w)),
        a3    = Gain(k = 1.0, u = der(k)),
    }
}

fn main() {}
