//! The Beam and FileMesh shapes (issue 13): mass properties against closed forms and an
//! independent integration, support maps against parry, and bodies of these shapes resting on
//! a table (the contact forces carry the weight).

use modia3d::core::geometry::{CollisionShape, Shape};
use modia3d::demo::{fixed_box, world};
use modia3d::prelude::*;
use nalgebra::{Matrix3, Point3};
use std::f64::consts::PI;

const G: f64 = 9.81;

/// Volume and second moments `∫ x xᵀ dV` about the origin of the solid bounded by the closed,
/// outward triangle mesh `tris` (divergence theorem: a sum of signed tetrahedra with the
/// origin). Written here independently of the library's mesh integrator.
fn tet_moments(tris: &[[Point3<f64>; 3]]) -> (f64, Matrix3<f64>) {
    let (mut v, mut c) = (0.0, Matrix3::zeros());
    for [a, b, d] in tris {
        let (a, b, d) = (a.coords, b.coords, d.coords);
        let vol = a.dot(&b.cross(&d)) / 6.0;
        let s = a + b + d;
        v += vol;
        c += (a * a.transpose() + b * b.transpose() + d * d.transpose() + s * s.transpose())
            * (vol / 20.0);
    }
    (v, c)
}

/// The outward triangles of a prism: the convex polygon `poly` (counter-clockwise in the
/// (u, w) plane) extruded over `−t/2 ≤ s ≤ t/2`, with coordinates placed as (u, w, s) → x, y, z.
fn prism(poly: &[(f64, f64)], t: f64) -> Vec<[Point3<f64>; 3]> {
    let p = |(u, w): (f64, f64), s: f64| Point3::new(u, w, s);
    let h = t / 2.0;
    let n = poly.len();
    let mut out = vec![];
    for i in 1..n - 1 {
        out.push([p(poly[0], h), p(poly[i], h), p(poly[i + 1], h)]);
        out.push([p(poly[0], -h), p(poly[i + 1], -h), p(poly[i], -h)]);
    }
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        out.push([p(a, -h), p(b, -h), p(b, h)]);
        out.push([p(a, -h), p(b, h), p(a, h)]);
    }
    out
}

/// A stadium (straight part `l`, radius `r`) as a polygon with `n` chords per half-disk:
/// vertices on the circle (`scale = 1`, inscribed) or on the circle of radius `r / cos(π/2n)`
/// (`scale = 1/cos`, its chords tangent to the circle: circumscribed).
fn stadium(l: f64, r: f64, n: usize, circumscribed: bool) -> Vec<(f64, f64)> {
    let rr = if circumscribed {
        r / (PI / (2.0 * n as f64)).cos()
    } else {
        r
    };
    let mut poly = vec![];
    for (sign, c) in [(1.0, l / 2.0), (-1.0, -l / 2.0)] {
        // Inscribed: vertices at φ = −π/2 + kπ/n. Circumscribed: the half-angle offset puts the
        // tangent chords' corners at φ = −π/2 + (k + ½)π/n, plus the two tangent points at ±π/2.
        let angles: Vec<f64> = if circumscribed {
            std::iter::once(-PI / 2.0)
                .chain((0..n).map(|k| -PI / 2.0 + (k as f64 + 0.5) * PI / n as f64))
                .chain(std::iter::once(PI / 2.0))
                .collect()
        } else {
            (0..=n)
                .map(|k| -PI / 2.0 + k as f64 * PI / n as f64)
                .collect()
        };
        for phi in angles {
            // The ±π/2 points of a circumscribed end lie on the circle (tangent points).
            let rad = if circumscribed && (phi.abs() - PI / 2.0).abs() < 1e-15 {
                r
            } else {
                rr
            };
            poly.push((c + sign * rad * phi.cos(), sign * rad * phi.sin()));
        }
    }
    poly
}

