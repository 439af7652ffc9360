//! Applied forces: force elements and user force laws → external body forces (`ws.f_ext`,
//! about body origins, resolved in body frames) and generalised joint forces (`ws.tau_applied`).
//! Needs `kinematics::position_velocity` first. No allocation.

use super::kinematics::{object_in_world, point_velocity};
use super::{BodyId, InputTarget, ObjectId, Plan, Workspace};
use crate::scene::{Bushing, Law, ObjectMotion, ScalarLaw, VectorLaw, Wrench};
use crate::scene::{SceneError, SceneErrors, ValidForce};
use crate::spatial::Force;
use nalgebra::{Matrix3, Vector3};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// A force element that failed: a user law that panicked or returned a non-finite value, or
/// an element in a configuration where it is undefined (a bushing's Cardan angles at gimbal
/// lock, a body at the centre of point gravity). Its contribution is left out of that
/// evaluation; the driver ends the run with it.
#[derive(Clone, Debug, PartialEq)]
pub struct UserFault {
    /// The object the law acts on, or the element's name.
    pub object: String,
    /// What the element is, before `object` in messages ("ObjectForce on", "bushing", …).
    pub what: &'static str,
    /// Index of the force element (in the scene's order of force elements); `None` for the
    /// gravity field.
    pub element: Option<usize>,
    /// Time \[s\] of the call.
    pub t: f64,
    /// What went wrong.
    pub kind: FaultKind,
}

/// How a force element failed.
#[derive(Clone, Debug, PartialEq)]
pub enum FaultKind {
    /// It panicked, with this payload as text.
    Panic(String),
    /// It returned a NaN or infinite component: force \[N\] and torque [N·m], in world.
    NonFinite {
        /// The force returned \[N\].
        force: [f64; 3],
        /// The torque returned [N·m].
        torque: [f64; 3],
    },
    /// The element is undefined in this configuration, or a scalar law returned a non-finite
    /// value; the text says which and what to do.
    Undefined(String),
}

impl UserFault {
    /// The element in words: `ObjectForce on `ball` (force element 2)`.
    pub fn element_name(&self) -> String {
        match self.element {
            Some(e) => format!("{} `{}` (force element {e})", self.what, self.object),
            None => format!("{} `{}`", self.what, self.object),
        }
    }
}

/// The text of a panic payload (`&str` or `String`; otherwise a placeholder).
pub(crate) fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(a panic without a text payload)".into())
}

/// Adds a force `force` \[N\] acting at the world point `point` \[m\] and a pure torque `torque`
/// [N·m], all resolved in world, to body `b` (nothing for the world).
#[inline]
pub(crate) fn add_world_wrench(
    ws: &mut Workspace,
    b: Option<BodyId>,
    point: &Vector3<f64>,
    force: &Vector3<f64>,
    torque: &Vector3<f64>,
) {
    if let Some(b) = b {
        let f = world_wrench_in_body(ws, b, point, force, torque);
        ws.f_ext[b] = ws.f_ext[b] + f;
    }
}

/// The wrench of `force` \[N\] acting at `point` and `torque` \[N·m\] (all resolved in world) as
/// a spatial force on body `b` about its origin, resolved in the body frame (what
/// [`add_world_wrench`] adds to `ws.f_ext`).
#[inline]
pub(crate) fn world_wrench_in_body(
    ws: &Workspace,
    b: BodyId,
    point: &Vector3<f64>,
    force: &Vector3<f64>,
    torque: &Vector3<f64>,
) -> Force {
    let x = &ws.world[b];
    let n_world = torque + (point - x.pos).cross(force);
    Force {
        n: x.rot.tr_mul(&n_world),
        f: x.rot.tr_mul(force),
    }
}

/// The motion of object `o` at the current workspace state.
pub(crate) fn object_motion(plan: &Plan, ws: &Workspace, o: usize) -> ObjectMotion {
    let x = object_in_world(plan, ws, ObjectId(o));
    let (v, w) = point_velocity(ws, plan.objects[o].body, &x.pos);
    ObjectMotion {
        r_abs: x.pos,
        rot_abs: x.rot,
        v_abs: v,
        w_abs: w,
    }
}

/// Evaluates a scalar law at `x`: a linear law inline, a closure out of line (`call_law`), so
/// the linear elements cost what they did before laws existed.
#[inline]
fn eval_law(law: &Law, x: f64, name: &'static str) -> Result<f64, FaultKind> {
    match law {
        Law::Linear(c) => Ok(c * x),
        Law::Fn(f) => call_law(&**f, x, name),
    }
}

