//! Results stage, plots: line charts of signals over time, one subplot per unit (or per group
//! the user gives), each y axis labelled with its unit, a title, legends, vertical markers at
//! contact events, an optional logarithmic y axis; written as SVG (plotters' SVG backend) or
//! PNG (plotters' bitmap backend, encoded by the `png` crate). Text is laid out and, for PNG,
//! rasterised with the DejaVu Sans font bundled in `modia3d-core/assets/fonts/` (through
//! `ab_glyph`: `plot_text.rs`), so no system font stack is needed. Ticks and their labels come
//! from `plot_axis.rs` (whole multiples of a 1-2-5 step, one format per axis), the legend's
//! place from `plot_legend.rs` (where the fewest curve segments are). Reads a
//! `SimulationResult` only.

use super::plot_axis::{TickAxis, TickFormat, X_TICKS, Y_TICKS};
use super::plot_legend::legend_spot;
use super::plot_text::PngBackend;
use super::{ResultError, SimulationResult};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;

/// Colours of successive curves (Matplotlib's "tab10" without its red, which marks events).
const PALETTE: [RGBColor; 9] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Colour of the contact-event markers (vertical lines).
pub const EVENT_MARKER_COLOR: [u8; 3] = [240, 150, 150];

/// The bundled font (DejaVu Sans; licence in `modia3d-core/assets/fonts/LICENSE-DejaVu.txt`).
const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// File format of a plot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlotFormat {
    /// SVG document (text as `<text>` elements).
    Svg,
    /// PNG image, RGB, 8 bits per channel.
    Png,
}

impl PlotFormat {
    /// The format named by a path's extension (`.svg` or `.png`, any case); `None` otherwise.
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "svg" => Some(PlotFormat::Svg),
            "png" => Some(PlotFormat::Png),
            _ => None,
        }
    }
}

/// How a plot is drawn: size, title, markers, axis scale.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotOptions {
    /// Width and height of the whole figure \[px\] (default 900 × 300 per subplot, at least 540
    /// high; `None`); each at least 200.
    pub size: Option<(u32, u32)>,
    /// Title above the subplots (default none).
    pub title: Option<String>,
    /// Vertical lines at the times of contact events (events at which a pair entered or left
    /// the contact set), default true.
    pub event_markers: bool,
    /// Logarithmic y axes (default false); values ≤ 0 are left out of the curves.
    pub log_y: bool,
}

impl Default for PlotOptions {
    fn default() -> Self {
        PlotOptions {
            size: None,
            title: None,
            event_markers: true,
            log_y: false,
        }
    }
}

impl PlotOptions {
    /// Default options: automatic size, no title, event markers, linear axes.
    pub fn new() -> Self {
        Self::default()
    }
    /// Sets the figure size, width × height \[px\].
    pub fn size(mut self, width: u32, height: u32) -> Self {
        self.size = Some((width, height));
        self
    }
    /// Sets the title.
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = Some(title.into());
        self
    }
    /// Turns the contact-event markers on or off.
    pub fn event_markers(mut self, on: bool) -> Self {
        self.event_markers = on;
        self
    }
    /// Turns logarithmic y axes on or off.
    pub fn log_y(mut self, on: bool) -> Self {
        self.log_y = on;
        self
    }
}

/// One curve: legend label, unit, values per time point.
struct Curve {
    label: String,
    unit: &'static str,
    values: Vec<f64>,
}

/// One subplot: its curves and y-axis label.
struct Panel {
    curves: Vec<Curve>,
    y_desc: String,
}

/// `-` for a dimensionless unit, the unit otherwise.
fn unit_text(unit: &str) -> &str {
    if unit == "1" {
        "-"
    } else {
        unit
    }
}

/// The quantity a unit measures, for axis labels.
fn quantity(unit: &str) -> &'static str {
    match unit {
        "m" => "length",
        "m/s" => "velocity",
        "rad" => "angle",
        "rad/s" => "angular velocity",
        "N" => "force",
        "N·m" => "torque",
        _ => "value",
    }
}

