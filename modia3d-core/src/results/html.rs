//! Results stage, HTML player: one self-contained page (no network) that plays the animation
//! with three.js. The page (`viewer.html`) gets, each in a script tag: the vendored three.js
//! module build and its OrbitControls addon (`results/vendor/`, three.js 0.170.0, MIT licence
//! beside them), the scene and motion as three.js JSON ([`SimulationResult::threejs_json`]),
//! and an overlay of what is drawn besides the objects (joint axes, rods between the frames of
//! a body, contact points and forces), all in the world frame of the scene. Reads a
//! `SimulationResult` only.

use super::threejs::write_text;
use super::{ResultError, SimulationResult};
use crate::dynamics::{BodyId, ObjectId};
use nalgebra::{Matrix3, Vector3};
use serde_json::{json, Value};
use std::path::Path;

/// The viewer page; the `/*MODIA3D_…*/` markers are replaced at export.
const VIEWER: &str = include_str!("viewer.html");
/// three.js 0.170.0, `build/three.module.min.js` (MIT, `vendor/LICENSE-three.txt`).
const THREE: &str = include_str!("vendor/three.module.min.js");
/// three.js 0.170.0, `examples/jsm/controls/OrbitControls.js` (imports from `'three'`).
const ORBIT_CONTROLS: &str = include_str!("vendor/OrbitControls.js");

/// A contact pair's track for the player: at every output time point whether the pair is in
/// contact, the contact point [m] and the force on the pair's second object [N], both in world.
/// Fed today from the contact signals (`SimOptions::contact_results`); any source of the same
/// three sequences can feed it.
pub(crate) struct ContactTrack {
    /// The pair's name, `"<a>|<b>"`.
    pub name: String,
    /// In contact (per time point).
    pub active: Vec<bool>,
    /// Contact point, resolved in world [m], 3 per time point.
    pub point: Vec<f64>,
    /// Force on `b` (normal and friction), resolved in world [N], 3 per time point.
    pub force: Vec<f64>,
}

/// Rounds for the page (µm / mN resolution keeps the document small; the pose tracks of the
/// objects are exported at full precision by `threejs_json`).
fn round(values: impl IntoIterator<Item = f64>, scale: f64) -> Vec<f64> {
    values
        .into_iter()
        .map(|v| (v * scale).round() / scale)
        .collect()
}

impl SimulationResult {
    /// The contact tracks from the recorded contact signals (empty without
    /// `SimOptions::contact_results`).
    fn contact_tracks(&self) -> Vec<ContactTrack> {
        if self.contacts.is_none() {
            return vec![];
        }
        let mut tracks = vec![];
        for name in self.contact_pairs() {
            let get = |f: &str| self.contact_signal(&name, f);
            let (Some(on), Some(point), Some(normal), Some(f_n), Some(friction)) = (
                get("in_contact"),
                get("point"),
                get("normal"),
                get("f_n"),
                get("friction_force"),
            ) else {
                continue;
            };
            let mut force = Vec::with_capacity(point.data.len());
            for k in 0..on.len() {
                let (Some(n), Some(f), Some(t)) = (normal.at(k), f_n.at(k), friction.at(k)) else {
                    break;
                };
                let fk = f.first().copied().unwrap_or(0.0);
                force.extend(n.iter().zip(t).map(|(n, t)| fk * n + t));
            }
            tracks.push(ContactTrack {
                active: on.data.iter().map(|&v| v > 0.5).collect(),
                point: point.data,
                force,
                name,
            });
        }
        tracks
    }

