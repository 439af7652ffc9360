//! Errors of the geometry stage (shape checks, narrow-phase failures). Touches nothing else.

use super::shapes::ShapeKind;
use thiserror::Error;

/// Why a geometric computation could not be done.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum GeometryError {
    /// A length parameter of a shape is not finite or not positive.
    #[error("invalid shape: `{name}` = {value} must be finite and > 0")]
    InvalidDimension {
        /// Name of the offending parameter (e.g. `diameter`).
        name: &'static str,
        /// Its value \[m\].
        value: f64,
    },
    /// A convex hull has fewer than 4 points not in a plane, or a non-finite point.
    #[error("degenerate convex hull: fewer than 4 points not in a plane (or a non-finite point)")]
    DegenerateHull,
    /// The smoothing radius is negative or not finite.
    #[error("invalid smoothing radius {0} [m]: must be finite and >= 0")]
    InvalidSmoothingRadius(f64),
    /// A pose or an intermediate result is not finite (NaN or infinity).
    #[error("non-finite input or intermediate result in the narrow phase")]
    NotFinite,
    /// A mesh file could not be read or holds fewer than 4 vertices.
    #[error("cannot read mesh file `{path}`: {message}")]
    MeshFile {
        /// The file path as given.
        path: String,
        /// What went wrong.
        message: String,
    },
    /// Neither MPR nor its fallback (GJK/EPA) produced a result.
    #[error("narrow phase failed for the pair ({0:?}, {1:?}): MPR and GJK/EPA both gave up")]
    NoConvergence(ShapeKind, ShapeKind),
}
