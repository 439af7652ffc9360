//! The comparator's scenes, each defined once for both sides (docs/rapier-comparison.md gives
//! the physics, the references and the error measures).

use crate::rapier_side::{self, Samples, Setting};
use crate::{median_of, rapier_settings, rtols, Point, RUNS};
use modia3d::demo;
use modia3d::prelude::*;
use std::time::Instant;

type BoxError = Box<dyn std::error::Error>;

/// A scene: its name, one line about it, and the two ladders.
pub struct Scene {
    pub name: &'static str,
    pub about: &'static str,
    pub modia: Box<dyn Fn() -> Result<Vec<Point>, BoxError>>,
    pub rapier: Box<dyn Fn() -> Result<Vec<Point>, BoxError>>,
}

/// Gravity [m/s²] (modia3d's default, −z; Rapier's worlds here use the same).
const G: f64 = 9.81;

fn steel_density() -> f64 {
    modia3d::core::scene::builtin_solid_material("Steel")
        .map(|m| m.density)
        .unwrap_or(7800.0)
}

/// Runs `model` at `rtol` `RUNS` times (wall of `simulate` alone) and measures the last run
/// with `measure`, which returns (error, note); a failed run is an infinite error.
fn modia_point(
    model: &Model,
    label: String,
    opts: SimOptions,
    measure: &dyn Fn(&SimulationResult) -> (f64, String),
) -> Point {
    median_of(label, RUNS, || {
        let t0 = Instant::now();
        let res = model.simulate(&opts);
        let wall = t0.elapsed().as_secs_f64();
        match res {
            Ok(res) => {
                let (e, note) = measure(&res);
                let s = res.stats.solver;
                (
                    wall,
                    e,
                    format!(
                        "{} steps, {} residuals, {} events{}",
                        s.steps,
                        s.residual_evals,
                        res.stats.events,
                        if note.is_empty() {
                            String::new()
                        } else {
                            format!("; {note}")
                        }
                    ),
                )
            }
            Err(e) => (wall, f64::INFINITY, format!("failed: {e}")),
        }
    })
}

fn options(stop: f64, rtol: f64) -> SimOptions {
    SimOptions::new(stop)
        .tolerance(rtol)
        .interval(stop / 100.0)
        .progress(false)
}

fn last3(res: &SimulationResult, signal: &str) -> [f64; 3] {
    res.signal(signal)
        .ok()
        .and_then(|s| s.last().map(|v| [v[0], v[1], v[2]]))
        .unwrap_or([f64::NAN; 3])
}

// ---------------------------------------------------------------------------------------------
// One ball on a plate: bounce (cor 0.9) and steel drop (cor 0.7)

/// Ball diameter \[m\] of the bounce and drop scenes.
const BALL_D: f64 = 0.1;
/// Drop height \[m\]: the ball's lowest point starts this far above the plate.
const DROP_H: f64 = 0.5;

/// modia3d: a steel ball (Ø `BALL_D`) dropped from `DROP_H` onto a fixed steel plate
/// (1 × 1 × 0.1 m, top face at z = 0), Steel–Steel pair `cor`, no friction, exact restitution.
fn modia_drop(cor: f64, exact: bool) -> SceneDesc {
    demo::steel_drop(BALL_D, DROP_H, cor, exact)
}

/// One flight between two contacts, as the engine computed it.
#[derive(Clone, Copy, Debug, Default)]
struct Bounce {
    /// Time the ball touched the plate \[s\].
    hit: f64,
    /// Upward speed when it left [m/s].
    rebound: f64,
    /// Height of the following apex above the touching height \[m\] (NaN if after the stop).
    apex: f64,
}

