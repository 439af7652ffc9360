//! Results stage, glTF export: the scene and its motion as one glTF 2.0 JSON file with an
//! embedded base64 buffer. Reads a `SimulationResult`.
//!
//! Layout: scene 0 has one root node "world" whose rotation turns the world's up axis (against
//! gravity) into glTF's +y; its children are one node per object with a shape, posed like the
//! object at the first time point (translation \[m\], rotation quaternion `[x, y, z, w]`), each
//! with a mesh of flat-shaded triangles (one primitive per shape, in the object frame). One
//! animation has, per moving node, a `translation` and a `rotation` channel with LINEAR
//! samplers that share one input accessor of the output times \[s\] (times that do not increase,
//! as at an event restart, are dropped: glTF requires strictly increasing key times).
// Export encoding: offsets into buffers this module sized itself from the same lengths; no
// index comes from user input, which reaches it only through the checked signal look-up.
#![allow(clippy::indexing_slicing)]

use super::animation::world_to_y_up;
use super::threejs::{write_text, COLORS};
use super::{ResultError, SimulationResult};
use serde_json::{json, Value};
use std::path::Path;

/// glTF component type FLOAT.
const FLOAT: u32 = 5126;
/// glTF buffer view target ARRAY_BUFFER.
const ARRAY_BUFFER: u32 = 34962;

/// Standard base64 (RFC 4648, with padding).
pub(crate) fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for c in bytes.chunks(3) {
        let n = (c[0] as u32) << 16
            | (*c.get(1).unwrap_or(&0) as u32) << 8
            | *c.get(2).unwrap_or(&0) as u32;
        for i in 0..4 {
            if i <= c.len() {
                out.push(A[(n >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// The binary buffer under construction with its views and accessors.
#[derive(Default)]
struct Builder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Builder {
    /// Appends `data` (`width` floats per element) as a new view and accessor; returns its index.
    fn floats(&mut self, data: &[f32], width: usize, target: Option<u32>, bounds: bool) -> usize {
        let offset = self.bin.len();
        for x in data {
            self.bin.extend_from_slice(&x.to_le_bytes());
        }
        let mut view = json!({"buffer": 0, "byteOffset": offset, "byteLength": 4 * data.len()});
        if let Some(t) = target {
            view["target"] = json!(t);
        }
        self.views.push(view);
        let kind = match width {
            1 => "SCALAR",
            3 => "VEC3",
            4 => "VEC4",
            _ => unreachable!("only scalars, VEC3 and VEC4 are written"),
        };
        let mut acc = json!({"bufferView": self.views.len() - 1, "componentType": FLOAT,
            "count": data.len() / width, "type": kind});
        if bounds {
            let mut lo = vec![f32::INFINITY; width];
            let mut hi = vec![f32::NEG_INFINITY; width];
            for e in data.chunks(width) {
                for i in 0..width {
                    lo[i] = lo[i].min(e[i]);
                    hi[i] = hi[i].max(e[i]);
                }
            }
            acc["min"] = json!(lo);
            acc["max"] = json!(hi);
        }
        self.accessors.push(acc);
        self.accessors.len() - 1
    }
}

impl SimulationResult {
    /// The scene and its motion as a glTF 2.0 document (see the module doc).
    pub fn gltf_json(&self) -> Result<Value, ResultError> {
        let objects = self.animated_objects()?;
        let time = self.time();
        // Keyframes kept: strictly increasing times (in f32, as stored).
        let mut keep: Vec<usize> = vec![];
        for (k, t) in time.iter().enumerate() {
            if keep.last().is_none_or(|&j| (*t as f32) > (time[j] as f32)) {
                keep.push(k);
            }
        }
        let mut b = Builder::default();
        let (mut nodes, mut meshes, mut materials) = (vec![], vec![], vec![]);
        let (mut samplers, mut channels) = (vec![], vec![]);
        let times: Vec<f32> = keep.iter().map(|&k| time[k] as f32).collect();
        let input = (!times.is_empty() && objects.iter().any(|o| o.moving))
            .then(|| b.floats(&times, 1, None, true));
        for (i, o) in objects.iter().enumerate() {
            let c = COLORS[i % COLORS.len()];
            let rgb = |s: u32| ((c >> s) & 0xff) as f64 / 255.0;
            materials.push(
                json!({"name": o.name, "doubleSided": true, "pbrMetallicRoughness": {
                "baseColorFactor": [rgb(16), rgb(8), rgb(0), 1.0],
                "metallicFactor": 0.1, "roughnessFactor": 0.6}}),
            );
            let mut primitives = vec![];
            for shape in &o.shapes {
                let m = shape.display_mesh();
                if m.positions.is_empty() {
                    continue;
                }
                let flat = |v: &[[f32; 3]]| v.iter().flatten().copied().collect::<Vec<f32>>();
                let pos = b.floats(&flat(&m.positions), 3, Some(ARRAY_BUFFER), true);
                let nor = b.floats(&flat(&m.normals), 3, Some(ARRAY_BUFFER), false);
                primitives.push(json!({"attributes": {"POSITION": pos, "NORMAL": nor},
                    "material": i, "mode": 4}));
            }
            let mut node = json!({"name": o.name});
            if let (Some(p), Some(q)) = (o.positions.first(), o.rotations.first()) {
                node["translation"] = json!(p);
                node["rotation"] = json!(q);
            }
            if !primitives.is_empty() {
                node["mesh"] = json!(meshes.len());
                meshes.push(json!({"name": o.name, "primitives": primitives}));
            }
            let node_index = nodes.len() + 1; // node 0 is "world"
            nodes.push(node);
            if let (true, Some(input)) = (o.moving, input) {
                let tr: Vec<f32> = keep
                    .iter()
                    .flat_map(|&k| o.positions[k].map(|x| x as f32))
                    .collect();
                let ro: Vec<f32> = keep
                    .iter()
                    .flat_map(|&k| o.rotations[k].map(|x| x as f32))
                    .collect();
                for (path, data, width) in [("translation", tr, 3), ("rotation", ro, 4)] {
                    let output = b.floats(&data, width, None, false);
                    channels.push(json!({"sampler": samplers.len(),
                        "target": {"node": node_index, "path": path}}));
                    samplers
                        .push(json!({"input": input, "output": output, "interpolation": "LINEAR"}));
                }
            }
        }
        let world = json!({"name": "world", "rotation": world_to_y_up(&self.plan().gravity),
            "children": (1..=nodes.len()).collect::<Vec<_>>()});
        nodes.insert(0, world);
        let mut doc = json!({
            "asset": {"version": "2.0", "generator": "modia3d"},
            "scene": 0,
            "scenes": [{"name": "modia3d", "nodes": [0]}],
            "nodes": nodes,
            "materials": materials,
            "meshes": meshes,
            "accessors": b.accessors,
            "bufferViews": b.views,
            "buffers": [{"byteLength": b.bin.len(),
                "uri": format!("data:application/octet-stream;base64,{}", base64(&b.bin))}],
        });
        if !channels.is_empty() {
            doc["animations"] =
                json!([{"name": "simulation", "samplers": samplers, "channels": channels}]);
        }
        Ok(doc)
    }

    /// Writes [`gltf_json`](Self::gltf_json) to `path` (conventionally `*.gltf`).
    pub fn write_gltf(&self, path: impl AsRef<Path>) -> Result<(), ResultError> {
        let doc = self.gltf_json()?;
        write_text(path.as_ref(), &doc.to_string())
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn base64_matches_rfc4648_examples() {
        for (raw, enc) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(super::base64(raw.as_bytes()), enc);
        }
    }
}
