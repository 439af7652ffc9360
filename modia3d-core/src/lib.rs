//! modia3d-core: scenes, multibody dynamics, contacts and the IDA solver wrapper.
#![warn(missing_docs)]
// Only the solver stage's FFI module (solver/ida.rs) may use `unsafe`; it opts back in explicitly.
#![deny(unsafe_code)]

pub mod geometry;
pub mod solver;
