//! Builder types of the force elements after Modia3D (`Bushing`, `SpringDamperPtP`,
//! `WorldForce`, `WorldTorque`) and of the gravity field: scalar and vector force laws as
//! constants or closures, and the user force closures' vocabulary (`ObjectMotion` in, `Wrench`
//! out, `ForceFn`). Plain data like the rest of `desc.rs`, which uses them; validation checks
//! it.

use nalgebra::{Matrix3, Vector3};
use std::fmt;
use std::sync::Arc;

/// The closure type behind [`Law::Fn`]: a force \[N\] or torque [N·m] from one scalar
/// (a deflection [m or rad] or its rate [m/s or rad/s]).
pub type ScalarLaw = dyn Fn(f64) -> f64 + Send + Sync;

/// A one-dimensional force law: a linear coefficient or a closure (Modia3D's "a `Real` number
/// represents a linear coefficient, a univariate `Function` computes the force").
#[derive(Clone)]
pub enum Law {
    /// `c · x`: a stiffness ([N/m], [N·m/rad]) or a damping ([N·s/m], [N·m·s/rad]).
    Linear(f64),
    /// `f(x)`, e.g. a cubic spring `|x| 100.0 * x + 1e4 * x.powi(3)`.
    Fn(Arc<ScalarLaw>),
}

impl Law {
    /// A law given by a closure.
    pub fn new(f: impl Fn(f64) -> f64 + Send + Sync + 'static) -> Self {
        Law::Fn(Arc::new(f))
    }
    /// The linear coefficient, `None` for a closure.
    pub fn coefficient(&self) -> Option<f64> {
        match self {
            Law::Linear(c) => Some(*c),
            Law::Fn(_) => None,
        }
    }
    /// Whether this law is the linear law `0 · x` (the element's axis is free).
    pub fn is_zero(&self) -> bool {
        matches!(self, Law::Linear(c) if *c == 0.0)
    }
}

impl Default for Law {
    fn default() -> Self {
        Law::Linear(0.0)
    }
}

impl From<f64> for Law {
    fn from(c: f64) -> Self {
        Law::Linear(c)
    }
}

impl fmt::Debug for Law {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Law::Linear(c) => write!(f, "Linear({c})"),
            Law::Fn(_) => f.write_str("Fn(..)"),
        }
    }
}

/// The closure type behind [`VectorLaw::Fn`]: time \[s\] and the motion of the object acted on
/// → a vector resolved in the element's `resolved_in` frame.
pub type VectorLawFn = dyn Fn(f64, &ObjectMotion) -> Vector3<f64> + Send + Sync;

/// The value of a [`WorldForce`](super::ForceElement::WorldForce) \[N\] or
/// [`WorldTorque`](super::ForceElement::WorldTorque) [N·m]: a constant or a closure.
#[derive(Clone)]
pub enum VectorLaw {
    /// A constant vector.
    Constant(Vector3<f64>),
    /// A closure of time \[s\] and the object's motion.
    Fn(Arc<VectorLawFn>),
}

impl VectorLaw {
    /// A law given by a closure of time \[s\] and the object's motion.
    pub fn new(f: impl Fn(f64, &ObjectMotion) -> Vector3<f64> + Send + Sync + 'static) -> Self {
        VectorLaw::Fn(Arc::new(f))
    }
}

impl From<Vector3<f64>> for VectorLaw {
    fn from(v: Vector3<f64>) -> Self {
        VectorLaw::Constant(v)
    }
}

impl From<[f64; 3]> for VectorLaw {
    fn from(v: [f64; 3]) -> Self {
        VectorLaw::Constant(Vector3::from(v))
    }
}

impl fmt::Debug for VectorLaw {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            VectorLaw::Constant(v) => write!(f, "Constant({}, {}, {})", v.x, v.y, v.z),
            VectorLaw::Fn(_) => f.write_str("Fn(..)"),
        }
    }
}