/// The bounces of a modia3d run: contact start and end from the events (exact root times),
/// the speed at the end from the state there, the apex where that speed has decayed to zero
/// (`t_e + v/g`), its height from IDA's own polynomial (dense output).
fn modia_bounces(res: &SimulationResult) -> Vec<Bounce> {
    let starts: Vec<f64> = res
        .events
        .iter()
        .filter(|e| !e.started.is_empty())
        .map(|e| e.t)
        .collect();
    let ends: Vec<f64> = res
        .events
        .iter()
        .filter(|e| !e.ended.is_empty())
        .map(|e| e.t)
        .collect();
    let stop = res.time().last().copied().unwrap_or(0.0);
    starts
        .iter()
        .zip(&ends)
        .map(|(&hit, &leave)| {
            let rebound = res
                .signal_at("ball.v_abs", leave)
                .map(|v| v[2])
                .unwrap_or(f64::NAN);
            let ta = leave + rebound / G;
            let apex = if ta < stop {
                res.signal_at("ball.r_abs", ta)
                    .map(|r| r[2] - BALL_D / 2.0)
                    .unwrap_or(f64::NAN)
            } else {
                f64::NAN
            };
            Bounce { hit, rebound, apex }
        })
        .collect()
}

/// The parabola through three samples `(t_k, z_k)`, as `(a, b, c)` of `a + b s + c s²` with
/// `s = t − t_1` (the middle sample).
fn parabola(t: [f64; 3], z: [f64; 3]) -> (f64, f64, f64) {
    let (s0, s2) = (t[0] - t[1], t[2] - t[1]);
    // z0 = a + b s0 + c s0², z1 = a, z2 = a + b s2 + c s2².
    let a = z[1];
    let (d0, d2) = (z[0] - a, z[2] - a);
    let c = (d0 / s0 - d2 / s2) / (s0 - s2);
    let b = d0 / s0 - c * s0;
    (a, b, c)
}

/// The bounces of a Rapier run from its samples: a bounce is a step where the vertical
/// velocity turns from downward to upward. The free flights on both sides are exact parabolas
/// of the engine's steps (symplectic Euler under constant gravity), so the parabola through the
/// last three samples before gives the touching time (its later crossing of the touching
/// height), the one through the first three after gives the leaving time and the rebound speed
/// (its earlier crossing and slope there), and the one through the samples around the highest
/// point the apex. A flight with fewer than three samples ends the list.
fn rapier_bounces(s: &Samples, r: f64) -> Vec<Bounce> {
    let vz: Vec<f64> = s.v.iter().map(|v| v[2]).collect();
    let z: Vec<f64> = s.r.iter().map(|p| p[2] - r).collect();
    let sample3 = |k: usize| ([s.t[k - 1], s.t[k], s.t[k + 1]], [z[k - 1], z[k], z[k + 1]]);
    let mut out = vec![];
    let mut k = 1;
    while k < vz.len() {
        // k: first sample moving up after one moving down.
        if !(vz[k - 1] < 0.0 && vz[k] > 0.0) {
            k += 1;
            continue;
        }
        // Before: samples k-3, k-2, k-1 (all falling).
        if k < 3 || vz[k - 3..k].iter().any(|&v| v >= 0.0) {
            break;
        }
        let (t, zz) = sample3(k - 2);
        let (a, b, c) = parabola(t, zz);
        let hit = t[1] + crossing(a, b, c, true);
        // After: k, k+1, k+2 rising; apex: around the first sample after which vz ≤ 0.
        if k + 2 >= vz.len() || vz[k..k + 3].iter().any(|&v| v <= 0.0) {
            break;
        }
        let (t, zz) = sample3(k + 1);
        let (a, b, c) = parabola(t, zz);
        let sl = crossing(a, b, c, false);
        let rebound = b + 2.0 * c * sl;
        let mut j = k + 1;
        while j + 1 < vz.len() && vz[j] > 0.0 {
            j += 1;
        }
        // Highest sample m (the last rising or the first falling one), parabola around it.
        let m = if j >= 1 && z[j - 1] > z[j] { j - 1 } else { j };
        let apex = if m >= 1 && m + 1 < z.len() {
            let (t, zz) = sample3(m);
            let (a, b, c) = parabola(t, zz);
            a - b * b / (4.0 * c)
        } else {
            f64::NAN
        };
        out.push(Bounce { hit, rebound, apex });
        k = j.max(k + 1);
    }
    out
}