/// A closure law with its panic caught and its value checked (`name` says which law in the
/// error: "spring law", …).
#[inline(never)]
fn call_law(f: &ScalarLaw, x: f64, name: &'static str) -> Result<f64, FaultKind> {
    match catch_unwind(AssertUnwindSafe(|| f(x))) {
        Ok(y) if y.is_finite() => Ok(y),
        Ok(y) => Err(FaultKind::Undefined(format!(
            "its {name} returned {y} for the argument {x}; a force law must return a finite value for every state the integrator tries"
        ))),
        Err(payload) => Err(FaultKind::Panic(panic_text(payload.as_ref()))),
    }
}

/// A point-to-point spring-damper at the current state: length \[m\], its rate [m/s], the
/// tension \[N\] (positive pulls the ends together) and the unit vector from obj1 to obj2
/// (zero at zero length, where no force acts).
pub(crate) struct PtpState {
    pub(crate) length: f64,
    pub(crate) rate: f64,
    pub(crate) tension: f64,
    pub(crate) dir: Vector3<f64>,
    /// The ends' origins, resolved in world \[m\].
    pub(crate) r1: Vector3<f64>,
    pub(crate) r2: Vector3<f64>,
}

/// [`PtpState`] of a `ValidForce::SpringDamper`.
pub(crate) fn ptp_state(
    plan: &Plan,
    ws: &Workspace,
    (obj1, obj2): (usize, usize),
    (spring, damper): (&Law, &Law),
    length0: f64,
) -> Result<PtpState, FaultKind> {
    let m1 = object_motion(plan, ws, obj1);
    let m2 = object_motion(plan, ws, obj2);
    let d = m2.r_abs - m1.r_abs;
    let length = d.norm();
    // Direction undefined at zero length: no force (a rod of zero length).
    let dir = if length > 0.0 {
        d / length
    } else {
        Vector3::zeros()
    };
    let rate = dir.dot(&(m2.v_abs - m1.v_abs));
    let tension = if length > 0.0 {
        eval_law(spring, length - length0, "spring law")? + eval_law(damper, rate, "damper law")?
    } else {
        0.0
    };
    Ok(PtpState {
        length,
        rate,
        tension,
        dir,
        r1: m1.r_abs,
        r2: m2.r_abs,
    })
}

/// A bushing at the current state, all resolved in obj1: position `r` \[m\] of obj2's origin
/// and its rate `v` [m/s] as seen in obj1, the angles \[rad\] and their rates [rad/s] (see
/// `scene::Bushing`), the force \[N\] and torque [N·m] on obj2.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct BushingState {
    pub(crate) r: Vector3<f64>,
    pub(crate) v: Vector3<f64>,
    pub(crate) angles: Vector3<f64>,
    pub(crate) rates: Vector3<f64>,
    pub(crate) force: Vector3<f64>,
    pub(crate) torque: Vector3<f64>,
}

/// `|cos β|` below which the large-angle bushing formulation counts as singular.
pub(crate) const BUSHING_GIMBAL_LOCK: f64 = 1e-6;

