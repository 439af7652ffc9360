//! The contact hot path allocates nothing: residual (continuous mode), root functions
//! (zero-crossing mode) and event mode of a scene with candidate pairs, once warmed up. The
//! crate's unit-test binary counts allocations per thread (`counting_alloc`, test builds
//! only), so tests running on other threads meanwhile are not seen.

use super::MultibodyDae;
use crate::counting_alloc::allocs;
use crate::solver::DaeSystem;
use crate::{FreeRotation, Joint, JointKind, Object3D, SceneDesc, SceneOptions, Shape, Solid};
use nalgebra::Vector3;

/// A fixed collision table `side × side × 0.1` m of `material`, its top face at z = 0.
fn table(side: f64, material: &str) -> Object3D {
    Object3D::new("table")
        .parent("world")
        .translation([0.0, 0.0, -0.05])
        .solid(
            Solid::new(Shape::Box {
                lengths: Vector3::new(side, side, 0.1),
            })
            .material(material)
            .collision(true),
        )
}

/// Eight steel balls (d = 0.06 m) on a steel table, each 1e-7 m into it (in contact from the
/// start), 0.02 m apart from each other: 8 ball–table contacts, 28 ball–ball candidate pairs
/// (all separated), exercising the broad phase, narrow phase and response of both kinds.
pub(crate) fn balls_on_a_table() -> SceneDesc {
    balls_on_a_table_apart(0.02)
}

/// [`balls_on_a_table`] with the balls `gap` \[m\] apart (negative: pressed into each other).
fn balls_on_a_table_apart(gap: f64) -> SceneDesc {
    let d = 0.06;
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions::default()))
        .add(table(1.0, "Steel"));
    for i in 0..8 {
        let name = format!("ball{i}");
        let (x, y) = ((i % 4) as f64 * (d + gap), (i / 4) as f64 * (d + gap));
        s.add(
            Object3D::new(&name).solid(
                Solid::new(Shape::Sphere { diameter: d })
                    .material("Steel")
                    .collision(true),
            ),
        )
        .add_joint(Joint::new(
            &format!("{name}.free"),
            "world",
            &name,
            JointKind::FreeMotion {
                r: Vector3::new(x, y, 0.5 * d - 1e-7),
                rot: FreeRotation::Cardan([0.0; 3]),
                v: Vector3::zeros(),
                w: Vector3::zeros(),
            },
        ));
    }
    s
}

#[test]
fn residual_roots_and_events_do_not_allocate() {
    let g = hot_path_allocations(balls_on_a_table());
    assert!(
        g[0] < 0.0 && g[1] > 0.0,
        "balls rest on the table, none touch each other: {g:?}"
    );
}

/// [`balls_on_a_table`] with an arm on a revolute joint resting on its lower stop and a
/// slider on a prismatic joint between two stops (`contact/limits.rs`): the stops' forces,
/// roots, events and Jacobian entries allocate nothing either.
#[test]
fn joint_limits_do_not_allocate() {
    let mut s = balls_on_a_table();
    let body = || {
        Solid::new(Shape::Box {
            lengths: Vector3::new(0.05, 0.05, 0.3),
        })
        .mass(1.0)
    };
    s.add(Object3D::new("arm").solid(body()))
        .add(Object3D::new("slider").solid(body()))
        .add_joint(Joint::new("hinge", "world", "arm", JointKind::revolute(1)).limits(0.0, 1.0))
        .add_joint(
            Joint::new("slide", "world", "slider", JointKind::prismatic(1))
                .init_velocity(0.5)
                .limits(-0.1, 0.1),
        );
    let g = hot_path_allocations(s);
    assert!(g[0] < 0.0 && g[1] > 0.0, "{g:?}");
}

/// The balls of [`balls_on_a_table`] pressed 1e-7 m into their neighbours: the ball–ball
/// pairs' exact Jacobian blocks (two moving bodies, `contact/pair_jacobian.rs`) allocate
/// nothing either.
#[test]
fn touching_balls_do_not_allocate() {
    let g = hot_path_allocations(balls_on_a_table_apart(-1e-7));
    assert!(g[0] < 0.0, "in contact: {g:?}");
}

