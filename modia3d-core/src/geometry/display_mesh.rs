//! Display meshes (geometry stage): the triangulation helpers the shape kinds draw their
//! display mesh with (`geometry/kinds/<kind>.rs`, `display_mesh`; [`Shape::display_mesh`](super::Shape::display_mesh) is
//! the dispatch), for the animation exports of `results/` (glTF, three.js), which serialise
//! them. Pure geometry in the shape frame (see `geometry::shapes` for the conventions).
//!
//! Every built-in shape is convex, so triangles are generated in any order and then turned to
//! face away from the shape's centre; a mesh keeps its triangles' orientation. Each triangle
//! gets its own (flat) normal.

// Without the `solver` feature (the `model!` macro's build, which asks only the rows and the
// validation facts) the contact preprocess and the display exports are not compiled.
#![cfg_attr(not(feature = "solver"), allow(dead_code))]

use super::shapes::Axis;
use nalgebra::{Point3, Vector3};

/// Segments around an axis of revolution.
pub(crate) const SEGMENTS: usize = 24;
/// Rings from pole to pole of a sphere (half of them per cap of a capsule).
pub(crate) const RINGS: usize = 12;

/// A non-indexed triangle list: three vertices per triangle, one normal per vertex \[m\].
#[derive(Clone, Debug, Default)]
pub(crate) struct TriMesh {
    /// Vertex positions in the shape frame \[m\].
    pub positions: Vec<[f32; 3]>,
    /// Unit normals, pointing out of the solid.
    pub normals: Vec<[f32; 3]>,
}

impl TriMesh {
    /// Adds triangle `a, b, c`, turned to face away from `centre`; skips degenerate ones.
    pub(crate) fn push(
        &mut self,
        a: Vector3<f64>,
        b: Vector3<f64>,
        c: Vector3<f64>,
        centre: &Vector3<f64>,
    ) {
        let n = (b - a).cross(&(c - a));
        let len = n.norm();
        if len < 1e-14 {
            return;
        }
        let mut n = n / len;
        let (b, c) = if n.dot(&((a + b + c) / 3.0 - centre)) < 0.0 {
            n = -n;
            (c, b)
        } else {
            (b, c)
        };
        let f = |v: Vector3<f64>| [v.x as f32, v.y as f32, v.z as f32];
        self.positions.extend([f(a), f(b), f(c)]);
        self.normals.extend([f(n); 3]);
    }

    /// Axis-aligned bounds `(min, max)` of the vertices, or `None` for an empty mesh.
    #[cfg(test)]
    pub(crate) fn bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        let mut it = self.positions.iter();
        let first = *it.next()?;
        Some(it.fold((first, first), |(mut lo, mut hi), p| {
            for i in 0..3 {
                lo[i] = lo[i].min(p[i]);
                hi[i] = hi[i].max(p[i]);
            }
            (lo, hi)
        }))
    }
}

/// A display primitive of a shape, in its shape frame, for an export that draws balls, boxes,
/// frustums and capsules with geometries of its own (three.js); a shape without one is drawn
/// as its display mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Primitive {
    /// A ball of radius `radius` \[m\] centred at the origin, scaled along x, y, z by
    /// `scaling` (an ellipsoid) if given.
    Ball {
        /// Radius \[m\].
        radius: f64,
        /// Factors along x, y, z.
        scaling: Option<Vector3<f64>>,
    },
    /// A box with edge lengths along x, y, z \[m\], centred at the origin.
    Box {
        /// Edge lengths \[m\].
        lengths: Vector3<f64>,
    },
    /// A frustum along `axis`, its centre at `lift` on the axis \[m\].
    Frustum {
        /// Its axis.
        axis: Axis,
        /// Radius of the end towards +axis \[m\].
        top: f64,
        /// Radius of the end towards −axis \[m\].
        bottom: f64,
        /// Length along the axis \[m\].
        length: f64,
        /// Position of its centre on the axis \[m\].
        lift: f64,
    },
    /// A capsule along `axis`, centred at the origin.
    Capsule {
        /// Its axis.
        axis: Axis,
        /// Radius of the cylinder and caps \[m\].
        radius: f64,
        /// Length of the cylindrical part \[m\].
        length: f64,
    },
}

/// A surface of revolution about `axis`: `profile` is a list of `(radius, height)` points from
/// one end to the other; the mesh is scaled by `scale` afterwards (ellipsoids).
pub(crate) fn lathe(axis: Axis, profile: &[(f64, f64)], scale: Vector3<f64>) -> TriMesh {
    let a = axis.index();
    let (e1, e2) = ((a + 1) % 3, (a + 2) % 3);
    let point = |r: f64, h: f64, k: usize| {
        let th = 2.0 * std::f64::consts::PI * (k % SEGMENTS) as f64 / SEGMENTS as f64;
        let mut v = Vector3::zeros();
        v[a] = h;
        v[e1] = r * th.cos();
        v[e2] = r * th.sin();
        v.component_mul(&scale)
    };
    let centre = {
        let hs: Vec<f64> = profile.iter().map(|p| p.1).collect();
        let mut c = Vector3::zeros();
        c[a] = 0.5
            * (hs.iter().cloned().fold(f64::INFINITY, f64::min)
                + hs.iter().cloned().fold(f64::NEG_INFINITY, f64::max));
        c.component_mul(&scale)
    };
    let mut m = TriMesh::default();
    for w in profile.windows(2) {
        let ((r0, h0), (r1, h1)) = (w[0], w[1]);
        for k in 0..SEGMENTS {
            let (p00, p01) = (point(r0, h0, k), point(r0, h0, k + 1));
            let (p10, p11) = (point(r1, h1, k), point(r1, h1, k + 1));
            m.push(p00, p10, p11, &centre);
            m.push(p00, p11, p01, &centre);
        }
    }
    m
}

