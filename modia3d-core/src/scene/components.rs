//! Components with states in the scene's DAE (docs/drive-trains.md): the [`Component`]
//! trait every block implements (the library's own in [`crate::scene::blocks`] and the
//! user's), the description of their ports, and how an input is wired ([`Src`]). Plain data:
//! the runner is `dynamics/components.rs`.

use std::fmt;
use std::sync::Arc;

/// An input port of a component.
#[derive(Clone, Debug, PartialEq)]
pub struct PortSpec {
    /// Name (`u`, `u1`, `tau`, …).
    pub name: String,
    /// Unit, as text (`"1"` for a unit-free signal, `"N·m"`, …).
    pub unit: &'static str,
}

impl PortSpec {
    /// Port `name` in `unit`.
    pub fn new(name: impl Into<String>, unit: &'static str) -> Self {
        PortSpec {
            name: name.into(),
            unit,
        }
    }
}

/// An output of a component.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputSpec {
    /// Name (`y`, `motor_phi`, …); the result signal is `<component>.<name>`.
    pub name: String,
    /// Unit, as text.
    pub unit: &'static str,
    /// Whether the output depends on the component's inputs at the same instant (direct
    /// feedthrough: `Gain`'s `y = k·u`); an output that depends on states, time and flanges
    /// only (`Integrator`'s `y = x`) breaks algebraic loops.
    pub feedthrough: bool,
}

impl OutputSpec {
    /// Output `name` in `unit`, with or without direct `feedthrough`.
    pub fn new(name: impl Into<String>, unit: &'static str, feedthrough: bool) -> Self {
        OutputSpec {
            name: name.into(),
            unit,
            feedthrough,
        }
    }
}

/// A continuous state (in the solver's state vector, under its error control) or a discrete
/// state (constant between events) of a component.
#[derive(Clone, Debug, PartialEq)]
pub struct StateSpec {
    /// Name; the result signal is `<component>.<name>`.
    pub name: String,
    /// Unit, as text.
    pub unit: &'static str,
    /// Initial value, in its unit.
    pub start: f64,
    /// Its typical size, in its unit (> 0): its absolute tolerance is the run's `atol` times
    /// this (a motor current of amperes and an angle of radians are then judged alike).
    pub nominal: f64,
}

impl StateSpec {
    /// State `name` in `unit` starting at `start`, of typical size `nominal`.
    pub fn new(name: impl Into<String>, unit: &'static str, start: f64, nominal: f64) -> Self {
        StateSpec {
            name: name.into(),
            unit,
            start,
            nominal,
        }
    }
}

/// A flange of a component on a scalar coordinate of a joint: the component reads the
/// coordinate's position and velocity and adds a generalised force to its row.
#[derive(Clone, Debug, PartialEq)]
pub struct FlangeSpec {
    /// The joint's name.
    pub joint: String,
    /// The coordinate (`"phi"`, `"s"`, `"phi2"`, …); `None` for a joint with one scalar
    /// coordinate.
    pub coordinate: Option<String>,
    /// An inertia rigidly geared to the coordinate, reflected to it ([kg·m²] on an angle,
    /// \[kg\] on a translation; ≥ 0): it adds `inertia · q̈` to the coordinate's row, as an
    /// ideal gear's `N²·J_motor`, with no state of its own.
    pub inertia: f64,
}

/// The motion of a flange at one evaluation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FlangeMotion {
    /// Position of the coordinate \[rad\] or \[m\].
    pub position: f64,
    /// Its velocity [rad/s] or [m/s].
    pub velocity: f64,
    /// Its acceleration [rad/s²] or [m/s²], read only by a component that says so
    /// ([`Component::reads_flange_acceleration`]; 0 otherwise). In the residual it is the
    /// solver's trial value, so a force that depends on it is part of the implicit equations;
    /// an inertia rigidly geared to the flange is better stated as [`FlangeSpec::inertia`].
    pub acceleration: f64,
}

/// What a component sees at one evaluation (in the order of its specs).
#[derive(Clone, Copy, Debug)]
pub struct ComponentIo<'a> {
    /// Time \[s\].
    pub t: f64,
    /// Continuous states ([`Component::states`]).
    pub x: &'a [f64],
    /// Discrete states ([`Component::discrete_states`]), constant between events.
    pub d: &'a [f64],
    /// Input values ([`Component::inputs`]).
    pub u: &'a [f64],
    /// Flange motions ([`Component::flanges`]).
    pub flanges: &'a [FlangeMotion],
}

