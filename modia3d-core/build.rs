//! Records the optimisation level this package is compiled at, for the notice of an
//! unoptimised build (`build_profile`): cargo gives a build script the `OPT_LEVEL` of the
//! profile the package itself is built with — a user crate's `[profile.dev]` or its
//! `[profile.dev.package."*"]` override, whichever applies to modia3d-core — which the library
//! cannot see otherwise (`debug_assertions` stays on under an opt-level override). The script
//! uses `std` only, so it costs about a second of build time.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let level = std::env::var("OPT_LEVEL").unwrap_or_default();
    println!("cargo:rustc-env=MODIA3D_CORE_OPT_LEVEL={level}");
}
