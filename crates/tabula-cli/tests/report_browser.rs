//! `tabula demo` runs the jobs and writes its report; the report opened in a real
//! browser (headless Chromium): the page loads from disk without script errors, every
//! image and plot decodes, every 3D replay draws (its canvas shows a scene, not one
//! flat colour) — and the same check fails on a copy of the report with a broken
//! picture and a missing replay.
//!
//! Needs Chromium (`apt-get install chromium`; `.ci/run` installs it and sets
//! `TABULA_REQUIRE_BROWSER=1`, so CI fails rather than skips without it).

use std::path::{Path, PathBuf};
use std::process::Command;

fn chromium() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("TABULA_CHROMIUM") {
        return Some(PathBuf::from(p));
    }
    let path = std::env::var_os("PATH")?;
    for dir in std::env::split_paths(&path) {
        for name in ["chromium", "chromium-browser", "google-chrome", "chrome"] {
            let p = dir.join(name);
            if p.is_file() {
                return Some(p);
            }
        }
    }
    None
}

/// Chromium as the machine's notes say it runs here: headless, no sandbox (root),
/// no background networking (the network is closed), WebGL on SwiftShader.
fn browser(chrome: &Path, profile: &Path) -> Command {
    let mut c = Command::new(chrome);
    c.args([
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--enable-unsafe-swiftshader",
        "--use-angle=swiftshader",
        "--virtual-time-budget=30000",
        "--window-size=1280,1600",
    ])
    .arg(format!("--user-data-dir={}", profile.display()));
    c
}

/// The page's own verdict (`#selftest`), read from the DOM after it loaded.
fn self_test(chrome: &Path, page: &Path, scratch: &Path) -> serde_json::Value {
    let out = browser(chrome, &scratch.join("profile-dom"))
        .arg("--dump-dom")
        .arg(format!("file://{}", page.display()))
        .output()
        .expect("run chromium");
    let dom = String::from_utf8_lossy(&out.stdout);
    let start = dom
        .find("<pre id=\"selftest\">")
        .unwrap_or_else(|| panic!("no #selftest in the page: {}", &dom[..dom.len().min(500)]))
        + "<pre id=\"selftest\">".len();
    let end = start + dom[start..].find("</pre>").expect("#selftest closed");
    let text = dom[start..end]
        .replace("&quot;", "\"")
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&");
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("#selftest is not JSON ({e}): {text}"))
}

#[test]
fn the_demo_runs_the_four_jobs_and_its_report_loads_draws_and_shows_every_image() {
    let scratch = Path::new(env!("CARGO_TARGET_TMPDIR")).join("report-browser");
    let _ = std::fs::remove_dir_all(&scratch);
    std::fs::create_dir_all(&scratch).unwrap();
    let report = scratch.join("demo");
    let run = Command::new(env!("CARGO_BIN_EXE_tabula"))
        .args(["demo", "--report"])
        .arg(&report)
        .output()
        .expect("run tabula demo");
    assert!(
        run.status.success(),
        "tabula demo failed: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    let stdout = String::from_utf8_lossy(&run.stdout);
    // Outcomes are pinned by the scenario tests (tests/it/placing.rs, clearing.rs,
    // pick_place.rs, tidying.rs); here: the jobs ran and were summarised.
    for job in [
        "placing     ",
        "clearing    ",
        "pick place  ",
        "tidying     ",
    ] {
        assert!(
            stdout.contains(job),
            "the demo's summary lacks `{job}`:\n{stdout}"
        );
    }
    assert!(stdout.contains("Kinematics") && stdout.contains("index.html"));
    let replays = std::fs::read_dir(&report)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .contains("replay-")
        })
        .count();
    assert_eq!(replays, 4, "one replay per job");

    let Some(chrome) = chromium() else {
        assert!(
            std::env::var_os("TABULA_REQUIRE_BROWSER").is_none(),
            "TABULA_REQUIRE_BROWSER is set but no chromium was found"
        );
        eprintln!("browser part skipped: no chromium on PATH (apt-get install chromium)");
        return;
    };
    let page = report.join("index.html");

    let verdict = self_test(&chrome, &page, &scratch);
    assert_eq!(verdict["ok"], true, "the page's self-test: {verdict}");
    assert_eq!(verdict["errors"].as_array().unwrap().len(), 0, "{verdict}");
    let replays = verdict["replays"].as_array().unwrap();
    assert_eq!(replays.len(), 4, "one replay per job: {verdict}");
    for r in replays {
        assert!(r["colours"].as_u64().unwrap() > 8, "a blank replay: {r}");
    }
    // Every picture and plot the page names is on disk and decoded by the browser.
    let html = std::fs::read_to_string(&page).unwrap();
    let named = html.matches("<img src=").count();
    assert!(named >= 20, "only {named} images in the demo's report");
    assert_eq!(verdict["images"].as_u64().unwrap() as usize, named);

    // A screenshot, kept for people (target/tmp/report-browser/demo.png), not blank.
    let shot = scratch.join("demo.png");
    let status = browser(&chrome, &scratch.join("profile-shot"))
        .arg(format!("--screenshot={}", shot.display()))
        .arg(format!("file://{}", page.display()))
        .output()
        .expect("run chromium");
    assert!(status.status.success() && shot.exists(), "no screenshot");
    let img = image::open(&shot).unwrap().to_rgb8();
    let mut colours = std::collections::HashSet::new();
    for p in img.pixels().step_by(13) {
        colours.insert(p.0);
    }
    assert!(
        colours.len() > 500,
        "a flat screenshot: {} colours",
        colours.len()
    );

    // The check can fail: a truncated picture and a missing replay are reported.
    let broken = scratch.join("broken");
    std::fs::create_dir_all(&broken).unwrap();
    let mut replay_file = None;
    let mut png_file = None;
    for e in std::fs::read_dir(&report).unwrap() {
        let e = e.unwrap();
        let name = e.file_name().to_string_lossy().to_string();
        if name.contains("replay-") && replay_file.is_none() {
            replay_file = Some(name);
            continue;
        }
        if name.ends_with(".png") && png_file.is_none() {
            png_file = Some(name.clone());
            std::fs::write(broken.join(&name), b"\x89PNG\r\n\x1a\n truncated").unwrap();
            continue;
        }
        std::fs::copy(e.path(), broken.join(&name)).unwrap();
    }
    let verdict = self_test(&chrome, &broken.join("index.html"), &scratch);
    assert_eq!(verdict["ok"], false, "{verdict}");
    let broken_list = verdict["broken"].to_string();
    assert!(
        broken_list.contains(png_file.as_deref().unwrap()),
        "{verdict}"
    );
    assert!(
        verdict["replays"]
            .as_array()
            .unwrap()
            .iter()
            .any(|r| r["colours"] == 0 && r["error"].is_string()),
        "{verdict}"
    );
}
