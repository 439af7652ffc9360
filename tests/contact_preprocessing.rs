//! Collision preprocessing, materials and validation: which pairs exist, which errors a scene
//! with collisions can have, and that scenes without pairs run no collision code.

use modia3d::demo;
use modia3d::prelude::*;

fn ball(name: &str) -> Object3D {
    Object3D::new(name).solid(
        Solid::new(Shape::Sphere { diameter: 0.1 })
            .material("Steel")
            .collision(true),
    )
}

fn pair_count(s: &SceneDesc) -> usize {
    let m = s.build().unwrap();
    m.contact_pairs().len()
}

/// Two collision spheres on one body (parent link) and a third on a body joined to it.
fn chain(can_collide: bool) -> SceneDesc {
    let mut s = SceneDesc::new();
    s.add(demo::world(SceneOptions::default()))
        .add(ball("a"))
        .add(ball("a2").parent("a").translation([0.0, 0.0, 0.3]))
        .add(ball("b"))
        .add(
            Object3D::new("hinge")
                .parent("b")
                .translation([0.0, 0.0, 0.5]),
        )
        .add_joint(Joint::new("free", "world", "a", JointKind::free()))
        .add_joint(
            Joint::new("rev", "a", "hinge", JointKind::revolute(2)).can_collide(can_collide),
        );
    s
}

#[test]
fn rigidly_attached_and_jointed_solids_form_pairs_only_when_allowed() {
    // a–a2 rigid: never; a–b and a2–b joined by `rev`: only with can_collide = true.
    assert_eq!(pair_count(&chain(false)), 0);
    assert_eq!(pair_count(&chain(true)), 2);
    let m = chain(true).build().unwrap();
    let names: Vec<String> = m.contact_pairs().into_iter().map(|p| p.name).collect();
    assert_eq!(names, ["a|b", "a2|b"]);
    // A fixed joint merges: solids on the two sides are one body.
    let mut s = SceneDesc::new();
    s.add(demo::world(SceneOptions::default()))
        .add(ball("a"))
        .add(ball("b"))
        .add_joint(Joint::new("free", "world", "a", JointKind::free()))
        .add_joint(Joint::new("fix", "a", "b", JointKind::Fix));
    assert_eq!(pair_count(&s), 0);
    // Contact detection off: no pairs at all.
    let mut s = demo::bouncing_sphere(0.1, 0.5, ContactPairMaterial::new(0.7, 0.0, 0.0));
    s.objects[0] = demo::world(SceneOptions {
        contact_detection: false,
        ..Default::default()
    });
    assert_eq!(pair_count(&s), 0);
}

#[test]
fn a_scene_without_candidate_pairs_has_no_root_functions_and_runs_no_collision_code() {
    let res = chain(false)
        .build()
        .unwrap()
        .simulate(&SimOptions::new(0.5))
        .unwrap();
    let st = res.stats;
    println!("{st:?}");
    assert_eq!(st.root_functions, 0);
    assert_eq!(st.narrow_phase_calls, 0);
    assert_eq!(st.aabb_tests, 0);
    assert_eq!(st.solver.root_evals, 0);
    // With a pair: two root functions and collision calls.
    let res = demo::bouncing_sphere(0.1, 0.5, ContactPairMaterial::new(0.7, 0.0, 0.0))
        .build()
        .unwrap()
        .simulate(&SimOptions::new(0.5))
        .unwrap();
    assert_eq!(res.stats.root_functions, 2);
    assert!(res.stats.narrow_phase_calls > 0 && res.stats.aabb_tests > 0);
}

#[test]
fn a_missing_pair_material_names_both_materials_and_objects() {
    let mut s = SceneDesc::new();
    s.add(demo::world(SceneOptions::default()))
        .add(demo::fixed_box(
            "floor",
            [1.0, 1.0, 0.1],
            [0.0, 0.0, -0.05],
            "BilliardTable",
        ))
        .add(ball("ball"))
        .add_joint(Joint::new("free", "world", "ball", JointKind::free()));
    let err = s.build().unwrap_err();
    assert!(
        matches!(
            &err.0[0],
            SceneError::MissingContactPair { material1, material2, object1, object2 }
                if material1 == "BilliardTable" && material2 == "Steel" && object1 == "floor" && object2 == "ball"
        ),
        "{err}"
    );
    let msg = err.to_string();
    assert!(
        msg.contains("`BilliardTable`")
            && msg.contains("`Steel`")
            && msg.contains("add_contact_pair"),
        "{msg}"
    );
    // Defining the pair (either order) fixes it.
    s.add_contact_pair(
        "Steel",
        "BilliardTable",
        ContactPairMaterial::new(0.5, 0.4, 0.01),
    );
    assert_eq!(pair_count(&s), 1);
}

