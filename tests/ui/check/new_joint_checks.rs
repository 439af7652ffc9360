use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        a = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        b = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        c = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        d = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        e = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        crooked = Universal(obj1 = world, obj2 = a, axis1 = [1.0, 0.0, 0.0], axis2 = [1.0, 1.0, 0.0]),
        flat = Cylindrical(obj1 = world, obj2 = b, axis = [0.0, 0.0, 0.0]),
        tilted = Planar(obj1 = world, obj2 = c, normal = 4),
        ball = Spherical(obj1 = world, obj2 = d, phi = Var(init = 0.1)),
        half = Universal(obj1 = world, obj2 = e, axis1 = 1),
    }
}

fn main() {}