/// The root `s` of `a + b s + c s² = 0` (a falling parabola, `c < 0`): the later one when
/// `later`, else the earlier.
fn crossing(a: f64, b: f64, c: f64, later: bool) -> f64 {
    let disc = (b * b - 4.0 * a * c).max(0.0).sqrt();
    let (r1, r2) = ((-b + disc) / (2.0 * c), (-b - disc) / (2.0 * c));
    let (lo, hi) = if r1 < r2 { (r1, r2) } else { (r2, r1) };
    if later {
        hi
    } else {
        lo
    }
}

/// Apex error of the bounce scene: max over the first `N_APEX` bounces of
/// |apex_n/h − cor^(2n)|; infinite when fewer were found.
const N_APEX: usize = 5;
const BOUNCE_COR: f64 = 0.9;
const BOUNCE_STOP: f64 = 2.6;

fn apex_error(b: &[Bounce]) -> (f64, String) {
    if b.len() < N_APEX || b[..N_APEX].iter().any(|x| !x.apex.is_finite()) {
        return (f64::INFINITY, format!("{} apexes found", b.len()));
    }
    let errs: Vec<f64> = (1..=N_APEX)
        .map(|n| (b[n - 1].apex / DROP_H - BOUNCE_COR.powi(2 * n as i32)).abs())
        .collect();
    let e = errs.iter().copied().fold(0.0, f64::max);
    (
        e,
        format!(
            "apex errors {}",
            errs.iter()
                .map(|x| format!("{x:.1e}"))
                .collect::<Vec<_>>()
                .join(" ")
        ),
    )
}

const DROP_COR: f64 = 0.7;
const DROP_STOP: f64 = 0.85;

/// Steel-drop error: first impact time, rebound speed and second impact time against the
/// rigid limit, the largest relative error.
fn drop_error(b: &[Bounce]) -> (f64, String) {
    if b.len() < 2 {
        return (f64::INFINITY, format!("{} impacts found", b.len()));
    }
    let v0 = (2.0 * G * DROP_H).sqrt();
    let t1 = v0 / G;
    let v1 = DROP_COR * v0;
    let t2 = t1 + 2.0 * v1 / G;
    let e = [
        (b[0].hit - t1).abs() / t1,
        (b[0].rebound - v1).abs() / v1,
        (b[1].hit - t2).abs() / t2,
    ];
    (
        e.iter().copied().fold(0.0, f64::max),
        format!("t1 {:.1e}, v1 {:.1e}, t2 {:.1e}", e[0], e[1], e[2]),
    )
}

fn drop_scene(
    name: &'static str,
    about: &'static str,
    cor: f64,
    stop: f64,
    error: fn(&[Bounce]) -> (f64, String),
) -> Scene {
    Scene {
        name,
        about,
        modia: Box::new(move || {
            let model = modia_drop(cor, true).build()?;
            let mut pts: Vec<Point> = rtols()
                .into_iter()
                .map(|rtol| {
                    modia_point(
                        &model,
                        format!("rtol {rtol:.0e}"),
                        options(stop, rtol).dense_output(true),
                        &|res| error(&modia_bounces(res)),
                    )
                })
                .collect();
            // The paper's damping law (exact_restitution off), for the record: not on the front.
            let paper = modia_drop(cor, false).build()?;
            for rtol in [1e-6, 1e-9] {
                pts.push(modia_point(
                    &paper,
                    format!("rtol {rtol:.0e}, paper's d (not ranked)"),
                    options(stop, rtol).dense_output(true),
                    &|res| error(&modia_bounces(res)),
                ));
            }
            Ok(pts)
        }),
        rapier: Box::new(move || {
            let rho = steel_density();
            Ok(rapier_settings()
                .into_iter()
                .map(|s| {
                    median_of(s.label(), RUNS, || {
                        let (wall, samples) = rapier_side::ball_on_plate(
                            s,
                            BALL_D,
                            rho,
                            BALL_D / 2.0 + DROP_H,
                            [0.0; 3],
                            ([0.5, 0.5, 0.05], [0.0, 0.0, -0.05]),
                            cor,
                            0.0,
                            stop,
                        );
                        let (e, n) = error(&rapier_bounces(&samples, BALL_D / 2.0));
                        (wall, e, n)
                    })
                })
                .collect())
        }),
    }
}

