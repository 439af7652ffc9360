use modia3d::prelude::*;

model! {
    pub M(gain: f64 = 2.0) {
        world = Object3D(feature = Scene()),
        load  = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        rev   = Revolute(obj1 = world, obj2 = load),
        ramp  = Ramp(height = 1.0, duration = 1.0),
        g1    = Gain(k = gain, u = rmp.y),
        g2    = Gain(k = gain, u = ramp.yy),
        g3    = Gain(k = gain, u = rev.omega),
        g4    = Gain(k = gain, u = load.phi),
        g5    = Gain(k = gain, u = ramp),
        pi    = PI(T = 1.0, u = gain * (ramp.y - rev.phi) - rev.ww + time),
    }
}

fn main() {}
