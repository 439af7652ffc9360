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
use super::mass_properties::UnitMassProperties;
use nalgebra::{Matrix3, Point3, Vector3};
use std::collections::HashMap;
use std::path::Path;

/// How a triangle mesh collides.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum MeshCollision {
    /// One collision shape: the convex hull of all vertices (exact for a convex mesh).
    #[default]
    ConvexHull,
    /// Several collision shapes of the same body: the convex parts of a decomposition
    /// (parry's V-HACD; see `geometry::mesh_file::convex_parts`), for non-convex meshes. The
    /// parts never collide with each other; each forms its own pairs, named `<object>#<k>`.
    ConvexDecomposition,
}

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

/// Volume \[m³\], centre of mass \[m\] and unit-density inertia about it \[m⁵\] of the solid
/// that `mesh` bounds, exactly (to rounding) by the divergence theorem: each triangle and a
/// reference point `o` (the vertex centroid, which keeps the terms small) span a tetrahedron
/// of signed volume `v = a·(b×c)/6` (`a, b, c` relative to `o`), first moment `v(a+b+c)/4` and
/// second moment `∫xxᵀ = v/20 (aaᵀ + bbᵀ + ccᵀ + ssᵀ)`, `s = a+b+c`; their sums are the solid's.
///
/// The mesh must be closed as a sum of oriented triangles: every edge is crossed as often in
/// one direction as in the other (a closed 2-manifold, or closed shells that touch along
/// edges); then the sums do not depend on `o`. A mesh read from a file for a solid is first
/// repaired by [`repair_mesh`] (`SceneDesc::build` does it).
///
/// Errors: an edge crossed more often in one direction than in the other
/// ([`GeometryError::MeshNotClosed`], naming the edge's vertices; such a mesh has holes, or is
/// not consistently oriented), or a volume that is not positive ([`GeometryError::MeshVolume`]:
/// all triangles clockwise seen from outside, or a flat mesh).
pub fn mesh_mass_properties(mesh: &TriangleMesh) -> Result<UnitMassProperties, GeometryError> {
    check_closed(mesh)?;
    let o = vertex_centroid(&mesh.vertices);
    let (vol, first, second) = moments(&mesh.vertices, &mesh.triangles, &o);
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

/// The mean of `vertices` (the origin for none) \[m\].
fn vertex_centroid(vertices: &[Point3<f64>]) -> Vector3<f64> {
    vertices.iter().fold(Vector3::zeros(), |s, p| s + p.coords) / vertices.len().max(1) as f64
}

/// Signed volume \[m³\], first moment \[m⁴\] and second moment `∫xxᵀ` \[m⁵\] (coordinates
/// relative to `o`) of the tetrahedra that `o` and each triangle span (see
/// [`mesh_mass_properties`]).
fn moments(
    vertices: &[Point3<f64>],
    triangles: &[[u32; 3]],
    o: &Vector3<f64>,
) -> (f64, Vector3<f64>, Matrix3<f64>) {
    let (mut vol, mut first, mut second) = (0.0, Vector3::zeros(), Matrix3::zeros());
    for t in triangles {
        let [a, b, c] = t.map(|i| vertices[i as usize].coords - o);
        let v = a.dot(&b.cross(&c)) / 6.0;
        let s = a + b + c;
        vol += v;
        first += s * (v / 4.0);
        second += (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose())
            * (v / 20.0);
    }
    (vol, first, second)
}

/// The net multiplicity of every undirected edge `(a, b)`, `a < b`: the number of triangles
/// that run along it from `a` to `b` minus those that run from `b` to `a`. Zero for every edge
/// of a closed, consistently oriented mesh; the non-zero ones form the holes' boundary loops.
fn edge_balance(triangles: &[[u32; 3]]) -> HashMap<(u32, u32), i64> {
    let mut net: HashMap<(u32, u32), i64> = HashMap::with_capacity(3 * triangles.len());
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if a < b {
                *net.entry((a, b)).or_insert(0) += 1;
            } else {
                *net.entry((b, a)).or_insert(0) -= 1;
            }
        }
    }
    net.retain(|_, n| *n != 0);
    net
}

/// Every edge must be crossed as often in one direction as in the other (a closed,
/// consistently oriented surface, as the divergence theorem needs).
fn check_closed(mesh: &TriangleMesh) -> Result<(), GeometryError> {
    check_indices(mesh)?;
    let net = edge_balance(&mesh.triangles);
    match net.keys().min() {
        None => Ok(()),
        Some(&(a, b)) => Err(GeometryError::MeshNotClosed {
            path: mesh.source.clone(),
            edges: net.len(),
            example: format!(
                "{a} → {b} at {:?} → {:?}",
                mesh.vertices[a as usize].coords.as_slice(),
                mesh.vertices[b as usize].coords.as_slice()
            ),
        }),
    }
}

