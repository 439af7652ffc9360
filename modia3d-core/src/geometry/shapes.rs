//! Shapes of solids: the builder's [`Shape`] and its conventions (geometry stage; touches
//! nothing else). Each variant's facts (mass properties, core, volume-law solid, display mesh,
//! …) are stated by its file in `geometry/kinds/`.
//!
//! Every shape is given in its own *shape frame*, which is the frame of the object that carries
//! it. Conventions (after Modia3D.jl):
//! - `Sphere`, `Box`, `Ellipsoid`, `Cylinder`, `Capsule` are centred at the origin;
//! - `Cylinder`, `Capsule` and `Cone` have their axis along the frame axis `axis`;
//! - `Capsule::length` is the length of its cylindrical part (the total length is
//!   `length + diameter`);
//! - a `Cone`'s base circle (diameter `diameter`) lies in the plane `axis = 0`, its top circle
//!   (diameter `top_diameter`, 0 for a pointed cone) at `axis = length`;
//! - a `Beam` (Modia3D's `Beam`) is a box with two half-cylinder ends, centred at the origin:
//!   `length` (the box part only; the total length is `length + width`) along `axis`, `width`
//!   (= the diameter of the ends) along the next axis cyclically and `thickness` along the one
//!   after (axis x: width y, thickness z; y: z, x; z: x, y); the ends' cylinder axes point along
//!   the thickness direction, their centres at `±length/2` on `axis`.

use super::error::GeometryError;
pub use super::mass_properties::UnitMassProperties;
pub use super::mesh_file::MeshCollision;
use super::mesh_file::{obj_vertices, TriangleMesh};
pub use super::shape_kind::ShapeKind;
use nalgebra::{Point3, Vector3};
use std::path::Path;
use std::path::PathBuf;
use std::sync::Arc;

/// A frame axis: 1 = x, 2 = y, 3 = z (Modia's numbering).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    /// The x axis (Modia: 1).
    X,
    /// The y axis (Modia: 2).
    Y,
    /// The z axis (Modia: 3).
    Z,
}

impl Axis {
    /// The axis from Modia's number 1, 2 or 3; `None` for anything else.
    pub fn from_index(i: i64) -> Option<Axis> {
        match i {
            1 => Some(Axis::X),
            2 => Some(Axis::Y),
            3 => Some(Axis::Z),
            _ => None,
        }
    }

    /// Index (0, 1, 2) of the width and of the thickness direction of a [`Shape::Beam`] along
    /// this axis: the next two axes cyclically (x → y, z; y → z, x; z → x, y).
    pub fn beam_directions(self) -> (usize, usize) {
        let k = self.index();
        ((k + 1) % 3, (k + 2) % 3)
    }

    /// 0, 1 or 2.
    pub fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        }
    }

    /// The unit vector along this axis.
    pub fn unit(self) -> Vector3<f64> {
        let mut e = Vector3::zeros();
        e[self.index()] = 1.0;
        e
    }
}