/// [`BushingState`] of a bushing between objects `obj1` and `obj2`; also returns obj2's
/// origin and obj1's rotation (to apply the wrench).
pub(crate) fn bushing_state(
    plan: &Plan,
    ws: &Workspace,
    obj1: usize,
    obj2: usize,
    b: &Bushing,
) -> Result<(BushingState, Vector3<f64>, Matrix3<f64>), FaultKind> {
    let m1 = object_motion(plan, ws, obj1);
    let m2 = object_motion(plan, ws, obj2);
    let r1 = m1.rot_abs;
    let d = m2.r_abs - m1.r_abs;
    let r = r1.tr_mul(&d);
    let v = r1.tr_mul(&(m2.v_abs - m1.v_abs - m1.w_abs.cross(&d)));
    let rel = r1.tr_mul(&m2.rot_abs); // columns: obj2's axes in obj1
    let w = r1.tr_mul(&(m2.w_abs - m1.w_abs)); // relative angular velocity in obj1
    let (angles, rates, cardan) = if b.large_angles {
        let sb = rel[(0, 2)].clamp(-1.0, 1.0);
        let cb = (1.0 - sb * sb).sqrt();
        if cb < BUSHING_GIMBAL_LOCK {
            return Err(FaultKind::Undefined(format!(
                "its Cardan angle β = {:.6} rad is at ±90° (|cos β| = {cb:.1e} < {BUSHING_GIMBAL_LOCK:e}), where the large-angle formulation is singular; keep the relative rotation about obj1's y axis well below 90° (stiffer rot_spring[1]) or turn obj1's frame",
                sb.asin()
            )));
        }
        let alpha = (-rel[(1, 2)]).atan2(rel[(2, 2)]);
        let gamma = (-rel[(0, 1)]).atan2(rel[(0, 0)]);
        let (sa, ca) = alpha.sin_cos();
        let gd = (-sa * w.y + ca * w.z) / cb;
        let angles = Vector3::new(alpha, sb.asin(), gamma);
        let rates = Vector3::new(w.x - sb * gd, ca * w.y + sa * w.z, gd);
        (angles, rates, Some((sa, ca, sb, cb)))
    } else {
        let angles = Vector3::new(rel[(2, 1)], rel[(0, 2)], rel[(1, 0)]);
        (angles, w, None)
    };
    let mut f = b.nominal_force;
    let mut m = b.nominal_torque;
    for i in 0..3 {
        f[i] += eval_law(&b.spring[i], r[i], "spring law")?
            + eval_law(&b.damper[i], v[i], "damper law")?;
        m[i] += eval_law(&b.rot_spring[i], angles[i], "rotational spring law")?
            + eval_law(&b.rot_damper[i], rates[i], "rotational damper law")?;
    }
    // Small angles: the moments act about obj1's axes. Cardan angles: τ = J⁻ᵀ m with
    // ω = J (α̇, β̇, γ̇), J = [e_x, Rx(α) e_y, Rx(α) Ry(β) e_z], so τ·ω = m·(α̇, β̇, γ̇).
    let tau = match cardan {
        None => m,
        Some((sa, ca, sb, cb)) => {
            let k = (m.z - sb * m.x) / cb;
            Vector3::new(m.x, ca * m.y - sa * k, sa * m.y + ca * k)
        }
    };
    let state = BushingState {
        r,
        v,
        angles,
        rates,
        force: -f,
        torque: -tau,
    };
    Ok((state, m2.r_abs, r1))
}

/// The value of a `WorldForce`/`WorldTorque` at time `t` \[s\], resolved in world, and the
/// motion of the object it acts on.
pub(crate) fn world_vector(
    plan: &Plan,
    ws: &Workspace,
    t: f64,
    (object, resolved_in): (usize, Option<usize>),
    value: &VectorLaw,
) -> Result<(Vector3<f64>, ObjectMotion), FaultKind> {
    let m = object_motion(plan, ws, object);
    let x = match value {
        VectorLaw::Constant(x) => *x,
        VectorLaw::Fn(f) => match catch_unwind(AssertUnwindSafe(|| f(t, &m))) {
            Ok(x) if x.iter().all(|c| c.is_finite()) => x,
            Ok(x) => {
                return Err(FaultKind::Undefined(format!(
                    "its law returned the non-finite vector ({}, {}, {}) at t = {t} s",
                    x.x, x.y, x.z
                )))
            }
            Err(payload) => return Err(FaultKind::Panic(panic_text(payload.as_ref()))),
        },
    };
    let x = match resolved_in {
        None => x,
        Some(r) => object_in_world(plan, ws, ObjectId(r)).rot * x,
    };
    Ok((x, m))
}

/// The first failure of an evaluation is kept (later ones are follow-ups).
fn record(ws: &mut Workspace, fault: impl FnOnce() -> UserFault) {
    if ws.fault.is_none() {
        ws.fault = Some(fault());
    }
}

/// Clears and fills `ws.f_ext` and `ws.tau_applied` at time `t` \[s\].
pub(crate) fn applied_forces(plan: &Plan, ws: &mut Workspace, t: f64, q: &[f64], v: &[f64]) {
    ws.f_ext.fill(Force::default());
    ws.tau_applied.fill(0.0);
    for e in 0..plan.scene.forces.len() {
        apply_element(plan, ws, t, q, v, e);
    }
    if let Some((mu, centre)) = plan.point_gravity {
        point_gravity(plan, ws, t, mu, &centre);
    }
    for inp in &plan.inputs {
        let u = &ws.inputs[inp.offset..inp.offset + inp.len];
        match inp.target {
            InputTarget::JointForce { joint, coordinate } => {
                let j = &plan.joints[joint];
                let (k, f) = (j.v_offset + j.coord.coordinates()[coordinate].v, u[0]);
                ws.tau_applied[k] += f;
            }
            // Enforced in the residual (the acceleration row is replaced).
            InputTarget::JointAcceleration { .. } => {}
            InputTarget::ObjectWrench { object } => {
                let force = Vector3::new(u[0], u[1], u[2]);
                let torque = Vector3::new(u[3], u[4], u[5]);
                let at = object_in_world(plan, ws, object).pos;
                add_world_wrench(ws, plan.objects[object].body, &at, &force, &torque);
            }
        }
    }
}

