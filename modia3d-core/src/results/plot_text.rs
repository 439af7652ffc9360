//! Results stage, PNG text: plotters' bitmap backend with its text laid out and rasterised here
//! by `ab_glyph` with the bundled font. plotters' own `ab_glyph` text draws each glyph's bitmap
//! from the pen position, dropping the glyph's left side bearing (so "contact" shows a gap after
//! the narrow-bearing "t" and the letters crowd elsewhere), and places each glyph's top at half
//! the font size plus its own rounded top, so glyphs of different height sit on different
//! baselines. Here every glyph is positioned at its pen position (advance widths and kerning,
//! sub-pixel) on one baseline, and drawn from its exact pixel bounds.

use ab_glyph::{point, Font, FontRef, GlyphId, PxScale, PxScaleFont, ScaleFont};
use plotters::prelude::BitMapBackend;
use plotters::style::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
};

/// A glyph's pixels: `(x, y, coverage)` relative to the text's top-left corner (the ascent
/// line at the pen start), coverage in 0..=1.
type Ink = Vec<(i32, i32, f32)>;

/// The glyphs of `text` with their pen positions [px] (advances and kerning), and the
/// advance of the whole text.
fn pens(scaled: &PxScaleFont<&FontRef<'_>>, text: &str) -> (Vec<(GlyphId, f32)>, f32) {
    let mut glyphs = vec![];
    let mut pen = 0.0f32;
    let mut previous = None;
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = previous {
            pen += scaled.kern(p, id);
        }
        previous = Some(id);
        glyphs.push((id, pen));
        pen += scaled.h_advance(id);
    }
    (glyphs, pen)
}

/// The pixels of `text` at `size` (plotters' font size: ascent − descent in pixels) and the
/// text box's width and height (advance of the whole text; ascent − descent).
fn rasterise(font: &FontRef<'_>, size: f64, text: &str) -> (Ink, f32, f32) {
    let scale = PxScale::from(size as f32);
    let scaled = font.as_scaled(scale);
    let ascent = scaled.ascent();
    let mut ink = vec![];
    let (glyphs, width) = pens(&scaled, text);
    for (id, pen) in glyphs {
        let glyph = id.with_scale_and_position(scale, point(pen, ascent));
        if let Some(outline) = font.outline_glyph(glyph) {
            let b = outline.px_bounds();
            let (x0, y0) = (b.min.x as i32, b.min.y as i32);
            outline.draw(|x, y, c| {
                if c > 0.0 {
                    ink.push((x0 + x as i32, y0 + y as i32, c.min(1.0)));
                }
            });
        }
    }
    (ink, width, scaled.height())
}

/// plotters' bitmap backend (RGB) with text drawn by [`rasterise`] in `font`.
pub(crate) struct PngBackend<'a> {
    inner: BitMapBackend<'a>,
    font: FontRef<'static>,
}

impl<'a> PngBackend<'a> {
    /// Draws into `rgb` (`w` × `h` × 3 bytes) with text in `font`.
    pub(crate) fn new(rgb: &'a mut [u8], (w, h): (u32, u32), font: FontRef<'static>) -> Self {
        PngBackend {
            inner: BitMapBackend::with_buffer(rgb, (w, h)),
            font,
        }
    }
}

type Drawn<E> = Result<(), DrawingErrorKind<E>>;