impl Panel {
    fn new(curves: Vec<Curve>) -> Self {
        let mut units: Vec<&str> = curves.iter().map(|c| c.unit).collect();
        units.sort_unstable();
        units.dedup();
        let y_desc = match (&units[..], &curves[..]) {
            ([u], [c]) => format!("{} [{}]", c.label, unit_text(u)),
            ([u], _) => format!("{} [{}]", quantity(u), unit_text(u)),
            _ => format!(
                "value [{}]",
                units
                    .iter()
                    .map(|u| unit_text(u))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        };
        Panel { curves, y_desc }
    }
}

/// Registers the bundled font with plotters once.
fn register_font() -> Result<(), String> {
    static DONE: std::sync::OnceLock<Result<(), String>> = std::sync::OnceLock::new();
    DONE.get_or_init(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
            .map_err(|_| "the bundled font cannot be read".to_string())
    })
    .clone()
}

impl SimulationResult {
    /// Plots signals over time with the default [`PlotOptions`]: one subplot per unit (in the
    /// order the units first appear), x axis `time [s]`, y axes labelled with their unit, one
    /// curve per component (a vector signal such as `"ball.r_abs"` gives `ball.r_abs[0]`,
    /// `[1]`, `[2]`), legends, and vertical lines at contact events. The format follows the
    /// extension: `.svg` or `.png`.
    ///
    /// ```no_run
    /// # fn f(result: &modia3d_core::SimulationResult) -> Result<(), modia3d_core::ResultError> {
    /// result.plot(&["rev.phi", "ball.r_abs[2]"], "out/pendulum.svg")?;
    /// result.plot(&["rev.phi", "ball.r_abs[2]"], "out/pendulum.png")?;
    /// # Ok(()) }
    /// ```
    ///
    /// Errors: [`ResultError::UnknownSignal`] for a name that is not a signal,
    /// [`ResultError::Export`] when there is nothing to plot or the extension is neither
    /// `.svg` nor `.png`, [`ResultError::Io`] when the file cannot be written.
    pub fn plot(&self, names: &[&str], path: impl AsRef<Path>) -> Result<(), ResultError> {
        self.plot_with(names, path, &PlotOptions::default())
    }

    /// [`plot`](Self::plot) with options (size, title, event markers, log axis).
    pub fn plot_with(
        &self,
        names: &[&str],
        path: impl AsRef<Path>,
        options: &PlotOptions,
    ) -> Result<(), ResultError> {
        let path = path.as_ref();
        let with_path = |e| relabel(e, path);
        let panels = self.panels_by_unit(names).map_err(with_path)?;
        self.write_plot(panels, path, options)
    }

    /// Plots one subplot per group of signal names, in the order given (e.g.
    /// `&[&["rev1.phi", "rev2.phi"], &["ball0|ball1.f_n"]]`); a group of several units lists
    /// them all on its y axis. Options and format as [`plot_with`](Self::plot_with).
    pub fn plot_groups(
        &self,
        groups: &[&[&str]],
        path: impl AsRef<Path>,
        options: &PlotOptions,
    ) -> Result<(), ResultError> {
        let path = path.as_ref();
        let with_path = |e| relabel(e, path);
        let panels = self.panels_by_group(groups).map_err(with_path)?;
        self.write_plot(panels, path, options)
    }

    /// The SVG document [`plot`](Self::plot) writes, as a string.
    pub fn plot_svg(&self, names: &[&str]) -> Result<String, ResultError> {
        let panels = self.panels_by_unit(names)?;
        let bytes = self.render(panels, PlotFormat::Svg, &PlotOptions::default())?;
        String::from_utf8(bytes).map_err(|e| export_error(e.to_string()))
    }

