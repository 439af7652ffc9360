// The keys of the force elements after Modia3D: a misspelt key (did-you-mean), Modia3D's and
// the linear element's names for a law (synonyms), a law given for one axis only, a law and
// its coefficient both given, a reference to an unknown object, `gravity_field` beside
// `gravity`, and a negative literal coefficient (the core's rule, on its token).
use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene(gravity = [0, 0, -9.81], gravity_field = GravityField::None)),
        block = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        free = FreeMotion(obj1 = world, obj2 = block),
        b1 = Bushing(obj1 = world, obj2 = block, large_angel = true),
        b2 = Bushing(obj1 = world, obj2 = block, stiffness = [1, 1, 1], spring_force_law = [1, 1, 1]),
        b3 = Bushing(obj1 = world, obj2 = block, rot_spring_law = |a| 2.0 * a),
        b4 = Bushing(obj1 = world, obj2 = blok, damper_law = [1, -2, 1]),
        sd = SpringDamper(obj1 = world, obj2 = block, stiffness = 1, spring_law = |x| x),
        f1 = WorldForce(object = block, force = [1, 0, 0], resolved_in = wrld),
        f2 = WorldTorque(object = block, force = [1, 0, 0]),
        b5 = Bushing(obj1 = world, obj2 = block, damper_law = [1, -2, |v| v], nominal_torque = [0, 1, 0]),
    }
}

fn main() {}