/// Adds force element `e`'s (index in the scene's force elements) wrenches at time `t` \[s\] to
/// `ws.f_ext` and `ws.tau_applied`; a failure of its law is recorded in `ws.fault`.
#[inline]
pub(crate) fn apply_element(
    plan: &Plan,
    ws: &mut Workspace,
    t: f64,
    q: &[f64],
    v: &[f64],
    e: usize,
) {
    element_wrenches(plan, ws, t, q, v, e, &mut |ws, o, point, force, torque| {
        add_world_wrench(ws, plan.objects[o].body, point, force, torque)
    });
}

/// Force element `e`'s wrenches at time `t` \[s\], each handed to `sink` with the object it acts
/// on: `sink(ws, object, point, force, torque)`, a force \[N\] at the world point \[m\] and a
/// torque [N·m], all resolved in world. Its generalised joint forces go to `ws.tau_applied`, a
/// failure of its law to `ws.fault`. [`apply_element`] adds the wrenches to the objects' bodies;
/// the joint loads (`dynamics/loads.rs`) need them per object, to cut a body between its parts.
#[inline]
pub(crate) fn element_wrenches(
    plan: &Plan,
    ws: &mut Workspace,
    t: f64,
    q: &[f64],
    v: &[f64],
    e: usize,
    sink: &mut impl FnMut(&mut Workspace, ObjectId, &Vector3<f64>, &Vector3<f64>, &Vector3<f64>),
) {
    let zero = Vector3::zeros();
    let f = &plan.scene.forces[e];
    let fault = |object: &str, what, kind| UserFault {
        object: object.to_string(),
        what,
        element: Some(e),
        t,
        kind,
    };
    match f {
        ValidForce::SpringDamper {
            name,
            obj1,
            obj2,
            spring,
            damper,
            length0,
        } => match ptp_state(plan, ws, (*obj1, *obj2), (spring, damper), *length0) {
            Ok(s) => {
                let f2 = -s.dir * s.tension; // on obj2, towards obj1 when stretched
                sink(ws, ObjectId(*obj2), &s.r2, &f2, &zero);
                sink(ws, ObjectId(*obj1), &s.r1, &-f2, &zero);
            }
            Err(k) => record(ws, || fault(name, "spring-damper", k)),
        },
        ValidForce::Bushing { obj1, obj2, spec } => {
            match bushing_state(plan, ws, *obj1, *obj2, spec) {
                Ok((s, at, r1)) => {
                    // On obj2 at its origin; the opposite on obj1 at the same point, so
                    // the pair exerts no net moment.
                    let (f2, t2) = (r1 * s.force, r1 * s.torque);
                    sink(ws, ObjectId(*obj2), &at, &f2, &t2);
                    sink(ws, ObjectId(*obj1), &at, &-f2, &-t2);
                }
                Err(k) => record(ws, || fault(&spec.name, "bushing", k)),
            }
        }
        ValidForce::WorldVector {
            object,
            value,
            resolved_in,
            torque,
            ..
        } => match world_vector(plan, ws, t, (*object, *resolved_in), value) {
            Ok((x, m)) => {
                let (f, n) = if *torque { (zero, x) } else { (x, zero) };
                sink(ws, ObjectId(*object), &m.r_abs, &f, &n);
            }
            Err(k) => {
                let what = if *torque {
                    "WorldTorque on"
                } else {
                    "WorldForce on"
                };
                record(ws, || fault(&plan.objects[*object].name, what, k))
            }
        },
        ValidForce::JointSpringDamper {
            joint,
            coordinate,
            stiffness,
            damping,
            offset,
        } => {
            // Validation admits only joints with scalar coordinates, which are in the tree.
            let Some(tj) = plan.tree_joint_of[*joint] else {
                return;
            };
            let j = &plan.joints[tj];
            let c = &j.coord.coordinates()[*coordinate];
            let (qi, vi) = (j.q_offset + c.q, j.v_offset + c.v);
            ws.tau_applied[vi] += -stiffness * (q[qi] - offset) - damping * v[vi];
        }
        ValidForce::ObjectForce { object, law } => {
            let m = object_motion(plan, ws, *object);
            // User code: a panic is caught here, at the call, whichever stage called
            // (residual, consistent derivatives, restarts), and never unwinds further.
            let outcome = catch_unwind(AssertUnwindSafe(|| (law.0)(t, &m)));
            let kind = match outcome {
                Ok(Wrench { force, torque })
                    if force.iter().chain(torque.iter()).all(|x| x.is_finite()) =>
                {
                    sink(ws, ObjectId(*object), &m.r_abs, &force, &torque);
                    return;
                }
                Ok(w) => FaultKind::NonFinite {
                    force: [w.force.x, w.force.y, w.force.z],
                    torque: [w.torque.x, w.torque.y, w.torque.z],
                },
                Err(payload) => FaultKind::Panic(panic_text(payload.as_ref())),
            };
            record(ws, || {
                fault(&plan.objects[*object].name, "ObjectForce on", kind)
            });
        }
    }
}

