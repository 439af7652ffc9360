//! The block library: Modelica's names, parameters and equations (`Modelica.Blocks.Sources`,
//! `Modelica.Blocks.Continuous`, `Modelica.Blocks.Nonlinear`) and a `Drive` (motor and gear on
//! a joint coordinate), each a [`Component`] like a user's. Equations with units:
//! docs/drive-trains.md. Field names are Modelica's (`T`, `Ti`, `yMax`), so a ported model
//! reads line by line.
#![allow(non_snake_case)] // Modelica's parameter names

use super::components::{
    Component, ComponentIo, ComponentJacobian, FlangeSpec, OutputSpec, PortSpec, StateSpec,
};
use std::sync::Arc;

fn finite(what: &str, v: f64) -> Result<(), String> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(format!("{what} = {v} is not finite: give a finite value"))
    }
}

fn positive(what: &str, v: f64) -> Result<(), String> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(format!("{what} = {v} must be positive and finite"))
    }
}

fn y_out(unit: &'static str) -> Vec<OutputSpec> {
    vec![OutputSpec::new("y", unit, false)]
}

fn y_through() -> Vec<OutputSpec> {
    vec![OutputSpec::new("y", "1", true)]
}

fn u_in() -> Vec<PortSpec> {
    vec![PortSpec::new("u", "1")]
}

/// The first of `times` strictly after `t` (a source's kinks).
fn next_after(t: f64, times: impl IntoIterator<Item = f64>) -> Option<f64> {
    times.into_iter().filter(|&s| s > t).min_by(f64::total_cmp)
}

// ---------------------------------------------------------------- sources

/// `Modelica.Blocks.Sources.Constant`: `y = k`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Constant {
    /// The value.
    pub k: f64,
}

impl Component for Constant {
    fn kind(&self) -> &'static str {
        "Constant"
    }
    fn inputs(&self) -> Vec<PortSpec> {
        vec![]
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        y_out("1")
    }
    fn check(&self) -> Result<(), String> {
        finite("k", self.k)
    }
    fn outputs_at(&self, _io: &ComponentIo<'_>, y: &mut [f64]) {
        y[0] = self.k;
    }
}

/// `Modelica.Blocks.Sources.Step`: `y = offset + (t < startTime ? 0 : height)`, a time event
/// at `startTime`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Step {
    /// Height of the step.
    pub height: f64,
    /// Offset of the output.
    pub offset: f64,
    /// Time of the step \[s\].
    pub startTime: f64,
}

impl Component for Step {
    fn kind(&self) -> &'static str {
        "Step"
    }
    fn inputs(&self) -> Vec<PortSpec> {
        vec![]
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        y_out("1")
    }
    fn check(&self) -> Result<(), String> {
        finite("height", self.height)?;
        finite("offset", self.offset)?;
        finite("startTime", self.startTime)
    }
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]) {
        y[0] = self.offset
            + if io.t < self.startTime {
                0.0
            } else {
                self.height
            };
    }
    fn next_time_event(&self, t: f64, _d: &[f64]) -> Option<f64> {
        next_after(t, [self.startTime])
    }
}

/// `Modelica.Blocks.Sources.Ramp`: from `offset` at `startTime` linearly to `offset + height`
/// at `startTime + duration`, constant before and after; time events at both kinks.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Ramp {
    /// Height of the ramp.
    pub height: f64,
    /// Its duration \[s\] (≥ 0; 0 is a step).
    pub duration: f64,
    /// Offset of the output.
    pub offset: f64,
    /// Its start \[s\].
    pub startTime: f64,
}

impl Component for Ramp {
    fn kind(&self) -> &'static str {
        "Ramp"
    }
    fn inputs(&self) -> Vec<PortSpec> {
        vec![]
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        y_out("1")
    }
    fn check(&self) -> Result<(), String> {
        finite("height", self.height)?;
        finite("offset", self.offset)?;
        finite("startTime", self.startTime)?;
        if !(self.duration.is_finite() && self.duration >= 0.0) {
            return Err(format!(
                "duration = {} must be finite and ≥ 0 s",
                self.duration
            ));
        }
        Ok(())
    }
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]) {
        let t = io.t;
        y[0] = self.offset
            + if t < self.startTime {
                0.0
            } else if t < self.startTime + self.duration {
                (t - self.startTime) * self.height / self.duration
            } else {
                self.height
            };
    }
    fn next_time_event(&self, t: f64, _d: &[f64]) -> Option<f64> {
        next_after(t, [self.startTime, self.startTime + self.duration])
    }
}

/// `Modelica.Blocks.Sources.Sine`:
/// `y = offset + (t < startTime ? 0 : amplitude·sin(2π·f·(t − startTime) + phase))`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sine {
    /// Amplitude.
    pub amplitude: f64,
    /// Frequency \[Hz\].
    pub f: f64,
    /// Phase \[rad\].
    pub phase: f64,
    /// Offset of the output.
    pub offset: f64,
    /// Its start \[s\].
    pub startTime: f64,
}

impl Component for Sine {
    fn kind(&self) -> &'static str {
        "Sine"
    }
    fn inputs(&self) -> Vec<PortSpec> {
        vec![]
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        y_out("1")
    }
    fn check(&self) -> Result<(), String> {
        finite("amplitude", self.amplitude)?;
        finite("f", self.f)?;
        finite("phase", self.phase)?;
        finite("offset", self.offset)?;
        finite("startTime", self.startTime)
    }
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]) {
        let s = io.t - self.startTime;
        y[0] = self.offset
            + if s < 0.0 {
                0.0
            } else {
                self.amplitude * (std::f64::consts::TAU * self.f * s + self.phase).sin()
            };
    }
    fn next_time_event(&self, t: f64, _d: &[f64]) -> Option<f64> {
        next_after(t, [self.startTime])
    }
}

/// `Modelica.Blocks.Sources.TimeTable`: linear interpolation in a table of `(t, y)` rows with
/// increasing times, held constant before the first and after the last; a time event at every
/// row.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    /// Rows `(time [s], value)`, times non-decreasing (a repeated time is a jump).
    pub table: Vec<(f64, f64)>,
}

