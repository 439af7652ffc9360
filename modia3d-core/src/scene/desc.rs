//! Scene description: the plain-data builder API that `model!` expands into and that programs
//! use to build scenes from data. Nothing here is checked; [`SceneDesc::validate`] does that.

use super::force_laws::{Bushing, ForceFn, GravityField, Law, VectorLaw};
use super::materials::{ContactPairMaterial, MaterialFileError, MaterialPalette, SolidMaterial};
use crate::geometry::Shape;
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

/// Orientation of a frame relative to its parent.
#[derive(Clone, Debug, PartialEq, Default)]
pub enum Rotation {
    /// Same orientation as the parent.
    #[default]
    Identity,
    /// Cardan angles \[rad\]: rotate about x, then about the new y, then about the new z
    /// (Modia's default sequence `x-y-z`).
    Cardan([f64; 3]),
    /// The rotation matrix whose columns are this frame's axes resolved in the parent.
    Matrix(Matrix3<f64>),
}

impl Rotation {
    /// The rotation matrix whose columns are the frame's axes resolved in the parent.
    pub fn to_matrix(&self) -> Matrix3<f64> {
        match self {
            Rotation::Identity => Matrix3::identity(),
            Rotation::Cardan(a) => cardan_to_matrix(*a),
            Rotation::Matrix(m) => *m,
        }
    }

    /// All numbers of this rotation, for validation.
    pub(crate) fn values(&self) -> Vec<f64> {
        match self {
            Rotation::Identity => vec![],
            Rotation::Cardan(a) => a.to_vec(),
            Rotation::Matrix(m) => m.iter().copied().collect(),
        }
    }
}

/// Rotation matrix of Cardan angles `[x, y, z]` in the sequence x, then new y, then new z \[rad\].
pub fn cardan_to_matrix(a: [f64; 3]) -> Matrix3<f64> {
    let rx = Rotation3::from_axis_angle(&Vector3::x_axis(), a[0]);
    let ry = Rotation3::from_axis_angle(&Vector3::y_axis(), a[1]);
    let rz = Rotation3::from_axis_angle(&Vector3::z_axis(), a[2]);
    (rx * ry * rz).into_inner()
}

/// Which variant of the contact law (docs/contact-model.md §3) is used.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ContactProfile {
    /// The default: pairs with a sphere get the paper's Hertz law exactly as
    /// [`ContactProfile::Paper2019`] (the same numbers, bit for bit); pairs of boxes, convex
    /// hulls and mesh parts, and cylinders or cones against their flat faces, get the volume
    /// law (force from the overlap volume of the sharp shapes at its centroid, damping per unit
    /// area through the overlap's second moment; docs/contact-model.md §3.2); every other pair
    /// without a sphere (capsules, ellipsoids, beams, cylinder on cylinder) keeps the paper's
    /// law as [`ContactProfile::Paper2019`] has it.
    #[default]
    Volume,
    /// Neumayr & Otter, EOOLT 2019: `cor_reg` by the exponential blend towards `cor_min`;
    /// Hertz coefficients only where a sphere is involved, the linear law `c_res·δ` for every
    /// other pair. Pin it to reproduce the paper.
    Paper2019,
    /// Later Modia3D.jl versions: `cor` replaced by 0 when `|δ̇⁻| ≤ v_min`; Hertz coefficients
    /// (`n_geo = 3/2`) for every pair with a contact radius per shape. Use
    /// [`SceneOptions::modia3d_later`] to also get that profile's `d_max = 2000` s/m and
    /// hysteresis `1e-13` m.
    Modia3DLater,
}

