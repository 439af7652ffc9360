//! Random-scene generator shared by `tests/fuzz_scenes.rs` and `tests/regressions.rs`
//! (issue 15, point 1): small seeded scenes as a new user might write them — 1 to 12 bodies
//! of every shape (`Shape`: sphere, box, cylinder, capsule, cone, ellipsoid, convex hull),
//! sizes 1e-3…1 m, masses 1e-3…1e3 kg, random poses including overlaps, velocities up to
//! 10 m/s, free, revolute, prismatic and fixed joints, rigid attachments and chains, every
//! force element of `scene/desc.rs` (spring-dampers, joint spring-dampers, object-force
//! closures) and inputs with loads relative to the body they act on (forces and torques that,
//! held over the run, bring a free body or its surface to 0.01…10 m/s, spring periods
//! 2 ms…6 s and long enough that the initial stretch gives no more than 10 m/s, drag time
//! constants 10 ms…100 s), the built-in materials, contact on and off, rtol 1e-3…1e-9,
//! 0.05–1 s simulated, and for some scenes the step-wise API (`Simulation::new` /
//! `advance_to` / `set_input`).
//!
//! A scene is plain data ([`SceneSpec`], serialisable to JSON for reproducers); [`generate`]
//! draws one from a seed with its own PRNG (splitmix64), `build.rs` turns it into a
//! `SceneDesc` and `run.rs` runs it and classifies the outcome. Every scene sets
//! `SimOptions::max_wall_time`, so a run that would take long ends with the typed work-budget
//! error.

#![allow(dead_code)] // each test binary uses a different part of the module

pub mod build;
pub mod run;

use serde::{Deserialize, Serialize};

/// splitmix64 (Steele, Lea & Flood 2014): tiny, fast and good enough for scene generation.
#[derive(Clone, Debug)]
pub struct Rng(pub u64);

impl Rng {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    /// Log-uniform in [lo, hi) (lo > 0).
    pub fn log_uniform(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.unit()).exp()
    }
    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }
    /// An index below `n` (n > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
    /// One of `xs`.
    pub fn pick<T: Clone>(&mut self, xs: &[T]) -> T {
        xs[self.below(xs.len())].clone()
    }
    /// A vector with components uniform in [-a, a).
    pub fn vec3(&mut self, a: f64) -> [f64; 3] {
        [
            self.uniform(-a, a),
            self.uniform(-a, a),
            self.uniform(-a, a),
        ]
    }
}

/// The seed of scene `i` of a batch with base seed `base`.
pub fn scene_seed(base: u64, i: u64) -> u64 {
    Rng(base ^ i.wrapping_mul(0xd1b5_4a32_d192_ed03)).next_u64()
}

/// A shape with its dimensions \[m\].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ShapeSpec {
    /// Diameter.
    Sphere(f64),
    /// Edge lengths.
    Box([f64; 3]),
    /// Axis (1..3), diameter, length.
    Cylinder(i64, f64, f64),
    /// Axis, diameter, length of the cylindrical part.
    Capsule(i64, f64, f64),
    /// Axis, base diameter, height, top diameter.
    Cone(i64, f64, f64, f64),
    /// Axis lengths.
    Ellipsoid([f64; 3]),
    /// Points of a convex hull.
    Hull(Vec<[f64; 3]>),
}