// ---------------------------------------------------------------------------------------------
// Slide to roll

const SLIDE_V0: f64 = 4.0;
const SLIDE_MU: f64 = 0.5;
const SLIDE_T: f64 = 0.5;

/// Relative errors of speed and position at `SLIDE_T` against the rigid analytic solution
/// (rolling from t_r = 2 v0/(7 μ g) on at 5/7 v0), the larger one.
fn slide_error(x: f64, v: f64) -> (f64, String) {
    let tr = 2.0 * SLIDE_V0 / (7.0 * SLIDE_MU * G);
    let v_ref = 5.0 / 7.0 * SLIDE_V0;
    let x_ref = SLIDE_V0 * tr - 0.5 * SLIDE_MU * G * tr * tr + v_ref * (SLIDE_T - tr);
    let (ev, ex) = ((v - v_ref).abs() / v_ref, (x - x_ref).abs() / x_ref);
    (ev.max(ex), format!("speed {ev:.1e}, position {ex:.1e}"))
}

fn slide_scene() -> Scene {
    Scene {
        name: "slide-to-roll",
        about: "Steel ball Ø 0.1 m launched at 4 m/s without spin on a steel plane, μ = 0.5; \
                error = max relative error of speed and position at t = 0.5 s against the \
                rigid solution (rolling from t_r = 2v0/(7μg) = 0.233 s at 5/7·v0).",
        modia: Box::new(|| {
            let model = demo::sliding_ball(
                BALL_D,
                SLIDE_V0,
                0.0,
                ContactPairMaterial::new(0.7, 0.5, 0.0),
            )
            .build()?;
            Ok(rtols()
                .into_iter()
                .map(|rtol| {
                    modia_point(
                        &model,
                        format!("rtol {rtol:.0e}"),
                        options(SLIDE_T, rtol),
                        &|res| {
                            slide_error(last3(res, "ball.r_abs")[0], last3(res, "ball.v_abs")[0])
                        },
                    )
                })
                .collect())
        }),
        rapier: Box::new(|| {
            let rho = steel_density();
            Ok(rapier_settings()
                .into_iter()
                .map(|s| {
                    median_of(s.label(), RUNS, || {
                        let (wall, smp) = rapier_side::ball_on_plate(
                            s,
                            BALL_D,
                            rho,
                            BALL_D / 2.0,
                            [SLIDE_V0, 0.0, 0.0],
                            ([20.0, 1.0, 0.05], [15.0, 0.0, -0.05]),
                            0.0,
                            SLIDE_MU,
                            SLIDE_T,
                        );
                        // The step count reaches SLIDE_T exactly for these dt (1/60 · 4^-k).
                        let k = smp.t.len() - 1;
                        let (e, n) = slide_error(smp.r[k][0], smp.v[k][0]);
                        (wall, e, format!("t = {:.4}; {n}", smp.t[k]))
                    })
                })
                .collect())
        }),
    }
}

// ---------------------------------------------------------------------------------------------
// Three-ball cradle

const CRADLE_D: f64 = 0.05;
const CRADLE_GAP: f64 = 1e-3;
const CRADLE_V: f64 = 0.5;
const CRADLE_T: f64 = 0.02;

fn cradle_start() -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let p = (0..3)
        .map(|k| [k as f64 * (CRADLE_D + CRADLE_GAP), 0.0, 0.0])
        .collect();
    let v = vec![[CRADLE_V, 0.0, 0.0], [0.0; 3], [0.0; 3]];
    (p, v)
}

