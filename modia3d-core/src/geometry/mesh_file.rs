//! Triangle meshes from files and their exact mass properties (geometry stage; reads files,
//! touches nothing else).
//!
//! Formats, chosen by the file extension (case-insensitive):
//! - Wavefront OBJ (`.obj`), parsed here: `v x y z` lines and `f` lines (indices 1-based or
//!   negative, `i`, `i/t`, `i//n`, `i/t/n`; polygons split into a fan of triangles); all other
//!   lines (normals, texture coordinates, groups, materials) are ignored. A malformed line is a
//!   [`GeometryError::MeshParse`] with its line number.
//! - STL (`.stl`), ASCII or binary, through the `stl_io` crate (no dependencies of its own);
//!   corners with bit-identical coordinates are one vertex. A malformed file is a
//!   [`GeometryError::MeshParse`] naming the facet (STL has one facet per 7 lines in ASCII).
//!
//! Paths are used as given: a relative path is relative to the process's current directory
//! (for `cargo run`/`cargo test` the package root). For a file shipped with a crate, write
//! `concat!(env!("CARGO_MANIFEST_DIR"), "/assets/part.stl")`.
//!
//! [`mesh_mass_properties`]: volume, centre of mass and inertia of the solid a closed, oriented
//! triangle mesh bounds, by the divergence theorem (a sum of signed tetrahedra). Collision uses
//! convex pieces: the convex hull of all vertices, or a convex decomposition (parry's V-HACD)
//! into several hulls ([`convex_parts`]).

use super::error::GeometryError;
use super::shapes::{MeshCollision, Shape, UnitMassProperties};
use nalgebra::{Matrix3, Point3, Vector3};
use std::collections::HashMap;
use std::path::Path;

/// A triangle mesh in its shape frame: vertices \[m\] and triangles as vertex indices,
/// counter-clockwise seen from outside for a mesh that bounds a solid.
#[derive(Clone, Debug, PartialEq)]
pub struct TriangleMesh {
    /// Vertex positions in the shape frame \[m\].
    pub vertices: Vec<Point3<f64>>,
    /// Triangles as indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
    /// Where the mesh came from (the file path as given), for messages.
    pub source: String,
}

/// Reads the mesh file at `path` (OBJ or STL by extension) and multiplies every vertex
/// component-wise by `scale` (each component > 0) [m after scaling].
pub fn load_mesh(path: &Path, scale: Vector3<f64>) -> Result<TriangleMesh, GeometryError> {
    let source = path.display().to_string();
    let io = |message: String| GeometryError::MeshFile {
        path: source.clone(),
        message,
    };
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let (vertices, triangles) = match ext.as_deref() {
        Some("obj") => {
            let text = std::fs::read_to_string(path).map_err(|e| io(io_message(&e)))?;
            parse_obj(&text, &source)?
        }
        Some("stl") => {
            let mut file = std::fs::File::open(path).map_err(|e| io(io_message(&e)))?;
            read_stl(&mut file, &source)?
        }
        _ => {
            return Err(io(
                "unknown format: the file name must end in .obj or .stl".into()
            ))
        }
    };
    if triangles.is_empty() {
        return Err(io("no triangles in the file".into()));
    }
    Ok(TriangleMesh {
        vertices: vertices
            .into_iter()
            .map(|p| Point3::from(p.coords.component_mul(&scale)))
            .collect(),
        triangles,
        source,
    })
}

fn io_message(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => {
            "file not found (relative paths are relative to the current directory; use \
             concat!(env!(\"CARGO_MANIFEST_DIR\"), \"/…\") for a crate's own files)"
                .into()
        }
        _ => e.to_string(),
    }
}

type Parsed = (Vec<Point3<f64>>, Vec<[u32; 3]>);

/// Vertices and triangles of an OBJ text (see the module docs).
fn parse_obj(text: &str, source: &str) -> Result<Parsed, GeometryError> {
    let (mut vertices, mut triangles) = (Vec::new(), Vec::new());
    for (n, line) in text.lines().enumerate() {
        let err = |message: String| GeometryError::MeshParse {
            path: source.into(),
            location: format!("line {}", n + 1),
            message,
        };
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let mut c = [0.0; 3];
                for x in &mut c {
                    let w = words
                        .next()
                        .ok_or_else(|| err("`v` needs three coordinates".into()))?;
                    *x = w
                        .parse::<f64>()
                        .ok()
                        .filter(|x| x.is_finite())
                        .ok_or_else(|| err(format!("`{w}` is not a finite number")))?;
                }
                vertices.push(Point3::from(c));
            }
            Some("f") => {
                let mut idx = Vec::new();
                for w in words {
                    let first = w.split('/').next().unwrap_or("");
                    let i: i64 = first
                        .parse()
                        .map_err(|_| err(format!("`{w}` is not a vertex index")))?;
                    let n_v = vertices.len() as i64;
                    let k = if i < 0 { n_v + i } else { i - 1 };
                    if !(0..n_v).contains(&k) || i == 0 {
                        return Err(err(format!(
                            "vertex index {i} out of range (1..={n_v} or -1..=-{n_v})"
                        )));
                    }
                    idx.push(k as u32);
                }
                if idx.len() < 3 {
                    return Err(err("a face needs at least three vertices".into()));
                }
                for j in 1..idx.len() - 1 {
                    triangles.push([idx[0], idx[j], idx[j + 1]]);
                }
            }
            _ => {}
        }
    }
    Ok((vertices, triangles))
}