impl Component for Table {
    fn kind(&self) -> &'static str {
        "Table"
    }
    fn inputs(&self) -> Vec<PortSpec> {
        vec![]
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        y_out("1")
    }
    fn check(&self) -> Result<(), String> {
        if self.table.is_empty() {
            return Err("the table is empty: give at least one row (time, value)".into());
        }
        for (i, &(t, y)) in self.table.iter().enumerate() {
            finite(&format!("row {i}'s time"), t)?;
            finite(&format!("row {i}'s value"), y)?;
        }
        if let Some(i) = self.table.windows(2).position(|w| w[1].0 < w[0].0) {
            return Err(format!(
                "row {}'s time {} s is before row {i}'s {} s: times must not decrease",
                i + 1,
                self.table[i + 1].0,
                self.table[i].0
            ));
        }
        Ok(())
    }
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]) {
        let tb = &self.table;
        let t = io.t;
        // The last row at or before t (so a jump takes its later value at its time).
        let k = tb.partition_point(|r| r.0 <= t);
        y[0] = if k == 0 {
            tb[0].1
        } else if k == tb.len() {
            tb[k - 1].1
        } else {
            let (a, b) = (tb[k - 1], tb[k]);
            a.1 + (t - a.0) * (b.1 - a.1) / (b.0 - a.0)
        };
    }
    fn next_time_event(&self, t: f64, _d: &[f64]) -> Option<f64> {
        next_after(t, self.table.iter().map(|r| r.0))
    }
}

/// A value set by the host between steps (`Simulation::set_input("<name>", &[v])`); `start`
/// until set. A change restarts the integration there, as the scene's other inputs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Input {
    /// The value until the host sets one.
    pub start: f64,
}

impl Component for Input {
    fn kind(&self) -> &'static str {
        "Input"
    }
    fn inputs(&self) -> Vec<PortSpec> {
        vec![]
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        y_out("1")
    }
    fn discrete_states(&self) -> Vec<StateSpec> {
        vec![StateSpec::new("value", "1", self.start, 1.0)]
    }
    fn check(&self) -> Result<(), String> {
        finite("start", self.start)
    }
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]) {
        y[0] = io.d[0];
    }
}

/// Point-to-point motion (Modelica's `KinematicPTP`, Modia3D's `PTP_path`): from each row of
/// `positions` to the next as fast as `v_max` and `a_max` allow, at rest at every row, all axes
/// synchronised (the slowest axis at its limits, the others scaled to arrive with it).
/// Outputs per axis `i` (from 1; without the number for one axis): `q` (position), `qd`,
/// `qdd`, in the axes' units; time events at every switch of the acceleration.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PtpPath {
    /// The points, one row per point, one column per axis (\[rad\] or \[m\]).
    pub positions: Vec<Vec<f64>>,
    /// Largest speed per axis (> 0).
    pub v_max: Vec<f64>,
    /// Largest acceleration per axis (> 0).
    pub a_max: Vec<f64>,
    /// When the motion starts \[s\].
    pub startTime: f64,
}

/// One segment of a [`PtpPath`] in the path parameter `s ∈ [0, 1]`.
#[derive(Clone, Copy, Debug)]
struct PtpSegment {
    /// Whether it moves (a repeated point does not).
    moving: bool,
    /// Largest `ṡ` and `s̈`.
    sd_max: f64,
    sdd_max: f64,
    /// End of the acceleration phase, start of the deceleration phase, end \[s\] (relative).
    ta: f64,
    tv: f64,
    te: f64,
}

impl PtpPath {
    fn axes(&self) -> usize {
        self.positions.first().map_or(0, Vec::len)
    }

    /// `(s, ṡ, s̈)` of segment `g` at time `t` (relative to its start).
    fn path(g: &PtpSegment, t: f64) -> (f64, f64, f64) {
        if !g.moving || t <= 0.0 {
            return (0.0, 0.0, 0.0);
        }
        let a = g.sdd_max;
        if t < g.ta {
            (0.5 * a * t * t, a * t, a)
        } else if t < g.tv {
            let s1 = 0.5 * a * g.ta * g.ta;
            (s1 + g.sd_max * (t - g.ta), g.sd_max, 0.0)
        } else if t < g.te {
            let s1 = 0.5 * a * g.ta * g.ta;
            let s2 = s1 + g.sd_max * (g.tv - g.ta);
            let r = t - g.tv;
            (s2 + g.sd_max * r - 0.5 * a * r * r, g.sd_max - a * r, -a)
        } else {
            (1.0, 0.0, 0.0)
        }
    }
}

impl Component for PtpPath {
    fn kind(&self) -> &'static str {
        "PtpPath"
    }
    fn inputs(&self) -> Vec<PortSpec> {
        vec![]
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        let np = self.axes();
        let mut o = vec![];
        for i in 1..=np {
            let n = if np == 1 {
                String::new()
            } else {
                i.to_string()
            };
            o.push(OutputSpec::new(format!("q{n}"), "1", false));
            o.push(OutputSpec::new(format!("qd{n}"), "1/s", false));
            o.push(OutputSpec::new(format!("qdd{n}"), "1/s²", false));
        }
        o
    }
    fn check(&self) -> Result<(), String> {
        let np = self.axes();
        if self.positions.len() < 2 || np == 0 {
            return Err("positions needs at least two rows (points) of at least one axis".into());
        }
        if self.positions.iter().any(|r| r.len() != np) {
            return Err(format!("every row of positions must have {np} axes"));
        }
        if self.v_max.len() != np || self.a_max.len() != np {
            return Err(format!(
                "v_max and a_max need one value per axis ({np}); got {} and {}",
                self.v_max.len(),
                self.a_max.len()
            ));
        }
        for (j, (&v, &a)) in self.v_max.iter().zip(&self.a_max).enumerate() {
            positive(&format!("v_max[{j}]"), v)?;
            positive(&format!("a_max[{j}]"), a)?;
        }
        for r in &self.positions {
            for &p in r {
                finite("a position", p)?;
            }
        }
        finite("startTime", self.startTime)
    }
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]) {
        // Allocation-free: the segments are recomputed on the fly (a few per path).
        let np = self.axes();
        let t = io.t;
        let n = self.positions.len() - 1;
        let (mut row, mut s, mut sd, mut sdd) = (0, 0.0, 0.0, 0.0);
        let mut t0 = self.startTime;
        for w in 0..n {
            let g = self.segment(w);
            if t < t0 + g.te || w + 1 == n {
                row = w;
                (s, sd, sdd) = Self::path(&g, t - t0);
                break;
            }
            t0 += g.te;
        }
        let (p0, p1) = (&self.positions[row], &self.positions[row + 1]);
        for j in 0..np {
            let d = p1[j] - p0[j];
            y[3 * j] = p0[j] + d * s;
            y[3 * j + 1] = d * sd;
            y[3 * j + 2] = d * sdd;
        }
    }
    fn next_time_event(&self, t: f64, _d: &[f64]) -> Option<f64> {
        let mut t0 = self.startTime;
        let mut best: Option<f64> = next_after(t, [t0]);
        for w in 0..self.positions.len() - 1 {
            let g = self.segment(w);
            if g.moving {
                let e = next_after(t, [t0 + g.ta, t0 + g.tv, t0 + g.te]);
                best = match (best, e) {
                    (Some(a), Some(b)) => Some(a.min(b)),
                    (a, b) => a.or(b),
                };
            }
            t0 += g.te;
        }
        best
    }
}

