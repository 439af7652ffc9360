use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        body = Object3D(can_collide = true, feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        spring = SpringDamper(obj1 = world, obj2 = body, stiffness = 1.0, can_collide = false),
    }
}

fn main() {}
