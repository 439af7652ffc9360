//! Results stage, three.js export: the scene and its motion in three.js's JSON Object format 4
//! (what `THREE.ObjectLoader` reads, as Modia3D.jl exports it). Reads a `SimulationResult`.
//!
//! Layout: a `Scene` holds one `Group` "world" that turns the world's up axis (against gravity)
//! into three.js's +y; under it one `Group` per object with a shape, posed like the object at
//! the first time point, each with one child `Mesh` per shape. three.js geometries are along y
//! and centred, so the mesh's matrix turns y onto the shape's `axis` (and lifts a cone so that
//! its base lies at `axis = 0`); an ellipsoid is a unit-diameter sphere scaled by its lengths; a
//! convex hull is a `BufferGeometry` of flat triangles. One animation clip holds a `.position`
//! (vector) and a `.quaternion` track per moving object, named `<object uuid>.position` etc.
//! (by uuid, since three.js track names cannot hold the dots of assembly paths like `arm1.tip`),
//! with one keyframe per output time point. Lengths in \[m\], times in \[s\].

use super::animation::world_to_y_up;
use super::{ResultError, SimulationResult};
use crate::geometry::display_mesh::Primitive;
use crate::geometry::{Axis, Shape};
use nalgebra::{Matrix4, Translation3, UnitQuaternion, Vector3};
use serde_json::{json, Value};
use std::path::Path;

/// Object colours (RGB), given in turn.
pub(crate) const COLORS: [u32; 8] = [
    0x4e79a7, 0xf28e2b, 0xe15759, 0x76b7b2, 0x59a14f, 0xedc948, 0xb07aa1, 0x9c755f,
];

/// A deterministic UUID-shaped id: `kind` (1 geometry, 2 material, 3 object, 4 clip) and index.
fn uuid(kind: u32, i: usize) -> String {
    format!("6d6f6469-6133-4{kind:03x}-8000-{i:012x}")
}

/// Column-major 4×4 matrix, as three.js stores `Object3D.matrix`.
fn matrix_json(m: &Matrix4<f64>) -> Value {
    json!(m.as_slice())
}

/// Pose matrix of a translation and a quaternion `[x, y, z, w]`.
pub(crate) fn pose_matrix(p: [f64; 3], q: [f64; 4]) -> Matrix4<f64> {
    let q = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[3], q[0], q[1], q[2]));
    Translation3::new(p[0], p[1], p[2]).to_homogeneous() * q.to_homogeneous()
}

/// The rotation that turns three.js's geometry axis (+y) onto `axis`.
fn y_onto(axis: Axis) -> UnitQuaternion<f64> {
    UnitQuaternion::rotation_between(&Vector3::y(), &axis.unit()).unwrap_or_default()
}

/// The three.js geometry of a shape (without uuid) and the matrix placing it in the object frame.
fn geometry(shape: &Shape) -> (Value, Matrix4<f64>) {
    use std::f64::consts::PI;
    let along = |axis: Axis, lift: f64| {
        Translation3::from(axis.unit() * lift).to_homogeneous() * y_onto(axis).to_homogeneous()
    };
    let cylinder = |top: f64, bottom: f64, height: f64| {
        json!({"type": "CylinderGeometry", "radiusTop": top, "radiusBottom": bottom,
               "height": height, "radialSegments": 32, "heightSegments": 1, "openEnded": false,
               "thetaStart": 0.0, "thetaLength": 2.0 * PI})
    };
    let sphere = |radius: f64| {
        json!({"type": "SphereGeometry", "radius": radius, "widthSegments": 32,
               "heightSegments": 16, "phiStart": 0.0, "phiLength": 2.0 * PI,
               "thetaStart": 0.0, "thetaLength": PI})
    };
    // The kind's primitive (`geometry/kinds/<kind>.rs`, `display_primitive`), else its mesh.
    match shape.display_primitive() {
        Some(Primitive::Ball { radius, scaling }) => (
            sphere(radius),
            scaling.map_or_else(Matrix4::identity, |s| Matrix4::new_nonuniform_scaling(&s)),
        ),
        Some(Primitive::Box { lengths }) => (
            json!({"type": "BoxGeometry", "width": lengths.x, "height": lengths.y,
                   "depth": lengths.z, "widthSegments": 1, "heightSegments": 1,
                   "depthSegments": 1}),
            Matrix4::identity(),
        ),
        Some(Primitive::Frustum {
            axis,
            top,
            bottom,
            length,
            lift,
        }) => (cylinder(top, bottom, length), along(axis, lift)),
        Some(Primitive::Capsule {
            axis,
            radius,
            length,
        }) => (
            json!({"type": "CapsuleGeometry", "radius": radius, "length": length,
                   "capSegments": 8, "radialSegments": 24, "heightSegments": 1}),
            along(axis, 0.0),
        ),
        None => {
            let m = shape.display_mesh();
            let flat = |v: &[[f32; 3]]| v.iter().flatten().copied().collect::<Vec<f32>>();
            (
                json!({"type": "BufferGeometry", "data": {"attributes": {
                    "position": {"itemSize": 3, "type": "Float32Array", "normalized": false,
                                 "array": flat(&m.positions)},
                    "normal": {"itemSize": 3, "type": "Float32Array", "normalized": false,
                               "array": flat(&m.normals)}}}}),
                Matrix4::identity(),
            )
        }
    }
}

