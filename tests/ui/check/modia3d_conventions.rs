use modia3d::prelude::*;

model! {
    /// With Modia3D's conventions a Revolute lets its links collide unless told otherwise, so
    /// the arm and the base need a contact pair (oak–Steel is not built in); the contact
    /// material names the solid material of the contact stiffness, so it must be one.
    pub M {
        world = Object3D(feature = Scene(modia3d_conventions = true)),
        oak   = SolidMaterial(density = 700.0, young_modulus = 1.1e10, poisson_ratio = 0.4),
        base  = Object3D(parent = world, feature = Solid(shape = Box(lengths = [1.0, 1.0, 0.1]),
                                                         solid_material = oak, collision = true)),
        arm   = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel",
                                         collision = true)),
        hinge = Revolute(obj1 = world, obj2 = arm),
        cap   = Object3D(parent = arm, feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel",
                                                       contact_material = "Wood", collision = true)),
    }
}

fn main() {}