/// The centre of mass of body `b`, resolved in world \[m\].
#[inline]
pub(crate) fn body_com(plan: &Plan, ws: &Workspace, b: BodyId) -> Vector3<f64> {
    let x = &ws.world[b];
    x.pos + x.rot * plan.bodies[b].inertia.com
}

/// Point gravity: `m · (−μ r/|r|³)` at each body's centre of mass, `r` from the centre; a body
/// at the centre is a fault (the field is undefined there).
fn point_gravity(plan: &Plan, ws: &mut Workspace, t: f64, mu: f64, centre: &Vector3<f64>) {
    for i in 0..plan.bodies.len() {
        let b = BodyId(i);
        let mass = plan.bodies[b].inertia.mass;
        if mass == 0.0 {
            continue;
        }
        let c = body_com(plan, ws, b);
        let (g, r2) = point_gravity_at(&c, mu, centre);
        if g.iter().all(|x| x.is_finite()) {
            add_world_wrench(ws, Some(b), &c, &(g * mass), &Vector3::zeros());
        } else {
            record(ws, || {
                UserFault {
                object: body_name(plan, b).to_string(),
                what: "point gravity on body",
                element: None,
                t,
                kind: FaultKind::Undefined(format!(
                    "the body's centre of mass is {:e} m from the field's centre, where −μ r/|r|³ is undefined",
                    r2.sqrt()
                )),
            }
            });
        }
    }
}

/// Point gravity's acceleration `−μ r/|r|³` [m/s²] at the world point `c` \[m\] (`r = c −
/// centre`, resolved in world) and `|r|²` \[m²\]; non-finite at the centre.
#[inline]
pub(crate) fn point_gravity_at(
    c: &Vector3<f64>,
    mu: f64,
    centre: &Vector3<f64>,
) -> (Vector3<f64>, f64) {
    let r = c - centre;
    let r2 = r.norm_squared();
    (r * (-mu / (r2 * r2.sqrt())), r2)
}

/// A body's name in messages: its first object's.
fn body_name(plan: &Plan, b: BodyId) -> &str {
    plan.bodies[b]
        .objects
        .first()
        .map_or("?", |&o| plan.objects[o].name.as_str())
}

/// The build-time check of point gravity: no body's centre of mass at the field's centre at
/// the initial state (`SceneError::AtGravityCentre`).
pub(crate) fn check_gravity_centre(plan: &Plan) -> Result<(), SceneErrors> {
    let Some((mu, centre)) = plan.point_gravity else {
        return Ok(());
    };
    let mut ws = Workspace::new(plan);
    super::kinematics::position_velocity(plan, &mut ws, &plan.q0, &plan.v0);
    let errors: Vec<SceneError> = (0..plan.bodies.len())
        .map(BodyId)
        .filter(|&b| plan.bodies[b].inertia.mass != 0.0)
        .filter_map(|b| {
            let r = (body_com(plan, &ws, b) - centre).norm();
            let g = mu / (r * r);
            (!g.is_finite()).then(|| SceneError::AtGravityCentre {
                object: body_name(plan, b).to_string(),
                distance: r,
            })
        })
        .collect();
    if errors.is_empty() {
        Ok(())
    } else {
        Err(SceneErrors(errors))
    }
}
