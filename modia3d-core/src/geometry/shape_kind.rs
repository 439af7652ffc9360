//! The kinds of shapes (geometry vocabulary, imports nothing): what messages and the narrow
//! phase's dispatch table name a shape by.

/// The kind of a shape, for messages and dispatch tables.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ShapeKind {
    /// [`Shape::Sphere`](super::Shape::Sphere)
    Sphere,
    /// [`Shape::Box`](super::Shape::Box)
    Box,
    /// [`Shape::Cylinder`](super::Shape::Cylinder)
    Cylinder,
    /// [`Shape::Capsule`](super::Shape::Capsule)
    Capsule,
    /// [`Shape::Cone`](super::Shape::Cone)
    Cone,
    /// [`Shape::Beam`](super::Shape::Beam)
    Beam,
    /// [`Shape::Ellipsoid`](super::Shape::Ellipsoid)
    Ellipsoid,
    /// [`Shape::ConvexHull`](super::Shape::ConvexHull)
    ConvexHull,
    /// [`Shape::FileMesh`](super::Shape::FileMesh), [`Shape::Mesh`](super::Shape::Mesh)
    Mesh,
}
