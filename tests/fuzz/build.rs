//! A [`SceneSpec`] as builder calls: world `world`, table `table`, body `k` as object `b{k}`
//! on mount frame `m{k}` with joint `j{k}`, inputs `i{k}`.

use super::{BodySpec, ForceSpec, InputSpec, JointSpec, SceneSpec, ShapeSpec};
use modia3d::prelude::*;

fn axis(i: i64) -> Axis {
    Axis::from_index(i.abs()).unwrap_or(Axis::Z)
}

/// The library shape of a shape spec.
pub fn shape(s: &ShapeSpec) -> Shape {
    match s {
        ShapeSpec::Sphere(d) => Shape::Sphere { diameter: *d },
        ShapeSpec::Box(l) => Shape::Box {
            lengths: Vector3::from(*l),
        },
        ShapeSpec::Cylinder(a, d, l) => Shape::Cylinder {
            axis: axis(*a),
            diameter: *d,
            length: *l,
        },
        ShapeSpec::Capsule(a, d, l) => Shape::Capsule {
            axis: axis(*a),
            diameter: *d,
            length: *l,
        },
        ShapeSpec::Cone(a, d, l, t) => Shape::Cone {
            axis: axis(*a),
            diameter: *d,
            length: *l,
            top_diameter: *t,
        },
        ShapeSpec::Ellipsoid(l) => Shape::Ellipsoid {
            lengths: Vector3::from(*l),
        },
        ShapeSpec::Hull(p) => Shape::ConvexHull {
            points: p.iter().map(|x| Point3::from(*x)).collect(),
        },
    }
}

fn parent_name(p: Option<usize>) -> String {
    p.map_or_else(|| "world".into(), |k| format!("b{k}"))
}

fn add_body(d: &mut SceneDesc, k: usize, b: &BodySpec) {
    let mut solid = Solid::new(shape(&b.shape))
        .material(&b.material)
        .collision(b.collision);
    if let Some(m) = b.mass {
        solid = solid.mass(m);
    }
    let name = format!("b{k}");
    let parent = parent_name(b.parent);
    let mount = |d: &mut SceneDesc| {
        let m = format!("m{k}");
        d.add(
            Object3D::new(&m)
                .parent(&parent)
                .translation(b.mount)
                .rotation(Rotation::Cardan(b.mount_rot)),
        );
        m
    };
    let jname = format!("j{k}");
    match &b.joint {
        JointSpec::Attached => {
            d.add(
                Object3D::new(&name)
                    .parent(&parent)
                    .translation(b.mount)
                    .rotation(Rotation::Cardan(b.mount_rot))
                    .solid(solid),
            );
        }
        JointSpec::Free { r, rot, v, w } => {
            d.add(Object3D::new(&name).solid(solid));
            d.add_joint(Joint::new(
                &jname,
                &parent,
                &name,
                JointKind::FreeMotion {
                    r: Vector3::from(*r),
                    rot: FreeRotation::Cardan(*rot),
                    v: Vector3::from(*v),
                    w: Vector3::from(*w),
                },
            ));
        }
        joint @ (JointSpec::Spherical { .. }
        | JointSpec::Universal { .. }
        | JointSpec::Cylindrical { .. }
        | JointSpec::Planar { .. }) => {
            let (kind, can_collide) = match *joint {
                JointSpec::Spherical {
                    rot,
                    w,
                    can_collide,
                } => (
                    JointKind::Spherical {
                        rot: FreeRotation::Cardan(rot),
                        w: Vector3::from(w),
                    },
                    can_collide,
                ),
                JointSpec::Universal {
                    axis1,
                    axis2,
                    phi,
                    w,
                    can_collide,
                } => {
                    let mut k = JointKind::universal(axis1, axis2);
                    if let JointKind::Universal {
                        phi1, phi2, w1, w2, ..
                    } = &mut k
                    {
                        (*phi1, *phi2, *w1, *w2) = (phi[0], phi[1], w[0], w[1]);
                    }
                    (k, can_collide)
                }
                JointSpec::Cylindrical {
                    axis,
                    q,
                    v,
                    can_collide,
                } => {
                    let mut k = JointKind::cylindrical(axis);
                    if let JointKind::Cylindrical {
                        phi, s, w, v: vs, ..
                    } = &mut k
                    {
                        (*phi, *s, *w, *vs) = (q[0], q[1], v[0], v[1]);
                    }
                    (k, can_collide)
                }
                JointSpec::Planar {
                    normal,
                    q,
                    v,
                    can_collide,
                } => {
                    let mut k = JointKind::planar(normal);
                    if let JointKind::Planar {
                        x,
                        y,
                        phi,
                        vx,
                        vy,
                        w,
                        ..
                    } = &mut k
                    {
                        (*x, *y, *phi, *vx, *vy, *w) = (q[0], q[1], q[2], v[0], v[1], v[2]);
                    }
                    (k, can_collide)
                }
                _ => unreachable!("matched above"),
            };
            let m = mount(d);
            d.add(Object3D::new(&name).solid(solid));
            d.add_joint(Joint::new(&jname, &m, &name, kind).can_collide(can_collide));
        }
        joint => {
            // Fix, Revolute or Prismatic at the mount frame.
            let (kind, x, dx, can_collide) = match *joint {
                JointSpec::Revolute {
                    axis,
                    phi,
                    w,
                    can_collide,
                } => (JointKind::revolute(axis), phi, w, can_collide),
                JointSpec::Prismatic {
                    axis,
                    s,
                    v,
                    can_collide,
                } => (JointKind::prismatic(axis), s, v, can_collide),
                _ => (JointKind::Fix, 0.0, 0.0, false),
            };
            let m = mount(d);
            d.add(Object3D::new(&name).solid(solid));
            d.add_joint(
                Joint::new(&jname, &m, &name, kind)
                    .init_position(x)
                    .init_velocity(dx)
                    .can_collide(can_collide),
            );
        }
    }
}