/// How a body is connected to its parent (the world or an earlier body).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum JointSpec {
    /// FreeMotion from the parent: position \[m\], Cardan angles \[rad\], velocity [m/s],
    /// angular velocity [rad/s].
    Free {
        /// Position in the parent \[m\].
        r: [f64; 3],
        /// Cardan angles \[rad\].
        rot: [f64; 3],
        /// Velocity [m/s].
        v: [f64; 3],
        /// Angular velocity [rad/s].
        w: [f64; 3],
    },
    /// Revolute about Modia axis `axis` at the mount frame.
    Revolute {
        /// ±1..3.
        axis: i64,
        /// Initial angle \[rad\].
        phi: f64,
        /// Initial rate [rad/s].
        w: f64,
        /// The joined bodies may collide.
        can_collide: bool,
    },
    /// Prismatic along Modia axis `axis` at the mount frame.
    Prismatic {
        /// ±1..3.
        axis: i64,
        /// Initial position \[m\].
        s: f64,
        /// Initial velocity [m/s].
        v: f64,
        /// The joined bodies may collide.
        can_collide: bool,
    },
    /// Spherical at the mount frame: Cardan angles [rad], angular velocity in the body [rad/s].
    Spherical {
        /// Cardan angles [rad].
        rot: [f64; 3],
        /// Angular velocity [rad/s].
        w: [f64; 3],
        /// The joined bodies may collide.
        can_collide: bool,
    },
    /// Universal about Modia axes `axis1` (mount) and `axis2` (body), perpendicular.
    Universal {
        /// ±1..3.
        axis1: i64,
        /// ±1..3, not along `axis1`.
        axis2: i64,
        /// Initial angles [rad].
        phi: [f64; 2],
        /// Initial rates [rad/s].
        w: [f64; 2],
        /// The joined bodies may collide.
        can_collide: bool,
    },
    /// Cylindrical along Modia axis `axis`: angle [rad], position [m], their rates.
    Cylindrical {
        /// ±1..3.
        axis: i64,
        /// Initial angle [rad] and position [m].
        q: [f64; 2],
        /// Initial rates [rad/s], [m/s].
        v: [f64; 2],
        /// The joined bodies may collide.
        can_collide: bool,
    },
    /// Planar with normal along Modia axis `normal`: x, y [m], phi [rad] and their rates.
    Planar {
        /// ±1..3.
        normal: i64,
        /// Initial x, y [m], phi [rad].
        q: [f64; 3],
        /// Initial rates [m/s, m/s, rad/s].
        v: [f64; 3],
        /// The joined bodies may collide.
        can_collide: bool,
    },
    /// A Fix joint at the mount frame.
    Fix,
    /// Rigidly attached (parent link) at the mount frame, no joint.
    Attached,
}

/// One body: object `b{k}` with a solid, mount frame `m{k}`, joint `j{k}`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BodySpec {
    /// Geometry.
    pub shape: ShapeSpec,
    /// Solid material (a built-in name).
    pub material: String,
    /// Mass \[kg\]; `None` = from the shape and the material's density.
    pub mass: Option<f64>,
    /// Takes part in collisions.
    pub collision: bool,
    /// Parent body index (`None` = the world).
    pub parent: Option<usize>,
    /// Mount frame position in the parent \[m\].
    pub mount: [f64; 3],
    /// Mount frame Cardan angles \[rad\].
    pub mount_rot: [f64; 3],
    /// Connection to the parent.
    pub joint: JointSpec,
}

/// A force element (`scene::ForceElement`); closures are described by their law.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ForceSpec {
    /// Spring-damper between the origins of body `a` (`None` = world) and body `b`.
    Spring {
        /// First body (`None` = world).
        a: Option<usize>,
        /// Second body.
        b: usize,
        /// [N/m]
        stiffness: f64,
        /// [N·s/m]
        damping: f64,
        /// \[m\]
        length0: f64,
    },
    /// Joint spring-damper on body `body`'s joint (must be revolute or prismatic).
    JointSpring {
        /// Body index.
        body: usize,
        /// Stiffness.
        stiffness: f64,
        /// Damping.
        damping: f64,
        /// Offset.
        offset: f64,
    },
    /// `ObjectForce` closure: a constant world force \[N\] and torque [N·m] on body `body`.
    Constant {
        /// Body index.
        body: usize,
        /// Force \[N\].
        force: [f64; 3],
        /// Torque [N·m].
        torque: [f64; 3],
    },
    /// `ObjectForce` closure: linear drag `−c·v` \[N\] on body `body`.
    Drag {
        /// Body index.
        body: usize,
        /// [N·s/m]
        c: f64,
    },
}

/// An input declared on body `body` (`scene::Input`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum InputSpec {
    /// Generalised force on the body's (scalar) joint.
    JointForce(usize),
    /// Prescribed acceleration of the body's (scalar) joint.
    JointAcceleration(usize),
    /// World wrench on the body's origin.
    Wrench(usize),
}