/// Every triangle's vertex indices must be in range ([`GeometryError::MeshIndex`]).
fn check_indices(mesh: &TriangleMesh) -> Result<(), GeometryError> {
    let n = mesh.vertices.len();
    for (triangle, t) in mesh.triangles.iter().enumerate() {
        if let Some(&index) = t.iter().find(|&&i| i as usize >= n) {
            return Err(GeometryError::MeshIndex {
                path: mesh.source.clone(),
                triangle,
                index,
                vertices: n,
            });
        }
    }
    Ok(())
}

/// Vertices closer than this fraction of the mesh's bounding-box diagonal are merged by
/// [`repair_mesh`] [-]. Exporters repeat a vertex at every seam of normals, UVs or materials
/// (Blender's OBJ: the same printed coordinates); 1e-6 of the size merges those and float
/// noise (f32 STL: 6e-8 relative) but no feature of a part: a 0.3 m link merges vertices
/// within 0.3 µm, below the 1 µm that its six-decimal OBJ file can resolve.
pub const MERGE_TOLERANCE: f64 = 1e-6;

/// Holes are closed by [`repair_mesh`] when the caps that close them cover at most this
/// fraction of the mesh's surface area [-]; larger holes are an error
/// ([`GeometryError::MeshHoles`]). Pinholes and the missing faces of a CAD export are far
/// below (the KUKA youBot's arm link 2 of Modia3D: 2.6 %, ten holes, three of them lone
/// quads); a box with one face missing (20 %) or a cup is far above. A planar hole's cap is
/// exactly the missing face; a curved hole's flat cap changes the volume by up to about its
/// area × its sag (a spherical cap of 5 % of a sphere's surface: 2.8 % of its volume).
pub const MAX_HOLE_AREA_RATIO: f64 = 0.05;

/// What [`repair_mesh`] changed in a mesh, for the warning that reports it. Volumes are of the
/// unit-density solid \[m³\].
#[derive(Clone, Debug, PartialEq)]
pub struct MeshRepair {
    /// The mesh's source (file path).
    pub path: String,
    /// Distance within which vertices were merged \[m\] ([`MERGE_TOLERANCE`] × the
    /// bounding-box diagonal).
    pub merge_distance: f64,
    /// Vertices merged into another one.
    pub merged_vertices: usize,
    /// Triangles dropped because two of their corners became one vertex (no area).
    pub dropped_triangles: usize,
    /// Holes (boundary loops) closed with a fan of triangles around the loop's centroid.
    pub holes: usize,
    /// Area of the caps that close them \[m²\].
    pub hole_area: f64,
    /// Surface area of the mesh before the holes were closed \[m²\].
    pub area: f64,
    /// The divergence-theorem sum over the file's triangles as they were, with the vertex
    /// centroid as reference point \[m³\] (an open mesh bounds no volume: this is the volume
    /// of the mesh with each hole closed by a cone from that point).
    pub volume_before: f64,
    /// The volume of the repaired, closed mesh \[m³\].
    pub volume: f64,
}

impl MeshRepair {
    /// Whether anything was repaired.
    pub fn changed(&self) -> bool {
        self.merged_vertices + self.dropped_triangles + self.holes > 0
    }

    /// `(volume − volume_before) / volume` [-].
    pub fn relative_volume_change(&self) -> f64 {
        (self.volume - self.volume_before) / self.volume
    }
}

impl std::fmt::Display for MeshRepair {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "mesh `{}` repaired for its mass properties: {} coincident vertices merged \
             (within {:.1e} m), {} degenerate triangles dropped, {} hole(s) closed \
             ({:.3e} m², {:.2} % of the surface {:.3e} m²); volume {:.6e} m³, {:+.3} % against \
             the unrepaired triangles' {:.6e} m³",
            self.path,
            self.merged_vertices,
            self.merge_distance,
            self.dropped_triangles,
            self.holes,
            self.hole_area,
            100.0 * self.hole_area / self.area,
            self.area,
            self.volume,
            100.0 * self.relative_volume_change(),
            self.volume_before,
        )
    }
}

