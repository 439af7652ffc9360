//! The Beam and FileMesh shapes (issue 13): mass properties against closed forms and an
//! independent integration, support maps against parry, and bodies of these shapes resting on
//! a table (the contact forces carry the weight).

use modia3d::core::geometry::{CollisionShape, Shape};
use modia3d::demo::{wooden_table, world};
use modia3d::prelude::*;
use nalgebra::{Matrix3, Point3};
use std::f64::consts::PI;

const G: f64 = 9.81;

/// Volume and second moments `∫ x xᵀ dV` about the origin of the solid bounded by the closed,
/// outward triangle mesh `tris` (divergence theorem: a sum of signed tetrahedra with the
/// origin). Written here independently of the library's mesh integrator.
fn tet_moments(tris: &[[Point3<f64>; 3]]) -> (f64, Matrix3<f64>) {
    let (mut v, mut c) = (0.0, Matrix3::zeros());
    for [a, b, d] in tris {
        let (a, b, d) = (a.coords, b.coords, d.coords);
        let vol = a.dot(&b.cross(&d)) / 6.0;
        let s = a + b + d;
        v += vol;
        c += (a * a.transpose() + b * b.transpose() + d * d.transpose() + s * s.transpose())
            * (vol / 20.0);
    }
    (v, c)
}

/// The outward triangles of a prism: the convex polygon `poly` (counter-clockwise in the
/// (u, w) plane) extruded over `−t/2 ≤ s ≤ t/2`, with coordinates placed as (u, w, s) → x, y, z.
fn prism(poly: &[(f64, f64)], t: f64) -> Vec<[Point3<f64>; 3]> {
    let p = |(u, w): (f64, f64), s: f64| Point3::new(u, w, s);
    let h = t / 2.0;
    let n = poly.len();
    let mut out = vec![];
    for i in 1..n - 1 {
        out.push([p(poly[0], h), p(poly[i], h), p(poly[i + 1], h)]);
        out.push([p(poly[0], -h), p(poly[i + 1], -h), p(poly[i], -h)]);
    }
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        out.push([p(a, -h), p(b, -h), p(b, h)]);
        out.push([p(a, -h), p(b, h), p(a, h)]);
    }
    out
}

/// A stadium (straight part `l`, radius `r`) as a polygon with `n` chords per half-disk:
/// vertices on the circle (`scale = 1`, inscribed) or on the circle of radius `r / cos(π/2n)`
/// (`scale = 1/cos`, its chords tangent to the circle: circumscribed).
fn stadium(l: f64, r: f64, n: usize, circumscribed: bool) -> Vec<(f64, f64)> {
    let rr = if circumscribed {
        r / (PI / (2.0 * n as f64)).cos()
    } else {
        r
    };
    let mut poly = vec![];
    for (sign, c) in [(1.0, l / 2.0), (-1.0, -l / 2.0)] {
        // Inscribed: vertices at φ = −π/2 + kπ/n. Circumscribed: the half-angle offset puts the
        // tangent chords' corners at φ = −π/2 + (k + ½)π/n, plus the two tangent points at ±π/2.
        let angles: Vec<f64> = if circumscribed {
            std::iter::once(-PI / 2.0)
                .chain((0..n).map(|k| -PI / 2.0 + (k as f64 + 0.5) * PI / n as f64))
                .chain(std::iter::once(PI / 2.0))
                .collect()
        } else {
            (0..=n)
                .map(|k| -PI / 2.0 + k as f64 * PI / n as f64)
                .collect()
        };
        for phi in angles {
            // The ±π/2 points of a circumscribed end lie on the circle (tangent points).
            let rad = if circumscribed && (phi.abs() - PI / 2.0).abs() < 1e-15 {
                r
            } else {
                rr
            };
            poly.push((c + sign * rad * phi.cos(), sign * rad * phi.sin()));
        }
    }
    poly
}