impl PtpPath {
    /// The times \[s\] at which the path reaches each row of `positions` (at rest there):
    /// `startTime` for the first. For scheduling what happens at a point (a grip, a
    /// release). Assumes a path that passes [`Component::check`].
    pub fn arrival_times(&self) -> Vec<f64> {
        let mut t = vec![self.startTime];
        for w in 0..self.positions.len().saturating_sub(1) {
            let last = t[t.len() - 1];
            t.push(last + self.segment(w).te);
        }
        t
    }

    /// Segment `w` (from row `w` to `w + 1`), without allocating.
    fn segment(&self, w: usize) -> PtpSegment {
        let (a, b) = (&self.positions[w], &self.positions[w + 1]);
        let mut inv_v: f64 = 0.0;
        let mut inv_a: f64 = 0.0;
        for j in 0..a.len() {
            let d = b[j] - a[j];
            inv_v = inv_v.max((d / self.v_max[j]).abs());
            inv_a = inv_a.max((d / self.a_max[j]).abs());
        }
        let small = 1000.0 * f64::EPSILON;
        if inv_v <= small || inv_a <= small {
            return PtpSegment {
                moving: false,
                sd_max: 0.0,
                sdd_max: 0.0,
                ta: 0.0,
                tv: 0.0,
                te: 0.0,
            };
        }
        let (sd_max, sdd_max) = (1.0 / inv_v, 1.0 / inv_a);
        let ta1 = (1.0 / sdd_max).sqrt();
        let ta2 = sd_max / sdd_max;
        let (sd_top, ta, tv, te) = if ta2 >= ta1 {
            (sdd_max * ta1, ta1, ta1, 2.0 * ta1)
        } else {
            (sd_max, ta2, 1.0 / sd_max, 1.0 / sd_max + ta2)
        };
        PtpSegment {
            moving: true,
            sd_max: sd_top,
            sdd_max,
            ta,
            tv,
            te,
        }
    }
}

// ---------------------------------------------------------------- static blocks

/// `Modelica.Blocks.Math.Gain`: `y = k·u`.
#[derive(Clone, Debug, PartialEq)]
pub struct Gain {
    /// The gain.
    pub k: f64,
}

impl Default for Gain {
    fn default() -> Self {
        Gain { k: 1.0 }
    }
}

impl Component for Gain {
    fn kind(&self) -> &'static str {
        "Gain"
    }
    fn provides_jacobian(&self) -> bool {
        true
    }
    fn jacobian(&self, _io: &ComponentIo<'_>, jac: &mut ComponentJacobian<'_>) {
        jac.y_u(0, 0, self.k);
    }
    fn inputs(&self) -> Vec<PortSpec> {
        u_in()
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        y_through()
    }
    fn check(&self) -> Result<(), String> {
        finite("k", self.k)
    }
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]) {
        y[0] = self.k * io.u[0];
    }
}

/// `Modelica.Blocks.Math.Feedback`: `y = u1 − u2`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Feedback;

impl Component for Feedback {
    fn kind(&self) -> &'static str {
        "Feedback"
    }
    fn provides_jacobian(&self) -> bool {
        true
    }
    fn jacobian(&self, _io: &ComponentIo<'_>, jac: &mut ComponentJacobian<'_>) {
        jac.y_u(0, 0, 1.0);
        jac.y_u(0, 1, -1.0);
    }
    fn inputs(&self) -> Vec<PortSpec> {
        vec![PortSpec::new("u1", "1"), PortSpec::new("u2", "1")]
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        y_through()
    }
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]) {
        y[0] = io.u[0] - io.u[1];
    }
}

/// `Modelica.Blocks.Math.Add`: `y = k1·u1 + k2·u2`.
#[derive(Clone, Debug, PartialEq)]
pub struct Add {
    /// Gain of `u1`.
    pub k1: f64,
    /// Gain of `u2`.
    pub k2: f64,
}

impl Default for Add {
    fn default() -> Self {
        Add { k1: 1.0, k2: 1.0 }
    }
}

impl Component for Add {
    fn kind(&self) -> &'static str {
        "Add"
    }
    fn provides_jacobian(&self) -> bool {
        true
    }
    fn jacobian(&self, _io: &ComponentIo<'_>, jac: &mut ComponentJacobian<'_>) {
        jac.y_u(0, 0, self.k1);
        jac.y_u(0, 1, self.k2);
    }
    fn inputs(&self) -> Vec<PortSpec> {
        vec![PortSpec::new("u1", "1"), PortSpec::new("u2", "1")]
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        y_through()
    }
    fn check(&self) -> Result<(), String> {
        finite("k1", self.k1)?;
        finite("k2", self.k2)
    }
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]) {
        y[0] = self.k1 * io.u[0] + self.k2 * io.u[1];
    }
}

/// `Modelica.Blocks.Math.Add3`: `y = k1·u1 + k2·u2 + k3·u3`.
#[derive(Clone, Debug, PartialEq)]
pub struct Add3 {
    /// Gain of `u1`.
    pub k1: f64,
    /// Gain of `u2`.
    pub k2: f64,
    /// Gain of `u3`.
    pub k3: f64,
}

impl Default for Add3 {
    fn default() -> Self {
        Add3 {
            k1: 1.0,
            k2: 1.0,
            k3: 1.0,
        }
    }
}

impl Component for Add3 {
    fn kind(&self) -> &'static str {
        "Add3"
    }
    fn provides_jacobian(&self) -> bool {
        true
    }
    fn jacobian(&self, _io: &ComponentIo<'_>, jac: &mut ComponentJacobian<'_>) {
        jac.y_u(0, 0, self.k1);
        jac.y_u(0, 1, self.k2);
        jac.y_u(0, 2, self.k3);
    }
    fn inputs(&self) -> Vec<PortSpec> {
        vec![
            PortSpec::new("u1", "1"),
            PortSpec::new("u2", "1"),
            PortSpec::new("u3", "1"),
        ]
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        y_through()
    }
    fn check(&self) -> Result<(), String> {
        finite("k1", self.k1)?;
        finite("k2", self.k2)?;
        finite("k3", self.k3)
    }
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]) {
        y[0] = self.k1 * io.u[0] + self.k2 * io.u[1] + self.k3 * io.u[2];
    }
}

