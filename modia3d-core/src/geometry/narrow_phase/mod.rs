//! Narrow phase: signed distance, contact normal and witness points of two collision shapes
//! (geometry stage; touches nothing else).
//!
//! [`signed_distance`] (in `dispatch.rs`) is the single entry point; it picks an exact closed
//! form (`closed_form.rs`) or the improved MPR (`mpr.rs`) by the two shape kinds.

mod closed_form;
mod contact_point;
mod curved;
mod dispatch;
mod gjk_distance;
mod mpr;

pub use contact_point::{contact_patch, contact_point, ContactPatch};
pub use dispatch::{exact, signed_distance, signed_distance_method};

use nalgebra::{Point3, Vector3};

/// Result of a narrow-phase query between shape `a` and shape `b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SignedDistance {
    /// Signed distance \[m\]: > 0 separated (Euclidean distance), < 0 penetrating (depth).
    pub distance: f64,
    /// Unit contact normal pointing from `a` to `b`, resolved in world.
    pub normal: Vector3<f64>,
    /// Witness point on the surface of `a`, resolved in world \[m\].
    pub point_a: Point3<f64>,
    /// Witness point on the surface of `b`, resolved in world \[m\];
    /// `point_b − point_a = distance · normal` up to the algorithm's tolerance.
    pub point_b: Point3<f64>,
}

impl SignedDistance {
    /// The same contact seen from the other shape (normal reversed, points swapped).
    #[inline]
    pub fn flipped(self) -> Self {
        SignedDistance {
            distance: self.distance,
            normal: -self.normal,
            point_a: self.point_b,
            point_b: self.point_a,
        }
    }
}

/// Which algorithm the narrow phase used (for tests and statistics).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// An exact closed form.
    ClosedForm,
    /// MPR alone (cores penetrating, or `exact_separation == false`).
    Mpr,
    /// MPR found the cores separated; their distance was then made exact by GJK.
    MprThenGjk,
    /// MPR hit a degenerate case; parry's GJK/EPA on the cores gave the answer.
    Fallback,
    /// MPR's refinement or GJK stopped at [`NarrowPhaseOptions::max_iterations`] before
    /// meeting the tolerance; the best iterate is returned (for MPR a lower bound of the
    /// signed distance). The collision stage counts these (`SimStats::narrow_phase_limits`)
    /// and warns once per pair.
    IterationLimit,
}

/// Tolerances and switches of the narrow phase.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NarrowPhaseOptions {
    /// MPR stops when the support point in the portal normal lies less than
    /// `mpr_tolerance · size` beyond the portal, `size` being the sum of the two bounding radii
    /// \[m\]; GJK (separated cores) stops when its certified gap is below the same length.
    /// Default 1e-11: about 50 ulps of the size, so the tests still stop reliably in floating
    /// point, while the error they admit is far below any contact stiffness scale.
    pub mpr_tolerance: f64,
    /// Maximum number of MPR refinement (and of GJK) iterations (default 100). When reached, MPR
    /// returns its current estimate, which is still a lower bound of the signed distance, and
    /// GJK its best certified iterate.
    pub max_iterations: u32,
    /// When MPR finds the *cores* separated (which is the case for every penetration of smoothed
    /// shapes shallower than the sum of their margins), compute the exact core distance by GJK
    /// started from MPR's normal (default `true`). With `false` the MPR estimate `−h(n)` along the
    /// final portal normal is returned: a lower bound, exact where the closest features lie on
    /// the centre ray.
    pub exact_separation: bool,
    /// Use MPR even where a closed form exists (for testing MPR; default `false`).
    pub force_mpr: bool,
}

impl Default for NarrowPhaseOptions {
    fn default() -> Self {
        NarrowPhaseOptions {
            mpr_tolerance: 1e-11,
            max_iterations: 100,
            exact_separation: true,
            force_mpr: false,
        }
    }
}

pub use mpr::mpr_signed_distance;