/// Beam mass properties: (1) the second moments of the exact beam lie between those of an
/// inscribed and a circumscribed polygonal beam (set inclusion: `∫x_i² dV` and `V` grow with
/// the set), integrated by the divergence theorem; the bracket is 2e-6 wide with 4096 chords,
/// so an error of the closed form's `l·4r/(3π)` shift term (1e-1 relative) or of a factor in
/// any term would show. (2) The closed form in its own expression (`V = lwt + πr²t`, `I` from
/// the second moments) to 1e-12, for each axis (the directions cyclic as in Modia3D).
#[test]
fn beam_mass_properties_closed_form_and_bracketed_by_polygons() {
    let (l, w, t) = (0.7, 0.3, 0.11);
    let r = w / 2.0;
    let beam = Shape::Beam {
        axis: Axis::X,
        length: l,
        width: w,
        thickness: t,
    };
    let p = beam.unit_mass_properties().unwrap();
    let n = 4096;
    let (v_in, c_in) = tet_moments(&prism(&stadium(l, r, n, false), t));
    let (v_out, c_out) = tet_moments(&prism(&stadium(l, r, n, true), t));
    // Second moments of the beam from its inertia: S = tr(I)/2 − I on the diagonal.
    let tr = p.inertia.trace() / 2.0;
    let s = [
        tr - p.inertia[(0, 0)],
        tr - p.inertia[(1, 1)],
        tr - p.inertia[(2, 2)],
    ];
    println!("V: {} <= {} <= {}", v_in, p.volume, v_out);
    assert!(v_in <= p.volume && p.volume <= v_out);
    assert!((v_out - v_in) / p.volume < 5e-6);
    for i in 0..3 {
        println!("S{i}: {} <= {} <= {}", c_in[(i, i)], s[i], c_out[(i, i)]);
        assert!(c_in[(i, i)] <= s[i] * (1.0 + 1e-14) && s[i] <= c_out[(i, i)] * (1.0 + 1e-14));
        assert!((c_out[(i, i)] - c_in[(i, i)]) / s[i] < 5e-6);
    }
    // Closed form, written out once more: box + full cylinder volume; second moments per part.
    let vol = l * w * t + PI * r * r * t;
    let s_u = l * w * t * l * l / 12.0
        + PI * r * r * t * (l * l / 4.0 + r * r / 4.0)
        + 4.0 / 3.0 * l * r.powi(3) * t;
    let s_w = l * w * t * w * w / 12.0 + PI * r * r * t * r * r / 4.0;
    let s_t = vol * t * t / 12.0;
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs();
    assert!(close(p.volume, vol));
    for (axis, [iu, iw, it]) in [
        (Axis::X, [0, 1, 2]),
        (Axis::Y, [1, 2, 0]),
        (Axis::Z, [2, 0, 1]),
    ] {
        let q = Shape::Beam {
            axis,
            length: l,
            width: w,
            thickness: t,
        }
        .unit_mass_properties()
        .unwrap();
        assert!(close(q.inertia[(iu, iu)], s_w + s_t), "{axis:?}");
        assert!(close(q.inertia[(iw, iw)], s_u + s_t), "{axis:?}");
        assert!(close(q.inertia[(it, it)], s_u + s_w), "{axis:?}");
    }
}

