use modia3d::prelude::*;

model! {
    pub M {
        world = Object3D(feature = Scene()),
        wood = SolidMaterial(density = 700.0, young_modulus = 1.1e10, poisson_ratio = 0.4),
        steel_wood = ContactPair(material1 = "Steel", material2 = wood, cor = 1.2, mu_k = -0.3,
                                 mu_r = -0.001, v_min = 0.0, w_min = -1.0),
        bad_names = ContactPair(material1 = wod, material2 = world, cor = 0.5, mu_k = 0.1, mu_r = 0.0),
        no_mu = ContactPair(material1 = "Steel", material2 = "Steel", cor = 0.5),
    }
}

fn main() {}