#[test]
fn ranges_shapes_and_materials_are_checked() {
    let mut s = SceneDesc::new();
    s.add(demo::world(SceneOptions {
        k_red: 0.0,
        hysteresis: -1.0,
        ..Default::default()
    }))
    .add(Object3D::new("noshape").solid(Solid {
        mass_properties: MassSpec::Explicit {
            mass: 1.0,
            com: Vector3::zeros(),
            inertia: Matrix3::identity(),
        },
        collision: true,
        ..Default::default()
    }))
    .add(
        Object3D::new("nomat").solid(
            Solid::new(Shape::Sphere { diameter: 0.1 })
                .mass(1.0)
                .collision(true),
        ),
    )
    .add_solid_material(
        "Jelly",
        SolidMaterial {
            density: 0.0,
            young_modulus: -1.0,
            poisson_ratio: 1.0,
        },
    )
    .add_contact_pair(
        "Steel",
        "Steel",
        ContactPairMaterial::new(1.5, -0.1, -1.0).v_min(0.0),
    );
    let err = s.validate().unwrap_err();
    let msg = err.to_string();
    println!("{msg}");
    for needle in [
        "k_red",
        "hysteresis",
        "`noshape` takes part in collisions but has no shape",
        "`nomat` takes part in collisions but has no material",
        "`Jelly`: density",
        "`Jelly`: Young's modulus",
        "`Jelly`: Poisson's ratio",
        "`Steel`–`Steel`: cor",
        "`Steel`–`Steel`: mu_k",
        "`Steel`–`Steel`: mu_r",
        "`Steel`–`Steel`: v_min",
    ] {
        assert!(msg.contains(needle), "missing `{needle}` in:\n{msg}");
    }
}

#[test]
fn palettes_load_from_json() {
    let text = r#"{
        "solid": { "Rubber": { "density": 1100, "young_modulus": 5e7, "poisson_ratio": 0.45 } },
        "contact_pairs": [
            { "materials": ["Rubber", "Steel"], "cor": 0.5, "mu_k": 0.8, "mu_r": 0.01, "v_min": 0.02 }
        ]
    }"#;
    let path = std::env::temp_dir().join(format!("modia3d_palette_{}.json", std::process::id()));
    std::fs::write(&path, text).unwrap();
    let mut s = SceneDesc::new();
    s.load_materials_json(&path).unwrap();
    std::fs::remove_file(&path).ok();
    s.add(demo::world(SceneOptions::default()))
        .add(demo::fixed_box(
            "floor",
            [1.0, 1.0, 0.1],
            [0.0, 0.0, -0.05],
            "Rubber",
        ))
        .add(ball("ball"))
        .add_joint(Joint::new("free", "world", "ball", JointKind::free()));
    let m = s.build().unwrap();
    let cp = m.contact_pairs();
    assert_eq!((cp[0].cor, cp[0].v_min, cp[0].w_min), (0.5, 0.02, 0.01));
    // Errors say where.
    let bad = MaterialPalette::from_json_str(
        r#"{ "contact_pairs": [ { "materials": ["A", "B"], "cor": 1 } ] }"#,
        "inline",
    );
    let msg = bad.unwrap_err().to_string();
    assert!(msg.contains("inline") && msg.contains("mu_k"), "{msg}");
    let missing = SceneDesc::new()
        .load_materials_json("/nonexistent/palette.json")
        .err()
        .unwrap();
    assert!(missing.to_string().contains("/nonexistent/palette.json"));
}

