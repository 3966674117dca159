//! The dry-run report: its view model (snapshot of the data, not the markup) for the traces in
//! `tests/fixtures/report/*.jsonl`, and the page: well-formed (parsed as XML), self-contained
//! (no URL, every in-page reference resolves), one vision mark per vision pose in every view.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use quick_xml::Reader;
use quick_xml::events::Event;

use krlkit::report;

mod report_support;

fn fixture(name: &str) -> String {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/report")
        .join(name);
    std::fs::read_to_string(p).expect("fixture")
}

#[test]
fn view_model_snapshots() {
    insta::glob!("fixtures/report/*.jsonl", |path| {
        let text = std::fs::read_to_string(path).unwrap();
        let entries = report::trace::parse(&text).expect("trace parses");
        insta::assert_json_snapshot!(report::build(&entries));
    });
}

/// What the page holds, read with a strict XML parser: element counts by class per view,
/// ids, in-page references, and every attribute and text that could name a resource.
#[derive(Default, Debug)]
struct Page {
    ids: BTreeSet<String>,
    refs: Vec<String>,
    /// `data-view` → number of `g.vision-pose` inside that view.
    vision_marks: BTreeMap<String, usize>,
    /// `data-view` → number of `g.target` inside that view.
    target_marks: BTreeMap<String, usize>,
    suspicious: Vec<String>,
    elements: BTreeMap<String, usize>,
}

fn class_has(class: &str, wanted: &str) -> bool {
    class.split_whitespace().any(|c| c == wanted)
}

fn read_page(html: &str) -> Page {
    let mut reader = Reader::from_str(html);
    reader.config_mut().check_end_names = true;
    let mut page = Page::default();
    let mut stack: Vec<String> = Vec::new();
    let mut view: Option<(String, usize)> = None;
    loop {
        let ev = reader.read_event().unwrap_or_else(|e| {
            panic!("not well-formed at byte {}: {e}", reader.buffer_position())
        });
        let (start, empty) = match &ev {
            Event::Start(s) => (Some(s.clone()), false),
            Event::Empty(s) => (Some(s.clone()), true),
            _ => (None, false),
        };
        if let Some(s) = start {
            let name = s.name().as_ref().to_string();
            *page.elements.entry(name.clone()).or_default() += 1;
            let mut class = String::new();
            for a in s.attributes() {
                let a = a.expect("attribute well-formed");
                let key = a.key.as_ref().to_string();
                let value = a
                    .normalized_value(quick_xml::XmlVersion::Implicit1_0)
                    .expect("attribute value")
                    .into_owned();
                match key.as_str() {
                    "id" => assert!(page.ids.insert(value.clone()), "id {value} twice"),
                    "href" | "xlink:href" | "src" | "action" | "data" | "poster" => {
                        page.refs.push(value.clone())
                    }
                    "class" => class = value.clone(),
                    "data-view" => view = Some((value.clone(), stack.len())),
                    _ => {}
                }
                if value.contains("://") || value.starts_with("//") {
                    page.suspicious.push(format!("{name} {key}={value}"));
                }
            }
            if let Some((v, _)) = &view {
                if class_has(&class, "vision-pose") {
                    *page.vision_marks.entry(v.clone()).or_default() += 1;
                }
                if class_has(&class, "target") {
                    *page.target_marks.entry(v.clone()).or_default() += 1;
                }
            }
            if !empty {
                stack.push(name);
            }
        }
        match ev {
            Event::End(_) => {
                stack.pop();
                if view
                    .as_ref()
                    .is_some_and(|(_, depth)| stack.len() == *depth)
                {
                    view = None;
                }
            }
            Event::Text(t) => {
                let t: &str = t.as_ref();
                for bad in ["://", "@import", "url(http", "url(//"] {
                    if t.contains(bad) {
                        page.suspicious.push(format!("text containing {bad}"));
                    }
                }
                if t.contains("url(") && t.split("url(").skip(1).any(|r| !r.starts_with('#')) {
                    page.suspicious
                        .push("a url() that is not an in-page #reference".into());
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    assert!(stack.is_empty(), "unclosed elements: {stack:?}");
    page
}

#[test]
fn page_is_well_formed_self_contained_and_marks_every_pose() {
    let text = fixture("cell.jsonl");
    let entries = report::trace::parse(&text).unwrap();
    let model = report::build(&entries);
    let html = report::render(&model).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>"));
    let page = read_page(&html);
    assert!(page.suspicious.is_empty(), "{:?}", page.suspicious);
    for bad in ["link", "img", "iframe", "object", "embed", "base"] {
        assert!(!page.elements.contains_key(bad), "<{bad}> in the page");
    }
    for r in &page.refs {
        let id = r
            .strip_prefix('#')
            .unwrap_or_else(|| panic!("reference {r} leaves the page"));
        assert!(page.ids.contains(id), "reference {r} has no target");
    }
    let views = ["front", "side", "top"];
    let drawn = model.path.motions.iter().filter(|m| !m.axis).count();
    for v in views {
        assert_eq!(
            page.vision_marks.get(v),
            Some(&model.path.vision.len()),
            "{v}"
        );
        assert_eq!(page.target_marks.get(v), Some(&drawn), "{v}");
    }
    // Three poses received (one never fetched), two of them fetched and moved to.
    assert_eq!(model.path.vision.len(), 3);
    // Each drawing has a title and a text description, and a table behind it.
    assert!(page.elements["title"] >= 4 && page.elements["desc"] >= 4);
    assert!(page.elements["table"] >= 5);
}

#[test]
fn the_same_trace_gives_the_same_page() {
    let text = fixture("cell.jsonl");
    assert_eq!(
        report::from_trace(&text).unwrap(),
        report::from_trace(&text).unwrap()
    );
}

#[test]
fn a_bad_trace_is_an_error_naming_the_line() {
    let e = report::from_trace("{\"event\":\"end\",\"status\":\"ok\"}\n{oops\n").unwrap_err();
    assert!(e.to_string().contains("line 2"), "{e}");
}

/// The page marks every pose the vision server sent, also the ones the program never fetched:
/// `first_only.src` takes the first pose of each of the three batches of the examples
/// scenario's project 1 (nine poses).
#[test]
fn every_pose_the_server_sent_is_marked_even_unfetched_ones() {
    let trace = report_support::trace_of(
        "tests/fixtures/report/first_only.src",
        "tests/fixtures/scenarios/examples.toml",
    );
    let model = report::build(&report::trace::parse(&trace).unwrap());
    assert_eq!(model.path.motions.len(), 3);
    let got: Vec<(Vec<f64>, Option<String>)> = model
        .path
        .vision
        .iter()
        .map(|v| {
            let pose = v.values.iter().map(|x| x.parse().unwrap()).collect();
            (pose, v.label.clone())
        })
        .collect();
    let want: Vec<(Vec<f64>, Option<String>)> =
        report_support::scenario_poses("tests/fixtures/scenarios/examples.toml", 1)
            .into_iter()
            .map(|(pose, label)| (pose, Some(label.to_string())))
            .collect();
    assert_eq!(want.len(), 9);
    assert_eq!(got, want);
    // The fetched ones are linked to their motions; the others have none.
    let moved: Vec<usize> = model.path.motions.iter().filter_map(|m| m.vision).collect();
    assert_eq!(moved, [1, 5, 9]);
    let page = read_page(&report::render(&model).unwrap());
    for v in ["front", "side", "top"] {
        assert_eq!(page.vision_marks.get(v), Some(&9), "{v}");
    }
}
