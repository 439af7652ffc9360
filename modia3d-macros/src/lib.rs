//! The `model!` macro of modia3d.