/// The later-Modia3D profile: Hertz coefficients for every pair (a box counts as flat, so a
/// box–box pair gets R* = 1/(1/r1 + 1/r2) of half the smallest edges), d_max = 2000 s/m,
/// hysteresis 1e-13 m, and cor → 0 for impacts slower than v_min (the ball then stays on
/// the table after its first, slow impact).
#[test]
fn the_later_modia3d_profile_is_an_option() {
    let opts = SceneOptions::modia3d_later();
    assert_eq!(opts.contact_profile, ContactProfile::Modia3DLater);
    assert_eq!((opts.d_max, opts.hysteresis), (2000.0, 1e-13));
    let mut s = SceneDesc::new();
    s.add(demo::world(opts.clone()))
        .add(demo::fixed_box(
            "floor",
            [1.0, 1.0, 0.1],
            [0.0, 0.0, -0.05],
            "Steel",
        ))
        .add(
            Object3D::new("cube").solid(
                Solid::new(Shape::Box {
                    lengths: Vector3::new(0.1, 0.2, 0.3),
                })
                .material("Steel")
                .collision(true),
            ),
        )
        .add_joint(Joint::new(
            "free",
            "world",
            "cube",
            // Above the floor: half inside it would be an initial-penetration error.
            JointKind::FreeMotion {
                r: Vector3::new(0.0, 0.0, 0.2),
                rot: FreeRotation::Cardan([0.0; 3]),
                v: Vector3::zeros(),
                w: Vector3::zeros(),
            },
        ));
    let m = s.build().unwrap();
    let p = &m.contact_pairs()[0];
    let r_star = 1.0 / (1.0 / 0.05 + 1.0 / 0.05);
    assert_eq!(p.n_geo, 1.5);
    assert!(
        (p.mu_geo - r_star).abs() < 1e-15 && (p.c_geo - 4.0 / 3.0 * r_star.sqrt()).abs() < 1e-15
    );
    // The paper's profile: linear law for two non-spheres.
    s.objects[0] = demo::world(SceneOptions {
        contact_profile: ContactProfile::Paper2019,
        ..Default::default()
    });
    let m = s.build().unwrap();
    let p = &m.contact_pairs()[0];
    assert_eq!((p.n_geo, p.c_geo, p.mu_geo), (1.0, 1.0, 1.0));
    assert_eq!(p.volume_stiffness, None);
    // The default profile: the volume law, κ_i = c/H_i with H = half the smallest edge (floor
    // 0.05 m, cube 0.05 m), in series.
    s.objects[0] = demo::world(SceneOptions::default());
    let m = s.build().unwrap();
    let p = &m.contact_pairs()[0];
    let steel = modia3d::core::scene::builtin_solid_material("Steel").unwrap();
    let c = demo::c_res(&steel, &steel) * 2.0; // E/(1 − ν²) of one steel body
    let kappa = 1.0 / (0.05 / c + 0.05 / c);
    let got = p.volume_stiffness.expect("volume law");
    assert!((got - kappa).abs() < 1e-12 * kappa, "{got} vs {kappa}");
    // A slow drop (impact 5 mm/s < v_min): cor replaced by 0, no rebound event.
    let mut s = demo::bouncing_sphere(
        0.1,
        0.05 + 0.005f64.powi(2) / (2.0 * 9.81),
        ContactPairMaterial::new(0.9, 0.0, 0.0),
    );
    s.objects[0] = demo::world(opts);
    let res = s
        .build()
        .unwrap()
        .simulate(&SimOptions::new(0.5).tolerance(1e-7))
        .unwrap();
    println!(
        "{:?}",
        res.events
            .iter()
            .map(|e| (e.t, e.description.clone()))
            .collect::<Vec<_>>()
    );
    assert_eq!(res.events.len(), 1, "one contact start, never ends");
}

/// Every joint that is a mechanical connection keeps its two bodies apart unless
/// `can_collide` is set (the rule `scene/contact_rules.rs` shares with `model!`): a ball joined
/// to a free ball by each new kind forms no pair without `can_collide` and exactly one with it.
#[test]
fn new_joints_exclude_their_bodies_from_contact_unless_can_collide() {
    for kind in [
        JointKind::spherical(),
        JointKind::universal(1, 2),
        JointKind::cylindrical(3),
        JointKind::planar(3),
    ] {
        let name = kind.name();
        let scene = |can_collide: bool| {
            let mut s = SceneDesc::new();
            s.add(demo::world(SceneOptions::default()))
                .add(ball("a"))
                .add(
                    Object3D::new("mount")
                        .parent("a")
                        .translation([0.0, 0.0, 0.3]),
                )
                .add(ball("b"))
                .add_joint(Joint::new("free", "world", "a", JointKind::free()))
                .add_joint(Joint::new("j", "mount", "b", kind.clone()).can_collide(can_collide));
            s
        };
        assert_eq!(pair_count(&scene(false)), 0, "{name} without can_collide");
        assert_eq!(pair_count(&scene(true)), 1, "{name} with can_collide");
    }
}
