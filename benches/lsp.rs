//! The language server on a workspace of about 1,000 files (~8 MB, generated here) plus one
//! program of just over 10,000 lines: the time from a one-character edit of that program to its new
//! diagnostics being published (inside a routine body, and of a declaration), and the time to
//! answer hover and go-to-definition in it.
//! The server runs in process (its message loop without the stdio threads); the debounce is 0.
//! Then `krlkit lsp` itself is started on the same folder and its resident memory is printed
//! once it has checked every file; `LSP_BENCH_WORKSPACE=<folder>` measures that folder too (a
//! real backup). Run: `cargo bench --bench lsp`
//! (`-- --warm-up-time 1 --measurement-time 5` for a short run).

use std::path::Path;
use std::time::{Duration, Instant};

use criterion::Criterion;
use lsp_server::{Message, Notification, Request, RequestId};
use serde_json::{Value, json};

#[path = "support/sample.rs"]
#[allow(dead_code)] // each bench uses part of it
mod sample;
#[path = "support/tree.rs"]
#[allow(dead_code)] // each bench uses part of it
mod tree;

const BIG: &str = "R1/Program/big_cell.src";

/// The 10,000-line program: the sample's routines, then a routine with an `MM_` call whose
/// first argument the edit toggles between 1 (valid) and 0 (MM003), so every edit changes the
/// findings and is published.
fn big_program() -> String {
    // The routines that make at least 10,000 lines with the header and the added routine.
    let per = sample::synthetic(2).lines().count() - sample::synthetic(1).lines().count();
    let mut s = sample::synthetic(10_000_usize.div_ceil(per));
    s = s
        .replace("DEFDAT bench PUBLIC", "DEFDAT big_cell_data PUBLIC")
        .replace("GLOBAL DEF cell_", "GLOBAL DEF big_");
    let body = s.find("GLOBAL DEF").unwrap();
    s.insert_str(
        body,
        "DEF big_cell( )\r\n  DECL E6AXIS jnt\r\n  MM_Init_Socket(\"XML_Kuka_MMIND\", 873, 871, 60)\r\n  MM_Start_Vis(1, 0, 2, jnt)\r\n  cell_0()\r\nEND\r\n\r\n",
    );
    s
}

fn write_workspace(root: &Path) -> usize {
    let mut bytes = 0;
    let mut files = tree::tree_with(8 << 20, 32);
    files.push(krlkit::lint::Input {
        path: BIG.into(),
        text: big_program(),
    });
    for f in &files {
        let p = root.join(&f.path);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(&p, &f.text).unwrap();
        bytes += f.text.len();
    }
    println!(
        "workspace: {} files, {:.1} MB; {BIG}: {} lines",
        files.len(),
        bytes as f64 / (1 << 20) as f64,
        files.last().unwrap().text.lines().count()
    );
    files.len()
}

fn uri(path: &Path) -> String {
    url::Url::from_file_path(path).unwrap().to_string()
}

struct InProcess {
    server: krlkit::lsp::Server,
    rx: crossbeam_channel::Receiver<Message>,
    uri: String,
    text: String,
    version: i32,
    next_id: i32,
}

impl InProcess {
    fn idle(&mut self) {
        while self.server.pending() > 0 {
            self.server.step();
        }
        while self.rx.try_recv().is_ok() {}
    }

    fn request(&mut self, method: &str, params: Value) -> Value {
        self.next_id += 1;
        self.server.handle(Message::Request(Request::new(
            RequestId::from(self.next_id),
            method.into(),
            params,
        )));
        loop {
            if let Message::Response(r) = self.rx.recv().unwrap() {
                return r.response_result.unwrap();
            }
        }
    }

    /// Position (line, UTF-16 column) of the first `needle` + `offset` bytes (ASCII text).
    fn position(&self, needle: &str, offset: usize) -> Value {
        let at = self.text.find(needle).unwrap() + offset;
        let line = self.text[..at].matches('\n').count();
        let col = at - self.text[..at].rfind('\n').map_or(0, |i| i + 1);
        json!({ "line": line, "character": col })
    }

    /// One edit: the character `offset` bytes into the first `needle` becomes `c`; returns
    /// when the new diagnostics of the file are out.
    fn edit(&mut self, needle: &str, offset: usize, c: &str) -> Duration {
        let pos = self.position(needle, offset);
        let end =
            json!({ "line": pos["line"], "character": pos["character"].as_u64().unwrap() + 1 });
        self.version += 1;
        let change = Notification::new(
            "textDocument/didChange".into(),
            json!({
                "textDocument": { "uri": self.uri, "version": self.version },
                "contentChanges": [ { "range": { "start": pos, "end": end }, "text": c } ],
            }),
        );
        let at = self.text.find(needle).unwrap() + offset;
        self.text.replace_range(at..at + 1, c);
        let start = Instant::now();
        self.server.handle(Message::Notification(change));
        self.server.flush();
        loop {
            match self.rx.recv().unwrap() {
                Message::Notification(n)
                    if n.method == "textDocument/publishDiagnostics"
                        && n.params["uri"] == self.uri =>
                {
                    break;
                }
                _ => {}
            }
        }
        let took = start.elapsed();
        // The other files the edit may affect are checked between messages; not part of the
        // latency, but done before the next edit.
        self.idle();
        took
    }
}