/// The geometry of a solid, in its shape frame. All lengths in \[m\].
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A ball of the given diameter \[m\], centred at the origin.
    Sphere {
        /// Diameter \[m\].
        diameter: f64,
    },
    /// A box with edge lengths along x, y, z \[m\], centred at the origin.
    Box {
        /// Edge lengths along the frame's x, y, z axes \[m\].
        lengths: Vector3<f64>,
    },
    /// A circular cylinder along `axis`, centred at the origin.
    Cylinder {
        /// Axis of the cylinder.
        axis: Axis,
        /// Diameter \[m\].
        diameter: f64,
        /// Length along the axis \[m\].
        length: f64,
    },
    /// A cylinder with hemispherical caps, along `axis`, centred at the origin.
    Capsule {
        /// Axis of the capsule.
        axis: Axis,
        /// Diameter of the cylinder and caps \[m\].
        diameter: f64,
        /// Length of the cylindrical part, without the caps \[m\].
        length: f64,
    },
    /// A (truncated) cone along `axis`: base circle at `axis = 0`, top circle at `axis = length`.
    Cone {
        /// Axis of the cone.
        axis: Axis,
        /// Diameter of the base \[m\].
        diameter: f64,
        /// Height \[m\].
        length: f64,
        /// Diameter of the top (0 for a pointed cone) \[m\].
        top_diameter: f64,
    },
    /// A box with half-cylinder ends (Modia3D's `Beam`), centred at the origin; see the module
    /// docs for the directions.
    Beam {
        /// Longitudinal axis; width along the next axis cyclically, thickness along the third.
        axis: Axis,
        /// Length of the box part along `axis`, without the rounded ends (the total length is
        /// `length + width`), > 0 (with no straight part it is a [`Shape::Cylinder`]) \[m\].
        length: f64,
        /// Width = diameter of the half-cylinder ends \[m\].
        width: f64,
        /// Thickness, along the ends' cylinder axes \[m\].
        thickness: f64,
    },
    /// An ellipsoid with full axis lengths along x, y, z \[m\], centred at the origin.
    Ellipsoid {
        /// Full lengths of the three axes (twice the semi-axes) \[m\].
        lengths: Vector3<f64>,
    },
    /// The convex hull of a set of points given in the shape frame \[m\].
    ConvexHull {
        /// Points whose convex hull is the solid \[m\].
        points: Vec<Point3<f64>>,
    },
    /// A triangle mesh read from an OBJ or STL file (Modia3D's `FileMesh`), its frame the
    /// file's. Loaded by `SceneDesc::build` (or [`Shape::load`]) into a [`Shape::Mesh`]; a
    /// relative `path` is relative to the current directory (see `geometry::mesh_file`). Mass
    /// properties come from the closed mesh, collision from `collision`.
    FileMesh {
        /// The file, `.obj` or `.stl`.
        path: PathBuf,
        /// Factors applied to the file's x, y, z coordinates (each > 0) [-]; the file's unit
        /// times the factor must give metres.
        scale: Vector3<f64>,
        /// Convex hull or convex decomposition for collision.
        collision: MeshCollision,
    },
    /// A closed triangle mesh (what a [`Shape::FileMesh`] becomes when loaded).
    Mesh {
        /// The mesh, in the shape frame \[m\].
        mesh: Arc<TriangleMesh>,
        /// Convex hull or convex decomposition for collision.
        collision: MeshCollision,
    },
}

