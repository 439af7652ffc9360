//! The HTML player (three.js, inlined) in headless Chromium: it loads offline and renders the
//! scene, plays, and when scrubbed (`?t=`) draws a marked body where the result has it; joints
//! and rods are drawn; contact arrows appear during a contact and only then.
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
    static RUNS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = RUNS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let profile = dir.join(format!("profile-{n}"));
    let out_path = dir.join(format!("stdout-{n}.html"));
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
            // WebGL without a GPU: SwiftShader through ANGLE.
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--window-size=800,600",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(extra)
        .arg(url)
        // To a file: the dumped DOM (three.js inlined) is larger than a pipe's buffer.
        .stdout(std::fs::File::create(&out_path).expect("stdout file"))
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
    std::fs::remove_dir_all(&profile).ok();
    let out = std::fs::read(&out_path).unwrap_or_default();
    std::fs::remove_file(&out_path).ok();
    String::from_utf8_lossy(&out).into_owned()
}

/// The value of attribute `attr` of the element `#modia3d-info` in a dumped DOM.
fn info_attr(dom: &str, attr: &str) -> Option<String> {
    let el = &dom[dom.find("id=\"modia3d-info\"")?..];
    let el = &el[..el.find('>')?];
    let v = &el[el.find(&format!("{attr}=\""))? + attr.len() + 2..];
    Some(v[..v.find('"')?].to_string())
}

/// The screenshot as (width, height, RGB or RGBA bytes, channels).
fn screenshot(png_path: &Path) -> (usize, usize, Vec<u8>, usize) {
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
    (info.width as usize, info.height as usize, buf, channels)
}

