use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        a = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        b = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        uj = Universal(obj1 = world, obj2 = a, axis1 = 1, axis2 = 2),
        ball = Spherical(obj1 = world, obj2 = b),
        which = JointSpringDamper(joint = uj, stiffness = 1.0),
        typo = JointSpringDamper(joint = uj, coordinate = "phi3", stiffness = 1.0),
        twist = JointForce(joint = ball),
    }
}

fn main() {}
