use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        load  = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        rev   = Revolute(obj1 = world, obj2 = load),
        ramp  = Ramp(height = 1.0, duration = 1.0),
        pi    = PI(T = 1.0, u = ramp.y - rev.phi),
        // Outputs and states of blocks, objects: no derivative signals.
        a1    = Gain(k = 1.0, u = der(ramp.y)),
        a2    = Gain(k = 1.0, u = der(pi.x) + der(rev.w)),
        a3    = Gain(k = 1.0, u = der(load.w)),
        // Not a path.
        a4    = Gain(k = 1.0, u = der(2.0 * rev.w)),
        a5    = Gain(k = 1.0, u = der(rev.w, ramp.y)),
    }
}

fn main() {}
