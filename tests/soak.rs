//! Soak (issue 15, point 7): build + simulate cycles of a contact scene keep the resident set
//! size flat — every SUNDIALS object, contact state and result is freed with its run.
//!
//! RSS from /proc/self/statm (Linux; elsewhere the test only runs the cycles). After 10
//! warm-up cycles (allocator pools, lazily initialised statics) the RSS may grow by at most
//! 4 MiB over the cycles: a leak of one IDA memory block (~100 kB for this scene) per cycle
//! would add ~10 MiB over 100 cycles and fail; the allocator's fragmentation stays below it.

use modia3d::demo;
use modia3d::prelude::*;

fn rss_bytes() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/statm").ok()?;
    let pages: u64 = s.split_whitespace().nth(1)?.parse().ok()?;
    Some(pages * 4096)
}

/// One cycle: build the bouncing steel ball, run 0.3 s (a bounce: two events), drop it all.
fn cycle() {
    let model = demo::bouncing_sphere(0.1, 0.1, demo::STEEL_STEEL)
        .build()
        .unwrap();
    let res = model
        .simulate(&SimOptions::new(0.3).progress(false).contact_results(true))
        .unwrap();
    assert!(res.stats.events >= 1);
}

fn soak(cycles: usize) {
    for _ in 0..10 {
        cycle();
    }
    let before = rss_bytes();
    for _ in 0..cycles {
        cycle();
    }
    if let (Some(a), Some(b)) = (before, rss_bytes()) {
        let growth = b as f64 - a as f64;
        println!(
            "{cycles} cycles: RSS {:.1} MiB -> {:.1} MiB ({:+.2} MiB)",
            a as f64 / 1048576.0,
            b as f64 / 1048576.0,
            growth / 1048576.0
        );
        assert!(growth < 4.0 * 1048576.0, "RSS grew by {growth} bytes");
    }
}

#[test]
fn hundred_build_simulate_cycles_keep_rss_flat() {
    soak(100);
}

/// The acceptance run: 1,000 cycles (about a minute in a dev build).
#[test]
#[ignore = "long: 1,000 cycles; cargo test --test soak -- --ignored"]
fn thousand_build_simulate_cycles_keep_rss_flat() {
    soak(1000);
}
