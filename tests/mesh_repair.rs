//! Issue 44, point 4: real meshes load. Modia3D's own KUKA youBot arm links
//! (`tests/data/meshes/`, Blender exports with repeated vertices, pinholes and open holes) are
//! repaired for their mass properties with a warning that says what was repaired; a mesh with
//! a large hole is still rejected, with the reason.

use modia3d::core::geometry::{repair_mesh, GeometryError, MeshRepair, Shape, TriangleMesh};
use modia3d::demo::world;
use modia3d::prelude::*;
use nalgebra::{Matrix3, Point3};
use std::collections::HashMap;
use std::path::PathBuf;

fn mesh_path(name: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/meshes")).join(name)
}

/// The mesh file `path` as a shape, unloaded.
fn file_mesh(path: PathBuf) -> Shape {
    Shape::FileMesh {
        path,
        scale: Vector3::repeat(1.0),
        collision: MeshCollision::ConvexHull,
    }
}

/// A world and one steel solid `link` of the mesh file `path`, swinging on a revolute joint
/// about the world's x axis.
fn link_scene(path: PathBuf) -> SceneDesc {
    shape_scene(file_mesh(path))
}

/// [`link_scene`] with the solid's shape `shape`.
fn shape_scene(shape: Shape) -> SceneDesc {
    let mut s = SceneDesc::new();
    s.add(world(SceneOptions::default()))
        .add(Object3D::new("link").solid(Solid::new(shape).material("Steel")))
        .add_joint(Joint::new("rev", "world", "link", JointKind::revolute(1)));
    s
}

/// The mesh file `path` read and repaired as `build()` does for a solid.
fn repaired(path: PathBuf) -> (TriangleMesh, MeshRepair) {
    let shape = file_mesh(path).load().unwrap();
    let Shape::Mesh { mesh, .. } = shape else {
        panic!("{shape:?}")
    };
    repair_mesh(&mesh).unwrap()
}

/// Volume [m³], centre of mass [m] and unit-density inertia about it [m⁵] of the closed
/// triangle mesh, by Eberly's "Polyhedral Mass Properties (Revisited)" (2002): the divergence
/// theorem with the fields (x,0,0), (x²,0,0), (x³,0,0), (x²y,0,0)… integrated over each
/// triangle in closed form from its normal and three subexpressions per axis. An independent
/// route from the library's (a sum of signed tetrahedra from the vertex centroid with their
/// covariance matrices): it shares no code and no formula with it. Coordinates are taken
/// relative to the bounding-box centre to keep the cubic terms small.
fn eberly(vertices: &[Point3<f64>], triangles: &[[u32; 3]]) -> (f64, Vector3<f64>, Matrix3<f64>) {
    let (lo, hi) = vertices.iter().fold(
        (Vector3::repeat(f64::MAX), Vector3::repeat(f64::MIN)),
        |(lo, hi), p| (lo.inf(&p.coords), hi.sup(&p.coords)),
    );
    let shift = (lo + hi) / 2.0;
    let sub = |w0: f64, w1: f64, w2: f64| {
        let t0 = w0 + w1;
        let f1 = t0 + w2;
        let t1 = w0 * w0;
        let t2 = t1 + w1 * t0;
        let f2 = t2 + w2 * f1;
        let f3 = w0 * t1 + w1 * t2 + w2 * f2;
        let g0 = f2 + w0 * (f1 + w0);
        let g1 = f2 + w1 * (f1 + w1);
        let g2 = f2 + w2 * (f1 + w2);
        (f1, f2, f3, g0, g1, g2)
    };
    let mut i = [0.0f64; 10];
    for t in triangles {
        let [p0, p1, p2] = t.map(|k| vertices[k as usize].coords - shift);
        let d = (p1 - p0).cross(&(p2 - p0));
        let (f1x, f2x, f3x, g0x, g1x, g2x) = sub(p0.x, p1.x, p2.x);
        let (_, f2y, f3y, g0y, g1y, g2y) = sub(p0.y, p1.y, p2.y);
        let (_, f2z, f3z, g0z, g1z, g2z) = sub(p0.z, p1.z, p2.z);
        i[0] += d.x * f1x;
        i[1] += d.x * f2x;
        i[2] += d.y * f2y;
        i[3] += d.z * f2z;
        i[4] += d.x * f3x;
        i[5] += d.y * f3y;
        i[6] += d.z * f3z;
        i[7] += d.x * (p0.y * g0x + p1.y * g1x + p2.y * g2x);
        i[8] += d.y * (p0.z * g0y + p1.z * g1y + p2.z * g2y);
        i[9] += d.z * (p0.x * g0z + p1.x * g1z + p2.x * g2z);
    }
    let mult = [
        1.0 / 6.0,
        1.0 / 24.0,
        1.0 / 24.0,
        1.0 / 24.0,
        1.0 / 60.0,
        1.0 / 60.0,
        1.0 / 60.0,
        1.0 / 120.0,
        1.0 / 120.0,
        1.0 / 120.0,
    ];
    for (x, m) in i.iter_mut().zip(mult) {
        *x *= m;
    }
    let v = i[0];
    let c = Vector3::new(i[1], i[2], i[3]) / v;
    let ixx = i[5] + i[6] - v * (c.y * c.y + c.z * c.z);
    let iyy = i[4] + i[6] - v * (c.z * c.z + c.x * c.x);
    let izz = i[4] + i[5] - v * (c.x * c.x + c.y * c.y);
    let ixy = -(i[7] - v * c.x * c.y);
    let iyz = -(i[8] - v * c.y * c.z);
    let ixz = -(i[9] - v * c.z * c.x);
    let inertia = Matrix3::new(ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz);
    (v, c + shift, inertia)
}