/// Options of a scene; every field has the default of the contact specification
/// (`docs/contact-model.md`). Write `SceneOptions { gravity, ..Default::default() }`.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneOptions {
    /// Gravity acceleration, resolved in world [m/s²]. Default `(0, 0, -9.81)`.
    pub gravity: Vector3<f64>,
    /// Another gravity field (none, point gravity) in place of `gravity` (default `None`:
    /// uniform `gravity`). Setting both is a validation error unless `gravity` keeps its default.
    pub gravity_field: Option<GravityField>,
    /// Collision handling on (default) or off; off = no collision pairs, no root functions.
    pub contact_detection: bool,
    /// Elastic contact reduction factor `k_red` [-], > 0 (default 1): scales every contact
    /// stiffness down.
    pub k_red: f64,
    /// Upper bound of the damping factor `d` [s/m] (default 1000).
    pub d_max: f64,
    /// Coefficient of restitution approached by very slow impacts, `cor_min` [-] (default 0.001).
    pub cor_min: f64,
    /// Regularisation velocity `v_min` [m/s] of friction and `cor` (default 0.01); a contact
    /// pair material may override it.
    pub v_min: f64,
    /// Regularisation velocity [m/s] of the volume law's sliding and spin friction (default
    /// 1e-4, Drake's default stiction tolerance; docs/contact-model.md §3.2): a pair of the
    /// volume law whose contact-pair material sets no `v_min` regularises its friction at this
    /// speed instead of `v_min`. A contact held by friction creeps at about
    /// `v_min_volume·|F_t/f_n|/(3 μ_k)`, and the error it makes is proportional: a 0.1 m cube
    /// pivoting on its edge falls back 3.4e-4 early with 1e-3 and 3.8e-5 with 1e-4 (the
    /// paper's 0.01 m/s: 3.2e-3). A pair whose lighter body is light against the whole scene
    /// gets up to ten times this (its friction's time constant stays ≥ 1e-7 s). Its `cor`
    /// blend and resting damping keep `v_min`; pairs with a sphere are unaffected.
    pub v_min_volume: f64,
    /// Regularisation angular velocity `ω_min` [rad/s] of rolling resistance (default 0.01);
    /// a contact pair material may override it.
    pub w_min: f64,
    /// Hysteresis `ε` \[m\] of the zero-crossing functions (default 1e-8).
    pub hysteresis: f64,
    /// Relative tolerance of MPR / GJK in the narrow phase [-] (default 1e-11).
    pub mpr_tolerance: f64,
    /// Iteration limit of MPR / GJK (default 100).
    pub mpr_max_iterations: u32,
    /// Smoothing radius \[m\] of non-smooth collision shapes without their own (default 1 mm).
    pub smoothing_radius: f64,
    /// Variant of the contact law (default [`ContactProfile::Volume`]).
    pub contact_profile: ContactProfile,
    /// Damping from the exact restitution relation of the force law (default `false`: the
    /// paper's `d = 8(1 − cor)/(5·cor·δ̇⁻)`, kept for comparability, which turns cor 0.9 into
    /// an effective 0.894). With `true`, `d = χ(cor_reg)/reg(δ̇⁻, v_min)` where `χ(e)` solves
    /// the law's closed-form rebound relation, so an impact rebounds with exactly the pair's
    /// (regularised) cor whatever the masses, stiffness, speed and exponent
    /// (`docs/contact-model.md` §3); `d_max` still caps it.
    pub exact_restitution: bool,
    /// A contact-pair material `a|b` that neither the scene nor the built-in palette defines is
    /// taken as the mean of the self-pairs `a|a` and `b|b` (cor, μ_k, μ_r; Modia3D's rule),
    /// with a warning through `tracing` naming the pair (default `false`: a missing pair is
    /// [`SceneError::MissingContactPair`](crate::scene::SceneError::MissingContactPair)). A
    /// pair whose self-pairs are missing too stays an error.
    pub average_missing_pairs: bool,
    /// Modia3D.jl's conventions where they differ from ours, for porting a Modia3D model
    /// (default `false`; README "Coming from Modia3D"). With `true`:
    /// - the contact stiffness (Young's modulus, Poisson's ratio) comes from the solid
    ///   material named by the solid's contact material, as Modia3D reads it from its
    ///   `contactMaterial` (ours: from the solid material; the two agree unless a solid names a
    ///   different contact material);
    /// - `Revolute` and `Prismatic` joints whose `can_collide` is not given let their bodies
    ///   collide (Modia3D's `canCollide = true`; ours: false);
    /// - a mass without inertia ([`MassSpec::Mass`], `model!`'s `MassProperties(mass = …)`) is
    ///   a point mass at the object's origin, as Modia3D's `MassProperties(mass = m)` (ours:
    ///   the shape's inertia scaled to the mass);
    /// - the absolute tolerance a run uses when [`SimOptions::atol`](crate::SimOptions::atol)
    ///   is not set is `0.1·rtol` (Modia's; ours: `0.01·rtol`).
    pub modia3d_conventions: bool,
}

impl Default for SceneOptions {
    fn default() -> Self {
        SceneOptions {
            gravity: Vector3::new(0.0, 0.0, -9.81),
            gravity_field: None,
            contact_detection: true,
            k_red: 1.0,
            d_max: 1000.0,
            cor_min: 0.001,
            v_min: 0.01,
            v_min_volume: 1e-4,
            w_min: 0.01,
            hysteresis: 1e-8,
            mpr_tolerance: 1e-11,
            mpr_max_iterations: 100,
            smoothing_radius: crate::geometry::DEFAULT_SMOOTHING_RADIUS,
            contact_profile: ContactProfile::Volume,
            exact_restitution: false,
            average_missing_pairs: false,
            modia3d_conventions: false,
        }
    }
}

impl SceneOptions {
    /// The field in effect: `gravity_field`, or uniform `gravity` without one.
    pub fn field(&self) -> GravityField {
        self.gravity_field
            .unwrap_or(GravityField::Uniform(self.gravity))
    }
    /// The defaults of later Modia3D.jl versions: profile [`ContactProfile::Modia3DLater`],
    /// `d_max = 2000` s/m, hysteresis `1e-13` m; everything else as [`Default`].
    pub fn modia3d_later() -> Self {
        SceneOptions {
            contact_profile: ContactProfile::Modia3DLater,
            d_max: 2000.0,
            hysteresis: 1e-13,
            ..Default::default()
        }
    }
}

