//! Plot and animation export: the SVG plot, three.js JSON and glTF are well-formed and agree
//! with the result's signals (time points, initial poses, shape conventions).

use modia3d::prelude::*;
use serde_json::Value;

/// A pendulum (revolute about x) whose body carries one shape of every kind, plus a fixed
/// visual box at the pivot. Visual shapes carry no mass.
fn showcase() -> SimulationResult {
    let visual = |name: &str, at: [f64; 3], shape: Shape| {
        Object3D::new(name)
            .parent("bob")
            .translation(at)
            .feature(Feature::Visual(shape))
    };
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions::default()))
        .add(Object3D::new("bob").solid(Solid::new(Shape::Sphere { diameter: 0.1 }).mass(1.0)))
        .add(visual(
            "rod",
            [0.0, 0.0, 0.5],
            Shape::Cylinder {
                axis: Axis::Z,
                diameter: 0.02,
                length: 1.0,
            },
        ))
        .add(visual(
            "cone",
            [0.2, 0.0, 0.0],
            Shape::Cone {
                axis: Axis::Z,
                diameter: 0.1,
                length: 0.2,
                top_diameter: 0.0,
            },
        ))
        .add(visual(
            "capsule",
            [-0.2, 0.0, 0.0],
            Shape::Capsule {
                axis: Axis::X,
                diameter: 0.05,
                length: 0.1,
            },
        ))
        .add(visual(
            "egg",
            [0.0, 0.2, 0.0],
            Shape::Ellipsoid {
                lengths: Vector3::new(0.1, 0.05, 0.2),
            },
        ))
        .add(visual(
            "hull",
            [0.0, -0.2, 0.0],
            Shape::ConvexHull {
                points: vec![
                    Point3::new(0.0, 0.0, 0.0),
                    Point3::new(0.1, 0.0, 0.0),
                    Point3::new(0.0, 0.1, 0.0),
                    Point3::new(0.0, 0.0, 0.1),
                ],
            },
        ))
        .add(
            Object3D::new("support")
                .parent("world")
                .feature(Feature::Visual(Shape::Box {
                    lengths: Vector3::new(0.1, 0.04, 0.04),
                })),
        )
        .add(
            Object3D::new("pivot")
                .parent("bob")
                .translation([0.0, 0.0, 1.0]),
        )
        .add_joint(Joint::new("rev", "world", "pivot", JointKind::revolute(1)).init_position(0.7));
    s.build()
        .unwrap()
        .simulate(&SimOptions::new(1.0).tolerance(1e-8).interval(0.05))
        .unwrap()
}

const SHAPED: [&str; 7] = ["bob", "rod", "cone", "capsule", "egg", "hull", "support"];
const MOVING: [&str; 6] = ["bob", "rod", "cone", "capsule", "egg", "hull"];

/// The quaternion `[x, y, z, w]` of a row-major rotation matrix.
fn quaternion(r: &[f64]) -> [f64; 4] {
    let m = Matrix3::from_row_slice(r);
    let q = UnitQuaternion::from_rotation_matrix(&nalgebra::Rotation3::from_matrix_unchecked(m));
    [q.i, q.j, q.k, q.w]
}

fn same_rotation(a: &[f64], b: &[f64], tol: f64) -> bool {
    let dot: f64 = a.iter().zip(b).map(|(x, y)| x * y).sum();
    (1.0 - dot.abs()) < tol
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn base64_decode(s: &str) -> Vec<u8> {
    let val = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c}"),
    } as u32;
    let mut out = vec![];
    for chunk in s.as_bytes().chunks(4) {
        let pad = chunk.iter().filter(|&&c| c == b'=').count();
        let n = chunk
            .iter()
            .map(|&c| if c == b'=' { 0 } else { val(c) })
            .fold(0u32, |n, v| n << 6 | v);
        out.extend_from_slice(&n.to_be_bytes()[1..4 - pad]);
    }
    out
}

