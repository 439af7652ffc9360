//! Spatial (6D) vector algebra as pairs of 3-vectors (Featherstone's notation), used by the
//! recursive algorithms. A motion vector is `(ω, v)`: angular velocity and the linear velocity
//! of the point at the frame origin; a force vector is `(n, f)`: moment about the frame origin and
//! force. Both are resolved in the frame they belong to.

use nalgebra::{Matrix3, Vector3};

/// A spatial motion vector `(ω, v)` resolved in some frame ([rad/s], [m/s] or their rates).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Motion {
    /// Angular part.
    pub w: Vector3<f64>,
    /// Linear part (of the point at the frame origin).
    pub v: Vector3<f64>,
}

/// A spatial force vector `(n, f)` resolved in some frame ([N·m], \[N\]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Force {
    /// Moment about the frame origin.
    pub n: Vector3<f64>,
    /// Force.
    pub f: Vector3<f64>,
}

impl Motion {
    /// The zero motion.
    pub(crate) fn zero() -> Self {
        Self::default()
    }
    /// Motion cross product `self ×ₘ m`.
    #[inline]
    pub(crate) fn cross_motion(&self, m: &Motion) -> Motion {
        Motion {
            w: self.w.cross(&m.w),
            v: self.w.cross(&m.v) + self.v.cross(&m.w),
        }
    }
    /// Force cross product `self ×f f`.
    #[inline]
    pub(crate) fn cross_force(&self, f: &Force) -> Force {
        Force {
            n: self.w.cross(&f.n) + self.v.cross(&f.f),
            f: self.w.cross(&f.f),
        }
    }
}

impl std::ops::Add for Motion {
    type Output = Motion;
    #[inline]
    fn add(self, o: Motion) -> Motion {
        Motion {
            w: self.w + o.w,
            v: self.v + o.v,
        }
    }
}

impl std::ops::Add for Force {
    type Output = Force;
    #[inline]
    fn add(self, o: Force) -> Force {
        Force {
            n: self.n + o.n,
            f: self.f + o.f,
        }
    }
}

impl std::ops::Sub for Force {
    type Output = Force;
    #[inline]
    fn sub(self, o: Force) -> Force {
        Force {
            n: self.n - o.n,
            f: self.f - o.f,
        }
    }
}

/// Placement of a child frame in its parent: `rot` has the child's axes resolved in the parent
/// as columns, `pos` is the child's origin resolved in the parent \[m\].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Transform {
    /// Child axes resolved in the parent.
    pub rot: Matrix3<f64>,
    /// Child origin resolved in the parent \[m\].
    pub pos: Vector3<f64>,
}

impl Default for Transform {
    fn default() -> Self {
        Transform {
            rot: Matrix3::identity(),
            pos: Vector3::zeros(),
        }
    }
}

impl Transform {
    /// Parent motion → child motion (Featherstone's `X m`).
    #[inline]
    pub(crate) fn motion_to_child(&self, m: &Motion) -> Motion {
        Motion {
            w: self.rot.tr_mul(&m.w),
            v: self.rot.tr_mul(&(m.v + m.w.cross(&self.pos))),
        }
    }
    /// Child force → parent force (Featherstone's `Xᵀ f`).
    #[inline]
    pub(crate) fn force_to_parent(&self, f: &Force) -> Force {
        let fp = self.rot * f.f;
        Force {
            n: self.rot * f.n + self.pos.cross(&fp),
            f: fp,
        }
    }
    /// Composition: `self` (child in parent) followed by `c` (grandchild in child).
    #[inline]
    pub(crate) fn then(&self, c: &Transform) -> Transform {
        Transform {
            rot: self.rot * c.rot,
            pos: self.pos + self.rot * c.pos,
        }
    }
}

/// Rigid-body inertia about a frame origin: mass \[kg\], centre of mass \[m\] and inertia about the
/// centre of mass [kg·m²], resolved in that frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Inertia {
    /// Mass \[kg\].
    pub mass: f64,
    /// Centre of mass \[m\].
    pub com: Vector3<f64>,
    /// Inertia about the centre of mass [kg·m²].
    pub inertia_com: Matrix3<f64>,
}

impl Inertia {
    /// No mass.
    pub(crate) fn zero() -> Self {
        Inertia {
            mass: 0.0,
            com: Vector3::zeros(),
            inertia_com: Matrix3::zeros(),
        }
    }
    /// Spatial momentum `I m` of a motion.
    #[inline]
    pub(crate) fn mul_motion(&self, m: &Motion) -> Force {
        let lin = (m.v + m.w.cross(&self.com)) * self.mass;
        Force {
            n: self.inertia_com * m.w + self.com.cross(&lin),
            f: lin,
        }
    }
    /// The velocity-product force `v ×f (I v)` of a body moving with `m`. Equal to
    /// `m.cross_force(&self.mul_motion(m))`, but the term `v × (mass·v)`, zero in exact
    /// arithmetic, is left out exactly instead of being formed from two rounded products: its
    /// rounding (~mass·|v|²·1e-16) lands in the torque rows, where for a small body it
    /// dwarfs the inertia terms (a 3 µm sphere drifting at 0.1 m/s: a torque noise of 1e-31
    /// N·m against an inertia of 1e-25 kg·m², and IDA needed 650,000 steps for 0.3 s).
    #[inline]
    pub(crate) fn bias_force(&self, m: &Motion) -> Force {
        let wc = m.w.cross(&self.com);
        let lin = (m.v + wc) * self.mass;
        let n_h = self.inertia_com * m.w + self.com.cross(&lin);
        Force {
            n: m.w.cross(&n_h) + m.v.cross(&wc) * self.mass,
            f: m.w.cross(&lin),
        }
    }
    /// Adds `other`, given in a frame placed at `x` in this frame (parallel-axis theorem).
    pub(crate) fn add_transformed(&self, other: &Inertia, x: &Transform) -> Inertia {
        let m = self.mass + other.mass;
        if m == 0.0 {
            return Inertia::zero();
        }
        let c2 = x.pos + x.rot * other.com;
        let com = (self.com * self.mass + c2 * other.mass) / m;
        let shift = |mass: f64, d: Vector3<f64>| {
            (Matrix3::identity() * d.dot(&d) - d * d.transpose()) * mass
        };
        let inertia_com = self.inertia_com
            + shift(self.mass, self.com - com)
            + x.rot * other.inertia_com * x.rot.transpose()
            + shift(other.mass, c2 - com);
        Inertia {
            mass: m,
            com,
            inertia_com,
        }
    }
}