/// A component of the DAE: continuous states integrated with the mechanism under one error
/// control, inputs wired to other signals ([`Src`]), outputs, flanges on joint coordinates,
/// and optionally discrete states changed at time events and zero crossings. Its rows are
/// explicit, `ẋ = f(t, x, d, u, flanges)`; an inertia rigidly geared to a flange is stated
/// in [`FlangeSpec::inertia`]. The library's blocks ([`crate::scene::blocks`]) implement it
/// as a user's component does.
///
/// Every method must be a pure function of its arguments (the solver evaluates them at trial
/// points and in any order); a panic or a non-finite value ends the run with an error naming
/// the component and the time.
pub trait Component: fmt::Debug + Send + Sync {
    /// What it is, for messages (`"PI"`, `"Drive"`).
    fn kind(&self) -> &'static str;
    /// Its input ports, in the order of [`ComponentIo::u`].
    fn inputs(&self) -> Vec<PortSpec>;
    /// Its outputs, in the order [`Component::outputs_at`] fills them.
    fn outputs(&self) -> Vec<OutputSpec>;
    /// Its continuous states. Default: none.
    fn states(&self) -> Vec<StateSpec> {
        vec![]
    }
    /// Its discrete states. Default: none.
    fn discrete_states(&self) -> Vec<StateSpec> {
        vec![]
    }
    /// Its flanges. Default: none.
    fn flanges(&self) -> Vec<FlangeSpec> {
        vec![]
    }
    /// Whether it reads its flanges' accelerations ([`FlangeMotion::acceleration`]). Default:
    /// no (the start and the events then need no iteration for consistent accelerations).
    fn reads_flange_acceleration(&self) -> bool {
        false
    }
    /// Checks its parameters (finite, in range); `Err` says what is wrong and what to do.
    /// Default: nothing to check.
    fn check(&self) -> Result<(), String> {
        Ok(())
    }
    /// Fills `y` with the outputs. An output without feedthrough must not read `io.u`
    /// (it may be evaluated before the inputs are known).
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]);
    /// Fills `xdot` with the states' derivatives and `flange_forces` with the generalised
    /// forces on the flanges ([N·m] on an angle, \[N\] on a translation; positive drives the
    /// coordinate forwards). Default: nothing (no state, no flange).
    fn derivatives(&self, io: &ComponentIo<'_>, xdot: &mut [f64], flange_forces: &mut [f64]) {
        let _ = (io, xdot, flange_forces);
    }
    /// The first time event strictly after `t` \[s\] (a source's kink, a sampler's tick), with
    /// the discrete states `d`; the run stops there and calls [`Component::event`]. Default:
    /// none.
    fn next_time_event(&self, t: f64, d: &[f64]) -> Option<f64> {
        let _ = (t, d);
        None
    }
    /// Number of zero-crossing functions. Default: 0.
    fn n_crossings(&self) -> usize {
        0
    }
    /// Fills `z` (len [`Component::n_crossings`]) with functions that are positive while the
    /// discrete states hold and reach zero where they must change (a limiter's `u − y_max`
    /// while unsaturated…); the run locates the zero and calls [`Component::event`].
    /// Default: nothing.
    fn crossings(&self, io: &ComponentIo<'_>, z: &mut [f64]) {
        let _ = (io, z);
    }
    /// At a time event or a zero crossing of any component, and at the start: sets the new
    /// discrete states `d_new` (arriving as the old ones) from the signals at that instant.
    /// Default: nothing.
    fn event(&self, io: &ComponentIo<'_>, d_new: &mut [f64]) {
        let _ = (io, d_new);
    }
    /// Whether [`Component::jacobian`] gives this component's partial derivatives. Default:
    /// no. When every component of a scene says yes, the iteration matrix's columns of the
    /// components' states are formed from them by the chain rule through the signals
    /// (docs/drive-trains.md, "Jacobian"), exactly and without a residual evaluation per
    /// state; otherwise those columns are difference quotients of the residual. A component
    /// without states and inputs (a source) has none to give and needs not say so.
    fn provides_jacobian(&self) -> bool {
        false
    }
    /// Fills `jac` (every entry arrives as 0) with the partial derivatives of
    /// [`Component::derivatives`]' `xdot` and flange forces and of
    /// [`Component::outputs_at`]'s `y` with respect to the component's own continuous
    /// states `io.x` and inputs `io.u`, at `io` (discrete states and flange motions held):
    /// [`ComponentJacobian::f_x`] and the other setters. Called only if
    /// [`Component::provides_jacobian`]. An output without feedthrough has no `u` entries.
    /// Default: nothing.
    fn jacobian(&self, io: &ComponentIo<'_>, jac: &mut ComponentJacobian<'_>) {
        let _ = (io, jac);
    }
}

/// The partial derivatives [`Component::jacobian`] fills, dense, zero where not set. Indices
/// are in the order of the component's specs: `i` a state (`xdot[i]`), an output (`y[i]`) or a
/// flange; `j` a state (`x[j]`) or an input (`u[j]`). Setting an index outside the
/// component's sizes does nothing.
#[derive(Debug)]
pub struct ComponentJacobian<'a> {
    pub(crate) nx: usize,
    pub(crate) nu: usize,
    pub(crate) f_x: &'a mut [f64],
    pub(crate) f_u: &'a mut [f64],
    pub(crate) y_x: &'a mut [f64],
    pub(crate) y_u: &'a mut [f64],
    pub(crate) t_x: &'a mut [f64],
    pub(crate) t_u: &'a mut [f64],
}

