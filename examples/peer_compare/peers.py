#!/usr/bin/env python3
"""MuJoCo and Drake on five rigid-body contact scenes, against rigid references.

Scenes, references and error measures: docs/peer-comparison.md. For every engine
configuration the program walks a ladder of accuracy settings from the cheapest (largest
time step, loosest integrator accuracy) to the finest and stops once all targets
(1e-2, 1e-3, 1e-4) are reached, when a run would exceed the wall cap, or when the error has
stopped improving (an error floor). For each target, the first (cheapest) setting of the
ladder that reaches it is timed twice more; its wall time is the median of 3 runs of the
simulation alone (model building, context creation and initial state excluded).

Usage: python peers.py [scene-name-filter ...]   (run.sh sets up the venv and calls this)
Environment: PEER_CAP (wall cap per run [s], default 60), PEER_RUNS (default 3).
"""

import math
import os
import sys
import time
from importlib.metadata import version

import numpy as np

G = 9.81
RHO = 700.0  # dry wood [kg/m^3]
E_WOOD = 1.1e10  # [Pa], hydroelastic modulus of Drake's compliant geometries
A = 0.1  # cube edge [m]
B = A / 2
TARGETS = (1e-2, 1e-3, 1e-4)
CAP = float(os.environ.get("PEER_CAP", "60"))
RUNS = int(os.environ.get("PEER_RUNS", "3"))
DT_LADDER = [1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5, 5e-6, 2e-6, 1e-6]
ACC_LADDER = [1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10]
FLOOR_WINDOW = 4  # stop a ladder when the best error has not improved over this many settings


class OverCap(Exception):
    pass


# ---------------------------------------------------------------------------------------
# scenes: geometry, initial state, reference and error
# ---------------------------------------------------------------------------------------


def housner_t_ref(theta0=0.3, b=B, h=1e-6):
    """Time the rigid block (Housner) falls back from theta0 to 0: RK4 at step h, the last
    step's crossing located by linear interpolation."""
    R = b * math.sqrt(2.0)
    p2 = 3.0 * G / (4.0 * R)
    alpha = math.pi / 4

    def f(y):
        return np.array([y[1], -p2 * math.sin(alpha - y[0])])

    y = np.array([theta0, 0.0])
    t = 0.0
    while True:
        k1 = f(y)
        k2 = f(y + 0.5 * h * k1)
        k3 = f(y + 0.5 * h * k2)
        k4 = f(y + h * k3)
        yn = y + h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
        if yn[0] <= 0.0:
            return t + h * y[0] / (y[0] - yn[0])
        y, t = yn, t + h