/// Vertices (corners with bit-identical coordinates merged) and triangles of an STL stream.
fn read_stl<R: std::io::Read + std::io::Seek>(
    read: &mut R,
    source: &str,
) -> Result<Parsed, GeometryError> {
    let err = |location: String, e: std::io::Error| GeometryError::MeshParse {
        path: source.into(),
        location,
        message: e.to_string(),
    };
    let reader = stl_io::create_stl_reader(read).map_err(|e| err("header".into(), e))?;
    let (mut vertices, mut triangles) = (Vec::new(), Vec::new());
    let mut index: HashMap<[u32; 3], u32> = HashMap::new();
    for (k, tri) in reader.enumerate() {
        let tri = tri.map_err(|e| err(format!("facet {}", k + 1), e))?;
        let mut t = [0u32; 3];
        for (slot, v) in t.iter_mut().zip(tri.vertices.iter()) {
            let c: [f32; 3] = (*v).into();
            if !c.iter().all(|x| x.is_finite()) {
                return Err(GeometryError::MeshParse {
                    path: source.into(),
                    location: format!("facet {}", k + 1),
                    message: "a vertex coordinate is not finite".into(),
                });
            }
            *slot = *index.entry(c.map(f32::to_bits)).or_insert_with(|| {
                vertices.push(Point3::new(
                    f64::from(c[0]),
                    f64::from(c[1]),
                    f64::from(c[2]),
                ));
                (vertices.len() - 1) as u32
            });
        }
        triangles.push(t);
    }
    Ok((vertices, triangles))
}

/// All vertex positions of the OBJ file at `path` that a face uses, each multiplied
/// component-wise by `scale` [m after scaling].
pub fn obj_vertices(path: &Path, scale: Vector3<f64>) -> Result<Vec<Point3<f64>>, GeometryError> {
    let mesh = load_mesh(path, scale)?;
    let mut used = vec![false; mesh.vertices.len()];
    for t in &mesh.triangles {
        for &i in t {
            used[i as usize] = true;
        }
    }
    let points: Vec<Point3<f64>> = mesh
        .vertices
        .iter()
        .zip(&used)
        .filter(|(_, u)| **u)
        .map(|(p, _)| *p)
        .collect();
    if points.len() < 4 {
        return Err(GeometryError::MeshFile {
            path: mesh.source,
            message: format!("{} vertices, need at least 4", points.len()),
        });
    }
    Ok(points)
}

/// The convex hull of the vertices of the OBJ file at `path` (scaled by `scale`) as a
/// [`Shape::ConvexHull`].
pub fn convex_hull_from_obj(path: &Path, scale: Vector3<f64>) -> Result<Shape, GeometryError> {
    Ok(Shape::ConvexHull {
        points: obj_vertices(path, scale)?,
    })
}

/// Volume \[m³\], centre of mass \[m\] and unit-density inertia about it \[m⁵\] of the solid
/// that `mesh` bounds, exactly (to rounding) by the divergence theorem: each triangle and a
/// reference point `o` (the vertex centroid, which keeps the terms small) span a tetrahedron
/// of signed volume `v = a·(b×c)/6` (`a, b, c` relative to `o`), first moment `v(a+b+c)/4` and
/// second moment `∫xxᵀ = v/20 (aaᵀ + bbᵀ + ccᵀ + ssᵀ)`, `s = a+b+c`; their sums are the solid's.
///
/// Errors: an edge not shared by exactly two triangles in opposite directions
/// ([`GeometryError::MeshNotClosed`], naming the edge's vertices; such a mesh bounds no
/// solid, or is not consistently oriented), or a volume that is not positive
/// ([`GeometryError::MeshVolume`]: all triangles clockwise seen from outside, or a flat mesh).
pub fn mesh_mass_properties(mesh: &TriangleMesh) -> Result<UnitMassProperties, GeometryError> {
    check_closed(mesh)?;
    let o = mesh
        .vertices
        .iter()
        .fold(Vector3::zeros(), |s, p| s + p.coords)
        / mesh.vertices.len().max(1) as f64;
    let (mut vol, mut first, mut second) = (0.0, Vector3::zeros(), Matrix3::zeros());
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize].coords - o);
        let v = a.dot(&b.cross(&c)) / 6.0;
        let s = a + b + c;
        vol += v;
        first += s * (v / 4.0);
        second += (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose())
            * (v / 20.0);
    }
    let size = mesh
        .vertices
        .iter()
        .map(|p| (p.coords - o).norm())
        .fold(0.0, f64::max);
    if !(vol.is_finite() && vol > 1e-12 * size.powi(3)) {
        return Err(GeometryError::MeshVolume {
            path: mesh.source.clone(),
            volume: vol,
        });
    }
    let com = first / vol;
    let c = second - com * com.transpose() * vol; // ∫ (x − com)(x − com)ᵀ
    Ok(UnitMassProperties {
        volume: vol,
        com: com + o,
        inertia: Matrix3::identity() * c.trace() - c,
    })
}

