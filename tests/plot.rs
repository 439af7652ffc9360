//! Plots of a mixed-unit run (Newton's cradle: pendulum angle [rad], contact force [N]) as PNG
//! and SVG: one subplot per unit, units on the axes, markers at the contact events. The PNG is
//! decoded and probed: its size, each curve's colour only inside its own subplot, event-marker
//! columns at the same x in both subplots (one time axis), text pixels in the axis-label band.

use modia3d::demo;
use modia3d::prelude::*;

/// Curve colours in drawing order (the plot's palette: tab10 without red).
const BLUE: [u8; 3] = [31, 119, 180];
const ORANGE: [u8; 3] = [255, 127, 14];

fn cradle() -> SimulationResult {
    let model = demo::newtons_cradle(0.05, 1e-3, 0.5, ContactPairMaterial::new(1.0, 0.0, 0.0))
        .build()
        .unwrap();
    model
        .simulate(
            &SimOptions::new(0.02)
                .tolerance(1e-7)
                .interval(1e-4)
                .contact_results(true)
                .progress(false),
        )
        .unwrap()
}

/// Events at which a pair entered or left the contact set (those the plot marks).
fn contact_events(result: &SimulationResult) -> usize {
    result
        .events
        .iter()
        .filter(|e| !e.started.is_empty() || !e.ended.is_empty())
        .count()
}

struct Image {
    w: usize,
    h: usize,
    rgb: Vec<u8>,
}

impl Image {
    fn decode(bytes: &[u8]) -> Image {
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!(info.color_type, png::ColorType::Rgb);
        buf.truncate(info.buffer_size());
        Image {
            w: info.width as usize,
            h: info.height as usize,
            rgb: buf,
        }
    }
    fn px(&self, x: usize, y: usize) -> [u8; 3] {
        let i = 3 * (y * self.w + x);
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }
    /// Pixels of exactly colour `c` in rows `rows`.
    fn count(
        &self,
        c: [u8; 3],
        rows: std::ops::Range<usize>,
        cols: std::ops::Range<usize>,
    ) -> usize {
        rows.flat_map(|y| cols.clone().map(move |x| (x, y)))
            .filter(|&(x, y)| self.px(x, y) == c)
            .count()
    }
    /// Columns holding at least `min` pixels of colour `c` within rows `rows`.
    fn columns(&self, c: [u8; 3], rows: std::ops::Range<usize>, min: usize) -> Vec<usize> {
        (0..self.w)
            .filter(|&x| self.count(c, rows.clone(), x..x + 1) >= min)
            .collect()
    }
}

/// 800 × 600 px with a title: the two subplots share the height below the title. The angle
/// (blue, first curve) is drawn only in the upper half, the force (orange) only in the lower
/// one (legends included); each half has event-marker columns (≥ 100 px tall: the plotting
/// area is ~220 px), at the same x in both (the subplots share the time axis; where a curve covers the
/// marker, its pixels count), no more marker
/// columns than 3 px per contact event (lines 1 px wide, anti-aliasing off), and dark text
/// pixels in its y-label band (the rotated axis label and tick labels drawn with the bundled
/// font — a missing font would leave the band blank).
#[test]
fn png_of_a_mixed_unit_run_has_one_subplot_per_unit_and_event_markers() {
    let result = cradle();
    let contact_events = contact_events(&result);
    assert!(contact_events >= 2, "the run has contact events");
    let groups: &[&[&str]] = &[&["rev0.phi"], &["ball0|ball1.f_n"]];
    let options = PlotOptions::new().title("cradle").size(800, 600);
    let bytes = result
        .plot_bytes(groups, PlotFormat::Png, &options)
        .unwrap();
    let img = Image::decode(&bytes);
    assert_eq!((img.w, img.h), (800, 600));
    let (top, bottom) = (0..300, 300..600);
    let all = 0..800;
    assert!(
        img.count(BLUE, top.clone(), all.clone()) > 300,
        "angle curve in the upper subplot"
    );
    assert_eq!(
        img.count(BLUE, bottom.clone(), all.clone()),
        0,
        "no angle curve below"
    );
    assert!(
        img.count(ORANGE, bottom.clone(), all.clone()) > 300,
        "force curve in the lower subplot"
    );
    assert_eq!(
        img.count(ORANGE, top.clone(), all.clone()),
        0,
        "no force curve above"
    );
    let marker = modia3d::core::EVENT_MARKER_COLOR;
    let upper = img.columns(marker, top.clone(), 100);
    let lower = img.columns(marker, bottom.clone(), 100);
    assert!(!upper.is_empty(), "event markers in the upper subplot");
    // A marker column of one subplot is a marker column of the other, unless that one's curve
    // is drawn over it there (a force spike at the impact).
    for (cols, rows, curve) in [
        (&upper, bottom.clone(), ORANGE),
        (&lower, top.clone(), BLUE),
    ] {
        for &x in cols {
            let n = img.count(marker, rows.clone(), x..x + 1)
                + img.count(curve, rows.clone(), x..x + 1);
            assert!(n >= 100, "marker column {x} in both subplots ({n} px)");
        }
    }
    assert!(upper.len() <= 3 * contact_events, "{upper:?}");
    for rows in [top, bottom] {
        let dark = rows
            .flat_map(|y| (0..90).map(move |x| (x, y)))
            .filter(|&(x, y)| img.px(x, y).iter().all(|&v| v < 100))
            .count();
        assert!(dark > 100, "text in the y-label band ({dark} dark pixels)");
    }
}