/// How the mass properties of a solid are obtained.
#[derive(Clone, Debug, PartialEq, Default)]
pub enum MassSpec {
    /// From the shape's volume and the solid material's density (default).
    #[default]
    FromShapeAndDensity,
    /// From the shape, scaled to the given mass \[kg\] (Modia3D's
    /// `MassPropertiesFromShapeAndMass`).
    FromShapeAndMass(f64),
    /// A mass \[kg\] without inertia, what `model!`'s `MassProperties(mass = …)` gives: as
    /// [`MassSpec::FromShapeAndMass`] by default; with
    /// [`SceneOptions::modia3d_conventions`] a point mass at the object's origin (zero inertia),
    /// as Modia3D's `MassProperties(mass = m)`.
    Mass(f64),
    /// Explicit values, in the object's frame.
    Explicit {
        /// Mass \[kg\].
        mass: f64,
        /// Centre of mass, resolved in the object's frame \[m\].
        com: Vector3<f64>,
        /// Inertia tensor about the centre of mass, resolved in the object's frame [kg·m²].
        inertia: Matrix3<f64>,
    },
}

/// A solid material given by name (looked up in the palette) or by value.
#[derive(Clone, Debug, PartialEq)]
pub enum MaterialRef {
    /// A name of the palette, e.g. `"Steel"`.
    Name(String),
    /// A material given by value.
    Value(SolidMaterial),
}

/// A solid body part: shape, material, mass properties and collision data.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Solid {
    /// Geometry; may be `None` only with explicit mass properties.
    pub shape: Option<Shape>,
    /// Solid material; needed for mass from density and for contact.
    pub material: Option<MaterialRef>,
    /// How mass properties are obtained.
    pub mass_properties: MassSpec,
    /// Whether this solid takes part in collision handling.
    pub collision: bool,
    /// Name of its contact material (default: the solid material's name).
    pub contact_material: Option<String>,
    /// Radius that rounds edges of non-smooth shapes \[m\]; default of the scene when `None`.
    pub smoothing_radius: Option<f64>,
    /// Depth \[m\] of the elastic layer of the volume contact law
    /// ([`ContactProfile::Volume`]): the solid's contact stiffness per unit volume is
    /// `E/((1 − ν²)·H)`. `None` (default): the shape's own, half its smallest edge for a box
    /// (docs/contact-model.md §3.2). Finite and > 0.
    pub layer_depth: Option<f64>,
}

impl Solid {
    /// A solid with this shape and defaults otherwise.
    pub fn new(shape: Shape) -> Self {
        Solid {
            shape: Some(shape),
            ..Default::default()
        }
    }
    /// Sets the solid material by name: a built-in one (see
    /// [`builtin_palette`](crate::scene::builtin_palette): `"Steel"`, `"Aluminium"`,
    /// `"NaturalRubber"`, …) or one added with `SceneDesc::add_solid_material` or a JSON
    /// palette. The same key as `model!`'s `solid_material = "Steel"`.
    pub fn solid_material(mut self, name: &str) -> Self {
        self.material = Some(MaterialRef::Name(name.to_string()));
        self
    }
    /// The former name of [`solid_material`](Self::solid_material), kept as an alias.
    pub fn material(self, name: &str) -> Self {
        self.solid_material(name)
    }
    /// Sets the solid material by value.
    pub fn material_value(mut self, m: SolidMaterial) -> Self {
        self.material = Some(MaterialRef::Value(m));
        self
    }
    /// Sets the mass \[kg\] (> 0); inertia follows from the shape.
    pub fn mass(mut self, mass: f64) -> Self {
        self.mass_properties = MassSpec::FromShapeAndMass(mass);
        self
    }
    /// Sets a mass \[kg\] (> 0) without inertia ([`MassSpec::Mass`], what `model!`'s
    /// `MassProperties(mass = …)` gives): the shape's inertia scaled to the mass, or a point
    /// mass at the object's origin with [`SceneOptions::modia3d_conventions`].
    pub fn given_mass(mut self, mass: f64) -> Self {
        self.mass_properties = MassSpec::Mass(mass);
        self
    }
    /// Sets explicit mass properties in the object's frame: mass \[kg\] (> 0), centre of mass \[m\],
    /// inertia about the centre of mass [kg·m²].
    pub fn mass_properties(mut self, mass: f64, com: Vector3<f64>, inertia: Matrix3<f64>) -> Self {
        self.mass_properties = MassSpec::Explicit { mass, com, inertia };
        self
    }
    /// Enables collision handling for this solid.
    pub fn collision(mut self, on: bool) -> Self {
        self.collision = on;
        self
    }
    /// Sets the contact material's name.
    pub fn contact_material(mut self, name: &str) -> Self {
        self.contact_material = Some(name.to_string());
        self
    }
    /// Sets the smoothing radius \[m\].
    pub fn smoothing_radius(mut self, r: f64) -> Self {
        self.smoothing_radius = Some(r);
        self
    }
    /// Sets the depth \[m\] of the volume law's elastic layer ([`Solid::layer_depth`]).
    pub fn layer_depth(mut self, h: f64) -> Self {
        self.layer_depth = Some(h);
        self
    }
}

/// What an object is, besides a frame.
#[derive(Clone, Debug, PartialEq, Default)]
pub enum Feature {
    /// A bare frame.
    #[default]
    None,
    /// The scene: exactly one, at the root (the world frame).
    Scene(SceneOptions),
    /// A solid part.
    Solid(Solid),
    /// A shape that is only drawn.
    Visual(Shape),
}

