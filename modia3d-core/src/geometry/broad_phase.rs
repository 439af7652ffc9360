//! Broad phase: candidate pairs of shapes whose world AABBs overlap (geometry stage).
//!
//! Sort and sweep on one world axis. The order of the boxes along the axis is kept from one call
//! to the next and repaired by insertion sort, which is O(n + swaps) when the bodies moved little
//! (temporal coherence). The sweep then tests only pairs whose intervals overlap on that axis.
//! The axis is the one with the largest spread of box centres (re-chosen with hysteresis so that
//! the kept order is not thrown away needlessly). The sweep reads the boxes from a copy in
//! sweep order (`[min x, y, z, max x, y, z]` side by side), so that its inner loop runs over
//! contiguous memory and tests the six bounds without branching: shapes in rows or grids
//! share their interval on any one axis with a whole row (32 balls of the 1024-ball scaling
//! scene), and the sweep then tests every pair of a row.

use super::aabb::Aabb;

/// A box as the sweep reads it: `[min x, min y, min z, max x, max y, max z]` \[m\].
type Bounds = [f64; 6];

/// Whether two boxes overlap or touch (as `aabb::aabbs_overlap`: every bound compared, `NaN`
/// never overlaps), without branches.
#[inline(always)]
fn bounds_overlap(a: &Bounds, b: &Bounds) -> bool {
    (a[0] <= b[3])
        & (b[0] <= a[3])
        & (a[1] <= b[4])
        & (b[1] <= a[4])
        & (a[2] <= b[5])
        & (b[2] <= a[5])
}

/// Sort-and-sweep broad phase over a fixed number of shapes. No allocation after the first
/// [`update`](Self::update) (the output vector keeps its capacity).
#[derive(Clone, Debug)]
pub struct BroadPhase {
    order: Vec<u32>,
    /// The boxes of the last update in `order`.
    sorted: Vec<Bounds>,
    axis: usize,
    box_tests: u64,
}

impl BroadPhase {
    /// A broad phase for `n` shapes (indices `0..n` into the AABB slice of every update).
    pub fn new(n: usize) -> Self {
        BroadPhase {
            order: (0..n as u32).collect(),
            sorted: Vec::with_capacity(n),
            axis: 0,
            box_tests: 0,
        }
    }

    /// Number of shapes.
    pub fn len(&self) -> usize {
        self.order.len()
    }

    /// `true` when there are no shapes.
    pub fn is_empty(&self) -> bool {
        self.order.is_empty()
    }

    /// The sweep axis used by the last update (0 = x, 1 = y, 2 = z).
    pub fn axis(&self) -> usize {
        self.axis
    }

    /// Number of AABB–AABB overlap tests done by the last update (the cost measure).
    pub fn box_tests(&self) -> u64 {
        self.box_tests
    }

    /// Write into `out` (cleared first) every pair `(i, j)`, `i < j`, whose AABBs
    /// (`aabbs[i]`, resolved in world, \[m\]) overlap or touch and for which `allowed(i, j)` is
    /// true. Pairs come out in sweep order, not sorted. Panics if `aabbs.len()` differs from `n`.
    pub fn update(
        &mut self,
        aabbs: &[Aabb],
        allowed: impl Fn(u32, u32) -> bool,
        out: &mut Vec<(u32, u32)>,
    ) {
        assert_eq!(aabbs.len(), self.order.len(), "one AABB per shape");
        out.clear();
        self.box_tests = 0;
        self.choose_axis(aabbs);
        let k = self.axis;
        // Insertion sort by the lower bound on the sweep axis, starting from the last order.
        let key = |i: u32| aabbs[i as usize].mins[k];
        for i in 1..self.order.len() {
            let item = self.order[i];
            let v = key(item);
            let mut j = i;
            while j > 0 && key(self.order[j - 1]) > v {
                self.order[j] = self.order[j - 1];
                j -= 1;
            }
            self.order[j] = item;
        }
        // Sweep, over the boxes copied in sweep order.
        self.sorted.clear();
        self.sorted.extend(self.order.iter().map(|&i| {
            let b = &aabbs[i as usize];
            [b.mins.x, b.mins.y, b.mins.z, b.maxs.x, b.maxs.y, b.maxs.z]
        }));
        for (a, (bi, &i)) in self.sorted.iter().zip(&self.order).enumerate() {
            let hi = bi[3 + k];
            for (bj, &j) in self.sorted[a + 1..].iter().zip(&self.order[a + 1..]) {
                if bj[k] > hi {
                    break;
                }
                self.box_tests += 1;
                if bounds_overlap(bi, bj) {
                    let (p, q) = if i < j { (i, j) } else { (j, i) };
                    if allowed(p, q) {
                        out.push((p, q));
                    }
                }
            }
        }
    }

    /// Switch to the axis with the largest variance of box centres if it beats the current one
    /// by a factor 2 (hysteresis keeps the sorted order useful).
    fn choose_axis(&mut self, aabbs: &[Aabb]) {
        if aabbs.len() < 2 {
            return;
        }
        let n = aabbs.len() as f64;
        let mut s = [0.0f64; 3];
        let mut s2 = [0.0f64; 3];
        for b in aabbs {
            for k in 0..3 {
                let c = 0.5 * (b.mins[k] + b.maxs[k]);
                s[k] += c;
                s2[k] += c * c;
            }
        }
        let var = |k: usize| s2[k] / n - (s[k] / n).powi(2);
        let best = (0..3)
            .max_by(|&a, &b| var(a).total_cmp(&var(b)))
            .unwrap_or(0);
        if var(best) > 2.0 * var(self.axis) {
            self.axis = best;
        }
    }
}
