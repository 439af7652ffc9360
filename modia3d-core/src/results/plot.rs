//! Results stage, plots: line charts of signals over time as SVG (plotters' SVG backend; text is
//! left to the SVG viewer's fonts, so no font stack is built). Reads a `SimulationResult` only.

use super::{ResultError, SimulationResult};
use plotters::prelude::*;
use std::path::Path;

/// Colours of successive curves (Matplotlib's "tab10").
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// One curve: legend label, unit, values per time point.
struct Curve {
    label: String,
    unit: &'static str,
    values: Vec<f64>,
}

impl SimulationResult {
    /// Plots signals over time into one SVG chart of 900 × 540 px: x axis `time [s]`, y axis
    /// labelled with the signals' units, one curve per component (a vector signal such as
    /// `"ball.r_abs"` gives `ball.r_abs[0]`, `[1]`, `[2]`), and a legend.
    ///
    /// ```no_run
    /// # fn f(result: &modia3d_core::SimulationResult) -> Result<(), modia3d_core::ResultError> {
    /// result.plot(&["rev.phi", "ball.r_abs[2]"], "out/pendulum.svg")?;
    /// # Ok(()) }
    /// ```
    ///
    /// Errors: [`ResultError::UnknownSignal`] for a name that is not a signal,
    /// [`ResultError::Export`] when there is nothing to plot, [`ResultError::Io`] when the file
    /// cannot be written.
    pub fn plot(&self, names: &[&str], path: impl AsRef<Path>) -> Result<(), ResultError> {
        let path = path.as_ref();
        let svg = self.plot_svg(names).map_err(|e| match e {
            ResultError::Export { reason, .. } => ResultError::Export {
                path: path.display().to_string(),
                reason,
            },
            e => e,
        })?;
        std::fs::write(path, svg).map_err(|source| ResultError::Io {
            path: path.display().to_string(),
            source,
        })
    }

    /// The SVG document [`plot`](Self::plot) writes, as a string.
    pub fn plot_svg(&self, names: &[&str]) -> Result<String, ResultError> {
        let export = |reason: String| ResultError::Export {
            path: "<svg>".into(),
            reason,
        };
        if names.is_empty() {
            return Err(export("no signal names given".into()));
        }
        let time = self.time();
        let (Some(&t0), Some(&t_last)) = (time.first(), time.last()) else {
            return Err(export("the result has no time points".into()));
        };
        let mut curves = vec![];
        for name in names {
            let s = self.signal(name)?;
            for i in 0..s.dim {
                let label = if s.dim == 1 {
                    s.name.clone()
                } else {
                    format!("{}[{i}]", s.name)
                };
                curves.push(Curve {
                    label,
                    unit: s.unit,
                    values: s.component(i),
                });
            }
        }
        let mut t1 = t_last;
        if t1 <= t0 {
            t1 = t0 + 1.0;
        }
        let finite = curves
            .iter()
            .flat_map(|c| c.values.iter().copied())
            .filter(|v| v.is_finite());
        let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
        if lo > hi {
            return Err(export("no finite values to plot".into()));
        }
        let pad = if hi > lo { 0.05 * (hi - lo) } else { 0.5 };
        let (lo, hi) = (lo - pad, hi + pad);

        let mut units: Vec<&str> = curves.iter().map(|c| c.unit).collect();
        units.dedup();
        units.sort_unstable();
        units.dedup();
        let y_desc = if let [only] = units[..] {
            let unit = if only == "1" { "-" } else { only };
            format!(
                "{} [{unit}]",
                match &curves[..] {
                    [c] => c.label.as_str(),
                    _ => "value",
                }
            )
        } else {
            format!("value [{}]", units.join(", "))
        };

        let mut svg = String::new();
        {
            let backend = SVGBackend::with_string(&mut svg, (900, 540));
            let root = backend.into_drawing_area();
            let draw = |e: DrawingAreaErrorKind<std::io::Error>| export(e.to_string());
            root.fill(&WHITE).map_err(draw)?;
            let mut chart = ChartBuilder::on(&root)
                .margin(16)
                .x_label_area_size(44)
                .y_label_area_size(72)
                .build_cartesian_2d(t0..t1, lo..hi)
                .map_err(draw)?;
            chart
                .configure_mesh()
                .x_desc("time [s]")
                .y_desc(y_desc)
                .light_line_style(RGBColor(235, 235, 235))
                .draw()
                .map_err(draw)?;
            for (c, color) in curves.iter().zip(PALETTE.iter().cycle()) {
                let points = time
                    .iter()
                    .zip(&c.values)
                    .filter(|(_, v)| v.is_finite())
                    .map(|(&t, &v)| (t, v));
                let unit = if c.unit == "1" { "-" } else { c.unit };
                chart
                    .draw_series(LineSeries::new(points, color.stroke_width(2)))
                    .map_err(draw)?
                    .label(format!("{} [{unit}]", c.label))
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                    });
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .draw()
                .map_err(draw)?;
            root.present().map_err(draw)?;
        }
        Ok(svg)
    }
}
