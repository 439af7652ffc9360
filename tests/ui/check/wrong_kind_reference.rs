use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        body = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        rev = Revolute(obj1 = world, obj2 = body),
        tip = Object3D(parent = rev),
        spring = JointSpringDamper(joint = body, stiffness = 1.0),
        path = Object3D(parent = body.tip),
    }
}

fn main() {}
