//! Errors of the geometry stage (shape checks, narrow-phase failures). Touches nothing else.

use super::shape_kind::ShapeKind;
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
        "mesh `{path}` is not closed and consistently oriented: {edges} edge(s) crossed more \
         often in one direction than in the other, e.g. vertices {example}; repair the mesh \
         (close holes, make all triangles counter-clockwise seen from outside) or give explicit \
         mass properties and use it as a Visual"
    )]
    MeshNotClosed {
        /// The mesh's source (file path).
        path: String,
        /// How many edges are unbalanced.
        edges: usize,
        /// One of them: vertex indices and positions.
        example: String,
    },
    /// A mesh for a solid has holes too large to close without guessing its shape
    /// (`geometry::mesh_file::repair_mesh` closes those whose caps cover at most
    /// `MAX_HOLE_AREA_RATIO` of the surface).
    #[error(
        "mesh `{path}` has {holes} hole(s) whose closing caps would cover {hole_area:.3e} m², \
         {:.1} % of its surface {area:.3e} m² (at most {:.0} % is closed automatically); the \
         largest, {largest_area:.3e} m² bounded by {largest_edges} edges, is centred at \
         {largest_centre:?} m (file coordinates × scale): close it in a mesh editor (Blender: \
         Select > Select All by Trait > Non Manifold, then Face > Fill), or give the solid \
         explicit mass properties (`MassSpec::Explicit`) and collide it as its convex hull",
        100.0 * hole_area / area,
        100.0 * closable
    )]
    MeshHoles {
        /// The mesh's source (file path).
        path: String,
        /// Number of holes (boundary loops).
        holes: u32,
        /// Area of the caps that would close them all \[m²\].
        hole_area: f64,
        /// Surface area of the mesh \[m²\].
        area: f64,
        /// Area of the largest hole's cap \[m²\].
        largest_area: f64,
        /// Number of edges around the largest hole.
        largest_edges: u32,
        /// Centroid of the largest hole's boundary vertices, in the shape frame \[m\] (boxed:
        /// every error that can hold a `GeometryError` stays small).
        largest_centre: Box<[f64; 3]>,
        /// The largest share of the surface that is closed automatically (`closable` ×
        /// `area`; `mesh_file::MAX_HOLE_AREA_RATIO`) [-].
        closable: f64,
    },
    /// A triangle of a mesh refers to a vertex that does not exist.
    #[error("mesh `{path}`: triangle {triangle} refers to vertex {index}, but there are only {vertices} vertices; build the `TriangleMesh` with indices into its `vertices`")]
    MeshIndex {
        /// The mesh's source (file path).
        path: String,
        /// Index of the triangle (0-based).
        triangle: usize,
        /// The vertex index it holds (0-based).
        index: u32,
        /// Number of vertices.
        vertices: usize,
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