/// A frame in the assembly, with an optional parent and a feature.
#[derive(Clone, Debug, PartialEq)]
pub struct Object3D {
    /// Unique name; paths into assemblies use dots (`arm1.tip`).
    pub name: String,
    /// Name of the parent object; the object is rigidly attached to it.
    pub parent: Option<String>,
    /// Position of this frame's origin relative to the parent, resolved in the parent \[m\].
    pub translation: Vector3<f64>,
    /// Orientation relative to the parent.
    pub rotation: Rotation,
    /// Scene, solid, visual or nothing.
    pub feature: Feature,
}

impl Object3D {
    /// A bare frame without parent.
    pub fn new(name: &str) -> Self {
        Object3D {
            name: name.to_string(),
            parent: None,
            translation: Vector3::zeros(),
            rotation: Rotation::Identity,
            feature: Feature::None,
        }
    }
    /// Sets the parent by name.
    pub fn parent(mut self, parent: &str) -> Self {
        self.parent = Some(parent.to_string());
        self
    }
    /// Sets the translation relative to the parent, resolved in the parent \[m\].
    pub fn translation(mut self, t: [f64; 3]) -> Self {
        self.translation = Vector3::from(t);
        self
    }
    /// Sets the rotation relative to the parent.
    pub fn rotation(mut self, r: Rotation) -> Self {
        self.rotation = r;
        self
    }
    /// Sets the feature.
    pub fn feature(mut self, f: Feature) -> Self {
        self.feature = f;
        self
    }
    /// Makes this object the scene with the given options.
    pub fn scene(self, options: SceneOptions) -> Self {
        self.feature(Feature::Scene(options))
    }
    /// Makes this object a solid.
    pub fn solid(self, solid: Solid) -> Self {
        self.feature(Feature::Solid(solid))
    }
}

/// Initial orientation of a free-moving object relative to `obj1`.
#[derive(Clone, Debug, PartialEq)]
pub enum FreeRotation {
    /// Cardan angles x-y-z \[rad\].
    Cardan([f64; 3]),
    /// A unit quaternion.
    Quaternion(UnitQuaternion<f64>),
}

/// The kind of a joint and its initial values.
#[derive(Clone, Debug, PartialEq)]
pub enum JointKind {
    /// Rigid: `obj2`'s frame coincides with `obj1`'s.
    Fix,
    /// Rotation of `obj2` relative to `obj1` about `axis` (resolved in `obj1`, unit length after
    /// normalisation); the frames coincide at `phi = 0`.
    Revolute {
        /// Axis, resolved in obj1 (any non-zero vector; normalised).
        axis: Vector3<f64>,
        /// Initial angle \[rad\].
        phi: f64,
        /// Initial angular velocity [rad/s].
        w: f64,
    },
    /// Translation of `obj2` relative to `obj1` along `axis` (resolved in `obj1`).
    Prismatic {
        /// Axis, resolved in obj1 (any non-zero vector; normalised).
        axis: Vector3<f64>,
        /// Initial position \[m\].
        s: f64,
        /// Initial velocity [m/s].
        v: f64,
    },
    /// Six degrees of freedom of `obj2` relative to `obj1` (unit quaternion internally).
    FreeMotion {
        /// Initial position of obj2's origin relative to obj1, resolved in obj1 \[m\].
        r: Vector3<f64>,
        /// Initial orientation of obj2 relative to obj1.
        rot: FreeRotation,
        /// Initial velocity `der(r)`, resolved in obj1 [m/s].
        v: Vector3<f64>,
        /// Initial angular velocity of obj2 relative to obj1, resolved in obj2 [rad/s].
        w: Vector3<f64>,
    },
    /// Ball joint: rotation of `obj2` relative to `obj1` about their common origin (a unit
    /// quaternion internally: no singular angles). Signals `q` (quaternion) and `w`
    /// (resolved in obj2, [rad/s]).
    Spherical {
        /// Initial orientation of obj2 relative to obj1.
        rot: FreeRotation,
        /// Initial angular velocity of obj2 relative to obj1, resolved in obj2 [rad/s].
        w: Vector3<f64>,
    },
    /// Cardan (Hooke) joint: rotation `phi1` about `axis1` (fixed in obj1), then `phi2` about
    /// `axis2` (fixed in obj2; resolved in obj2, which coincides with obj1 at zero angles).
    /// The axes must be perpendicular. Signals `phi1`, `phi2` \[rad\], `w1`, `w2` [rad/s].
    Universal {
        /// First axis, resolved in obj1 (any non-zero vector; normalised).
        axis1: Vector3<f64>,
        /// Second axis, resolved in obj2 (non-zero, perpendicular to `axis1`; normalised).
        axis2: Vector3<f64>,
        /// Initial angle about `axis1` \[rad\].
        phi1: f64,
        /// Initial angle about `axis2` \[rad\].
        phi2: f64,
        /// Initial rate of `phi1` [rad/s].
        w1: f64,
        /// Initial rate of `phi2` [rad/s].
        w2: f64,
    },
    /// Rotation `phi` about and translation `s` along `axis` (resolved in obj1). Signals
    /// `phi` \[rad\], `s` \[m\], `w` [rad/s], `v` [m/s].
    Cylindrical {
        /// Axis, resolved in obj1 (any non-zero vector; normalised).
        axis: Vector3<f64>,
        /// Initial angle \[rad\].
        phi: f64,
        /// Initial position \[m\].
        s: f64,
        /// Initial angular velocity [rad/s].
        w: f64,
        /// Initial velocity [m/s].
        v: f64,
    },
    /// Motion of `obj2` in the plane through obj1's origin normal to `normal`: obj2's origin
    /// at `x e1 + y e2`, resolved in obj1, and rotation `phi` about `normal`. The plane axes
    /// are fixed in obj1: `e1` is the coordinate axis following `normal`'s largest component
    /// cyclically (x → y → z → x) made perpendicular to `normal`, `e2 = normal × e1` (normal
    /// z: x, y; normal x: y, z; normal y: z, x). Signals `x`, `y` \[m\], `phi` \[rad\], `vx`, `vy`
    /// (rates of `x`, `y`, [m/s]), `w` [rad/s].
    Planar {
        /// Normal of the plane, resolved in obj1 (any non-zero vector; normalised).
        normal: Vector3<f64>,
        /// Initial position along `e1` \[m\].
        x: f64,
        /// Initial position along `e2` \[m\].
        y: f64,
        /// Initial angle about `normal` \[rad\].
        phi: f64,
        /// Initial rate of `x` [m/s].
        vx: f64,
        /// Initial rate of `y` [m/s].
        vy: f64,
        /// Initial rate of `phi` [rad/s].
        w: f64,
    },
}

