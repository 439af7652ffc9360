//! Compile-fail and pass cases of `model!` (trybuild). Families: `parse` (syntax), `check`
//! (the macro's own checks), `rustc` (errors rustc reports on the user's tokens through spanned
//! code); `pass` groups features that must compile. Regenerate the `.stderr` files with
//! `TRYBUILD=overwrite cargo test --test ui` and review them like code.

#[test]
fn ui() {
    // trybuild's nested cargo builds in its own workspace, without our `[profile.dev]`; its
    // default full debug info made ~50 MB per pass case and ~0.9 GB in all. The nested cargo
    // inherits the environment, and this test binary runs nothing else.
    std::env::set_var("CARGO_PROFILE_DEV_DEBUG", "false");
    std::env::set_var("CARGO_PROFILE_DEV_STRIP", "debuginfo");
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/parse/*.rs");
    t.compile_fail("tests/ui/check/*.rs");
    t.compile_fail("tests/ui/rustc/*.rs");
    t.pass("tests/ui/pass/*.rs");
}