/// The discrete mode of a limit: 0 inside, 1 at the upper, −1 at the lower limit, decided at
/// events from the unlimited value `v` and the mode `old` (so the output is smooth between
/// events and the kinks are located as zero crossings). A mode is left when its crossing
/// function reaches zero (`v` at the limit counts as reached), so an event at the limit's
/// value switches, and cannot stay in a mode whose crossing is zero.
fn limit_mode(v: f64, lo: f64, hi: f64, old: f64) -> f64 {
    // Staying at a limit needs `v` strictly beyond it; reaching one, only `v` at it.
    let (to_hi, to_lo) = if old > 0.5 {
        (v > hi, v <= lo)
    } else if old < -0.5 {
        (v >= hi, v < lo)
    } else {
        (v >= hi, v <= lo)
    };
    if to_hi {
        1.0
    } else if to_lo {
        -1.0
    } else {
        0.0
    }
}

/// The limited value of `v` in `mode`.
fn limited(v: f64, lo: f64, hi: f64, mode: f64) -> f64 {
    if mode > 0.5 {
        hi
    } else if mode < -0.5 {
        lo
    } else {
        v
    }
}

/// The crossing functions of a limit in `mode` (positive while the mode holds).
fn limit_crossings(v: f64, lo: f64, hi: f64, mode: f64, z: &mut [f64]) {
    if mode > 0.5 {
        z[0] = v - hi;
        z[1] = 1.0;
    } else if mode < -0.5 {
        z[0] = lo - v;
        z[1] = 1.0;
    } else {
        z[0] = hi - v;
        z[1] = v - lo;
    }
}

/// `Modelica.Blocks.Nonlinear.Limiter`: `y = clamp(u, uMin, uMax)`, its kinks located as zero
/// crossings.
#[derive(Clone, Debug, PartialEq)]
pub struct Limiter {
    /// Upper limit.
    pub uMax: f64,
    /// Lower limit.
    pub uMin: f64,
}

impl Limiter {
    /// Limits `[uMin, uMax]`.
    pub fn new(uMin: f64, uMax: f64) -> Self {
        Limiter { uMax, uMin }
    }
}

impl Component for Limiter {
    fn kind(&self) -> &'static str {
        "Limiter"
    }
    fn provides_jacobian(&self) -> bool {
        true
    }
    fn jacobian(&self, io: &ComponentIo<'_>, jac: &mut ComponentJacobian<'_>) {
        // y = u inside; a limit's value (constant) at it.
        if io.d[0].abs() < 0.5 {
            jac.y_u(0, 0, 1.0);
        }
    }
    fn inputs(&self) -> Vec<PortSpec> {
        u_in()
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        y_through()
    }
    fn discrete_states(&self) -> Vec<StateSpec> {
        vec![StateSpec::new("mode", "1", 0.0, 1.0)]
    }
    fn check(&self) -> Result<(), String> {
        finite("uMax", self.uMax)?;
        finite("uMin", self.uMin)?;
        if self.uMin > self.uMax {
            return Err(format!(
                "uMin = {} is above uMax = {}",
                self.uMin, self.uMax
            ));
        }
        Ok(())
    }
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]) {
        y[0] = limited(io.u[0], self.uMin, self.uMax, io.d[0]);
    }
    fn n_crossings(&self) -> usize {
        2
    }
    fn crossings(&self, io: &ComponentIo<'_>, z: &mut [f64]) {
        limit_crossings(io.u[0], self.uMin, self.uMax, io.d[0], z);
    }
    fn event(&self, io: &ComponentIo<'_>, d_new: &mut [f64]) {
        d_new[0] = limit_mode(io.u[0], self.uMin, self.uMax, d_new[0]);
    }
}

// ---------------------------------------------------------------- continuous blocks

/// `Modelica.Blocks.Continuous.Integrator`: `ẋ = k·u`, `y = x`.
#[derive(Clone, Debug, PartialEq)]
pub struct Integrator {
    /// The gain [1/s].
    pub k: f64,
    /// The initial output.
    pub y_start: f64,
}

impl Default for Integrator {
    fn default() -> Self {
        Integrator {
            k: 1.0,
            y_start: 0.0,
        }
    }
}

impl Component for Integrator {
    fn kind(&self) -> &'static str {
        "Integrator"
    }
    fn provides_jacobian(&self) -> bool {
        true
    }
    fn jacobian(&self, _io: &ComponentIo<'_>, jac: &mut ComponentJacobian<'_>) {
        jac.y_x(0, 0, 1.0);
        jac.f_u(0, 0, self.k);
    }
    fn inputs(&self) -> Vec<PortSpec> {
        u_in()
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        y_out("1")
    }
    fn states(&self) -> Vec<StateSpec> {
        vec![StateSpec::new("x", "1", self.y_start, 1.0)]
    }
    fn check(&self) -> Result<(), String> {
        finite("k", self.k)?;
        finite("y_start", self.y_start)
    }
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]) {
        y[0] = io.x[0];
    }
    fn derivatives(&self, io: &ComponentIo<'_>, xdot: &mut [f64], _f: &mut [f64]) {
        xdot[0] = self.k * io.u[0];
    }
}

/// `Modelica.Blocks.Continuous.FirstOrder`: `T·ẋ = k·u − x`, `y = x`.
#[derive(Clone, Debug, PartialEq)]
pub struct FirstOrder {
    /// The gain.
    pub k: f64,
    /// The time constant \[s\] (> 0).
    pub T: f64,
    /// The initial output.
    pub y_start: f64,
}

impl Default for FirstOrder {
    fn default() -> Self {
        FirstOrder {
            k: 1.0,
            T: 1.0,
            y_start: 0.0,
        }
    }
}

impl Component for FirstOrder {
    fn kind(&self) -> &'static str {
        "FirstOrder"
    }
    fn provides_jacobian(&self) -> bool {
        true
    }
    fn jacobian(&self, _io: &ComponentIo<'_>, jac: &mut ComponentJacobian<'_>) {
        jac.y_x(0, 0, 1.0);
        jac.f_x(0, 0, -1.0 / self.T);
        jac.f_u(0, 0, self.k / self.T);
    }
    fn inputs(&self) -> Vec<PortSpec> {
        u_in()
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        y_out("1")
    }
    fn states(&self) -> Vec<StateSpec> {
        vec![StateSpec::new("x", "1", self.y_start, 1.0)]
    }
    fn check(&self) -> Result<(), String> {
        finite("k", self.k)?;
        positive("T", self.T)?;
        finite("y_start", self.y_start)
    }
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]) {
        y[0] = io.x[0];
    }
    fn derivatives(&self, io: &ComponentIo<'_>, xdot: &mut [f64], _f: &mut [f64]) {
        xdot[0] = (self.k * io.u[0] - io.x[0]) / self.T;
    }
}

