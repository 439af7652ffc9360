//! Every feature `model!` offers, checked against the `SceneDesc` the builder API would give,
//! and built (validated and planned) by the core. Nested assemblies: names, the attach rule,
//! parameters passing down, the same assembly several times.

use modia3d::prelude::*;
use std::f64::consts::PI;

model! {
    /// All shapes, materials and mass-property forms.
    pub assembly Shapes(d: f64 = 0.2, steel: &'static str = "Steel") {
        wood     = SolidMaterial(density = 700.0, young_modulus = 1.1e10, poisson_ratio = 0.4),
        sphere   = Object3D(feature = Solid(shape = Sphere(diameter = d), solid_material = steel)),
        cube     = Object3D(parent = sphere, translation = [1.0, 0.0, 0.0], rotation = [0.0, 0.0, PI / 2.0],
                            feature = Solid(shape = Box(lengths = [d, 2.0 * d, 3.0 * d]), solid_material = wood,
                                            collision = true, contact_material = "Wood", smoothing_radius = 0.001)),
        cyl      = Object3D(parent = sphere, feature = Solid(shape = Cylinder(axis = 1, diameter = d, length = 0.5),
                                                             solid_material = "wood")),
        capsule  = Object3D(parent = sphere, feature = Solid(shape = Capsule(axis = Axis::Y, diameter = d, length = 0.5),
                                                             mass_properties = MassProperties(mass = 2.0))),
        cone     = Object3D(parent = sphere, feature = Solid(shape = Cone(diameter = d, length = 0.3, top_diameter = 0.1),
                                                             solid_material = "Aluminium", collision = true)),
        ellipse  = Object3D(parent = sphere, feature = Solid(shape = Ellipsoid(lengths = [0.1, 0.2, 0.3]),
                                                             mass_properties = MassProperties(mass = 1.0, com = [0.0, 0.0, 0.1],
                                                                                              inertia = Matrix3::identity()))),
        hull     = Object3D(parent = sphere, feature = Solid(shape = ConvexHull(points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0],
                                                                                         [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
                                                             solid_material = "DryWood")),
        scaled   = Object3D(parent = sphere, feature = Solid(shape = Sphere(diameter = d),
                                                             mass_properties = MassPropertiesFromShapeAndMass(mass = 3.0))),
        point    = Object3D(parent = sphere, feature = Solid(mass_properties = MassProperties(mass = 1.0, inertia = [[0.0; 3]; 3]))),
        drawn    = Object3D(parent = sphere, rotation = Matrix3::identity(), feature = Visual(shape = Sphere(diameter = 0.05))),
        custom   = Object3D(parent = sphere, feature = Feature::Visual(Shape::Sphere { diameter: 0.01 })),
    }
}

model! {
    /// Every joint kind, force element and scene option.
    pub Machine(gravity: f64 = -9.81, k: f64 = 100.0) {
        tilted  = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        spin    = Revolute(obj1 = world, obj2 = tilted, axis = [0.0, 1.0, 1.0]),
        turned  = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        swirl   = FreeMotion(obj1 = world, obj2 = turned, rot = Var(init = UnitQuaternion::identity())),
        world   = Object3D(feature = Scene(gravity = [0.0, 0.0, gravity])),
        parts   = Shapes(d = 0.1),
        slider  = Object3D(feature = Solid(shape = Box(lengths = [0.1, 0.1, 0.1]), solid_material = "Steel")),
        pendel  = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        pivot   = Object3D(parent = pendel, translation = [0.0, 0.0, 0.5]),
        free    = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel")),
        fixed   = Fix(obj1 = world, obj2 = parts.sphere),
        slide   = Prismatic(obj1 = world, obj2 = slider, axis = -3, s = Var(init = 0.1), v = Var(init = 0.2)),
        rev     = Revolute(obj1 = slider, obj2 = pivot, axis = 2, phi = Var(init = 0.3), w = Var(init = -0.1),
                           can_collide = true),
        fly     = FreeMotion(obj1 = world, obj2 = free, r = Var(init = [0.0, 1.0, 2.0]), rot = Var(init = [0.1, 0.2, 0.3]),
                             v = Var(init = [1.0, 0.0, 0.0]), w = Var(init = [0.0, 0.0, 1.0])),
        spring  = SpringDamper(obj1 = world, obj2 = slider, stiffness = k, damping = 1.0, length0 = 0.1),
        rot_d   = JointSpringDamper(joint = rev, stiffness = 0.0, damping = 0.5, offset = 0.1),
        lift    = ObjectForce(object = free, law = move |_t: f64, _m: &ObjectMotion| Wrench {
            force: Vector3::new(0.0, 0.0, -gravity),
            torque: Vector3::zeros(),
        }),
    }
}

fn obj<'a>(s: &'a SceneDesc, name: &str) -> &'a Object3D {
    s.objects
        .iter()
        .find(|o| o.name == name)
        .unwrap_or_else(|| panic!("no object `{name}`"))
}