/// Pixels between the info line and the control bar that differ clearly from the background
/// (the light floor grid does not count), and all pixels.
fn drawn_pixels(png_path: &Path) -> (usize, usize) {
    let (w, h, buf, channels) = screenshot(png_path);
    let mut drawn = 0;
    for y in 40..h - 50 {
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

/// Headless Chromium, a scratch directory and the page of `result`; `None` (test skipped with
/// a message) when Chromium cannot be had.
fn page_of(result: &SimulationResult, test: &str) -> Option<(PathBuf, PathBuf, PathBuf)> {
    let chromium = match chromium() {
        Ok(p) => p,
        Err(why) => {
            println!("SKIPPED {test}: {why}");
            return None;
        }
    };
    let dir = std::env::temp_dir().join(format!("modia3d-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let page = dir.join("player.html");
    result.write_html(&page).unwrap();
    let html = std::fs::read_to_string(&page).unwrap();
    // three.js names URLs in comments and has loaders; the page loads nothing from a URL.
    for needle in ["src=\"http", "import(\"http", "from \"http", "from 'http"] {
        assert!(!html.contains(needle), "no network reference `{needle}`");
    }
    Some((chromium, dir, page))
}

/// Loads and plays: the page reports the three objects, the renderer, two revolute joints
/// with their rods (each rod body has a joint frame at each end), frames drawn and a time that
/// advanced; the screenshot has the rods and ball drawn (thousands of pixels, not half the
/// screen).
#[test]
fn html_player_loads_and_plays_in_headless_chromium() {
    let result = double_pendulum();
    let Some((chromium, dir, page)) = page_of(&result, "player-plays") else {
        return;
    };
    let url = format!("file://{}", page.display());
    // Frames per virtual second vary with the machine's load (seen: 1 to 21 in 3 s); the first
    // frame starts the clock, so playing shows from the second frame on: up to eight tries
    // (four were not enough once with a load average of ~6 on 2 cores).
    let mut dom = String::new();
    for _ in 0..8 {
        dom = run_chromium(&chromium, &url, &["--dump-dom"], &dir);
        let frames = info_attr(&dom, "data-frames-drawn").and_then(|f| f.parse::<u64>().ok());
        if frames.is_some_and(|f| f >= 2) {
            break;
        }
    }
    let attr = |a: &str| info_attr(&dom, a).unwrap_or_else(|| panic!("{a}; DOM: {dom:.3000}"));
    assert_eq!(attr("data-object-count"), "3", "rod1, rod2 and ball");
    assert!(dom.contains("drag to orbit"), "DOM: {dom:.3000}");
    assert_eq!(attr("data-joint-count"), "2");
    // rev1's frame top1 and rev2's frame bottom1 on body 1 (+ rod1), top2 and ball on body 2.
    let rods: usize = attr("data-rod-count").parse().unwrap();
    assert!(rods >= 3, "{rods} rods");
    let frames: u64 = attr("data-frames-drawn").parse().unwrap();
    let t: f64 = attr("data-time").parse().unwrap();
    // Each frame after the first advances the time by its duration, capped at 0.1 s (the sum
    // of capped durations rounds: 0.1 + 0.1 came out 0.2000000000000002 under load).
    assert!(
        frames >= 2 && t > 0.0 && t <= 0.1 * frames as f64 * (1.0 + 1e-12),
        "playing: {frames} frames, t = {t}"
    );

    let shot = dir.join("play.png");
    run_chromium(
        &chromium,
        &url,
        &[&format!("--screenshot={}", shot.display())],
        &dir,
    );
    let (drawn, total) = drawn_pixels(&shot);
    println!("{frames} frames, t = {t} s, {drawn} of {total} pixels drawn");
    assert!(
        drawn > 1000 && drawn < total / 2,
        "{drawn} of {total} pixels drawn"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A rubber ball (Ø 10 cm) at `r` with velocity `v` over a fixed concrete table of size
/// `table` whose top is at z = 0, simulated with contact results.
fn ball_on_table(table: [f64; 3], r: [f64; 3], v: [f64; 3], opts: SimOptions) -> SimulationResult {
    let mut s = SceneDesc::new();
    s.add(modia3d::demo::world(SceneOptions::default()))
        .add(modia3d::demo::fixed_box(
            "table",
            table,
            [0.0, 0.0, -table[2] / 2.0],
            "Concrete",
        ));
    modia3d::demo::add_free_sphere(&mut s, "ball", 0.1, "NaturalRubber", None, r, v, [0.0; 3]);
    s.build()
        .unwrap()
        .simulate(&opts.tolerance(1e-6).contact_results(true).progress(false))
        .unwrap()
}

/// The ball dropped 0.3 m onto the table: the contact lasts ~8 ms (Hertz, E ≈ 2 MPa), so a
/// 1 ms grid has points inside it.
fn rubber_ball() -> SimulationResult {
    ball_on_table(
        [0.6, 0.6, 0.1],
        [0.0, 0.0, 0.35],
        [0.0; 3],
        SimOptions::new(0.5).interval(1e-3),
    )
}

/// Scrubbed to three output times (falling, in contact, after the rebound) the page draws the
/// ball where the result has it: the drawn position (the ball's three.js object in the scene's
/// world frame, after the animation mixer set the time) equals `ball.r_abs` to 1e-5 m (three.js
/// keeps keyframes and matrices in float32: ~1e-7 relative at 0.35 m, so 1e-5 m is loose yet
/// 1/5000 of the ball's diameter). In the screenshot the pixel where the page projects the
/// ball's centre is the dark rubber, not the light background, and the hover tip there names
/// `ball`. A contact arrow is drawn at the
/// time in contact and none at the other two.
#[test]
fn scrubbed_pose_matches_the_result_and_contact_arrows_appear_during_contact() {
    let result = rubber_ball();
    let time = result.time().to_vec();
    let on = result
        .signal("table|ball.in_contact")
        .or_else(|_| result.signal("ball|table.in_contact"))
        .unwrap()
        .values();
    let first = on
        .iter()
        .position(|&v| v > 0.5)
        .expect("the ball hits the table");
    let len = on[first..].iter().take_while(|&&v| v > 0.5).count();
    assert!(len >= 3, "{len} output points in the contact");
    // The middle of the first contact phase: the force is near its peak.
    let k_contact = first + len / 2;
    let k_fall = k_contact / 2;
    let k_after = (k_contact + 150).min(time.len() - 1);
    assert!(on[k_after] < 0.5 && on[k_fall] < 0.5);
    let r = result.signal("ball.r_abs").unwrap();
    let Some((chromium, dir, page)) = page_of(&result, "player-scrub") else {
        return;
    };
    for (k, contact) in [(k_fall, false), (k_contact, true), (k_after, false)] {
        let url = format!("file://{}?t={:e}&probe=ball", page.display(), time[k]);
        let dom = run_chromium(&chromium, &url, &["--dump-dom"], &dir);
        let attr = |a: &str| info_attr(&dom, a).unwrap_or_else(|| panic!("{a}; DOM: {dom:.3000}"));
        let drawn: Vec<f64> = attr("data-probe-position")
            .split(',')
            .map(|v| v.parse().unwrap())
            .collect();
        let want = r.at(k).unwrap();
        println!("t = {}: drawn {drawn:?}, result {want:?}", time[k]);
        for i in 0..3 {
            assert!(
                (drawn[i] - want[i]).abs() < 1e-5,
                "t = {}: {drawn:?} vs {want:?}",
                time[k]
            );
        }
        assert_eq!(
            attr("data-probe-hover"),
            "ball",
            "the hover tip's name at the ball"
        );
        let t: f64 = attr("data-time").parse().unwrap();
        assert_eq!(t, time[k], "paused at the time asked for");
        let arrows: usize = attr("data-contacts-visible").parse().unwrap();
        assert_eq!(
            arrows,
            usize::from(contact),
            "contact arrows at t = {}",
            time[k]
        );

        let shot = dir.join(format!("scrub{k}.png"));
        run_chromium(
            &chromium,
            &url,
            &[&format!("--screenshot={}", shot.display())],
            &dir,
        );
        let (w, h, buf, channels) = screenshot(&shot);
        let view: Vec<f64> = attr("data-probe-view")
            .split(',')
            .map(|v| v.parse().unwrap())
            .collect();
        // The screenshot's viewport differs from the DOM dump's: place by half heights.
        let half = h as f64 / 2.0;
        let pixel = [
            (w as f64 / 2.0 + view[0] * half).round() as usize,
            (half - view[1] * half).round() as usize,
        ];
        let p = &buf[(pixel[1] * w + pixel[0]) * channels..][..3];
        assert!(
            p.iter().all(|&c| c < 120),
            "t = {}: the ball's centre pixel {pixel:?} is {p:?}",
            time[k]
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// The ball set down on the table with 0.3 m/s along x: it slides, then rolls, and is in
/// contact at the end of the run with its contact point under it. The run starts at 0.2 s: the
/// page's keyframes are at the result's times, not from 0.
fn rolling_ball() -> SimulationResult {
    ball_on_table(
        [0.8, 0.4, 0.1],
        [-0.2, 0.0, 0.0495],
        [0.3, 0.0, 0.0],
        SimOptions::new(0.8).start_time(0.2).interval(0.01),
    )
}

/// Opened at the first output time, one in the middle and the last (`?t=<t_end>`, where the
/// animation clip ends) the page draws the ball where the result has it and its contact marker
/// at the result's contact point. The drawn position must equal `ball.r_abs` to 1e-5 m (three.js
/// keeps keyframes and matrices in float32: ~1e-7 relative at 0.2 m; the ball moves ~0.11 m,
/// so a pose from another output time is off by millimetres, the start pose by ~0.11 m). The
/// marker is drawn from the page's overlay, rounded to 1 µm there: to 1e-5 m of the
/// `point` contact signal too. The number of markers equals the `in_contact` signal. Times past
/// the end (and before the start) show the last (first) pose.
#[test]
fn first_middle_and_last_frames_match_the_result_with_their_contact_markers() {
    let result = rolling_ball();
    let time = result.time().to_vec();
    let last = time.len() - 1;
    let r = result.signal("ball.r_abs").unwrap();
    let pair = |f: &str| {
        result
            .signal(&format!("table|ball.{f}"))
            .or_else(|_| result.signal(&format!("ball|table.{f}")))
            .unwrap()
    };
    let (on, point) = (pair("in_contact"), pair("point"));
    assert!(on.values()[last] > 0.5, "in contact at the end");
    let moved = (r.at(last).unwrap()[0] - r.at(0).unwrap()[0]).abs();
    assert!(moved > 0.05, "the ball rolled {moved} m");
    let Some((chromium, dir, page)) = page_of(&result, "player-ends") else {
        return;
    };
    let t_end = time[last];
    // (time asked for in the URL, output index whose state is expected)
    let cases = [
        (format!("{:e}", time[0]), 0),
        (format!("{:e}", time[last / 2]), last / 2),
        (format!("{t_end:e}"), last),
        // As a user types it: the end time printed with a few digits.
        (format!("{t_end}"), last),
        (format!("{}", t_end + 1.0), last),
        (format!("{}", time[0] - 1.0), 0),
    ];
    for (t, k) in cases {
        let url = format!("file://{}?t={t}&probe=ball", page.display());
        let dom = run_chromium(&chromium, &url, &["--dump-dom"], &dir);
        let attr = |a: &str| info_attr(&dom, a).unwrap_or_else(|| panic!("{a}; DOM: {dom:.3000}"));
        // The page's "x,y,z" against the result's vector, to 1e-5 m (see above).
        let check = |what: &str, want: &[f64]| {
            let drawn: Vec<f64> = attr(what).split(',').map(|v| v.parse().unwrap()).collect();
            println!("t = {t}: {what} {drawn:?}, result {want:?}");
            assert!(
                drawn.len() == 3 && (0..3).all(|i| (drawn[i] - want[i]).abs() < 1e-5),
                "t = {t}: {what} {drawn:?}, result (k = {k}) {want:?}"
            );
        };
        check("data-probe-position", r.at(k).unwrap());
        let contact = on.values()[k] > 0.5;
        let markers: usize = attr("data-contacts-visible").parse().unwrap();
        assert_eq!(markers, usize::from(contact), "contact markers at t = {t}");
        if contact {
            check("data-contact-points", point.at(k).unwrap());
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}