impl JointKind {
    /// Modia's axis numbering: ±1, ±2, ±3 for ±x, ±y, ±z; `None` otherwise.
    pub fn axis_from_index(i: i64) -> Option<Vector3<f64>> {
        let a = crate::geometry::Axis::from_index(i.abs())?;
        Some(a.unit() * (i.signum() as f64))
    }
    /// A revolute joint about Modia axis `axis` (±1..3), at rest at angle 0.
    /// An invalid axis gives the zero vector, which validation reports.
    pub fn revolute(axis: i64) -> Self {
        JointKind::Revolute {
            axis: Self::axis_from_index(axis).unwrap_or_else(Vector3::zeros),
            phi: 0.0,
            w: 0.0,
        }
    }
    /// A prismatic joint along Modia axis `axis` (±1..3), at rest at position 0.
    pub fn prismatic(axis: i64) -> Self {
        JointKind::Prismatic {
            axis: Self::axis_from_index(axis).unwrap_or_else(Vector3::zeros),
            s: 0.0,
            v: 0.0,
        }
    }
    /// A free motion at rest with frames coinciding.
    pub fn free() -> Self {
        JointKind::FreeMotion {
            r: Vector3::zeros(),
            rot: FreeRotation::Cardan([0.0; 3]),
            v: Vector3::zeros(),
            w: Vector3::zeros(),
        }
    }
    /// A spherical joint at rest with frames coinciding.
    pub fn spherical() -> Self {
        JointKind::Spherical {
            rot: FreeRotation::Cardan([0.0; 3]),
            w: Vector3::zeros(),
        }
    }
    /// A universal joint about Modia axes `axis1` (in obj1) and `axis2` (in obj2), ±1..3, at
    /// rest at zero angles. An invalid axis gives the zero vector, which validation reports.
    pub fn universal(axis1: i64, axis2: i64) -> Self {
        JointKind::Universal {
            axis1: Self::axis_from_index(axis1).unwrap_or_else(Vector3::zeros),
            axis2: Self::axis_from_index(axis2).unwrap_or_else(Vector3::zeros),
            phi1: 0.0,
            phi2: 0.0,
            w1: 0.0,
            w2: 0.0,
        }
    }
    /// A cylindrical joint along Modia axis `axis` (±1..3), at rest at zero.
    pub fn cylindrical(axis: i64) -> Self {
        JointKind::Cylindrical {
            axis: Self::axis_from_index(axis).unwrap_or_else(Vector3::zeros),
            phi: 0.0,
            s: 0.0,
            w: 0.0,
            v: 0.0,
        }
    }
    /// A planar joint with normal along Modia axis `normal` (±1..3), at rest at zero.
    pub fn planar(normal: i64) -> Self {
        JointKind::Planar {
            normal: Self::axis_from_index(normal).unwrap_or_else(Vector3::zeros),
            x: 0.0,
            y: 0.0,
            phi: 0.0,
            vx: 0.0,
            vy: 0.0,
            w: 0.0,
        }
    }
}