fn solid(o: &Object3D) -> &Solid {
    match &o.feature {
        Feature::Solid(s) => s,
        f => panic!("`{}` is {f:?}", o.name),
    }
}

#[test]
fn shapes_materials_and_mass_properties() {
    let s = Shapes::default().scene();
    assert_eq!(
        s.solid_materials,
        vec![(
            "wood".to_string(),
            SolidMaterial {
                density: 700.0,
                young_modulus: 1.1e10,
                poisson_ratio: 0.4
            }
        )]
    );
    assert_eq!(
        obj(&s, "sphere").feature,
        Feature::Solid(Solid::new(Shape::Sphere { diameter: 0.2 }).material("Steel"))
    );
    let cube = obj(&s, "cube");
    assert_eq!(cube.parent.as_deref(), Some("sphere"));
    assert_eq!(cube.translation, Vector3::new(1.0, 0.0, 0.0));
    assert_eq!(cube.rotation, Rotation::Cardan([0.0, 0.0, PI / 2.0]));
    assert_eq!(
        solid(cube),
        &Solid::new(Shape::Box {
            lengths: Vector3::new(0.2, 2.0 * 0.2, 3.0 * 0.2)
        })
        .material("wood")
        .collision(true)
        .contact_material("Wood")
        .smoothing_radius(0.001)
    );
    assert_eq!(
        solid(obj(&s, "cyl")).material,
        Some(MaterialRef::Name("wood".into()))
    );
    assert_eq!(
        solid(obj(&s, "cyl")).shape,
        Some(Shape::Cylinder {
            axis: Axis::X,
            diameter: 0.2,
            length: 0.5
        })
    );
    assert_eq!(
        solid(obj(&s, "capsule")).shape,
        Some(Shape::Capsule {
            axis: Axis::Y,
            diameter: 0.2,
            length: 0.5
        })
    );
    assert_eq!(
        solid(obj(&s, "capsule")).mass_properties,
        MassSpec::Mass(2.0)
    );
    assert_eq!(
        solid(obj(&s, "scaled")).mass_properties,
        MassSpec::FromShapeAndMass(3.0)
    );
    assert_eq!(
        solid(obj(&s, "cone")).shape,
        Some(Shape::Cone {
            axis: Axis::Z,
            diameter: 0.2,
            length: 0.3,
            top_diameter: 0.1
        })
    );
    assert_eq!(
        solid(obj(&s, "ellipse")).mass_properties,
        MassSpec::Explicit {
            mass: 1.0,
            com: Vector3::new(0.0, 0.0, 0.1),
            inertia: Matrix3::identity()
        }
    );
    match &solid(obj(&s, "hull")).shape {
        Some(Shape::ConvexHull { points }) => assert_eq!(points.len(), 4),
        other => panic!("{other:?}"),
    }
    assert_eq!(solid(obj(&s, "point")).shape, None);
    assert_eq!(
        obj(&s, "drawn").feature,
        Feature::Visual(Shape::Sphere { diameter: 0.05 })
    );
    assert_eq!(
        obj(&s, "custom").feature,
        Feature::Visual(Shape::Sphere { diameter: 0.01 })
    );
    // A sub-assembly without parent: its root `sphere` stays a root.
    assert_eq!(obj(&s, "sphere").parent, None);
}