/// A mesh for mass properties, repaired as far as it can be without guessing, and what was
/// changed: vertices closer than [`MERGE_TOLERANCE`] × the bounding-box diagonal merged (the
/// first of them kept), triangles with two corners on one vertex dropped, unused vertices
/// dropped, and each hole — a loop of edges crossed more often in one direction than in the
/// other ([`mesh_mass_properties`]) — closed by a fan of triangles from the loop's vertex
/// centroid (a new vertex) to each of its edges, oriented to cancel it. Non-manifold edges
/// where closed shells touch are left as they are (they are balanced); a triangle turned the
/// wrong way round in a closed mesh is a loop around it crossed twice, which two caps turn
/// right. The result is closed in the sense of [`mesh_mass_properties`].
///
/// Error: holes whose caps cover more than [`MAX_HOLE_AREA_RATIO`] of the surface
/// ([`GeometryError::MeshHoles`], naming the largest hole). Build time only (allocates).
pub fn repair_mesh(mesh: &TriangleMesh) -> Result<(TriangleMesh, MeshRepair), GeometryError> {
    check_indices(mesh)?;
    let o = vertex_centroid(&mesh.vertices);
    let volume_before = moments(&mesh.vertices, &mesh.triangles, &o).0;
    let (lo, hi) = mesh.vertices.iter().fold(
        (
            Vector3::repeat(f64::INFINITY),
            Vector3::repeat(f64::NEG_INFINITY),
        ),
        |(lo, hi), p| (lo.inf(&p.coords), hi.sup(&p.coords)),
    );
    let merge_distance = MERGE_TOLERANCE * (hi - lo).norm();
    // Merge: each used vertex onto the first kept one within `merge_distance` (a grid of
    // cells of that size; a match lies in one of the 27 cells around).
    let mut used = vec![false; mesh.vertices.len()];
    for &i in mesh.triangles.iter().flatten() {
        if let Some(u) = used.get_mut(i as usize) {
            *u = true;
        }
    }
    let cell = |p: &Point3<f64>| {
        p.coords
            .map(|x| (x / merge_distance.max(f64::MIN_POSITIVE)).floor() as i64)
    };
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    let mut vertices: Vec<Point3<f64>> = Vec::new();
    let mut map = vec![u32::MAX; mesh.vertices.len()];
    let mut merged_vertices = 0;
    for (i, p) in mesh.vertices.iter().enumerate() {
        if !used[i] {
            continue;
        }
        let c = cell(p);
        let mut found = None;
        'search: for d in 0..27i64 {
            let key = [c.x + d % 3 - 1, c.y + (d / 3) % 3 - 1, c.z + d / 9 - 1];
            for &k in grid.get(&key).into_iter().flatten() {
                if (vertices[k as usize] - p).norm() <= merge_distance {
                    found = Some(k);
                    break 'search;
                }
            }
        }
        map[i] = match found {
            Some(k) => {
                merged_vertices += 1;
                k
            }
            None => {
                vertices.push(*p);
                let k = (vertices.len() - 1) as u32;
                grid.entry([c.x, c.y, c.z]).or_default().push(k);
                k
            }
        };
    }
    let mut triangles: Vec<[u32; 3]> = mesh
        .triangles
        .iter()
        .map(|t| t.map(|i| map[i as usize]))
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
        .collect();
    let dropped_triangles = mesh.triangles.len() - triangles.len();
    let area: f64 = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| vertices[i as usize]);
            0.5 * (b - a).cross(&(c - a)).norm()
        })
        .sum();
    // The holes' edges, `a → b` as often as the triangles cross it more from a to b.
    let mut out: HashMap<u32, Vec<u32>> = HashMap::new();
    let mut net: Vec<((u32, u32), i64)> = edge_balance(&triangles).into_iter().collect();
    net.sort_unstable();
    for &((a, b), n) in &net {
        let (from, to) = if n > 0 { (a, b) } else { (b, a) };
        for _ in 0..n.unsigned_abs() {
            out.entry(from).or_default().push(to);
        }
    }
    // Walk the loops: every vertex has as many hole edges in as out, so a walk from a vertex
    // returns to it. A walk that comes back to a vertex it passed (two holes that touch at a
    // vertex) is split there, so each hole gets its own cap.
    let mut loops: Vec<Vec<u32>> = Vec::new();
    let mut starts: Vec<u32> = out.keys().copied().collect();
    starts.sort_unstable();
    for start in starts {
        while out.get(&start).is_some_and(|v| !v.is_empty()) {
            let mut path = vec![start];
            let mut at = start;
            loop {
                let Some(next) = out.get_mut(&at).and_then(Vec::pop) else {
                    // Unbalanced (cannot happen for edges of triangles): report as not closed.
                    return Err(GeometryError::MeshNotClosed {
                        path: mesh.source.clone(),
                        edges: net.len(),
                        example: format!("the hole through vertex {at}"),
                    });
                };
                match path.iter().position(|&v| v == next) {
                    Some(k) => {
                        loops.push(path.split_off(k));
                        if k == 0 {
                            break;
                        }
                        path.push(next);
                    }
                    None => path.push(next),
                }
                at = next;
            }
        }
    }
    let mut hole_area = 0.0;
    let mut largest = (0.0, 0usize, Vector3::zeros());
    for lp in &loops {
        let c = Point3::from(
            lp.iter()
                .fold(Vector3::zeros(), |s, &i| s + vertices[i as usize].coords)
                / lp.len() as f64,
        );
        vertices.push(c);
        let ci = (vertices.len() - 1) as u32;
        let mut cap = 0.0;
        for (k, &a) in lp.iter().enumerate() {
            let b = lp[(k + 1) % lp.len()];
            triangles.push([ci, b, a]);
            cap += 0.5
                * (vertices[b as usize] - c)
                    .cross(&(vertices[a as usize] - c))
                    .norm();
        }
        hole_area += cap;
        if cap > largest.0 {
            largest = (cap, lp.len(), c.coords);
        }
    }
    if hole_area > MAX_HOLE_AREA_RATIO * area {
        return Err(GeometryError::MeshHoles {
            path: mesh.source.clone(),
            holes: u32::try_from(loops.len()).unwrap_or(u32::MAX),
            hole_area,
            area,
            largest_area: largest.0,
            largest_edges: u32::try_from(largest.1).unwrap_or(u32::MAX),
            largest_centre: Box::new([largest.2.x, largest.2.y, largest.2.z]),
            closable: MAX_HOLE_AREA_RATIO,
        });
    }
    let repaired = TriangleMesh {
        vertices,
        triangles,
        source: mesh.source.clone(),
    };
    let volume = moments(&repaired.vertices, &repaired.triangles, &o).0;
    Ok((
        repaired,
        MeshRepair {
            path: mesh.source.clone(),
            merge_distance,
            merged_vertices,
            dropped_triangles,
            holes: loops.len(),
            hole_area,
            area,
            volume_before,
            volume,
        },
    ))
}