/// `Modelica.Blocks.Continuous.PI`: `ẋ = u/T`, `y = k·(x + u)`.
#[derive(Clone, Debug, PartialEq)]
pub struct PI {
    /// The gain.
    pub k: f64,
    /// The integral time constant \[s\] (> 0).
    pub T: f64,
    /// The initial state.
    pub x_start: f64,
}

impl Default for PI {
    fn default() -> Self {
        PI {
            k: 1.0,
            T: 1.0,
            x_start: 0.0,
        }
    }
}

impl PI {
    /// Gain `k` and time constant `T` \[s\].
    pub fn new(k: f64, T: f64) -> Self {
        PI { k, T, x_start: 0.0 }
    }
}

impl Component for PI {
    fn kind(&self) -> &'static str {
        "PI"
    }
    fn provides_jacobian(&self) -> bool {
        true
    }
    fn jacobian(&self, _io: &ComponentIo<'_>, jac: &mut ComponentJacobian<'_>) {
        jac.y_x(0, 0, self.k);
        jac.y_u(0, 0, self.k);
        jac.f_u(0, 0, 1.0 / self.T);
    }
    fn inputs(&self) -> Vec<PortSpec> {
        u_in()
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        y_through()
    }
    fn states(&self) -> Vec<StateSpec> {
        vec![StateSpec::new("x", "1", self.x_start, 1.0)]
    }
    fn check(&self) -> Result<(), String> {
        finite("k", self.k)?;
        positive("T", self.T)?;
        finite("x_start", self.x_start)
    }
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]) {
        y[0] = self.k * (io.x[0] + io.u[0]);
    }
    fn derivatives(&self, io: &ComponentIo<'_>, xdot: &mut [f64], _f: &mut [f64]) {
        xdot[0] = io.u[0] / self.T;
    }
}

/// `Modelica.Blocks.Continuous.PID`: `y = k·(u + I + D)` with `İ = u/Ti` and the
/// derivative filtered by `Td/Nd`: `ẋ_D = (u − x_D)·Nd/Td`, `D = Nd·(u − x_D)`.
#[derive(Clone, Debug, PartialEq)]
pub struct PID {
    /// The gain.
    pub k: f64,
    /// The integral time constant \[s\] (> 0).
    pub Ti: f64,
    /// The derivative time constant \[s\] (> 0).
    pub Td: f64,
    /// The derivative's filter: its time constant is `Td/Nd` (> 0).
    pub Nd: f64,
    /// Initial integral state.
    pub xi_start: f64,
    /// Initial derivative state.
    pub xd_start: f64,
}

impl Default for PID {
    fn default() -> Self {
        PID {
            k: 1.0,
            Ti: 0.5,
            Td: 0.1,
            Nd: 10.0,
            xi_start: 0.0,
            xd_start: 0.0,
        }
    }
}

impl Component for PID {
    fn kind(&self) -> &'static str {
        "PID"
    }
    fn provides_jacobian(&self) -> bool {
        true
    }
    fn jacobian(&self, _io: &ComponentIo<'_>, jac: &mut ComponentJacobian<'_>) {
        jac.y_x(0, 0, self.k);
        jac.y_x(0, 1, -self.k * self.Nd);
        jac.y_u(0, 0, self.k * (1.0 + self.Nd));
        jac.f_u(0, 0, 1.0 / self.Ti);
        jac.f_x(1, 1, -self.Nd / self.Td);
        jac.f_u(1, 0, self.Nd / self.Td);
    }
    fn inputs(&self) -> Vec<PortSpec> {
        u_in()
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        y_through()
    }
    fn states(&self) -> Vec<StateSpec> {
        vec![
            StateSpec::new("xi", "1", self.xi_start, 1.0),
            StateSpec::new("xd", "1", self.xd_start, 1.0),
        ]
    }
    fn check(&self) -> Result<(), String> {
        finite("k", self.k)?;
        positive("Ti", self.Ti)?;
        positive("Td", self.Td)?;
        positive("Nd", self.Nd)?;
        finite("xi_start", self.xi_start)?;
        finite("xd_start", self.xd_start)
    }
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]) {
        let u = io.u[0];
        y[0] = self.k * (u + io.x[0] + self.Nd * (u - io.x[1]));
    }
    fn derivatives(&self, io: &ComponentIo<'_>, xdot: &mut [f64], _f: &mut [f64]) {
        let u = io.u[0];
        xdot[0] = u / self.Ti;
        xdot[1] = (u - io.x[1]) * self.Nd / self.Td;
    }
}

/// `Modelica.Blocks.Continuous.LimPID` (controller type PID): set point `u_s`, measurement
/// `u_m`; `P = wp·u_s − u_m`, `D = Nd·(e_d − x_D)` with `e_d = wd·u_s − u_m` and
/// `ẋ_D = (e_d − x_D)·Nd/Td`, `v = k·(P + I + D)`, `y = clamp(v, yMin, yMax)` and anti-windup
/// `İ = (u_s − u_m + (y − v)/(k·Ni))/Ti`. The limits are located as zero crossings.
#[derive(Clone, Debug, PartialEq)]
pub struct LimPID {
    /// The gain (> 0).
    pub k: f64,
    /// The integral time constant \[s\] (> 0).
    pub Ti: f64,
    /// The derivative time constant \[s\] (> 0).
    pub Td: f64,
    /// Upper limit of the output.
    pub yMax: f64,
    /// Lower limit of the output (default −1, the negative of `yMax`'s default: set both).
    pub yMin: f64,
    /// Set-point weight of the proportional part.
    pub wp: f64,
    /// Set-point weight of the derivative part.
    pub wd: f64,
    /// Anti-windup: `Ni·Ti` is the time constant of the integrator's tracking (> 0).
    pub Ni: f64,
    /// The derivative's filter (`Td/Nd`, > 0).
    pub Nd: f64,
    /// Initial integral state.
    pub xi_start: f64,
    /// Initial derivative state.
    pub xd_start: f64,
}

impl Default for LimPID {
    fn default() -> Self {
        LimPID {
            k: 1.0,
            Ti: 0.5,
            Td: 0.1,
            yMax: 1.0,
            yMin: -1.0,
            wp: 1.0,
            wd: 0.0,
            Ni: 0.9,
            Nd: 10.0,
            xi_start: 0.0,
            xd_start: 0.0,
        }
    }
}

