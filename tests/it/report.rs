//! The HTML report end to end, in a real browser: `wireflight diagnose --report` on a flight
//! with a hidden cause writes one self-contained page (nothing fetched: every picture inline),
//! which headless Chromium renders without console errors to a screenshot with drawn bands
//! from top to bottom, and whose DOM holds the verdict and the pictures. `--out model.toml`
//! writes the model with the cause found, and `compare --model` with it is at the noise.
//!
//! Chromium is Debian's `chromium` (`apt-get install chromium`). Without it the browser part
//! is skipped with a note — unless `WIREFLIGHT_REQUIRE_BROWSER=1` (CI sets it), when it fails.
//! Set `WIREFLIGHT_REPORT_KEEP=DIR` to keep the page and its screenshot.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::support::cli::{ok_in, refused_in};
use crate::support::flights::Flight;

/// The browser: `chromium` (or `chromium-browser`) on PATH.
fn chromium() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .flat_map(|d| [d.join("chromium"), d.join("chromium-browser")])
        .find(|p| p.is_file())
}

fn run_chromium(exe: &Path, args: &[&str], page: &Path) -> Output {
    Command::new(exe)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
            "--enable-logging=stderr",
            "--v=0",
        ])
        .args(args)
        .arg(format!("file://{}", page.display()))
        .output()
        .expect("run chromium")
}

/// Console errors a page caused (Chromium logs them as `CONSOLE` lines, uncaught exceptions
/// as `Uncaught`).
fn console_errors(stderr: &str) -> Vec<&str> {
    stderr
        .lines()
        .filter(|l| l.contains("Uncaught") || l.contains(":CONSOLE") || l.contains("Console"))
        .collect()
}

/// A screenshot's rows, as RGB.
fn decode(path: &Path) -> (u32, u32, Vec<[u8; 3]>) {
    let bytes = std::fs::read(path).unwrap();
    let mut dec = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .unwrap();
    let mut buf = vec![0; dec.output_buffer_size().unwrap()];
    let info = dec.next_frame(&mut buf).unwrap();
    let channels = match info.color_type {
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        other => panic!("{}: colour type {other:?}", path.display()),
    };
    let rgb = buf[..info.buffer_size()]
        .chunks_exact(channels)
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    (info.width, info.height, rgb)
}