/// The convex pieces of a mesh for collision, as point sets (each is a
/// [`Shape::ConvexHull`](super::Shape::ConvexHull)'s points): the hull of all vertices
/// (`MeshCollision::ConvexHull`), or the exact hulls of the parts of parry's V-HACD decomposition (voxel resolution 64, its
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

    /// A unit cube as an exporter writes it: each face a 10 × 10 grid of quads with its own
    /// vertices (the edges' vertices repeated on both faces, the corners' on three, each copy
    /// off by up to 1e-9 m of float noise), with one triangle missing (a hole of 1/1200 of the
    /// surface). The repair merges the copies, closes the hole, and the mass properties are the
    /// cube's closed form: the hole is planar, so its cap is exactly the missing triangle; only
    /// the noise (1e-9 m on a 1 m cube) remains, hence 1e-8.
    #[test]
    fn repair_merges_seams_and_closes_a_pinhole() {
        let n = 10;
        let (mut vertices, mut triangles) = (Vec::new(), Vec::new());
        let mut noise = 0u32;
        for axis in 0..3 {
            for side in [0.0, 1.0] {
                let base = vertices.len() as u32;
                for i in 0..=n {
                    for j in 0..=n {
                        noise = noise.wrapping_mul(1_103_515_245).wrapping_add(12345);
                        let e = 1e-9 * (f64::from(noise >> 16) / 65536.0 - 0.5);
                        let mut p = Vector3::zeros();
                        p[axis] = side;
                        p[(axis + 1) % 3] = f64::from(i) / f64::from(n) + e;
                        p[(axis + 2) % 3] = f64::from(j) / f64::from(n) - e;
                        vertices.push(Point3::from(p));
                    }
                }
                let at = |i: u32, j: u32| base + i * (n + 1) + j;
                for i in 0..n {
                    for j in 0..n {
                        let q = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
                        // Counter-clockwise seen from outside: (u, v, axis) is right-handed,
                        // so the face at side 1 runs u → v, the one at side 0 the other way.
                        let t = if side > 0.5 {
                            [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
                        } else {
                            [[q[0], q[2], q[1]], [q[0], q[3], q[2]]]
                        };
                        triangles.extend(t);
                    }
                }
            }
        }
        triangles.remove(357);
        let mesh = TriangleMesh {
            vertices,
            triangles,
            source: "cube.obj".into(),
        };
        assert!(mesh_mass_properties(&mesh).is_err());
        let (repaired, repair) = repair_mesh(&mesh).unwrap();
        // 6·121 vertices, 8 corners and 12·9 edge vertices of the cube: 726 − 602 merged.
        assert_eq!(repair.merged_vertices, 6 * 121 - (8 + 12 * 9 + 6 * 81));
        assert_eq!((repair.holes, repair.dropped_triangles), (1, 0));
        assert!((repair.hole_area - 0.005).abs() < 1e-9, "{repair}");
        assert!((repair.area - 5.995).abs() < 1e-8, "{repair}");
        let p = mesh_mass_properties(&repaired).unwrap();
        assert!((p.volume - 1.0).abs() < 1e-8, "{}", p.volume);
        assert!((p.com - Vector3::repeat(0.5)).norm() < 1e-8);
        assert!((p.inertia - Matrix3::identity() / 6.0).norm() < 1e-8);
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