/// max_i |v_i − v_i,ref| / v with v_ref = (0, 0, v) along the line.
fn cradle_error(v: &[[f64; 3]]) -> (f64, String) {
    let reference = [0.0, 0.0, CRADLE_V];
    let e = v
        .iter()
        .zip(reference)
        .map(|(v, r)| ((v[0] - r).powi(2) + v[1] * v[1] + v[2] * v[2]).sqrt() / CRADLE_V)
        .fold(0.0, f64::max);
    (
        e,
        format!(
            "v_x = {:.6} {:.6} {:.6}",
            v[0][0] / CRADLE_V,
            v[1][0] / CRADLE_V,
            v[2][0] / CRADLE_V
        ),
    )
}

fn cradle_scene() -> Scene {
    Scene {
        name: "cradle-3",
        about: "Three steel balls Ø 50 mm in a line 1 mm apart, no gravity, cor 1, no \
                friction; ball 1 at 0.5 m/s. Error = max_i |v_i − v_i,ref|/v at 0.02 s \
                against the rigid sequence of impacts (ball 3 leaves with v, balls 1 and 2 \
                at rest).",
        modia: Box::new(|| {
            let mut s = SceneDesc::new();
            s.add(demo::world(SceneOptions {
                gravity: Vector3::zeros(),
                exact_restitution: true,
                ..Default::default()
            }));
            let (p, v) = cradle_start();
            for k in 0..3 {
                demo::add_free_sphere(
                    &mut s,
                    &format!("b{k}"),
                    CRADLE_D,
                    "Steel",
                    None,
                    p[k],
                    v[k],
                    [0.0; 3],
                );
            }
            s.add_contact_pair("Steel", "Steel", ContactPairMaterial::new(1.0, 0.0, 0.0));
            let model = s.build()?;
            Ok(rtols()
                .into_iter()
                .map(|rtol| {
                    modia_point(
                        &model,
                        format!("rtol {rtol:.0e}"),
                        options(CRADLE_T, rtol),
                        &|res| {
                            let v: Vec<[f64; 3]> =
                                (0..3).map(|k| last3(res, &format!("b{k}.v_abs"))).collect();
                            cradle_error(&v)
                        },
                    )
                })
                .collect())
        }),
        rapier: Box::new(|| {
            let rho = steel_density();
            let (p, v) = cradle_start();
            Ok(rapier_settings()
                .into_iter()
                .map(|s| {
                    median_of(s.label(), RUNS, || {
                        let (wall, vf) =
                            rapier_side::free_balls(s, CRADLE_D, rho, &p, &v, 1.0, CRADLE_T);
                        let (e, n) = cradle_error(&vf);
                        (wall, e, n)
                    })
                })
                .collect())
        }),
    }
}

// ---------------------------------------------------------------------------------------------
// 16-ball break

const BREAK_T: f64 = 1.5;
const CUE_V: [f64; 3] = [3.0, 0.0, 0.0];

/// Rack order of `demo::billiards16`: ball k+1 is row i, place j.
fn rack_places() -> Vec<(usize, usize)> {
    (0..5).flat_map(|i| (0..=i).map(move |j| (i, j))).collect()
}

/// The mirror image partner of each ball (row i, place j ↔ place i − j); the cue ball (last)
/// is its own.
fn mirror_partner() -> Vec<usize> {
    let places = rack_places();
    let mut out: Vec<usize> = places
        .iter()
        .map(|&(i, j)| {
            places
                .iter()
                .position(|&q| q == (i, i - j))
                .unwrap_or_default()
        })
        .collect();
    out.push(places.len());
    out
}

/// Trajectory error against the reference (max over balls of |r − r_ref| \[m\]) and the
/// mirror error (max over mirror pairs of |r_a − M r_b|, M: y → −y).
fn break_error(r: &[[f64; 3]], r_ref: &[[f64; 3]]) -> (f64, String) {
    let dist = |a: [f64; 3], b: [f64; 3]| {
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    };
    let e = r
        .iter()
        .zip(r_ref)
        .map(|(a, b)| dist(*a, *b))
        .fold(0.0, f64::max);
    let m = mirror_partner()
        .iter()
        .enumerate()
        .map(|(k, &p)| dist(r[k], [r[p][0], -r[p][1], r[p][2]]))
        .fold(0.0, f64::max);
    (e, format!("mirror error {m:.1e} m"))
}