/// Beam mass properties: (1) the second moments of the exact beam lie between those of an
/// inscribed and a circumscribed polygonal beam (set inclusion: `∫x_i² dV` and `V` grow with
/// the set), integrated by the divergence theorem; the bracket is 2e-6 wide with 4096 chords,
/// so an error of the closed form's `l·4r/(3π)` shift term (1e-1 relative) or of a factor in
/// any term would show. (2) The closed form in its own expression (`V = lwt + πr²t`, `I` from
/// the second moments) to 1e-12, for each axis (the directions cyclic as in Modia3D).
#[test]
fn beam_mass_properties_closed_form_and_bracketed_by_polygons() {
    let (l, w, t) = (0.7, 0.3, 0.11);
    let r = w / 2.0;
    let beam = Shape::Beam {
        axis: Axis::X,
        length: l,
        width: w,
        thickness: t,
    };
    let p = beam.unit_mass_properties().unwrap();
    let n = 4096;
    let (v_in, c_in) = tet_moments(&prism(&stadium(l, r, n, false), t));
    let (v_out, c_out) = tet_moments(&prism(&stadium(l, r, n, true), t));
    // Second moments of the beam from its inertia: S = tr(I)/2 − I on the diagonal.
    let tr = p.inertia.trace() / 2.0;
    let s = [
        tr - p.inertia[(0, 0)],
        tr - p.inertia[(1, 1)],
        tr - p.inertia[(2, 2)],
    ];
    println!("V: {} <= {} <= {}", v_in, p.volume, v_out);
    assert!(v_in <= p.volume && p.volume <= v_out);
    assert!((v_out - v_in) / p.volume < 5e-6);
    for i in 0..3 {
        println!("S{i}: {} <= {} <= {}", c_in[(i, i)], s[i], c_out[(i, i)]);
        assert!(c_in[(i, i)] <= s[i] * (1.0 + 1e-14) && s[i] <= c_out[(i, i)] * (1.0 + 1e-14));
        assert!((c_out[(i, i)] - c_in[(i, i)]) / s[i] < 5e-6);
    }
    // Closed form, written out once more: box + full cylinder volume; second moments per part.
    let vol = l * w * t + PI * r * r * t;
    let s_u = l * w * t * l * l / 12.0
        + PI * r * r * t * (l * l / 4.0 + r * r / 4.0)
        + 4.0 / 3.0 * l * r.powi(3) * t;
    let s_w = l * w * t * w * w / 12.0 + PI * r * r * t * r * r / 4.0;
    let s_t = vol * t * t / 12.0;
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs();
    assert!(close(p.volume, vol));
    for (axis, [iu, iw, it]) in [
        (Axis::X, [0, 1, 2]),
        (Axis::Y, [1, 2, 0]),
        (Axis::Z, [2, 0, 1]),
    ] {
        let q = Shape::Beam {
            axis,
            length: l,
            width: w,
            thickness: t,
        }
        .unit_mass_properties()
        .unwrap();
        assert!(close(q.inertia[(iu, iu)], s_w + s_t), "{axis:?}");
        assert!(close(q.inertia[(iw, iw)], s_u + s_t), "{axis:?}");
        assert!(close(q.inertia[(it, it)], s_u + s_w), "{axis:?}");
    }
}

/// The beam's support map (with and without smoothing) against parry: the support function
/// `h(d) = max d·x` of parry's `RoundConvexPolyhedron` over points sampled on the core's
/// stadium ends (inscribed, `n` chords per end) and rounded by the smoothing radius. Inscribed
/// polygons give `h_parry ≤ h ≤ h_parry + ρ(1 − cos(π/2n))` with `ρ` the core's end radius;
/// checked over 2000 directions.
#[test]
fn beam_support_map_matches_parry() {
    use parry3d_f64::shape::{RoundConvexPolyhedron, SupportMap};
    let (l, w, t) = (0.5, 0.2, 0.08);
    for (axis, smoothing) in [(Axis::X, 0.0), (Axis::Y, 0.004), (Axis::Z, 0.01)] {
        let shape = Shape::Beam {
            axis,
            length: l,
            width: w,
            thickness: t,
        };
        let cs = CollisionShape::with_smoothing(&shape, smoothing).unwrap();
        let rs = cs.smoothing_radius();
        assert_eq!(rs, smoothing.min(0.1 * t));
        let (k, (kw, kt)) = (axis.index(), axis.beam_directions());
        let rho = w / 2.0 - rs;
        let n = 256;
        let mut pts = vec![];
        for (u, w) in stadium(l, rho, n, false) {
            for s in [-1.0, 1.0] {
                let mut p = Point3::origin();
                p[k] = u;
                p[kw] = w;
                p[kt] = s * (t / 2.0 - rs);
                pts.push(p);
            }
        }
        let parry = RoundConvexPolyhedron {
            inner_shape: parry3d_f64::shape::ConvexPolyhedron::from_convex_hull(&pts).unwrap(),
            border_radius: rs,
        };
        let sag = rho * (1.0 - (PI / (2.0 * n as f64)).cos());
        let mut worst: f64 = 0.0;
        for i in 0..2000 {
            // Fibonacci sphere directions.
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / 2000.0;
            let phi = i as f64 * PI * (3.0 - 5f64.sqrt());
            let d = Vector3::new(
                (1.0 - z * z).sqrt() * phi.cos(),
                (1.0 - z * z).sqrt() * phi.sin(),
                z,
            );
            let h = d.dot(&cs.support(&d).coords);
            let hp = d.dot(&parry.local_support_point(&d).coords);
            assert!(
                h >= hp - 1e-12 && h <= hp + sag + 1e-12,
                "{axis:?}: h = {h}, parry {hp}, sagitta {sag}"
            );
            worst = worst.max(h - hp);
        }
        println!("{axis:?}, r_s = {rs}: max h − h_parry = {worst:.3e} (sagitta {sag:.3e})");
    }
}