/// Rotation matrix of `angle` \[rad\] about the unit vector `axis`.
#[inline]
pub(crate) fn axis_angle(axis: &Vector3<f64>, angle: f64) -> Matrix3<f64> {
    let (s, c) = angle.sin_cos();
    let k = axis.cross_matrix();
    Matrix3::identity() + k * s + k * k * (1.0 - c)
}

/// Rotation matrix of the quaternion `(w, x, y, z)` after normalising it.
#[inline]
pub(crate) fn quat_to_matrix(q: &[f64]) -> Matrix3<f64> {
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    let (w, x, y, z) = (q[0] / n, q[1] / n, q[2] / n, q[3] / n);
    Matrix3::new(
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y - w * z),
        2.0 * (x * z + w * y),
        2.0 * (x * y + w * z),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z - w * x),
        2.0 * (x * z - w * y),
        2.0 * (y * z + w * x),
        1.0 - 2.0 * (x * x + y * y),
    )
}

/// `½ q ⊗ (0, ω)`: the derivative of the quaternion `q = (w, x, y, z)` for the angular velocity
/// `ω` resolved in the rotated (body) frame.
#[inline]
pub(crate) fn quat_rate(q: &[f64], w: &Vector3<f64>) -> [f64; 4] {
    [
        0.5 * (-q[1] * w.x - q[2] * w.y - q[3] * w.z),
        0.5 * (q[0] * w.x + q[2] * w.z - q[3] * w.y),
        0.5 * (q[0] * w.y + q[3] * w.x - q[1] * w.z),
        0.5 * (q[0] * w.z + q[1] * w.y - q[2] * w.x),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{UnitQuaternion, Vector3};

    #[test]
    fn quaternion_helpers_match_nalgebra() {
        let uq = UnitQuaternion::from_euler_angles(0.3, -1.1, 2.0);
        let q = [uq.w, uq.i, uq.j, uq.k];
        assert!((quat_to_matrix(&q) - uq.to_rotation_matrix().into_inner()).norm() < 1e-14);
        // q̇ = ½ q ⊗ (0, ω): compare with a finite difference of q ⊗ exp(ω h / 2).
        let w = Vector3::new(0.4, -0.7, 1.3);
        let h = 1e-7;
        let q2 = uq * UnitQuaternion::from_scaled_axis(w * h);
        let fd = [
            (q2.w - uq.w) / h,
            (q2.i - uq.i) / h,
            (q2.j - uq.j) / h,
            (q2.k - uq.k) / h,
        ];
        let an = quat_rate(&q, &w);
        for i in 0..4 {
            assert!((fd[i] - an[i]).abs() < 1e-6, "{i}: {} vs {}", fd[i], an[i]);
        }
        let r = axis_angle(&Vector3::new(0.0, 0.6, 0.8), 0.9);
        let n = nalgebra::Rotation3::from_axis_angle(
            &nalgebra::Unit::new_normalize(Vector3::new(0.0, 0.6, 0.8)),
            0.9,
        );
        assert!((r - n.into_inner()).norm() < 1e-14);
    }

    #[test]
    fn bias_force_equals_the_cross_product_of_the_momentum() {
        let inertia = Inertia {
            mass: 2.5,
            com: Vector3::new(0.1, -0.2, 0.05),
            inertia_com: nalgebra::Matrix3::new(0.3, 0.01, 0.0, 0.01, 0.2, 0.02, 0.0, 0.02, 0.4),
        };
        let m = Motion {
            w: Vector3::new(0.7, -1.1, 2.0),
            v: Vector3::new(-0.4, 0.9, 0.3),
        };
        let a = inertia.bias_force(&m);
        let b = m.cross_force(&inertia.mul_motion(&m));
        // The same expression up to rounding: entries are O(1), so 1e-14.
        assert!((a.n - b.n).norm() < 1e-14 && (a.f - b.f).norm() < 1e-14);
        // A body at its centre of mass translating without spin: exactly no bias torque.
        let point = Inertia {
            com: Vector3::zeros(),
            ..inertia
        };
        let slide = Motion {
            w: Vector3::zeros(),
            v: Vector3::new(0.1, 0.3, -0.7),
        };
        assert_eq!(point.bias_force(&slide).n, Vector3::zeros());
    }
}