    /// What the player draws besides the objects, as JSON: the time points, the joints
    /// (revolute and prismatic: position of the joint frame and its axis, per time point),
    /// rods (between the joint frames on one moving body and to the origins of its objects with
    /// a shape: what holds a body together), and the contact tracks. Positions in the scene's
    /// world frame [m], forces [N].
    fn overlay(&self) -> Result<Value, ResultError> {
        let plan = self.plan();
        let scene = &plan.scene;
        let name = |o: usize| scene.objects.get(o).map_or("", |x| x.name.as_str());
        let position = |o: usize| -> Result<Vec<f64>, ResultError> {
            Ok(round(self.signal(&format!("{}.r_abs", name(o)))?.data, 1e6))
        };
        let mut joints = vec![];
        for j in &scene.joints {
            let Some((kind, axis)) = j.kind.drawn_axis() else {
                continue;
            };
            // The axis is resolved in obj1; obj1's orientation carries it into world.
            let r1 = self.signal(&format!("{}.R_abs", name(j.obj1)))?;
            let dirs: Vec<f64> = r1
                .data
                .chunks_exact(9)
                .flat_map(|m| {
                    let d: Vector3<f64> = Matrix3::from_row_slice(m) * axis;
                    [d.x, d.y, d.z]
                })
                .collect();
            joints.push(json!({"name": j.name, "kind": kind,
                "position": position(j.obj2)?, "axis": round(dirs, 1e6)}));
        }
        // Anchors per moving body: joint frames first, then objects with a shape.
        let body_of = |o: usize| plan.objects.get(ObjectId(o)).and_then(|p| p.body);
        let joint_frames: Vec<usize> = scene.joints.iter().flat_map(|j| [j.obj1, j.obj2]).collect();
        let shaped = scene.objects.iter().enumerate().filter(|(_, x)| {
            x.visual.is_some() || x.solid.as_ref().is_some_and(|s| s.shape.is_some())
        });
        let mut anchors: Vec<(BodyId, Vec<usize>)> = vec![];
        for o in joint_frames.iter().copied().chain(shaped.map(|(o, _)| o)) {
            let Some(b) = body_of(o) else { continue };
            match anchors.iter_mut().find(|(body, _)| *body == b) {
                Some((_, list)) if !list.contains(&o) => list.push(o),
                Some(_) => {}
                None => anchors.push((b, vec![o])),
            }
        }
        let mut rods = vec![];
        for (_, group) in &anchors {
            for (k, &a) in group.iter().enumerate() {
                // Rods start at a joint frame: two shapes of one body need none.
                if !joint_frames.contains(&a) {
                    continue;
                }
                for &b in group.iter().skip(k + 1) {
                    let (pa, pb) = (position(a)?, position(b)?);
                    let d2: f64 = pa
                        .iter()
                        .zip(&pb)
                        .take(3)
                        .map(|(x, y)| (x - y).powi(2))
                        .sum();
                    if d2.sqrt() > 1e-9 {
                        rods.push(json!({"from": name(a), "to": name(b), "a": pa, "b": pb}));
                    }
                }
            }
        }
        let contacts: Vec<Value> = self
            .contact_tracks()
            .into_iter()
            .map(|c| {
                json!({"name": c.name, "active": c.active, "point": round(c.point, 1e6),
                    "force": round(c.force, 1e3)})
            })
            .collect();
        Ok(json!({"time": self.time(), "joints": joints, "rods": rods, "contacts": contacts}))
    }

    /// The self-contained HTML page [`write_html`](Self::write_html) writes.
    pub fn html(&self) -> Result<String, ResultError> {
        // `</` inside a script element would end it; JSON allows `<\/`.
        let scene = self.threejs_json()?.to_string().replace("</", "<\\/");
        let overlay = self.overlay()?.to_string().replace("</", "<\\/");
        Ok(VIEWER
            .replacen("/*MODIA3D_THREE*/", THREE, 1)
            .replacen("/*MODIA3D_ORBIT_CONTROLS*/", ORBIT_CONTROLS, 1)
            .replacen("/*MODIA3D_SCENE*/null", &scene, 1)
            .replacen("/*MODIA3D_OVERLAY*/null", &overlay, 1))
    }

    /// Writes a self-contained HTML page (three.js inlined, no network) that plays the
    /// animation: orbit (left drag), pan (right drag) and zoom (wheel) camera; play/pause, a
    /// time slider and a speed choice; object names on hover; world axes (x red, y green,
    /// z blue) and a floor grid; revolute and prismatic joint axes and rods between the joint
    /// frames of each body; contact points and force arrows when the run recorded contact
    /// results (`SimOptions::contact_results`), with toggles. Colours are the built-in solid
    /// materials' (`palette.json`), others in turn from a fixed set.
    ///
    /// URL parameters: `?t=<time [s]>` opens paused at that time (the last output time shows
    /// the last pose; times outside the run show its first or last pose), `&probe=<object>`
    /// writes that object's drawn position (world frame of the scene, \[m\]) into
    /// `#modia3d-info`'s `data-probe-position`, `data-contacts-visible` counts the contact
    /// arrows drawn and `data-contact-points` lists their points (`x,y,z;…`, world \[m\]); with
    /// `data-probe-view` (where it is drawn: right and up from the view's centre in half view
    /// heights), `data-probe-hover` (the name the hover tip shows there), `data-time`, `data-object-count`, `data-frames-drawn`, `data-joint-count` and
    /// `data-rod-count` these let tests read the page's
    /// state (`tests/browser.rs`).
    pub fn write_html(&self, path: impl AsRef<Path>) -> Result<(), ResultError> {
        write_text(path.as_ref(), &self.html()?)
    }
}