#[test]
fn joints_forces_and_scene_options() {
    let m = Machine {
        gravity: -1.62,
        ..Default::default()
    };
    let s = m.scene();
    assert_eq!(
        obj(&s, "world").feature,
        Feature::Scene(SceneOptions {
            gravity: Vector3::new(0.0, 0.0, -1.62),
            ..Default::default()
        })
    );
    // Sub-assembly objects and materials are prefixed; parameters pass down.
    assert_eq!(
        obj(&s, "parts.cube").parent.as_deref(),
        Some("parts.sphere")
    );
    assert_eq!(
        solid(obj(&s, "parts.sphere")).shape,
        Some(Shape::Sphere { diameter: 0.1 })
    );
    assert_eq!(
        solid(obj(&s, "parts.cyl")).material,
        Some(MaterialRef::Name("parts.wood".into()))
    );
    assert_eq!(s.solid_materials[0].0, "parts.wood");
    let spin = s.joints.iter().find(|j| j.name == "spin").unwrap();
    assert_eq!(
        spin.kind,
        JointKind::Revolute {
            axis: Vector3::new(0.0, 1.0, 1.0),
            phi: 0.0,
            w: 0.0
        }
    );
    let swirl = s.joints.iter().find(|j| j.name == "swirl").unwrap();
    assert!(matches!(
        swirl.kind,
        JointKind::FreeMotion {
            rot: FreeRotation::Quaternion(_),
            ..
        }
    ));
    assert_eq!(
        obj(&s, "parts.drawn").rotation,
        Rotation::Matrix(Matrix3::identity())
    );
    let j: Vec<&Joint> = s
        .joints
        .iter()
        .filter(|j| j.name != "spin" && j.name != "swirl")
        .collect();
    assert_eq!(
        j[0],
        &Joint::new("fixed", "world", "parts.sphere", JointKind::Fix)
    );
    assert_eq!(
        j[1],
        &Joint::new("slide", "world", "slider", JointKind::prismatic(-3))
            .init_position(0.1)
            .init_velocity(0.2)
    );
    assert_eq!(
        j[2],
        &Joint::new("rev", "slider", "pivot", JointKind::revolute(2))
            .init_position(0.3)
            .init_velocity(-0.1)
            .can_collide(true)
    );
    assert_eq!(
        j[3].kind,
        JointKind::FreeMotion {
            r: Vector3::new(0.0, 1.0, 2.0),
            rot: FreeRotation::Cardan([0.1, 0.2, 0.3]),
            v: Vector3::new(1.0, 0.0, 0.0),
            w: Vector3::new(0.0, 0.0, 1.0)
        }
    );
    match &s.forces[..] {
        [ForceElement::SpringDamper {
            name,
            obj1,
            obj2,
            stiffness,
            damping,
            length0,
        }, ForceElement::JointSpringDamper {
            joint,
            coordinate: None,
            stiffness: c,
            damping: d,
            offset,
        }, ForceElement::ObjectForce { object, law }] => {
            assert_eq!(
                (name.as_str(), obj1.as_str(), obj2.as_str()),
                ("spring", "world", "slider")
            );
            assert_eq!((*stiffness, *damping, *length0), (100.0, 1.0, 0.1));
            assert_eq!((joint.as_str(), *c, *d, *offset), ("rev", 0.0, 0.5, 0.1));
            assert_eq!(object, "free");
            let motion = ObjectMotion {
                r_abs: Vector3::zeros(),
                rot_abs: Matrix3::identity(),
                v_abs: Vector3::zeros(),
                w_abs: Vector3::zeros(),
            };
            assert_eq!((law.0)(0.0, &motion).force, Vector3::new(0.0, 0.0, 1.62));
        }
        other => panic!("{other:?}"),
    }
    // The core accepts it and it simulates.
    let model = m.build().unwrap();
    let r = model.simulate(&SimOptions::new(0.2)).unwrap();
    assert_eq!(r.signal("rev.phi").unwrap().at(0).unwrap()[0], 0.3);
    assert_eq!(r.signal("slide.s").unwrap().at(0).unwrap()[0], 0.1);
}

model! {
    /// A link: a body with its two end frames.
    pub assembly Link(length: f64 = 0.5) {
        body = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), mass_properties = MassProperties(mass = 1.0))),
        top  = Object3D(parent = body, translation = [0.0, 0.0, length]),
    }
}