fn modia_break_positions(res: &SimulationResult) -> Vec<[f64; 3]> {
    let mut names: Vec<String> = (1..=15).map(|k| format!("ball{k}.r_abs")).collect();
    names.push("cue.r_abs".into());
    names.iter().map(|n| last3(res, n)).collect()
}

fn break_scene() -> Scene {
    Scene {
        name: "break-16",
        about: "Modia3D's 16-ball break (demo::billiards16) with the cue ball on the symmetry \
                axis at 3 m/s, 1.5 s. Error = max over balls of |r − r_ref| [m] at 1.5 s \
                against a converged run of the same side (modia3d rtol 1e-11; Rapier dt \
                1/61440, 16 iterations); the mirror error is reported beside it.",
        modia: Box::new(|| {
            let model = demo::billiards16(CUE_V, 1.0).build()?;
            let t0 = Instant::now();
            let reference = model.simulate(&options(BREAK_T, 1e-11))?;
            let wall_ref = t0.elapsed().as_secs_f64();
            let r_ref = modia_break_positions(&reference);
            let mut pts: Vec<Point> = rtols()
                .into_iter()
                .map(|rtol| {
                    modia_point(
                        &model,
                        format!("rtol {rtol:.0e}"),
                        options(BREAK_T, rtol),
                        &|res| break_error(&modia_break_positions(res), &r_ref),
                    )
                })
                .collect();
            let (_, mirror) = break_error(&r_ref, &r_ref);
            pts.push(Point {
                setting: "rtol 1e-11 (reference, not ranked)".into(),
                wall: wall_ref,
                error: f64::NAN,
                note: mirror,
            });
            Ok(pts)
        }),
        rapier: Box::new(|| {
            let rho = modia3d::core::scene::builtin_solid_material("BilliardBall")
                .map(|m| m.density)
                .unwrap_or(1700.0);
            let z = demo::BALL_DIAMETER / 2.0;
            let mut balls: Vec<[f64; 3]> = rack_places()
                .into_iter()
                .map(|(i, j)| demo::rack(i, j, z))
                .collect();
            balls.push([-0.56, 0.0, z]);
            let fine = Setting {
                dt: 1.0 / 61440.0,
                iterations: 16,
            };
            let (wall_ref, r_ref) = rapier_side::billiards(fine, rho, &balls, CUE_V, BREAK_T);
            let mut pts: Vec<Point> = rapier_settings()
                .into_iter()
                .map(|s| {
                    median_of(s.label(), RUNS, || {
                        let (wall, r) = rapier_side::billiards(s, rho, &balls, CUE_V, BREAK_T);
                        let (e, n) = break_error(&r, &r_ref);
                        (wall, e, n)
                    })
                })
                .collect();
            let (_, mirror) = break_error(&r_ref, &r_ref);
            pts.push(Point {
                setting: format!("{} (reference, not ranked)", fine.label()),
                wall: wall_ref,
                error: f64::NAN,
                note: mirror,
            });
            Ok(pts)
        }),
    }
}

/// Every scene, in the order of docs/rapier-comparison.md.
pub fn all() -> Vec<Scene> {
    vec![
        slide_scene(),
        drop_scene(
            "bounce-0.9",
            "Steel ball Ø 0.1 m dropped from h = 0.5 m (lowest point) onto a steel plate, cor \
             0.9, no friction (modia3d with exact_restitution). Error = max over the first 5 \
             bounces of |apex_n/h − 0.9^(2n)|.",
            BOUNCE_COR,
            BOUNCE_STOP,
            apex_error,
        ),
        cradle_scene(),
        break_scene(),
        drop_scene(
            "steel-drop-0.7",
            "Steel ball Ø 0.1 m dropped from h = 0.5 m onto a steel plate, cor 0.7 (modia3d \
             with exact_restitution). Error = max relative error of the first impact time, the \
             rebound speed and the second impact time against the rigid limit.",
            DROP_COR,
            DROP_STOP,
            drop_error,
        ),
    ]
}
