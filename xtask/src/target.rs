//! The platforms `dist` builds for, and what each one's files are called.

/// One platform: its Rust target, and the names the other packaging tools give it.
pub struct Target {
    pub triple: &'static str,
    /// The binary's file name.
    pub exe: &'static str,
    /// `tar.gz` or `zip`: what users of the platform unpack without extra tools.
    pub archive: Archive,
    /// VS Code's platform name (`vsce package --target`).
    pub vscode: &'static str,
}

#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Archive {
    TarGz,
    Zip,
}

/// macOS would be `x86_64-apple-darwin` / `aarch64-apple-darwin` (`krlkit`, `TarGz`,
/// `darwin-x64` / `darwin-arm64`), built on a Mac: Debian has no linker for it.
pub const TARGETS: &[Target] = &[
    Target {
        triple: "x86_64-unknown-linux-gnu",
        exe: "krlkit",
        archive: Archive::TarGz,
        vscode: "linux-x64",
    },
    Target {
        triple: "x86_64-pc-windows-gnu",
        exe: "krlkit.exe",
        archive: Archive::Zip,
        vscode: "win32-x64",
    },
];

pub fn find(triple: &str) -> Option<&'static Target> {
    TARGETS.iter().find(|t| t.triple == triple)
}