/// A joint between two objects.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// Unique name (signals: `"<name>.phi"`, …).
    pub name: String,
    /// The object on the world side.
    pub obj1: String,
    /// The moved object.
    pub obj2: String,
    /// Kind and initial values.
    pub kind: JointKind,
    /// Whether solids of the two joined bodies may collide; `None` (not given) is false, or
    /// true for a Revolute or Prismatic joint with [`SceneOptions::modia3d_conventions`].
    /// Applies to every joint that is a mechanical connection (all but FreeMotion); a
    /// FreeMotion never prevents a collision (as in Modia3D).
    pub can_collide: Option<bool>,
    /// Whether this joint should be the one that closes its kinematic loop (default false): a
    /// cut joint stays out of the spanning joint tree and is enforced by constraints
    /// (`dynamics/loops.rs`). Marking is a preference: unmarked loop-closing joints are cut
    /// in declaration order, and a marked joint that is needed to connect a body to the world
    /// stays in the tree.
    pub cut: bool,
    /// Stops on its scalar coordinates (docs/joint-limits.md): compliant impacts located by
    /// the contact events. Empty: no stop (and no cost).
    pub limits: Vec<JointLimit>,
}

/// A stop on a scalar coordinate of a joint: a lower and/or upper bound (\[rad\] for an angle,
/// \[m\] for a translation) at which the coordinate meets a compliant, damped spring, as a
/// contact pair meets its surface (docs/joint-limits.md has the law, units and defaults).
#[derive(Clone, Debug, PartialEq)]
pub struct JointLimit {
    /// The coordinate (`"phi"`, `"s"`, `"phi1"`, …); `None`: the joint's only one.
    pub coordinate: Option<String>,
    /// Lower bound \[rad or m\]; `None`: none.
    pub lower: Option<f64>,
    /// Upper bound \[rad or m\]; `None`: none.
    pub upper: Option<f64>,
    /// Stiffness of the stop \[N·m/rad or N/m\]; `None`: the default from the coordinate's
    /// effective inertia (docs/joint-limits.md).
    pub stiffness: Option<f64>,
    /// Coefficient of restitution of an impact on the stop \[-\], in \[0, 1\];
    /// `None`: [`JointLimit::DEFAULT_COR`].
    pub cor: Option<f64>,
}

impl JointLimit {
    /// The coefficient of restitution of a stop that does not set one \[-\].
    pub const DEFAULT_COR: f64 = 0.5;

    /// Stops at `lower` and `upper` (`lower < upper`; `f64::NEG_INFINITY` / `f64::INFINITY`:
    /// no bound on that side) on the joint's only coordinate (name one with [`Self::on`]).
    pub fn range(lower: f64, upper: f64) -> Self {
        JointLimit {
            coordinate: None,
            lower: Some(lower),
            upper: Some(upper),
            stiffness: None,
            cor: None,
        }
    }
    /// A lower stop only.
    pub fn lower(lower: f64) -> Self {
        JointLimit {
            upper: None,
            ..Self::range(lower, f64::NAN)
        }
    }
    /// An upper stop only.
    pub fn upper(upper: f64) -> Self {
        JointLimit {
            lower: None,
            ..Self::range(f64::NAN, upper)
        }
    }
    /// On coordinate `name` of the joint (needed for joints with several).
    pub fn on(mut self, name: &str) -> Self {
        self.coordinate = Some(name.to_string());
        self
    }
    /// Sets the stiffness \[N·m/rad or N/m\].
    pub fn stiffness(mut self, k: f64) -> Self {
        self.stiffness = Some(k);
        self
    }
    /// Sets the coefficient of restitution \[-\].
    pub fn cor(mut self, e: f64) -> Self {
        self.cor = Some(e);
        self
    }
}

impl Joint {
    /// A joint of `kind` moving `obj2` relative to `obj1`.
    pub fn new(name: &str, obj1: &str, obj2: &str, kind: JointKind) -> Self {
        Joint {
            name: name.to_string(),
            obj1: obj1.to_string(),
            obj2: obj2.to_string(),
            kind,
            can_collide: None,
            cut: false,
            limits: vec![],
        }
    }
    /// Stops at `lower` and `upper` \[rad or m\] on the joint's only scalar coordinate
    /// (Revolute `phi`, Prismatic `s`); see [`JointLimit`], and [`Self::limit`] for one side,
    /// another coordinate, a stiffness or a restitution.
    pub fn limits(self, lower: f64, upper: f64) -> Self {
        self.limit(JointLimit::range(lower, upper))
    }
    /// Adds the stop `limit` (see [`JointLimit`]).
    pub fn limit(mut self, limit: JointLimit) -> Self {
        self.limits.push(limit);
        self
    }
    /// Marks this joint as the one to cut when it closes a kinematic loop (see the field `cut`).
    pub fn cut(mut self, on: bool) -> Self {
        self.cut = on;
        self
    }
    /// Sets `can_collide`.
    pub fn can_collide(mut self, on: bool) -> Self {
        self.can_collide = Some(on);
        self
    }
    /// Sets the initial angle \[rad\] (revolute) or position \[m\] (prismatic); ignored otherwise.
    pub fn init_position(mut self, x: f64) -> Self {
        match &mut self.kind {
            JointKind::Revolute { phi, .. } => *phi = x,
            JointKind::Prismatic { s, .. } => *s = x,
            // The other kinds have several coordinates or none: their initial values are
            // the variant's own fields (listed, so a new kind must decide here).
            JointKind::Fix
            | JointKind::FreeMotion { .. }
            | JointKind::Spherical { .. }
            | JointKind::Universal { .. }
            | JointKind::Cylindrical { .. }
            | JointKind::Planar { .. } => {}
        }
        self
    }
    /// Sets the initial angular velocity [rad/s] (revolute) or velocity [m/s] (prismatic).
    pub fn init_velocity(mut self, x: f64) -> Self {
        match &mut self.kind {
            JointKind::Revolute { w, .. } => *w = x,
            JointKind::Prismatic { v, .. } => *v = x,
            // The other kinds have several coordinates or none: their initial values are
            // the variant's own fields (listed, so a new kind must decide here).
            JointKind::Fix
            | JointKind::FreeMotion { .. }
            | JointKind::Spherical { .. }
            | JointKind::Universal { .. }
            | JointKind::Cylindrical { .. }
            | JointKind::Planar { .. } => {}
        }
        self
    }
}