/// Resident memory of `krlkit lsp` on the folder once every file is checked (Linux).
fn server_memory(root: &Path) {
    let Ok(status) = std::fs::read_to_string("/proc/self/status") else {
        println!("memory: /proc not available, not measured");
        return;
    };
    let _ = status;
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_krlkit"))
        .arg("lsp")
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .expect("start krlkit lsp");
    let mut stdin = child.stdin.take().unwrap();
    let mut stdout = std::io::BufReader::new(child.stdout.take().unwrap());
    let mut send = |m: Message| m.write(&mut stdin).unwrap();
    let start = Instant::now();
    send(Message::Request(Request::new(
        RequestId::from(1),
        "initialize".into(),
        json!({ "processId": null, "rootUri": uri(root), "capabilities": {} }),
    )));
    send(Message::Notification(Notification::new(
        "initialized".into(),
        json!({}),
    )));
    let mut id = 1;
    loop {
        id += 1;
        send(Message::Request(Request::new(
            RequestId::from(id),
            "krlkit/status".into(),
            Value::Null,
        )));
        let pending = loop {
            match Message::read(&mut stdout).unwrap().unwrap() {
                Message::Response(r) if r.id == RequestId::from(id) => {
                    break r.response_result.unwrap()["pending"].as_u64().unwrap();
                }
                _ => {}
            }
        };
        if pending == 0 {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let ready = start.elapsed();
    let status = std::fs::read_to_string(format!("/proc/{}/status", child.id())).unwrap();
    let field = |name: &str| {
        status
            .lines()
            .find(|l| l.starts_with(name))
            .map(|l| l[name.len()..].trim().to_owned())
            .unwrap_or_default()
    };
    println!(
        "memory: krlkit lsp on {}, every file checked after {:.2} s: VmRSS {}, VmHWM (peak) {}",
        root.display(),
        ready.as_secs_f64(),
        field("VmRSS:"),
        field("VmHWM:")
    );
    send(Message::Request(Request::new(
        RequestId::from(id + 1),
        "shutdown".into(),
        Value::Null,
    )));
    send(Message::Notification(Notification::new(
        "exit".into(),
        Value::Null,
    )));
    let _ = child.wait();
}

fn main() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().canonicalize().unwrap();
    write_workspace(&root);
    let (tx, rx) = crossbeam_channel::unbounded();
    let mut s = InProcess {
        server: krlkit::lsp::Server::new(tx, Some(root.clone()), krlkit::lsp::Options::default()),
        rx,
        uri: uri(&root.join(BIG)),
        text: std::fs::read_to_string(root.join(BIG)).unwrap(),
        version: 1,
        next_id: 0,
    };
    let t = Instant::now();
    s.server.load_workspace();
    s.idle();
    println!(
        "in process: loaded and checked every file in {:.2} s",
        t.elapsed().as_secs_f64()
    );
    s.server.handle(Message::Notification(Notification::new(
        "textDocument/didOpen".into(),
        json!({ "textDocument": { "uri": s.uri, "languageId": "krl", "version": 1, "text": s.text } }),
    )));
    s.idle();

    let mut c = Criterion::default().configure_from_args();
    let mut g = c.benchmark_group("lsp");
    g.sample_size(20);
    let mut flip = false;
    g.bench_function("edit_to_diagnostics", |b| {
        b.iter_custom(|iters| {
            (0..iters)
                .map(|_| {
                    flip = !flip;
                    s.edit("MM_Start_Vis(", 13, if flip { "0" } else { "1" })
                })
                .sum()
        })
    });
    let hover = json!({
        "textDocument": { "uri": s.uri },
        "position": s.position("MM_Start_Vis(", 20),
    });
    g.bench_function("hover_mm_argument", |b| {
        b.iter(|| s.request("textDocument/hover", hover.clone()))
    });
    let def = json!({
        "textDocument": { "uri": s.uri },
        "position": s.position("cell_0()", 2),
    });
    assert!(!s.request("textDocument/definition", def.clone()).is_null());
    g.bench_function("definition_global_def", |b| {
        b.iter(|| s.request("textDocument/definition", def.clone()))
    });
    g.finish();
    c.final_summary();
    // An edit of a declaration changes what other files may see: the model is rebuilt and
    // every file queued for a re-check (not timed; each takes a whole workspace's check, so
    // a few edits are timed by hand rather than sampled by criterion).
    let times: Vec<f64> = (0..10)
        .map(|k| {
            let c = if k % 2 == 0 { "u" } else { "t" };
            s.edit("DECL E6AXIS jn", 14, c).as_secs_f64() * 1000.0
        })
        .collect();
    let mean = times.iter().sum::<f64>() / times.len() as f64;
    let max = times.iter().copied().fold(0.0, f64::max);
    println!(
        "lsp/edit_declaration_to_diagnostics: mean {mean:.1} ms, max {max:.1} ms over {} edits",
        times.len()
    );
    drop(s);
    server_memory(&root);
    if let Some(real) = std::env::var_os("LSP_BENCH_WORKSPACE") {
        server_memory(
            &Path::new(&real)
                .canonicalize()
                .expect("LSP_BENCH_WORKSPACE"),
        );
    }
}