    /// The bytes of a plot of the given groups (one subplot each) in `format`.
    pub fn plot_bytes(
        &self,
        groups: &[&[&str]],
        format: PlotFormat,
        options: &PlotOptions,
    ) -> Result<Vec<u8>, ResultError> {
        let panels = self.panels_by_group(groups)?;
        self.render(panels, format, options)
    }

    fn write_plot(
        &self,
        panels: Vec<Panel>,
        path: &Path,
        options: &PlotOptions,
    ) -> Result<(), ResultError> {
        let with_path = |e| relabel(e, path);
        let format = PlotFormat::from_path(path).ok_or_else(|| {
            with_path(export_error(
                "unknown plot format: the file name must end in `.svg` or `.png`".into(),
            ))
        })?;
        let bytes = self.render(panels, format, options).map_err(with_path)?;
        std::fs::write(path, bytes).map_err(|source| ResultError::Io {
            path: path.display().to_string(),
            source,
        })
    }

    /// The curves of one signal name (one per component).
    fn curves(&self, name: &str) -> Result<Vec<Curve>, ResultError> {
        let s = self.signal(name)?;
        Ok((0..s.dim)
            .map(|i| Curve {
                label: if s.dim == 1 {
                    s.name.clone()
                } else {
                    format!("{}[{i}]", s.name)
                },
                unit: s.unit,
                values: s.component(i),
            })
            .collect())
    }

    fn panels_by_unit(&self, names: &[&str]) -> Result<Vec<Panel>, ResultError> {
        if names.is_empty() {
            return Err(export_error("no signal names given".into()));
        }
        let mut groups: Vec<Vec<Curve>> = vec![];
        for name in names {
            for c in self.curves(name)? {
                match groups
                    .iter_mut()
                    .find(|g| g.first().is_some_and(|f| f.unit == c.unit))
                {
                    Some(g) => g.push(c),
                    None => groups.push(vec![c]),
                }
            }
        }
        Ok(groups.into_iter().map(Panel::new).collect())
    }

    fn panels_by_group(&self, groups: &[&[&str]]) -> Result<Vec<Panel>, ResultError> {
        if groups.iter().all(|g| g.is_empty()) {
            return Err(export_error("no signal names given".into()));
        }
        let mut panels = vec![];
        for (i, group) in groups.iter().enumerate() {
            if group.is_empty() {
                return Err(export_error(format!(
                    "group {i} has no signal names: give at least one per subplot"
                )));
            }
            let mut curves = vec![];
            for name in group.iter() {
                curves.extend(self.curves(name)?);
            }
            panels.push(Panel::new(curves));
        }
        Ok(panels)
    }

    /// Times [s] of the events at which a pair entered or left the contact set.
    fn contact_event_times(&self) -> Vec<f64> {
        self.events
            .iter()
            .filter(|e| !e.started.is_empty() || !e.ended.is_empty())
            .map(|e| e.t)
            .collect()
    }

    fn render(
        &self,
        panels: Vec<Panel>,
        format: PlotFormat,
        options: &PlotOptions,
    ) -> Result<Vec<u8>, ResultError> {
        let time = self.time();
        let (Some(&t0), Some(&t_last)) = (time.first(), time.last()) else {
            return Err(export_error("the result has no time points".into()));
        };
        let t1 = if t_last > t0 { t_last } else { t0 + 1.0 };
        let (w, h) = options
            .size
            .unwrap_or((900, (300 * panels.len() as u32).max(540)));
        if w < 200 || h < 200 {
            return Err(export_error(format!(
                "plot size {w} × {h} px is too small: give at least 200 × 200"
            )));
        }
        let events = if options.event_markers {
            self.contact_event_times()
        } else {
            vec![]
        };
        let figure = Figure {
            time,
            x: (t0, t1),
            panels: &panels,
            events: &events,
            options,
            // Thick polylines in the bitmap rasteriser misplace sharp corners (see `panel`).
            segments: format == PlotFormat::Png,
        };
        render_bytes(&figure, format, (w, h)).map_err(export_error)
    }
}