#[test]
fn diagnose_writes_a_self_contained_report_a_browser_renders_and_a_model_that_fits() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let flight = Flight::new()
        .manoeuvre("flight-test")
        .duration(24)
        .hidden("aircraft:c_m_q=-20")
        .noise_pos(0.05)
        .noise_att(0.05)
        .noise_vel(0.05)
        .noise_rate(0.2);
    ok_in(dir, &flight.args("a.csv"));
    let out = ok_in(
        dir,
        &[
            "diagnose",
            "--flight",
            "a.csv",
            "--report",
            "report.html",
            "--out",
            "model.toml",
        ],
    );
    assert!(out.contains("verdict: `aircraft:c_m_q`"), "{out}");
    assert!(
        out.ends_with("wrote model.toml\nwrote report.html\n"),
        "{out}"
    );

    // The page: one file, nothing fetched, every picture inline.
    let page = dir.join("report.html");
    let html = std::fs::read_to_string(&page).unwrap();
    for bad in ["http://", "https://", "<script", "<link", "@import"] {
        assert!(!html.contains(bad), "the report holds {bad}");
    }
    let images = html.matches("<img src=\"data:image/").count();
    assert!(images >= 5, "{images} inline images");
    assert!(html.contains("data:image/gif;base64,"), "no replay GIF");
    assert!(
        html.contains("pitch damping <code>c_m_q</code>"),
        "no physical name"
    );
    assert!(html.len() < 3_000_000, "the report is {} bytes", html.len());
    // The fitted value and its change from the set, and the ladder.
    assert!(html.contains("<code>c_m_q</code>"));
    assert!(html.contains("How the causes were found"));
    for channel in ["rates q", "air alpha", "velocity down"] {
        assert!(html.contains(channel), "no row for {channel}");
    }

    // The model kept: compare with it is at the noise.
    let model = std::fs::read_to_string(dir.join("model.toml")).unwrap();
    assert!(model.contains("aircraft:c_m_q="), "{model}");
    let cmp = ok_in(
        dir,
        &["compare", "--flight", "a.csv", "--model", "model.toml"],
    );
    let units: f64 = cmp
        .lines()
        .find(|l| l.trim_start().starts_with("× noise"))
        .and_then(|l| l.split_whitespace().last())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("{cmp}"));
    assert!(
        units < 1.1,
        "with the model kept, {units} × the noise: {cmp}"
    );

    if let Ok(keep) = std::env::var("WIREFLIGHT_REPORT_KEEP") {
        std::fs::create_dir_all(&keep).unwrap();
        std::fs::copy(&page, Path::new(&keep).join("report.html")).unwrap();
    }

    // In a real browser.
    let Some(browser) = chromium() else {
        assert!(
            std::env::var("WIREFLIGHT_REQUIRE_BROWSER").as_deref() != Ok("1"),
            "WIREFLIGHT_REQUIRE_BROWSER=1 but no chromium on PATH"
        );
        eprintln!("report: no chromium on PATH; the browser checks are skipped");
        return;
    };
    let shot = dir.join("report.png");
    let o = run_chromium(
        &browser,
        &[
            &format!("--screenshot={}", shot.display()),
            "--window-size=1200,3000",
        ],
        &page,
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "chromium: {stderr}");
    assert!(console_errors(&stderr).is_empty(), "{stderr}");
    let (w, h, rgb) = decode(&shot);
    assert_eq!((w, h), (1200, 3000));
    // Drawn from top to bottom: of 10 horizontal bands, every one has many non-white pixels.
    let band = h as usize / 10;
    for b in 0..10 {
        let drawn = rgb[b * band * w as usize..(b + 1) * band * w as usize]
            .iter()
            .filter(|p| p.iter().any(|&c| c < 200))
            .count();
        assert!(
            drawn > 2000,
            "band {b} of the screenshot: {drawn} drawn pixels"
        );
    }
    if let Ok(keep) = std::env::var("WIREFLIGHT_REPORT_KEEP") {
        std::fs::copy(&shot, Path::new(&keep).join("report.png")).unwrap();
    }

    // The DOM as the browser built it.
    let o = run_chromium(&browser, &["--dump-dom"], &page);
    let dom = String::from_utf8_lossy(&o.stdout);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "chromium: {stderr}");
    assert!(console_errors(&stderr).is_empty(), "{stderr}");
    assert!(dom.contains("id=\"verdict\""), "no verdict in the DOM");
    assert!(
        dom.contains("pitch damping <code>c_m_q</code> is wrong in the set"),
        "the verdict sentence is not in the DOM"
    );
    assert!(
        dom.matches("<img ").count() >= 5,
        "images missing from the DOM"
    );
    assert!(dom.contains("<figcaption>"), "no captions");
}

#[test]
fn compare_keeps_the_added_effects_and_refuses_other_out_names() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let windy = Flight::new()
        .manoeuvre("climbing-turn")
        .duration(16)
        .hidden("wind:north_mps=4,east_mps=-3")
        .noise_pos(0.5)
        .noise_att(0.3);
    ok_in(dir, &windy.args("w.csv"));
    let out = ok_in(
        dir,
        &[
            "compare", "--flight", "w.csv", "--add", "wind", "--out", "m.toml", "--report",
            "r.html",
        ],
    );
    assert!(out.contains("wrote m.toml\nwrote r.html\n"), "{out}");
    let model = std::fs::read_to_string(dir.join("m.toml")).unwrap();
    assert!(
        model.contains("effects = [\"wind\"]") && model.contains("north_mps = "),
        "{model}"
    );
    let html = std::fs::read_to_string(dir.join("r.html")).unwrap();
    assert!(!html.contains("http://") && !html.contains("https://"));
    assert!(html.contains("data:image/gif;base64,"));
    // The kept model is the fitted one: at the noise, with no --add.
    let cmp = ok_in(dir, &["compare", "--flight", "w.csv", "--model", "m.toml"]);
    let units: f64 = cmp
        .lines()
        .find(|l| l.trim_start().starts_with("× noise"))
        .and_then(|l| l.split_whitespace().last())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("{cmp}"));
    assert!(units < 1.25, "{cmp}");

    // Any other --out name is refused before any work, naming the file and both kinds.
    let err = refused_in(dir, &["compare", "--flight", "w.csv", "--out", "x.png"]);
    assert!(
        err.contains("x.png") && err.contains(".gif") && err.contains(".toml"),
        "{err}"
    );
    let err = refused_in(dir, &["diagnose", "--flight", "w.csv", "--report", "r.pdf"]);
    assert!(err.contains("r.pdf") && err.contains(".html"), "{err}");
}