/// The convex hull of the vertices of the OBJ file at `path` (scaled by `scale`) as a
/// [`Shape::ConvexHull`].
pub fn convex_hull_from_obj(path: &Path, scale: Vector3<f64>) -> Result<Shape, GeometryError> {
    Ok(Shape::ConvexHull {
        points: obj_vertices(path, scale)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * b.abs().max(1e-300)
    }

    #[test]
    fn pointed_cone_matches_textbook() {
        // Solid cone, base radius R, height h: V = πR²h/3, centroid h/4 above the base,
        // axial I = 3/10 m R², transverse about centroid 3/20 m R² + 3/80 m h².
        let (r, h) = (0.3, 1.2);
        let p = Shape::Cone {
            axis: Axis::Z,
            diameter: 2.0 * r,
            length: h,
            top_diameter: 0.0,
        }
        .unit_mass_properties()
        .unwrap();
        let v = PI * r * r * h / 3.0;
        assert!(close(p.volume, v, 1e-14));
        assert!(close(p.com.z, h / 4.0, 1e-14));
        assert!(close(p.inertia[(2, 2)], 0.3 * v * r * r, 1e-14));
        assert!(close(
            p.inertia[(0, 0)],
            v * (0.15 * r * r + 3.0 / 80.0 * h * h),
            1e-13
        ));
    }

    #[test]
    fn cone_with_equal_diameters_is_a_cylinder() {
        let cone = Shape::Cone {
            axis: Axis::X,
            diameter: 0.4,
            length: 0.7,
            top_diameter: 0.4,
        }
        .unit_mass_properties()
        .unwrap();
        let cyl = Shape::Cylinder {
            axis: Axis::X,
            diameter: 0.4,
            length: 0.7,
        }
        .unit_mass_properties()
        .unwrap();
        assert!(close(cone.volume, cyl.volume, 1e-14));
        assert!(close(cone.com.x, 0.35, 1e-14));
        for i in 0..3 {
            assert!(close(cone.inertia[(i, i)], cyl.inertia[(i, i)], 1e-13));
        }
    }

    #[test]
    fn capsule_of_zero_length_is_a_sphere() {
        let cap = Shape::Capsule {
            axis: Axis::Y,
            diameter: 0.2,
            length: 0.0,
        }
        .unit_mass_properties()
        .unwrap();
        let sph = Shape::Sphere { diameter: 0.2 }
            .unit_mass_properties()
            .unwrap();
        assert!(close(cap.volume, sph.volume, 1e-14));
        for i in 0..3 {
            assert!(close(cap.inertia[(i, i)], sph.inertia[(i, i)], 1e-13));
        }
    }

    /// The beam's closed form against Modia3D's route to it (each half-cylinder's inertia about
    /// the full cylinder's axis, shifted to its own centroid `4r/(3π)` away, then to the beam's
    /// centre): the same numbers by different algebra, to rounding (1e-12).
    #[test]
    fn beam_matches_the_parallel_axis_route() {
        let (l, w, t) = (0.7, 0.3, 0.11);
        for axis in [Axis::X, Axis::Y, Axis::Z] {
            let p = Shape::Beam {
                axis,
                length: l,
                width: w,
                thickness: t,
            }
            .unit_mass_properties()
            .unwrap();
            let r = w / 2.0;
            let (m_box, m_half) = (l * w * t, PI * r * r * t / 2.0);
            let d = 4.0 * r / (3.0 * PI);
            let shift = |i0: f64| i0 - m_half * d * d + m_half * (d + l / 2.0).powi(2);
            let i_l = m_box / 12.0 * (w * w + t * t) + 2.0 * m_half / 12.0 * (3.0 * r * r + t * t);
            let i_w =
                m_box / 12.0 * (t * t + l * l) + 2.0 * shift(m_half / 12.0 * (3.0 * r * r + t * t));
            let i_t = m_box / 12.0 * (l * l + w * w) + 2.0 * shift(m_half / 2.0 * r * r);
            assert!(close(p.volume, m_box + 2.0 * m_half, 1e-14));
            assert_eq!(p.com, Vector3::zeros());
            let (kw, kt) = axis.beam_directions();
            assert!(close(p.inertia[(axis.index(), axis.index())], i_l, 1e-12));
            assert!(close(p.inertia[(kw, kw)], i_w, 1e-12));
            assert!(close(p.inertia[(kt, kt)], i_t, 1e-12));
            assert_eq!(p.inertia[(0, 1)], 0.0);
        }
        // Modia3D's table: axis 2 puts length on y, width on z, thickness on x.
        assert_eq!(Axis::Y.beam_directions(), (2, 0));
    }

    #[test]
    fn convex_hull_of_box_corners_is_the_box() {
        let l = Vector3::new(0.2, 0.5, 1.1);
        let mut pts = Vec::new();
        for i in 0..8 {
            let s = |k: usize| if i & (1 << k) != 0 { 0.5 } else { -0.5 };
            pts.push(Point3::new(s(0) * l.x, s(1) * l.y, s(2) * l.z + 3.0));
        }
        let hull = Shape::ConvexHull { points: pts }
            .unit_mass_properties()
            .unwrap();
        let bx = Shape::Box { lengths: l }.unit_mass_properties().unwrap();
        assert!(close(hull.volume, bx.volume, 1e-12));
        assert!((hull.com - Vector3::new(0.0, 0.0, 3.0)).norm() < 1e-12);
        assert!((hull.inertia - bx.inertia).norm() < 1e-12 * bx.inertia.norm());
    }
}
