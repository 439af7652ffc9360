use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        load  = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        e     = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        rev   = Revolute(obj1 = world, obj2 = load),
        cyl   = Cylindrical(obj1 = load, obj2 = e),
        // A position: its velocity is the signal whose derivative is read.
        a1    = Gain(k = 1.0, u = der(rev.phi)),
        a2    = Gain(k = 1.0, u = 2.0 * der(cyl.s) + der(cyl.w)),
        // A joint alone, or a coordinate it lacks.
        a3    = Gain(k = 1.0, u = der(rev)),
        a4    = Gain(k = 1.0, u = der(cyl.ww)),
    }
}

fn main() {}
