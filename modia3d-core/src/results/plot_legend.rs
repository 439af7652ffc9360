//! Results stage, plot legends: where in a subplot the legend box goes. Of six places (the
//! four corners, then the middle of the top and bottom edges, each inset by [`INSET`] px) the
//! first one whose box the fewest curve segments cross: a free place when there is one.

/// Distance of the legend box from the edges of the plotting area [px].
pub(crate) const INSET: i32 = 10;

/// Half the width of a drawn curve plus a pixel: a segment this close to the box touches it.
const REACH: i32 = 2;

/// Whether the segment `a`–`b` passes within [`REACH`] of the box `(x0, y0, x1, y1)`
/// (Liang–Barsky clipping against the grown box).
fn crosses(a: (i32, i32), b: (i32, i32), (x0, y0, x1, y1): (i32, i32, i32, i32)) -> bool {
    let (x0, y0, x1, y1) = (
        f64::from(x0 - REACH),
        f64::from(y0 - REACH),
        f64::from(x1 + REACH),
        f64::from(y1 + REACH),
    );
    let (ax, ay) = (f64::from(a.0), f64::from(a.1));
    let (dx, dy) = (f64::from(b.0) - ax, f64::from(b.1) - ay);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [(-dx, ax - x0), (dx, x1 - ax), (-dy, ay - y0), (dy, y1 - ay)] {
        if p == 0.0 {
            if q < 0.0 {
                return false;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    t0 <= t1
}

/// How many segments of `runs` (polylines in pixels; a single point counts as one) touch the
/// box at `(x, y)` of size `(w, h)`.
pub(crate) fn covered(runs: &[Vec<(i32, i32)>], (x, y): (i32, i32), (w, h): (i32, i32)) -> usize {
    let rect = (x, y, x + w, y + h);
    runs.iter()
        .map(|run| match run.as_slice() {
            [p] => usize::from(crosses(*p, *p, rect)),
            _ => run
                .windows(2)
                .filter(|s| matches!(s, [a, b] if crosses(*a, *b, rect)))
                .count(),
        })
        .sum()
}

/// The top-left corner of the legend box of size `size` in a plotting area of size `area`
/// (both px) over the curves `runs` (px, relative to the area): the first of upper right,
/// upper left, lower right, lower left, upper middle, lower middle that the fewest segments
/// touch.
pub(crate) fn legend_spot(
    area: (i32, i32),
    size: (i32, i32),
    runs: &[Vec<(i32, i32)>],
) -> (i32, i32) {
    let (right, bottom) = (area.0 - INSET - size.0, area.1 - INSET - size.1);
    let middle = (area.0 - size.0) / 2;
    let spots = [
        (right, INSET),
        (INSET, INSET),
        (right, bottom),
        (INSET, bottom),
        (middle, INSET),
        (middle, bottom),
    ];
    let mut best = (usize::MAX, (right, INSET));
    for spot in spots {
        let n = covered(runs, spot, size);
        if n < best.0 {
            best = (n, spot);
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A curve that rises and stays at the top (a pendulum angle after a push) covers the upper
    /// right: the legend goes to the upper left or below, where no segment touches it.
    #[test]
    fn the_legend_avoids_a_curve_in_the_upper_right() {
        let area = (800, 200);
        let size = (150, 40);
        let rise: Vec<(i32, i32)> = (0..=800)
            .step_by(4)
            .map(|x| (x, (190 - x).max(15)))
            .collect();
        let runs = vec![rise];
        assert!(covered(&runs, (800 - INSET - 150, INSET), size) > 0);
        let spot = legend_spot(area, size, &runs);
        assert_eq!(covered(&runs, spot, size), 0, "{spot:?}");
        assert_eq!(
            spot,
            (800 - INSET - 150, 200 - INSET - 40),
            "lower right is free"
        );
    }

    /// A long segment through a box counts even without a sample inside it; where every place
    /// is crossed the least crossed one is taken.
    #[test]
    fn segments_count_and_the_least_covered_place_wins() {
        let size = (100, 30);
        let diagonal = vec![vec![(0, 0), (400, 200)]];
        assert!(crosses((0, 0), (400, 200), (150, 60, 250, 90)));
        assert!(!crosses((0, 0), (400, 0), (150, 60, 250, 90)));
        assert_eq!(covered(&diagonal, (150, 60), size), 1);
        // Horizontal lines through the top and bottom rows cover all six places, the top one
        // twice as densely (two lines): a bottom place wins.
        let lines = vec![
            vec![(0, 20), (400, 20)],
            vec![(0, 25), (400, 25)],
            vec![(0, 185), (400, 185)],
        ];
        let spot = legend_spot((400, 200), size, &lines);
        assert_eq!(spot.1, 200 - INSET - 30);
    }
}