/// A beam (its own core) and a decomposed L-block mesh (two hull parts on one body) resting
/// 1e-7 m into a table: the contact hot path allocates nothing for them either.
#[test]
fn beam_and_decomposed_mesh_do_not_allocate() {
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions::default()))
        .add(table(2.0, "DryWood"));
    let beam = Shape::Beam {
        axis: crate::geometry::Axis::X,
        length: 0.3,
        width: 0.1,
        thickness: 0.04,
    };
    let mesh = Shape::FileMesh {
        path: concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/data/l_block.stl").into(),
        scale: Vector3::repeat(1.0),
        collision: crate::geometry::MeshCollision::ConvexDecomposition,
    };
    for (name, shape, r) in [
        ("beam", beam, Vector3::new(-0.5, 0.0, 0.02 - 1e-7)),
        ("block", mesh, Vector3::new(0.2, 0.0, -1e-7)),
    ] {
        add_wooden_body(&mut s, name, shape, r);
    }
    let g = hot_path_allocations(s);
    assert!(g[0] < 0.0, "in contact: {g:?}");
}

/// A box on its face, a cylinder on its side and a cone on its base, each 1e-7 m into a
/// wooden table: the volume law's hot path (polytope clipping, the frustum's quadrature, the
/// sharp shapes' signed distance at the roots) allocates nothing either.
#[test]
fn volume_law_pairs_do_not_allocate() {
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions::default()))
        .add(table(2.0, "DryWood"));
    let axis = crate::geometry::Axis::Y;
    for (name, shape, r) in [
        (
            "box",
            Shape::Box {
                lengths: Vector3::new(0.2, 0.1, 0.05),
            },
            Vector3::new(-0.5, 0.0, 0.025 - 1e-7),
        ),
        (
            "cylinder",
            Shape::Cylinder {
                axis,
                diameter: 0.1,
                length: 0.2,
            },
            Vector3::new(0.0, 0.0, 0.05 - 1e-7),
        ),
        (
            "cone",
            Shape::Cone {
                axis: crate::geometry::Axis::Z,
                diameter: 0.1,
                length: 0.1,
                top_diameter: 0.04,
            },
            Vector3::new(0.5, 0.0, -1e-7),
        ),
        (
            "beam",
            Shape::Beam {
                axis: crate::geometry::Axis::X,
                length: 0.2,
                width: 0.05,
                thickness: 0.02,
            },
            Vector3::new(0.0, 0.5, 0.01 - 1e-7),
        ),
    ] {
        add_wooden_body(&mut s, name, shape, r);
    }
    let g = hot_path_allocations(s);
    assert!(g[0] < 0.0, "in contact: {g:?}");
}

/// Adds a free DryWood collision body `name` of `shape` at `r` \[m\], at rest.
fn add_wooden_body(s: &mut SceneDesc, name: &str, shape: Shape, r: Vector3<f64>) {
    s.add(Object3D::new(name).solid(Solid::new(shape).material("DryWood").collision(true)))
        .add_joint(Joint::new(
            &format!("{name}.free"),
            "world",
            name,
            JointKind::FreeMotion {
                r,
                rot: FreeRotation::Cardan([0.0; 3]),
                v: Vector3::zeros(),
                w: Vector3::zeros(),
            },
        ));
}

/// Runs residual, roots, event handling, the DAE's Jacobian columns (structure, own blocks
/// and pair-local quotients, `dae/jacobian.rs`), `∂F/∂y'` and the solver's quotient residuals
/// (`begin_quotients`, `quotient_residual`) 100 times on the built `scene` at its initial
/// state after a warm-up, asserts that nothing was allocated and that the consistent
/// derivative solves the residual; returns the root values.
fn hot_path_allocations(scene: SceneDesc) -> Vec<f64> {
    let model = scene.build().unwrap();
    assert!(model.contact.is_some(), "the scene has candidate pairs");
    let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
    dae.set_contact_tightening(100.0);
    let y = model.plan.y0();
    let n = y.len();
    let mut ewt = vec![1.0; n];
    dae.handle_event(0.0, &y).unwrap();
    let yp = dae.consistent_derivative(0.0, &mut y.clone()).unwrap();
    let mut res = vec![0.0; n];
    let mut g = vec![0.0; 2];
    let mut s = crate::solver::BlockStructure::default();
    let zero_size = vec![1e-2; n];
    let mut entries = 0usize;
    let mut jacobian = |dae: &mut MultibodyDae, s: &mut crate::solver::BlockStructure| {
        assert!(dae.jacobian_structure(s));
        let args = jacobian_args(0.0, &y, &yp, &zero_size);
        dae.jacobian(&args, &mut |_: usize, _: usize, _: f64| entries += 1)
            .unwrap();
        assert!(dae
            .yp_jacobian(&args, &mut |_: usize, _: usize, _: f64| entries += 1)
            .unwrap());
    };
    // The solver's quotient residuals: one per perturbed unknown (a position, a velocity).
    let mut y2 = y.clone();
    let mut res_q = vec![0.0; n];
    let mut quotients = |dae: &mut MultibodyDae, res: &mut [f64]| {
        dae.begin_quotients(0.0, &y, &yp).unwrap();
        for j in [0, model.plan.nq] {
            y2[j] += 1e-8;
            dae.quotient_residual(0.0, &y2, &yp, res, &[j]).unwrap();
            y2[j] = y[j];
        }
    };
    // Warm up.
    dae.residual(0.0, &y, &yp, &mut res).unwrap();
    dae.roots(0.0, &y, &yp, &mut g);
    jacobian(&mut dae, &mut s);
    quotients(&mut dae, &mut res_q);
    let before = allocs();
    for k in 0..100 {
        let t = k as f64 * 1e-3;
        dae.residual(t, &y, &yp, &mut res).unwrap();
        dae.roots(t, &y, &yp, &mut g);
        dae.error_weight_factors(&y, &mut ewt);
        dae.handle_event(t, &y).unwrap();
        jacobian(&mut dae, &mut s);
        quotients(&mut dae, &mut res_q);
    }
    let after = allocs();
    assert!(
        s.analytic.iter().all(|&a| a),
        "free bodies on a fixed table: every block analytic"
    );
    assert!(entries > 0);
    assert_eq!(after - before, 0, "allocations on the contact hot path");
    // The consistent derivative solves the residual to round-off of the forces (m g ≈ 8.7 N
    // per ball, 10 to 40 N for the beam and block; 1e-6 is far above round-off and far below
    // any missed term).
    assert!(res.iter().all(|r| r.abs() < 1e-6), "consistent start");
    g
}

