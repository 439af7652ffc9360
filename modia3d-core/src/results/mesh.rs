//! Results stage, display meshes: triangle meshes of the shapes for animation export (glTF).
//! Pure geometry in the shape frame (see `geometry::shapes` for the conventions); touches
//! nothing else.
//!
//! Every built-in shape is convex, so triangles are generated in any order and then turned to
//! face away from the shape's centre; a mesh keeps its triangles' orientation. Each triangle
//! gets its own (flat) normal.
// Export encoding: offsets into buffers this module sized itself from the same lengths; no
// index comes from user input, which reaches it only through the checked signal look-up.
#![allow(clippy::indexing_slicing)]

use crate::geometry::{Axis, Shape};
use nalgebra::{Point3, Vector3};

/// Segments around an axis of revolution.
const SEGMENTS: usize = 24;
/// Rings from pole to pole of a sphere (half of them per cap of a capsule).
const RINGS: usize = 12;

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
    pub(super) fn push(
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
    pub(super) fn bounds(&self) -> Option<([f32; 3], [f32; 3])> {
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

/// A surface of revolution about `axis`: `profile` is a list of `(radius, height)` points from
/// one end to the other; the mesh is scaled by `scale` afterwards (ellipsoids).
fn lathe(axis: Axis, profile: &[(f64, f64)], scale: Vector3<f64>) -> TriMesh {
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
fn arc(r: f64, h0: f64, from: f64, to: f64, rings: usize) -> Vec<(f64, f64)> {
    (0..=rings)
        .map(|i| {
            let t = from + (to - from) * i as f64 / rings as f64;
            (r * t.sin(), h0 - r * t.cos())
        })
        .collect()
}

/// The display mesh of a shape, in its shape frame.
pub(crate) fn shape_mesh(shape: &Shape) -> TriMesh {
    use std::f64::consts::{FRAC_PI_2, PI};
    let one = Vector3::new(1.0, 1.0, 1.0);
    match shape {
        Shape::Sphere { diameter } => {
            lathe(Axis::Y, &arc(diameter / 2.0, 0.0, 0.0, PI, RINGS), one)
        }
        Shape::Ellipsoid { lengths } => {
            lathe(Axis::Y, &arc(1.0, 0.0, 0.0, PI, RINGS), lengths / 2.0)
        }
        Shape::Cylinder {
            axis,
            diameter,
            length,
        } => {
            let (r, h) = (diameter / 2.0, length / 2.0);
            lathe(*axis, &[(0.0, -h), (r, -h), (r, h), (0.0, h)], one)
        }
        Shape::Capsule {
            axis,
            diameter,
            length,
        } => {
            let (r, h) = (diameter / 2.0, length / 2.0);
            let mut p = arc(r, -h, 0.0, FRAC_PI_2, RINGS / 2);
            p.extend(arc(r, h, FRAC_PI_2, PI, RINGS / 2));
            lathe(*axis, &p, one)
        }
        Shape::Cone {
            axis,
            diameter,
            length,
            top_diameter,
        } => lathe(
            *axis,
            &[
                (0.0, 0.0),
                (diameter / 2.0, 0.0),
                (top_diameter / 2.0, *length),
                (0.0, *length),
            ],
            one,
        ),
        Shape::Box { lengths } => {
            let h = lengths / 2.0;
            let c = |i: usize| {
                Vector3::new(
                    if i & 1 == 0 { -h.x } else { h.x },
                    if i & 2 == 0 { -h.y } else { h.y },
                    if i & 4 == 0 { -h.z } else { h.z },
                )
            };
            let mut m = TriMesh::default();
            let centre = Vector3::zeros();
            // Faces as corner-index quads (bit 0 = x, bit 1 = y, bit 2 = z).
            for q in [
                [0, 2, 6, 4],
                [1, 3, 7, 5],
                [0, 1, 5, 4],
                [2, 3, 7, 6],
                [0, 1, 3, 2],
                [4, 5, 7, 6],
            ] {
                m.push(c(q[0]), c(q[1]), c(q[2]), &centre);
                m.push(c(q[0]), c(q[2]), c(q[3]), &centre);
            }
            m
        }
        Shape::Beam {
            axis,
            length,
            width,
            thickness,
        } => hull_mesh(&beam_points(*axis, *length, *width, *thickness)),
        Shape::ConvexHull { points } => hull_mesh(points),
        // A mesh keeps its own (outward) orientation: it need not be convex.
        Shape::Mesh { mesh, .. } => {
            let mut m = TriMesh::default();
            for t in &mesh.triangles {
                let [a, b, c] = t.map(|i| mesh.vertices[i as usize].coords);
                let centre = (a + b + c) / 3.0 - (b - a).cross(&(c - a));
                m.push(a, b, c, &centre);
            }
            m
        }
        // Loaded by `SceneDesc::build`; a result never holds an unloaded one.
        Shape::FileMesh { .. } => TriMesh::default(),
    }
}

/// Points whose convex hull is a [`Shape::Beam`] with each half-disk end drawn as `SEGMENTS / 2`
/// chords (vertices on the circle).
fn beam_points(axis: Axis, length: f64, width: f64, thickness: f64) -> Vec<Point3<f64>> {
    let (k, (kw, kt)) = (axis.index(), axis.beam_directions());
    let (r, n) = (width / 2.0, SEGMENTS / 2);
    let mut pts = Vec::with_capacity(4 * (n + 1));
    for end in [-1.0, 1.0] {
        for i in 0..=n {
            let phi = std::f64::consts::PI * (i as f64 / n as f64 - 0.5);
            for s in [-1.0, 1.0] {
                let mut p = Point3::origin();
                p[k] = end * (length / 2.0 + r * phi.cos());
                p[kw] = r * phi.sin();
                p[kt] = s * thickness / 2.0;
                pts.push(p);
            }
        }
    }
    pts
}

/// The display mesh of the convex hull of `points`.
fn hull_mesh(points: &[Point3<f64>]) -> TriMesh {
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
            let v = volume(&shape_mesh(&s));
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
        assert!((volume(&shape_mesh(&shape)) - exact).abs() < 1e-6);
    }

    #[test]
    fn cone_base_is_at_zero_along_its_axis() {
        let m = shape_mesh(&Shape::Cone {
            axis: Axis::Z,
            diameter: 1.0,
            length: 2.0,
            top_diameter: 0.0,
        });
        let (lo, hi) = m.bounds().unwrap();
        assert_eq!((lo[2], hi[2]), (0.0, 2.0));
    }
}