impl SimulationResult {
    /// The scene and its motion as a three.js JSON Object-format document (see the module doc).
    pub fn threejs_json(&self) -> Result<Value, ResultError> {
        let objects = self.animated_objects()?;
        let time = self.time();
        let (mut geometries, mut materials, mut children, mut tracks) =
            (vec![], vec![], vec![], vec![]);
        for (i, o) in objects.iter().enumerate() {
            let mat = uuid(2, i);
            materials.push(json!({"uuid": mat, "type": "MeshStandardMaterial",
                "name": o.name, "color": o.color
                    .map(|[r, g, b]| u32::from_be_bytes([0, r, g, b]))
                    .or_else(|| COLORS.iter().cycle().nth(i).copied()),
                "roughness": 0.6,
                "metalness": 0.1, "side": 2}));
            let mut meshes = vec![];
            for (s, shape) in o.shapes.iter().enumerate() {
                let g = uuid(1, geometries.len());
                let (mut geo, m) = geometry(shape);
                if let Some(fields) = geo.as_object_mut() {
                    fields.insert("uuid".into(), json!(g));
                }
                geometries.push(geo);
                meshes.push(json!({"uuid": uuid(3, 1000 * (i + 1) + s), "type": "Mesh",
                    "name": format!("{}_shape{s}", o.name), "geometry": g, "material": mat,
                    "matrix": matrix_json(&m)}));
            }
            let (p0, q0) = match (o.positions.first(), o.rotations.first()) {
                (Some(p), Some(q)) => (*p, *q),
                _ => ([0.0; 3], [0.0, 0.0, 0.0, 1.0]),
            };
            children.push(
                json!({"uuid": uuid(3, i + 1), "type": "Group", "name": o.name,
                "matrix": matrix_json(&pose_matrix(p0, q0)), "children": meshes,
                "userData": {"moving": o.moving}}),
            );
            if o.moving {
                let flat = |v: &[[f64; 3]]| v.iter().flatten().copied().collect::<Vec<f64>>();
                let qs: Vec<f64> = o.rotations.iter().flatten().copied().collect();
                tracks.push(
                    json!({"name": format!("{}.position", uuid(3, i + 1)), "type": "vector",
                    "times": time, "values": flat(&o.positions), "interpolation": 2301}),
                );
                tracks.push(json!({"name": format!("{}.quaternion", uuid(3, i + 1)),
                    "type": "quaternion", "times": time, "values": qs, "interpolation": 2301}));
            }
        }
        let up = world_to_y_up(&self.plan().gravity);
        let duration = match (time.first(), time.last()) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        };
        let clip = uuid(4, 0);
        Ok(json!({
            "metadata": {"version": 4.6, "type": "Object", "generator": "modia3d"},
            "geometries": geometries,
            "materials": materials,
            "object": {"uuid": uuid(3, 0), "type": "Scene", "name": "modia3d",
                "animations": [clip],
                "children": [{"uuid": uuid(3, 999_999), "type": "Group", "name": "world",
                    "matrix": matrix_json(&pose_matrix([0.0; 3], up)),
                    "children": children}]},
            "animations": [{"uuid": clip, "name": "simulation", "duration": duration,
                "blendMode": 2500, "tracks": tracks}],
        }))
    }

    /// Writes [`threejs_json`](Self::threejs_json) to `path` (load it with `THREE.ObjectLoader`
    /// and play `scene.animations[0]` with an `AnimationMixer`).
    pub fn write_threejs_json(&self, path: impl AsRef<Path>) -> Result<(), ResultError> {
        let doc = self.threejs_json()?;
        write_text(path.as_ref(), &doc.to_string())
    }
}

/// Writes `text` to `path`, with the path in the error.
pub(crate) fn write_text(path: &Path, text: &str) -> Result<(), ResultError> {
    std::fs::write(path, text).map_err(|source| ResultError::Io {
        path: path.display().to_string(),
        source,
    })
}