/// A planar parallelogram four-bar (crank and rocker 0.1 m, coupler 0.3 m, ground 0.3 m) closed
/// by the cut revolute `close`: the loop's residual (constraint rows, `Gᵀμ`, constraint
/// wrenches) allocates nothing either.
#[test]
fn residual_of_a_closed_loop_does_not_allocate() {
    use crate::dynamics::loops::LoopPlan;
    let bar = |name: &str, l: f64| {
        Object3D::new(name).translation([l / 2.0, 0.0, 0.0]).solid(
            Solid::new(Shape::Box {
                lengths: Vector3::new(l, 0.01, 0.01),
            })
            .material("Steel"),
        )
    };
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions::default()))
        .add(
            Object3D::new("pivot")
                .parent("world")
                .translation([0.3, 0.0, 0.0]),
        );
    for (link, l) in [("crank", 0.1), ("coupler", 0.3), ("rocker", 0.1)] {
        s.add(Object3D::new(link))
            .add(bar(&format!("{link}_bar"), l).parent(link))
            .add(
                Object3D::new(&format!("{link}_tip"))
                    .parent(link)
                    .translation([l, 0.0, 0.0]),
            );
    }
    let rev = |n: &str, a: &str, b: &str, phi: f64| {
        Joint::new(n, a, b, JointKind::revolute(3)).init_position(phi)
    };
    s.add_joint(rev("j1", "world", "crank", 1.0).init_velocity(2.0))
        .add_joint(rev("j2", "crank_tip", "coupler", -1.0))
        .add_joint(rev("j3", "pivot", "rocker", 1.0))
        .add_joint(rev("close", "coupler_tip", "rocker_tip", 0.0).cut(true));
    let model = s.build().unwrap();
    let lp: &LoopPlan = &model.plan.loops;
    assert_eq!((lp.cuts.len(), lp.m()), (1, 2), "one cut, two kept rows");
    let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
    let mut y = model.plan.y0();
    y.resize(dae.len(), 0.0);
    let yp = dae.consistent_derivative(0.0, &mut y).unwrap();
    let mut res = vec![0.0; y.len()];
    dae.residual(0.0, &y, &yp, &mut res).unwrap();
    let before = allocs();
    for k in 0..100 {
        dae.residual(k as f64 * 1e-3, &y, &yp, &mut res).unwrap();
    }
    assert_eq!(allocs() - before, 0, "allocations in the loop residual");
    // Consistent start: every row (kinematics, dynamics, g, G v) vanishes to round-off of
    // forces of a few newtons (1e-9 is far above it and far below any missing term).
    assert!(res.iter().all(|r| r.abs() < 1e-9), "{res:?}");
}

