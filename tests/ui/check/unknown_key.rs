use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        body = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        rev = Revolute(obj1 = world, obj2 = body, axsi = 1),
        tip = Object3D(parent = body, feature = Solid(shape = Sphere(diameter = 0.1),
                                                      mass_properties = MassPropertiesFromShapeAndMass(mas = 1.0))),
    }
}

fn main() {}