/// A scene with a table (top face at z = 0) and one free body `body` of `solid` at `r`.
fn on_table(solid: Solid, r: [f64; 3]) -> SceneDesc {
    let mut s = SceneDesc::new();
    s.add(world(SceneOptions {
        k_red: 1e-3,
        ..Default::default()
    }))
    .add(fixed_box(
        "table",
        [2.0, 2.0, 0.1],
        [0.0, 0.0, -0.05],
        "DryWood",
    ))
    .add(Object3D::new("body").solid(solid.material("DryWood").collision(true)))
    .add_joint(Joint::new(
        "body.free",
        "world",
        "body",
        JointKind::FreeMotion {
            r: Vector3::from(r),
            rot: FreeRotation::Cardan([0.0; 3]),
            v: Vector3::zeros(),
            w: Vector3::zeros(),
        },
    ));
    s
}

/// Runs `scene` for `t_end` s with contact results and returns the weight of the body [N] and
/// the vertical contact force on it summed over `pairs` (`"table|…"` names) at the end [N].
fn settle(scene: SceneDesc, t_end: f64) -> (SimulationResult, f64) {
    let model = scene.build().unwrap();
    let mass: f64 = model.bodies().iter().map(|b| b.mass).sum();
    let opts = SimOptions::new(t_end)
        .tolerance(1e-8)
        .interval(1e-2)
        .contact_results(true)
        .progress(false);
    let res = model.simulate(&opts).unwrap();
    (res, mass * G)
}

/// The vertical force of pair `pair` on its second object at the last output point [N].
fn vertical_force(res: &SimulationResult, pair: &str) -> f64 {
    let f_n = res.signal(&format!("{pair}.f_n")).unwrap().last().unwrap()[0];
    let n = res.signal(&format!("{pair}.normal")).unwrap();
    f_n * n.last().unwrap()[2]
}

/// A beam lying on its flat face comes to rest; the normal force carries its weight to 1e-6
/// (the residual acceleration after 1 s of damped settling at rtol 1e-8 is far below that).
#[test]
fn beam_rests_on_table_and_contact_carries_its_weight() {
    let (l, w, t) = (0.3, 0.1, 0.04);
    let beam = Shape::Beam {
        axis: Axis::X,
        length: l,
        width: w,
        thickness: t,
    };
    let (res, weight) = settle(on_table(Solid::new(beam), [0.0, 0.0, t / 2.0 + 1e-4]), 1.0);
    let f = vertical_force(&res, "table|body");
    let z = res.signal("body.r_abs[2]").unwrap().last().unwrap()[0];
    println!("weight {weight} N, contact {f} N, z = {z} m");
    assert!((f - weight).abs() < 1e-6 * weight, "{f} vs {weight}");
    // It rests on its flat face (thickness along z): centre t/2 above the table, less the
    // micrometre penetration.
    assert!((z - t / 2.0).abs() < 1e-5, "z = {z}");
}
