use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        ramp  = Ramp(height = 1.0, duraton = 1.0),
        g     = Gain(k = 2.0),
        pi    = PI(kk = 1.0, T = 1.0, uu = ramp.y),
        lim   = Limiter(uMin = -1.0, u = ramp.y),
        pid   = LimPID(Ti = 0.5, Td = 0.1, yMax = 10.0, u_s = ramp.y),
        s1    = Sampled(period = 0.001, inner = Limiter(uMax = 1.0), u = ramp.y),
        s2    = Sampled(period = 0.001, inner = Pi(T = 1.0), u = ramp.y),
        s3    = Sampled(period = 0.001, inner = PI(k = 1.0), u = ramp.y),
        s4    = Sampled(period = 0.001, inner = PI(T = 1.0)),
    }
}

fn main() {}
