//! Every `sh` command block of README.md runs as printed, so the README cannot drift from the tool.
//!
//! Each block runs in a fresh temporary folder holding a copy of what the README refers to
//! (`krl/`, `xml/`, `as/`, `tests/fixtures/`) plus the reader's own files the examples name
//! (`my_pick.src`, `cell.src`, `path/to/robot/backup` and its `backup.zip`, …). Every
//! line must exit 0, or the code its comment announces as `(exit N: why)`. A `krlkit sim serve` line
//! is started in the background (what "terminal 1" or a trailing `&` means) and waited for; the
//! one liberty taken is its port: the address it listens on (`127.0.0.1:50000` by default)
//! becomes a free port throughout the block, so parallel runs do not collide. Besides `krlkit`,
//! a block may use a few shell utilities (`printf … > spec.toml`); any other command (cargo, npm,
//! python3 …) needs `<!-- readme-test: not run: REASON -->` just above the block, and is then
//! not run: the reason says what covers it instead.

use std::io::Read;
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const MARKER: &str = "<!-- readme-test: not run:";
/// What a debug build may need for the slowest README command (a run against the fake server).
const COMMAND_DEADLINE: Duration = Duration::from_secs(120);
const DEFAULT_ADDR: &str = "127.0.0.1:50000";
/// Commands every `sh` has that README blocks may use to set a scene (`printf … > spec.toml`).
const SHELL_UTILITIES: [&str; 5] = ["printf", "echo", "mkdir", "cp", "cat"];

struct Block {
    /// 1-based line of the opening fence in README.md.
    line: usize,
    /// Why non-krlkit lines are not run; `None` when every line must run.
    not_run: Option<String>,
    commands: Vec<String>,
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn sh_blocks(readme: &str) -> Vec<Block> {
    let lines: Vec<&str> = readme.lines().collect();
    let mut blocks = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        if lines[i].trim_end() != "```sh" {
            i += 1;
            continue;
        }
        let marker = lines[..i]
            .iter()
            .rev()
            .find(|l| !l.trim().is_empty())
            .and_then(|l| l.trim().strip_prefix(MARKER))
            .map(|r| r.trim_end_matches("-->").trim().to_string());
        let start = i;
        i += 1;
        let mut commands = Vec::new();
        while i < lines.len() && lines[i].trim_end() != "```" {
            // A continued line (`\` at its end) is one command.
            let l = lines[i].trim_end();
            if let Some(prev) = commands
                .last_mut()
                .filter(|p: &&mut String| p.ends_with('\\'))
            {
                prev.pop();
                prev.push_str(l.trim_start());
            } else if !l.trim().is_empty() {
                commands.push(l.to_string());
            }
            i += 1;
        }
        blocks.push(Block {
            line: start + 1,
            not_run: marker,
            commands,
        });
        i += 1;
    }
    blocks
}

/// The command without its trailing `# comment`, and the comment.
fn split_comment(line: &str) -> (&str, &str) {
    let bytes = line.as_bytes();
    for (k, &b) in bytes.iter().enumerate() {
        if b == b'#' && k > 0 && bytes[k - 1].is_ascii_whitespace() {
            return (line[..k].trim(), line[k + 1..].trim());
        }
    }
    (line.trim(), "")
}

/// The exit code a comment announces as `(exit N: why)`, else 0 (`(exit 1)` alone says when a
/// command would fail, not that this one does).
fn expected_exit(comment: &str) -> i32 {
    comment
        .split("(exit ")
        .nth(1)
        .and_then(|r| r.split_once(':'))
        .and_then(|(n, _)| n.parse().ok())
        .unwrap_or(0)
}

fn copy_tree(from: &Path, to: &Path) {
    if from.is_dir() {
        std::fs::create_dir_all(to).unwrap();
        for e in std::fs::read_dir(from).unwrap() {
            let e = e.unwrap();
            copy_tree(&e.path(), &to.join(e.file_name()));
        }
    } else {
        if let Some(p) = to.parent() {
            std::fs::create_dir_all(p).unwrap();
        }
        std::fs::copy(from, to).unwrap();
    }
}

fn add_to_zip(zip: &mut zip::ZipWriter<std::fs::File>, from: &Path, name: &str) {
    if from.is_dir() {
        for e in std::fs::read_dir(from).unwrap() {
            let e = e.unwrap();
            let child = format!("{name}/{}", e.file_name().to_string_lossy());
            add_to_zip(zip, &e.path(), &child);
        }
    } else {
        zip.start_file(name, zip::write::SimpleFileOptions::default())
            .unwrap();
        std::io::Write::write_all(zip, &std::fs::read(from).unwrap()).unwrap();
    }
}

