//! Acceptance harness over a local corpus of real controller files (never committed):
//! `KRLKIT_CORPUS=/path/to/corpus cargo test --release --test fmt_corpus -- --ignored --nocapture`.
//! For every KRL file below the folder: the bytes round-trip through decode/encode, the result
//! is idempotent, equivalent on re-parse (no new syntax error, same tokens up to blanks and word
//! case), every protected line (`&` headers, inline-form folds, lines with a syntax error) is
//! byte-identical, every line keeps its ending, and the written bytes keep the encoding.
//! Prints the figures; fails listing the files that break a promise.

mod fmt_support;

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;

use krlkit::fmt::{FmtOptions, check_equivalent, format_text};
use krlkit::syntax::{decode, encode_as};

#[test]
#[ignore = "needs KRLKIT_CORPUS=<folder of real controller files>"]
fn corpus_keeps_every_promise() {
    let dir = PathBuf::from(std::env::var("KRLKIT_CORPUS").expect("set KRLKIT_CORPUS"));
    let walk = krlkit::files::walk(std::slice::from_ref(&dir));
    let opts = FmtOptions::default();
    let (mut files, mut bytes, mut changed, mut lines_changed) = (0usize, 0usize, 0usize, 0usize);
    let mut inline_lines = 0usize;
    let mut header_lines = 0usize;
    let mut failures = Vec::new();
    let start = std::time::Instant::now();
    for c in &walk.found {
        let Ok(raw) = std::fs::read(&c.path) else {
            continue;
        };
        let decoded = decode(&raw);
        if !krlkit::files::looks_like_krl(&decoded.text) {
            continue;
        }
        files += 1;
        bytes += raw.len();
        let name = c.path.display().to_string();
        if decoded.encode() != raw {
            failures.push(format!("{name}: bytes do not round-trip"));
            continue;
        }
        let text = &decoded.text;
        let result = catch_unwind(AssertUnwindSafe(|| {
            let out = format_text(text, &opts);
            let again = format_text(&out.text, &opts);
            if again.text != out.text {
                return Err("not idempotent".to_owned());
            }
            check_equivalent(text, &out.text).map_err(|e| e.to_string())?;
            fmt_support::assert_protected_kept(text, &out.text, &name);
            let written = encode_as(&out.text, decoded.encoding);
            let back = decode(&written);
            if back.encoding != decoded.encoding || back.text != out.text {
                return Err("encoding not kept".to_owned());
            }
            Ok(out)
        }));
        match result {
            Ok(Ok(out)) => {
                if out.changed {
                    changed += 1;
                    let a = fmt_support::lines(text);
                    let b = fmt_support::lines(&out.text);
                    lines_changed += a.len().abs_diff(b.len())
                        + a.iter().zip(&b).filter(|(x, y)| x != y).count();
                }
                let prot = fmt_support::protected(text);
                for ((l, _), p) in fmt_support::lines(text).iter().zip(&prot) {
                    if *p && l.trim_start().starts_with('&') {
                        header_lines += 1;
                    } else if *p {
                        inline_lines += 1;
                    }
                }
            }
            Ok(Err(e)) => failures.push(format!("{name}: {e}")),
            Err(_) => failures.push(format!("{name}: panicked")),
        }
    }
    println!(
        "corpus {}: {files} KRL files, {bytes} bytes in {:.2} s; {changed} files would change \
         ({lines_changed} lines); {header_lines} header lines and {inline_lines} other protected \
         lines (inline forms, syntax errors) kept byte-identical; {} failures",
        dir.display(),
        start.elapsed().as_secs_f64(),
        failures.len()
    );
    assert!(files > 0, "no KRL files below {}", dir.display());
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
