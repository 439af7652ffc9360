//! Results stage, animation sampling: the pose of every object that has a shape (solid or
//! visual) at every output time point, from the `r_abs` and `R_abs` signals. Shared by the
//! three.js JSON, glTF and HTML exporters; reads a `SimulationResult` only.

use super::{ResultError, SimulationResult};
use crate::geometry::Shape;
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

/// An object to animate: its shapes (in the object frame) and its pose at every time point.
pub(crate) struct AnimObject {
    /// Object name (unique in the scene).
    pub name: String,
    /// Shapes drawn in the object frame: the solid's shape, then the visual shape.
    pub shapes: Vec<Shape>,
    /// Whether it moves (belongs to a moving body); fixed objects get no keyframe tracks.
    pub moving: bool,
    /// Display colour of its solid's built-in material (`palette.json`), if any.
    pub color: Option<[u8; 3]>,
    /// Position of the object frame origin in world, per time point \[m\].
    pub positions: Vec<[f64; 3]>,
    /// Orientation object → world as a unit quaternion `[x, y, z, w]` per time point, with the
    /// sign chosen so consecutive quaternions have a non-negative dot product (short arcs).
    pub rotations: Vec<[f64; 4]>,
}

/// The quaternion `[x, y, z, w]` of a row-major rotation matrix (columns = object axes in world).
pub(crate) fn quaternion_of_row_major(r: &[f64]) -> [f64; 4] {
    let m = Matrix3::from_row_slice(r);
    let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m));
    [q.i, q.j, q.k, q.w]
}

/// The rotation that turns the world's "up" (against gravity; +z when there is no gravity) into
/// +y, the up axis of three.js and glTF, as `[x, y, z, w]`.
pub(crate) fn world_to_y_up(gravity: &Vector3<f64>) -> [f64; 4] {
    let up = if gravity.norm() > 0.0 {
        -gravity.normalize()
    } else {
        Vector3::z()
    };
    let q = UnitQuaternion::rotation_between(&up, &Vector3::y()).unwrap_or_else(|| {
        // up = −y: half a turn about x.
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
    });
    [q.i, q.j, q.k, q.w]
}

impl SimulationResult {
    /// Every object with a shape, in scene order, with its pose at every time point.
    pub(crate) fn animated_objects(&self) -> Result<Vec<AnimObject>, ResultError> {
        let plan = self.plan();
        let mut out = vec![];
        for (op, so) in plan.objects.iter().zip(&plan.scene.objects) {
            let shapes: Vec<Shape> = so
                .solid
                .as_ref()
                .and_then(|s| s.shape.clone())
                .into_iter()
                .chain(so.visual.clone())
                .collect();
            if shapes.is_empty() {
                continue;
            }
            let r = self.signal(&format!("{}.r_abs", op.name))?;
            let rot = self.signal(&format!("{}.R_abs", op.name))?;
            let n = self.time().len();
            let positions = r
                .data
                .chunks_exact(3)
                .filter_map(|p| <[f64; 3]>::try_from(p).ok());
            let mut rotations: Vec<[f64; 4]> = Vec::with_capacity(n);
            for row in rot.data.chunks_exact(9) {
                let mut q = quaternion_of_row_major(row);
                if let Some(prev) = rotations.last() {
                    let dot: f64 = prev.iter().zip(&q).map(|(a, b)| a * b).sum();
                    if dot < 0.0 {
                        q = q.map(|c| -c);
                    }
                }
                rotations.push(q);
            }
            out.push(AnimObject {
                name: op.name.clone(),
                shapes,
                moving: op.body.is_some(),
                color: so
                    .solid
                    .as_ref()
                    .and_then(|s| s.material_name.as_deref())
                    .and_then(crate::scene::builtin_material_color),
                positions: positions.collect(),
                rotations,
            });
        }
        Ok(out)
    }
}
