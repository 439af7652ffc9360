//! The `model!` macro of modia3d: Modia-like declarative 3D multibody models written as Rust
//! source, checked at compile time and expanded into the core builder API
//! (`modia3d::core::SceneDesc`). Use it through the facade: `use modia3d::prelude::*;`.
//!
//! Stages: `ast.rs` (parse) → `check/` (names, keys, references; lowers to the IR of
//! `ir.rs`, with `vocab.rs` and `names.rs`) → `rules.rs` (the core's scene rules on the
//! literal part: `modia3d_core::SceneDesc::scene_errors`, the code `build()` runs) →
//! `expand/` (builder calls). The entry point below only chains them.
#![warn(missing_docs)]
#![warn(unreachable_pub)]
#![forbid(unsafe_code)]

mod ast;
mod check;
mod expand;
mod floats;
mod ir;
mod names;
mod rules;
#[cfg(test)]
mod verdict_tests;
mod vocab;

use proc_macro::TokenStream;

/// Defines a 3D multibody model (or a reusable sub-assembly) as a Rust type.
///
/// ```ignore
/// use modia3d::prelude::*;
///
/// model! {
///     /// A pendulum. Doc comments become the generated type's docs.
///     pub Pendulum(length: f64 = 1.0, mass: f64 = 1.0, phi0: f64 = 0.5) {
///         world = Object3D(feature = Scene(gravity = [0.0, 0.0, -9.81])),
///         body  = Object3D(feature = Solid(shape = Sphere(diameter = 0.1),
///                                          mass_properties = MassProperties(mass = mass))),
///         frame = Object3D(parent = body, translation = [0.0, 0.0, length]),
///         rev   = Revolute(obj1 = world, obj2 = frame, axis = 1, phi = Var(init = phi0)),
///     }
/// }
///
/// let model = Pendulum { length: 2.0, ..Default::default() }.build()?;
/// let result = model.simulate(&SimOptions::new(5.0).tolerance(1e-8))?;
/// let phi = result.signal("rev.phi")?;
/// ```
///
/// # Grammar
///
/// ```text
/// model!     { attr* vis [assembly] Name [( param, … )] { component, … } }
/// param      := attr* name: Type = default
/// component  := name = Constructor(key = value, …)
/// value      := a Rust expression; parameters are locals of type `Type` (cloned);
///               nested constructors (`Sphere(…)`, `Var(…)`) where the key expects one
/// reference  := name | subassembly.path.to.part
/// ```
///
/// A *model* (no `assembly` keyword) has exactly one `Scene` object and gets `build()`.
/// An *assembly* (`pub assembly Arm(…) { … }`) has no `Scene`; it is used as a component of
/// other models.
///
/// ## Components (`name = …`)
///
/// | constructor | keys (`*` required, `= default`) |
/// |---|---|
/// | `Object3D` | `parent` (reference), `translation = [0,0,0]` (`[f64; 3]`, m, in the parent), `rotation` (Cardan angles `[f64; 3]` in rad, x then new y then new z; or a `Matrix3<f64>` whose columns are the frame's axes; or a `Rotation`), `feature` |
/// | `Revolute` | `obj1*`, `obj2*`, `axis = 3` (±1, ±2, ±3, an `i64` expression, or an array `[x, y, z]`), `phi = Var(init = …)` (rad), `w = Var(init = …)` (rad/s), `can_collide = false` (true with `modia3d_conventions` on Revolute and Prismatic), `cut = false` (prefer this joint as the one that closes its kinematic loop: it becomes a cut joint, enforced by constraints) |
/// | `Prismatic` | `obj1*`, `obj2*`, `axis = 3`, `s = Var(init = …)` (m), `v = Var(init = …)` (m/s), `can_collide`, `cut` |
/// | `FreeMotion` | `obj1*`, `obj2*`, `r`, `v`, `w`: each `Var(init = [f64; 3] or Vector3<f64>)`, default zero; `rot = Var(init = …)`: Cardan angles `[f64; 3]` or a `UnitQuaternion<f64>`; `can_collide`, `cut` |
/// | `Spherical` | `obj1*`, `obj2*`, `rot = Var(init = …)` (Cardan angles or a `UnitQuaternion<f64>`), `w = Var(init = [f64; 3])` (rad/s, resolved in obj2), `can_collide`, `cut` |
/// | `Universal` | `obj1*`, `obj2*`, `axis1*` (fixed in obj1), `axis2*` (fixed in obj2, perpendicular to `axis1`; each as `axis`), `phi1`, `phi2` (rad), `w1`, `w2` (rad/s) as `Var(init = …)`, `can_collide`, `cut` |
/// | `Cylindrical` | `obj1*`, `obj2*`, `axis = 3`, `phi` (rad), `s` (m), `w` (rad/s), `v` (m/s) as `Var(init = …)`, `can_collide`, `cut` |
/// | `Planar` | `obj1*`, `obj2*`, `normal = 3` (as `axis`), `x`, `y` (m, resolved in obj1 along the plane axes: normal z → x, y; x → y, z; y → z, x), `phi` (rad), `vx`, `vy` (m/s), `w` (rad/s) as `Var(init = …)`, `can_collide`, `cut` |
/// | `Fix` | `obj1*`, `obj2*`, `can_collide`, `cut` |
/// | limits (every kind above with scalar coordinates) | per coordinate `c` (`phi`, `s`, `phi1`, `x`, …): `c_limits = [lower, upper]` (rad or m; `f64::NEG_INFINITY`/`f64::INFINITY` for an open side), `c_limit_stiffness` (N·m/rad or N/m; default from the coordinate's inertia), `c_limit_cor = 0.5`: a compliant stop (docs/joint-limits.md); signal `<joint>.limit_f` (`limit_f_<c>` on joints with several) |
/// | `SpringDamper` | `obj1*`, `obj2*`, `stiffness*` (N/m), `damping = 0` (N·s/m), `length0 = 0` (m); or `spring_law` (N from the elongation in m) / `damper_law` (N from the rate in m/s) in place of `stiffness` / `damping`: a number (the coefficient) or a closure `\|x\| …` (a `SpringDamperPtP`; signals `length`, `length_rate`, `tension`) |
/// | `Bushing` | `obj1*`, `obj2*`, `nominal_force = 0` (N, along obj1's axes), `spring_law`, `damper_law` (per axis x, y, z of obj1: `[a, b, c]`, each a number in N/m, N·s/m or a closure `\|x\| …` → N), `nominal_torque = 0` (N·m), `rot_spring_law`, `rot_damper_law` (per angle, N·m/rad, N·m·s/rad or closures → N·m), `large_angles = false` (Cardan formulation); unset laws are 0; signals `r`, `v`, `angles`, `rates`, `force`, `torque` |
/// | `WorldForce` | `object*`, `force*` (N: `[f64; 3]`, `Vector3<f64>` or a closure `\|t, m: &ObjectMotion\| -> Vector3<f64>`), `resolved_in` (an object whose axes resolve the force; default world) |
/// | `WorldTorque` | `object*`, `torque*` (N·m, as `force`), `resolved_in` |
/// | `JointSpringDamper` | `joint*` (a joint with scalar coordinates), `coordinate` (`"phi2"`, `"s"`, …; needed on a joint with several), `stiffness*`, `damping = 0`, `offset = 0` |
/// | `ObjectForce` | `object*`, `law*`: a closure `move \|t: f64, m: &ObjectMotion\| -> Wrench` |
/// | `SolidMaterial` | `density*` (kg/m³), `young_modulus*` (N/m²), `poisson_ratio*` — a material of this block |
/// | `ContactPair` | `material1*`, `material2*` (`"Steel"`, a block material `wood` or `"wood"`, or a `&str`/`String` expression), `cor*` ([0, 1]), `mu_k*`, `mu_r*` (≥ 0), `v_min` (m/s), `w_min` (rad/s) (`f64` or `Option<f64>`; default: the scene's) — a contact-pair material (`SceneDesc::add_contact_pair`) |
/// | `JointForce` | `joint*` (a joint with scalar coordinates), `coordinate` (as for `JointSpringDamper`) — an input: generalised force, 1 value (N·m or N) |
/// | `JointAcceleration` | `joint*`, `coordinate` (as for `JointForce`) — an input: prescribed acceleration, 1 value (rad/s² or m/s²) |
/// | `ObjectWrench` | `object*` — an input: world force and torque at the object's origin, 6 values |
/// | `ActionAttach` | `object*` (obj2 of a FreeMotion), `to*` (objects), `at*` (s, ≥ 0), `gap*` (m, ≥ 0) — at time `at`, fix `object` rigidly to `to` at their current relative pose if they are at most `gap` apart (`SceneDesc::add_action`; docs/segments.md) |
/// | `ActionRelease` | `object*`, `at*` — give the attached `object` a FreeMotion again at its current pose and velocity |
/// | `ActionDelete` | `object*`, `at*` — remove `object`, its children, joints, force elements and inputs |
/// | a block kind (below) | a block with ports and states in the DAE: `pi = PI(k = k2, T = t2, u = …)` |
/// | any other type | a sub-assembly: `arm1 = Arm(parent = base, length = 0.5)` |
///
/// ## Blocks
///
/// Controllers, sources and drives solved with the mechanism under one error control
/// (docs/drive-trains.md; the builder's `SceneDesc::add_component`), from the core's table
/// `BLOCK_KINDS` (the structs of `modia3d::core::blocks`, Modelica's names):
///
/// ```text
/// ramp  = Ramp(height = 2.95, duration = 1.18),
/// pi    = PI(k = k2, T = t2, u = k1 * (ratio * ramp.y - drive.motor_phi) - drive.motor_w),
/// drive = Drive(joint = rev, ratio = 156.0, J_motor = 1.3909e-5, tau = pi.y),
/// ```
///
/// A key is a parameter (a struct field: a Rust expression over the model's parameters) or an
/// input port. An input is a Rust `f64` expression over the parameters, `time` \[s\] and
/// signals by path: `<block>.<output or state>` (`ramp.y`, `pi.x`, `drive.motor_w`),
/// `<joint>.<position or velocity>` of a scalar coordinate (`rev.phi`, `rev.w`, `slide.s`,
/// `slide.v`), or the same inside a sub-assembly (`axis1.drive.motor_phi`); and a joint
/// coordinate's acceleration as the derivative of its velocity, `der(<joint>.<velocity>)`
/// (`der(rev.w)` \[rad/s²\], `der(slide.v)` \[m/s²\], `der(axis1.rev.w)`; the signal
/// `"der(rev.w)"`, with the sub-assembly's prefix inside the parentheses). A lone path or
/// `der(…)` reads the signal (`Src::signal`), an expression becomes
/// `Src::expr(&[paths…], |time, v| …)` with each path and `der(…)` replaced by its value, one
/// of parameters only a `Src::Const`. `der(…)` of anything else (a position `der(rev.phi)`, a
/// block's output or state, an expression) is an error: only accelerations are derivatives
/// a block reads. An acceleration comes from the solver, not from a block's output, so a
/// `der(…)` read is no feedthrough edge of the algebraic-loop check (a force that depends on
/// an acceleration as strongly as the inertia it acts on is `SimErrorKind::AccelerationLoop`
/// at run time). Where `der` is a parameter of the model, `der(…)` is Rust's call.
///
/// | block | parameters (`*` required, `= default`) | inputs | signals (`→` feedthrough) |
/// |---|---|---|---|
/// | `Constant` | `k*` | | `y` |
/// | `Step` | `height*`, `offset = 0`, `startTime = 0` (s) | | `y` |
/// | `Ramp` | `height*`, `duration*` (s), `offset = 0`, `startTime = 0` | | `y` |
/// | `Sine` | `amplitude*`, `f*` (Hz), `phase = 0` (rad), `offset = 0`, `startTime = 0` | | `y` |
/// | `Table` | `table*` (`[(t, y), …]`) | | `y` |
/// | `Input` | `start = 0` (set by `Simulation::set_input`) | | `y`, `value` |
/// | `PtpPath` | `positions*` (rows of points `[[…], …]`), `v_max*`, `a_max*` (per axis), `startTime = 0` | | `q`, `qd`, `qdd` (several axes: `q1`, `qd1`, …) |
/// | `Gain` | `k*` | `u` | `y` → |
/// | `Feedback` | | `u1`, `u2` | `y = u1 − u2` → |
/// | `Add`, `Add3` | `k1 = 1`, `k2 = 1` (, `k3 = 1`) | `u1`, `u2` (, `u3`) | `y` → |
/// | `Limiter` | `uMax*`, `uMin = −uMax` | `u` | `y` →, `mode` |
/// | `Integrator` | `k = 1`, `y_start = 0` | `u` | `y`, `x` |
/// | `FirstOrder` | `k = 1`, `T*` (s), `y_start = 0` | `u` | `y`, `x` |
/// | `PI` | `k = 1`, `T*` (s), `x_start = 0` | `u` | `y` →, `x` |
/// | `PID` | `k = 1`, `Ti*`, `Td*` (s), `Nd = 10`, `xi_start = 0`, `xd_start = 0` | `u` | `y` →, `xi`, `xd` |
/// | `LimPID` | `k = 1`, `Ti*`, `Td*`, `yMax*`, `yMin = −yMax`, `wp = 1`, `wd = 0`, `Ni = 0.9`, `Nd = 10`, `xi_start`, `xd_start` | `u_s`, `u_m` | `y` →, `xi`, `xd`, `mode` |
/// | `Drive` | `joint*` (a joint with a scalar coordinate), `coordinate` (`"phi"`, …; needed on a joint with several), `ratio*` (motor angle per joint coordinate), `J_motor*` (kg·m²), `gear = Rigid` or `Elastic(c = …, d = …)` (N·m/rad, N·m·s/rad), `motor = Torque` or `Dc(R = …, L = …, k = …)` (Ω, H, N·m/A) | `tau` (N·m); with `Dc`: `v` (V) | `motor_phi`, `motor_w`, `tau_motor` → (not with `Dc`), `tau_load` → (rigid torque drive only); `Elastic`: `phi_gear`; `Dc`: `i` |
/// | `Sampled` | `period*` (s), `startTime = 0`, `inner*`: a block with continuous states and outputs only, as its constructor without inputs (`inner = PI(k = …, T = …)`) | the inner block's | the inner block's outputs (held, no feedthrough), `tick`, its states, `<output>_held` |
///
/// Checked at compile time, each on its token: unknown keys, missing required parameters and
/// inputs, unknown signal paths and `der(…)` of what is no joint velocity (with did-you-mean
/// hints; paths into sub-assemblies by rustc, also that a `der(…)` path is a velocity there),
/// a `Drive` on a joint without a scalar coordinate or with a `coordinate` it lacks, and
/// algebraic loops among the block's blocks (a cycle of blocks each reading another's `→`
/// output at the same instant; one through a sub-assembly is reported by `build()`). In a
/// sub-assembly blocks are named with its prefix (`axis1.pi`, signals `axis1.pi.y`), so an
/// assembly with blocks is used several times with different parameters.
///
/// An assembly reaches the outer model's signals and joints through parameters of type
/// `SignalRef` and `JointRef` (`modia3d::SignalRef`, in the prelude): inside, a `SignalRef`
/// parameter is a signal in an input (`u = k * reference`) and a `JointRef` parameter a
/// `Drive`'s joint; outside, the parameter is given a path of the outer block
/// (`servo1 = Servo(joint = shoulder, reference = ramp.y)`, checked like a block's signal
/// paths; a path given to a parameter of another type is a type error on the key):
///
/// ```text
/// pub assembly Servo(joint: JointRef = JointRef::default(), reference: SignalRef = SignalRef::time()) {
///     pi    = PI(k = 0.1, T = 1.0, u = 50.0 * (156.0 * reference - drive.motor_phi) - drive.motor_w),
///     drive = Drive(joint = joint, ratio = 156.0, J_motor = 1.3909e-5, tau = pi.y),
/// }
/// ```
///
/// Checks that need the other block's contents (a loop through a sub-assembly, a flange on a
/// `JointRef`) are `build()`'s.
///
/// ## Values of `feature`, `shape`, `mass_properties`
///
/// | constructor | keys |
/// |---|---|
/// | `Scene` | the fields of `SceneOptions`, others from its `Default`: `gravity = [0, 0, -9.81]` (`[f64; 3]` or `Vector3<f64>`, m/s²), `gravity_field` (a `GravityField`: `None`, `Uniform(g)`, `Point { mu, centre }`; replaces `gravity`), `contact_detection = true`, `exact_restitution = false` (`bool`: damping from the exact restitution relation instead of the paper's approximation), `average_missing_pairs = false` (`bool`: a missing contact pair is the mean of its two self-pairs, with a warning), `modia3d_conventions = false` (`bool`: Modia3D.jl's readings of contact stiffness, `can_collide`, `MassProperties(mass = …)` and atol; `SceneOptions::modia3d_conventions`), `k_red = 1`, `d_max = 1000` (s/m), `cor_min = 0.001`, `v_min = 0.01` (m/s), `w_min = 0.01` (rad/s), `hysteresis = 1e-8` (m), `mpr_tolerance = 1e-11`, `mpr_max_iterations = 100` (`u32`), `smoothing_radius = 0.001` (m), `profile = Volume` (or `Paper2019`, `Modia3DLater`, or a `ContactProfile` expression; sets only the profile) |
/// | `Solid` | `shape*` (unless explicit mass properties), `solid_material` (`"Steel"`, a block material's name as string or identifier, or a `&str`/`String` expression), `mass_properties` (default: from density), `collision = false`, `contact_material` (string), `smoothing_radius` (m), `layer_depth` (m: the volume contact law's elastic layer; default the shape's, `Solid::layer_depth`) |
/// | `Visual` | `shape*` |
/// | `MassProperties` | `mass*` (kg): the shape's inertia scaled to the mass, or a point mass with `modia3d_conventions`; with `inertia` (`Matrix3<f64>` or rows `[[f64; 3]; 3]`, kg·m², about the centre of mass) and `com = [0,0,0]`: explicit properties |
/// | `MassPropertiesFromShapeAndMass` | `mass*` (kg): the shape's inertia scaled to the mass, whatever the conventions |
/// | `Sphere` | `diameter*` |
/// | `Box`, `Ellipsoid` | `lengths*` (`[f64; 3]` or `Vector3<f64>`, full lengths) |
/// | `Cylinder`, `Capsule` | `axis = 3` (literal 1..3 or an `Axis` expression), `diameter*`, `length*` |
/// | `Cone` | `axis = 3`, `diameter*`, `length*`, `top_diameter = 0` |
/// | `ConvexHull` | `points*`: anything iterable over `[f64; 3]` or `Point3<f64>` |
/// | `FileMesh` | `path*` (`.obj` or `.stl`; anything `PathBuf::from` takes, read by `build()`, relative to the current directory: write `concat!(env!("CARGO_MANIFEST_DIR"), "/…")` for a crate's own file), `scale = [1, 1, 1]` (factors to metres), `convex_decomposition = false` (`bool`: collide as convex parts instead of the convex hull) |
/// | `Beam` | `axis = 3`, `length*` (straight part, without the round ends), `width*` (= diameter of the ends), `thickness*` (m) |
///
/// Any `feature` or `shape` value that is not one of these constructors is taken as a Rust
/// expression of type `Feature` or `Shape`.
///
/// ## Names and sub-assemblies
///
/// Inputs are set with `Simulation::set_input(name, values)`.
///
/// Objects, joints, force elements and inputs are named `prefix + name`: top-level names are plain
/// (`"rev"`, signals `"rev.phi"`); a sub-assembly `arm1` adds `"arm1."` (`"arm1.rev.phi"`).
/// References reach into sub-assemblies by path: `parent = arm1.tip`, `joint = arm1.rev`, to
/// any depth. Keys of a sub-assembly component other than `parent` are its parameters.
///
/// **Attach rule.** `arm1 = Arm(parent = base, …)` makes `base` the parent of Arm's
/// *root-level parts*: its objects without `parent` whose rigid body no joint of Arm moves,
/// and its own sub-assemblies without `parent` that no joint of Arm moves (recursively).
/// Without `parent`, those parts stay roots (connect them with a joint to `arm1.<part>`).
///
/// ## The generated type
///
/// `vis struct Name { pub param: Type, … }` with `Clone`, `Debug`, `Default` (the defaults in
/// the header), and
/// - `add_to(&self, scene: &mut SceneDesc, prefix: &str, parent: Option<&str>)`;
/// - `scene(&self) -> SceneDesc`;
/// - for models: `build(&self) -> Result<Model, SceneErrors>`.
///
/// A hidden module `__modia3d_Name` holds one item per component; references into a
/// sub-assembly expand to spanned uses of it, so rustc reports an unknown part on the user's
/// token. Models must be defined at module level (not inside a function) to be used as
/// sub-assemblies.
///
/// ## Compile-time checks
///
/// All errors of a block are reported in one pass, each on the offending token. The macro
/// itself checks what needs the tokens: unknown or duplicate component names, unknown
/// constructors and keys (with did-you-mean hints), missing and duplicate keys, references of
/// the wrong kind, a missing/duplicate/misplaced `Scene`, `can_collide` outside joints, shape
/// and joint axes outside 1..3 / ±1..3. The rules of a valid scene are the core's: the macro
/// builds the block's literal part as a `SceneDesc` (neutral stand-ins for values known only at
/// run time and for the parts of sub-assemblies) and runs `SceneDesc::scene_errors` on it — the
/// same code `SceneDesc::build` runs — so it reports, on the literal's token: values out of
/// range (dimensions, masses, material data, damping, scene options, contact pairs), unknown
/// solid materials, solids without a mass or with `collision = true` but no material, parent
/// cycles, objects moved by two joints, joints with identical ends, zero joint axes, Universal
/// axes that are not perpendicular, kinematic loops, inputs and joint spring-dampers on joints
/// without a scalar coordinate or with an unknown or (on a joint with several) missing
/// `coordinate`, a joint driven twice, and two
/// contact materials that can meet without a pair entry (only in a model without
/// sub-assemblies, with literal contact detection and literal pair names; solids on one rigid
/// body or on the two bodies of a joint other than FreeMotion without `can_collide` never meet). Errors
/// that concern stand-ins are left to `build()`; so is "not connected to the world" while
/// other errors are reported. Via rustc: unknown parts of sub-assemblies, unknown sub-assembly
/// parameters and type mismatches of values.
#[proc_macro]
pub fn model(input: TokenStream) -> TokenStream {
    let mut def = syn::parse_macro_input!(input as ast::ModelDef);
    floats::floatify(&mut def);
    match check_block(&def) {
        Ok(ir) => expand::expand(&def, &ir).into(),
        Err(e) => {
            let mut out = e.to_compile_error();
            out.extend(expand::fallback(&def));
            out.into()
        }
    }
}

/// The macro's verdict on a parsed block: its own checks, then the core's scene rules on the
/// literal part; all errors combined.
fn check_block(def: &ast::ModelDef) -> Result<ir::Ir, syn::Error> {
    let (ir, mut errors) = check::check(def);
    rules::check(def, &ir, &mut errors);
    match errors.combined() {
        None => Ok(ir),
        Some(e) => Err(e),
    }
}