impl LimPID {
    /// The unlimited output `v`.
    fn unlimited(&self, io: &ComponentIo<'_>) -> f64 {
        let (us, um) = (io.u[0], io.u[1]);
        let p = self.wp * us - um;
        let d = self.Nd * (self.wd * us - um - io.x[1]);
        self.k * (p + io.x[0] + d)
    }
}

impl Component for LimPID {
    fn kind(&self) -> &'static str {
        "LimPID"
    }
    fn provides_jacobian(&self) -> bool {
        true
    }
    fn jacobian(&self, io: &ComponentIo<'_>, jac: &mut ComponentJacobian<'_>) {
        // ∂v over (u_s, u_m, x_I, x_D).
        let (k, nd) = (self.k, self.Nd);
        let dv = [k * (self.wp + nd * self.wd), -k * (1.0 + nd), k, -k * nd];
        let r = nd / self.Td;
        if io.d[0].abs() < 0.5 {
            // y = v; İ = (u_s − u_m)/Ti.
            jac.y_u(0, 0, dv[0]);
            jac.y_u(0, 1, dv[1]);
            jac.y_x(0, 0, dv[2]);
            jac.y_x(0, 1, dv[3]);
            jac.f_u(0, 0, 1.0 / self.Ti);
            jac.f_u(0, 1, -1.0 / self.Ti);
        } else {
            // y at a limit (constant); İ = (u_s − u_m + (y − v)/(k·Ni))/Ti.
            let a = 1.0 / (k * self.Ni * self.Ti);
            jac.f_u(0, 0, 1.0 / self.Ti - a * dv[0]);
            jac.f_u(0, 1, -1.0 / self.Ti - a * dv[1]);
            jac.f_x(0, 0, -a * dv[2]);
            jac.f_x(0, 1, -a * dv[3]);
        }
        // ẋ_D = (wd·u_s − u_m − x_D)·Nd/Td.
        jac.f_u(1, 0, self.wd * r);
        jac.f_u(1, 1, -r);
        jac.f_x(1, 1, -r);
    }
    fn inputs(&self) -> Vec<PortSpec> {
        vec![PortSpec::new("u_s", "1"), PortSpec::new("u_m", "1")]
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        y_through()
    }
    fn states(&self) -> Vec<StateSpec> {
        vec![
            StateSpec::new("xi", "1", self.xi_start, 1.0),
            StateSpec::new("xd", "1", self.xd_start, 1.0),
        ]
    }
    fn discrete_states(&self) -> Vec<StateSpec> {
        vec![StateSpec::new("mode", "1", 0.0, 1.0)]
    }
    fn check(&self) -> Result<(), String> {
        positive("k", self.k)?;
        positive("Ti", self.Ti)?;
        positive("Td", self.Td)?;
        positive("Ni", self.Ni)?;
        positive("Nd", self.Nd)?;
        finite("yMax", self.yMax)?;
        finite("yMin", self.yMin)?;
        finite("wp", self.wp)?;
        finite("wd", self.wd)?;
        if self.yMin > self.yMax {
            return Err(format!(
                "yMin = {} is above yMax = {}",
                self.yMin, self.yMax
            ));
        }
        Ok(())
    }
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]) {
        y[0] = limited(self.unlimited(io), self.yMin, self.yMax, io.d[0]);
    }
    fn derivatives(&self, io: &ComponentIo<'_>, xdot: &mut [f64], _f: &mut [f64]) {
        let (us, um) = (io.u[0], io.u[1]);
        let v = self.unlimited(io);
        let y = limited(v, self.yMin, self.yMax, io.d[0]);
        xdot[0] = (us - um + (y - v) / (self.k * self.Ni)) / self.Ti;
        xdot[1] = (self.wd * us - um - io.x[1]) * self.Nd / self.Td;
    }
    fn n_crossings(&self) -> usize {
        2
    }
    fn crossings(&self, io: &ComponentIo<'_>, z: &mut [f64]) {
        limit_crossings(self.unlimited(io), self.yMin, self.yMax, io.d[0], z);
    }
    fn event(&self, io: &ComponentIo<'_>, d_new: &mut [f64]) {
        d_new[0] = limit_mode(self.unlimited(io), self.yMin, self.yMax, d_new[0]);
    }
}

// ---------------------------------------------------------------- sampled

/// A digital controller: the block `inner` evaluated at the ticks `startTime + k·period` only
/// (time events), its inputs sampled there, its outputs held until the next tick (zero-order
/// hold) and its states advanced from tick to tick by forward Euler, `x_{k+1} = x_k +
/// period·f(x_k, u_k)` (the discrete PI of a 1 kHz servo). Its outputs have no feedthrough
/// between ticks; `inner` must have no flange, discrete states or zero crossings. Signals:
/// the inner states `<name>.<state>` and outputs as `inner`'s.
#[derive(Clone, Debug)]
pub struct Sampled {
    /// The sample period \[s\] (> 0).
    pub period: f64,
    /// The first tick \[s\].
    pub startTime: f64,
    /// The block sampled.
    pub inner: Arc<dyn Component>,
}

impl Sampled {
    /// `inner` sampled every `period` \[s\] from time 0.
    pub fn new(period: f64, inner: impl Component + 'static) -> Self {
        Sampled {
            period,
            startTime: 0.0,
            inner: Arc::new(inner),
        }
    }
    fn counts(&self) -> (usize, usize) {
        (self.inner.states().len(), self.inner.outputs().len())
    }
    /// The tick at `t` \[s\] (its index), if `t` is one (within 1e-9 of a period).
    fn tick(&self, t: f64) -> Option<f64> {
        let k = ((t - self.startTime) / self.period).round();
        (k >= 0.0 && (t - (self.startTime + k * self.period)).abs() <= 1e-9 * self.period)
            .then_some(k)
    }
}