def rot_y(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def quat_y(a):
    return np.array([math.cos(a / 2), 0.0, math.sin(a / 2), 0.0])  # w x y z


class Scene:
    """name, about, stop time, bodies (list of dicts: shape, pos, quat, vel), ground tilt
    about y [rad], friction, and what is measured."""


def scene_incline():
    al = math.radians(30.0)
    mu = 0.3
    n = rot_y(al) @ np.array([0, 0, 1.0])
    s = rot_y(al) @ np.array([1.0, 0, 0])
    a_ref = G * (math.sin(al) - mu * math.cos(al))
    sc = Scene()
    sc.name = "incline"
    sc.about = ("0.1 m wooden cube released at rest on a 30° incline, μ = 0.3; "
                f"a = (v(0.5) − v(0.1))/0.4 along the slope against g(sin α − μ cos α) = {a_ref:.5f} m/s²")
    sc.stop = 0.5
    sc.tilt = al
    sc.mu = mu
    sc.bodies = [dict(shape="box", pos=n * B, quat=quat_y(al), vel=np.zeros(3))]
    sc.samples = [0.1, 0.5]
    sc.kind = "accel"
    sc.slope = s
    sc.ref = a_ref
    return sc


def scene_slide():
    mu = 0.3
    v0 = 1.0
    d_ref = v0 * v0 / (2 * mu * G)
    sc = Scene()
    sc.name = "slide"
    sc.about = ("0.1 m wooden cube sliding on a flat table from 1 m/s, μ = 0.3; final distance "
                f"after 0.6 s against v0²/(2μg) = {d_ref:.5f} m")
    sc.stop = 0.6
    sc.tilt = 0.0
    sc.mu = mu
    sc.bodies = [dict(shape="box", pos=np.array([0, 0, B]), quat=quat_y(0.0), vel=np.array([v0, 0, 0]))]
    sc.samples = [0.6]
    sc.kind = "distance"
    sc.ref = d_ref
    return sc


def scene_stack():
    sc = Scene()
    sc.name = "stack"
    sc.about = ("three 0.1 m wooden cubes stacked at rest on a table, 0.5 s; error = max over the "
                "3 interfaces of |F − weight above|/weight above, F = normal contact force "
                "averaged over the last 0.05 s (every step / every sample at 1 ms)")
    sc.stop = 0.5
    sc.tilt = 0.0
    sc.mu = 0.5
    sc.bodies = [dict(shape="box", pos=np.array([0, 0, B + k * A]), quat=quat_y(0.0), vel=np.zeros(3))
                 for k in range(3)]
    sc.kind = "stack"
    sc.avg_from = 0.45
    return sc


def scene_pivot():
    th0 = 0.3
    t_ref = housner_t_ref(th0)
    sc = Scene()
    sc.name = "pivot"
    sc.about = ("0.1 m wooden cube tilted by 0.3 rad onto a bottom edge, released at rest, μ = 0.8; "
                f"time θ reaches 0 against Housner's rigid block (RK4 at 1e-6 s): t_ref = {t_ref:.6f} s")
    sc.stop = 0.2  # a run stops at the crossing; 0.2 s bounds it
    sc.tilt = 0.0
    sc.mu = 0.8
    edge = np.array([B, 0.0, 0.0])
    sc.bodies = [dict(shape="box", pos=edge + rot_y(th0) @ np.array([-B, 0, B]), quat=quat_y(th0),
                      vel=np.zeros(3))]
    sc.kind = "pivot"
    sc.ref = t_ref
    return sc


def scene_rolling():
    al = math.radians(20.0)
    mu = 0.6
    r = 0.05
    n = rot_y(al) @ np.array([0, 0, 1.0])
    s = rot_y(al) @ np.array([1.0, 0, 0])
    a_ref = 2.0 / 3.0 * G * math.sin(al)
    # cylinder axis (local z) along world y: rotate about x by -90°, then tilt about y
    qx = np.array([math.cos(-math.pi / 4), math.sin(-math.pi / 4), 0, 0])
    q = quat_mul(quat_y(al), qx)
    sc = Scene()
    sc.name = "rolling"
    sc.about = ("solid wooden cylinder Ø 0.1 m × 0.2 m, axis across the slope, released at rest on a "
                f"20° incline, μ = 0.6; a as in incline against (2/3) g sin α = {a_ref:.5f} m/s²")
    sc.stop = 0.5
    sc.tilt = al
    sc.mu = mu
    sc.bodies = [dict(shape="cylinder", pos=n * r, quat=q, vel=np.zeros(3))]
    sc.samples = [0.1, 0.5]
    sc.kind = "accel"
    sc.slope = s
    sc.ref = a_ref
    return sc


def quat_mul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
                     w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
                     w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


SCENES = [scene_incline, scene_slide, scene_stack, scene_pivot, scene_rolling]

BOX_MASS = RHO * A ** 3
CYL_MASS = RHO * math.pi * 0.05 ** 2 * 0.2


def error_of(sc, meas):
    """meas: accel -> (v(0.1), v(0.5)) along the slope; distance -> x(T) - x(0);
    stack -> mean normal forces [table-1, 1-2, 2-3]; pivot -> crossing time (None: none)."""
    if sc.kind == "accel":
        v1, v5 = meas
        a = (v5 - v1) / 0.4
        return abs(a - sc.ref) / sc.ref, f"a = {a:.6f}"
    if sc.kind == "distance":
        return abs(meas - sc.ref) / sc.ref, f"d = {meas:.6f}"
    if sc.kind == "stack":
        w = BOX_MASS * G
        errs = [abs(f - k * w) / (k * w) for f, k in zip(meas, (3, 2, 1))]
        return max(errs), "F/weight above = " + " ".join(f"{f / (k * w):.6f}" for f, k in zip(meas, (3, 2, 1)))
    if sc.kind == "pivot":
        if meas is None:
            return math.inf, "θ never reached 0"
        return abs(meas - sc.ref) / sc.ref, f"t_hit = {meas:.6f}"
    raise ValueError(sc.kind)


def hermite_root(t0, t1, th0, th1, w0, w1):
    """Root in [t0, t1] of the cubic Hermite interpolant of θ with slopes w (θ0 > 0 ≥ θ1)."""
    h = t1 - t0

    def p(s):
        h00 = 2 * s ** 3 - 3 * s ** 2 + 1
        h10 = s ** 3 - 2 * s ** 2 + s
        h01 = -2 * s ** 3 + 3 * s ** 2
        h11 = s ** 3 - s ** 2
        return h00 * th0 + h10 * h * w0 + h01 * th1 + h11 * h * w1

    lo, hi = 0.0, 1.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if p(mid) > 0:
            lo = mid
        else:
            hi = mid
    return t0 + 0.5 * (lo + hi) * h


# ---------------------------------------------------------------------------------------
# MuJoCo
# ---------------------------------------------------------------------------------------

MJ_OPTS = dict(integrator="implicitfast", cone="elliptic", impratio="10")
MJ_CFGS = [
    # solref time constant 1e-9 s: MuJoCo's refsafe clamps it to 2·timestep, the stiffest it
    # allows; solimp near 1 (hard); noslip post-iterations for the friction
    ("stiff: solref 2·dt, solimp 0.99–0.999, noslip 10",
     dict(noslip_iterations="10"), dict(condim="3", solref="1e-9 1", solimp="0.99 0.999 0.0001")),
    ("default softness: solref 0.02, solimp 0.9–0.95", {}, dict(condim="3")),
]


def fmt(v):
    return " ".join(f"{x:.12g}" for x in v)


def mujoco_xml(sc, dt, opts, geom):
    opt = " ".join(f'{k}="{v}"' for k, v in {**MJ_OPTS, **opts}.items())
    gd = " ".join(f'{k}="{v}"' for k, v in geom.items())
    mu = sc.mu
    bodies = []
    for i, b in enumerate(sc.bodies):
        if b["shape"] == "box":
            geom = f'<geom type="box" size="{B} {B} {B}" density="{RHO}"/>'
        else:
            geom = f'<geom type="cylinder" size="0.05 0.1" density="{RHO}"/>'
        bodies.append(f'<body name="b{i}" pos="{fmt(b["pos"])}" quat="{fmt(b["quat"])}">'
                      f'<freejoint/>{geom}</body>')
    return f"""<mujoco>
  <option timestep="{dt}" gravity="0 0 -{G}" {opt}>
    <flag multiccd="enable"/>
  </option>
  <default><geom {gd} friction="{mu} 0 0"/></default>
  <worldbody>
    <geom name="ground" type="plane" size="0 0 1" quat="{fmt(quat_y(sc.tilt))}"/>
    {''.join(bodies)}
  </worldbody>
</mujoco>"""


class MujocoRun:
    engine = "MuJoCo"

    def __init__(self, sc, dt, cfg=0):
        import mujoco
        self.mj = mujoco
        self.sc = sc
        self.dt = dt
        _, opts, geom = MJ_CFGS[cfg]
        self.m = mujoco.MjModel.from_xml_string(mujoco_xml(sc, dt, opts, geom))
        self.d = mujoco.MjData(self.m)
        self.setting = f"dt {dt:g}"

    def reset(self):
        mj, m, d = self.mj, self.m, self.d
        mj.mj_resetData(m, d)
        for i, b in enumerate(self.sc.bodies):
            d.qpos[7 * i:7 * i + 3] = b["pos"]
            d.qpos[7 * i + 3:7 * i + 7] = b["quat"]
            d.qvel[6 * i:6 * i + 3] = b["vel"]
        mj.mj_forward(m, d)

    def steps(self, t):
        return int(round(t / self.dt))

    def run(self, t_start):
        """Simulate from the reset state; return the scene's measurement."""
        mj, m, d, sc = self.mj, self.m, self.d, self.sc
        chunk = max(1, self.steps(0.01))

        def advance(n):
            done = 0
            while done < n:
                k = min(chunk, n - done)
                mj.mj_step(m, d, nstep=k)
                done += k
                if time.perf_counter() - t_start > CAP:
                    raise OverCap()

        if sc.kind == "accel":
            vs = []
            done = 0
            for ts in sc.samples:
                n = self.steps(ts)
                advance(n - done)
                done = n
                vs.append(float(np.dot(d.qvel[0:3], sc.slope)))
            return vs
        if sc.kind == "distance":
            x0 = float(d.qpos[0])
            advance(self.steps(sc.stop))
            return float(d.qpos[0]) - x0
        if sc.kind == "stack":
            n_avg0 = self.steps(sc.avg_from)
            advance(n_avg0)
            sums = np.zeros(3)
            cnt = 0
            f6 = np.zeros(6)
            geom_body = m.geom_bodyid
            for _ in range(self.steps(sc.stop) - n_avg0):
                mj.mj_step(m, d)
                fs = np.zeros(3)
                for i in range(d.ncon):
                    c = d.contact[i]
                    b1, b2 = geom_body[c.geom1], geom_body[c.geom2]
                    lo = min(b1, b2)  # world 0 / cube k: interface index = lower body id
                    mj.mj_contactForce(m, d, i, f6)
                    fs[lo] += f6[0]
                sums += fs
                cnt += 1
            if time.perf_counter() - t_start > CAP:
                raise OverCap()
            return sums / cnt
        if sc.kind == "pivot":
            th = 2 * math.atan2(d.qpos[5], d.qpos[3])
            w = float(d.qvel[4])
            nmax = self.steps(sc.stop)
            for k in range(nmax):
                mj.mj_step(m, d)
                th1 = 2 * math.atan2(d.qpos[5], d.qpos[3])
                w1 = float(d.qvel[4])
                if th1 <= 0.0:
                    return hermite_root(k * self.dt, (k + 1) * self.dt, th, th1, w, w1)
                th, w = th1, w1
                if k % 1000 == 0 and time.perf_counter() - t_start > CAP:
                    raise OverCap()
            return None
        raise ValueError(sc.kind)


# ---------------------------------------------------------------------------------------
# Drake
# ---------------------------------------------------------------------------------------


class DrakeRun:
    engine = "Drake"

    def __init__(self, sc, cfg, setting):
        from pydrake.all import (AddCompliantHydroelasticProperties,
                                 AddCompliantHydroelasticPropertiesForHalfSpace, AddRigidHydroelasticProperties,
                                 AddContactMaterial, AddMultibodyPlantSceneGraph, Box,
                                 ContactModel, CoulombFriction, Cylinder, DiagramBuilder,
                                 DiscreteContactApproximation, HalfSpace, ProximityProperties,
                                 RigidTransform, RotationMatrix, SpatialInertia)
        self.sc = sc
        self.cfg = cfg
        self.mode, self.contact = cfg  # ("sap"|"lagged"|"cenic"|"rk3", "point"|"hydro")
        discrete = self.mode in ("sap", "lagged")
        self.dt = setting if discrete else 0.0
        self.acc = None if discrete else setting
        self.setting = f"dt {setting:g}" if discrete else f"accuracy {setting:g}"
        builder = DiagramBuilder()
        plant, sg = AddMultibodyPlantSceneGraph(builder, time_step=self.dt)
        if discrete:
            plant.set_discrete_contact_approximation(
                DiscreteContactApproximation.kSap if self.mode == "sap" else DiscreteContactApproximation.kLagged)
        plant.set_contact_model(ContactModel.kHydroelasticWithFallback if self.contact == "hydro" else ContactModel.kPoint)
        fr = CoulombFriction(sc.mu, sc.mu)

        def props(ground=False, hint=None):
            p = ProximityProperties()
            AddContactMaterial(friction=fr, properties=p)
            if self.contact == "hydro":
                # the table: a compliant half space with wood's modulus (1 m slab); the bodies:
                # rigid hydroelastic; body-body pairs (rigid-rigid) fall back to point contact
                if ground:
                    AddCompliantHydroelasticPropertiesForHalfSpace(1.0, E_WOOD, p)
                else:
                    AddRigidHydroelasticProperties(hint or 0.01, p)
            return p

        X_G = RigidTransform(RotationMatrix.MakeYRotation(sc.tilt), [0, 0, 0])
        plant.RegisterCollisionGeometry(plant.world_body(), X_G, HalfSpace(), "ground", props(True))
        self.bodies = []
        for i, b in enumerate(sc.bodies):
            if b["shape"] == "box":
                M = SpatialInertia.SolidBoxWithDensity(RHO, A, A, A)
                shape, hint = Box(A, A, A), None
            else:
                M = SpatialInertia.SolidCylinderWithDensity(RHO, 0.05, 0.2, [0, 0, 1])
                shape, hint = Cylinder(0.05, 0.2), 0.005
            body = plant.AddRigidBody(f"b{i}", M)
            plant.RegisterCollisionGeometry(body, RigidTransform(), shape, f"g{i}", props(hint=hint))
            self.bodies.append(body)
        plant.mutable_gravity_field().set_gravity_vector([0, 0, -G])
        plant.Finalize()
        self.plant = plant
        self.sg = sg
        self.diagram = builder.Build()

    def reset(self):
        from pydrake.all import (Quaternion, RigidTransform, Simulator, SpatialVelocity,
                                 ResetIntegratorFromFlags)
        self.sim = Simulator(self.diagram)
        ctx = self.sim.get_mutable_context()
        self.pctx = self.plant.GetMyMutableContextFromRoot(ctx)
        for body, b in zip(self.bodies, self.sc.bodies):
            pos = np.asarray(b["pos"], float)
            if self.contact == "hydro":
                # vertices exactly on the compliant half space trip Drake's mesh clipping
                # (mesh_half_space_intersection.cc: sgn(s_a) != sgn(s_b)); start 1e-9 m deep
                pos = pos - 1e-9 * rot_y(self.sc.tilt)[:, 2]
            X = RigidTransform(Quaternion(b["quat"] / np.linalg.norm(b["quat"])), pos)
            self.plant.SetFreeBodyPose(self.pctx, body, X)
            self.plant.SetFreeBodySpatialVelocity(body, SpatialVelocity(np.zeros(3), np.asarray(b["vel"], float)), self.pctx)
        if self.acc is not None:
            scheme = {"cenic": "cenic", "rk3": "runge_kutta3"}[self.mode]
            integ = ResetIntegratorFromFlags(self.sim, scheme, 0.01)
            integ.set_target_accuracy(self.acc)
            integ.set_requested_minimum_step_size(1e-10)
            integ.set_throw_on_minimum_step_size_violation(False)
        self.sim.Initialize()

    def _v(self, k=0):
        return self.plant.EvalBodySpatialVelocityInWorld(self.pctx, self.bodies[k]).translational()

    def _X(self, k=0):
        return self.plant.EvalBodyPoseInWorld(self.pctx, self.bodies[k])

    def run(self, t_start):
        sc, sim = self.sc, self.sim

        def advance_to(t):
            now = sim.get_context().get_time()
            while now < t - 1e-12:
                now = min(t, now + 0.01)
                sim.AdvanceTo(now)
                if time.perf_counter() - t_start > CAP:
                    raise OverCap()

        if sc.kind == "accel":
            vs = []
            for ts in sc.samples:
                advance_to(ts)
                vs.append(float(np.dot(self._v(), sc.slope)))
            return vs
        if sc.kind == "distance":
            x0 = self._X().translation()[0]
            advance_to(sc.stop)
            return float(self._X().translation()[0] - x0)
        if sc.kind == "stack":
            advance_to(sc.avg_from)
            port = self.plant.get_contact_results_output_port()
            insp = self.sg.get_query_output_port().Eval(self.sg.GetMyContextFromRoot(sim.get_context())).inspector()
            body_of = {}
            for k, body in enumerate(self.bodies):
                for gid in self.plant.GetCollisionGeometriesForBody(body):
                    body_of[gid] = k + 1
            step = max(self.dt, 1e-3)
            n = int(round((sc.stop - sc.avg_from) / step))
            sums = np.zeros(3)
            for j in range(1, n + 1):
                advance_to(sc.avg_from + j * step)
                cr = port.Eval(self.pctx)
                fs = np.zeros(3)
                for i in range(cr.num_point_pair_contacts()):
                    info = cr.point_pair_contact_info(i)
                    pp = info.point_pair()
                    lo = min(body_of.get(pp.id_A, 0), body_of.get(pp.id_B, 0))
                    fs[lo] += abs(info.contact_force()[2])
                for i in range(cr.num_hydroelastic_contacts()):
                    info = cr.hydroelastic_contact_info(i)
                    s = info.contact_surface()
                    lo = min(body_of.get(s.id_M(), 0), body_of.get(s.id_N(), 0))
                    fs[lo] += abs(info.F_Ac_W().translational()[2])
                sums += fs
            return sums / n
        if sc.kind == "pivot":
            from pydrake.all import EventStatus, RollPitchYaw
            rec = []

            def monitor(ctx):
                X = self.plant.EvalBodyPoseInWorld(self.pctx, self.bodies[0])
                th = RollPitchYaw(X.rotation()).pitch_angle()
                w = self.plant.EvalBodySpatialVelocityInWorld(self.pctx, self.bodies[0]).rotational()[1]
                rec.append((ctx.get_time(), th, w))
                if th <= 0.0 or time.perf_counter() - t_start > CAP:
                    return EventStatus.ReachedTermination(self.diagram, "done")
                return EventStatus.Succeeded()

            sim.set_monitor(monitor)
            sim.AdvanceTo(sc.stop)
            if time.perf_counter() - t_start > CAP:
                raise OverCap()
            for (t0, a0, w0), (t1, a1, w1) in zip(rec, rec[1:]):
                if a1 <= 0.0 < a0:
                    return hermite_root(t0, t1, a0, a1, w0, w1)
            return None
        raise ValueError(sc.kind)


DRAKE_CFGS = [
    (("sap", "point"), "discrete SAP, point contact", DT_LADDER[:10]),
    (("sap", "hydro"), "discrete SAP, hydroelastic", DT_LADDER[:10]),
    (("cenic", "point"), "continuous CENIC, point contact", ACC_LADDER),
    (("cenic", "hydro"), "continuous CENIC, hydroelastic", ACC_LADDER),
    (("rk3", "point"), "continuous RK3, point contact", ACC_LADDER),
]


# ---------------------------------------------------------------------------------------
# ladders, targets, tables
# ---------------------------------------------------------------------------------------


def one_run(runner):
    runner.reset()
    t0 = time.perf_counter()
    meas = runner.run(t0)
    wall = time.perf_counter() - t0
    return wall, meas


def walk_ladder(sc, make, ladder, log):
    """Returns the ladder rows (setting, wall, error, note) and per target the index of the
    first row reaching it together with the runner of that row."""
    rows = []
    hits = {}
    runners = {}
    confirmed = set()
    best = math.inf
    best_at = -1
    prev_wall, prev_cost = None, None
    for i, s in enumerate(ladder):
        cost = 1.0 / s  # steps (or work) scale like 1/setting for a time step
        if prev_wall is not None and make.is_dt and prev_wall * cost / prev_cost > CAP:
            rows.append((f"dt {s:g}", math.nan, math.nan, f"skipped: would take ≈{prev_wall * cost / prev_cost:.0f} s > cap"))
            break
        try:
            r = make(s)
        except Exception as ex:  # noqa: BLE001
            rows.append((f"{s:g}", math.nan, math.inf, f"build failed: {type(ex).__name__}: {ex}"[:160]))
            break
        try:
            wall, meas = one_run(r)
            err, note = error_of(sc, meas)
        except OverCap:
            rows.append((r.setting, math.nan, math.nan, f"over the {CAP:.0f} s cap"))
            break
        except Exception as ex:  # noqa: BLE001
            rows.append((r.setting, math.nan, math.inf, f"failed: {type(ex).__name__}: {ex}"[:160]))
            break
        rows.append((r.setting, wall, err, note))
        log(f"    {r.setting:>16}  wall {wall:9.4f} s  error {err:.3e}  {note}")
        # a target counts as reached at the first setting whose error, and the next finer
        # setting's error, are both within it (a lucky zero crossing of the error does not count)
        for tg in TARGETS:
            if tg in confirmed:
                continue
            if err <= tg:
                if tg in hits:
                    confirmed.add(tg)
                else:
                    hits[tg] = len(rows) - 1
                    runners[tg] = r
            else:
                hits.pop(tg, None)
                runners.pop(tg, None)
        if all(tg in confirmed for tg in TARGETS):
            break
        if err < best * 0.8:
            best, best_at = err, i
        elif i - best_at >= FLOOR_WINDOW:
            rows.append(("…", math.nan, math.nan,
                         f"stopped: no improvement over the last {FLOOR_WINDOW} settings (error floor)"))
            break
        prev_wall, prev_cost = wall, cost
    return rows, hits, runners, confirmed


def median_wall(runner, first_wall):
    """Median wall of RUNS runs (the ladder's run among them). A repeat over the cap (a
    setting whose first run took just under it) ends the repeats: the median of the runs
    made, which for a run near the cap says it costs about the cap either way."""
    walls = [first_wall]
    for _ in range(RUNS - 1):
        try:
            w, _ = one_run(runner)
        except OverCap:
            walls.append(CAP)
            break
        walls.append(w)
    walls.sort()
    return walls[len(walls) // 2]


def fmt_err(e):
    if e is None or (isinstance(e, float) and (math.isnan(e) or math.isinf(e))):
        return "—"
    return f"{e:.2e}"


def fmt_wall(w):
    return "—" if w is None or math.isnan(w) else f"{w:.4f}"


def main():
    filt = sys.argv[1:]
    log = lambda s: print(s, file=sys.stderr, flush=True)  # noqa: E731
    import mujoco
    print(f"mujoco {mujoco.__version__}, drake {version('drake')}, numpy {np.__version__}, "
          f"python {sys.version.split()[0]}; wall = median of {RUNS} runs, cap {CAP:.0f} s per run")
    print()
    summary = []
    for mk in SCENES:
        sc = mk()
        if filt and not any(f in sc.name for f in filt):
            continue
        log(f"== {sc.name}")
        print(f"### {sc.name}")
        print()
        print(sc.about + ".")
        print()
        engines = []

        for ci, (label, _, _) in enumerate(MJ_CFGS):
            def mj_make(s, sc=sc, ci=ci):
                return MujocoRun(sc, s, ci)

            mj_make.is_dt = True
            engines.append(("MuJoCo", label, mj_make, DT_LADDER))
        for cfg, label, ladder in DRAKE_CFGS:
            def dk_make(s, sc=sc, cfg=cfg):
                return DrakeRun(sc, cfg, s)

            dk_make.is_dt = cfg[0] in ("sap", "lagged")
            engines.append(("Drake", label, dk_make, ladder))

        ladder_rows = []
        best = {}  # (engine, target) -> (wall, label, setting, error)
        for eng, label, make, ladder in engines:
            log(f"  {eng}: {label}")
            rows, hits, runners, confirmed = walk_ladder(sc, make, ladder, log)
            for setting, wall, err, note in rows:
                ladder_rows.append((eng, label, setting, wall, err, note))
            finite = [r for r in rows if not math.isnan(r[2]) and not math.isinf(r[2])]
            best_err = min((r[2] for r in finite), default=math.inf)
            for tg in TARGETS:
                key = (eng, tg)
                if tg in hits:
                    row = rows[hits[tg]]
                    w = median_wall(runners[tg], row[1])
                    mark = "" if tg in confirmed else " (no finer setting run)"
                    cand = (w, label, row[0] + mark, row[2], True)
                    if key not in best or not best[key][4] or w < best[key][0]:
                        best[key] = cand
                else:
                    cand = (None, label, None, best_err, False)
                    if key not in best or (not best[key][4] and best_err < best[key][3]):
                        best[key] = cand
        print(f"| target | engine | configuration | setting | wall [s] (median of {RUNS}) | error |")
        print("|---:|---|---|---|---:|---:|")
        for tg in TARGETS:
            for eng in ("MuJoCo", "Drake"):
                w, label, setting, err, ok = best[(eng, tg)]
                if ok:
                    print(f"| {tg:.0e} | {eng} | {label} | {setting} | {fmt_wall(w)} | {fmt_err(err)} |")
                else:
                    print(f"| {tg:.0e} | {eng} | — | not reached | — | best {fmt_err(err)} |")
                summary.append((sc.name, tg, eng, w if ok else None, label if ok else None, setting, err, ok))
        print()
        print(f"{sc.name}: every setting tried (wall of one run)")
        print()
        print("| engine | configuration | setting | wall [s] | error | notes |")
        print("|---|---|---|---:|---:|---|")
        for eng, label, setting, wall, err, note in ladder_rows:
            print(f"| {eng} | {label} | {setting} | {fmt_wall(wall)} | {fmt_err(err)} | {note} |")
        print()
        sys.stdout.flush()
    print("### summary: wall [s] at each target (cheapest setting reaching it)")
    print()
    print("| scene | target | MuJoCo | Drake | Drake configuration |")
    print("|---|---:|---:|---:|---|")
    by = {}
    for name, tg, eng, w, label, setting, err, ok in summary:
        by[(name, tg, eng)] = (w, label, setting, err, ok)
    for name in dict.fromkeys(s[0] for s in summary):
        for tg in TARGETS:
            m = by[(name, tg, "MuJoCo")]
            d = by[(name, tg, "Drake")]
            mc = f"{m[0]:.4f} ({m[2]})" if m[4] else f"not reached (best {fmt_err(m[3])})"
            dc = f"{d[0]:.4f} ({d[2]})" if d[4] else f"not reached (best {fmt_err(d[3])})"
            print(f"| {name} | {tg:.0e} | {mc} | {dc} | {d[1] or '—'} |")


if __name__ == "__main__":
    main()
