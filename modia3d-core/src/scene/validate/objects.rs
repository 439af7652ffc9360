//! Validation of objects: the `Scene` object and its options, solid materials, poses,
//! shapes, solids (materials, mass properties, collision data) and visuals.

use super::{did_you_mean, Checker, MassProps, Names, SceneError, ValidObject, ValidSolid};
use crate::geometry::Shape;
use crate::scene::desc::{Feature, MassSpec, MaterialRef, SceneDesc, SceneOptions};
use crate::scene::materials::{builtin_solid_material, SolidMaterial};
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};
use std::collections::HashMap;

/// The scene's solid materials, checked (the built-in palette is looked up on demand).
pub(super) fn solid_materials<'a>(
    c: &mut Checker,
    desc: &'a SceneDesc,
) -> HashMap<&'a str, SolidMaterial> {
    let mut materials: HashMap<&str, SolidMaterial> = HashMap::new();
    for (name, m) in &desc.solid_materials {
        let what = |f: &str| format!("solid material `{name}`: {f}");
        c.positive(|| what("density [kg/m³]"), m.density);
        c.positive(|| what("Young's modulus [N/m²]"), m.young_modulus);
        c.value(
            || what("Poisson's ratio"),
            m.poisson_ratio,
            m.poisson_ratio > 0.0 && m.poisson_ratio < 1.0,
            "in (0, 1)",
        );
        materials.insert(name.as_str(), *m);
    }
    materials
}

/// The `Scene` object (the world) and its options: exactly one, at the root, values in range.
pub(super) fn world(c: &mut Checker, desc: &SceneDesc) -> (Option<usize>, SceneOptions) {
    let scenes: Vec<usize> = desc
        .objects
        .iter()
        .enumerate()
        .filter(|(_, o)| matches!(o.feature, Feature::Scene(_)))
        .map(|(i, _)| i)
        .collect();
    let world = match scenes.len() {
        0 => {
            c.errors.push(SceneError::NoScene);
            None
        }
        1 => Some(scenes[0]),
        _ => {
            c.errors.push(SceneError::SeveralScenes {
                objects: scenes
                    .iter()
                    .map(|&i| desc.objects[i].name.clone())
                    .collect(),
            });
            None
        }
    };
    let mut options = SceneOptions::default();
    if let Some(w) = world {
        let o = &desc.objects[w];
        if o.parent.is_some() {
            c.errors.push(SceneError::SceneNotRoot {
                object: o.name.clone(),
            });
        }
        if let Feature::Scene(opts) = &o.feature {
            c.finite(
                || format!("scene `{}`: gravity [m/s²]", o.name),
                opts.gravity.as_slice(),
            );
            super::options::check_options(c, &o.name, opts);
            options = opts.clone();
        }
    }

    (world, options)
}