impl Component for Sampled {
    fn kind(&self) -> &'static str {
        "Sampled"
    }
    /// Its output is a discrete state: every partial derivative is 0.
    fn provides_jacobian(&self) -> bool {
        true
    }
    fn inputs(&self) -> Vec<PortSpec> {
        self.inner.inputs()
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        let mut o = self.inner.outputs();
        for s in &mut o {
            s.feedthrough = false;
        }
        o
    }
    /// `[last tick, inner states…, held outputs…]`.
    fn discrete_states(&self) -> Vec<StateSpec> {
        let mut d = vec![StateSpec::new("tick", "1", -1.0, 1.0)];
        d.extend(self.inner.states());
        for o in self.inner.outputs() {
            d.push(StateSpec::new(format!("{}_held", o.name), o.unit, 0.0, 1.0));
        }
        d
    }
    fn check(&self) -> Result<(), String> {
        positive("period", self.period)?;
        finite("startTime", self.startTime)?;
        if !self.inner.flanges().is_empty()
            || !self.inner.discrete_states().is_empty()
            || self.inner.n_crossings() > 0
        {
            return Err(format!(
                "the sampled block ({}) has flanges, discrete states or zero crossings: sample a block with continuous states and outputs only",
                self.inner.kind()
            ));
        }
        self.inner.check()
    }
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]) {
        // The held outputs end the discrete states (no allocation: the residual calls this).
        let n = io.d.len();
        y.copy_from_slice(&io.d[n - y.len()..]);
    }
    fn next_time_event(&self, t: f64, _d: &[f64]) -> Option<f64> {
        let k = ((t - self.startTime) / self.period).floor() + 1.0;
        let mut next = self.startTime + k.max(0.0) * self.period;
        // A tick within rounding of `t` is `t`'s own.
        if next <= t + 1e-9 * self.period {
            next += self.period;
        }
        Some(next)
    }
    fn event(&self, io: &ComponentIo<'_>, d_new: &mut [f64]) {
        let Some(k) = self.tick(io.t) else {
            return;
        };
        if d_new[0] == k {
            return; // this tick was taken (another component's event at the same instant)
        }
        let (nx, ny) = self.counts();
        let mut scratch = vec![0.0; nx.max(1) + ny.max(1)];
        let (xdot, y) = scratch.split_at_mut(nx.max(1));
        let x = io.d[1..1 + nx].to_vec();
        let inner_io = ComponentIo {
            t: io.t,
            x: &x,
            d: &[],
            u: io.u,
            flanges: &[],
        };
        self.inner.outputs_at(&inner_io, &mut y[..ny]);
        self.inner.derivatives(&inner_io, &mut xdot[..nx], &mut []);
        d_new[0] = k;
        for i in 0..nx {
            d_new[1 + i] = x[i] + self.period * xdot[i];
        }
        d_new[1 + nx..1 + nx + ny].copy_from_slice(&y[..ny]);
    }
}

// ---------------------------------------------------------------- drive

/// The gear of a [`Drive`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Gear {
    /// A rigid ideal gear: the motor angle is `ratio·q`; the motor's inertia reflected to the
    /// joint (`ratio²·J_motor`) and its torque (`ratio·τ_motor`) act on the coordinate, with
    /// no state of its own.
    Rigid,
    /// An elastic gear: a spring `c` [N·m/rad] and damper `d` [N·m·s/rad] on the joint's side
    /// between `φ_motor/ratio` and `q`; states the deflection `phi_gear = φ_motor/ratio − q`
    /// \[rad\] and the motor speed `motor_w` [rad/s].
    Elastic {
        /// Stiffness on the joint's side [N·m/rad] (> 0).
        c: f64,
        /// Damping on the joint's side [N·m·s/rad] (≥ 0).
        d: f64,
    },
}

/// The motor of a [`Drive`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Motor {
    /// A torque source: input `tau` [N·m] is the motor's torque.
    Torque,
    /// A DC motor with armature resistance `R` \[Ω\], inductance `L` \[H\] and motor constant
    /// `k` [N·m/A = V·s/rad]: input `v` \[V\], state the current `i` \[A\],
    /// `L·di/dt = v − R·i − k·ω_motor`, `τ_motor = k·i`.
    Dc {
        /// Armature resistance \[Ω\] (≥ 0).
        R: f64,
        /// Armature inductance \[H\] (> 0).
        L: f64,
        /// Motor constant [N·m/A] (> 0).
        k: f64,
    },
}

/// A motor with inertia `J_motor` driving a joint coordinate through a gear of ratio `ratio`
/// (motor angle = `ratio` × joint angle): Modia3D's servo drive (`Inertia` + `IdealGear` on a
/// `RevoluteWithFlange`), with an elastic gear or a DC motor as options. On a prismatic
/// coordinate the ratio is [rad/m] and the reflected inertia \[kg\]. Outputs: `motor_phi`
/// \[rad\], `motor_w` [rad/s], `tau_motor` [N·m] (the motor's torque) and `tau_load` (the
/// gear's torque on the joint, [N·m] or \[N\]).
#[derive(Clone, Debug, PartialEq)]
pub struct Drive {
    /// The joint driven.
    pub joint: String,
    /// Its coordinate; `None` for a joint with one scalar coordinate.
    pub coordinate: Option<String>,
    /// Gear ratio, motor angle per joint coordinate (≠ 0).
    pub ratio: f64,
    /// Motor (rotor) inertia [kg·m²] (≥ 0; > 0 with an elastic gear).
    pub J_motor: f64,
    /// The gear.
    pub gear: Gear,
    /// The motor.
    pub motor: Motor,
}

impl Drive {
    /// A torque-source motor of inertia `J_motor` on joint `joint`'s single coordinate through
    /// a rigid gear `ratio`.
    pub fn rigid(joint: &str, ratio: f64, J_motor: f64) -> Self {
        Drive {
            joint: joint.to_string(),
            coordinate: None,
            ratio,
            J_motor,
            gear: Gear::Rigid,
            motor: Motor::Torque,
        }
    }
    /// Drives coordinate `c` of the joint.
    pub fn coordinate(mut self, c: &str) -> Self {
        self.coordinate = Some(c.to_string());
        self
    }
    /// An elastic gear of stiffness `c` [N·m/rad] and damping `d` [N·m·s/rad].
    pub fn elastic(mut self, c: f64, d: f64) -> Self {
        self.gear = Gear::Elastic { c, d };
        self
    }
    /// A DC motor (resistance `R` \[Ω\], inductance `L` \[H\], constant `k` [N·m/A]).
    pub fn dc_motor(mut self, R: f64, L: f64, k: f64) -> Self {
        self.motor = Motor::Dc { R, L, k };
        self
    }
    /// Index of the current `i` among the states, and the number of gear states.
    fn gear_states(&self) -> usize {
        match self.gear {
            Gear::Rigid => 0,
            Gear::Elastic { .. } => 2,
        }
    }
    /// Motor angle and speed and the gear's torque on the joint.
    fn motion(&self, io: &ComponentIo<'_>) -> (f64, f64, f64) {
        let f = io.flanges[0];
        match self.gear {
            Gear::Rigid => (self.ratio * f.position, self.ratio * f.velocity, 0.0),
            Gear::Elastic { c, d } => {
                let (dphi, w) = (io.x[0], io.x[1]);
                let rel_w = w / self.ratio - f.velocity;
                (self.ratio * (f.position + dphi), w, c * dphi + d * rel_w)
            }
        }
    }
    fn motor_torque(&self, io: &ComponentIo<'_>) -> f64 {
        match self.motor {
            Motor::Torque => io.u[0],
            Motor::Dc { k, .. } => k * io.x[self.gear_states()],
        }
    }
}

