//! Solver stage: options of the IDA integrator (plain data, no FFI).
//!
//! May touch only the standard library; [`super::ida`] translates these options into IDA calls
//! and validates them against the system size.

/// Absolute tolerance: one value for all components or one per component.
///
/// In the units of the corresponding component of `y`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Atol {
    /// The same absolute tolerance for every component (must be > 0).
    Scalar(f64),
    /// One absolute tolerance per component (length n, every entry > 0).
    Vector(Vec<f64>),
}

impl Default for Atol {
    fn default() -> Self {
        Atol::Scalar(1e-8)
    }
}

/// Options for [`super::Ida::new`]. Build with `IdaOptions::default()` and the builder methods,
/// or set the public fields directly.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct IdaOptions {
    /// Relative tolerance (dimensionless, > 0). Default 1e-6.
    pub rtol: f64,
    /// Absolute tolerance. Default `Atol::Scalar(1e-8)`.
    pub atol: Atol,
    /// Largest step size \[s\]; `None` = unlimited.
    pub max_step: Option<f64>,
    /// Largest number of internal steps per `solve` call (> 0). Default 100_000.
    pub max_num_steps: usize,
    /// Which components are differential (`true`) and which algebraic (`false`), for
    /// `IDASetId`; length n. `None` = all differential.
    pub differential: Option<Vec<bool>>,
    /// Leave algebraic components out of the local error test (`IDASetSuppressAlg`). Needs
    /// `differential`. Default false.
    pub suppress_algebraic_error: bool,
    /// Direction of root crossings to report, one per root function (`IDASetRootDirection`):
    /// +1 only increasing, -1 only decreasing, 0 both. `None` = both for all roots.
    pub root_directions: Option<Vec<i32>>,
    /// First step size to try \[s\]; `None` lets IDA estimate it.
    pub init_step: Option<f64>,
    /// Safety factor of the Newton convergence test (`IDASetNonlinConvCoef`), as a fraction of
    /// the local error tolerance; `None` keeps IDA's 0.33. Smaller values make every corrector
    /// solve more exact, which reduces the drift of invariants at tight tolerances.
    pub nonlinear_convergence_coefficient: Option<f64>,
    /// Largest BDF order, 1 to 5 (`IDASetMaxOrd`); `None` keeps IDA's 5.
    pub max_order: Option<i32>,
    /// Use the system's [`super::DaeSystem::jacobian_structure`], when it reports one, for a
    /// coloured difference-quotient Jacobian (default true); false = IDA's dense difference
    /// quotients, one residual evaluation per unknown.
    pub structured_jacobian: bool,
    /// With the coloured Jacobian and a system with [`super::DaeSystem::yp_jacobian`]: the
    /// iteration matrix for a new `c_j` from the last difference-quotient matrix's parts
    /// until Newton's method fails to converge (default true).
    pub jacobian_reuse: bool,
    /// With the coloured Jacobian: factor every component of the iteration matrix densely
    /// instead of choosing dense or block-sparse per component (default false).
    pub dense_lu: bool,
}

impl Default for IdaOptions {
    fn default() -> Self {
        IdaOptions {
            rtol: 1e-6,
            atol: Atol::default(),
            max_step: None,
            max_num_steps: 100_000,
            differential: None,
            suppress_algebraic_error: false,
            root_directions: None,
            init_step: None,
            nonlinear_convergence_coefficient: None,
            max_order: None,
            structured_jacobian: true,
            jacobian_reuse: true,
            dense_lu: false,
        }
    }
}

impl IdaOptions {
    /// Sets the relative tolerance (dimensionless).
    pub(crate) fn rtol(mut self, rtol: f64) -> Self {
        self.rtol = rtol;
        self
    }

    /// Sets one absolute tolerance for all components.
    pub(crate) fn atol(mut self, atol: f64) -> Self {
        self.atol = Atol::Scalar(atol);
        self
    }

    /// Sets one absolute tolerance per component (length n).
    pub(crate) fn atol_vector(mut self, atol: Vec<f64>) -> Self {
        self.atol = Atol::Vector(atol);
        self
    }

    /// Sets the largest step size \[s\] (`None` = unlimited).
    pub(crate) fn max_step(mut self, max_step: Option<f64>) -> Self {
        self.max_step = max_step;
        self
    }

    /// Sets the largest number of internal steps per `solve` call.
    pub(crate) fn max_num_steps(mut self, max_num_steps: usize) -> Self {
        self.max_num_steps = max_num_steps;
        self
    }

    /// Marks components as differential (`true`) or algebraic (`false`); length n.
    pub(crate) fn differential(mut self, differential: Vec<bool>) -> Self {
        self.differential = Some(differential);
        self
    }

    /// Sets the root crossing directions (+1 up, -1 down, 0 both), one per root function.
    pub(crate) fn root_directions(mut self, directions: Vec<i32>) -> Self {
        self.root_directions = Some(directions);
        self
    }

    /// Sets the first step size to try \[s\].
    pub(crate) fn init_step(mut self, h: Option<f64>) -> Self {
        self.init_step = h;
        self
    }
}
