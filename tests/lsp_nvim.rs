//! A real editor end to end: Neovim (headless) starts `krlkit lsp` with its built-in LSP client
//! on the fixture backup, and the test checks the diagnostics Neovim received and where its
//! go-to-definition jumped (a GLOBAL DEF in another module, a `$config.dat` global).
//! It needs `nvim`: outside CI it is ignored, with that reason in the test's outcome (run it
//! with `cargo test --test lsp_nvim -- --ignored`); in CI (`cfg(krlkit_ci)`, set by build.rs
//! when `CI` is set; `.ci/run` installs Neovim) it runs and fails without Neovim.

mod lsp_support;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

fn nvim_available() -> bool {
    Command::new("nvim")
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

#[test]
#[cfg_attr(
    not(krlkit_ci),
    ignore = "needs Neovim (`nvim`; apt-get install neovim): CI runs it; here `cargo test --test lsp_nvim -- --ignored`"
)]
fn neovim_shows_diagnostics_and_jumps_to_definitions() {
    assert!(
        nvim_available(),
        "this test needs Neovim (`nvim` on PATH; .ci/run installs the Debian package `neovim`)"
    );
    let fixture = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/lsp");
    let dir = lsp_support::copy_tree(&fixture.join("backup"));
    let root = dir.path().canonicalize().unwrap();
    let out = root.join("nvim_result.json");
    let mut child = Command::new("nvim")
        .args(["--headless", "--clean", "-c"])
        .arg(format!(
            "luafile {}",
            fixture.join("nvim_e2e.lua").display()
        ))
        .env("KRLKIT_ROOT", &root)
        .env("KRLKIT_BIN", env!("CARGO_BIN_EXE_krlkit"))
        .env("KRLKIT_OUT", &out)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("start nvim");
    let deadline = Instant::now() + Duration::from_secs(90);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("nvim did not finish in 90 s");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let result: Value =
        serde_json::from_str(&std::fs::read_to_string(&out).expect("nvim wrote its results"))
            .unwrap();
    assert!(result["error"].is_null(), "{}", result["error"]);

    let mut found: Vec<(u64, String)> = result["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| {
            (
                d["line"].as_u64().unwrap(),
                d["code"].as_str().unwrap_or("?").to_owned(),
            )
        })
        .collect();
    found.sort();
    let expected = [
        (3, "KRL003"),
        (4, "KRL016"),
        (5, "MM003"),
        (5, "MM010"),
        (7, "MM001"),
        (8, "KRL004"),
    ];
    let expected: Vec<(u64, String)> = expected.iter().map(|(l, c)| (*l, c.to_string())).collect();
    assert_eq!(found, expected, "diagnostics Neovim received");

    let defs = result["definitions"].as_array().unwrap();
    let at = |i: usize| {
        let d = &defs[i];
        (
            d["file"].as_str().unwrap().to_owned(),
            d["line"].as_u64().unwrap(),
            d["col"].as_u64().unwrap(),
        )
    };
    // `GLOBAL DEF grip_open(wait_s:IN)`: line 6, the name at column 12.
    assert_eq!(at(0), ("gripper.src".into(), 6, 12), "grip_open");
    // `DECL INT g_vis_job=1` in $config.dat: line 5, column 10.
    assert_eq!(at(1), ("$config.dat".into(), 5, 10), "g_vis_job");
}
