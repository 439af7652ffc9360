// Wrong value types for the force elements' keys are reported by rustc on the user's tokens.
use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene(gravity_field = [0.0, 0.0, -9.81])),
        block = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        free = FreeMotion(obj1 = world, obj2 = block),
        b = Bushing(obj1 = world, obj2 = block, spring_law = [1.0, "stiff", |x: f64| x]),
        f = WorldForce(object = block, force = 3.0),
    }
}

fn main() {}
