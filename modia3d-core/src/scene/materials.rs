//! Solid materials and their built-in palette (data from Modia3D.jl's palettes).

/// Mechanical data of a solid material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolidMaterial {
    /// Density [kg/m³].
    pub density: f64,
    /// Young's modulus [N/m²].
    pub young_modulus: f64,
    /// Poisson's ratio [-], 0 < ν < 1.
    pub poisson_ratio: f64,
}

/// The built-in solid materials: (name, material).
pub const SOLID_MATERIALS: &[(&str, SolidMaterial)] = &[
    ("Steel", mat(8000.0, 2.0e11, 0.30)),
    ("Aluminium", mat(2700.0, 6.9e10, 0.32)),
    ("DryWood", mat(700.0, 1.1e10, 0.40)),
    ("BilliardBall", mat(1768.0, 5.4e9, 0.34)),
    ("BilliardTable", mat(700.0, 1.1e10, 0.40)),
    ("BilliardCushion", mat(700.0, 1.1e10, 0.40)),
    ("BilliardCue", mat(700.0, 1.1e10, 0.40)),
];

const fn mat(density: f64, young_modulus: f64, poisson_ratio: f64) -> SolidMaterial {
    SolidMaterial {
        density,
        young_modulus,
        poisson_ratio,
    }
}

/// Looks up a built-in solid material by name.
pub fn builtin_solid_material(name: &str) -> Option<SolidMaterial> {
    SOLID_MATERIALS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, m)| *m)
}