model! {
    /// Two links: the first fixed at the root-level mount, the second on a revolute.
    pub assembly Arm(l1: f64 = 0.5, l2: f64 = 0.4, q: f64 = 0.0) {
        mount = Object3D(),
        base  = Link(length = l1),
        upper = Link(length = l2),
        hinge = Revolute(obj1 = base.body, obj2 = upper.top, axis = 1, phi = Var(init = q)),
    }
}

/// Assemblies in another module are named by path.
mod tools {
    modia3d::model! {
        /// A gripper with a sub-assembly of its own (a link, reached through `super::`).
        pub assembly Gripper(width: f64 = 0.1) {
            palm   = Object3D(feature = Solid(shape = Box(lengths = [width, 0.02, 0.02]), solid_material = "Steel")),
            finger = super::Link(parent = palm, length = width),
        }
    }
}

model! {
    /// The same arm twice, one mounted by `parent`, one by a joint.
    pub Cell(spacing: f64 = 1.0) {
        world = Object3D(feature = Scene()),
        left  = Object3D(parent = world, translation = [-spacing, 0.0, 0.0]),
        arm1  = Arm(parent = left, q = 0.3),
        arm2  = Arm(l1 = 0.7, q = -0.3),
        slide = Prismatic(obj1 = world, obj2 = arm2.mount, axis = 1, s = Var(init = spacing)),
        weld  = Fix(obj1 = arm2.mount, obj2 = arm2.base.body),
        stop  = JointSpringDamper(joint = arm2.hinge, stiffness = 1.0),
        hand  = tools::Gripper(parent = arm1.upper.top, width = 0.2),
        probe = Object3D(parent = hand.finger.top),
    }
}

#[test]
fn nested_assemblies_names_attach_rule_and_parameters() {
    let s = Cell::default().scene();
    let parent = |n: &str| obj(&s, n).parent.clone();
    let names: Vec<&str> = s.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "world",
            "left",
            "arm1.mount",
            "arm1.base.body",
            "arm1.base.top",
            "arm1.upper.body",
            "arm1.upper.top",
            "arm2.mount",
            "arm2.base.body",
            "arm2.base.top",
            "arm2.upper.body",
            "arm2.upper.top",
            "hand.palm",
            "hand.finger.body",
            "hand.finger.top",
            "probe",
        ]
    );
    assert_eq!(parent("hand.palm").as_deref(), Some("arm1.upper.top"));
    assert_eq!(parent("hand.finger.body").as_deref(), Some("hand.palm"));
    assert_eq!(parent("probe").as_deref(), Some("hand.finger.top"));
    assert_eq!(obj(&s, "hand.finger.top").translation[2], 0.2);
    // Attach rule: root-level parts of arm1 (mount, base.body) hang on `left`; upper.body is
    // moved by the hinge and stays a root; arm2 has no parent, so nothing is attached.
    assert_eq!(parent("arm1.mount").as_deref(), Some("left"));
    assert_eq!(parent("arm1.base.body").as_deref(), Some("left"));
    assert_eq!(parent("arm1.upper.body"), None);
    assert_eq!(parent("arm2.mount"), None);
    assert_eq!(parent("arm2.base.body"), None);
    // Parameters pass down, per instance.
    assert_eq!(obj(&s, "arm1.base.top").translation[2], 0.5);
    assert_eq!(obj(&s, "arm2.base.top").translation[2], 0.7);
    let hinge2 = s.joints.iter().find(|j| j.name == "arm2.hinge").unwrap();
    assert_eq!(
        (hinge2.obj1.as_str(), hinge2.obj2.as_str()),
        ("arm2.base.body", "arm2.upper.top")
    );
    assert_eq!(
        hinge2.kind,
        JointKind::Revolute {
            axis: Vector3::x(),
            phi: -0.3,
            w: 0.0
        }
    );
    // It builds and its signals read as dotted paths.
    let r = Cell::default()
        .build()
        .unwrap()
        .simulate(&SimOptions::new(0.5))
        .unwrap();
    assert_eq!(r.signal("arm1.hinge.phi").unwrap().at(0).unwrap()[0], 0.3);
    assert!(r.signal("arm2.upper.top.r_abs").is_ok());
}