#[test]
fn threejs_json_has_the_shapes_and_one_keyframe_per_time_point() {
    let result = showcase();
    let nt = result.time().len();
    let dir = std::env::temp_dir().join(format!("modia3d-threejs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.json");
    result.write_threejs_json(&path).unwrap();
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(doc["metadata"]["type"], "Object");
    assert_eq!(doc["metadata"]["version"].as_f64().unwrap().floor(), 4.0);

    let mut types: Vec<&str> = doc["geometries"]
        .as_array()
        .unwrap()
        .iter()
        .map(|g| g["type"].as_str().unwrap())
        .collect();
    types.sort_unstable();
    assert_eq!(
        types,
        [
            "BoxGeometry",
            "BufferGeometry",
            "CapsuleGeometry",
            "CylinderGeometry",
            "CylinderGeometry",
            "SphereGeometry",
            "SphereGeometry"
        ]
    );
    let geometry = |uuid: &Value| {
        doc["geometries"]
            .as_array()
            .unwrap()
            .iter()
            .find(|g| &g["uuid"] == uuid)
            .unwrap()
            .clone()
    };

    let world = &doc["object"]["children"][0];
    let groups = world["children"].as_array().unwrap();
    let names: Vec<&str> = groups.iter().map(|g| g["name"].as_str().unwrap()).collect();
    assert_eq!(names, SHAPED);
    for g in groups {
        let name = g["name"].as_str().unwrap();
        let mesh = &g["children"][0];
        assert_eq!(mesh["type"], "Mesh");
        let geo = geometry(&mesh["geometry"]);
        let m = floats(&mesh["matrix"]); // column-major
        match name {
            // A cone along z, base at z = 0: three.js's centred y-cylinder turned onto z and
            // lifted by half its height; the pointed end is the top (radiusTop = 0).
            "cone" => {
                assert_eq!(geo["type"], "CylinderGeometry");
                assert_eq!(geo["radiusTop"], 0.0);
                assert_eq!(geo["radiusBottom"], 0.05);
                let y_axis = [m[4], m[5], m[6]];
                assert!((y_axis[2] - 1.0).abs() < 1e-12, "y onto z: {m:?}");
                assert!((m[14] - 0.1).abs() < 1e-12, "lifted by length/2: {m:?}");
            }
            "capsule" => {
                assert_eq!(geo["length"], 0.1, "cylindrical part only");
                assert!((m[4] - 1.0).abs() < 1e-12, "y onto x: {m:?}");
            }
            "egg" => {
                assert_eq!(geo["radius"], 0.5);
                assert_eq!([m[0], m[5], m[10]], [0.1, 0.05, 0.2]);
            }
            "hull" => {
                let pos = geo["data"]["attributes"]["position"]["array"]
                    .as_array()
                    .unwrap()
                    .len();
                assert_eq!(pos, 4 * 3 * 3, "a tetrahedron: 4 triangles of 3 vertices");
            }
            _ => {}
        }
        // The group's matrix is the initial pose.
        let gm = floats(&g["matrix"]);
        let r = result.signal(&format!("{name}.r_abs")).unwrap();
        for i in 0..3 {
            assert!((gm[12 + i] - r.at(0).unwrap()[i]).abs() < 1e-12);
        }
    }

    let clip = &doc["animations"][0];
    assert_eq!(doc["object"]["animations"][0], clip["uuid"]);
    let tracks = clip["tracks"].as_array().unwrap();
    assert_eq!(
        tracks.len(),
        2 * MOVING.len(),
        "the fixed support has no tracks"
    );
    // Tracks are bound by the node's uuid (names may hold the dots of assembly paths).
    fn uuid_of(node: &serde_json::Value, name: &str) -> Option<String> {
        if node["name"] == name {
            return node["uuid"].as_str().map(str::to_string);
        }
        node["children"]
            .as_array()?
            .iter()
            .find_map(|c| uuid_of(c, name))
    }
    for name in MOVING {
        let id = uuid_of(&doc["object"], name).unwrap();
        let pos = tracks
            .iter()
            .find(|t| t["name"] == format!("{id}.position"))
            .unwrap();
        let quat = tracks
            .iter()
            .find(|t| t["name"] == format!("{id}.quaternion"))
            .unwrap();
        assert_eq!(pos["type"], "vector");
        assert_eq!(quat["type"], "quaternion");
        assert_eq!(pos["times"].as_array().unwrap().len(), nt);
        let (p, q) = (floats(&pos["values"]), floats(&quat["values"]));
        assert_eq!((p.len(), q.len()), (3 * nt, 4 * nt));
        let r = result.signal(&format!("{name}.r_abs")).unwrap();
        let rot = result.signal(&format!("{name}.R_abs")).unwrap();
        for k in [0, nt / 2, nt - 1] {
            for i in 0..3 {
                assert!((p[3 * k + i] - r.at(k).unwrap()[i]).abs() < 1e-12);
            }
            assert!(same_rotation(
                &q[4 * k..4 * k + 4],
                &quaternion(rot.at(k).unwrap()),
                1e-12
            ));
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn gltf_accessors_buffer_and_keyframes_are_consistent() {
    let result = showcase();
    let nt = result.time().len();
    let dir = std::env::temp_dir().join(format!("modia3d-gltf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.gltf");
    result.write_gltf(&path).unwrap();
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(doc["asset"]["version"], "2.0");

    let buffer = &doc["buffers"][0];
    let uri = buffer["uri"].as_str().unwrap();
    let bin = base64_decode(
        uri.strip_prefix("data:application/octet-stream;base64,")
            .unwrap(),
    );
    assert_eq!(bin.len() as u64, buffer["byteLength"].as_u64().unwrap());

    let views = doc["bufferViews"].as_array().unwrap();
    for v in views {
        let end = v["byteOffset"].as_u64().unwrap() + v["byteLength"].as_u64().unwrap();
        assert!(end <= bin.len() as u64);
        assert_eq!(v["byteOffset"].as_u64().unwrap() % 4, 0, "floats aligned");
    }
    let accessors = doc["accessors"].as_array().unwrap();
    let width = |t: &str| match t {
        "SCALAR" => 1,
        "VEC3" => 3,
        "VEC4" => 4,
        t => panic!("unexpected accessor type {t}"),
    };
    // The floats of accessor `a`.
    let read = |a: usize| -> Vec<f32> {
        let acc = &accessors[a];
        assert_eq!(acc["componentType"], 5126);
        let view = &views[acc["bufferView"].as_u64().unwrap() as usize];
        let (off, len) = (
            view["byteOffset"].as_u64().unwrap() as usize,
            view["byteLength"].as_u64().unwrap() as usize,
        );
        let n = acc["count"].as_u64().unwrap() as usize * width(acc["type"].as_str().unwrap());
        assert_eq!(
            4 * n,
            len,
            "accessor {a}: count × components × 4 = view length"
        );
        bin[off..off + len]
            .chunks(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect()
    };
    for a in 0..accessors.len() {
        read(a);
    }

    let nodes = doc["nodes"].as_array().unwrap();
    assert_eq!(nodes[0]["name"], "world");
    // Gravity along −z: the world node turns +z onto glTF's +y (a quarter turn about −x).
    let w = floats(&nodes[0]["rotation"]);
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert!(same_rotation(&w, &[-h, 0.0, 0.0, h], 1e-12), "{w:?}");
    let names: Vec<&str> = nodes[1..]
        .iter()
        .map(|n| n["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, SHAPED);
    for node in &nodes[1..] {
        let mesh = &doc["meshes"][node["mesh"].as_u64().unwrap() as usize];
        for prim in mesh["primitives"].as_array().unwrap() {
            let (p, n) = (
                &prim["attributes"]["POSITION"],
                &prim["attributes"]["NORMAL"],
            );
            let (p, n) = (p.as_u64().unwrap() as usize, n.as_u64().unwrap() as usize);
            assert_eq!(accessors[p]["count"], accessors[n]["count"]);
            assert_eq!(
                accessors[p]["count"].as_u64().unwrap() % 3,
                0,
                "whole triangles"
            );
            assert!(accessors[p]["min"].is_array() && accessors[p]["max"].is_array());
        }
        let name = node["name"].as_str().unwrap();
        let r = result.signal(&format!("{name}.r_abs")).unwrap();
        let rot = result.signal(&format!("{name}.R_abs")).unwrap();
        let t0 = floats(&node["translation"]);
        assert!((0..3).all(|i| (t0[i] - r.at(0).unwrap()[i]).abs() < 1e-12));
        assert!(same_rotation(
            &floats(&node["rotation"]),
            &quaternion(rot.at(0).unwrap()),
            1e-12
        ));
    }

    let anim = &doc["animations"][0];
    let (samplers, channels) = (
        anim["samplers"].as_array().unwrap(),
        anim["channels"].as_array().unwrap(),
    );
    assert_eq!(channels.len(), 2 * MOVING.len());
    for c in channels {
        let node = c["target"]["node"].as_u64().unwrap() as usize;
        let name = nodes[node]["name"].as_str().unwrap();
        assert!(MOVING.contains(&name), "{name} moves");
        let s = &samplers[c["sampler"].as_u64().unwrap() as usize];
        assert_eq!(s["interpolation"], "LINEAR");
        let (input, output) = (
            s["input"].as_u64().unwrap() as usize,
            s["output"].as_u64().unwrap() as usize,
        );
        let times = read(input);
        assert_eq!(times.len(), nt, "one keyframe per time point");
        assert!(times.windows(2).all(|w| w[1] > w[0]));
        assert_eq!(accessors[input]["count"], accessors[output]["count"]);
        let values: Vec<f64> = read(output).iter().map(|&x| x as f64).collect();
        match c["target"]["path"].as_str().unwrap() {
            "translation" => {
                let r = result.signal(&format!("{name}.r_abs")).unwrap();
                for k in [0, nt - 1] {
                    assert!((0..3).all(|i| (values[3 * k + i] - r.at(k).unwrap()[i]).abs() < 1e-6));
                }
            }
            "rotation" => {
                let rot = result.signal(&format!("{name}.R_abs")).unwrap();
                for k in [0, nt - 1] {
                    assert!(same_rotation(
                        &values[4 * k..4 * k + 4],
                        &quaternion(rot.at(k).unwrap()),
                        1e-6
                    ));
                }
            }
            p => panic!("unexpected path {p}"),
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn plot_writes_an_svg_with_axis_labels_and_legend_and_rejects_unknown_signals() {
    let result = showcase();
    let dir = std::env::temp_dir().join(format!("modia3d-plot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("plot.svg");
    result.plot(&["rev.phi", "bob.r_abs[2]"], &path).unwrap();
    let svg = std::fs::read_to_string(&path).unwrap();
    assert!(svg.starts_with("<svg"));
    for text in ["time [s]", "rev.phi [rad]", "bob.r_abs[2] [m]"] {
        assert!(svg.contains(text), "missing `{text}`");
    }
    assert!(svg.matches("<polyline").count() >= 2, "two curves");
    match result.plot(&["rev.ph"], &path) {
        Err(ResultError::UnknownSignal { name, reason }) => {
            assert_eq!(name, "rev.ph");
            assert!(reason.contains("rev.phi"), "{reason}");
        }
        other => panic!("expected UnknownSignal, got {other:?}"),
    }
    assert!(matches!(
        result.plot(&[], &path),
        Err(ResultError::Export { .. })
    ));
    assert!(matches!(
        result.plot(&["rev.phi"], dir.join("no/such/dir/plot.svg")),
        Err(ResultError::Io { .. })
    ));
    std::fs::remove_dir_all(&dir).ok();
}
