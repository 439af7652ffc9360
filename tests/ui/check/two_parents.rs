use modia3d::prelude::*;

// `body` is obj2 of two joints, and `hanging` is connected only through `rev2`: a body moved
// by two joints without a loop.
model! {
    pub M {
        world = Object3D(feature = Scene()),
        body = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        hanging = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        rev1 = Revolute(obj1 = world, obj2 = body),
        rev2 = Prismatic(obj1 = hanging, obj2 = body),
    }
}

fn main() {}
