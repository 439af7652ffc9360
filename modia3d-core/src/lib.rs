//! modia3d-core: scenes, multibody dynamics, contacts and the IDA solver wrapper.
#![warn(missing_docs)]

pub mod geometry;
pub mod solver;
