//! Closed kinematic loops against independent references: Freudenstein's equation of the
//! four-bar, energy conservation, constraint residuals. Every tolerance is argued where it is
//! asserted.

use modia3d::prelude::*;

mod energy;
use energy::{energy, Part};

#[allow(dead_code)] // the model type and the closed form are used, not the example's main
#[path = "../examples/four_bar.rs"]
mod four_bar;
use four_bar::{freudenstein, FourBar};

/// The crank driven at 2π rad/s for one revolution: the rocker angle equals Freudenstein's
/// closed form at the simulated crank angle. The crank coordinate is prescribed, so it is the
/// independent coordinate; the rocker angle is then fixed by the constraints alone, which the
/// stabilised formulation holds to the Newton tolerance of each step (~rtol · atol-scale ≈
/// 1e-12 rad here) plus the interpolation error of output points inside a step (the local
/// error, ≤ ~1e-10 at rtol 1e-10); 1e-9 rad leaves a factor ten.
#[test]
fn driven_four_bar_follows_freudenstein() {
    let fb = FourBar::default();
    let model = fb.build().unwrap();
    let loops = model.loops();
    assert_eq!(loops.len(), 1, "{loops:?}");
    assert_eq!(loops[0].cut, "loop_joint");
    // A planar loop of spatial revolutes: 5 rows of rank 2 (x, y kept; z, two tilts dropped).
    assert_eq!(loops[0].rows, 2, "{loops:?}");
    assert_eq!(loops[0].dropped.len(), 3, "{loops:?}");
    assert_eq!(model.independent_coordinates(), vec!["crank_joint.phi"]);
    let res = model
        .simulate(&SimOptions::new(1.0).tolerance(1e-10).interval(0.005))
        .unwrap();
    let theta2 = res.signal("crank_joint.phi").unwrap().values();
    let theta4 = res.signal("rocker_joint.phi").unwrap().values();
    assert!(
        theta2.last().unwrap() - theta2[0] > 2.0 * std::f64::consts::PI - 1e-9,
        "a full revolution"
    );
    let worst = theta2
        .iter()
        .zip(&theta4)
        .map(|(t2, t4)| (freudenstein(fb.a, fb.b, fb.c, fb.d, *t2) - t4).abs())
        .fold(0.0, f64::max);
    eprintln!("worst {worst:e} steps {}", res.stats.solver.steps);
    assert!(worst <= 1e-9, "max |θ4 − θ4_Freudenstein| = {worst:e} rad");
}

/// The four-bar without its drive (the input removed), swinging under gravity (−y) from the
/// example's initial state. Bars are steel boxes `l × w × w` (8000 kg/m³) whose centres are the
/// `*_bar` objects.
fn free_four_bar() -> (Model, Vec<Part<'static>>) {
    let fb = FourBar::default();
    let mut scene = fb.scene();
    scene.inputs.clear();
    let bar = |name, l: f64| {
        let m = 8000.0 * l * fb.w * fb.w;
        let (side, end) = (m * (fb.w * fb.w + l * l) / 12.0, m * fb.w * fb.w / 6.0);
        (
            name,
            m,
            Matrix3::from_diagonal(&Vector3::new(end, side, side)),
        )
    };
    let parts = vec![
        bar("crank_bar", fb.a),
        bar("coupler_bar", fb.b),
        bar("rocker_bar", fb.c),
    ];
    (scene.build().unwrap(), parts)
}

/// Free under gravity, the linkage conserves its energy: the constraint forces do no work
/// (they act at coincident points with equal and opposite velocities), so any change is
/// integration error. Scale: the largest energy of the run (0.64 J). BDF dissipates slowly and
/// steadily: at rtol 1e-10 the drift grows about linearly, measured 2.5e-9 J after 1 s,
/// 2.6e-9 J after 2 s (the crank's first two turns), 7e-9 J after 5 s; over 2 s 1e-8 of the
/// scale (6.4e-9 J) leaves a factor two, while a wrong constraint force (power λ·G v ≠ 0) or a
/// wrong inertia term changes it by orders of magnitude more.
#[test]
fn free_four_bar_conserves_energy() {
    let (model, parts) = free_four_bar();
    let res = model
        .simulate(&SimOptions::new(2.0).tolerance(1e-10).interval(0.01))
        .unwrap();
    let e = energy(&res, &parts, Vector3::new(0.0, -9.81, 0.0));
    let scale = e.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let drift = e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max);
    eprintln!(
        "energy scale {scale:e} J, drift {drift:e} J, steps {}",
        res.stats.solver.steps
    );
    assert!(
        drift <= 1e-8 * scale,
        "energy drift {drift:e} J of {scale:e} J"
    );
}
