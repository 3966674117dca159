//! `krlkit --version` names the commit when built from a git checkout: `0.1.0 (1a2b3c4d5)`.
//! A build from crates.io (or `cargo package`) has no `.git` and prints the version alone.
//! Under `CI` it sets `cfg(krlkit_ci)`, which runs the tests that need CI's tools.

use std::path::Path;
use std::process::Command;

fn main() {
    let root = std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR");
    let root = Path::new(&root);
    println!("cargo:rerun-if-changed=build.rs");
    // Tests that need a tool CI installs (tests/lsp_nvim.rs: Neovim) are ignored elsewhere, with
    // the reason in the test's outcome, and run (failing without the tool) in CI.
    println!("cargo:rustc-check-cfg=cfg(krlkit_ci)");
    println!("cargo:rerun-if-env-changed=CI");
    if std::env::var("CI").is_ok_and(|v| !v.is_empty() && v != "false" && v != "0") {
        println!("cargo:rustc-cfg=krlkit_ci");
    }
    // `.git` is a folder in a clone and a file in a worktree.
    if !root.join(".git").exists() {
        return;
    }
    let git = |args: &[&str]| {
        let out = Command::new("git")
            .args(args)
            .current_dir(root)
            .output()
            .ok()?;
        let text = String::from_utf8(out.stdout).ok()?;
        out.status.success().then(|| text.trim().to_string())
    };
    let Some(commit) = git(&["rev-parse", "--short=9", "HEAD"]) else {
        return;
    };
    println!(
        "cargo:rustc-env=KRLKIT_VERSION={} ({commit})",
        std::env::var("CARGO_PKG_VERSION").expect("cargo sets CARGO_PKG_VERSION")
    );
    // A commit or checkout moves HEAD's log; nothing else needs a rebuild.
    if let Some(dir) = git(&["rev-parse", "--absolute-git-dir"]) {
        for f in ["HEAD", "logs/HEAD"] {
            println!(
                "cargo:rerun-if-changed={}",
                Path::new(&dir).join(f).display()
            );
        }
    }
}