impl ComponentJacobian<'_> {
    fn put(m: &mut [f64], cols: usize, i: usize, j: usize, v: f64) {
        if j < cols {
            if let Some(e) = m.get_mut(i * cols + j) {
                *e = v;
            }
        }
    }
    /// `∂ẋ_i/∂x_j` [state i's unit per second per state j's unit].
    pub fn f_x(&mut self, i: usize, j: usize, value: f64) {
        Self::put(self.f_x, self.nx, i, j, value);
    }
    /// `∂ẋ_i/∂u_j`.
    pub fn f_u(&mut self, i: usize, j: usize, value: f64) {
        Self::put(self.f_u, self.nu, i, j, value);
    }
    /// `∂y_i/∂x_j`.
    pub fn y_x(&mut self, i: usize, j: usize, value: f64) {
        Self::put(self.y_x, self.nx, i, j, value);
    }
    /// `∂y_i/∂u_j` (outputs with feedthrough only).
    pub fn y_u(&mut self, i: usize, j: usize, value: f64) {
        Self::put(self.y_u, self.nu, i, j, value);
    }
    /// `∂F_i/∂x_j`, `F_i` the generalised force on flange `i`.
    pub fn flange_x(&mut self, i: usize, j: usize, value: f64) {
        Self::put(self.t_x, self.nx, i, j, value);
    }
    /// `∂F_i/∂u_j`, `F_i` the generalised force on flange `i`.
    pub fn flange_u(&mut self, i: usize, j: usize, value: f64) {
        Self::put(self.t_u, self.nu, i, j, value);
    }
}

/// A function from the values of named signals and time to an input value.
pub type SrcFn = dyn Fn(f64, &[f64]) -> f64 + Send + Sync;

/// Where an input's value comes from.
#[derive(Clone)]
pub enum Src {
    /// A constant.
    Const(f64),
    /// Another signal by path: a component's output or state (`"pi.y"`, `"servo.drive.motor_w"`),
    /// a joint coordinate's position or velocity (`"rev.phi"`, `"rev.w"`, `"slide.s"`), its
    /// acceleration as the derivative of its velocity (`"der(rev.w)"`, [rad/s²] or [m/s²]), or
    /// `"time"` \[s\].
    Signal(String),
    /// A function of time \[s\] and the values of the signals `deps` (in that order).
    Expr {
        /// The signals it reads, by path (as [`Src::Signal`]).
        deps: Vec<String>,
        /// `f(t, values)`.
        f: Arc<SrcFn>,
    },
}

impl Src {
    /// Another signal by path.
    pub fn signal(path: &str) -> Self {
        Src::Signal(path.to_string())
    }
    /// A function `f(t, values)` of time and the signals `deps`.
    pub fn expr(deps: &[&str], f: impl Fn(f64, &[f64]) -> f64 + Send + Sync + 'static) -> Self {
        Src::Expr {
            deps: deps.iter().map(|s| s.to_string()).collect(),
            f: Arc::new(f),
        }
    }
    /// The signals it reads.
    pub fn deps(&self) -> Vec<&str> {
        match self {
            Src::Const(_) => vec![],
            Src::Signal(s) => vec![s.as_str()],
            Src::Expr { deps, .. } => deps.iter().map(String::as_str).collect(),
        }
    }
}

impl From<f64> for Src {
    fn from(v: f64) -> Self {
        Src::Const(v)
    }
}

impl From<&str> for Src {
    fn from(s: &str) -> Self {
        Src::signal(s)
    }
}

impl fmt::Debug for Src {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Src::Const(v) => write!(f, "Const({v})"),
            Src::Signal(s) => write!(f, "Signal({s:?})"),
            Src::Expr { deps, .. } => write!(f, "Expr(deps = {deps:?})"),
        }
    }
}

/// A component of a scene with its name and its inputs' wiring.
#[derive(Clone, Debug)]
pub struct ComponentDecl {
    /// Name, the prefix of its signals (`"servo.ppi.PI"`: dots nest assemblies).
    pub name: String,
    /// The component.
    pub component: Arc<dyn Component>,
    /// Each input port's source, by port name.
    pub inputs: Vec<(String, Src)>,
}

impl ComponentDecl {
    /// Component `component` named `name`, its inputs not yet wired.
    pub fn new(name: &str, component: impl Component + 'static) -> Self {
        ComponentDecl {
            name: name.to_string(),
            component: Arc::new(component),
            inputs: vec![],
        }
    }
    /// Wires input port `port` to `src`.
    pub fn input(mut self, port: &str, src: impl Into<Src>) -> Self {
        self.inputs.push((port.to_string(), src.into()));
        self
    }
}
