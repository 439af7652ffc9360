//! Constraint rows (plan vocabulary, imports nothing of the crate): the scalar constraints a
//! joint kind locks when it is cut out of the spanning tree ([`Row`], each kind lists its rows in
//! its own file of `joints/`), and the basis helper the kinds share. `dynamics/loops.rs`
//! evaluates them (see its module docs for the constraint functions `g`).

use nalgebra::Vector3;

/// One scalar constraint of a cut joint (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Row {
    /// `e·p = 0`: no translation of obj2's origin along `e` (unit, resolved in obj1).
    Translation {
        /// Locked direction, resolved in obj1.
        e: Vector3<f64>,
    },
    /// `u·(R a) = 0`: obj2's axis `a` (resolved in obj2) stays perpendicular to `u` (resolved
    /// in obj1).
    Align {
        /// Direction of obj1, resolved in obj1.
        u: Vector3<f64>,
        /// Axis of obj2, resolved in obj2.
        a: Vector3<f64>,
    },
    /// `½ vee(R − Rᵀ)_k = 0`: rotation about obj1's axis `k` locked.
    Rotation {
        /// Axis index 0, 1, 2.
        k: usize,
    },
}

impl Row {
    /// Translations along each of the unit directions `es` (resolved in obj1).
    pub(crate) fn translations(es: &[Vector3<f64>]) -> Vec<Row> {
        es.iter().map(|e| Row::Translation { e: *e }).collect()
    }
    /// The three rotations.
    pub(crate) fn rotations() -> impl Iterator<Item = Row> {
        (0..3).map(|k| Row::Rotation { k })
    }
    /// The two alignments that keep obj2's `axis` on obj1's (rotations across it locked).
    pub(crate) fn alignments(axis: &Vector3<f64>) -> [Row; 2] {
        let (u, w) = perpendiculars(axis);
        [Row::Align { u, a: *axis }, Row::Align { u: w, a: *axis }]
    }
    /// A short name of the row for messages: `x`, `y`, `z` (translations along obj1's axes or
    /// other directions `t0`…), `align0`…, `rot_x`, `rot_y`, `rot_z`.
    pub(crate) fn label(&self, i: usize) -> String {
        match self {
            Row::Translation { e } => match (0..3).find(|&k| (e[k].abs() - 1.0).abs() < 1e-12) {
                Some(k) => ["x", "y", "z"][k].to_string(),
                None => format!("t{i}"),
            },
            Row::Align { .. } => format!("align{i}"),
            Row::Rotation { k } => ["rot_x", "rot_y", "rot_z"][*k].to_string(),
        }
    }
}

/// Two unit vectors completing the unit `a` to a right-handed orthonormal basis `(u, w, a)`.
pub(crate) fn perpendiculars(a: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let k = (0..3)
        .min_by(|&i, &j| a[i].abs().total_cmp(&a[j].abs()))
        .unwrap_or(0);
    let u = a.cross(&Vector3::ith(k, 1.0)).normalize();
    let w = a.cross(&u);
    (u, w)
}