/// A figure that can draw itself on any plotters backend.
pub(crate) trait Drawing {
    /// Draws the whole figure on `root`.
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String>;
}

/// The bytes of `drawing` as an SVG document or a PNG image (RGB, 8 bits) of `w` × `h` px,
/// with the bundled font registered.
pub(crate) fn render_bytes(
    drawing: &impl Drawing,
    format: PlotFormat,
    (w, h): (u32, u32),
) -> Result<Vec<u8>, String> {
    register_font()?;
    match format {
        PlotFormat::Svg => {
            let mut svg = String::new();
            drawing.draw(SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area())?;
            Ok(svg.into_bytes())
        }
        PlotFormat::Png => {
            let font = ab_glyph::FontRef::try_from_slice(FONT)
                .map_err(|_| "the bundled font cannot be read".to_string())?;
            let mut rgb = vec![0u8; w as usize * h as usize * 3];
            drawing.draw(PngBackend::new(&mut rgb, (w, h), font).into_drawing_area())?;
            let mut out = vec![];
            let mut enc = png::Encoder::new(&mut out, w, h);
            enc.set_color(png::ColorType::Rgb);
            enc.set_depth(png::BitDepth::Eight);
            let png_error = |e: png::EncodingError| e.to_string();
            let mut writer = enc.write_header().map_err(png_error)?;
            writer.write_image_data(&rgb).map_err(png_error)?;
            writer.finish().map_err(png_error)?;
            Ok(out)
        }
    }
}

/// An export error without a path yet (the caller names the file).
fn export_error(reason: String) -> ResultError {
    ResultError::Export {
        path: "<plot>".into(),
        reason,
    }
}

/// An export error named after the file it was for.
fn relabel(e: ResultError, path: &Path) -> ResultError {
    match e {
        ResultError::Export { reason, .. } => ResultError::Export {
            path: path.display().to_string(),
            reason,
        },
        e => e,
    }
}

/// Everything one figure draws.
struct Figure<'a> {
    time: &'a [f64],
    /// Time range [s].
    x: (f64, f64),
    panels: &'a [Panel],
    /// Marker times [s].
    events: &'a [f64],
    options: &'a PlotOptions,
    /// Draw curves segment by segment (the bitmap backend) instead of as polylines.
    segments: bool,
}

impl Drawing for Figure<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String> {
        let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        root.fill(&WHITE).map_err(err)?;
        let area = match &self.options.title {
            Some(t) => root.titled(t, ("sans-serif", 22)).map_err(err)?,
            None => root.clone(),
        };
        let areas = area.split_evenly((self.panels.len(), 1));
        let mut colours = PALETTE.iter().cycle();
        for (i, (panel, a)) in self.panels.iter().zip(&areas).enumerate() {
            let last = i + 1 == self.panels.len();
            let colours: Vec<RGBColor> =
                colours.by_ref().take(panel.curves.len()).copied().collect();
            let x = TickAxis::new(self.x.0, self.x.1, X_TICKS);
            if self.options.log_y {
                let (lo, hi) =
                    value_range(panel, |v| v > 0.0).ok_or_else(|| no_values(panel, "positive "))?;
                let (lo, hi) = if hi > lo {
                    (lo / (hi / lo).powf(0.05), hi * (hi / lo).powf(0.05))
                } else {
                    (lo / 2.0, hi * 2.0)
                };
                let y: plotters::coord::combinators::LogCoord<f64> = (lo..hi).log_scale().into();
                let format = TickFormat::log(lo, hi);
                let label = |v: f64| format.label(v);
                let axes = Axes {
                    x,
                    y,
                    label: &label,
                };
                self.panel(a, axes, (lo, hi), panel, &colours, last, |v| v > 0.0)?;
            } else {
                let (lo, hi) = value_range(panel, |_| true).ok_or_else(|| no_values(panel, ""))?;
                let pad = if hi > lo { 0.05 * (hi - lo) } else { 0.5 };
                let (lo, hi) = (lo - pad, hi + pad);
                let y = TickAxis::new(lo, hi, Y_TICKS);
                let label = |v: f64| y.label(v);
                let axes = Axes {
                    x,
                    y: y.clone(),
                    label: &label,
                };
                self.panel(a, axes, (lo, hi), panel, &colours, last, |_| true)?;
            }
        }
        root.present().map_err(err)
    }
}

