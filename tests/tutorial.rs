//! Issue 44, point 9: docs/tutorial.md, a first model from an empty crate, stays true. Its Rust
//! code blocks, in order, are `examples/tutorial.rs` (after the example's `//!` header), its
//! `Cargo.toml` block has the README's dependency and profile lines, and the example runs: the
//! contact forces and speeds it prints are the rigid answers, and the plots and the viewer page
//! are written.

use modia3d::core::build_profile::CARGO_TOML_FIX;
use std::time::Instant;

#[allow(dead_code)] // the test calls `run`, not the example's `main`
#[path = "../examples/tutorial.rs"]
mod tutorial;

const PAGE: &str = include_str!("../docs/tutorial.md");
const EXAMPLE: &str = include_str!("../examples/tutorial.rs");

/// The contents of the page's fenced code blocks in language `lang`, in order.
fn code_blocks(page: &str, lang: &str) -> Vec<String> {
    let open = format!("```{lang}");
    let mut blocks = vec![];
    let mut current: Option<Vec<&str>> = None;
    for line in page.lines() {
        match current.as_mut() {
            None if line == open => current = Some(vec![]),
            None => {}
            Some(block) if line == "```" => {
                blocks.push(block.join("\n"));
                current = None;
            }
            Some(block) => block.push(line),
        }
    }
    assert!(current.is_none(), "an unclosed ```{lang} block");
    blocks
}

/// The page's Rust blocks, one blank line between them, are the example's code verbatim.
#[test]
fn the_tutorials_code_is_the_example() {
    let blocks = code_blocks(PAGE, "rust");
    assert!(blocks.len() >= 4, "{} rust blocks", blocks.len());
    let code = EXAMPLE
        .lines()
        .skip_while(|l| l.starts_with("//!"))
        .skip_while(|l| l.is_empty())
        .collect::<Vec<_>>()
        .join("\n");
    let page = blocks.join("\n\n");
    if page != code {
        let at = page
            .lines()
            .zip(code.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(page.lines().count().min(code.lines().count()));
        panic!(
            "docs/tutorial.md and examples/tutorial.rs differ at line {} of the code:\n  page:    {:?}\n  example: {:?}",
            at + 1,
            page.lines().nth(at),
            code.lines().nth(at)
        );
    }
}

/// The page's `Cargo.toml` has the dependency and the profile lines the README gives (and the
/// notice of an unoptimised build names), and starts from `cargo new`.
#[test]
fn the_tutorial_starts_from_an_empty_crate() {
    let toml = code_blocks(PAGE, "toml").join("\n");
    assert!(toml.contains("[dependencies]\nmodia3d = {"), "{toml}");
    assert!(toml.contains(CARGO_TOML_FIX), "{toml}");
    assert!(PAGE.contains("cargo new "), "{PAGE}");
    assert!(
        include_str!("../README.md").contains("(docs/tutorial.md)"),
        "the README links the tutorial"
    );
}

/// The example runs: the sliding block's normal force is m g cos α (the volume law's rest
/// force, to 1e-6 relative), the rolling ball's speed is within 1 % of the rigid 5/7 g sin α t
/// (its rolling resistance, μ_r 0.002, takes ~0.3 %), and the PNG, SVG and HTML files are
/// written. Quick: ~0.03 s of simulation in a release build.
#[test]
fn the_tutorial_runs() {
    let dir = std::env::temp_dir().join(format!("modia3d-tutorial-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let started = Instant::now();
    let res = tutorial::run(&dir).unwrap();
    println!("tutorial: {:.3} s", started.elapsed().as_secs_f64());
    assert!(res.warnings.is_empty(), "{:?}", res.warnings);
    let alpha = tutorial::Incline::default().alpha;
    assert_eq!(alpha, 30f64.to_radians());
    let m = 700.0 * 0.1f64.powi(3); // DryWood 700 kg/m³, a 0.1 m cube
    let f_n = res.signal_at("plank|block.f_n", 0.4).unwrap()[0];
    let rigid = m * 9.81 * alpha.cos();
    assert!((f_n - rigid).abs() < 1e-6 * rigid, "{f_n} N vs {rigid} N");
    let v = res.signal_at("ball.v_abs", 0.4).unwrap();
    let v = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let rolling = 5.0 / 7.0 * 9.81 * alpha.sin() * 0.4;
    assert!(
        (v - rolling).abs() < 0.01 * rolling,
        "{v} m/s vs {rolling} m/s"
    );
    let png = std::fs::read(dir.join("incline_f_n.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG"), "a PNG");
    let svg = std::fs::read_to_string(dir.join("incline_speed.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("ball.v_abs"), "an SVG");
    let html = std::fs::read_to_string(dir.join("incline.html")).unwrap();
    assert!(
        html.contains("<html") && html.contains("block"),
        "the viewer page"
    );
    std::fs::remove_dir_all(&dir).ok();
}