/// An element that applies forces.
#[derive(Clone, Debug)]
pub enum ForceElement {
    /// Linear spring-damper between the origins of `obj1` and `obj2`:
    /// force `c (L − L0) + d L̇` along the line, pulling them together when positive.
    SpringDamper {
        /// Name (for messages).
        name: String,
        /// First object.
        obj1: String,
        /// Second object.
        obj2: String,
        /// Stiffness [N/m].
        stiffness: f64,
        /// Damping [N·s/m].
        damping: f64,
        /// Unstretched length \[m\].
        length0: f64,
    },
    /// Spring and damper on a scalar coordinate of a joint (a rotation [N·m/rad, N·m·s/rad]
    /// or a translation [N/m, N·s/m]): generalised force `−c (x − x0) − d ẋ`.
    JointSpringDamper {
        /// Name of the joint.
        joint: String,
        /// The coordinate (`"phi1"`, `"s"`, `"x"`, …; see the joint kinds); `None` for a joint
        /// with a single scalar coordinate (Revolute, Prismatic).
        coordinate: Option<String>,
        /// Stiffness.
        stiffness: f64,
        /// Damping.
        damping: f64,
        /// Position where the spring is relaxed [rad or m].
        offset: f64,
    },
    /// A force and torque on an object's origin given by a closure.
    ObjectForce {
        /// Name of the object.
        object: String,
        /// The force law.
        law: ForceFn,
    },
    /// Spring-damper between the origins of `obj1` and `obj2` with force laws (Modia3D's
    /// `SpringDamperPtP`): tension `spring(L − L0) + damper(L̇)` \[N\] along the line, pulling
    /// them together when positive. Signals `<name>.length` \[m\], `<name>.tension` \[N\].
    SpringDamperPtP {
        /// Name (signals; unique among objects, joints and force elements).
        name: String,
        /// First object.
        obj1: String,
        /// Second object.
        obj2: String,
        /// Unstretched length \[m\].
        length0: f64,
        /// Spring law: tension \[N\] from the elongation `L − L0` \[m\].
        spring: Law,
        /// Damper law: tension \[N\] from the rate `L̇` [m/s].
        damper: Law,
    },
    /// A six-axis bushing (see [`Bushing`]; `Bushing::into()` makes the element).
    Bushing(Box<Bushing>),
    /// A force \[N\] at `object`'s origin (Modia3D's `WorldForce`), resolved in world or, with
    /// `resolved_in`, in that object's frame (turning with it).
    WorldForce {
        /// Name (signal `<name>.force`: the force resolved in world \[N\]).
        name: String,
        /// The object acted on.
        object: String,
        /// The force, resolved in world or `resolved_in` \[N\].
        force: VectorLaw,
        /// The object whose axes the force is resolved in; `None`: world.
        resolved_in: Option<String>,
    },
    /// A torque [N·m] on `object` (Modia3D's `WorldTorque`), resolved in world or in
    /// `resolved_in`'s frame.
    WorldTorque {
        /// Name (signal `<name>.torque`: the torque resolved in world [N·m]).
        name: String,
        /// The object acted on.
        object: String,
        /// The torque, resolved in world or `resolved_in` [N·m].
        torque: VectorLaw,
        /// The object whose axes the torque is resolved in; `None`: world.
        resolved_in: Option<String>,
    },
}

/// What an input drives. Input values are set between steps of a
/// [`crate::simulation::Simulation`] and are 0 until set.
#[derive(Clone, Debug, PartialEq)]
pub enum InputKind {
    /// A generalised force on a scalar coordinate of a joint ([N·m] for a rotation, \[N\] for a
    /// translation; 1 value), added to its spring-dampers.
    JointForce {
        /// Name of the joint.
        joint: String,
        /// The coordinate; `None` for a joint with a single scalar coordinate.
        coordinate: Option<String>,
    },
    /// Prescribed motion of a scalar coordinate of a joint: its acceleration ([rad/s²] or
    /// [m/s²]; 1 value); position and velocity follow by integration, the joint force is
    /// whatever the motion needs.
    JointAcceleration {
        /// Name of the joint.
        joint: String,
        /// The coordinate; `None` for a joint with a single scalar coordinate.
        coordinate: Option<String>,
    },
    /// A force \[N\] and a torque [N·m], both resolved in world, on an object's origin
    /// (6 values: force x, y, z, then torque x, y, z).
    ObjectWrench {
        /// Name of the object.
        object: String,
    },
}