/// One step of the step-wise API: set the inputs, then `advance_to(t)`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StepSpec {
    /// Values for input `i{k}` (index into `SceneSpec::inputs`).
    pub inputs: Vec<(usize, Vec<f64>)>,
    /// Target time \[s\].
    pub t: f64,
}

/// Run options.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunSpec {
    /// Stop time \[s\].
    pub stop_time: f64,
    /// Relative tolerance.
    pub rtol: f64,
    /// `SimOptions::max_wall_time` \[s\].
    pub max_wall_time: f64,
    /// `SimOptions::max_steps` (`None`: the default budget). Reproducers of work-budget
    /// outcomes set it below the steps their wall budget reaches, so that they end at the same
    /// step, with the same diagnosis, however loaded the machine (the generator leaves it out).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_steps: Option<u64>,
    /// Output interval \[s\] (`None` = default).
    pub interval: Option<f64>,
    /// `SimOptions::contact_results`.
    pub contact_results: bool,
    /// `SimOptions::structured_jacobian`.
    pub structured_jacobian: bool,
    /// `SimOptions::jacobian_reuse` (the generator leaves the default, true; reproducers
    /// recorded before it existed set false where their path depends on it).
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub jacobian_reuse: bool,
    /// Step-wise API: the steps (`None` = `Model::simulate`).
    pub steps: Option<Vec<StepSpec>>,
}

/// A whole random scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SceneSpec {
    /// The seed it was drawn from (0 for hand-written reproducers).
    pub seed: u64,
    /// `SceneOptions::contact_detection`.
    pub contact: bool,
    /// `SceneOptions::k_red`.
    pub k_red: f64,
    /// `SceneOptions::mpr_tolerance` (≤ 1e-9, the checked range).
    pub mpr_tolerance: f64,
    /// `SceneOptions::hysteresis` \[m\].
    pub hysteresis: f64,
    /// `ContactProfile::Modia3DLater` instead of `paper_profile`'s choice.
    pub later_profile: bool,
    /// `ContactProfile::Paper2019` instead of the default (`ContactProfile::Volume`).
    /// Reproducers recorded before the volume law became the default have no such key and
    /// replay under the paper's law, the default they were recorded with.
    #[serde(default = "paper_profile_default")]
    pub paper_profile: bool,
    /// Gravity [m/s²].
    pub gravity: [f64; 3],
    /// A fixed table (box) attached to the world: edge lengths and centre \[m\], material.
    pub table: Option<([f64; 3], [f64; 3], String)>,
    /// User contact-pair materials (cor, mu_k, mu_r) for pairs of material names.
    pub pairs: Vec<(String, String, [f64; 3])>,
    /// Bodies, parents before children.
    pub bodies: Vec<BodySpec>,
    /// Force elements.
    pub forces: Vec<ForceSpec>,
    /// Inputs (named `i{k}`).
    pub inputs: Vec<InputSpec>,
    /// Run options.
    pub run: RunSpec,
}

impl SceneSpec {
    /// The scene as JSON (for reproducers and failure reports).
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).expect("a scene spec serialises")
    }
    /// A scene from its JSON form.
    pub fn from_json(s: &str) -> Result<Self, String> {
        serde_json::from_str(s).map_err(|e| e.to_string())
    }
    /// Typical size of body `k` \[m\] (largest dimension of its shape).
    pub fn body_size(&self, k: usize) -> f64 {
        shape_size(&self.bodies[k].shape)
    }
}

/// Largest dimension of a shape \[m\].
pub fn shape_size(s: &ShapeSpec) -> f64 {
    let m3 = |l: &[f64; 3]| l[0].max(l[1]).max(l[2]);
    match s {
        ShapeSpec::Sphere(d) => *d,
        ShapeSpec::Box(l) | ShapeSpec::Ellipsoid(l) => m3(l),
        ShapeSpec::Cylinder(_, d, l) | ShapeSpec::Cone(_, d, l, _) => d.max(*l),
        ShapeSpec::Capsule(_, d, l) => d + l,
        ShapeSpec::Hull(p) => p
            .iter()
            .map(|x| 2.0 * m3(&[x[0].abs(), x[1].abs(), x[2].abs()]))
            .fold(0.0, f64::max),
    }
}