impl DrawingBackend for PngBackend<'_> {
    type ErrorType = <BitMapBackend<'static> as DrawingBackend>::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }
    fn ensure_prepared(&mut self) -> Drawn<Self::ErrorType> {
        self.inner.ensure_prepared()
    }
    fn present(&mut self) -> Drawn<Self::ErrorType> {
        self.inner.present()
    }
    fn draw_pixel(&mut self, point: BackendCoord, color: BackendColor) -> Drawn<Self::ErrorType> {
        self.inner.draw_pixel(point, color)
    }
    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Drawn<Self::ErrorType> {
        self.inner.draw_line(from, to, style)
    }
    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Drawn<Self::ErrorType> {
        self.inner.draw_rect(upper_left, bottom_right, style, fill)
    }
    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Drawn<Self::ErrorType> {
        self.inner.draw_path(path, style)
    }
    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Drawn<Self::ErrorType> {
        self.inner.draw_circle(center, radius, style, fill)
    }
    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Drawn<Self::ErrorType> {
        self.inner.fill_polygon(vert, style)
    }
    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Drawn<Self::ErrorType> {
        self.inner.blit_bitmap(pos, size, src)
    }

    /// The text box (advance width, ascent − descent), as plotters lays out labels and legends.
    fn estimate_text_size<TStyle: BackendTextStyle>(
        &self,
        text: &str,
        style: &TStyle,
    ) -> Result<(u32, u32), DrawingErrorKind<Self::ErrorType>> {
        let scaled = self.font.as_scaled(PxScale::from(style.size() as f32));
        let (_, width) = pens(&scaled, text);
        Ok((width.ceil() as u32, scaled.height().ceil() as u32))
    }

    /// The text anchored at `pos` like plotters' default (the box from the ascent line to the
    /// descent line, aligned by the style's anchor), rotated by the style's transform.
    fn draw_text<TStyle: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &TStyle,
        pos: BackendCoord,
    ) -> Drawn<Self::ErrorType> {
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let (ink, width, height) = rasterise(&self.font, style.size(), text);
        let anchor = style.anchor();
        let dx = match anchor.h_pos {
            HPos::Left => 0.0,
            HPos::Center => -width / 2.0,
            HPos::Right => -width,
        }
        .round() as i32;
        let dy = match anchor.v_pos {
            VPos::Top => 0.0,
            VPos::Center => -height / 2.0,
            VPos::Bottom => -height,
        }
        .round() as i32;
        let transform = style.transform();
        let (w, h) = self.get_size();
        for (x, y, coverage) in ink {
            let (x, y) = transform.transform(x + dx, y + dy);
            let (x, y) = (pos.0 + x, pos.1 + y);
            if x >= 0 && y >= 0 && (x as u32) < w && (y as u32) < h {
                let c = BackendColor {
                    alpha: color.alpha * f64::from(coverage),
                    rgb: color.rgb,
                };
                self.inner.draw_pixel((x, y), c)?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
// In tests an out-of-range index is a failure report like any assertion.
#[allow(clippy::indexing_slicing)]
mod tests {
    use crate::results::plot::{render_bytes, Drawing};
    use crate::PlotFormat;
    use plotters::coord::Shift;
    use plotters::prelude::*;

    /// A white page with one text at (10, 10).
    struct Label(&'static str, f64);

    impl Drawing for Label {
        fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String> {
            root.fill(&WHITE).map_err(|e| e.to_string())?;
            root.draw(&Text::new(self.0, (10, 10), ("sans-serif", self.1)))
                .map_err(|e| e.to_string())?;
            root.present().map_err(|e| e.to_string())
        }
    }

    /// The ink of `text` rendered in a PNG plot: per column with ink (any channel below 128,
    /// i.e. more than half covered), its first and last inked row; glyphs as runs of such
    /// columns, each `(first column, last column, top row, bottom row)`.
    fn glyph_runs(text: &'static str, size: f64) -> Vec<(usize, usize, usize, usize)> {
        let (w, h) = (300usize, 80usize);
        let png = render_bytes(&Label(text, size), PlotFormat::Png, (w as u32, h as u32))
            .expect("rendered");
        let mut reader = png::Decoder::new(std::io::Cursor::new(png))
            .read_info()
            .expect("png");
        let mut rgb = vec![0; reader.output_buffer_size()];
        reader.next_frame(&mut rgb).expect("frame");
        let ink = |x: usize, y: usize| {
            rgb.get(3 * (y * w + x)..3 * (y * w + x) + 3)
                .is_some_and(|p| p.iter().any(|&c| c < 128))
        };
        let mut runs: Vec<(usize, usize, usize, usize)> = vec![];
        let mut open = false;
        for x in 0..w {
            let rows: Vec<usize> = (0..h).filter(|&y| ink(x, y)).collect();
            match (rows.first(), rows.last(), open, runs.last_mut()) {
                (Some(&t), Some(&b), true, Some(r)) => {
                    r.1 = x;
                    r.2 = r.2.min(t);
                    r.3 = r.3.max(b);
                }
                (Some(&t), Some(&b), _, _) => {
                    runs.push((x, x, t, b));
                    open = true;
                }
                _ => open = false,
            }
        }
        runs
    }

    /// The period sits on the baseline: in "n.n" its lowest inked row is the n's lowest (both
    /// glyphs have their bottom on the baseline in DejaVu Sans, and all glyphs of a text share
    /// one baseline position, so their bottom rows quantise alike: no tolerance), and it lies in
    /// the lower fifth of the n's height. plotters' own text put it one row higher at 13 px
    /// (row 15 against the n's 16), half-way up the stroke.
    #[test]
    fn the_period_sits_on_the_baseline() {
        for size in [13.0, 26.0] {
            let runs = glyph_runs("n.n", size);
            assert_eq!(runs.len(), 3, "{size} px: n, period, n: {runs:?}");
            let (n, dot) = (runs[0], runs[1]);
            assert_eq!(
                dot.3, n.3,
                "{size} px: bottom rows of period and n: {runs:?}"
            );
            let height = (n.3 - n.2 + 1) as f64;
            assert!(
                (n.3 - dot.2 + 1) as f64 <= 0.4 * height,
                "{size} px: the period reaches too high: {runs:?}"
            );
        }
    }

    /// "contact" shows seven separate glyphs with even spacing: no gap between two glyphs
    /// wider than the median gap by more than a pixel (each glyph lands at its sub-pixel pen
    /// position, and the half-coverage threshold rounds each edge by up to half a pixel).
    /// plotters' own text, which dropped each glyph's left bearing, left 4 px after the "n" at
    /// 13 px (median 2) and 6 px at 26 px (median 3), and let "o" and "n" touch.
    #[test]
    fn contact_has_no_gap() {
        for size in [13.0, 26.0] {
            let runs = glyph_runs("contact", size);
            assert_eq!(runs.len(), 7, "{size} px: seven glyphs apart: {runs:?}");
            let mut gaps: Vec<usize> = runs.windows(2).map(|w| w[1].0 - w[0].1 - 1).collect();
            let widest = gaps.iter().copied().max().unwrap_or(0);
            gaps.sort_unstable();
            let median = gaps[gaps.len() / 2];
            assert!(
                widest <= median + 1,
                "{size} px: gap of {widest} px against a median of {median}: {runs:?}"
            );
        }
    }
}
