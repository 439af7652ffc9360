use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        ramp  = Ramp(height = 1.0, duration = 1.0),
        sum   = Feedback(u1 = ramp.y, u2 = g2.y),
        g1    = Gain(k = 2.0, u = sum.y),
        g2    = Gain(k = 0.5, u = 3.0 * g1.y),
        self_ = Gain(k = 0.5, u = self_.y + ramp.y),
        // Not a loop: the integrator's output has no feedthrough.
        i     = Integrator(u = ramp.y - g3.y),
        g3    = Gain(k = 1.0, u = i.y),
    }
}

fn main() {}