/// Volume of a shape \[m³\] (a hull by a third of its bounding box: for load scales only).
fn shape_volume(s: &ShapeSpec) -> f64 {
    use std::f64::consts::PI;
    match s {
        ShapeSpec::Sphere(d) => PI / 6.0 * d * d * d,
        ShapeSpec::Box(l) => l[0] * l[1] * l[2],
        ShapeSpec::Ellipsoid(l) => PI / 6.0 * l[0] * l[1] * l[2],
        ShapeSpec::Cylinder(_, d, l) => PI / 4.0 * d * d * l,
        ShapeSpec::Capsule(_, d, l) => PI / 4.0 * d * d * l + PI / 6.0 * d * d * d,
        ShapeSpec::Cone(_, d, l, t) => PI / 12.0 * l * (d * d + d * t + t * t),
        ShapeSpec::Hull(p) => {
            let ext = |i: usize| {
                let (lo, hi) = p
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                        (a.min(x[i]), b.max(x[i]))
                    });
                hi - lo
            };
            ext(0) * ext(1) * ext(2) / 3.0
        }
    }
}

/// A body's mass \[kg\]: as given, or from its material's density (for load scales only).
fn mass_estimate(b: &BodySpec) -> f64 {
    b.mass.unwrap_or_else(|| {
        let rho =
            modia3d::core::scene::builtin_solid_material(&b.material).map_or(1000.0, |m| m.density);
        rho * shape_volume(&b.shape)
    })
}

/// Materials a scene draws from: mostly one family with a built-in pair, sometimes mixed.
const FAMILIES: &[&[&str]] = &[
    &["Steel"],
    &["Steel"],
    &["DryWood"],
    &["BilliardBall"],
    &[
        "BilliardBall",
        "BilliardTable",
        "BilliardCushion",
        "BilliardCue",
    ],
    &["Steel", "DryWood", "Aluminium"],
];

fn gen_shape(r: &mut Rng, scale: f64) -> ShapeSpec {
    let dim = |r: &mut Rng| (scale * r.log_uniform(0.3, 3.0)).clamp(1e-3, 1.0);
    let axis = r.pick(&[1, 2, 3]);
    match r.below(7) {
        0 => ShapeSpec::Sphere(dim(r)),
        1 => ShapeSpec::Box([dim(r), dim(r), dim(r)]),
        2 => ShapeSpec::Cylinder(axis, dim(r), dim(r)),
        3 => ShapeSpec::Capsule(axis, dim(r), dim(r)),
        4 => {
            let d = dim(r);
            let top = if r.chance(0.5) {
                0.0
            } else {
                d * r.uniform(0.1, 0.9)
            };
            ShapeSpec::Cone(axis, d, dim(r), top)
        }
        5 => ShapeSpec::Ellipsoid([dim(r), dim(r), dim(r)]),
        _ => {
            // A tetrahedron-like hull around the origin plus a few random points.
            let s = 0.5 * dim(r);
            let mut p = vec![[s, s, s], [s, -s, -s], [-s, s, -s], [-s, -s, s]];
            for _ in 0..r.below(5) {
                p.push(r.vec3(s));
            }
            ShapeSpec::Hull(p)
        }
    }
}

/// A random offset \[m\] from a parent: anywhere in a box of half-width `spread` above the
/// table for the world, a few sizes away in a random direction for a body.
fn offset(r: &mut Rng, scale: f64, parent_is_world: bool, spread: f64) -> [f64; 3] {
    if parent_is_world {
        let p = r.vec3(spread);
        [p[0], p[1], p[2].abs() + 2.0 * scale]
    } else {
        let d = unit(r);
        let l = r.uniform(1.5, 4.0) * scale;
        [l * d[0], l * d[1], l * d[2]]
    }
}

/// A random unit vector.
fn unit(r: &mut Rng) -> [f64; 3] {
    let v = r.vec3(1.0);
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt().max(1e-12);
    [v[0] / n, v[1] / n, v[2] / n]
}

