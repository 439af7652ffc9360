//! modia3d: 3D multibody models written as Rust, simulated with SUNDIALS IDA.
#![warn(missing_docs)]
pub use modia3d_core as core;
