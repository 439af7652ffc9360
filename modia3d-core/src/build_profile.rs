//! The optimisation level modia3d-core was compiled at, and the notice a run prints once
//! when it is 0.
//!
//! Cargo's default `dev` profile (`cargo run`, `cargo test` of a crate that depends on
//! modia3d) compiles every dependency at opt-level 0, and the hot loops (contact detection,
//! the multibody residual, SUNDIALS' callbacks) then run up to about 100 times slower than in a
//! release build (measured in the README's section "Using modia3d in your own crate"). A
//! crate's own `Cargo.toml` fixes that for its dependencies with the lines of
//! [`CARGO_TOML_FIX`]; this repository's `[profile.dev]` settings do not carry over to a crate
//! that depends on it.
//!
//! What the library can see is the level it was itself compiled at: the build script records
//! cargo's `OPT_LEVEL` for modia3d-core ([`OPT_LEVEL`]), which is the profile that matters —
//! the hot code is in modia3d-core. (`cfg!(debug_assertions)` would not tell: a dev profile
//! with `[profile.dev.package."*"] opt-level = 3` keeps debug assertions on.)
//!
//! When modia3d-core is compiled at opt-level 0, the first simulation of the process that is
//! not [`quiet`](crate::SimOptions::quiet) — or the first [`Sweep`](crate::Sweep) run —
//! prints [`unoptimised_notice`] once: through `tracing::warn!` when a `tracing` subscriber
//! is installed, else on standard error (as the run warnings are). It is not a
//! [`SimWarning`](crate::SimWarning): it concerns the build, not the run, and a run's results
//! (its `warnings` included) do not depend on how the library was compiled.

use std::sync::atomic::{AtomicBool, Ordering};

/// The opt-level modia3d-core was compiled at, as cargo gives it to build scripts: `"0"` …
/// `"3"`, `"s"` or `"z"` (empty if the build script ran outside cargo).
pub const OPT_LEVEL: &str = env!("MODIA3D_CORE_OPT_LEVEL");

/// The lines that make a crate's `cargo run` and `cargo test` compile modia3d (and every
/// other dependency) optimised, to add to the crate's own `Cargo.toml`. With them a fresh
/// crate's `cargo run` runs about as fast as `cargo run --release` (measured in the README's
/// section "Using modia3d in your own crate").
pub const CARGO_TOML_FIX: &str = "[profile.dev.package.\"*\"]\nopt-level = 3";

/// Whether a package compiled at `opt_level` (cargo's `OPT_LEVEL`: `"0"` … `"3"`, `"s"`,
/// `"z"`) is unoptimised: only `"0"` is, cargo's default for `dev`; any other level was chosen
/// on purpose.
pub fn is_unoptimised(opt_level: &str) -> bool {
    opt_level.trim() == "0"
}

/// Whether modia3d-core itself was compiled without optimisation ([`OPT_LEVEL`] is `"0"`).
pub fn unoptimised() -> bool {
    is_unoptimised(OPT_LEVEL)
}

/// The notice printed once by the first run of a process in an unoptimised build: what is
/// slow, why, and the [`CARGO_TOML_FIX`] lines.
pub fn unoptimised_notice() -> String {
    format!(
        "modia3d: this build compiled modia3d-core without optimisation (opt-level 0, cargo's\n\
         default `dev` profile): simulations run up to about 100 times slower than in a release\n\
         build. To compile the dependencies optimised in `cargo run` and `cargo test`, add these\n\
         lines to your crate's Cargo.toml (or use `cargo run --release`):\n\n{}\n\n\
         (`SimOptions::quiet(true)` hides this notice.)\n",
        indent(CARGO_TOML_FIX)
    )
}

fn indent(text: &str) -> String {
    text.lines()
        .map(|l| format!("    {l}"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// Set once the notice of this process has been given.
#[cfg_attr(not(feature = "solver"), allow(dead_code))]
static NOTICE_GIVEN: AtomicBool = AtomicBool::new(false);

/// The notice for a build at `opt_level`, the first time it is asked for through `given`;
/// `None` for an optimised build and afterwards.
#[cfg_attr(not(feature = "solver"), allow(dead_code))]
fn take_notice(opt_level: &str, given: &AtomicBool) -> Option<String> {
    if !is_unoptimised(opt_level) || given.swap(true, Ordering::Relaxed) {
        return None;
    }
    Some(unoptimised_notice())
}

/// Gives the notice of an unoptimised build, once per process (see the module docs): through
/// `tracing` when the caller found a `subscriber` installed, else on standard error.
#[cfg(feature = "solver")]
pub(crate) fn notice_once(subscriber: bool) {
    let Some(text) = take_notice(OPT_LEVEL, &NOTICE_GIVEN) else {
        return;
    };
    if subscriber {
        tracing::warn!("{text}");
    } else {
        eprint!("{text}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_opt_level_zero_is_unoptimised() {
        assert!(is_unoptimised("0"));
        assert!(is_unoptimised(" 0\n"));
        for level in ["1", "2", "3", "s", "z"] {
            assert!(!is_unoptimised(level), "{level}");
        }
        // This workspace's dev profile (and so its test builds) compiles at opt-level 2.
        assert!(
            !unoptimised(),
            "modia3d-core built at opt-level {OPT_LEVEL:?}"
        );
        assert!(!OPT_LEVEL.is_empty());
    }

    #[test]
    fn the_notice_names_the_fix_and_is_given_once() {
        let text = unoptimised_notice();
        assert!(
            text.contains("[profile.dev.package.\"*\"]\n    opt-level = 3"),
            "{text}"
        );
        assert!(
            text.contains("Cargo.toml") && text.contains("quiet(true)"),
            "{text}"
        );
        let given = AtomicBool::new(false);
        assert_eq!(take_notice("3", &given), None);
        assert_eq!(take_notice("0", &given), Some(text));
        assert_eq!(take_notice("0", &given), None);
    }
}
