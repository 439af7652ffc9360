use modia3d::prelude::*;

model! {
    /// Steel balls and one with the contact material of a billiard ball over a table of a
    /// block material: no built-in pairs for Steel–BilliardBall, Steel–oak, BilliardBall–oak
    /// (each reported once, on the later solid's material). Steel–Steel is built in.
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
                                         contact_material = "BilliardBall", collision = true)),
        free1 = FreeMotion(obj1 = world, obj2 = ball),
        free2 = FreeMotion(obj1 = world, obj2 = ball2),
        free3 = FreeMotion(obj1 = world, obj2 = wood),
    }
}

fn main() {}