/// The faces of an OBJ file as triangles of positions (quads and polygons as fans), read here
/// independently of the library's parser.
fn obj_triangles(text: &str) -> Vec<[[f64; 3]; 3]> {
    let mut v: Vec<[f64; 3]> = vec![];
    let mut out = vec![];
    for line in text.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.first() {
            Some(&"v") => v.push([1, 2, 3].map(|k| w[k].parse().unwrap())),
            Some(&"f") => {
                let idx: Vec<usize> = w[1..]
                    .iter()
                    .map(|x| x.split('/').next().unwrap().parse::<usize>().unwrap() - 1)
                    .collect();
                for k in 1..idx.len() - 1 {
                    out.push([v[idx[0]], v[idx[k]], v[idx[k + 1]]]);
                }
            }
            _ => {}
        }
    }
    out
}

/// A triangle of positions as a key that does not depend on which corner comes first.
fn key(t: [[f64; 3]; 3]) -> [[u64; 3]; 3] {
    let b = t.map(|p| p.map(f64::to_bits));
    let k = (0..3).min_by_key(|&k| b[k]).unwrap();
    [b[k], b[(k + 1) % 3], b[(k + 2) % 3]]
}

/// Checks, independently of the library, that `mesh` (the repaired mesh of a solid) is the
/// file's triangles — each with three distinct corners — plus caps: every such triangle of the
/// file is in it with the same orientation, and every other triangle has a corner that is not
/// a vertex of the file (the caps' fan centres); and that it is closed: every edge is crossed
/// as often in one direction as in the other.
fn check_repaired_mesh(file: &str, mesh: &TriangleMesh, repair: &MeshRepair) {
    let text = std::fs::read_to_string(mesh_path(file)).unwrap();
    let file_tris: Vec<_> = obj_triangles(&text)
        .into_iter()
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
        .collect();
    let file_points: std::collections::HashSet<[u64; 3]> = file_tris
        .iter()
        .flatten()
        .map(|p| p.map(f64::to_bits))
        .collect();
    let mut repaired: HashMap<[[u64; 3]; 3], usize> = HashMap::new();
    let mut caps = 0;
    for t in &mesh.triangles {
        let pos = t.map(|k| {
            let p = mesh.vertices[k as usize];
            [p.x, p.y, p.z]
        });
        if pos
            .iter()
            .all(|p| file_points.contains(&p.map(f64::to_bits)))
        {
            *repaired.entry(key(pos)).or_default() += 1;
        } else {
            caps += 1;
        }
    }
    for t in &file_tris {
        let n = repaired.get_mut(&key(*t));
        let n = n.unwrap_or_else(|| panic!("{file}: triangle {t:?} of the file was lost"));
        assert!(*n > 0, "{file}: triangle {t:?} of the file was lost");
        *n -= 1;
    }
    assert!(
        repaired.values().all(|&n| n == 0),
        "{file}: triangles that are neither the file's nor caps"
    );
    assert_eq!(
        mesh.triangles.len(),
        file_tris.len() + caps,
        "{file}: repaired triangles"
    );
    assert_eq!(
        file_tris.len() + repair.dropped_triangles,
        obj_triangles(&text).len()
    );
    assert!(caps >= 3 * repair.holes, "{file}: {caps} cap triangles");
    let mut net: HashMap<(u32, u32), i64> = HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *net.entry((a.min(b), a.max(b))).or_default() += if a < b { 1 } else { -1 };
        }
    }
    assert!(
        net.values().all(|&n| n == 0),
        "{file}: the repaired mesh is not closed"
    );
}