/// The beam's support map (with and without smoothing) against parry: the support function
/// `h(d) = max d·x` of parry's `RoundConvexPolyhedron` over points sampled on the core's
/// stadium ends (inscribed, `n` chords per end) and rounded by the smoothing radius. Inscribed
/// polygons give `h_parry ≤ h ≤ h_parry + ρ(1 − cos(π/2n))` with `ρ` the core's end radius;
/// checked over 2000 directions.
#[test]
fn beam_support_map_matches_parry() {
    use parry3d_f64::shape::{RoundConvexPolyhedron, SupportMap};
    let (l, w, t) = (0.5, 0.2, 0.08);
    for (axis, smoothing) in [(Axis::X, 0.0), (Axis::Y, 0.004), (Axis::Z, 0.01)] {
        let shape = Shape::Beam {
            axis,
            length: l,
            width: w,
            thickness: t,
        };
        let cs = CollisionShape::with_smoothing(&shape, smoothing).unwrap();
        let rs = cs.smoothing_radius();
        assert_eq!(rs, smoothing.min(0.1 * t));
        let (k, (kw, kt)) = (axis.index(), axis.beam_directions());
        let rho = w / 2.0 - rs;
        let n = 256;
        let mut pts = vec![];
        for (u, w) in stadium(l, rho, n, false) {
            for s in [-1.0, 1.0] {
                let mut p = Point3::origin();
                p[k] = u;
                p[kw] = w;
                p[kt] = s * (t / 2.0 - rs);
                pts.push(p);
            }
        }
        let parry = RoundConvexPolyhedron {
            inner_shape: parry3d_f64::shape::ConvexPolyhedron::from_convex_hull(&pts).unwrap(),
            border_radius: rs,
        };
        let sag = rho * (1.0 - (PI / (2.0 * n as f64)).cos());
        let mut worst: f64 = 0.0;
        for i in 0..2000 {
            // Fibonacci sphere directions.
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / 2000.0;
            let phi = i as f64 * PI * (3.0 - 5f64.sqrt());
            let d = Vector3::new(
                (1.0 - z * z).sqrt() * phi.cos(),
                (1.0 - z * z).sqrt() * phi.sin(),
                z,
            );
            let h = d.dot(&cs.support(&d).coords);
            let hp = d.dot(&parry.local_support_point(&d).coords);
            assert!(
                h >= hp - 1e-12 && h <= hp + sag + 1e-12,
                "{axis:?}: h = {h}, parry {hp}, sagitta {sag}"
            );
            worst = worst.max(h - hp);
        }
        println!("{axis:?}, r_s = {rs}: max h − h_parry = {worst:.3e} (sagitta {sag:.3e})");
    }
}

/// A scene with a table (top face at z = 0) and one free body `body` of `solid` at `r`.
fn on_table(solid: Solid, r: [f64; 3]) -> SceneDesc {
    let mut s = wooden_table(1e-3);
    s.add(Object3D::new("body").solid(solid.material("DryWood").collision(true)))
        .add_joint(Joint::new(
            "body.free",
            "world",
            "body",
            JointKind::FreeMotion {
                r: Vector3::from(r),
                rot: FreeRotation::Cardan([0.0; 3]),
                v: Vector3::zeros(),
                w: Vector3::zeros(),
            },
        ));
    s
}

/// Runs `scene` for `t_end` s with contact results and returns the weight of the body [N] and
/// the vertical contact force on it summed over `pairs` (`"table|…"` names) at the end [N].
fn settle(scene: SceneDesc, t_end: f64) -> (SimulationResult, f64) {
    let model = scene.build().unwrap();
    let mass: f64 = model.bodies().iter().map(|b| b.mass).sum();
    let opts = SimOptions::new(t_end)
        .tolerance(1e-8)
        .interval(1e-2)
        .contact_results(true)
        .progress(false);
    let res = model.simulate(&opts).unwrap();
    (res, mass * G)
}

/// The vertical force of pair `pair` on its second object at the last output point [N].
fn vertical_force(res: &SimulationResult, pair: &str) -> f64 {
    let f_n = res.signal(&format!("{pair}.f_n")).unwrap().last().unwrap()[0];
    let n = res.signal(&format!("{pair}.normal")).unwrap();
    f_n * n.last().unwrap()[2]
}