/// Every object resolved and checked, in declaration order, and which of them lost their
/// parent link to an error (an unknown parent).
pub(super) fn objects(
    c: &mut Checker,
    desc: &SceneDesc,
    names: &Names,
    materials: &HashMap<&str, SolidMaterial>,
    options: &SceneOptions,
) -> (Vec<ValidObject>, Vec<bool>) {
    let modia3d = options.modia3d_conventions;
    let lookup_material = |name: &str| {
        materials
            .get(name)
            .copied()
            .or_else(|| builtin_solid_material(name))
    };
    let mut objects = Vec::with_capacity(desc.objects.len());
    // Objects whose links were dropped because of an error already reported.
    let mut suspect = Vec::with_capacity(desc.objects.len());
    for o in &desc.objects {
        let parent = o
            .parent
            .as_ref()
            .and_then(|p| names.resolve(c, format!("object `{}`'s parent", o.name), p));
        // An unknown parent: the object may now look unconnected.
        suspect.push(o.parent.is_some() && parent.is_none());
        c.finite(
            || format!("object `{}`: translation [m]", o.name),
            o.translation.as_slice(),
        );
        let rv = o.rotation.values();
        c.finite(|| format!("object `{}`: rotation", o.name), &rv);
        let rm = o.rotation.to_matrix();
        if rv.iter().all(|v| v.is_finite()) && !rotation_is_proper(&rm) {
            c.errors.push(SceneError::InvalidValue {
                what: format!("object `{}`: rotation matrix determinant", o.name),
                value: rm.determinant(),
                expected: "1 with orthonormal columns (a proper rotation)",
            });
        }
        let pose = Isometry3::from_parts(
            Translation3::from(o.translation),
            UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(rm)),
        );
        let mut solid = None;
        let mut visual = None;
        match &o.feature {
            Feature::Solid(s) => {
                // Mesh files are read here, once, and a solid's mesh repaired; the rest of
                // validation sees the mesh.
                let loaded;
                let mut mesh_repair = None;
                // A mesh given as `Shape::Mesh` (not read from a file) is repaired too.
                let mesh = s
                    .shape
                    .clone()
                    .filter(|sh| matches!(sh, Shape::Mesh { .. }));
                let s = match s
                    .shape
                    .as_ref()
                    .and_then(|sh| load_shape(c, &o.name, sh))
                    .or(mesh)
                {
                    Some(shape) => {
                        let (shape, repair) = solid_mesh(c, &o.name, shape);
                        mesh_repair = repair;
                        loaded = crate::scene::desc::Solid {
                            shape: Some(shape),
                            ..s.clone()
                        };
                        &loaded
                    }
                    None => s,
                };
                if let Some(shape) = &s.shape {
                    check_shape(c, &o.name, shape);
                }
                let (material_name, material) = match &s.material {
                    None => (None, None),
                    Some(MaterialRef::Name(n)) => match lookup_material(n) {
                        Some(m) => (Some(n.clone()), Some(m)),
                        None => {
                            c.errors.push(SceneError::Unknown {
                                referrer: format!("solid `{}`", o.name),
                                kind: "solid material",
                                name: n.clone(),
                                hint: did_you_mean(
                                    n,
                                    materials
                                        .keys()
                                        .copied()
                                        .chain(crate::scene::materials::builtin_solid_names()),
                                ),
                            });
                            (Some(n.clone()), None)
                        }
                    },
                    Some(MaterialRef::Value(m)) => {
                        let what = |f: &str| format!("solid `{}`: material {f}", o.name);
                        c.positive(|| what("density [kg/m³]"), m.density);
                        c.positive(|| what("Young's modulus [N/m²]"), m.young_modulus);
                        c.value(
                            || what("Poisson's ratio"),
                            m.poisson_ratio,
                            m.poisson_ratio > 0.0 && m.poisson_ratio < 1.0,
                            "in (0, 1)",
                        );
                        (None, Some(*m))
                    }
                };
                if let Some(r) = s.smoothing_radius {
                    c.non_negative(|| format!("solid `{}`: smoothing radius [m]", o.name), r);
                }
                if let Some(h) = s.layer_depth {
                    c.positive(|| format!("solid `{}`: layer depth [m]", o.name), h);
                }
                let mass = solid_mass(c, &o.name, s, material.as_ref(), modia3d);
                check_mass_range(c, &o.name, s, material.as_ref(), mass.mass);
                let contact_material = s.contact_material.clone().or(material_name.clone());
                let mut contact_elasticity = None;
                if s.collision {
                    if s.shape.is_none() {
                        c.errors.push(SceneError::CollisionWithoutShape {
                            object: o.name.clone(),
                        });
                    }
                    let by_contact_material = s
                        .contact_material
                        .as_deref()
                        .map(|n| (n, lookup_material(n)));
                    contact_elasticity = match by_contact_material {
                        // Modia3D reads E and ν from the solid material its contact material
                        // names.
                        Some((n, None)) if modia3d => {
                            c.errors.push(SceneError::Unknown {
                                referrer: format!(
                                    "solid `{}`'s contact material (with Modia3D conventions it names the solid material that gives the contact stiffness)",
                                    o.name
                                ),
                                kind: "solid material",
                                name: n.to_string(),
                                hint: did_you_mean(
                                    n,
                                    materials
                                        .keys()
                                        .copied()
                                        .chain(crate::scene::materials::builtin_solid_names()),
                                ),
                            });
                            material
                        }
                        Some((_, Some(m))) if modia3d => Some(m),
                        _ => material.or_else(|| by_contact_material.and_then(|(_, m)| m)),
                    };
                    if contact_elasticity.is_none() || contact_material.is_none() {
                        c.errors.push(SceneError::CollisionWithoutMaterial {
                            object: o.name.clone(),
                        });
                    }
                }
                solid = Some(ValidSolid {
                    shape: s.shape.clone(),
                    material_name,
                    material,
                    mass,
                    collision: s.collision,
                    contact_material,
                    smoothing_radius: s.smoothing_radius,
                    layer_depth: s.layer_depth,
                    contact_elasticity,
                    mesh_repair,
                });
            }
            Feature::Visual(shape) => {
                let shape = load_shape(c, &o.name, shape).unwrap_or_else(|| shape.clone());
                check_shape(c, &o.name, &shape);
                visual = Some(shape);
            }
            Feature::None | Feature::Scene(_) => {}
        }
        objects.push(ValidObject {
            name: o.name.clone(),
            parent,
            pose,
            solid,
            visual,
        });
    }

    (objects, suspect)
}

