//! Validation of joints: ends resolved and distinct; each kind's parameters (unit axes, finite
//! initial values, unit quaternions, …) are checked by the kind's own file in `joints/`
//! (`joints::validate_kind`), with the scene's `Checker`, in the same round as every other check. Topology (loops, two parents, connectivity) is `topology.rs`.

use super::{Checker, Names, SceneError, ValidJoint, ValidLimit};
use crate::scene::desc::{Joint, JointLimit, SceneDesc, SceneOptions};

/// Every joint resolved and checked, in declaration order; a joint with an error is left out
/// and its resolved ends marked in `suspect` (they may now look unconnected).
pub(super) fn joints(
    c: &mut Checker,
    desc: &SceneDesc,
    names: &Names,
    suspect: &mut [bool],
    options: &SceneOptions,
) -> Vec<ValidJoint> {
    let mut joints = Vec::with_capacity(desc.joints.len());
    for j in &desc.joints {
        let o1 = names.resolve(c, format!("joint `{}`'s obj1", j.name), &j.obj1);
        let o2 = names.resolve(c, format!("joint `{}`'s obj2", j.name), &j.obj2);
        let kind = crate::joints::validate_kind(c, &j.name, &j.kind);
        let (Some(o1), Some(o2), Some(kind)) = (o1, o2, kind) else {
            // Dropped: its resolved ends may now look unconnected.
            for o in [o1, o2].into_iter().flatten() {
                suspect[o] = true;
            }
            continue;
        };
        let limits = limits(c, j);
        if o1 == o2 {
            c.errors.push(SceneError::IdenticalJointEnds {
                joint: j.name.clone(),
                object: j.obj1.clone(),
            });
            suspect[o1] = true;
            continue;
        }
        joints.push(ValidJoint {
            name: j.name.clone(),
            obj1: o1,
            obj2: o2,
            kind,
            can_collide: j
                .can_collide
                .unwrap_or(options.modia3d_conventions && j.kind.facts().modia3d_can_collide),
            cut: j.cut,
            limits,
        });
    }

    joints
}

/// The checked stops of joint `j` (docs/joint-limits.md): each on a scalar coordinate of its
/// kind (named, or the only one), at most one per coordinate, bounds finite with
/// `lower < upper`, the initial value inside (or on) them, stiffness > 0, cor in [0, 1].
fn limits(c: &mut Checker, j: &Joint) -> Vec<ValidLimit> {
    let facts = j.kind.facts();
    let (kind, coords) = (facts.spec.name, facts.spec.coordinates);
    let mut out: Vec<ValidLimit> = Vec::with_capacity(j.limits.len());
    for l in &j.limits {
        if coords.is_empty() {
            c.errors.push(SceneError::LimitWithoutCoordinate {
                joint: j.name.clone(),
                kind,
            });
            return vec![];
        }
        let referrer = format!("limit of joint `{}`", j.name);
        let Some(k) = super::forces::coordinate_index(c, &referrer, facts, &l.coordinate) else {
            continue;
        };
        let coord = &coords[k];
        let (name, unit) = (coord.name, coord.unit);
        if out.iter().any(|v| v.coordinate == k) {
            c.errors.push(SceneError::LimitTwice {
                joint: j.name.clone(),
                coordinate: name,
            });
            continue;
        }
        let before = c.errors.len();
        let what = |side: &str| format!("joint `{}`: {side} limit of `{name}` [{unit}]", j.name);
        // `−∞` below and `+∞` above mean no bound (`model!`'s `[lower, f64::INFINITY]`).
        let open = [f64::NEG_INFINITY, f64::INFINITY];
        for ((side, b), none) in [("lower", l.lower), ("upper", l.upper)]
            .into_iter()
            .zip(open)
        {
            if let Some(b) = b.filter(|&b| b != none) {
                c.finite(|| what(side), &[b]);
            }
        }
        if let Some(k) = l.stiffness {
            c.positive(
                || format!("joint `{}`: limit stiffness of `{name}`", j.name),
                k,
            );
        }
        let cor = l.cor.unwrap_or(JointLimit::DEFAULT_COR);
        c.value(
            || format!("joint `{}`: limit cor of `{name}`", j.name),
            cor,
            (0.0..=1.0).contains(&cor),
            "in [0, 1]",
        );
        if c.errors.len() > before {
            continue;
        }
        let lower = l.lower.unwrap_or(f64::NEG_INFINITY);
        let upper = l.upper.unwrap_or(f64::INFINITY);
        if lower >= upper {
            c.errors.push(SceneError::LimitRange {
                joint: j.name.clone(),
                coordinate: name,
                lower,
                upper,
                unit,
            });
            continue;
        }
        let value = j.kind.initial_number(name).unwrap_or(0.0);
        if !(lower <= value && value <= upper) {
            c.errors.push(SceneError::LimitOutside {
                joint: j.name.clone(),
                coordinate: name,
                value,
                lower,
                upper,
                unit,
            });
            continue;
        }
        out.push(ValidLimit {
            coordinate: k,
            lower,
            upper,
            stiffness: l.stiffness,
            cor,
        });
    }
    out
}