/// Only pairs the broad phase reports near have a state (memory linear in the shapes, not in
/// the N²/2 candidate pairs). Reference, from the geometry: the balls are 2 cm apart and the
/// broad phase loosens each box by half the margin, a quarter of the smallest bounding radius
/// (3 cm): 7.5 mm per side, 1.5 cm per pair < 2 cm, so no ball–ball pair is near and the 8
/// ball–table pairs (all touching) are the only ones of the 36 candidate pairs with a state.
#[test]
fn only_near_pairs_have_a_state() {
    let model = balls_on_a_table().build().unwrap();
    let cp = model.contact.clone().expect("candidate pairs");
    assert_eq!(cp.n_pairs, 8 + 28, "8 ball–table and 28 ball–ball pairs");
    assert_eq!(model.contact_pairs().len(), cp.n_pairs);
    let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
    let y = model.plan.y0();
    dae.handle_event(0.0, &y).unwrap();
    let cs = dae.contact().unwrap();
    assert_eq!(cs.pairs_with_state(), 8);
    assert_eq!(cs.n_active(), 8, "every ball rests on the table");
    let names = model.contact_pairs();
    for (id, pp, ps) in cs.active_pairs() {
        assert!(
            ps.in_contact && ps.z < 0.0,
            "penetrating the table by 1e-7 m"
        );
        assert_eq!(cs.state_of(pp.b, pp.a), Some(ps), "lookup in either order");
        // The id is the pair's index among all candidate pairs (the signals' order).
        assert_eq!(cp.pair_by_id(id), Some(*pp));
        assert_eq!(cp.pair_id(pp.b, pp.a), Some(id));
        assert_eq!(names[id].name, cp.pair_name(&model.plan.scene, pp));
    }
    // Ids and enumeration agree for every candidate pair.
    for (id, pp) in cp.candidate_pairs().enumerate() {
        assert_eq!(cp.pair_id(pp.a, pp.b), Some(id));
        assert_eq!(cp.pair_by_id(id), Some(pp));
    }
    assert_eq!(cp.pair_by_id(cp.n_pairs), None);
}

/// The new force elements allocate nothing in the residual: a large-angle bushing with a
/// closure law, a nonlinear point-to-point spring-damper, world forces and torques (constant,
/// closure, resolved in an object) under point gravity.
#[test]
fn force_elements_and_point_gravity_do_not_allocate() {
    use crate::scene::{Bushing, ForceElement, GravityField, Law, VectorLaw};
    let mut s = SceneDesc::new();
    let field = GravityField::Point {
        mu: 1.0,
        centre: Vector3::new(0.0, 0.0, -3.0),
    };
    s.add(Object3D::new("world").scene(SceneOptions {
        gravity_field: Some(field),
        ..Default::default()
    }))
    .add(Object3D::new("block").solid(Solid::new(Shape::Sphere { diameter: 0.2 }).mass(1.0)))
    .add_joint(Joint::new(
        "free",
        "world",
        "block",
        JointKind::FreeMotion {
            r: Vector3::new(0.1, 0.0, 0.2),
            rot: FreeRotation::Cardan([0.3, 0.2, 0.1]),
            v: Vector3::new(0.0, 0.1, 0.0),
            w: Vector3::new(0.2, 0.0, 0.1),
        },
    ));
    let mut b = Bushing::new("mount", "world", "block")
        .stiffness([100.0; 3])
        .damping([1.0; 3])
        .rot_stiffness([10.0; 3])
        .large_angles(true);
    b.rot_damper[2] = Law::new(|w| 0.1 * w + 0.01 * w * w * w);
    s.add_force(ForceElement::from(b))
        .add_force(ForceElement::SpringDamperPtP {
            name: "cubic".into(),
            obj1: "world".into(),
            obj2: "block".into(),
            length0: 0.1,
            spring: Law::new(|x| 50.0 * x + 1e3 * x * x * x),
            damper: Law::Linear(0.5),
        })
        .add_force(ForceElement::WorldForce {
            name: "push".into(),
            object: "block".into(),
            force: VectorLaw::new(|t, m| Vector3::new(t.sin(), 0.0, -m.v_abs.z)),
            resolved_in: None,
        })
        .add_force(ForceElement::WorldTorque {
            name: "twist".into(),
            object: "block".into(),
            torque: VectorLaw::from([0.0, 0.0, 0.5]),
            resolved_in: Some("block".into()),
        });
    let model = s.build().unwrap();
    let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
    let y = model.plan.y0();
    let yp = dae.consistent_derivative(0.0, &mut y.clone()).unwrap();
    let mut res = vec![0.0; y.len()];
    dae.residual(0.0, &y, &yp, &mut res).unwrap();
    let before = allocs();
    for k in 0..100 {
        dae.residual(k as f64 * 1e-3, &y, &yp, &mut res).unwrap();
    }
    assert_eq!(allocs() - before, 0, "allocations in the force elements");
    // At t = 0 the consistent derivative makes the residual vanish: every element is applied
    // the same way in both (the time-dependent force changes it at later times).
    dae.residual(0.0, &y, &yp, &mut res).unwrap();
    assert!(res.iter().all(|r| r.abs() < 1e-9), "{res:?}");
}

