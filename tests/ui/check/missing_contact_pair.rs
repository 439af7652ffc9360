use modia3d::prelude::*;

model! {
    /// A steel ball and a wooden ball over a table of a block material: no built-in pairs for
    /// Steel–DryWood, Steel–oak, DryWood–oak (each reported once, on the later solid's
    /// material). Steel–Steel and DryWood–DryWood are built in.
    pub M {
        world = Object3D(feature = Scene()),
        oak   = SolidMaterial(density = 700.0, young_modulus = 1.1e10, poisson_ratio = 0.4),
        table = Object3D(parent = world, feature = Solid(shape = Box(lengths = [1.0, 1.0, 0.1]),
                                                         solid_material = oak, collision = true)),
        ball  = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel",
                                         collision = true)),
        ball2 = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel",
                                         collision = true)),
        wood  = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel",
                                         contact_material = "DryWood", collision = true)),
        free1 = FreeMotion(obj1 = world, obj2 = ball),
        free2 = FreeMotion(obj1 = world, obj2 = ball2),
        free3 = FreeMotion(obj1 = world, obj2 = wood),
    }
}

fn main() {}
