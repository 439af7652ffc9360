use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        body = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), mass_properties = MassProperties(mass = 0.0))),
        spring = SpringDamper(obj1 = world, obj2 = body, stiffness = 100.0, damping = -1.0),
    }
}

fn main() {}
