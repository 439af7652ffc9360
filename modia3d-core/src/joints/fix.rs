//! Fix joint: obj2's frame coincides with obj1's. The two objects are one rigid body
//! (`scene/topology.rs` merges them), so the joint has no coordinates and is never in the
//! tree: its tree data [`Coord`] is uninhabited, and every dynamics function is unreachable by
//! type. Cut to close a loop it locks all six directions.

use super::{AxisParam, Checker, Facts, InitialParam, JointKindSpec};
#[cfg(feature = "solver")]
use super::{KindDynamics, Row};
#[cfg(feature = "solver")]
use crate::spatial::{Force, Motion, Transform};
#[cfg(feature = "solver")]
use nalgebra::Vector3;

/// A validated Fix joint: nothing to validate.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Valid;

/// A Fix joint in the tree: none (uninhabited).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Coord {}

/// No parameters, no coordinates; rigid.
pub(crate) const FACTS: Facts = Facts {
    spec: JointKindSpec {
        name: "Fix",
        axes: &[] as &[AxisParam],
        initial: &[] as &[InitialParam],
        coordinates: &[],
        at_rest: |_| crate::JointKind::Fix,
    },
    nq: 0,
    nv: 0,
    signals: &[],
    turning: &[],
    shifting: &[],
    reversed: None,
    rigid: true,
    connects: true,
    modia3d_can_collide: false,
    hinge: false,
};

/// Validation of the builder's parameters: none.
pub(crate) fn validate(_c: &mut Checker, _joint: &str) -> Valid {
    Valid
}

#[cfg(feature = "solver")]
impl KindDynamics for Coord {
    type Valid = Valid;
    fn new(_: &Valid, _: bool, _: &mut Vec<f64>, _: &mut Vec<f64>) -> Coord {
        unreachable!("fix joints are merged")
    }
    /// All six: the three translations and the three rotations.
    fn locked_rows(_: &Valid) -> Vec<Row> {
        let mut r = Row::translations(&[Vector3::x(), Vector3::y(), Vector3::z()]);
        r.extend(Row::rotations());
        r
    }
    fn drawn_axis(_: &Valid) -> Option<(&'static str, Vector3<f64>)> {
        None
    }
    fn has_bias(&self) -> bool {
        match *self {}
    }
    fn free_velocities(&self) -> Option<bool> {
        match *self {}
    }
    fn resolve_in_obj1(&mut self, _: &[f64], _: &mut [f64]) -> bool {
        match *self {}
    }
    fn transform(&self, _: &[f64]) -> Transform {
        match *self {}
    }
    fn motion(&self, _: &[f64], _: &[f64]) -> Motion {
        match *self {}
    }
    fn motion_at(&self, _: &Transform, _: &[f64], _: &[f64]) -> Motion {
        match *self {}
    }
    fn bias(&self, _: &[f64], _: &[f64], _: &Motion) -> Motion {
        match *self {}
    }
    fn project(&self, _: &[f64], _: &Force, _: &mut [f64]) {
        match *self {}
    }
    fn project_at(&self, _: &Transform, _: &[f64], _: &Force, _: &mut [f64]) {
        match *self {}
    }
    fn position_residual(&self, _: &[f64], _: &[f64], _: &[f64], _: &mut [f64]) {
        match *self {}
    }
    fn derived_signal(&self, _: &str, _: &[f64], _: &[f64], _: &mut Vec<f64>) -> Option<()> {
        match *self {}
    }
}
