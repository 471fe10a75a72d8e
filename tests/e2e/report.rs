//! The study report in a real browser: headless Chromium opens `report/index.html` from the
//! file system (no server) and screenshots it; the picture must show the page and its
//! figures. Without Chromium it prints SKIPPED and passes, unless `XHAB_REQUIRE_CHROMIUM=1`.

use image::RgbImage;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use xhab_experiment::report::{example, figures, write_report};

/// Chromium's executable; panics when `XHAB_REQUIRE_CHROMIUM=1` demands it and it is missing.
fn chromium(test: &str) -> Option<PathBuf> {
    for name in ["chromium", "chromium-browser", "google-chrome"] {
        let found = Command::new("which").arg(name).stderr(Stdio::null()).output().ok().filter(|o| o.status.success());
        if let Some(o) = found {
            return Some(PathBuf::from(String::from_utf8_lossy(&o.stdout).trim()));
        }
    }
    if std::env::var("XHAB_REQUIRE_CHROMIUM").as_deref() == Ok("1") {
        panic!("{test}: XHAB_REQUIRE_CHROMIUM=1 but chromium is not installed (Debian: apt-get install chromium)");
    }
    crate::common::skipped(test, "chromium not installed");
    None
}

/// Screenshots `page` at 1280 × `height` px into `shot` (a minute at most).
fn screenshot(browser: &Path, page: &Path, shot: &Path, height: u32, profile: &Path) {
    let mut child = Command::new(browser)
        .args(["--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", "--no-first-run", "--disable-dev-shm-usage"])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--screenshot={}", shot.display()))
        .arg(format!("--window-size=1280,{height}"))
        .arg(format!("file://{}", page.display()))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starting chromium");
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            if let Some(mut e) = child.stderr.take() {
                std::io::Read::read_to_string(&mut e, &mut err).ok();
            }
            assert!(status.success() && shot.is_file(), "chromium failed ({status}): {err}");
            return;
        }
        if Instant::now() > deadline {
            child.kill().ok();
            child.wait().ok();
            panic!("chromium took over a minute to screenshot {}", page.display());
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// Pixels of `img` that are `c` blended over white, at least `min` of `c` (what a thin line of
/// colour `c` becomes in a scaled-down picture), within `tol` in every channel.
fn count_blended(img: &RgbImage, c: [u8; 3], min: f64, tol: f64) -> usize {
    let d = c.map(|v| 255.0 - v as f64);
    let dd: f64 = d.iter().map(|x| x * x).sum();
    img.pixels()
        .filter(|p| {
            let q = p.0.map(|v| 255.0 - v as f64);
            let a = (0..3).map(|k| q[k] * d[k]).sum::<f64>() / dd;
            (min..=1.05).contains(&a) && (0..3).all(|k| (q[k] - a * d[k]).abs() <= tol)
        })
        .count()
}

/// Pixels of `img` within `tol` of `c` in every channel.
fn count_near(img: &RgbImage, c: [u8; 3], tol: u8) -> usize {
    img.pixels().filter(|p| p.0.iter().zip(c).all(|(a, b)| a.abs_diff(b) <= tol)).count()
}

#[test]
fn report_renders_in_headless_chromium() {
    let test = "report_renders_in_headless_chromium";
    let Some(browser) = chromium(test) else { return };
    let dir = std::env::temp_dir().join(format!("xhab-e2e-report-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    example::write_example(&dir).expect("the example study");
    let page = write_report(&dir).expect("the report");
    let shot = dir.join("screenshot.png");
    screenshot(&browser, &page, &shot, 4000, &dir.join("profile"));

    let img = image::open(&shot).expect("a PNG screenshot").to_rgb8();
    assert_eq!(img.dimensions(), (1280, 4000));
    let n = (img.width() * img.height()) as f64;
    let white = count_near(&img, [255, 255, 255], 2) as f64 / n;
    let dark = img.pixels().filter(|p| p.0.iter().all(|&v| v < 90)).count() as f64 / n;
    let mut colours: Vec<[u8; 3]> = img.pixels().map(|p| p.0).collect();
    colours.sort_unstable();
    colours.dedup();
    eprintln!("{test}: {} colours, {:.1}% not white, {:.2}% dark (text), screenshot {}", colours.len(), 100.0 * (1.0 - white), 100.0 * dark, shot.display());
    assert!(colours.len() > 200, "a blank or flat page: {} colours", colours.len());
    assert!(1.0 - white > 0.05, "the page is {:.1}% white", 100.0 * white);
    // The text rendered (tables, titles, chart labels): dark pixels, not just borders.
    assert!(dark > 0.002, "hardly any text: {:.3}% dark pixels", 100.0 * dark);
    // The SVG figures loaded: each configuration's colour fills its histogram bars and its
    // bars in the other charts.
    for i in 0..4 {
        let c = figures::colour(i);
        let k = count_near(&img, c, 6);
        assert!(k > 2000, "configuration {i}'s colour {c:?} covers only {k} px: the figures did not load");
    }
    // The trajectory maps (PNG) loaded further down: a taller screenshot reaches them.
    let tall = dir.join("screenshot-tall.png");
    screenshot(&browser, &page, &tall, 9000, &dir.join("profile"));
    let img = image::open(&tall).expect("a PNG screenshot").to_rgb8();
    // The paths are thin lines shown scaled down: count their colours blended over white (the
    // configuration colours' blends differ; the legend's swatches are 144 px each).
    let robot = count_blended(&img, xhab_experiment::report::trajectories::ROBOT, 0.4, 8.0);
    let shortest = count_blended(&img, xhab_experiment::report::trajectories::SHORTEST, 0.4, 8.0);
    eprintln!("{test}: {robot} robot-path and {shortest} shortest-path px");
    assert!(robot > 3000 && shortest > 3000, "trajectory maps missing: {robot} robot-path and {shortest} shortest-path px");
    // XHAB_KEEP=1 keeps the folder and its screenshots to look at.
    if std::env::var_os("XHAB_KEEP").is_none() {
        std::fs::remove_dir_all(&dir).ok();
    }
}
