use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        body = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steal")),
        wood = SolidMaterial(density = 700.0, young_modulus = 1.1e10, poisson_ratio = 0.4),
        ball = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "wod")),
    }
}

fn main() {}