/// The SVG of the same figure: unit-labelled y axes, the time axis, the legend entries, the
/// title, and one marker line per contact event in each of the two subplots.
#[test]
fn svg_of_a_mixed_unit_run_labels_units_and_marks_events() {
    let result = cradle();
    let contact_events = contact_events(&result);
    let dir = std::env::temp_dir().join(format!("modia3d-plot-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("cradle.svg");
    result
        .plot_with(
            &["rev0.phi", "ball0|ball1.f_n", "ball1|ball2.f_n"],
            &path,
            &PlotOptions::new().title("cradle"),
        )
        .unwrap();
    let svg = std::fs::read_to_string(&path).unwrap();
    for text in [
        "cradle",
        "time [s]",
        "rev0.phi [rad]",
        "force [N]",
        "ball0|ball1.f_n [N]",
        "ball1|ball2.f_n [N]",
        "contact event",
    ] {
        assert!(svg.contains(text), "missing `{text}`");
    }
    let [r, g, b] = modia3d::core::EVENT_MARKER_COLOR;
    let stroke = format!("stroke=\"#{r:02X}{g:02X}{b:02X}\"");
    // One line per event and subplot, plus one legend sample per subplot.
    assert_eq!(svg.matches(&stroke).count(), 2 * contact_events + 2);
    std::fs::remove_dir_all(&dir).ok();
}

/// A logarithmic axis needs positive values: a signal that is zero throughout (the last
/// ball's lateral position) is an export error naming the signal, a contact force is drawn.
#[test]
fn log_axis_draws_positive_values_and_names_a_signal_without_any() {
    let result = cradle();
    let options = PlotOptions::new().log_y(true);
    let png = result
        .plot_bytes(&[&["ball0|ball1.f_n"]], PlotFormat::Png, &options)
        .unwrap();
    let img = Image::decode(&png);
    assert!(img.count(BLUE, 0..img.h, 0..img.w) > 50);
    match result.plot_bytes(&[&["ball4.r_abs[1]"]], PlotFormat::Png, &options) {
        Err(ResultError::Export { reason, .. }) => {
            assert!(
                reason.contains("ball4.r_abs[1]") && reason.contains("positive"),
                "{reason}"
            )
        }
        other => panic!("expected an export error, got {other:?}"),
    }
    let err = result
        .plot(&["rev0.phi"], std::env::temp_dir().join("plot.pdf"))
        .unwrap_err();
    assert!(err.to_string().contains(".svg` or `.png`"), "{err}");
}

/// The `<text>` elements of an SVG: `(text-anchor, text)`.
fn svg_texts(svg: &str) -> Vec<(String, String)> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            let anchor = t.split("text-anchor=\"").nth(1)?.split('"').next()?;
            let body = t.split_once('>')?.1.split("</text>").next()?.trim();
            Some((anchor.to_string(), body.to_string()))
        })
        .collect()
}

/// Notation (scientific or not) and decimals of the mantissa of a tick label.
fn label_format(label: &str) -> (bool, usize) {
    let (mantissa, sci) = match label.split_once('e') {
        Some((m, _)) => (m, true),
        None => (label, false),
    };
    (sci, mantissa.split_once('.').map_or(0, |(_, d)| d.len()))
}

