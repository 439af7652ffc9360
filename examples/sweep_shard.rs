//! Sharded parameter sweeps for clusters: the command-line front end for job arrays. Copy this
//! file into your crate as a binary and register your own models in place of the demo's:
//!
//! ```ignore
//! let registry = SweepRegistry::new().add(
//!     "pendulum",
//!     Sweep::new(|p| Ok(Pendulum { l: p.get("l")?, ..Default::default() }.build()?))
//!         .options(SimOptions::new(5.0))
//!         .metric("phi_max", "rad", |res| {
//!             Ok(res.signal("rev.phi")?.values().into_iter().fold(0.0, f64::max))
//!         }),
//! );
//! ```
//!
//! A sweep file (JSON, see `SweepSpec`) names the model and the points; shard `I` of `N` runs
//! the points `I, I+N, I+2N, …` on all cores and writes its part, `merge` joins the parts:
//!
//!     cargo run --release --example sweep_shard -- run examples/bouncing_sweep.json
//!     cargo run --release --example sweep_shard -- run examples/bouncing_sweep.json --shard 0 --of 4 --out out/part-{shard}.csv
//!     sbatch --array=0-3 --wrap 'target/release/examples/sweep_shard run sweep.json --of 4 --out parts/part-{shard}.csv'
//!     hq submit --array 0-3 -- target/release/examples/sweep_shard run sweep.json --of 4 --out parts/part-{shard}.csv
//!     cargo run --release --example sweep_shard -- merge examples/bouncing_sweep.json --out out/sweep.csv out/part-*.csv
//!
//! In a job array the shard index comes from `HQ_TASK_ID`, `SLURM_ARRAY_TASK_ID`,
//! `PBS_ARRAY_INDEX` or `PBS_ARRAYID` (0-based: `--array=0-3`). `scripts/hq_sweep.py` submits
//! the shards to a HyperQueue server and merges them.

fn main() -> std::process::ExitCode {
    modia3d::core::sweep_main(&modia3d::demo::sweep_registry())
}
