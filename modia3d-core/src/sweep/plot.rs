//! Sweep stage, plots of a table: a heat map of one column over two grid parameters, and a
//! scatter plot of one column against another (colour by a third), as SVG or PNG through the
//! results stage's renderer (`results/plot.rs`: same font, same encoder). Reads a table only.
#![deny(clippy::indexing_slicing)]

use super::{SweepError, SweepTable};
use crate::results::plot::{render_bytes, Drawing};
use crate::results::plot_axis::{TickAxis, X_TICKS, Y_TICKS};
use crate::PlotFormat;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// Viridis (matplotlib) at 0, 0.25, 0.5, 0.75, 1, linearly interpolated between.
const VIRIDIS: [(f64, f64, f64); 5] = [
    (68.0, 1.0, 84.0),
    (59.0, 82.0, 139.0),
    (33.0, 145.0, 140.0),
    (94.0, 201.0, 98.0),
    (253.0, 231.0, 37.0),
];

/// Colour of a cell or dot whose value is NaN (a failed run).
const MISSING: RGBColor = RGBColor(200, 200, 200);

fn viridis(u: f64) -> RGBColor {
    let u = if u.is_finite() {
        u.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = u * 4.0;
    let k = (x.floor() as usize).min(3);
    let f = x - k as f64;
    let (Some(a), Some(b)) = (VIRIDIS.get(k), VIRIDIS.get(k + 1)) else {
        return MISSING;
    };
    let mix = |p: f64, q: f64| (p + f * (q - p)).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// One plotted column: its label `name [unit]` and values per row.
struct Series {
    label: String,
    values: Vec<f64>,
}

/// What a sweep plot draws.
enum Kind {
    /// Cells of a grid: the sorted distinct x and y values, and the cell edges.
    Heatmap {
        x_edges: Vec<f64>,
        y_edges: Vec<f64>,
        xs: Vec<f64>,
        ys: Vec<f64>,
    },
    Scatter,
}

struct SweepFigure {
    title: Option<String>,
    x: Series,
    y: Series,
    /// Colour values (the heat map's z, or the scatter's colour column).
    z: Option<Series>,
    kind: Kind,
}

impl SweepTable {
    fn series(&self, name: &str) -> Result<Series, SweepError> {
        let values = self
            .column(name)
            .ok_or_else(|| SweepError::InvalidOutputs {
                reason: format!(
                    "no column `{name}` to plot; the columns are: {}",
                    self.params
                        .iter()
                        .chain(&self.outputs)
                        .map(|c| c.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            })?;
        let unit = self
            .params
            .iter()
            .chain(&self.outputs)
            .find(|c| c.name == name)
            .map(|c| c.unit.as_str())
            .unwrap_or_default();
        Ok(Series {
            label: match unit {
                "" => name.to_string(),
                u => format!("{name} [{u}]"),
            },
            values,
        })
    }

    /// A heat map of column `z` over the parameters `x` and `y` of a grid: one cell per
    /// distinct `(x, y)` (cells centred on the values, edges half-way between neighbours),
    /// coloured by `z` on the viridis scale with a colour bar labelled `z [unit]`; cells whose
    /// run failed (NaN) are grey. Written as SVG or PNG after the extension of `path`.
    pub fn plot_heatmap(
        &self,
        x: &str,
        y: &str,
        z: &str,
        path: impl AsRef<Path>,
        title: Option<&str>,
    ) -> Result<(), SweepError> {
        let (xs, ys) = (self.series(x)?, self.series(y)?);
        let distinct = |v: &[f64]| {
            let mut d: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
            d.sort_by(f64::total_cmp);
            d.dedup();
            d
        };
        let (dx, dy) = (distinct(&xs.values), distinct(&ys.values));
        let figure = SweepFigure {
            title: title.map(str::to_string),
            kind: Kind::Heatmap {
                x_edges: edges(&dx),
                y_edges: edges(&dy),
                xs: dx,
                ys: dy,
            },
            x: xs,
            y: ys,
            z: Some(self.series(z)?),
        };
        write(&figure, path.as_ref())
    }

    /// A scatter plot of column `y` over column `x`, one dot per row (rows where either is
    /// NaN left out), coloured by column `color` on the viridis scale when given (NaN: grey).
    pub fn plot_scatter(
        &self,
        x: &str,
        y: &str,
        color: Option<&str>,
        path: impl AsRef<Path>,
        title: Option<&str>,
    ) -> Result<(), SweepError> {
        let figure = SweepFigure {
            title: title.map(str::to_string),
            x: self.series(x)?,
            y: self.series(y)?,
            z: color.map(|c| self.series(c)).transpose()?,
            kind: Kind::Scatter,
        };
        write(&figure, path.as_ref())
    }
}

/// Cell edges around sorted distinct centres: half-way between neighbours, the outer ones
/// half a spacing out (±0.5 for a single value).
fn edges(c: &[f64]) -> Vec<f64> {
    let mids: Vec<f64> = c
        .iter()
        .zip(c.iter().skip(1))
        .map(|(a, b)| 0.5 * (a + b))
        .collect();
    match (c.first(), c.last(), mids.first(), mids.last()) {
        (Some(&first), Some(&last), Some(&m0), Some(&m1)) => {
            let mut e = vec![2.0 * first - m0];
            e.extend(&mids);
            e.push(2.0 * last - m1);
            e
        }
        (Some(&v), ..) => vec![v - 0.5, v + 0.5],
        _ => vec![0.0, 1.0],
    }
}

fn write(figure: &SweepFigure, path: &Path) -> Result<(), SweepError> {
    let export = |reason: String| SweepError::Export {
        path: path.display().to_string(),
        reason,
    };
    let format = PlotFormat::from_path(path)
        .ok_or_else(|| export("the file name must end in `.svg` or `.png`".into()))?;
    let bytes = render_bytes(figure, format, (860, 640)).map_err(export)?;
    std::fs::write(path, bytes).map_err(|source| SweepError::Io {
        path: path.display().to_string(),
        source,
    })
}

/// The smallest and largest finite value of `v`; `None` without finite values.
fn finite_range(v: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = v
        .filter(|x| x.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
    (lo <= hi).then_some((lo, hi))
}

/// [`finite_range`] padded by 5 % on each side (±0.5 when flat).
fn range(v: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    finite_range(v).map(|(lo, hi)| {
        let pad = if hi > lo { 0.05 * (hi - lo) } else { 0.5 };
        (lo - pad, hi + pad)
    })
}

impl Drawing for SweepFigure {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String> {
        let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        root.fill(&WHITE).map_err(err)?;
        let area = match &self.title {
            Some(t) => root.titled(t, ("sans-serif", 22)).map_err(err)?,
            None => root.clone(),
        };
        let (main, bar) = match &self.z {
            Some(_) => {
                let (w, _) = area.dim_in_pixel();
                area.split_horizontally(w.saturating_sub(130))
            }
            None => (area.clone(), area.margin(0, 0, 0, 0)),
        };
        let z_range = self
            .z
            .as_ref()
            .and_then(|z| finite_range(z.values.iter().copied()));
        let colour = |v: f64| match z_range {
            Some((lo, hi)) if v.is_finite() => {
                viridis(if hi > lo { (v - lo) / (hi - lo) } else { 0.5 })
            }
            _ => MISSING,
        };
        let ((x0, x1), (y0, y1)) = match &self.kind {
            Kind::Heatmap {
                x_edges, y_edges, ..
            } => (
                (
                    x_edges.first().copied().unwrap_or(0.0),
                    x_edges.last().copied().unwrap_or(1.0),
                ),
                (
                    y_edges.first().copied().unwrap_or(0.0),
                    y_edges.last().copied().unwrap_or(1.0),
                ),
            ),
            Kind::Scatter => (
                range(self.x.values.iter().copied())
                    .ok_or_else(|| format!("`{}` has no finite values", self.x.label))?,
                range(self.y.values.iter().copied())
                    .ok_or_else(|| format!("`{}` has no finite values", self.y.label))?,
            ),
        };
        let mut chart = ChartBuilder::on(&main)
            .margin(14)
            .x_label_area_size(48)
            .y_label_area_size(84)
            .build_cartesian_2d(
                TickAxis::new(x0, x1, X_TICKS),
                TickAxis::new(y0, y1, Y_TICKS),
            )
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc(self.x.label.as_str())
            .y_desc(self.y.label.as_str())
            .label_style(("sans-serif", 13))
            .axis_desc_style(("sans-serif", 15))
            .x_labels(X_TICKS)
            .y_labels(Y_TICKS)
            .disable_mesh()
            .draw()
            .map_err(err)?;
        let z = self
            .z
            .as_ref()
            .map(|z| z.values.as_slice())
            .unwrap_or_default();
        match &self.kind {
            Kind::Heatmap {
                x_edges,
                y_edges,
                xs,
                ys,
            } => {
                let cell = |v: f64, centres: &[f64], e: &[f64]| {
                    let k = centres.iter().position(|&c| c == v)?;
                    Some((*e.get(k)?, *e.get(k + 1)?))
                };
                let cells = self
                    .x
                    .values
                    .iter()
                    .zip(&self.y.values)
                    .enumerate()
                    .filter_map(|(i, (&xv, &yv))| {
                        let (xa, xb) = cell(xv, xs, x_edges)?;
                        let (ya, yb) = cell(yv, ys, y_edges)?;
                        let c = colour(z.get(i).copied().unwrap_or(f64::NAN));
                        Some(Rectangle::new([(xa, ya), (xb, yb)], c.filled()))
                    });
                chart.draw_series(cells).map_err(err)?;
            }
            Kind::Scatter => {
                let dots = self
                    .x
                    .values
                    .iter()
                    .zip(&self.y.values)
                    .enumerate()
                    .filter(|(_, (x, y))| x.is_finite() && y.is_finite())
                    .map(|(i, (&x, &y))| {
                        let c = match self.z {
                            Some(_) => colour(z.get(i).copied().unwrap_or(f64::NAN)),
                            None => RGBColor(31, 119, 180),
                        };
                        Circle::new((x, y), 4, c.filled())
                    });
                chart.draw_series(dots).map_err(err)?;
            }
        }
        if let (Some(zs), Some((lo, hi))) = (&self.z, z_range) {
            let hi = if hi > lo { hi } else { lo + 1.0 };
            let mut bar_chart = ChartBuilder::on(&bar)
                .margin_top(14)
                .margin_bottom(62)
                .margin_right(8)
                .y_label_area_size(80)
                .build_cartesian_2d(0.0..1.0, TickAxis::new(lo, hi, Y_TICKS))
                .map_err(err)?;
            bar_chart
                .configure_mesh()
                .disable_x_axis()
                .disable_mesh()
                .y_desc(zs.label.as_str())
                .label_style(("sans-serif", 13))
                .axis_desc_style(("sans-serif", 15))
                .y_labels(Y_TICKS)
                .draw()
                .map_err(err)?;
            let steps = 100;
            let strips = (0..steps).map(|k| {
                let a = lo + (hi - lo) * k as f64 / steps as f64;
                let b = lo + (hi - lo) * (k + 1) as f64 / steps as f64;
                let c = viridis((k as f64 + 0.5) / steps as f64);
                Rectangle::new([(0.0, a), (1.0, b)], c.filled())
            });
            bar_chart.draw_series(strips).map_err(err)?;
        }
        root.present().map_err(err)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cell_edges_lie_half_way() {
        assert_eq!(edges(&[1.0, 2.0, 4.0]), [0.5, 1.5, 3.0, 5.0]);
        assert_eq!(edges(&[1.0, 3.0]), [0.0, 2.0, 4.0]);
        assert_eq!(edges(&[2.0]), [1.5, 2.5]);
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
    }

    /// A heat map over a grid whose parameter runs from -0.2 to 0.2 (cell edges ±0.25, where
    /// plotters' accumulated ticks missed 0) and a scatter plot render as SVG with the shared
    /// axis ticks: a `0` label, no rounding residue such as `e-17`, both colour bar ends.
    #[test]
    fn sweep_plots_label_their_axes_in_one_format() {
        let series = |label: &str, values: &[f64]| Series {
            label: label.into(),
            values: values.to_vec(),
        };
        let xs = [-0.2, -0.1, 0.0, 0.1, 0.2];
        let x: Vec<f64> = xs.iter().flat_map(|&v| [v, v]).collect();
        let y: Vec<f64> = xs.iter().flat_map(|_| [1.0e5, 2.0e5]).collect();
        let z: Vec<f64> = (0..10).map(|k| 0.1 * k as f64).collect();
        let heatmap = SweepFigure {
            title: Some("grid".into()),
            kind: Kind::Heatmap {
                x_edges: edges(&xs),
                y_edges: edges(&[1.0e5, 2.0e5]),
                xs: xs.to_vec(),
                ys: vec![1.0e5, 2.0e5],
            },
            x: series("cor", &x),
            y: series("h0 [m]", &y),
            z: Some(series("e", &z)),
        };
        let scatter = SweepFigure {
            title: None,
            kind: Kind::Scatter,
            x: series("cor", &x),
            y: series("h0 [m]", &y),
            z: None,
        };
        for figure in [heatmap, scatter] {
            let svg = render_bytes(&figure, PlotFormat::Svg, (860, 640)).expect("svg");
            let svg = String::from_utf8(svg).expect("utf-8");
            assert!(svg.contains(">\n0\n<"), "a 0 tick");
            assert!(!svg.contains("e-1"), "no rounding residue");
            assert!(svg.contains(">\n-0.2\n<") || svg.contains(">\n-0.20\n<"));
        }
    }
}