model! {
    /// Every scene option, contact-pair materials of the block (literal names, a block
    /// material, a parameter; `v_min`/`w_min` as `f64` and as `Option<f64>`), a colliding
    /// steel ball on a wooden table.
    pub Contacts(k_red: f64 = 1e-3, pair: ContactPairMaterial = ContactPairMaterial::new(0.5, 0.2, 0.01),
                 other: &'static str = "Rubber", profile: ContactProfile = ContactProfile::Paper2019) {
        world = Object3D(feature = Scene(gravity = [0.0, 0.0, -1.0], contact_detection = true,
                                         exact_restitution = true, average_missing_pairs = true, k_red = k_red,
                                         d_max = 2000.0, cor_min = 0.01, v_min = 0.02, v_min_volume = 0.004, w_min = 0.03,
                                         hysteresis = 1e-13, mpr_tolerance = 1e-10, mpr_max_iterations = 50,
                                         smoothing_radius = 0.002, profile = Modia3DLater)),
        oak   = SolidMaterial(density = 700.0, young_modulus = 1.1e10, poisson_ratio = 0.4),
        table = Object3D(parent = world, feature = Solid(shape = Box(lengths = [1.0, 1.0, 0.1]), solid_material = oak,
                                                         collision = true)),
        ball  = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), solid_material = "Steel", collision = true)),
        free  = FreeMotion(obj1 = world, obj2 = ball, r = Var(init = [0.0, 0.0, 0.2])),
        steel_oak = ContactPair(material1 = "Steel", material2 = oak, cor = 0.6, mu_k = 0.3, mu_r = 0.001,
                                v_min = 0.05, w_min = 0.5),
        steel_steel = ContactPair(material1 = "Steel", material2 = "Steel", cor = pair.cor, mu_k = pair.mu_k,
                                  mu_r = pair.mu_r, v_min = pair.v_min, w_min = pair.w_min),
        rubber = ContactPair(material1 = other, material2 = "oak", cor = 0.3, mu_k = 0.9, mu_r = 0.0),
    }
}

model! {
    /// The profile as a parameter; contact detection off.
    pub ProfileParam(profile: ContactProfile = ContactProfile::Modia3DLater) {
        world = Object3D(feature = Scene(profile = profile, contact_detection = false)),
    }
}

#[test]
fn scene_options_and_contact_pairs() {
    let s = Contacts::default().scene();
    let mut b = SceneDesc::new();
    b.add(Object3D::new("world").scene(SceneOptions {
        gravity: Vector3::new(0.0, 0.0, -1.0),
        gravity_field: None,
        contact_detection: true,
        k_red: 1e-3,
        d_max: 2000.0,
        cor_min: 0.01,
        v_min: 0.02,
        v_min_volume: 0.004,
        w_min: 0.03,
        hysteresis: 1e-13,
        mpr_tolerance: 1e-10,
        mpr_max_iterations: 50,
        smoothing_radius: 0.002,
        contact_profile: ContactProfile::Modia3DLater,
        exact_restitution: true,
        average_missing_pairs: true,
        modia3d_conventions: false,
    }))
    .add_solid_material(
        "oak",
        SolidMaterial {
            density: 700.0,
            young_modulus: 1.1e10,
            poisson_ratio: 0.4,
        },
    )
    .add(
        Object3D::new("table").parent("world").solid(
            Solid::new(Shape::Box {
                lengths: Vector3::new(1.0, 1.0, 0.1),
            })
            .material("oak")
            .collision(true),
        ),
    )
    .add(
        Object3D::new("ball").solid(
            Solid::new(Shape::Sphere { diameter: 0.1 })
                .material("Steel")
                .collision(true),
        ),
    )
    .add_joint(Joint::new(
        "free",
        "world",
        "ball",
        JointKind::FreeMotion {
            r: Vector3::new(0.0, 0.0, 0.2),
            rot: FreeRotation::Cardan([0.0; 3]),
            v: Vector3::zeros(),
            w: Vector3::zeros(),
        },
    ))
    .add_contact_pair(
        "Steel",
        "oak",
        ContactPairMaterial::new(0.6, 0.3, 0.001)
            .v_min(0.05)
            .w_min(0.5),
    )
    .add_contact_pair("Steel", "Steel", ContactPairMaterial::new(0.5, 0.2, 0.01))
    .add_contact_pair("Rubber", "oak", ContactPairMaterial::new(0.3, 0.9, 0.0));
    assert_eq!(s.objects, b.objects);
    assert_eq!(s.joints, b.joints);
    assert_eq!(s.solid_materials, b.solid_materials);
    assert_eq!(s.contact_pairs, b.contact_pairs);
    // `v_min = pair.v_min` passes an `Option<f64>` through.
    let with_v = Contacts {
        pair: ContactPairMaterial::new(0.5, 0.2, 0.01).v_min(0.1),
        ..Default::default()
    }
    .scene();
    assert_eq!(with_v.contact_pairs[1].2.v_min, Some(0.1));
    assert_eq!(with_v.contact_pairs[1].2.w_min, None);
    // The core accepts it and finds the pairs.
    Contacts::default().build().unwrap();

    assert_eq!(
        ProfileParam::default().scene().objects[0].feature,
        Feature::Scene(SceneOptions {
            contact_profile: ContactProfile::Modia3DLater,
            contact_detection: false,
            ..Default::default()
        })
    );
}

