//! modia3d-core: scenes, multibody dynamics, contacts and the IDA solver wrapper.
//!
//! Cargo feature `solver` (default) builds every stage; without it only the solver-free stages
//! compile — [`scene`] (description, materials, validation) and [`geometry`] — so the `model!`
//! macro can run the same scene checks at compile time without building SUNDIALS.
#![warn(missing_docs)]
#![warn(unreachable_pub)]
// Only the solver stage's FFI module `solver::ida` (solver/ida.rs with its children ida/callbacks.rs
// and ida/linear.rs) may use `unsafe`; `mod ida` opts back in explicitly.
#![deny(unsafe_code)]

// The public surface is the crate root's re-exports below plus the two stage modules a user
// may call directly: `scene` (the builder types, materials, scene errors) and `geometry`
// (shapes and collision queries). The pipeline's inner stages — contact, DAE, dynamics, the
// IDA wrapper — are internal, so changing them is never a breaking change; their tests are
// unit tests inside the crate.
// Bench hooks for examples/contact_cost.rs: not part of the supported API.
#[cfg(feature = "solver")]
#[doc(hidden)]
pub mod bench;
pub mod build_profile;
#[cfg(feature = "solver")]
mod contact;
#[cfg(feature = "solver")]
mod dae;
#[cfg(feature = "solver")]
mod dynamics;
pub mod geometry;
mod joints;
#[cfg(feature = "solver")]
mod model;
#[cfg(feature = "solver")]
mod results;
pub mod scene;
#[cfg(feature = "solver")]
mod simulation;
// Spatial (6D) algebra: vocabulary of `joints/`, `dynamics/`, `contact/` and `dae/`, so it sits
// below all of them (it imports nothing of the crate).
#[cfg(feature = "solver")]
mod spatial;
#[cfg(feature = "solver")]
mod sweep;
// The safe IDA wrapper is complete (vector tolerances, both `IDACalcIC` modes, recoverable
// residual errors, …) and every part of it is tested in `solver/tests`; the multibody DAE uses
// a subset, so the rest is unused outside the tests.
#[cfg(feature = "solver")]
#[cfg_attr(not(test), allow(dead_code))]
mod solver;

/// Test builds only: the unit tests' deterministic pseudo-random numbers (xorshift64, the
/// same sequences the tests used when each had its own copy). Only the solver stages' tests
/// use them.
#[cfg(all(test, feature = "solver"))]
pub(crate) mod test_rng {
    /// The raw xorshift64 sequence from `seed` (non-zero).
    pub(crate) fn bits(seed: u64) -> impl FnMut() -> u64 {
        let mut x = seed;
        move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        }
    }

    /// Uniform numbers in [−0.5, 0.5) from the top 53 bits of [`bits`].
    pub(crate) fn uniform(seed: u64) -> impl FnMut() -> f64 {
        let mut next = bits(seed);
        move || (next() >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}

// Test builds only: counts allocations per thread, for the "hot path allocates nothing" tests
// (the DAE's, a solver stage).
#[cfg(all(test, feature = "solver"))]
#[allow(unsafe_code)]
#[path = "../tests/common/counting_alloc.rs"]
mod counting_alloc;

#[cfg(feature = "solver")]
pub use contact::{ContactError, DEFAULT_STOP_FREQUENCY};
pub use geometry::{
    Axis, MeshCollision, Shape, ShapeKindSpec, ShapeParam, ShapeValue, ShapeValues, SHAPE_KINDS,
};
pub use joints::{
    AxisOf, AxisParam, InitialParam, JointCoordinate, JointKindSpec, LimitKeys, ParamValue,
    JOINT_KINDS,
};
#[cfg(feature = "solver")]
pub use model::{BodyInfo, ContactPairInfo, LoopInfo, Model};
#[cfg(feature = "solver")]
pub use results::{
    ContactPhase, Event, JointLoadPeak, PlotFormat, PlotOptions, ResultError, Signal, SimStats,
    SimWarning, SimulationResult, EVENT_MARKER_COLOR,
};
pub use scene::{
    block_kind, BlockKindSpec, BlockOutput, BlockParam, BlockValue, BlockVariant, BlockVariants,
    BLOCK_KINDS,
};
pub use scene::{
    blocks, Component, ComponentDecl, ComponentIo, ComponentJacobian, FlangeMotion, FlangeSpec,
    OutputSpec, PortSpec, Src, SrcFn, StateSpec,
};
pub use scene::{
    Action, ActionKind, ContactPairMaterial, ContactProfile, Feature, ForceElement, ForceFn,
    FreeRotation, Input, InputKind, Joint, JointKind, JointLimit, MassSpec, MaterialPalette,
    MaterialRef, Object3D, ObjectMotion, Rotation, SceneDesc, SceneError, SceneErrors,
    SceneOptions, Solid, SolidMaterial, Wrench,
};
pub use scene::{Bushing, GravityField, Law, VectorLaw};
#[cfg(feature = "solver")]
pub use simulation::{
    ActionError, Budget, InputError, SimError, SimErrorKind, SimOptions, Simulation, SlowCause,
    WorkDiagnosis, CHATTER_EVENTS, CHATTER_SPAN, DEFAULT_CONTACT_TIGHTENING, DEFAULT_MAX_STEPS,
    LOOSEST_CONTACT_RTOL, MAX_OUTPUT_POINTS, TOO_DEEP_STEP, TOO_DEEP_STEPS,
};
#[cfg(feature = "solver")]
pub use solver::{IdaError, IdaStats};
#[cfg(feature = "solver")]
pub use sweep::{
    linspace, sweep_main, BoxError, ColumnInfo, Distribution, MetricFn, ModelFn, ParamPoints,
    Params, RunError, Sweep, SweepError, SweepRegistry, SweepRow, SweepSpec, SweepTable,
    MAX_POINTS,
};