/// A folder with what the README refers to, as a reader's checkout plus their own files.
fn workspace(block: &Block) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let r = root();
    for d in ["krl", "xml", "as", "tests/fixtures"] {
        copy_tree(&r.join(d), &dir.path().join(d));
    }
    let own = r.join("tests/fixtures/readme");
    copy_tree(&own, dir.path());
    let placeholders: [(&str, PathBuf); 4] = [
        ("path/to/robot/backup", r.join("krl")),
        ("R1", r.join("krl/R1")),
        ("prog.src", own.join("my_pick.src")),
        // `MM_Init_Socket("XML_Kuka_MMIND", …)` finds the vision server's address beside the program.
        (
            "XML_Kuka_MMIND.xml",
            r.join("xml/Config/User/Common/EthernetKRL/XML_Kuka_MMIND.xml"),
        ),
    ];
    for (name, from) in placeholders {
        copy_tree(&from, &dir.path().join(name));
    }
    // A controller archive of the same backup.
    let file = std::fs::File::create(dir.path().join("backup.zip")).unwrap();
    let mut zip = zip::ZipWriter::new(file);
    add_to_zip(&mut zip, &r.join("krl"), "KRC/R1");
    zip.finish().unwrap();
    // The spec a block uses without writing it is the one `krlkit init` writes.
    let text = block.commands.join("\n");
    if text.contains("krlkit.toml") && !text.contains("krlkit init") {
        let out = krlkit(dir.path(), "krlkit init krlkit.toml");
        assert!(out.status.success(), "krlkit init failed: {out:?}");
    }
    dir
}

fn bin_dir() -> PathBuf {
    Path::new(env!("CARGO_BIN_EXE_krlkit"))
        .parent()
        .unwrap()
        .to_path_buf()
}

fn shell(dir: &Path, command: &str) -> Command {
    let path = std::env::var_os("PATH").unwrap_or_default();
    let mut paths = vec![bin_dir()];
    paths.extend(std::env::split_paths(&path));
    let mut c = Command::new("sh");
    c.arg("-c")
        .arg(command)
        .current_dir(dir)
        .env("PATH", std::env::join_paths(paths).unwrap())
        .env("NO_COLOR", "1");
    c
}

fn krlkit(dir: &Path, command: &str) -> std::process::Output {
    shell(dir, command).output().unwrap()
}