/// A beam lying on its flat face comes to rest; the normal force carries its weight to 1e-6
/// (the residual acceleration after 1 s of damped settling at rtol 1e-8 is far below that).
#[test]
fn beam_rests_on_table_and_contact_carries_its_weight() {
    let (l, w, t) = (0.3, 0.1, 0.04);
    let beam = Shape::Beam {
        axis: Axis::X,
        length: l,
        width: w,
        thickness: t,
    };
    let (res, weight) = settle(on_table(Solid::new(beam), [0.0, 0.0, t / 2.0 + 1e-4]), 1.0);
    let f = vertical_force(&res, "table|body");
    let z = res.signal("body.r_abs[2]").unwrap().last().unwrap()[0];
    println!("weight {weight} N, contact {f} N, z = {z} m");
    assert!((f - weight).abs() < 1e-6 * weight, "{f} vs {weight}");
    // It rests on its flat face (thickness along z): centre t/2 above the table, less the
    // micrometre penetration.
    assert!((z - t / 2.0).abs() < 1e-5, "z = {z}");
}

// ---------------------------------------------------------------- meshes from files

/// Thickness of the L-block [m] (a binary fraction: every coordinate is exact in f32).
const L_H: f64 = 0.0625;

/// The L-shaped block: box 1 `[0, 0.5] × [0, 0.125]`, box 2 `[0, 0.125] × [0.125, 0.375]`,
/// both `0 ≤ z ≤ L_H`: the L profile counter-clockwise in the x-y plane, extruded along z.
const L_PROFILE: [(f64, f64); 6] = [
    (0.0, 0.0),
    (0.5, 0.0),
    (0.5, 0.125),
    (0.125, 0.125),
    (0.125, 0.375),
    (0.0, 0.375),
];

/// The L-block's outward triangles: top and bottom as fans from the reflex corner (index 3,
/// which sees the whole profile), two per side face.
fn l_block_triangles() -> Vec<[[f64; 3]; 3]> {
    let p = |i: usize, z: f64| [L_PROFILE[i].0, L_PROFILE[i].1, z];
    let mut tris = vec![];
    for (a, b) in [(4, 5), (5, 0), (0, 1), (1, 2)] {
        tris.push([p(3, L_H), p(a, L_H), p(b, L_H)]);
        tris.push([p(3, 0.0), p(b, 0.0), p(a, 0.0)]);
    }
    for i in 0..6 {
        let j = (i + 1) % 6;
        tris.push([p(i, 0.0), p(j, 0.0), p(j, L_H)]);
        tris.push([p(i, 0.0), p(j, L_H), p(i, L_H)]);
    }
    tris
}

fn ascii_stl(tris: &[[[f64; 3]; 3]]) -> String {
    let mut s = String::from("solid l_block\n");
    for t in tris {
        s.push_str("  facet normal 0 0 0\n    outer loop\n");
        for v in t {
            s.push_str(&format!("      vertex {} {} {}\n", v[0], v[1], v[2]));
        }
        s.push_str("    endloop\n  endfacet\n");
    }
    s.push_str("endsolid l_block\n");
    s
}

fn binary_stl(tris: &[[[f64; 3]; 3]]) -> Vec<u8> {
    let mut b = vec![0u8; 80];
    b.extend((tris.len() as u32).to_le_bytes());
    for t in tris {
        b.extend([0f32; 3].iter().flat_map(|x| x.to_le_bytes()));
        for v in t {
            b.extend(v.iter().flat_map(|x| (*x as f32).to_le_bytes()));
        }
        b.extend(0u16.to_le_bytes());
    }
    b
}

fn obj(tris: &[[[f64; 3]; 3]]) -> String {
    // Unshared vertices would leave the mesh open: index the corners.
    let mut verts: Vec<[f64; 3]> = vec![];
    let mut faces = String::new();
    for t in tris {
        faces.push('f');
        for v in t {
            let i = verts.iter().position(|w| w == v).unwrap_or_else(|| {
                verts.push(*v);
                verts.len() - 1
            });
            faces.push_str(&format!(" {}/1/1", i + 1));
        }
        faces.push('\n');
    }
    let mut s = String::from("# L-block\no block\n");
    for v in &verts {
        s.push_str(&format!("v {} {} {}\n", v[0], v[1], v[2]));
    }
    s + "vn 0 0 1\nvt 0 0\n" + &faces
}

