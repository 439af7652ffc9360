//! Tests of the safe SUNDIALS IDA wrapper (`crate::solver`) against analytic or published
//! reference solutions ([`reference`]), plus its failure paths — panics, NaN, bad arguments —
//! memory hygiene and the coloured Jacobian ([`failures`]). The wrapper is internal to the
//! crate, so these are unit tests; the systems shared by both files live here.

use super::*;

mod failures;
mod reference;

/// y' = -k y written as the implicit residual F = y' + k y.
struct Decay {
    k: f64,
}

impl DaeSystem for Decay {
    fn len(&self) -> usize {
        1
    }
    fn residual(
        &mut self,
        _t: f64,
        y: &[f64],
        yp: &[f64],
        res: &mut [f64],
    ) -> Result<(), ResidualError> {
        res[0] = yp[0] + self.k * y[0];
        Ok(())
    }
}

fn decay_solver(k: f64, opts: &IdaOptions) -> Ida<Decay> {
    Ida::new(Decay { k }, 0.0, &[1.0], &[-k], opts).expect("valid decay problem")
}

/// Point mass falling onto the ground h = 0: h' = v, v' = -g, root h with direction -1.
struct Ball {
    g: f64,
}

impl DaeSystem for Ball {
    fn len(&self) -> usize {
        2
    }
    fn residual(
        &mut self,
        _t: f64,
        y: &[f64],
        yp: &[f64],
        res: &mut [f64],
    ) -> Result<(), ResidualError> {
        res[0] = yp[0] - y[1];
        res[1] = yp[1] + self.g;
        Ok(())
    }
    fn num_roots(&self) -> usize {
        1
    }
    fn roots(&mut self, _t: f64, y: &[f64], _yp: &[f64], g: &mut [f64]) {
        g[0] = y[0];
    }
}

/// Simulates `bounces` impacts with restitution `e`; returns the impact times and the
/// statistics after every impact (taken right before and right after the re-initialisation).
fn bouncing_ball(bounces: usize, e: f64) -> (Vec<f64>, Vec<(IdaStats, IdaStats)>) {
    let g = 9.81;
    let opts = IdaOptions::default()
        .rtol(1e-10)
        .atol(1e-12)
        .root_directions(vec![-1]);
    let mut ida = Ida::new(Ball { g }, 0.0, &[1.0, 0.0], &[0.0, -g], &opts).unwrap();
    let mut times = Vec::new();
    let mut stats = Vec::new();
    while times.len() < bounces {
        match ida.solve(10.0, false).unwrap() {
            SolveStatus::Root { t } => {
                assert_eq!(ida.root_info(), &[-1]);
                times.push(t);
                let (h, v) = (ida.y()[0], ida.y()[1]);
                assert!(h.abs() < 1e-9, "height at impact {h}");
                let before = ida.stats();
                ida.reinit(t, &[h, -e * v], &[-e * v, -g]).unwrap();
                assert_eq!(ida.root_info(), &[0]);
                stats.push((before, ida.stats()));
            }
            other => panic!("expected an impact before t = 10 s, got {other:?}"),
        }
    }
    (times, stats)
}
