//! Mass properties of a solid of unit density (geometry vocabulary, imports nothing of the
//! crate): what shapes and meshes compute and the plan scales by the density.

use nalgebra::{Matrix3, Vector3};

/// Volume \[m³\], centre of mass \[m\] and inertia about the centre of mass \[m⁵\] (multiply by a
/// density in [kg/m³] to get [kg·m²]) of a shape of unit density, in the shape frame.
#[derive(Clone, Debug, PartialEq)]
pub struct UnitMassProperties {
    /// Volume \[m³\].
    pub volume: f64,
    /// Centre of mass in the shape frame \[m\].
    pub com: Vector3<f64>,
    /// Inertia tensor about the centre of mass, for density 1, resolved in the shape frame \[m⁵\].
    pub inertia: Matrix3<f64>,
}