/// A fresh directory for this test's files.
fn scratch(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("modia3d-shapes-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The L-block's exact mass properties with coordinates scaled by `s`: the two boxes' volumes,
/// centres and central inertias, shifted to the common centre (parallel axes, with products).
fn l_block_exact(s: Vector3<f64>) -> (f64, Vector3<f64>, Matrix3<f64>) {
    let boxes = [
        (
            Vector3::new(0.5, 0.125, L_H),
            Vector3::new(0.25, 0.0625, L_H / 2.0),
        ),
        (
            Vector3::new(0.125, 0.25, L_H),
            Vector3::new(0.0625, 0.25, L_H / 2.0),
        ),
    ];
    let boxes = boxes.map(|(l, c)| (l.component_mul(&s), c.component_mul(&s)));
    let vol: f64 = boxes.iter().map(|(l, _)| l.x * l.y * l.z).sum();
    let com = boxes
        .iter()
        .map(|(l, c)| c * (l.x * l.y * l.z))
        .sum::<Vector3<f64>>()
        / vol;
    let mut inertia = Matrix3::zeros();
    for (l, c) in boxes {
        let v = l.x * l.y * l.z;
        let q = l.component_mul(&l) * (v / 12.0);
        inertia += Matrix3::from_diagonal(&Vector3::new(q.y + q.z, q.x + q.z, q.x + q.y));
        let d = c - com;
        inertia += (Matrix3::identity() * d.norm_squared() - d * d.transpose()) * v;
    }
    (vol, com, inertia)
}

/// The committed `tests/data/l_block.stl` is what the generator writes (so the data file is
/// reviewed: it is this code's output), and the L-block read from ASCII STL, binary STL and
/// OBJ, scaled non-uniformly, has the closed-form volume, centre and inertia (products
/// included) to 1e-12: the divergence theorem is exact for a polyhedron, and the binary
/// fractions are exact in the files' f32/decimal, so only rounding remains.
#[test]
fn l_block_mesh_mass_properties_match_the_closed_form() {
    let tris = l_block_triangles();
    let committed = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/l_block.stl");
    assert_eq!(
        std::fs::read_to_string(committed).unwrap(),
        ascii_stl(&tris)
    );
    let dir = scratch("mass");
    std::fs::write(dir.join("l.stl"), binary_stl(&tris)).unwrap();
    std::fs::write(dir.join("l.OBJ"), obj(&tris)).unwrap();
    let scale = Vector3::new(2.0, 0.5, 3.0);
    let (vol, com, inertia) = l_block_exact(scale);
    for path in [
        std::path::PathBuf::from(committed),
        dir.join("l.stl"),
        dir.join("l.OBJ"),
    ] {
        let shape = Shape::FileMesh {
            path: path.clone(),
            scale,
            collision: MeshCollision::ConvexHull,
        }
        .load()
        .unwrap();
        let p = shape.unit_mass_properties().unwrap();
        println!(
            "{}: V = {}, com = {:?}",
            path.display(),
            p.volume,
            p.com.as_slice()
        );
        assert!((p.volume - vol).abs() <= 1e-12 * vol);
        assert!((p.com - com).norm() <= 1e-12 * com.norm());
        assert!((p.inertia - inertia).norm() <= 1e-12 * inertia.norm());
        assert!(
            inertia[(0, 1)].abs() > 1e-3 * inertia.norm(),
            "products are tested"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// One object `block` of `shape` (DryWood) and a world, for the error tests.
fn mesh_scene(shape: Shape) -> SceneDesc {
    let mut s = SceneDesc::new();
    s.add(world(SceneOptions::default())).add(
        Object3D::new("block")
            .parent("world")
            .solid(Solid::new(shape).material("DryWood")),
    );
    s
}

/// Every way a mesh file can fail is a typed `SceneError::Mesh` naming the object and the file
/// (and the line, facet or edge), reported by `build()` together with the scene's other errors.
#[test]
fn mesh_file_errors_are_typed_and_named() {
    use modia3d::core::geometry::GeometryError as GE;
    let dir = scratch("errors");
    let tris = l_block_triangles();
    let files: [(&str, Vec<u8>); 5] = [
        ("open.stl", ascii_stl(&tris[1..]).into_bytes()),
        (
            "inside_out.obj",
            obj(&tris).replace("/1/1", "").into_bytes(),
        ),
        ("bad.obj", b"v 0 0 0\nv 1 0 0\nv 0 x 0\n".to_vec()),
        (
            "bad.stl",
            ascii_stl(&tris)
                .replacen("endloop", "endloops", 2)
                .into_bytes(),
        ),
        ("part.step", vec![]),
    ];
    for (name, data) in &files {
        std::fs::write(dir.join(name), data).unwrap();
    }
    // Turn the OBJ inside out: swap two corners of every face.
    let inside_out = std::fs::read_to_string(dir.join("inside_out.obj")).unwrap();
    let flipped: String = inside_out
        .lines()
        .map(|l| match l.strip_prefix("f ") {
            Some(f) => {
                let w: Vec<&str> = f.split_whitespace().collect();
                format!("f {} {} {}\n", w[0], w[2], w[1])
            }
            None => format!("{l}\n"),
        })
        .collect();
    std::fs::write(dir.join("inside_out.obj"), flipped).unwrap();
    let check = |file: &str, expect: &dyn Fn(&GE) -> bool| {
        let path = dir.join(file);
        let errs = mesh_scene(Shape::FileMesh {
            path: path.clone(),
            scale: Vector3::repeat(1.0),
            collision: MeshCollision::ConvexHull,
        })
        .build()
        .err()
        .unwrap_or_else(|| panic!("{file}: built"));
        let e = errs
            .0
            .iter()
            .find_map(|e| match e {
                SceneError::Mesh { object, error } => Some((object.clone(), error.clone())),
                _ => None,
            })
            .unwrap_or_else(|| panic!("{file}: {errs}"));
        println!("{file}: {}", errs);
        assert_eq!(e.0, "block");
        assert!(expect(&e.1), "{file}: {:?}", e.1);
        assert!(errs.to_string().contains(&path.display().to_string()));
    };
    check(
        "missing.stl",
        &|e| matches!(e, GE::MeshFile { message, .. } if message.contains("not found")),
    );
    // One triangle missing: a hole of 5.6 % of the surface, more than `repair_mesh` closes.
    check("open.stl", &|e| {
        matches!(
            e,
            GE::MeshHoles {
                holes: 1,
                largest_edges: 3,
                ..
            }
        )
    });
    check(
        "inside_out.obj",
        &|e| matches!(e, GE::MeshVolume { volume, .. } if *volume < 0.0),
    );
    check(
        "bad.obj",
        &|e| matches!(e, GE::MeshParse { location, .. } if location == "line 3"),
    );
    check(
        "bad.stl",
        &|e| matches!(e, GE::MeshParse { location, .. } if location == "facet 1"),
    );
    check(
        "part.step",
        &|e| matches!(e, GE::MeshFile { message, .. } if message.contains(".obj or .stl")),
    );
    // A visual mesh need not bound a solid: the open mesh draws.
    let mut visual = SceneDesc::new();
    visual
        .add(world(SceneOptions::default()))
        .add(
            Object3D::new("deco")
                .parent("world")
                .feature(Feature::Visual(Shape::FileMesh {
                    path: dir.join("open.stl"),
                    scale: Vector3::repeat(1.0),
                    collision: MeshCollision::ConvexHull,
                })),
        );
    visual.build().unwrap();
    // A bad scale is a value error, the file is not read.
    let errs = mesh_scene(Shape::FileMesh {
        path: dir.join("missing.stl"),
        scale: Vector3::new(1.0, -1.0, 1.0),
        collision: MeshCollision::ConvexHull,
    })
    .build()
    .err()
    .unwrap();
    assert!(errs.to_string().contains("scale[1]"), "{errs}");
    assert!(!errs.to_string().contains("not found"), "{errs}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The non-convex L-block lying flat on a table, colliding as a convex decomposition: at
/// least two parts (the two legs) touch the table, each carries part of the weight, the
/// vertical forces sum to the weight (1e-6) and their centre of pressure lies under the
/// centre of mass (torque balance, 1e-4 of the block's size: the contact points are the
/// parts' soft-support centres, exact for flat faces). Mass properties come from the mesh,
/// not the parts: the body's mass is the closed form's.
#[test]
fn l_block_decomposed_rests_on_both_legs() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/l_block.stl");
    let shape = Shape::FileMesh {
        path: path.into(),
        scale: Vector3::repeat(1.0),
        collision: MeshCollision::ConvexDecomposition,
    };
    let (vol, com, _) = l_block_exact(Vector3::repeat(1.0));
    let scene = on_table(Solid::new(shape), [0.0, 0.0, 1e-4]);
    let model = scene.clone().build().unwrap();
    let pairs: Vec<String> = model
        .contact_pairs()
        .iter()
        .map(|p| p.name.clone())
        .collect();
    println!("pairs: {pairs:?}");
    assert!(pairs.len() >= 2, "{pairs:?}");
    assert!(pairs.iter().all(|p| p.starts_with("table|body#")));
    let (res, weight) = settle(scene, 1.0);
    assert!((weight - 700.0 * vol * G).abs() < 1e-12 * weight);
    let (mut total, mut moment, mut loaded) = (0.0, Vector3::zeros(), 0);
    for p in &pairs {
        let f = vertical_force(&res, p);
        let x = res.signal(&format!("{p}.point")).unwrap();
        let x = Vector3::from_row_slice(x.last().unwrap());
        println!("{p}: {f:.9} N at {:?}", x.as_slice());
        total += f;
        moment += x * f;
        if f > 0.05 * weight {
            loaded += 1;
        }
    }
    let centre = moment / total;
    println!(
        "weight {weight} N, sum {total} N, centre of pressure {:?}, com {:?}",
        centre.as_slice(),
        com.as_slice()
    );
    assert!(
        (total - weight).abs() < 1e-6 * weight,
        "{total} vs {weight}"
    );
    assert!(loaded >= 2, "only {loaded} part(s) carry load");
    let r = res.signal("body.r_abs").unwrap();
    let r = Vector3::from_row_slice(r.last().unwrap());
    assert!((centre.xy() - (r + com).xy()).norm() < 1e-4 * 0.5);
}

model! {
    /// A beam and a mesh through the macro: the keys reach the builder.
    ShapesModel(decompose: bool = true) {
        world = Object3D(feature = Scene()),
        beam  = Object3D(parent = world, feature = Solid(shape = Beam(axis = 2, length = 0.3, width = 0.1, thickness = 0.05),
                                                        solid_material = "DryWood")),
        block = Object3D(parent = world, translation = [1.0, 0.0, 0.0],
                         feature = Solid(shape = FileMesh(path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/l_block.stl"),
                                                          scale = [1.0, 1.0, 2.0], convex_decomposition = decompose),
                                         solid_material = "DryWood")),
    }
}

/// `model!`'s `Beam` and `FileMesh` give the builder's shapes (the file read by `build()`).
#[test]
fn model_macro_builds_beam_and_file_mesh() {
    let desc = ShapesModel::default().scene();
    let shape = |name: &str| match &desc
        .objects
        .iter()
        .find(|o| o.name == name)
        .unwrap()
        .feature
    {
        Feature::Solid(s) => s.shape.clone().unwrap(),
        f => panic!("{f:?}"),
    };
    assert_eq!(
        shape("beam"),
        Shape::Beam {
            axis: Axis::Y,
            length: 0.3,
            width: 0.1,
            thickness: 0.05
        }
    );
    assert_eq!(
        shape("block"),
        Shape::FileMesh {
            path: concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/l_block.stl").into(),
            scale: Vector3::new(1.0, 1.0, 2.0),
            collision: MeshCollision::ConvexDecomposition,
        }
    );
    desc.build().unwrap();
}