fn rotation_is_proper(m: &Matrix3<f64>) -> bool {
    (m.transpose() * m - Matrix3::identity()).norm() < 1e-9 && (m.determinant() - 1.0).abs() < 1e-9
}

/// A [`Shape::FileMesh`] read into a [`Shape::Mesh`] (`None` for other shapes, and after an
/// error, which is reported).
fn load_shape(c: &mut Checker, object: &str, shape: &Shape) -> Option<Shape> {
    // A bad scale is reported by `check_shape` on the unloaded shape.
    let Shape::FileMesh { scale, .. } = shape else {
        return None;
    };
    if !scale.iter().all(|s| s.is_finite() && *s > 0.0) {
        return None;
    }
    match shape.load() {
        Ok(s) => Some(s),
        Err(error) => {
            c.errors.push(SceneError::Mesh {
                object: object.into(),
                error,
            });
            None
        }
    }
}

/// A solid's loaded mesh repaired for its mass properties
/// ([`repair_mesh`](crate::geometry::repair_mesh)), and what was repaired (if anything: also
/// traced, and a `SimWarning::MeshRepaired` of every run). A solid's mesh must bound a volume
/// (a visual's need not): what cannot be repaired is an error. Other shapes pass unchanged.
fn solid_mesh(
    c: &mut Checker,
    object: &str,
    shape: Shape,
) -> (Shape, Option<crate::geometry::MeshRepair>) {
    let Shape::Mesh { mesh, collision } = &shape else {
        return (shape, None);
    };
    let repaired = crate::geometry::repair_mesh(mesh).and_then(|(mesh, repair)| {
        crate::geometry::mesh_mass_properties(&mesh)?;
        Ok((mesh, repair))
    });
    match repaired {
        Ok((mesh, repair)) => {
            let repair = repair.changed().then(|| {
                tracing::warn!("solid `{object}`: {repair}");
                repair
            });
            let shape = Shape::Mesh {
                mesh: std::sync::Arc::new(mesh),
                collision: *collision,
            };
            (shape, repair)
        }
        Err(error) => {
            c.errors.push(SceneError::Mesh {
                object: object.into(),
                error,
            });
            (shape, None)
        }
    }
}

fn check_shape(c: &mut Checker, object: &str, shape: &Shape) {
    let kind = shape.kind();
    for (name, v) in shape.dimensions() {
        c.positive(|| format!("object `{object}`: {kind:?} {name} [m]"), v);
    }
    for (name, v) in shape.non_negative_lengths() {
        c.non_negative(|| format!("object `{object}`: {kind:?} {name} [m]"), v);
    }
    // Points given for a convex hull (a mesh is checked when it is read and repaired:
    // `load_shape`, `solid_mesh`).
    if let Some(points) = shape.hull_points() {
        let flat: Vec<f64> = points
            .iter()
            .flat_map(|p| p.coords.iter().copied())
            .collect();
        c.finite(|| format!("object `{object}`: {kind:?} points [m]"), &flat);
        if flat.iter().all(|v| v.is_finite()) && shape.unit_mass_properties().is_none() {
            c.errors.push(SceneError::InvalidValue {
                what: format!("object `{object}`: {kind:?} volume [m³]"),
                value: 0.0,
                expected: "> 0 (at least 4 points not in one plane)",
            });
        }
    }
}

/// Range of a solid's mass \[kg\]: far beyond any body the contact laws are meant for (a
/// 1e-20 kg steel sphere is 13 nm across; 1e20 kg is a small moon), and far enough from f64's
/// limits that `m·r²` of the inertia and `f/m` of the accelerations neither underflow nor
/// overflow (a 1e-300 kg body passed the positivity check and ended as `IDA_ILL_INPUT`).
pub(crate) const MASS_RANGE: (f64, f64) = (1e-20, 1e20);

