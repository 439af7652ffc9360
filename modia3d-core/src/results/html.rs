//! Results stage, HTML player: one self-contained page (no network) that plays the animation.
//! The viewer (`viewer.html`, a small self-written WebGL renderer with a Canvas 2D fallback)
//! gets the three.js JSON of [`SimulationResult::threejs_json`] embedded in a script tag.

use super::threejs::write_text;
use super::{ResultError, SimulationResult};
use std::path::Path;

/// The viewer page; `/*MODIA3D_SCENE*/null` is replaced by the scene document.
const VIEWER: &str = include_str!("viewer.html");

impl SimulationResult {
    /// The self-contained HTML page [`write_html`](Self::write_html) writes.
    pub fn html(&self) -> Result<String, ResultError> {
        // `</` inside a script element would end it; JSON allows `<\/`.
        let scene = self.threejs_json()?.to_string().replace("</", "<\\/");
        Ok(VIEWER.replacen("/*MODIA3D_SCENE*/null", &scene, 1))
    }

    /// Writes a self-contained HTML page that plays the animation in a loop, offline: it draws
    /// every object with a shape, frames the scene, and exposes
    /// `window.modia3d = { objectCount, framesDrawn, renderer }` and an element
    /// `#modia3d-info` with `data-object-count` for tests.
    pub fn write_html(&self, path: impl AsRef<Path>) -> Result<(), ResultError> {
        write_text(path.as_ref(), &self.html()?)
    }
}