/// Every directed edge must appear once and its reverse once (a closed, consistently oriented
/// 2-manifold surface, as the divergence theorem needs).
fn check_closed(mesh: &TriangleMesh) -> Result<(), GeometryError> {
    let mut edges: HashMap<(u32, u32), i32> = HashMap::with_capacity(3 * mesh.triangles.len());
    for t in &mesh.triangles {
        for k in 0..3 {
            *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
        }
    }
    let bad: Vec<(u32, u32)> = edges
        .iter()
        .filter(|(&(a, b), &n)| n != 1 || edges.get(&(b, a)) != Some(&1))
        .map(|(&e, _)| e)
        .collect();
    match bad.iter().min() {
        None => Ok(()),
        Some(&(a, b)) => Err(GeometryError::MeshNotClosed {
            path: mesh.source.clone(),
            edges: bad.len(),
            example: format!(
                "{a} → {b} at {:?} → {:?}",
                mesh.vertices[a as usize].coords.as_slice(),
                mesh.vertices[b as usize].coords.as_slice()
            ),
        }),
    }
}

/// The convex pieces of a mesh for collision, as point sets (each is a
/// [`Shape::ConvexHull`]'s points): the hull of all vertices (`MeshCollision::ConvexHull`), or
/// the exact hulls of the parts of parry's V-HACD decomposition (voxel resolution 64, its
/// default concavity 0.01 of the mesh size) clipped to the mesh's triangles, so the parts'
/// outer faces lie on the mesh's faces. Parts without volume are dropped; if none is left the
/// hull of all vertices is used.
pub fn convex_parts(mesh: &TriangleMesh, collision: MeshCollision) -> Vec<Vec<Point3<f64>>> {
    let all = || vec![mesh.vertices.clone()];
    match collision {
        MeshCollision::ConvexHull => all(),
        MeshCollision::ConvexDecomposition => {
            use parry3d_f64::transformation::vhacd::{VHACDParameters, VHACD};
            let params = VHACDParameters::default();
            let v = VHACD::decompose(&params, &mesh.vertices, &mesh.triangles, true);
            let parts: Vec<Vec<Point3<f64>>> = v
                .compute_exact_convex_hulls(&mesh.vertices, &mesh.triangles)
                .into_iter()
                .map(|(points, _)| points)
                .filter(|p| super::smoothing::hull_inner_width(p).is_ok())
                .collect();
            if parts.is_empty() {
                all()
            } else {
                parts
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube written with quads, `i/t/n` and negative (relative) indices: six quads fan
    /// into twelve triangles; volume 1, centre (½, ½, ½), inertia 1/6 on the diagonal (the
    /// closed form of a unit cube of unit density), to rounding.
    #[test]
    fn obj_quads_and_relative_indices_give_the_cube() {
        let mut text = String::from("# cube\nvn 0 0 1\n");
        for i in 0..8 {
            let b = |k: usize| (i >> k) & 1;
            text.push_str(&format!("v {} {} {}\n", b(0), b(1), b(2)));
        }
        // Faces counter-clockwise seen from outside (corner index = x + 2y + 4z, 1-based).
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        for (n, q) in quads.iter().enumerate() {
            let idx: Vec<String> = q
                .iter()
                .map(|&c| match n % 3 {
                    0 => format!("{}", c + 1),
                    1 => format!("{}//1", c as i64 - 8),
                    _ => format!("{}/1/1", c + 1),
                })
                .collect();
            text.push_str(&format!("f {}\n", idx.join(" ")));
        }
        let (vertices, triangles) = parse_obj(&text, "cube.obj").unwrap();
        assert_eq!(triangles.len(), 12);
        let mesh = TriangleMesh {
            vertices,
            triangles,
            source: "cube.obj".into(),
        };
        let p = mesh_mass_properties(&mesh).unwrap();
        assert!((p.volume - 1.0).abs() < 1e-15);
        assert!((p.com - Vector3::repeat(0.5)).norm() < 1e-15);
        assert!((p.inertia - Matrix3::identity() / 6.0).norm() < 1e-15);
    }

    #[test]
    fn obj_index_out_of_range_names_the_line() {
        let e = parse_obj("v 0 0 0\nv 1 0 0\n\nf 1 2 4\n", "t.obj").unwrap_err();
        assert!(
            matches!(&e, GeometryError::MeshParse { location, message, .. }
                if location == "line 4" && message.contains("out of range")),
            "{e}"
        );
    }
}
