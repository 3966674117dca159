//! The report in a real browser: headless Chromium (Debian package `chromium`; `.ci/run`
//! installs it) opens the page of an example run and of a 1 054-motion run, with the network
//! cut off (`--host-resolver-rules`), and a probe script added to the page reports what the DOM
//! holds once loaded: the vision marks and targets in each view, errors thrown or logged, and
//! the time to the load event. Chromium's own console log (stderr) must be empty too.
//!
//! Without Chromium the tests are skipped with a message, except in CI (`CI` set), where they
//! fail. `KRLKIT_CHROMIUM` names another browser binary.

mod report_support;

use std::path::PathBuf;
use std::process::Command;
use std::time::Instant;

use krlkit::report;
use report_support::trace_of;

fn chromium() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("KRLKIT_CHROMIUM") {
        return Some(PathBuf::from(p));
    }
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .flat_map(|d| ["chromium", "chromium-browser"].map(|n| d.join(n)))
        .find(|p| p.is_file())
}

/// The browser, or `None` after saying why the test is skipped (outside CI only).
fn browser(test: &str) -> Option<PathBuf> {
    let found = chromium();
    if found.is_none() {
        assert!(
            std::env::var_os("CI").is_none(),
            "{test}: chromium is not installed; CI must have it (`apt-get install -y chromium`)"
        );
        eprintln!(
            "{test}: SKIPPED: chromium not found (install the Debian package `chromium`, or set \
             KRLKIT_CHROMIUM)"
        );
    }
    found
}

const PROBE: &str = r#"<script>
window.__krlkitErrors = [];
window.addEventListener("error", function (e) { window.__krlkitErrors.push(String(e.message)); });
(function () {
  var orig = console.error;
  console.error = function () {
    window.__krlkitErrors.push(Array.prototype.join.call(arguments, " "));
    return orig.apply(console, arguments);
  };
})();
window.addEventListener("load", function () {
  var views = {};
  document.querySelectorAll("svg.path-view").forEach(function (v) {
    views[v.getAttribute("data-view")] = {
      vision: v.querySelectorAll("g.vision-pose").length,
      targets: v.querySelectorAll("g.target").length
    };
  });
  var height = document.body.getBoundingClientRect().height;
  var out = { views: views, errors: window.__krlkitErrors, load_ms: performance.now(),
              height: height };
  var pre = document.createElement("pre");
  pre.id = "krlkit-probe";
  pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
});
</script>
"#;

struct Opened {
    probe: serde_json::Value,
    console: Vec<String>,
    wall_ms: f64,
}

/// Open `html` (with the probe added at the top of `<head>`) and read back the probe's result.
fn open(browser: &PathBuf, html: &str) -> Opened {
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("report.html");
    let probed = html.replacen("<head>", &format!("<head>\n{PROBE}"), 1);
    std::fs::write(&page, probed).unwrap();
    let started = Instant::now();
    let out = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            "--host-resolver-rules=MAP * ~NOTFOUND",
            "--enable-logging=stderr",
            "--v=0",
        ])
        .arg(format!(
            "--user-data-dir={}",
            dir.path().join("profile").display()
        ))
        .arg("--dump-dom")
        .arg(format!("file://{}", page.display()))
        .output()
        .expect("chromium runs");
    let wall_ms = started.elapsed().as_secs_f64() * 1000.0;
    let dom = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let json = dom
        .split("<pre id=\"krlkit-probe\">")
        .nth(1)
        .and_then(|rest| rest.split("</pre>").next())
        .unwrap_or_else(|| panic!("no probe result in the DOM; chromium said:\n{stderr}"));
    let json = json.replace("&quot;", "\"").replace("&amp;", "&");
    Opened {
        probe: serde_json::from_str(&json).expect("probe JSON"),
        console: stderr
            .lines()
            .filter(|l| l.contains(":CONSOLE"))
            .map(str::to_string)
            .collect(),
        wall_ms,
    }
}

/// Marks per view as the browser counts them.
fn counts(o: &Opened, view: &str) -> (u64, u64) {
    let v = &o.probe["views"][view];
    (
        v["vision"].as_u64().unwrap(),
        v["targets"].as_u64().unwrap(),
    )
}

fn check(o: &Opened, vision: u64, targets: u64) {
    for view in ["top", "front", "side"] {
        assert_eq!(counts(o, view), (vision, targets), "{view} view");
    }
    assert_eq!(o.probe["errors"], serde_json::json!([]), "page errors");
    assert!(o.console.is_empty(), "console: {:?}", o.console);
}

#[test]
fn example_report_shows_every_vision_pose() {
    let Some(b) = browser("example_report_shows_every_vision_pose") else {
        return;
    };
    let trace = trace_of(
        "krl/examples/vision_pick.src",
        "tests/fixtures/scenarios/examples.toml",
    );
    let o = open(&b, &report::from_trace(&trace).unwrap());
    // The examples scenario's project 1 has nine poses; the program moves to each.
    check(&o, 9, 9);
}

#[test]
fn a_thousand_motion_report_opens_in_under_a_second() {
    let Some(b) = browser("a_thousand_motion_report_opens_in_under_a_second") else {
        return;
    };
    let trace = trace_of(
        "tests/fixtures/report/pick_loop.src",
        "tests/fixtures/report/pick_loop.toml",
    );
    let entries = report::trace::parse(&trace).unwrap();
    let model = report::build(&entries);
    let motions = model.path.motions.len() as u64;
    let drawn = model.path.motions.iter().filter(|m| !m.axis).count() as u64;
    assert!(motions >= 1000, "{motions} motions");
    let html = report::render(&model).unwrap();
    let o = open(&b, &html);
    check(&o, 20, drawn);
    let load_ms = o.probe["load_ms"].as_f64().unwrap();
    eprintln!(
        "{motions} motions, page {} KB: load event after {load_ms:.0} ms in Chromium \
         ({:.0} ms for the whole headless run)",
        html.len() / 1024,
        o.wall_ms
    );
    assert!(load_ms < 1000.0, "the page took {load_ms} ms to load");
}

#[test]
fn the_probe_sees_errors() {
    let Some(b) = browser("the_probe_sees_errors") else {
        return;
    };
    let html = "<!DOCTYPE html>\n<html><head><title>x</title></head><body>\
                <script>console.error(\"boom\"); noSuchFunction();</script></body></html>";
    let o = open(&b, html);
    let errors = o.probe["errors"].to_string();
    assert!(
        errors.contains("boom") && errors.contains("noSuchFunction"),
        "{errors}"
    );
    assert_eq!(o.console.len(), 2, "{:?}", o.console);
}