/// A six-axis bushing between the frames of `obj1` and `obj2` (Modia3D's `Bushing`).
///
/// Translation: the position `r` of obj2's origin relative to obj1's, resolved in obj1 \[m\],
/// and its rate as seen in obj1 [m/s]; per axis `i` of obj1 the force
/// `f_i = nominal_force_i + spring_i(r_i) + damper_i(ṙ_i)` \[N\]. It acts on obj1 (at obj2's
/// origin, so the pair is moment-free) and `−f` on obj2, both along obj1's axes: positive
/// values push obj1 in its positive axis directions and pull obj2 back.
///
/// Rotation: three angles `(α, β, γ)` of obj2 relative to obj1 and their rates; per angle the
/// moment `m_i = nominal_torque_i + rot_spring_i(angle_i) + rot_damper_i(rate_i)` [N·m].
/// * `large_angles = false` (default; Modia3D's small-angle mode, for deflections under about
///   10°): `α = R[2,1]`, `β = R[0,2]`, `γ = R[1,0]` of the relative rotation `R` (columns:
///   obj2's axes in obj1; equal to the angles to first order), rates = the relative angular
///   velocity resolved in obj1, torque `−m` on obj2 about obj1's axes.
/// * `large_angles = true`: Cardan angles x-y-z from obj1 to obj2 (as `Rotation::Cardan`), their
///   exact rates, and the torque `τ = J⁻ᵀ m` with `ω = J (α̇, β̇, γ̇)`: the moments are the
///   generalised forces of the angles, so a spring law with a potential conserves energy at
///   any angle. Singular at `β = ±90°`: a run reaching `|cos β| < 1e-6` stops with
///   `SimErrorKind::SingularForceElement` naming the bushing. Modia3D applies `τ = J m`
///   (each moment about its rotation axis) instead; the two agree when only one angle is
///   deflected or `β = 0`, and `J m` does not conserve energy in general (docs/force-elements.md).
///
/// Signals (`<name>.<field>`): `r` \[m\], `v` [m/s], `angles` \[rad\], `rates` [rad/s],
/// `force` \[N\] and `torque` [N·m] on obj2, resolved in obj1.
#[derive(Clone, Debug)]
pub struct Bushing {
    /// Name (signals `<name>.force`, …; unique among objects, joints and force elements).
    pub name: String,
    /// The object whose frame defines the axes.
    pub obj1: String,
    /// The second object.
    pub obj2: String,
    /// Force when spring and damper forces are zero, along obj1's axes \[N\].
    pub nominal_force: Vector3<f64>,
    /// Spring laws per axis x, y, z of obj1: force \[N\] from the deflection \[m\].
    pub spring: [Law; 3],
    /// Damper laws per axis: force \[N\] from the deflection rate [m/s].
    pub damper: [Law; 3],
    /// Moments when the rotational laws give zero [N·m].
    pub nominal_torque: Vector3<f64>,
    /// Rotational spring laws per angle α, β, γ: moment [N·m] from the angle \[rad\].
    pub rot_spring: [Law; 3],
    /// Rotational damper laws per angle: moment [N·m] from the angle's rate [rad/s].
    pub rot_damper: [Law; 3],
    /// Cardan-angle formulation (see the type's docs); default `false`.
    pub large_angles: bool,
}

impl Bushing {
    /// A bushing with every law zero (no force) between `obj1` and `obj2`.
    pub fn new(name: &str, obj1: &str, obj2: &str) -> Self {
        Bushing {
            name: name.into(),
            obj1: obj1.into(),
            obj2: obj2.into(),
            nominal_force: Vector3::zeros(),
            spring: Default::default(),
            damper: Default::default(),
            nominal_torque: Vector3::zeros(),
            rot_spring: Default::default(),
            rot_damper: Default::default(),
            large_angles: false,
        }
    }
    /// Linear stiffnesses per axis [N/m].
    pub fn stiffness(mut self, k: [f64; 3]) -> Self {
        self.spring = k.map(Law::Linear);
        self
    }
    /// Linear dampings per axis [N·s/m].
    pub fn damping(mut self, d: [f64; 3]) -> Self {
        self.damper = d.map(Law::Linear);
        self
    }
    /// Linear rotational stiffnesses per angle [N·m/rad].
    pub fn rot_stiffness(mut self, k: [f64; 3]) -> Self {
        self.rot_spring = k.map(Law::Linear);
        self
    }
    /// Linear rotational dampings per angle [N·m·s/rad].
    pub fn rot_damping(mut self, d: [f64; 3]) -> Self {
        self.rot_damper = d.map(Law::Linear);
        self
    }
    /// Sets the Cardan-angle formulation.
    pub fn large_angles(mut self, on: bool) -> Self {
        self.large_angles = on;
        self
    }
}

impl From<Bushing> for super::ForceElement {
    fn from(b: Bushing) -> Self {
        super::ForceElement::Bushing(Box::new(b))
    }
}

/// The gravity field of a scene ([`SceneOptions::gravity_field`](super::SceneOptions)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GravityField {
    /// The same acceleration for every body, resolved in world [m/s²].
    Uniform(Vector3<f64>),
    /// No gravity.
    None,
    /// Point gravity of a central body: the acceleration `−μ r/|r|³` at each body's centre of
    /// mass, `r` its position relative to `centre`.
    Point {
        /// Gravitational parameter `μ = G M` [m³/s²] (Earth: 3.986004418e14), > 0.
        mu: f64,
        /// Position of the attracting centre, resolved in world \[m\].
        centre: Vector3<f64>,
    },
}

/// Position and velocity of an object, handed to user force closures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectMotion {
    /// Position of the object's origin, resolved in world \[m\].
    pub r_abs: Vector3<f64>,
    /// Rotation matrix: columns are the object's axes resolved in world.
    pub rot_abs: Matrix3<f64>,
    /// Velocity of the object's origin, resolved in world [m/s].
    pub v_abs: Vector3<f64>,
    /// Angular velocity, resolved in world [rad/s].
    pub w_abs: Vector3<f64>,
}

/// A force \[N\] and a torque [N·m], both resolved in world, acting at an object's origin.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Wrench {
    /// Force, resolved in world \[N\].
    pub force: Vector3<f64>,
    /// Torque, resolved in world [N·m].
    pub torque: Vector3<f64>,
}

/// A user force law: time \[s\] and the object's motion → wrench at the object's origin.
#[derive(Clone)]
pub struct ForceFn(pub Arc<ForceLaw>);

/// The closure type behind [`ForceFn`].
pub type ForceLaw = dyn Fn(f64, &ObjectMotion) -> Wrench + Send + Sync;

impl ForceFn {
    /// Wraps a closure.
    pub fn new(f: impl Fn(f64, &ObjectMotion) -> Wrench + Send + Sync + 'static) -> Self {
        ForceFn(Arc::new(f))
    }
}

impl fmt::Debug for ForceFn {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("ForceFn(..)")
    }
}