/// The components' stage allocates nothing: residual and root functions of a link driven by
/// an elastic-gear servo with a limited PID, a limiter, a sampled PI and a path reference,
/// once warmed up.
/// The Jacobian's point at time `t` \[s\] with `c_j` = 1e3 and `h` = 1e-4 s.
fn jacobian_args<'a>(
    t: f64,
    y: &'a [f64],
    yp: &'a [f64],
    zero_size: &'a [f64],
) -> crate::solver::JacobianArgs<'a> {
    crate::solver::JacobianArgs {
        t,
        c_j: 1e3,
        h: 1e-4,
        y,
        yp,
        zero_size,
    }
}

#[test]
fn components_do_not_allocate() {
    use crate::scene::blocks::{Drive, Feedback, Gain, LimPID, Limiter, PtpPath, Sampled, PI};
    use crate::scene::{ComponentDecl, Src};
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions::default()))
        .add(Object3D::new("link").solid(Solid::new(Shape::Sphere { diameter: 0.1 }).mass(1.0)))
        .add(
            Object3D::new("pivot")
                .parent("link")
                .translation([0.3, 0.0, 0.0]),
        )
        .add_joint(Joint::new("rev", "world", "pivot", JointKind::revolute(2)));
    s.add_component(ComponentDecl::new(
        "path",
        PtpPath {
            positions: vec![vec![0.0], vec![0.5], vec![0.0]],
            v_max: vec![1.0],
            a_max: vec![2.0],
            startTime: 0.0,
        },
    ))
    .add_component(ComponentDecl::new("ref", Gain { k: 50.0 }).input("u", "path.q"))
    .add_component(
        ComponentDecl::new("err", Feedback)
            .input("u1", "ref.y")
            .input("u2", "drive.motor_phi"),
    )
    .add_component(
        ComponentDecl::new("pid", LimPID::default())
            .input(
                "u_s",
                Src::expr(&["err.y", "time"], |t, v| v[0] * (1.0 + t)),
            )
            .input("u_m", "drive.motor_w"),
    )
    .add_component(ComponentDecl::new("lim", Limiter::new(-5.0, 5.0)).input("u", "pid.y"))
    .add_component(
        ComponentDecl::new("dig", Sampled::new(1e-3, PI::new(1.0, 0.1))).input("u", "err.y"),
    )
    .add_component(
        ComponentDecl::new("drive", Drive::rigid("rev", 50.0, 1e-4).elastic(1e3, 1.0)).input(
            "tau",
            Src::expr(&["lim.y", "dig.y"], |_, v| v[0] + 1e-3 * v[1]),
        ),
    );
    let model = s.build().unwrap();
    let mut dae = MultibodyDae::new(model.plan.clone(), model.contact.clone());
    let n = dae.len();
    let mut y = model.plan.y0();
    y.resize(n, 0.0);
    dae.component_event(0.0, &y).unwrap();
    let yp = dae.consistent_derivative(0.0, &mut y).unwrap();
    let mut res = vec![0.0; n];
    let mut g = vec![0.0; dae.num_roots()];
    assert_eq!(g.len(), 1, "one root function: the components' crossings");
    for _ in 0..3 {
        dae.residual(0.1, &y, &yp, &mut res).unwrap();
        dae.roots(0.1, &y, &yp, &mut g);
    }
    // The states' columns from the blocks' partial derivatives (every block gives them).
    let mut s = crate::solver::BlockStructure::default();
    assert!(dae.jacobian_structure(&mut s));
    let xo = model.plan.x_offset();
    assert!(
        s.analytic[s.block_of[xo]],
        "the states' columns are analytic"
    );
    let zero_size = vec![1e-2; n];
    let mut entries = 0usize;
    let mut jacobian = |dae: &mut MultibodyDae, t: f64| {
        let args = jacobian_args(t, &y, &yp, &zero_size);
        dae.jacobian(&args, &mut |_: usize, _: usize, _: f64| entries += 1)
            .unwrap();
    };
    jacobian(&mut dae, 0.1);
    let before = allocs();
    for k in 0..100 {
        let t = 0.01 * k as f64;
        dae.residual(t, &y, &yp, &mut res).unwrap();
        dae.roots(t, &y, &yp, &mut g);
        jacobian(&mut dae, t);
    }
    assert_eq!(allocs() - before, 0, "allocations in the components' stage");
    assert!(entries > 0);
    assert!(res.iter().all(|r| r.is_finite()) && g[0].is_finite());
}
