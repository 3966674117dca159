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
use report_support::{scenario_poses, trace_of};
use serde_json::Value;

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

const PROBE: &str = r##"<script>
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
  function at(g) {
    var m = g.transform.baseVal.consolidate().matrix;
    return { x: m.e, y: m.f, values: (g.getAttribute("data-values") || "").split(" ").map(Number) };
  }
  function ticks(v, cls, attr) {
    return Array.prototype.map.call(v.querySelectorAll("text." + cls), function (t) {
      return [t[attr].baseVal[0].value, Number(t.textContent)];
    });
  }
  document.querySelectorAll("svg.path-view").forEach(function (v) {
    views[v.getAttribute("data-view")] = {
      vision: v.querySelectorAll("g.vision-pose").length,
      targets: v.querySelectorAll("g.target").length,
      vision_at: Array.prototype.map.call(v.querySelectorAll("g.vision-pose"), at),
      targets_at: Array.prototype.map.call(v.querySelectorAll("g.target"), at),
      ticks_h: ticks(v, "tick-h", "x"),
      ticks_v: ticks(v, "tick-v", "y")
    };
  });
  var calls = Array.prototype.map.call(document.querySelectorAll("#calls tbody tr"), function (r) {
    var c = r.cells;
    return [c[4].textContent, c[5].textContent, r.className];
  });
  var failed_bars = document.querySelectorAll("svg.timeline-view g.bar-error").length;
  var height = document.body.getBoundingClientRect().height;
  var out = { views: views, errors: window.__krlkitErrors, load_ms: performance.now(),
              height: height, calls: calls, failed_bars: failed_bars };
  var pre = document.createElement("pre");
  pre.id = "krlkit-probe";
  pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
});
</script>
"##;

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

/// `(offset, mm per px)` of a view axis, from the first and last labelled grid line as the
/// browser laid them out.
fn axis_fit(ticks: &Value) -> (f64, f64) {
    let t = ticks.as_array().unwrap();
    assert!(
        t.len() >= 2,
        "fewer than two grid labels on an axis: {ticks}"
    );
    let (p0, v0) = (t[0][0].as_f64().unwrap(), t[0][1].as_f64().unwrap());
    let (p1, v1) = (
        t[t.len() - 1][0].as_f64().unwrap(),
        t[t.len() - 1][1].as_f64().unwrap(),
    );
    let per_px = (v1 - v0) / (p1 - p0);
    (v0 - p0 * per_px, per_px)
}

/// Every vision pose and motion target sits where its coordinates say, read back through each
/// view's axis labels (within a pixel); returns the vision poses' `X Y Z A B C` as the page
/// gives them (top view).
fn check_coordinates(o: &Opened) -> Vec<Vec<f64>> {
    for (view, h, v) in [("top", 0, 1), ("front", 0, 2), ("side", 1, 2)] {
        let vw = &o.probe["views"][view];
        let (fh, fv) = (axis_fit(&vw["ticks_h"]), axis_fit(&vw["ticks_v"]));
        let marks = vw["vision_at"]
            .as_array()
            .unwrap()
            .iter()
            .chain(vw["targets_at"].as_array().unwrap());
        for m in marks {
            let values: Vec<f64> = m["values"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            assert_eq!(values.len(), 6, "{view}: {m}");
            let x = m["x"].as_f64().unwrap();
            let y = m["y"].as_f64().unwrap();
            let (wh, wv) = (fh.0 + fh.1 * x, fv.0 + fv.1 * y);
            assert!(
                (wh - values[h]).abs() <= fh.1.abs(),
                "{view}: mark {m} is drawn at {wh} on its horizontal axis"
            );
            assert!(
                (wv - values[v]).abs() <= fv.1.abs(),
                "{view}: mark {m} is drawn at {wv} on its vertical axis"
            );
        }
    }
    o.probe["views"]["top"]["vision_at"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| {
            m["values"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect()
        })
        .collect()
}

/// The scenario's poses of `project`, as the page should give them.
fn poses_of(scenario: &str, project: i64) -> Vec<Vec<f64>> {
    scenario_poses(scenario, project)
        .into_iter()
        .map(|(p, _)| p)
        .collect()
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
    assert_eq!(
        check_coordinates(&o),
        poses_of("tests/fixtures/scenarios/examples.toml", 1)
    );
}

/// The statuses a scenario forces (a failed trigger, a failed fetch) are in the calls table,
/// marked FAILED, and hatched in the timeline; the poses are still all there.
#[test]
fn forced_statuses_are_shown_as_failures() {
    let Some(b) = browser("forced_statuses_are_shown_as_failures") else {
        return;
    };
    let trace = trace_of(
        "tests/fixtures/report/forced.src",
        "tests/fixtures/report/forced.toml",
    );
    let o = open(&b, &report::from_trace(&trace).unwrap());
    check(&o, 2, 2);
    assert_eq!(
        check_coordinates(&o),
        poses_of("tests/fixtures/report/forced.toml", 1)
    );
    let calls: Vec<(String, String, String)> = o.probe["calls"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            let s = |i: usize| c[i].as_str().unwrap().trim().to_string();
            (s(0), s(1), s(2))
        })
        .collect();
    let row = |name: &str, status: &str, class: &str| {
        (name.to_string(), status.to_string(), class.to_string())
    };
    assert_eq!(
        calls,
        [
            row("MM_Init_Socket", "0", "ok"),
            row("MM_Start_Vis", "1007 FAILED", "error"),
            row("MM_Start_Vis", "1102", "ok"),
            row("MM_Get_VisData", "1003 FAILED", "error"),
            row("MM_Get_VisData", "1100", "ok"),
            row("MM_Get_Pose", "1100", "ok"),
            row("MM_Get_Pose", "1100", "ok"),
        ]
    );
    assert_eq!(o.probe["failed_bars"], 2);
}

#[test]
fn a_thousand_motion_report_opens_in_seconds() {
    let Some(b) = browser("a_thousand_motion_report_opens_in_seconds") else {
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
    check_coordinates(&o);
    // The best of up to three loads: a load time on a shared 2-core machine is noisy. The
    // goal is under a second (546-652 ms on a quiet machine); the same machine on a busy day
    // took 1140 ms (best of three) and 2179 ms for Chromium's first start, so the test only
    // guards against a page that takes seconds (a layout or script that grew with the
    // motions squared) and prints the figure.
    let mut load_ms = o.probe["load_ms"].as_f64().unwrap();
    for _ in 0..2 {
        if load_ms < 1000.0 {
            break;
        }
        load_ms = load_ms.min(open(&b, &html).probe["load_ms"].as_f64().unwrap());
    }
    eprintln!(
        "{motions} motions, page {} KB: load event after {load_ms:.0} ms in Chromium \
         ({:.0} ms for the whole headless run)",
        html.len() / 1024,
        o.wall_ms
    );
    assert!(load_ms < 3000.0, "the page took {load_ms} ms to load");
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