model! {
    /// A one-link arm with a motor torque, a prescribed slider and a push on the tip.
    pub assembly Driven(l: f64 = 0.5) {
        mount    = Object3D(),
        link     = Object3D(feature = Solid(shape = Sphere(diameter = 0.1), mass_properties = MassProperties(mass = 1.0))),
        tip      = Object3D(parent = link, translation = [0.0, 0.0, -l]),
        shoulder = Revolute(obj1 = mount, obj2 = link, axis = 1),
        tau      = JointForce(joint = shoulder),
        push     = ObjectWrench(object = tip),
    }
}

model! {
    /// Inputs of the block and into a sub-assembly.
    pub WithInputs {
        world  = Object3D(feature = Scene()),
        arm1   = Driven(parent = world),
        cart   = Object3D(feature = Solid(shape = Box(lengths = [0.1, 0.1, 0.1]), solid_material = "Steel")),
        slide  = Prismatic(obj1 = world, obj2 = cart, axis = 1),
        drive  = JointAcceleration(joint = slide),
        tau2   = JointForce(joint = arm1.shoulder),
        gust   = ObjectWrench(object = arm1.tip),
    }
}

#[test]
fn inputs_match_the_builder_and_drive_the_simulation() {
    let s = WithInputs::default().scene();
    assert_eq!(
        s.inputs,
        vec![
            Input::joint_force("arm1.tau", "arm1.shoulder"),
            Input::object_wrench("arm1.push", "arm1.tip"),
            Input::joint_acceleration("drive", "slide"),
            Input::joint_force("tau2", "arm1.shoulder"),
            Input::object_wrench("gust", "arm1.tip"),
        ]
    );
    let model = WithInputs::default().build().unwrap();
    let mut sim = model.simulation(&SimOptions::new(1.0)).unwrap();
    sim.set_input("drive", &[2.0]).unwrap();
    sim.advance_to(1.0).unwrap();
    // s = a t² / 2 with a = 2 m/s².
    let s_end = sim.output("slide.s").unwrap()[0];
    assert!((s_end - 1.0).abs() < 1e-6, "slide.s = {s_end}");
}

model! {
    /// A pendulum whose bob, a point mass by Modia3D's reading of `MassProperties(mass = …)`,
    /// hangs 1 m below the pivot over a wooden table; the bob's contact material differs
    /// from its solid material.
    pub Porting(conventions: bool = true) {
        world = Object3D(feature = Scene(gravity = [0.0, 0.0, -9.81], modia3d_conventions = conventions)),
        table = Object3D(parent = world, translation = [0.0, 0.0, -2.0],
                         feature = Solid(shape = Box(lengths = [1.0, 1.0, 0.1]), solid_material = "DryWood", collision = true)),
        bob   = Object3D(feature = Solid(shape = Sphere(diameter = 0.2), solid_material = "Steel",
                                         contact_material = "DryWood", collision = true,
                                         mass_properties = MassProperties(mass = 2.0))),
        pivot = Object3D(parent = bob, translation = [0.0, 0.0, 1.0]),
        rev   = Revolute(obj1 = world, obj2 = pivot, axis = 1, phi = Var(init = 1.0)),
    }
}