fn gen_joint(r: &mut Rng, scale: f64, parent_is_world: bool, spread: f64) -> JointSpec {
    let speed = |r: &mut Rng| {
        if r.chance(0.3) {
            0.0
        } else {
            r.log_uniform(1e-3, 10.0)
        }
    };
    match r.below(14) {
        0..=4 => {
            let (sp, d) = (speed(r), unit(r));
            let p = offset(r, scale, parent_is_world, spread);
            let spin = if r.chance(0.5) { 0.0 } else { 20.0 };
            JointSpec::Free {
                r: p,
                rot: r.vec3(3.2),
                v: [sp * d[0], sp * d[1], sp * d[2]],
                w: r.vec3(spin),
            }
        }
        5 | 6 => JointSpec::Revolute {
            axis: r.pick(&[1, 2, 3, -1, -2, -3]),
            phi: r.uniform(-3.2, 3.2),
            w: r.uniform(-10.0, 10.0) * r.unit(),
            can_collide: r.chance(0.3),
        },
        7 => JointSpec::Prismatic {
            axis: r.pick(&[1, 2, 3, -1, -2, -3]),
            s: r.uniform(-scale, scale),
            v: r.uniform(-10.0, 10.0) * r.unit(),
            can_collide: r.chance(0.3),
        },
        8 => JointSpec::Fix,
        10 => JointSpec::Spherical {
            rot: r.vec3(3.2),
            w: r.vec3(10.0),
            can_collide: r.chance(0.3),
        },
        11 => {
            let a1: i64 = r.pick(&[1, 2, 3]);
            let a2 = a1 % 3 + 1;
            JointSpec::Universal {
                axis1: a1 * r.pick(&[1, -1]),
                axis2: a2 * r.pick(&[1, -1]),
                phi: [r.uniform(-3.2, 3.2), r.uniform(-1.2, 1.2)],
                w: [r.uniform(-10.0, 10.0), r.uniform(-10.0, 10.0)],
                can_collide: r.chance(0.3),
            }
        }
        12 => JointSpec::Cylindrical {
            axis: r.pick(&[1, 2, 3, -1, -2, -3]),
            q: [r.uniform(-3.2, 3.2), r.uniform(-scale, scale)],
            v: [r.uniform(-10.0, 10.0), r.uniform(-10.0, 10.0) * r.unit()],
            can_collide: r.chance(0.3),
        },
        13 => JointSpec::Planar {
            normal: r.pick(&[1, 2, 3, -1, -2, -3]),
            q: [
                r.uniform(-scale, scale),
                r.uniform(-scale, scale),
                r.uniform(-3.2, 3.2),
            ],
            v: [
                r.uniform(-10.0, 10.0) * r.unit(),
                r.uniform(-10.0, 10.0) * r.unit(),
                r.uniform(-10.0, 10.0),
            ],
            can_collide: r.chance(0.3),
        },
        _ => JointSpec::Attached,
    }
}

