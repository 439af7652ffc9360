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
    /// A mesh file could not be parsed.
    #[error("cannot parse mesh file `{path}` at {location}: {message}")]
    MeshParse {
        /// The file path as given.
        path: String,
        /// Where: `line N` (OBJ), `facet N` or `header` (STL).
        location: String,
        /// What is wrong there.
        message: String,
    },
    /// A triangle mesh is not closed and consistently oriented, so it bounds no solid.
    #[error(
        "mesh `{path}` is not closed and consistently oriented: {edges} edge(s) not shared by \
         exactly two triangles in opposite directions, e.g. vertices {example}; repair the mesh \
         (close holes, make all triangles counter-clockwise seen from outside) or give explicit \
         mass properties and use it as a Visual"
    )]
    MeshNotClosed {
        /// The mesh's source (file path).
        path: String,
        /// How many directed edges are wrong.
        edges: usize,
        /// One of them: vertex indices and positions.
        example: String,
    },
    /// A closed mesh encloses no positive volume (turned inside out, or flat).
    #[error(
        "mesh `{path}` encloses volume {volume} m³: its triangles must be counter-clockwise seen \
         from outside and enclose a solid"
    )]
    MeshVolume {
        /// The mesh's source (file path).
        path: String,
        /// The signed volume found \[m³\].
        volume: f64,
    },
    /// A [`Shape::FileMesh`](super::Shape::FileMesh) was used before being loaded
    /// ([`Shape::load`](super::Shape::load); `SceneDesc::build` loads every mesh file).
    #[error("mesh file `{0}` is not loaded yet (Shape::load)")]
    MeshNotLoaded(String),
    /// Neither MPR nor its fallback (GJK/EPA) produced a result.
    #[error("narrow phase failed for the pair ({0:?}, {1:?}): MPR and GJK/EPA both gave up")]
    NoConvergence(ShapeKind, ShapeKind),
}