/// Runs a command to its end (or the deadline); its exit code and output.
fn run(dir: &Path, command: &str) -> (Option<i32>, String) {
    let mut child = shell(dir, command)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut out = child.stdout.take().unwrap();
    let mut err = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = out.read_to_string(&mut s);
        s
    });
    let err_reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = err.read_to_string(&mut s);
        s
    });
    let start = Instant::now();
    let code = loop {
        if let Some(st) = child.try_wait().unwrap() {
            break st.code();
        }
        if start.elapsed() > COMMAND_DEADLINE {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let output = format!(
        "--- stdout\n{}\n--- stderr\n{}",
        reader.join().unwrap(),
        err_reader.join().unwrap()
    );
    (code, output)
}

/// A background server, stopped when the block is done.
struct Server(Child);

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn start_server(dir: &Path, command: &str, addr: &str) -> Server {
    let mut child = shell(dir, &format!("exec {command}"))
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while TcpStream::connect(addr).is_err() {
        if let Some(st) = child.try_wait().unwrap() {
            panic!("`{command}` ended ({st}) before it listened on {addr}");
        }
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "`{command}` did not listen on {addr}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    Server(child)
}

/// Where a `krlkit sim serve` command listens.
fn listen_addr(command: &str) -> String {
    let mut words = command.split_whitespace();
    while let Some(w) = words.next() {
        if w == "--listen" {
            return words.next().unwrap_or(DEFAULT_ADDR).to_string();
        }
        if let Some(a) = w.strip_prefix("--listen=") {
            return a.to_string();
        }
    }
    DEFAULT_ADDR.to_string()
}

fn free_addr() -> String {
    let l = TcpListener::bind("127.0.0.1:0").unwrap();
    l.local_addr().unwrap().to_string()
}

/// Runs one block's commands; the failures, described.
fn run_block(block: &Block) -> (Vec<String>, usize) {
    let dir = workspace(block);
    // Each address a server of the block listens on, and the free one it gets instead.
    let addrs: Vec<(String, String)> = block
        .commands
        .iter()
        .filter(|c| c.starts_with("krlkit sim serve"))
        .map(|c| (listen_addr(split_comment(c).0), free_addr()))
        .collect();
    let mut servers = Vec::new();
    let mut failures = Vec::new();
    let mut ran = 0;
    for line in &block.commands {
        let (command, comment) = split_comment(line);
        let program = command.split_whitespace().next().unwrap_or("");
        if SHELL_UTILITIES.contains(&program) {
            let (code, output) = run(dir.path(), command);
            if code != Some(0) {
                failures.push(format!(
                    "README.md:{}: `{command}` exited {code:?}\n{output}",
                    block.line
                ));
            }
            continue;
        }
        if !command.starts_with("krlkit ") {
            if block.not_run.is_none() {
                failures.push(format!(
                    "README.md:{}: `{command}` is not a krlkit command: mark the block with `{MARKER} REASON -->`",
                    block.line
                ));
            }
            continue;
        }
        let mut command = command.trim_end_matches('&').trim().to_string();
        if command.starts_with("krlkit sim serve") && !command.contains("--listen") {
            command.push_str(&format!(" --listen {DEFAULT_ADDR}"));
        }
        for (from, to) in &addrs {
            command = command.replace(from.as_str(), to);
        }
        if command.starts_with("krlkit sim serve") {
            let addr = listen_addr(&command);
            servers.push(start_server(dir.path(), &command, &addr));
            ran += 1;
            continue;
        }
        let want = expected_exit(comment);
        let (code, output) = run(dir.path(), &command);
        ran += 1;
        if code != Some(want) {
            failures.push(format!(
                "README.md:{}: `{command}` exited {code:?}, the README promises {want}\n{output}",
                block.line
            ));
        }
    }
    (failures, ran)
}

#[test]
fn every_readme_command_block_runs_as_printed() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let blocks = sh_blocks(&readme);
    let mut failures = Vec::new();
    let mut ran = 0;
    let mut blocks_run = 0;
    for block in &blocks {
        if let Some(reason) = &block.not_run {
            assert!(
                !reason.is_empty(),
                "README.md:{}: say why the block is not run",
                block.line
            );
        }
        let (f, n) = run_block(block);
        failures.extend(f);
        ran += n;
        blocks_run += usize::from(n > 0);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
    // The README has command blocks in every section: finding few means the parser broke.
    assert!(
        blocks_run >= 10 && ran >= 30,
        "only {ran} commands in {blocks_run} blocks ran"
    );
}

#[test]
fn comments_and_announced_exit_codes_are_read() {
    assert_eq!(
        split_comment("krlkit fmt --diff a.src   # print a diff (exit 1: it would change)"),
        (
            "krlkit fmt --diff a.src",
            "print a diff (exit 1: it would change)"
        )
    );
    assert_eq!(expected_exit("print a diff (exit 1: it would change)"), 1);
    assert_eq!(expected_exit("CI: exit 1 if pkg/ differs"), 0);
    assert_eq!(expected_exit("list files that would change (exit 1)"), 0);
    let blocks = sh_blocks(
        "<!-- readme-test: not run: needs npm -->\n```sh\nnpm i \\\n  x\n```\n\n```sh\nkrlkit rules\n```\n",
    );
    assert_eq!(blocks.len(), 2);
    assert_eq!(blocks[0].not_run.as_deref(), Some("needs npm"));
    assert_eq!(blocks[0].commands, ["npm i x"]);
    assert_eq!((blocks[1].line, blocks[1].not_run.is_none()), (7, true));
}

/// The README travels with the binary (archives, wheel): it names nothing outside the
/// repository, and every relative link it has resolves in it.
#[test]
fn readme_points_only_inside_the_repository() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    for (i, line) in readme.lines().enumerate() {
        assert!(
            !line.contains("../shared") && !line.contains("/work/"),
            "README.md:{}: points outside the repository: {line}",
            i + 1
        );
        for target in line.split("](").skip(1).filter_map(|t| t.split(')').next()) {
            if target.contains("://") || target.starts_with('#') {
                continue;
            }
            let path = target.split('#').next().unwrap_or(target);
            assert!(
                root().join(path).exists(),
                "README.md:{}: link to a missing file `{target}`",
                i + 1
            );
        }
    }
}