/// Both reference meshes (rejected as "not closed" before) build, with the warning that says
/// what was repaired, and their mass properties are those of the closed solid the repaired
/// mesh bounds: the library's mass, centre of mass and inertia (steel, from the density) agree
/// with [`eberly`] over the repaired mesh to 1e-9 relative (the issue asks 1e-3). Both are exact
/// integrals of the same polyhedron, so only rounding separates them: ~10⁴ triangles of terms
/// ~1e-16 relative each, with cancellation between shells (the links are up to five closed
/// shells) of at most a factor 100 → below 1e-11; 1e-9 leaves margin and still catches any
/// wrong term (a wrong sign or factor in one moment is an O(1) error).
#[test]
fn reference_meshes_load_with_closed_solid_mass_properties() {
    let density = modia3d::core::scene::builtin_solid_material("Steel")
        .unwrap()
        .density;
    // file, holes closed, vertices merged (the repeated positions of arm_joint_1 counted by
    // tests/data/meshes/README.md).
    for (file, holes, merged) in [("arm_joint_1.obj", 2, 66), ("arm_joint_2.obj", 10, 0)] {
        // What the scene's solid weighs: built from the file (it failed before).
        let model = link_scene(mesh_path(file))
            .build()
            .unwrap_or_else(|e| panic!("{file}: {e}"));
        let mass = model.bodies()[0].mass;
        let (mesh, repair) = repaired(mesh_path(file));
        println!("{file}: {repair}");
        assert_eq!(repair.holes, holes, "{file}");
        assert_eq!(repair.merged_vertices, merged, "{file}");
        assert!(
            repair.relative_volume_change().abs() < 0.05,
            "{file}: {repair}"
        );
        check_repaired_mesh(file, &mesh, &repair);
        let p = Shape::Mesh {
            mesh: std::sync::Arc::new(mesh.clone()),
            collision: MeshCollision::ConvexHull,
        }
        .unit_mass_properties()
        .unwrap();
        let (v, com, inertia) = eberly(&mesh.vertices, &mesh.triangles);
        println!(
            "{file}: mass {mass:.9} kg (Eberly {:.9}), com {:?} m (Eberly {:?}), inertia diag {:?} kg·m² (Eberly {:?})",
            density * v,
            p.com.as_slice(),
            com.as_slice(),
            (p.inertia * density).diagonal().as_slice(),
            (inertia * density).diagonal().as_slice()
        );
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
        assert!(rel(mass, density * v) < 1e-9, "{file}: mass");
        assert!(rel(p.volume, v) < 1e-9, "{file}: volume");
        // The centre of mass relative to the link's size (its distance from the origin can be
        // small).
        let size = mesh
            .vertices
            .iter()
            .map(|p| p.coords.norm())
            .fold(0.0, f64::max);
        assert!((p.com - com).norm() < 1e-9 * size, "{file}: com");
        assert!(
            (p.inertia - inertia).norm() < 1e-9 * inertia.norm(),
            "{file}: inertia"
        );
        // Plausible: a steel link of a few kg (Modia3D gives these links 1.39 and 1.32 kg of
        // aluminium and plastic: steel is ~3-5× as dense).
        assert!(mass > 1.0 && mass < 10.0, "{file}: {mass} kg");
    }
}