fn add_force(d: &mut SceneDesc, i: usize, f: &ForceSpec) {
    let e = match f {
        ForceSpec::Spring {
            a,
            b,
            stiffness,
            damping,
            length0,
        } => ForceElement::SpringDamper {
            name: format!("spring{i}"),
            obj1: parent_name(*a),
            obj2: format!("b{b}"),
            stiffness: *stiffness,
            damping: *damping,
            length0: *length0,
        },
        ForceSpec::JointSpring {
            body,
            stiffness,
            damping,
            offset,
        } => ForceElement::JointSpringDamper {
            joint: format!("j{body}"),
            coordinate: None,
            stiffness: *stiffness,
            damping: *damping,
            offset: *offset,
        },
        ForceSpec::Constant {
            body,
            force,
            torque,
        } => {
            let w = Wrench {
                force: Vector3::from(*force),
                torque: Vector3::from(*torque),
            };
            ForceElement::ObjectForce {
                object: format!("b{body}"),
                law: ForceFn::new(move |_, _| w),
            }
        }
        ForceSpec::Drag { body, c } => {
            let c = *c;
            ForceElement::ObjectForce {
                object: format!("b{body}"),
                law: ForceFn::new(move |_, m| Wrench {
                    force: -c * m.v_abs,
                    torque: Vector3::zeros(),
                }),
            }
        }
    };
    d.add_force(e);
}

/// The scene description of `s`.
pub fn scene(s: &SceneSpec) -> SceneDesc {
    let mut d = SceneDesc::new();
    // `MODIA3D_FUZZ_LATER=1` replays scenes with the later Modia3D profile (Hertz for every
    // pair) in place of the drawn one, to tell the paper's linear law apart from the rest.
    let later = std::env::var("MODIA3D_FUZZ_LATER").is_ok_and(|v| v == "1");
    let mut opts = if s.later_profile || later {
        SceneOptions::modia3d_later()
    } else if s.paper_profile {
        SceneOptions {
            contact_profile: ContactProfile::Paper2019,
            ..Default::default()
        }
    } else {
        SceneOptions::default()
    };
    opts.contact_detection = s.contact;
    opts.k_red = s.k_red;
    opts.mpr_tolerance = s.mpr_tolerance;
    opts.hysteresis = s.hysteresis;
    opts.gravity = Vector3::from(s.gravity);
    d.add(Object3D::new("world").scene(opts));
    if let Some((lengths, centre, material)) = &s.table {
        d.add(modia3d::demo::fixed_box(
            "table", *lengths, *centre, material,
        ));
    }
    for (a, b, m) in &s.pairs {
        d.add_contact_pair(a, b, ContactPairMaterial::new(m[0], m[1], m[2]));
    }
    for (k, b) in s.bodies.iter().enumerate() {
        add_body(&mut d, k, b);
    }
    for (i, f) in s.forces.iter().enumerate() {
        add_force(&mut d, i, f);
    }
    for (i, inp) in s.inputs.iter().enumerate() {
        let name = format!("i{i}");
        d.add_input(match inp {
            InputSpec::JointForce(k) => Input::joint_force(&name, &format!("j{k}")),
            InputSpec::JointAcceleration(k) => Input::joint_acceleration(&name, &format!("j{k}")),
            InputSpec::Wrench(k) => Input::object_wrench(&name, &format!("b{k}")),
        });
    }
    d
}

/// The run options of `s` (`MODIA3D_FUZZ_TIGHTENING=<factor>` overrides
/// `SimOptions::contact_tightening`, to replay a scene without it: 1 turns it off).
pub fn options(s: &SceneSpec) -> SimOptions {
    let r = &s.run;
    let mut o = SimOptions::new(r.stop_time)
        .tolerance(r.rtol)
        .max_wall_time(r.max_wall_time)
        .contact_results(r.contact_results)
        .structured_jacobian(r.structured_jacobian)
        .jacobian_reuse(r.jacobian_reuse)
        .progress(false);
    if let Some(dt) = r.interval {
        o = o.interval(dt);
    }
    if let Some(n) = r.max_steps {
        o = o.max_steps(Some(n));
    }
    if let Some(k) = std::env::var("MODIA3D_FUZZ_TIGHTENING")
        .ok()
        .and_then(|k| k.parse().ok())
    {
        o = o.contact_tightening(k);
    }
    o
}
