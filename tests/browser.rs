//! The HTML player in headless Chromium: the page renders the scene (non-background pixels in a
//! screenshot) and reports the object count, with WebGL and with the Canvas 2D fallback.
//!
//! Needs Debian's `chromium`; installs it with apt-get when missing and running as root, and
//! otherwise skips with a message.

use modia3d::prelude::*;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The page's background colour (viewer.html's BACKGROUND).
const BACKGROUND: [u8; 3] = [0xee, 0xf1, 0xf5];

fn find_chromium() -> Option<PathBuf> {
    ["/usr/bin/chromium", "/usr/bin/chromium-browser"]
        .iter()
        .map(PathBuf::from)
        .find(|p| p.exists())
}

/// Chromium's path, installing it with apt-get when missing and possible; `Err` says why not.
fn chromium() -> Result<PathBuf, String> {
    if let Some(p) = find_chromium() {
        return Ok(p);
    }
    let root = Command::new("id")
        .arg("-u")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
        .unwrap_or(false);
    if !root {
        return Err("chromium is not installed and this is not root (cannot apt-get)".into());
    }
    if !Path::new("/usr/bin/apt-get").exists() {
        return Err("chromium is not installed and there is no apt-get".into());
    }
    let install = || {
        Command::new("apt-get")
            .args(["install", "-y", "--no-install-recommends", "chromium"])
            .env("DEBIAN_FRONTEND", "noninteractive")
            .stdout(Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    };
    let start = Instant::now();
    if !install() {
        let _ = Command::new("apt-get")
            .arg("update")
            .stdout(Stdio::null())
            .status();
        if !install() {
            return Err("`apt-get install chromium` failed".into());
        }
    }
    eprintln!(
        "installed chromium in {:.0} s",
        start.elapsed().as_secs_f64()
    );
    find_chromium().ok_or_else(|| "chromium installed but not found in /usr/bin".into())
}

/// Runs Chromium headless on `url` with `extra` flags and a fresh profile; returns stdout.
fn run_chromium(chromium: &Path, url: &str, extra: &[&str], dir: &Path) -> String {
    let profile = dir.join(format!("profile-{}", extra.len()));
    let mut child = Command::new(chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--virtual-time-budget=3000",
            "--window-size=800,600",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(extra)
        .arg(url)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("start chromium");
    let deadline = Instant::now() + Duration::from_secs(120);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            child.kill().ok();
            panic!("chromium did not finish within 120 s");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let out = child.wait_with_output().unwrap();
    std::fs::remove_dir_all(&profile).ok();
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The value of attribute `attr` of the element `#modia3d-info` in a dumped DOM.
fn info_attr(dom: &str, attr: &str) -> Option<String> {
    let el = &dom[dom.find("id=\"modia3d-info\"")?..];
    let el = &el[..el.find('>')?];
    let v = &el[el.find(&format!("{attr}=\""))? + attr.len() + 2..];
    Some(v[..v.find('"')?].to_string())
}

/// Pixels of the screenshot, below the info line, that differ clearly from the background (the
/// light floor grid does not count).
fn drawn_pixels(png_path: &Path) -> (usize, usize) {
    let decoder = png::Decoder::new(std::fs::File::open(png_path).unwrap());
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = match info.color_type {
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        c => panic!("unexpected colour type {c:?}"),
    };
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    let (w, h) = (info.width as usize, info.height as usize);
    let mut drawn = 0;
    for y in 40..h {
        for x in 0..w {
            let p = &buf[(y * w + x) * channels..][..3];
            if (0..3).any(|i| p[i].abs_diff(BACKGROUND[i]) > 50) {
                drawn += 1;
            }
        }
    }
    (drawn, w * h)
}

/// A double pendulum of two boxes with a ball at the end.
fn double_pendulum() -> SimulationResult {
    let rod = || {
        Solid::new(Shape::Box {
            lengths: Vector3::new(0.05, 0.05, 1.0),
        })
        .mass(1.0)
    };
    let mut s = SceneDesc::new();
    s.add(Object3D::new("world").scene(SceneOptions::default()))
        .add(Object3D::new("top1"))
        .add(
            Object3D::new("rod1")
                .parent("top1")
                .translation([0.0, 0.0, -0.5])
                .solid(rod()),
        )
        .add(
            Object3D::new("bottom1")
                .parent("rod1")
                .translation([0.0, 0.0, -0.5]),
        )
        .add(Object3D::new("top2"))
        .add(
            Object3D::new("rod2")
                .parent("top2")
                .translation([0.0, 0.0, -0.5])
                .solid(rod()),
        )
        .add(
            Object3D::new("ball")
                .parent("rod2")
                .translation([0.0, 0.0, -0.5])
                .feature(Feature::Visual(Shape::Sphere { diameter: 0.2 })),
        )
        .add_joint(Joint::new("rev1", "world", "top1", JointKind::revolute(1)).init_position(1.2))
        .add_joint(
            Joint::new("rev2", "bottom1", "top2", JointKind::revolute(1)).init_position(-0.6),
        );
    s.build()
        .unwrap()
        .simulate(&SimOptions::new(2.0).tolerance(1e-6).interval(0.02))
        .unwrap()
}

#[test]
fn html_player_renders_the_scene_in_headless_chromium() {
    let chromium = match chromium() {
        Ok(p) => p,
        Err(why) => {
            println!("SKIPPED html_player_renders_the_scene_in_headless_chromium: {why}");
            return;
        }
    };
    let result = double_pendulum();
    let dir = std::env::temp_dir().join(format!("modia3d-browser-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let page = dir.join("player.html");
    result.write_html(&page).unwrap();
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(
        !html.contains("http://") && !html.contains("https://"),
        "no network references"
    );

    for (query, renderers) in [
        ("", &["webgl", "canvas2d"][..]),
        ("?renderer=2d", &["canvas2d"][..]),
    ] {
        let url = format!("file://{}{query}", page.display());
        let dom = run_chromium(&chromium, &url, &["--dump-dom"], &dir);
        let count = info_attr(&dom, "data-object-count").expect("#modia3d-info in the DOM");
        assert_eq!(count, "3", "rod1, rod2 and ball; DOM: {dom:.2000}");
        let frames: u64 = info_attr(&dom, "data-frames-drawn")
            .unwrap()
            .parse()
            .unwrap();
        assert!(frames >= 1, "frames drawn: {frames}");
        assert!(
            renderers.iter().any(|r| dom.contains(&format!("· {r}<"))),
            "renderer {renderers:?} expected; DOM: {dom:.2000}"
        );

        let shot = dir.join(format!("shot{}.png", query.len()));
        run_chromium(
            &chromium,
            &url,
            &[&format!("--screenshot={}", shot.display())],
            &dir,
        );
        let (drawn, total) = drawn_pixels(&shot);
        println!("{url}: {frames} frames, {drawn} of {total} pixels drawn");
        // Two 5 cm × 1 m rods and a 20 cm ball framed in 800 × 600: thousands of pixels, and
        // far from all of them.
        assert!(
            drawn > 1000 && drawn < total / 2,
            "{drawn} of {total} pixels drawn"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