/// The scene of `seed`.
pub fn generate(seed: u64) -> SceneSpec {
    let r = &mut Rng(seed);
    let family = r.pick(FAMILIES);
    let scale = r.log_uniform(1e-3, 0.5);
    let n = 1 + r.below(12);
    // Room for the free bodies: a few sizes per body in each direction.
    let spread = (2.0 + n as f64) * scale;
    let mut bodies: Vec<BodySpec> = vec![];
    for k in 0..n {
        let parent = (k > 0 && r.chance(0.35)).then(|| r.below(k));
        let shape = gen_shape(r, scale);
        let mut joint = gen_joint(r, scale, parent.is_none(), spread);
        // Overlaps on purpose: now and then a free body starts at (or near) another's place.
        if let (JointSpec::Free { r: pos, .. }, true) = (&mut joint, k > 0 && r.chance(0.15)) {
            if let Some(JointSpec::Free { r: other, .. }) = bodies.last().map(|b| &b.joint) {
                let f = r.pick(&[0.0, 0.0, 0.2, 0.6, 0.95]) * scale;
                *pos = [other[0] + f, other[1], other[2]];
            }
        }
        bodies.push(BodySpec {
            shape,
            material: r.pick(family).to_string(),
            mass: (!r.chance(0.25)).then(|| r.log_uniform(1e-3, 1e3)),
            collision: r.chance(0.8),
            parent,
            mount: offset(r, scale, parent.is_none(), spread),
            mount_rot: if r.chance(0.5) { [0.0; 3] } else { r.vec3(3.2) },
            joint,
        });
    }
    let table = r.chance(0.7).then(|| {
        let l = [
            r.log_uniform(10.0 * scale, 20.0 * scale).min(2.0),
            r.log_uniform(10.0 * scale, 20.0 * scale).min(2.0),
            r.log_uniform(0.2 * scale, 2.0 * scale).clamp(1e-3, 1.0),
        ];
        (l, [0.0, 0.0, -0.5 * l[2]], r.pick(family).to_string())
    });
    let mut pairs = vec![];
    if family.len() > 1 && r.chance(0.6) {
        for (i, a) in family.iter().enumerate() {
            for b in &family[i..] {
                let m = [
                    r.uniform(0.0, 1.0),
                    r.uniform(0.0, 0.8),
                    r.uniform(0.0, 0.01),
                ];
                pairs.push((a.to_string(), b.to_string(), m));
            }
        }
    }
    let scalar: Vec<usize> = (0..n)
        .filter(|&k| {
            matches!(
                bodies[k].joint,
                JointSpec::Revolute { .. } | JointSpec::Prismatic { .. }
            )
        })
        .collect();
    // Loads are drawn relative to the body they act on (its mass and size), over
    // log-wide ranges: a user who had not tuned anything still writes a 10 N force for a
    // kilogram, not for a 14 mg bead (absolute loads gave millimetre scenes 1e5 g, bodies at
    // km/s and spins of 1e8 rad/s: physics no integrator follows cheaply, not library faults).
    // A load held over the whole run brings a free body to at most the 10 m/s of the drawn
    // velocities (its surface, for a torque): forces up to `m · 10 m/s / T`, torques up to
    // `(m L²/10) · (10 m/s / L) / T` (a constant torque of 10 times the weight times the size
    // spun a 1 mm body to 1e7 rad/s in a second).
    let stop_time = r.uniform(0.05, 1.0);
    let accel = 10.0 / stop_time;
    let mass: Vec<f64> = bodies.iter().map(mass_estimate).collect();
    let size: Vec<f64> = bodies.iter().map(|b| shape_size(&b.shape)).collect();
    let force_unit = |k: usize| mass[k] * accel;
    let torque_unit = |k: usize| 0.1 * mass[k] * size[k] * accel;
    let revolute = |k: usize| matches!(bodies[k].joint, JointSpec::Revolute { .. });
    // A scalar joint's inertia (mass, or a rotational inertia estimate m L² / 10) and its
    // acceleration unit (that of its surface for a rotation); their product is its load unit,
    // `torque_unit` or `force_unit`.
    let joint_inertia = |k: usize| {
        if revolute(k) {
            0.1 * mass[k] * size[k] * size[k]
        } else {
            mass[k]
        }
    };
    let joint_accel = |k: usize| if revolute(k) { accel / size[k] } else { accel };
    let mut forces = vec![];
    for _ in 0..r.below(4) {
        let b = r.below(n);
        // Natural angular frequency [rad/s] of a spring, log-uniform from 1 up to 3e3 (a 2 ms
        // period) or to the bound that keeps the speeds its initial stretch can give within
        // the 10 m/s of the drawn velocities (ω · stretch ≤ 10 m/s: a 1.4e6 N/m spring
        // stretched 0.7 m flung a 0.35 kg box into a sphere at ~200 m/s), and a damping ratio.
        let u = r.unit();
        let omega = |stretch: f64| (10.0 / stretch).clamp(1.0, 3e3).powf(u);
        let zeta = r.pick(&[0.0, 0.05, 1.0]);
        let f = match r.below(4) {
            0 => {
                let a = (r.chance(0.5) && b > 0).then(|| r.below(b));
                let m = a.map_or(mass[b], |a| mass[a].min(mass[b]));
                // Bodies lie within the placement box of half-width `spread`.
                let w = omega(2.0 * spread);
                let k = m * w * w;
                ForceSpec::Spring {
                    a,
                    b,
                    stiffness: k,
                    damping: 2.0 * zeta * (k * m).sqrt(),
                    length0: r.uniform(0.0, 2.0 * scale),
                }
            }
            1 if !scalar.is_empty() => {
                let body = r.pick(&scalar);
                let i = joint_inertia(body);
                // Offset and initial coordinate together: up to ~4 rad times the size for a
                // revolute joint, ~3 sizes for a prismatic one.
                let w = omega(if revolute(body) { 4.0 } else { 3.0 } * size[body]);
                let k = i * w * w;
                ForceSpec::JointSpring {
                    body,
                    stiffness: k,
                    damping: 2.0 * zeta * (k * i).sqrt(),
                    offset: r.uniform(-1.0, 1.0)
                        * if revolute(body) {
                            1.0
                        } else {
                            2.0 * size[body]
                        },
                }
            }
            2 => {
                let (f, t) = (unit(r), unit(r));
                let f_abs = force_unit(b) * r.log_uniform(1e-3, 1.0);
                let t_abs = torque_unit(b) * r.log_uniform(1e-3, 1.0);
                ForceSpec::Constant {
                    body: b,
                    force: f.map(|x| x * f_abs),
                    torque: t.map(|x| x * t_abs),
                }
            }
            _ => ForceSpec::Drag {
                body: b,
                // Time constants m/c of 10 ms…100 s.
                c: mass[b] * r.log_uniform(1e-2, 1e2),
            },
        };
        forces.push(f);
    }
    let mut inputs = vec![];
    let steps = r.chance(0.2).then(|| {
        if !scalar.is_empty() && r.chance(0.6) {
            let k = r.pick(&scalar);
            inputs.push(if r.chance(0.7) {
                InputSpec::JointForce(k)
            } else {
                InputSpec::JointAcceleration(k)
            });
        }
        if r.chance(0.5) {
            inputs.push(InputSpec::Wrench(r.below(n)));
        }
        let ns = 2 + r.below(4);
        (1..=ns)
            .map(|s| {
                let mut set = vec![];
                for (i, inp) in inputs.iter().enumerate() {
                    if r.chance(0.7) {
                        // Values in the load units of the force elements above (and up to
                        // the same 10 m/s over the run for a prescribed acceleration).
                        let units: Vec<f64> = match *inp {
                            InputSpec::Wrench(k) => {
                                let (f, t) = (force_unit(k), torque_unit(k));
                                vec![f, f, f, t, t, t]
                            }
                            InputSpec::JointForce(k) => vec![joint_inertia(k) * joint_accel(k)],
                            InputSpec::JointAcceleration(k) => vec![joint_accel(k)],
                        };
                        set.push((i, units.iter().map(|u| u * r.uniform(-1.0, 1.0)).collect()));
                    }
                }
                StepSpec {
                    inputs: set,
                    t: stop_time * s as f64 / ns as f64,
                }
            })
            .collect()
    });
    SceneSpec {
        seed,
        contact: r.chance(0.85),
        k_red: if r.chance(0.7) {
            1.0
        } else {
            r.log_uniform(1e-4, 1.0)
        },
        mpr_tolerance: if r.chance(0.6) {
            1e-11
        } else {
            r.log_uniform(1e-13, 1e-9)
        },
        hysteresis: if r.chance(0.7) {
            1e-8
        } else {
            r.log_uniform(1e-13, 1e-6)
        },
        later_profile: r.chance(0.2),
        paper_profile: false,
        gravity: if r.chance(0.9) {
            [0.0, 0.0, -9.81]
        } else {
            r.vec3(10.0)
        },
        table,
        pairs,
        bodies,
        forces,
        inputs,
        run: RunSpec {
            stop_time,
            rtol: r.log_uniform(1e-9, 1e-3),
            max_wall_time: 2.0,
            max_steps: None,
            interval: r
                .chance(0.2)
                .then(|| stop_time / r.log_uniform(10.0, 5000.0)),
            contact_results: r.chance(0.3),
            structured_jacobian: r.chance(0.85),
            jacobian_reuse: true,
            steps,
        },
    }
}

/// Serde default of [`RunSpec::jacobian_reuse`].
fn yes() -> bool {
    true
}

/// Serde: leave out a field at its default, true.
fn is_true(x: &bool) -> bool {
    *x
}

/// `SceneSpec::paper_profile` of a reproducer without the key (recorded under the paper's law).
fn paper_profile_default() -> bool {
    true
}