/// A named input of a model.
#[derive(Clone, Debug, PartialEq)]
pub struct Input {
    /// Name used with `Simulation::set_input`.
    pub name: String,
    /// What it drives.
    pub kind: InputKind,
}

impl Input {
    /// A generalised force on joint `joint`'s single scalar coordinate (1 value, [N·m] or \[N\]).
    pub fn joint_force(name: &str, joint: &str) -> Self {
        Input {
            name: name.into(),
            kind: InputKind::JointForce {
                joint: joint.into(),
                coordinate: None,
            },
        }
    }
    /// The prescribed acceleration of joint `joint`'s single scalar coordinate (1 value,
    /// [rad/s²] or [m/s²]).
    pub fn joint_acceleration(name: &str, joint: &str) -> Self {
        Input {
            name: name.into(),
            kind: InputKind::JointAcceleration {
                joint: joint.into(),
                coordinate: None,
            },
        }
    }
    /// Sets the joint coordinate a joint input acts on (`"phi2"`, `"s"`, …); no effect on an
    /// object wrench.
    pub fn coordinate(mut self, c: &str) -> Self {
        if let InputKind::JointForce { coordinate, .. }
        | InputKind::JointAcceleration { coordinate, .. } = &mut self.kind
        {
            *coordinate = Some(c.to_string());
        }
        self
    }
    /// A world force and torque on object `object`'s origin (6 values, \[N\] then [N·m]).
    pub fn object_wrench(name: &str, object: &str) -> Self {
        Input {
            name: name.into(),
            kind: InputKind::ObjectWrench {
                object: object.into(),
            },
        }
    }
    /// Number of values.
    pub fn len(&self) -> usize {
        match self.kind {
            InputKind::ObjectWrench { .. } => 6,
            _ => 1,
        }
    }
    /// Never true: every input has at least one value.
    pub fn is_empty(&self) -> bool {
        false
    }
}

/// An unchecked scene: objects, joints and force elements, referring to each other by name.
#[derive(Clone, Debug, Default)]
pub struct SceneDesc {
    /// Objects in declaration order.
    pub objects: Vec<Object3D>,
    /// Joints in declaration order.
    pub joints: Vec<Joint>,
    /// Force elements.
    pub forces: Vec<ForceElement>,
    /// User-defined solid materials (added to the built-in palette).
    pub solid_materials: Vec<(String, SolidMaterial)>,
    /// User-defined contact-pair materials (override the built-in palette; order of the two
    /// names does not matter).
    pub contact_pairs: Vec<(String, String, ContactPairMaterial)>,
    /// Inputs set from Rust between simulation steps.
    pub inputs: Vec<Input>,
    /// Scheduled structure changes (attach, release, delete; see [`crate::scene::Action`]).
    pub actions: Vec<crate::scene::Action>,
    /// Components with states in the DAE: controllers, sources, drives
    /// (docs/drive-trains.md).
    pub components: Vec<crate::scene::ComponentDecl>,
}

impl SceneDesc {
    /// Declares an input.
    pub fn add_input(&mut self, input: Input) -> &mut Self {
        self.inputs.push(input);
        self
    }
    /// Adds a component (see [`crate::scene::ComponentDecl`]).
    pub fn add_component(&mut self, component: crate::scene::ComponentDecl) -> &mut Self {
        self.components.push(component);
        self
    }
    /// An empty scene description.
    pub fn new() -> Self {
        Self::default()
    }
    /// Adds an object.
    pub fn add(&mut self, object: Object3D) -> &mut Self {
        self.objects.push(object);
        self
    }
    /// Adds a joint.
    pub fn add_joint(&mut self, joint: Joint) -> &mut Self {
        self.joints.push(joint);
        self
    }
    /// Adds a force element.
    pub fn add_force(&mut self, force: ForceElement) -> &mut Self {
        self.forces.push(force);
        self
    }
    /// Defines (or redefines) a solid material by name.
    pub fn add_solid_material(&mut self, name: &str, m: SolidMaterial) -> &mut Self {
        self.solid_materials.push((name.to_string(), m));
        self
    }
    /// Defines (or redefines) the response of contact materials `name1` and `name2` (either
    /// order).
    pub fn add_contact_pair(
        &mut self,
        name1: &str,
        name2: &str,
        m: ContactPairMaterial,
    ) -> &mut Self {
        self.contact_pairs
            .push((name1.to_string(), name2.to_string(), m));
        self
    }
    /// Adds every material of a palette (solid and contact-pair materials).
    pub fn add_palette(&mut self, palette: &MaterialPalette) -> &mut Self {
        for (n, m) in &palette.solid {
            self.add_solid_material(n, *m);
        }
        for e in &palette.contact_pairs {
            self.add_contact_pair(&e.materials[0], &e.materials[1], e.material);
        }
        self
    }
    /// Reads a JSON material file (see [`MaterialPalette`]) and adds its materials.
    pub fn load_materials_json(
        &mut self,
        path: impl AsRef<std::path::Path>,
    ) -> Result<&mut Self, MaterialFileError> {
        let p = MaterialPalette::from_json_file(path)?;
        Ok(self.add_palette(&p))
    }
}