impl Component for Drive {
    fn kind(&self) -> &'static str {
        "Drive"
    }
    fn provides_jacobian(&self) -> bool {
        true
    }
    fn jacobian(&self, _io: &ComponentIo<'_>, jac: &mut ComponentJacobian<'_>) {
        let n = self.ratio;
        let ng = self.gear_states();
        // τ_motor: the input, or k·i.
        let set_tau_m = |jac: &mut ComponentJacobian<'_>, i: usize, scale: f64, out: u8| {
            // d(scale·τ_m) into output i (out 0), flange i (out 1) or ẋ_i (out 2).
            match self.motor {
                Motor::Torque => match out {
                    0 => jac.y_u(i, 0, scale),
                    1 => jac.flange_u(i, 0, scale),
                    _ => jac.f_u(i, 0, scale),
                },
                Motor::Dc { k, .. } => match out {
                    0 => jac.y_x(i, ng, scale * k),
                    1 => jac.flange_x(i, ng, scale * k),
                    _ => jac.f_x(i, ng, scale * k),
                },
            }
        };
        set_tau_m(jac, 2, 1.0, 0);
        match self.gear {
            Gear::Rigid => {
                set_tau_m(jac, 3, n, 0);
                set_tau_m(jac, 0, n, 1);
            }
            Gear::Elastic { c, d } => {
                // φ = N·(q + δ), ω = x_1, τ_gear = c·δ + d·(ω/N − q̇).
                jac.y_x(0, 0, n);
                jac.y_x(1, 1, 1.0);
                jac.y_x(3, 0, c);
                jac.y_x(3, 1, d / n);
                jac.flange_x(0, 0, c);
                jac.flange_x(0, 1, d / n);
                // δ̇ = ω/N − q̇; ω̇ = (τ_m − τ_gear/N)/J.
                jac.f_x(0, 1, 1.0 / n);
                jac.f_x(1, 0, -c / (n * self.J_motor));
                jac.f_x(1, 1, -d / (n * n * self.J_motor));
                set_tau_m(jac, 1, 1.0 / self.J_motor, 2);
            }
        }
        if let Motor::Dc { R, L, k } = self.motor {
            // L·di/dt = v − R·i − k·ω, ω = x_1 (elastic) or N·q̇ (rigid: held).
            jac.f_u(ng, 0, 1.0 / L);
            jac.f_x(ng, ng, -R / L);
            if ng == 2 {
                jac.f_x(ng, 1, -k / L);
            }
        }
    }
    fn inputs(&self) -> Vec<PortSpec> {
        match self.motor {
            Motor::Torque => vec![PortSpec::new("tau", "N·m")],
            Motor::Dc { .. } => vec![PortSpec::new("v", "V")],
        }
    }
    fn outputs(&self) -> Vec<OutputSpec> {
        let torque_through = matches!(self.motor, Motor::Torque);
        vec![
            OutputSpec::new("motor_phi", "rad", false),
            OutputSpec::new("motor_w", "rad/s", false),
            OutputSpec::new("tau_motor", "N·m", torque_through),
            OutputSpec::new(
                "tau_load",
                "N·m",
                torque_through && matches!(self.gear, Gear::Rigid),
            ),
        ]
    }
    fn states(&self) -> Vec<StateSpec> {
        let mut s = vec![];
        if let Gear::Elastic { .. } = self.gear {
            s.push(StateSpec::new("phi_gear", "rad", 0.0, 1e-3));
            s.push(StateSpec::new("motor_w", "rad/s", 0.0, 1.0));
        }
        if let Motor::Dc { .. } = self.motor {
            s.push(StateSpec::new("i", "A", 0.0, 1.0));
        }
        s
    }
    fn flanges(&self) -> Vec<FlangeSpec> {
        vec![FlangeSpec {
            joint: self.joint.clone(),
            coordinate: self.coordinate.clone(),
            inertia: match self.gear {
                Gear::Rigid => self.ratio * self.ratio * self.J_motor,
                Gear::Elastic { .. } => 0.0,
            },
        }]
    }
    fn check(&self) -> Result<(), String> {
        if !(self.ratio.is_finite() && self.ratio != 0.0) {
            return Err(format!(
                "ratio = {} must be finite and non-zero",
                self.ratio
            ));
        }
        if !(self.J_motor.is_finite() && self.J_motor >= 0.0) {
            return Err(format!(
                "J_motor = {} kg·m² must be finite and ≥ 0",
                self.J_motor
            ));
        }
        if let Gear::Elastic { c, d } = self.gear {
            positive("the gear's stiffness c", c)?;
            if !(d.is_finite() && d >= 0.0) {
                return Err(format!("the gear's damping d = {d} must be finite and ≥ 0"));
            }
            positive(
                "J_motor (an elastic gear's motor needs an inertia)",
                self.J_motor,
            )?;
        }
        if let Motor::Dc { R, L, k } = self.motor {
            if !(R.is_finite() && R >= 0.0) {
                return Err(format!("the motor's R = {R} Ω must be finite and ≥ 0"));
            }
            positive("the motor's L", L)?;
            positive("the motor's k", k)?;
        }
        Ok(())
    }
    fn outputs_at(&self, io: &ComponentIo<'_>, y: &mut [f64]) {
        let (phi, w, tau_gear) = self.motion(io);
        let tau_m = self.motor_torque(io);
        y[0] = phi;
        y[1] = w;
        y[2] = tau_m;
        y[3] = match self.gear {
            Gear::Rigid => self.ratio * tau_m,
            Gear::Elastic { .. } => tau_gear,
        };
    }
    fn derivatives(&self, io: &ComponentIo<'_>, xdot: &mut [f64], flange: &mut [f64]) {
        let (_, w, tau_gear) = self.motion(io);
        let tau_m = self.motor_torque(io);
        let ng = self.gear_states();
        match self.gear {
            Gear::Rigid => flange[0] = self.ratio * tau_m,
            Gear::Elastic { .. } => {
                xdot[0] = w / self.ratio - io.flanges[0].velocity;
                xdot[1] = (tau_m - tau_gear / self.ratio) / self.J_motor;
                flange[0] = tau_gear;
            }
        }
        if let Motor::Dc { R, L, k } = self.motor {
            xdot[ng] = (io.u[0] - R * io.x[ng] - k * w) / L;
        }
    }
}