/// A subplot's axes: time, values (linear or logarithmic), and the y tick labels.
struct Axes<'l, Y> {
    x: TickAxis,
    y: Y,
    label: &'l dyn Fn(f64) -> String,
}

/// One legend line: its text and the style of its sample line.
struct LegendEntry {
    text: String,
    style: ShapeStyle,
}

impl Figure<'_> {
    /// Draws one subplot with y axis spanning `lo..hi`; values for which `keep` is false are
    /// left out.
    #[allow(clippy::too_many_arguments)]
    fn panel<DB, Y>(
        &self,
        area: &DrawingArea<DB, Shift>,
        Axes { x, y, label }: Axes<'_, Y>,
        (lo, hi): (f64, f64),
        panel: &Panel,
        colours: &[RGBColor],
        x_label: bool,
        keep: impl Fn(f64) -> bool,
    ) -> Result<(), String>
    where
        DB: DrawingBackend,
        Y: Ranged<ValueType = f64> + plotters::coord::ranged1d::ValueFormatter<f64>,
    {
        let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        let x_format = x.clone();
        let mut chart = ChartBuilder::on(area)
            .margin(12)
            // Room for half the last time label, centred on the right edge.
            .margin_right(28)
            .x_label_area_size(if x_label { 44 } else { 28 })
            .y_label_area_size(84)
            .build_cartesian_2d(x, y)
            .map_err(err)?;
        let x_format = |v: &f64| x_format.label(*v);
        let y_format = |v: &f64| label(*v);
        let mut mesh = chart.configure_mesh();
        mesh.y_desc(panel.y_desc.as_str())
            .label_style(("sans-serif", 13))
            .axis_desc_style(("sans-serif", 15))
            .x_labels(X_TICKS)
            .y_labels(Y_TICKS)
            .x_label_formatter(&x_format)
            .y_label_formatter(&y_format)
            .light_line_style(RGBColor(235, 235, 235));
        if x_label {
            mesh.x_desc("time [s]");
        }
        mesh.draw().map_err(err)?;
        let [r, g, b] = EVENT_MARKER_COLOR;
        let marker = RGBColor(r, g, b);
        let mut legend = vec![];
        for &t in self.events {
            chart
                .draw_series(LineSeries::new([(t, lo), (t, hi)], marker.stroke_width(1)))
                .map_err(err)?;
        }
        if !self.events.is_empty() {
            legend.push(LegendEntry {
                text: "contact event".into(),
                style: marker.stroke_width(1),
            });
        }
        // The curves in pixels relative to the plotting area, for the legend's place.
        let base = chart.plotting_area().get_base_pixel();
        let mut drawn: Vec<Vec<(i32, i32)>> = vec![];
        for (c, &color) in panel.curves.iter().zip(colours) {
            let style = color.stroke_width(2);
            for run in self.runs(&c.values, &keep, |p| chart.backend_coord(p)) {
                if self.segments {
                    // Thick polylines in the bitmap rasteriser put the inner corner of a sharp
                    // spike far off the chart: draw its segments one by one (no joins).
                    let segments = run.windows(2).map(|w| PathElement::new(w.to_vec(), style));
                    chart.draw_series(segments).map_err(err)?;
                } else {
                    chart
                        .draw_series(LineSeries::new(run.iter().copied(), style))
                        .map_err(err)?;
                }
                drawn.push(
                    run.iter()
                        .map(|p| {
                            let (x, y) = chart.backend_coord(p);
                            (x - base.0, y - base.1)
                        })
                        .collect(),
                );
            }
            legend.push(LegendEntry {
                text: format!("{} [{}]", c.label, unit_text(c.unit)),
                style,
            });
        }
        draw_legend(&chart.plotting_area().strip_coord_spec(), &legend, &drawn)
    }
}