/// `SceneOptions::modia3d_conventions`: each of the four differences it makes, on the same
/// model with the switch off and on.
#[test]
fn modia3d_conventions_switch_the_four_porting_differences() {
    let c = |m: &SolidMaterial| m.young_modulus / (1.0 - m.poisson_ratio * m.poisson_ratio);
    let material = |n: &str| modia3d::core::scene::builtin_solid_material(n).unwrap();
    let (steel, wood) = (c(&material("Steel")), c(&material("DryWood")));
    let ours = Porting { conventions: false }.build().unwrap();
    let modia = Porting { conventions: true }.build().unwrap();

    // 1. can_collide not given on a Revolute: Modia3D lets the joined bodies (world with its
    //    table, the bob) collide; ours does not.
    assert!(ours.contact_pairs().is_empty());
    let pairs = modia.contact_pairs();
    assert_eq!(pairs.len(), 1, "{pairs:?}");
    // 2. Contact stiffness from the contact material's solid material (DryWood on both
    //    sides: c_res = c/2), not from the bob's Steel. Same formula, so exact up to rounding.
    assert!(
        (pairs[0].c_res - wood / 2.0).abs() <= 1e-12 * wood,
        "{pairs:?}"
    );
    assert!((steel * wood / (steel + wood) - wood / 2.0).abs() > 0.4 * wood);

    // 3. `MassProperties(mass = 2)` is a point mass: the ideal pendulum φ'' = −(g/L) sin φ.
    //    Reference: RK4 at h = 1e-5 s (truncation ~h⁴ ≈ 1e-20, rounding over 2·10⁵ steps
    //    ≲ 1e-11 rad); IDA at rtol 1e-10 over 2 s stays within 1e-8 rad of it (100× its
    //    tolerance). The sphere's own inertia (ours) makes a
    //    physical pendulum that is 4e-3 rad off by then.
    let (g, l) = (9.81, 1.0);
    let reference = |t_end: f64| {
        let (mut phi, mut w, h) = (1.0f64, 0.0f64, 1e-5);
        let f = |p: f64| -(g / l) * p.sin();
        let n = (t_end / h).round() as usize;
        for _ in 0..n {
            let (k1p, k1w) = (w, f(phi));
            let (k2p, k2w) = (w + 0.5 * h * k1w, f(phi + 0.5 * h * k1p));
            let (k3p, k3w) = (w + 0.5 * h * k2w, f(phi + 0.5 * h * k2p));
            let (k4p, k4w) = (w + h * k3w, f(phi + h * k3p));
            phi += h / 6.0 * (k1p + 2.0 * k2p + 2.0 * k3p + k4p);
            w += h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w);
        }
        phi
    };
    let opts = SimOptions::new(2.0).tolerance(1e-10).progress(false);
    let end_phi = |m: &Model| {
        m.simulate(&opts)
            .unwrap()
            .signal("rev.phi")
            .unwrap()
            .last()
            .unwrap()[0]
    };
    let exact = reference(2.0);
    let (phi_modia, phi_ours) = (end_phi(&modia), end_phi(&ours));
    eprintln!("φ(2 s): point mass {phi_modia}, ours {phi_ours}, ideal pendulum {exact}");
    assert!((phi_modia - exact).abs() < 1e-8, "{phi_modia} vs {exact}");
    assert!((phi_ours - exact).abs() > 1e-3, "{phi_ours} vs {exact}");

    // 4. The default absolute tolerance: Modia's 0.1·rtol, ours 0.01·rtol; a given atol wins.
    let on = SceneOptions {
        modia3d_conventions: true,
        ..Default::default()
    };
    let sim = SimOptions::new(1.0).tolerance(1e-6);
    assert_eq!(sim.effective_atol(&on), 0.1 * 1e-6);
    assert_eq!(sim.effective_atol(&SceneOptions::default()), 0.01 * 1e-6);
    assert_eq!(sim.clone().atol(3e-9).effective_atol(&on), 3e-9);
}