/// The repair reaches the user as a typed warning of every run of the model (printed to
/// standard error unless quiet): `SimWarning::MeshRepaired`, naming the solid and the file,
/// with the volume change.
#[test]
fn a_run_warns_about_the_repaired_mesh() {
    let model = link_scene(mesh_path("arm_joint_2.obj")).build().unwrap();
    let res = model
        .simulate(&SimOptions::new(0.01).progress(false).quiet(true))
        .unwrap();
    let w = res
        .warnings
        .iter()
        .find_map(|w| match w {
            SimWarning::MeshRepaired { object, repair } => Some((w, object, repair)),
            _ => None,
        })
        .unwrap_or_else(|| panic!("{:?}", res.warnings));
    let text = w.0.to_string();
    println!("{text}\n{}", w.0.headline());
    assert_eq!(w.1, "link");
    assert_eq!(w.2.holes, 10);
    assert!(
        text.contains("arm_joint_2.obj")
            && text.contains("10 hole(s) closed")
            && text.contains("volume"),
        "{text}"
    );
}

/// The unit cube as an OBJ text of quads (corner `k` at the bits of `k`: x, y, z), without
/// the face `missing` (`(axis, side)`, side 0 or 1). Each face runs counter-clockwise seen
/// from outside: `(u, v, axis)` with `u`, `v` the next axes cyclically is right-handed, so the
/// face at side 1 runs u → v and the face at side 0 the other way.
fn cube_obj(missing: Option<(usize, usize)>) -> String {
    let mut s: String = (0..8)
        .map(|k| format!("v {} {} {}\n", k & 1, (k >> 1) & 1, (k >> 2) & 1))
        .collect();
    for axis in 0..3 {
        for side in 0..2 {
            if missing == Some((axis, side)) {
                continue;
            }
            let corner = |u: usize, v: usize| {
                1 + (side << axis) + (u << ((axis + 1) % 3)) + (v << ((axis + 2) % 3))
            };
            let mut q = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
            if side == 0 {
                q.reverse();
            }
            s.push_str(&format!("f {} {} {} {}\n", q[0], q[1], q[2], q[3]));
        }
    }
    s
}

/// A box with one face missing (a hole of 1 m², a fifth of the remaining surface) is not
/// guessed at: `build()` fails with `GeometryError::MeshHoles`, naming the object, the file,
/// the hole's size and place, and what to do. (Small holes closed: the reference meshes
/// above.)
#[test]
fn a_mesh_with_a_large_hole_is_rejected_with_the_reason() {
    let dir = std::env::temp_dir().join(format!("modia3d-mesh-repair-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("open_box.obj");
    // The top face z = 1 missing.
    std::fs::write(&path, cube_obj(Some((2, 1)))).unwrap();
    let errs = link_scene(path.clone()).build().unwrap_err();
    let text = errs.to_string();
    println!("{text}");
    let e = errs
        .0
        .iter()
        .find_map(|e| match e {
            SceneError::Mesh { object, error } => Some((object, error)),
            _ => None,
        })
        .unwrap_or_else(|| panic!("{text}"));
    assert_eq!(e.0, "link");
    match e.1 {
        GeometryError::MeshHoles {
            holes,
            hole_area,
            area,
            largest_edges,
            largest_centre,
            ..
        } => {
            assert_eq!(*holes, 1);
            // The cap of the square hole: 1 m² of the 5 m² left.
            assert!((hole_area - 1.0).abs() < 1e-12 && (area - 5.0).abs() < 1e-12);
            assert_eq!(*largest_edges, 4);
            assert_eq!(**largest_centre, [0.5, 0.5, 1.0]);
        }
        other => panic!("{other:?}"),
    }
    for part in [
        "object `link`",
        "open_box.obj",
        "1 hole(s)",
        "20.0 % of its surface",
        "Face > Fill",
        "MassSpec::Explicit",
    ] {
        assert!(text.contains(part), "{part}: {text}");
    }
    // The same mesh given as a loaded `Shape::Mesh` is checked the same way.
    let loaded = file_mesh(path.clone()).load().unwrap();
    let errs = shape_scene(loaded).build().unwrap_err();
    assert!(
        matches!(
            &errs.0[..],
            [SceneError::Mesh {
                error: GeometryError::MeshHoles { holes: 1, .. },
                ..
            }]
        ),
        "{errs:?}"
    );
    // The closed box builds, and needs no repair.
    std::fs::write(&path, cube_obj(None)).unwrap();
    link_scene(path.clone()).build().unwrap();
    assert!(!repaired(path).1.changed());
    std::fs::remove_dir_all(&dir).ok();
}