/// A sphere profile of radius `r` centred at height `h0`, from angle `from` to `to` (0 = the −axis
/// pole, π = the +axis pole), with `rings` steps.
pub(crate) fn arc(r: f64, h0: f64, from: f64, to: f64, rings: usize) -> Vec<(f64, f64)> {
    (0..=rings)
        .map(|i| {
            let t = from + (to - from) * i as f64 / rings as f64;
            (r * t.sin(), h0 - r * t.cos())
        })
        .collect()
}

/// The display mesh of the convex hull of `points`.
pub(crate) fn hull_mesh(points: &[Point3<f64>]) -> TriMesh {
    let (verts, tris) = convex_hull(points);
    let centre = verts.iter().fold(Vector3::zeros(), |s, p| s + p) / verts.len().max(1) as f64;
    let mut m = TriMesh::default();
    for t in tris {
        m.push(
            verts[t[0] as usize],
            verts[t[1] as usize],
            verts[t[2] as usize],
            &centre,
        );
    }
    m
}

/// Vertices and triangles of the convex hull of `points` (parry's quickhull); empty when the
/// points are too few or degenerate (flat).
pub(crate) fn convex_hull(points: &[Point3<f64>]) -> (Vec<Vector3<f64>>, Vec<[u32; 3]>) {
    match parry3d_f64::transformation::try_convex_hull(points) {
        Ok((v, t)) => (v.into_iter().map(|p| p.coords).collect(), t),
        Err(_) => (points.iter().map(|p| p.coords).collect(), vec![]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Shape;

    fn volume(m: &TriMesh) -> f64 {
        // Divergence theorem over outward triangles.
        m.positions
            .chunks(3)
            .map(|t| {
                let v = |p: [f32; 3]| Vector3::new(p[0] as f64, p[1] as f64, p[2] as f64);
                v(t[0]).dot(&v(t[1]).cross(&v(t[2]))) / 6.0
            })
            .sum()
    }

    #[test]
    fn meshes_are_closed_outward_and_close_to_the_exact_volume() {
        let shapes = [
            Shape::Sphere { diameter: 2.0 },
            Shape::Box {
                lengths: Vector3::new(1.0, 2.0, 3.0),
            },
            Shape::Cylinder {
                axis: Axis::X,
                diameter: 1.0,
                length: 2.0,
            },
            Shape::Capsule {
                axis: Axis::Z,
                diameter: 1.0,
                length: 1.0,
            },
            Shape::Cone {
                axis: Axis::Y,
                diameter: 1.0,
                length: 1.0,
                top_diameter: 0.5,
            },
            Shape::Ellipsoid {
                lengths: Vector3::new(1.0, 2.0, 3.0),
            },
            Shape::Beam {
                axis: Axis::Y,
                length: 1.0,
                width: 0.5,
                thickness: 0.2,
            },
        ];
        for s in shapes {
            let exact = s.unit_mass_properties().unwrap().volume;
            let v = volume(&s.display_mesh());
            assert!(
                (v - exact).abs() < 0.05 * exact,
                "{s:?}: mesh {v}, exact {exact}"
            );
        }
    }

    /// A non-convex mesh (an L prism) is drawn with its own orientation: turning triangles away
    /// from a centre, as for the convex shapes, would flip the faces of the inner corner and
    /// change the divergence-theorem volume.
    #[test]
    fn mesh_display_keeps_the_orientation_of_a_non_convex_mesh() {
        let profile = [
            (0.0, 0.0),
            (2.0, 0.0),
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 3.0),
            (0.0, 3.0),
        ];
        let mut vertices = vec![];
        for z in [0.0, 1.0] {
            vertices.extend(profile.iter().map(|&(x, y)| Point3::new(x, y, z)));
        }
        let mut triangles = vec![];
        for (a, b) in [(4, 5), (5, 0), (0, 1), (1, 2)] {
            triangles.push([9, a + 6, b + 6]);
            triangles.push([3, b, a]);
        }
        for i in 0..6u32 {
            let j = (i + 1) % 6;
            triangles.push([i, j, j + 6]);
            triangles.push([i, j + 6, i + 6]);
        }
        let mesh = crate::geometry::TriangleMesh {
            vertices,
            triangles,
            source: "L".into(),
        };
        let exact = crate::geometry::mesh_mass_properties(&mesh).unwrap().volume;
        assert!((exact - 4.0).abs() < 1e-14); // 2·1·1 + 1·2·1
        let shape = Shape::Mesh {
            mesh: std::sync::Arc::new(mesh),
            collision: crate::geometry::MeshCollision::ConvexHull,
        };
        assert!((volume(&shape.display_mesh()) - exact).abs() < 1e-6);
    }

    #[test]
    fn cone_base_is_at_zero_along_its_axis() {
        let m = Shape::Cone {
            axis: Axis::Z,
            diameter: 1.0,
            length: 2.0,
            top_diameter: 0.0,
        }
        .display_mesh();
        let (lo, hi) = m.bounds().unwrap();
        assert_eq!((lo[2], hi[2]), (0.0, 2.0));
    }
}
