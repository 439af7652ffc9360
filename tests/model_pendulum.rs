//! `model!` against the builder API: the same pendulum written both ways builds the same
//! `SceneDesc` shape and simulates to bit-identical trajectories (the expansion is only builder
//! calls).

use modia3d::prelude::*;

model! {
    /// A pendulum: a ball on a massless rod, released at `phi0`.
    pub Pendulum(length: f64 = 1.0, mass: f64 = 1.0, phi0: f64 = 0.5) {
        world = Object3D(feature = Scene(gravity = [0.0, 0.0, -9.81])),
        body  = Object3D(feature = Solid(shape = Sphere(diameter = 0.1),
                                         mass_properties = MassProperties(mass = mass))),
        frame = Object3D(parent = body, translation = [0.0, 0.0, length]),
        rev   = Revolute(obj1 = world, obj2 = frame, axis = 1, phi = Var(init = phi0)),
    }
}

fn by_builder(length: f64, mass: f64, phi0: f64) -> SceneDesc {
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions::default()))
        .add(
            Object3D::new("body")
                .solid(Solid::new(Shape::Sphere { diameter: 0.1 }).given_mass(mass)),
        )
        .add(
            Object3D::new("frame")
                .parent("body")
                .translation([0.0, 0.0, length]),
        )
        .add_joint(Joint::new("rev", "world", "frame", JointKind::revolute(1)).init_position(phi0));
    s
}

#[test]
fn defaults_and_fields() {
    let p = Pendulum::default();
    assert_eq!((p.length, p.mass, p.phi0), (1.0, 1.0, 0.5));
    let p = Pendulum {
        length: 2.0,
        ..Default::default()
    };
    assert_eq!(p.length, 2.0);
}

#[test]
fn same_scene_description_as_builder() {
    let m = Pendulum {
        length: 2.0,
        mass: 3.0,
        phi0: 0.7,
    }
    .scene();
    let b = by_builder(2.0, 3.0, 0.7);
    assert_eq!(m.objects, b.objects);
    assert_eq!(m.joints, b.joints);
    assert!(m.forces.is_empty() && m.solid_materials.is_empty());
}

#[test]
fn same_trajectory_as_builder() {
    let opts = SimOptions::new(3.0).tolerance(1e-8);
    let p = Pendulum {
        length: 2.0,
        ..Default::default()
    };
    let rm = p.build().unwrap().simulate(&opts).unwrap();
    let rb = by_builder(2.0, 1.0, 0.5)
        .build()
        .unwrap()
        .simulate(&opts)
        .unwrap();
    assert_eq!(rm.time(), rb.time());
    for s in ["rev.phi", "rev.w", "body.r_abs"] {
        let (a, b) = (rm.signal(s).unwrap(), rb.signal(s).unwrap());
        assert_eq!(a.values(), b.values(), "signal {s}");
    }
    // It moved.
    assert!(rm.signal("rev.phi").unwrap().last().unwrap()[0] != 0.5);
}
