use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene(k_red = 0.0, d_max = -1.0, cor_min = 0.0, v_min = 0.0,
                                         w_min = -0.01, hysteresis = 0.0, mpr_tolerance = -1e-11,
                                         mpr_max_iterations = 0, smoothing_radius = -0.001,
                                         profile = Modia3DLatr, dmax = 2000.0)),
    }
}

fn main() {}