/// The mass of a solid (given or density × volume) within [`MASS_RANGE`]; a mass that is not
/// positive and finite was reported by [`solid_mass`] already.
fn check_mass_range(
    c: &mut Checker,
    object: &str,
    s: &crate::scene::desc::Solid,
    material: Option<&SolidMaterial>,
    mass: f64,
) {
    let (lo, hi) = MASS_RANGE;
    if !(mass.is_finite() && mass > 0.0) || (lo..=hi).contains(&mass) {
        return;
    }
    let what = match (&s.mass_properties, material) {
        (MassSpec::FromShapeAndDensity, Some(m)) => format!(
            "solid `{object}`: mass [kg] from density {:e} kg/m³ × volume",
            m.density
        ),
        _ => format!("solid `{object}`: mass [kg]"),
    };
    c.errors.push(SceneError::InvalidValue {
        what,
        value: mass,
        expected: "in [1e-20, 1e20] kg (a rigid body from 13 nm of steel to a small moon)",
    });
}

fn solid_mass(
    c: &mut Checker,
    object: &str,
    s: &crate::scene::desc::Solid,
    material: Option<&SolidMaterial>,
    modia3d_conventions: bool,
) -> MassProps {
    let zero = MassProps {
        mass: 0.0,
        com: Vector3::zeros(),
        inertia: Matrix3::zeros(),
    };
    let unit = || s.shape.as_ref().and_then(|sh| sh.unit_mass_properties());
    match &s.mass_properties {
        MassSpec::FromShapeAndDensity => {
            let Some(m) = material else {
                c.errors.push(SceneError::NoMassSource {
                    object: object.into(),
                    reason:
                        "mass from density needs a solid material; set `material` or give a mass",
                });
                return zero;
            };
            if s.shape.is_none() {
                c.errors.push(SceneError::NoMassSource {
                    object: object.into(),
                    reason: "mass from density needs a shape; set `shape` or give explicit mass properties",
                });
                return zero;
            }
            match unit() {
                Some(u) => MassProps {
                    mass: m.density * u.volume,
                    com: u.com,
                    inertia: u.inertia * m.density,
                },
                None => zero, // degenerate hull: reported by check_shape
            }
        }
        MassSpec::Mass(mass) if modia3d_conventions => {
            c.positive(|| format!("solid `{object}`: mass [kg]"), *mass);
            MassProps {
                mass: *mass,
                ..zero
            }
        }
        MassSpec::FromShapeAndMass(mass) | MassSpec::Mass(mass) => {
            c.positive(|| format!("solid `{object}`: mass [kg]"), *mass);
            if s.shape.is_none() {
                c.errors.push(SceneError::NoMassSource {
                    object: object.into(),
                    reason: "inertia from mass needs a shape; set `shape` or give explicit mass properties",
                });
                return zero;
            }
            match unit() {
                Some(u) if u.volume > 0.0 && u.volume.is_finite() => MassProps {
                    mass: *mass,
                    com: u.com,
                    inertia: u.inertia * (*mass / u.volume),
                },
                _ => zero,
            }
        }
        MassSpec::Explicit { mass, com, inertia } => {
            c.positive(|| format!("solid `{object}`: mass [kg]"), *mass);
            c.finite(
                || format!("solid `{object}`: centre of mass [m]"),
                com.as_slice(),
            );
            c.finite(
                || format!("solid `{object}`: inertia [kg·m²]"),
                inertia.as_slice(),
            );
            if inertia.iter().all(|v| v.is_finite()) {
                let sym = (inertia - inertia.transpose()).norm() <= 1e-12 * inertia.norm();
                let ev = inertia.symmetric_eigenvalues();
                let (a, b, cc) = (ev[0], ev[1], ev[2]);
                let tol = 1e-12 * ev.abs().max();
                let triangle = a + b >= cc - tol && a + cc >= b - tol && b + cc >= a - tol;
                if !sym || ev.min() < -tol || !triangle {
                    c.errors.push(SceneError::InvalidValue {
                        what: format!(
                            "solid `{object}`: smallest principal inertia [kg·m²]"
                        ),
                        value: ev.min(),
                        expected: "a symmetric, positive semi-definite tensor whose principal moments satisfy the triangle inequality",
                    });
                }
            }
            MassProps {
                mass: *mass,
                com: *com,
                inertia: *inertia,
            }
        }
    }
}