/// Draws the legend `entries` (a sample line and a text each, in a framed box on a translucent
/// white ground) on the plotting area `area` where the fewest segments of `curves` (pixels
/// relative to the area) are.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[LegendEntry],
    curves: &[Vec<(i32, i32)>],
) -> Result<(), String> {
    if entries.is_empty() {
        return Ok(());
    }
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let text_style =
        TextStyle::from(("sans-serif", 13).into_font()).pos(Pos::new(HPos::Left, VPos::Center));
    let (pad, sample, gap) = (8, 24, 8);
    let mut text_w = 0;
    let mut line_h = 13;
    for e in entries {
        let (w, h) = area.estimate_text_size(&e.text, &text_style).map_err(err)?;
        text_w = text_w.max(w as i32);
        line_h = line_h.max(h as i32);
    }
    let line_h = line_h + 4;
    let size = (
        pad + sample + gap + text_w + pad,
        pad + line_h * entries.len() as i32 + pad - 4,
    );
    let (w, h) = area.dim_in_pixel();
    let (x, y) = legend_spot((w as i32, h as i32), size, curves);
    let corners = [(x, y), (x + size.0, y + size.1)];
    area.draw(&Rectangle::new(corners, WHITE.mix(0.85).filled()))
        .map_err(err)?;
    area.draw(&Rectangle::new(corners, BLACK)).map_err(err)?;
    for (k, e) in entries.iter().enumerate() {
        let cy = y + pad + line_h * k as i32 + (line_h - 4) / 2;
        area.draw(&PathElement::new(
            vec![(x + pad, cy), (x + pad + sample, cy)],
            e.style,
        ))
        .map_err(err)?;
        area.draw(&Text::new(
            e.text.clone(),
            (x + pad + sample + gap, cy),
            text_style.clone(),
        ))
        .map_err(err)?;
    }
    Ok(())
}

impl Figure<'_> {
    /// The runs of consecutive drawable points `(t, v)` of a curve (finite and accepted by
    /// `keep`; a left-out value breaks the line instead of being bridged), one point per pixel
    /// step of `pixel` (consecutive points on one pixel would make zero-length segments).
    fn runs(
        &self,
        values: &[f64],
        keep: impl Fn(f64) -> bool,
        pixel: impl Fn(&(f64, f64)) -> (i32, i32),
    ) -> Vec<Vec<(f64, f64)>> {
        let mut runs: Vec<Vec<(f64, f64)>> = vec![];
        let mut current: Vec<(f64, f64)> = vec![];
        let mut last_pixel = None;
        for (&t, &v) in self.time.iter().zip(values) {
            if !(v.is_finite() && keep(v)) {
                if !current.is_empty() {
                    runs.push(std::mem::take(&mut current));
                }
                last_pixel = None;
                continue;
            }
            let p = Some(pixel(&(t, v)));
            if p != last_pixel {
                current.push((t, v));
            }
            last_pixel = p;
        }
        if !current.is_empty() {
            runs.push(current);
        }
        runs
    }
}

/// The smallest and largest finite value of a panel's curves that `keep` accepts.
fn value_range(panel: &Panel, keep: impl Fn(f64) -> bool) -> Option<(f64, f64)> {
    let (lo, hi) = panel
        .curves
        .iter()
        .flat_map(|c| c.values.iter().copied())
        .filter(|v| v.is_finite() && keep(*v))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    (lo <= hi).then_some((lo, hi))
}

/// The error for a subplot without values to draw.
fn no_values(panel: &Panel, which: &str) -> String {
    let names: Vec<&str> = panel.curves.iter().map(|c| c.label.as_str()).collect();
    format!(
        "no finite {which}values to plot in the subplot of {}",
        names.join(", ")
    )
}