/// Tick labels of ball0's angular velocity (0 down to about -1 rad/s), a force up to 2.6 kN and
/// an angle up to 2.1 mrad, over a time axis of 0.02 s: a tick meant as 0 reads `0` (plotters'
/// ticks, accumulated from the lower end, read `-1.11e-16` on the velocity axis), every
/// other label parses as a number at least 1e-6 of the axis span away from zero, and the labels
/// of an axis share one notation and one number of decimals (the time axis read `0.0` beside
/// `0.002` and `0.01`).
#[test]
fn tick_labels_read_0_for_zero_and_share_one_format_per_axis() {
    let result = cradle();
    for name in ["ball0.w_abs", "ball0|ball1.f_n", "rev0.phi"] {
        let svg = result.plot_svg(&[name]).unwrap();
        let texts = svg_texts(&svg);
        // Tick labels: numbers; y labels are right-aligned, x labels centred.
        for anchor in ["end", "middle"] {
            let labels: Vec<&str> = texts
                .iter()
                .filter(|(a, t)| a == anchor && t.parse::<f64>().is_ok())
                .map(|(_, t)| t.as_str())
                .collect();
            println!("{name}: {labels:?}");
            assert!(labels.len() >= 3, "{name}: {anchor} labels {labels:?}");
            let values: Vec<f64> = labels.iter().map(|l| l.parse().unwrap()).collect();
            let span = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (l, v) in labels.iter().zip(&values) {
                assert!(
                    *l == "0" || v.abs() > 1e-6 * span,
                    "{name}: label {l} on an axis of {labels:?}"
                );
            }
            let formats: Vec<(bool, usize)> = labels
                .iter()
                .filter(|l| **l != "0")
                .map(|l| label_format(l))
                .collect();
            assert!(
                formats.windows(2).all(|w| w[0] == w[1]),
                "{name}: mixed formats {labels:?}"
            );
        }
    }
}

/// The points of the SVG polylines drawn with `stroke` (curves; the legend's sample line too).
fn polylines(svg: &str, stroke: &str) -> Vec<Vec<(f64, f64)>> {
    svg.lines()
        .filter(|l| l.contains("<polyline") && l.contains(&format!("stroke=\"{stroke}\"")))
        .filter_map(|l| {
            let points = l.split("points=\"").nth(1)?.split('"').next()?;
            Some(
                points
                    .split_whitespace()
                    .filter_map(|p| {
                        let (x, y) = p.split_once(',')?;
                        Some((x.parse().ok()?, y.parse().ok()?))
                    })
                    .collect(),
            )
        })
        .collect()
}

/// Whether segment a–b meets the rectangle (x0, y0, x1, y1): sampled every 0.25 px.
fn segment_meets(a: (f64, f64), b: (f64, f64), (x0, y0, x1, y1): (f64, f64, f64, f64)) -> bool {
    let n = ((b.0 - a.0).hypot(b.1 - a.1) * 4.0).ceil().max(1.0) as usize;
    (0..=n).any(|k| {
        let s = k as f64 / n as f64;
        let (x, y) = (a.0 + s * (b.0 - a.0), a.1 + s * (b.1 - a.1));
        (x0..=x1).contains(&x) && (y0..=y1).contains(&y)
    })
}

/// The pendulum angle of the cradle rises in the first 2 ms and stays at its top: a legend in
/// the upper right corner (where plotters put it) lies on the curve. The legend box (the
/// translucent white rectangle) must meet no segment of the curve (sampled every 0.25 px: the
/// curve is 2 px wide, the rectangle's edges are whole pixels); the lower half of the plot
/// right of the rise is empty, so a free place exists.
#[test]
fn the_legend_box_covers_no_curve() {
    let result = cradle();
    let options = PlotOptions::new().event_markers(false);
    let svg = result
        .plot_bytes(&[&["rev0.phi"]], PlotFormat::Svg, &options)
        .unwrap();
    let svg = String::from_utf8(svg).unwrap();
    let rect = svg
        .lines()
        .find(|l| l.contains("<rect") && l.contains("opacity=\"0.85\""))
        .expect("legend box");
    let attr = |a: &str| -> f64 {
        rect.split(&format!(" {a}=\""))
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    let (x, y, w, h) = (attr("x"), attr("y"), attr("width"), attr("height"));
    let boxed = (x, y, x + w, y + h);
    let curves: Vec<Vec<(f64, f64)>> = polylines(&svg, "#1F77B4")
        .into_iter()
        // The legend's own sample line lies inside the box.
        .filter(|c| {
            !c.iter()
                .all(|&(px, py)| (x..=x + w).contains(&px) && (y..=y + h).contains(&py))
        })
        .collect();
    assert!(!curves.is_empty());
    let n_points: usize = curves.iter().map(Vec::len).sum();
    assert!(n_points > 20, "{n_points} curve points");
    for c in &curves {
        for s in c.windows(2) {
            assert!(
                !segment_meets(s[0], s[1], boxed),
                "the legend box {boxed:?} covers the curve segment {:?}–{:?}",
                s[0],
                s[1]
            );
        }
    }
}
