//! The translation's replay tape: what the first pass lowered, written as it goes, for the
//! second pass to read back instead of parsing and lowering every statement again.
//!
//! The tape holds, in order, each routine's begin and end and between them each statement's
//! lowered ops (before the motions are resolved) with the runs the flow recorded for them
//! ([`ir::flow::Runs`]): all the second pass needs. It lives in a temporary file for the CLI
//! (the page cache, not the process, holds it) or in memory for a translation in memory. Each
//! event is a length and its `bincode` encoding; the `&'static` references in the ops are
//! indices into process-wide tables (`ir/codec.rs`), so a tape is read back by the process
//! that wrote it.

use std::fs::File;
use std::io::{self, BufReader, BufWriter, Read, Seek, Write};

use bincode::Options as _;
use serde::{Deserialize, Serialize};

use super::ir;

/// One event of the tape, as written.
#[derive(Serialize)]
enum Written<'a> {
    Begin(ir::RoutineId),
    Ops(&'a ir::Block, &'a ir::flow::Runs),
    End,
}

/// Appends `e`'s length and encoding to `v` (nothing when it cannot be encoded).
fn encode(v: &mut Vec<u8>, e: &Written<'_>) -> io::Result<()> {
    let at = v.len();
    v.extend_from_slice(&[0; 4]);
    if let Err(err) = codec().serialize_into(&mut *v, e) {
        v.truncate(at);
        return Err(io::Error::other(err));
    }
    let len = (v.len() - at - 4) as u32;
    v[at..at + 4].copy_from_slice(&len.to_le_bytes());
    Ok(())
}

/// One event of the tape, as read back (the same encoding as [`Written`]).
#[derive(Deserialize)]
pub(super) enum Event {
    Begin(ir::RoutineId),
    Ops(ir::Block, ir::flow::Runs),
    End,
}

fn codec() -> impl bincode::Options {
    bincode::DefaultOptions::new().with_fixint_encoding()
}

enum To {
    Memory(Vec<u8>),
    File(BufWriter<File>),
    /// A file written on a thread of its own.
    Behind(Behind),
}

/// How many bytes of events [`Behind`] gathers before handing them on, and how many such
/// chunks may wait.
const CHUNK: usize = 1 << 18;
const CHUNKS: usize = 4;

/// A file written on a thread of its own: the events' encodings are gathered here in chunks,
/// which the thread writes and hands back to be filled again (the `write`s were a tenth of the
/// first pass's critical path). Only bytes cross: the ops stay on the thread that made them
/// (handing them over to be encoded there kept each batch alive longer, and the first pass's
/// allocations slowed by more than the encoding saved).
struct Behind {
    chunk: Vec<u8>,
    send: std::sync::mpsc::SyncSender<Vec<u8>>,
    returned: std::sync::mpsc::Receiver<Vec<u8>>,
    /// The file back, with the first write error.
    thread: std::thread::JoinHandle<(File, io::Result<()>)>,
}

impl Behind {
    /// Writes to `file` on a thread of its own; the file back when no thread can be had.
    fn start(file: File) -> Result<Behind, File> {
        let (give, take) = std::sync::mpsc::channel::<File>();
        let (send, receive) = std::sync::mpsc::sync_channel::<Vec<u8>>(CHUNKS);
        let (give_back, returned) = std::sync::mpsc::channel::<Vec<u8>>();
        let spawned = std::thread::Builder::new()
            .name("tape".into())
            .spawn(move || {
                let mut file = take.recv().expect("the file is handed over");
                let mut written = Ok(());
                for chunk in receive {
                    if written.is_ok() {
                        written = file.write_all(&chunk);
                    }
                    // Back to be filled again (or dropped) where it was allocated.
                    let _ = give_back.send(chunk);
                }
                (file, written)
            });
        match spawned {
            Ok(thread) => {
                give.send(file).expect("the thread waits for the file");
                Ok(Behind {
                    chunk: Vec::with_capacity(CHUNK),
                    send,
                    returned,
                    thread,
                })
            }
            Err(_) => Err(file),
        }
    }

    /// Bytes were added to the chunk: a full one goes to the thread.
    fn written(&mut self) {
        if self.chunk.len() >= CHUNK {
            let next = self.returned.try_recv().map_or_else(
                |_| Vec::with_capacity(CHUNK + 4096),
                |mut done| {
                    done.clear();
                    done
                },
            );
            let full = std::mem::replace(&mut self.chunk, next);
            // The receiver only stops early when the thread panicked (seen at `finish`).
            let _ = self.send.send(full);
        }
    }

    /// Everything written: the file back.
    fn finish(self) -> io::Result<File> {
        let Behind {
            chunk,
            send,
            returned,
            thread,
        } = self;
        if !chunk.is_empty() {
            let _ = send.send(chunk);
        }
        drop(send);
        let (file, written) = thread
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        drop(returned);
        written.map(|()| file)
    }
}

/// The tape being written.
pub(super) struct Writer {
    to: To,
    /// Scratch: one event's encoding.
    buf: Vec<u8>,
    events: u64,
    /// The first write error (reported when the tape is read).
    error: Option<io::Error>,
}

impl Writer {
    /// A tape in memory.
    pub(super) fn memory() -> Writer {
        Writer::new(To::Memory(Vec::new()))
    }

    /// A tape in `file` (an unnamed temporary file), written on a thread of its own when one
    /// can be had.
    pub(super) fn file(file: File) -> Writer {
        match Behind::start(file) {
            Ok(behind) => Writer::new(To::Behind(behind)),
            Err(file) => Writer::file_here(file),
        }
    }

    /// A tape in `file`, written on this thread.
    fn file_here(file: File) -> Writer {
        Writer::new(To::File(BufWriter::with_capacity(1 << 16, file)))
    }

    fn new(to: To) -> Writer {
        Writer {
            to,
            buf: Vec::new(),
            events: 0,
            error: None,
        }
    }

    pub(super) fn begin(&mut self, id: ir::RoutineId) {
        self.write(&Written::Begin(id));
    }

    pub(super) fn ops(&mut self, ops: &ir::Block, runs: &ir::flow::Runs) {
        self.write(&Written::Ops(ops, runs));
    }

    pub(super) fn end(&mut self) {
        self.write(&Written::End);
    }

    fn write(&mut self, e: &Written<'_>) {
        if self.error.is_some() {
            return;
        }
        // Encoded in place where the bytes go, its length written before it once known (a
        // copy of every event's bytes was a tenth of the tape's time).
        let written = match &mut self.to {
            To::Memory(v) => encode(v, e),
            To::Behind(b) => encode(&mut b.chunk, e).map(|()| b.written()),
            To::File(f) => {
                self.buf.clear();
                encode(&mut self.buf, e).and_then(|()| f.write_all(&self.buf))
            }
        };
        match written {
            Ok(()) => self.events += 1,
            Err(e) => self.error = Some(e),
        }
    }

    /// The tape written, to be read from its start.
    pub(super) fn finish(self) -> io::Result<Reader> {
        self.read_back().map_err(named)
    }

    fn read_back(self) -> io::Result<Reader> {
        if let Some(e) = self.error {
            return Err(e);
        }
        let from = match self.to {
            To::Memory(v) => From::Memory(v, 0),
            To::File(f) => {
                let mut f = f.into_inner().map_err(io::IntoInnerError::into_error)?;
                f.rewind()?;
                From::File(BufReader::with_capacity(1 << 16, f))
            }
            To::Behind(b) => {
                let mut f = b.finish()?;
                f.rewind()?;
                From::File(BufReader::with_capacity(1 << 16, f))
            }
        };
        Ok(Reader {
            from,
            buf: Vec::new(),
            left: self.events,
        })
    }
}

enum From {
    /// The bytes and how many were read.
    Memory(Vec<u8>, usize),
    File(BufReader<File>),
}

/// The tape being read back, event by event.
pub(super) struct Reader {
    from: From,
    buf: Vec<u8>,
    left: u64,
}

impl Reader {
    /// The next event (`None` after the last one).
    pub(super) fn next(&mut self) -> io::Result<Option<Event>> {
        self.read().map_err(named)
    }

    fn read(&mut self) -> io::Result<Option<Event>> {
        if self.left == 0 {
            return Ok(None);
        }
        self.left -= 1;
        let bytes = match &mut self.from {
            From::Memory(v, at) => {
                let len = take(v, at, 4)?;
                let len = u32::from_le_bytes(len.try_into().expect("four bytes")) as usize;
                take(v, at, len)?
            }
            From::File(f) => {
                let mut len = [0u8; 4];
                f.read_exact(&mut len)?;
                self.buf.resize(u32::from_le_bytes(len) as usize, 0);
                f.read_exact(&mut self.buf)?;
                &self.buf[..]
            }
        };
        codec()
            .deserialize(bytes)
            .map(Some)
            .map_err(io::Error::other)
    }
}

/// A tape's error says it is the tape's: the CLI reports it under the output it was writing,
/// and the tape is elsewhere (the system's temporary folder), so "no space left" alone would
/// send the user to the wrong disk.
fn named(e: io::Error) -> io::Error {
    io::Error::new(
        e.kind(),
        format!("the translation's replay file in the system's temporary folder: {e}"),
    )
}

/// The next `n` bytes of `v` from `at`.
fn take<'v>(v: &'v [u8], at: &mut usize, n: usize) -> io::Result<&'v [u8]> {
    let bytes = v
        .get(*at..*at + n)
        .ok_or_else(|| io::Error::from(io::ErrorKind::UnexpectedEof))?;
    *at += n;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::super::{Lowered, Source, Target, each_lowered, first_pass, render};
    use super::*;

    /// What the second pass resolves, in order: a routine's begin, each statement's ops as
    /// resolved, its end.
    #[derive(Debug, PartialEq)]
    enum Seen {
        Begin(ir::RoutineId),
        Ops(ir::Block),
        End,
    }

    /// The second pass both ways on one program: the ops read back from the tape, resolved in
    /// the runs the first pass recorded; and the statements lowered again, resolved with the
    /// routine's graph built again from them (the way before the tape).
    fn both_ways(target: Target, src: Source, dat: Option<Source>) -> [Vec<Seen>; 2] {
        let backend = render::backend(target);
        let options = crate::transpile::Options::default();
        let first = first_pass(backend, src, dat, &options, Writer::memory());
        let flow = ir::flow::solve(first.graphs, &first.model);
        let mut tape = first.tape.expect("a tape in memory");
        let mut replayed = Vec::new();
        let mut resolver = None;
        while let Some(e) = tape.next().expect("the tape reads back") {
            replayed.push(match e {
                Event::Begin(id) => {
                    resolver = Some(flow.resolver(id));
                    Seen::Begin(id)
                }
                Event::Ops(mut ops, runs) => {
                    resolver.as_mut().expect("begun").replay(&mut ops, &runs);
                    Seen::Ops(ops)
                }
                Event::End => Seen::End,
            });
        }
        let second = || first.replay.lower(&first.model, &first.program, &options);
        let mut fresh = Vec::new();
        let mut resolver = None;
        each_lowered(&first.program, second, 1, |e| {
            fresh.push(match e {
                Lowered::Begin(id) => {
                    resolver = Some(flow.resolver(id));
                    Seen::Begin(id)
                }
                Lowered::Ops(ops, stmt) => {
                    resolver.as_mut().expect("begun").resolve(stmt, ops);
                    Seen::Ops(std::mem::take(ops))
                }
                Lowered::End(_) => Seen::End,
            })
        });
        [replayed, fresh]
    }

    fn read(path: &std::path::Path) -> Source {
        let bytes = std::fs::read(path).unwrap();
        Source {
            path: path.display().to_string(),
            text: String::from_utf8_lossy(&bytes).into_owned(),
        }
    }

    /// On every transpile and interpreter fixture and every target, the second pass resolves
    /// from the tape exactly what lowering the statements again and building each routine's
    /// graph again resolves (the same ops, in the same blocks, from the same facts).
    #[test]
    fn the_replay_resolves_what_lowering_again_does() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut programs = 0;
        let mut ops = 0;
        for dir in [
            "tests/fixtures/transpile",
            "tests/fixtures/interp/realistic",
            "krl/examples",
        ] {
            let mut files: Vec<_> = std::fs::read_dir(root.join(dir))
                .unwrap()
                .map(|e| e.unwrap().path())
                .filter(|p| p.extension().is_some_and(|e| e == "src"))
                .collect();
            files.sort();
            for src in files {
                let dat = src.with_extension("dat");
                for target in [Target::Kawasaki, Target::Flexiv, Target::Rapid] {
                    let dat = dat.exists().then(|| read(&dat));
                    let [replayed, fresh] = both_ways(target, read(&src), dat);
                    assert!(
                        replayed == fresh,
                        "{} ({target:?}): the replay differs",
                        src.display()
                    );
                    programs += 1;
                    ops += replayed
                        .iter()
                        .filter(|s| matches!(s, Seen::Ops(o) if !o.is_empty()))
                        .count();
                }
            }
        }
        assert!(programs >= 90, "{programs} programs");
        assert!(ops >= 1500, "{ops} statements");
    }

    /// A tape that cannot be written fails the translation with an error that names it.
    #[test]
    fn a_tape_that_cannot_be_written_is_named_in_the_error() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("tape");
        std::fs::write(&path, b"").unwrap();
        let read_only = File::open(&path).unwrap();
        let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/fixtures/transpile/bin_pick.src");
        let first = first_pass(
            render::backend(Target::Kawasaki),
            read(&src),
            None,
            &crate::transpile::Options::default(),
            Writer::file(read_only),
        );
        let e = first
            .tape
            .err()
            .expect("a read-only tape cannot be written");
        assert!(
            e.to_string().starts_with("the translation's replay file"),
            "{e}"
        );
    }

    /// The events of a program of many routines (many chunks for the writing thread), read
    /// back from a tape in a file written on its own thread, are those of a tape written here,
    /// in a file or in memory, in order.
    #[test]
    fn a_tape_written_on_its_own_thread_reads_back_as_one_written_here() {
        let mut text = String::new();
        for r in 0..5000 {
            text.push_str(&format!(
                "DEF r{r}()\n  DECL INT i\n  i = {r}\n  IF i > 3 THEN\n    PTP {{A1 {r}}}\n  ENDIF\n  r{}()\nEND\n",
                (r + 1) % 5000
            ));
        }
        let writers = [
            Writer::file(tempfile::tempfile().unwrap()),
            Writer::file_here(tempfile::tempfile().unwrap()),
            Writer::memory(),
        ];
        assert!(matches!(writers[0].to, To::Behind(_)));
        assert!(matches!(writers[1].to, To::File(_)));
        let tapes = writers.map(|w| {
            let first = first_pass(
                render::backend(Target::Kawasaki),
                Source {
                    path: "many.src".into(),
                    text: text.clone(),
                },
                None,
                &crate::transpile::Options::default(),
                w,
            );
            let mut tape = first.tape.unwrap();
            if let From::Memory(bytes, _) = &tape.from {
                // Many chunks' worth for the thread.
                assert!(bytes.len() > 6 * CHUNK, "{} bytes", bytes.len());
            }
            let mut events = Vec::new();
            while let Some(e) = tape.next().unwrap() {
                events.push(match e {
                    Event::Begin(id) => (Seen::Begin(id), None),
                    Event::Ops(ops, runs) => (Seen::Ops(ops), Some(runs)),
                    Event::End => (Seen::End, None),
                });
            }
            events
        });
        assert!(tapes[0].len() > 20_000, "{} events", tapes[0].len());
        assert_eq!(tapes[0], tapes[1]);
        assert_eq!(tapes[0], tapes[2]);
    }

    /// A tape in a file reads back what one in memory does, event by event, with the
    /// `&'static` texts and subprograms of the ops the same references.
    #[test]
    fn a_tape_in_a_file_reads_back_as_one_in_memory() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let src = root.join("tests/fixtures/transpile/bin_pick.src");
        let tapes = [
            Writer::memory(),
            Writer::file(tempfile::tempfile().unwrap()),
            Writer::file_here(tempfile::tempfile().unwrap()),
        ]
        .map(|w| {
            let first = first_pass(
                render::backend(Target::Kawasaki),
                read(&src),
                Some(read(&src.with_extension("dat"))),
                &crate::transpile::Options::default(),
                w,
            );
            let mut tape = first.tape.unwrap();
            let mut events = Vec::new();
            while let Some(e) = tape.next().unwrap() {
                events.push(match e {
                    Event::Begin(id) => Seen::Begin(id),
                    Event::Ops(ops, _) => Seen::Ops(ops),
                    Event::End => Seen::End,
                });
            }
            events
        });
        assert_eq!(tapes[0], tapes[1]);
        assert_eq!(tapes[0], tapes[2]);
        let mut mm = 0;
        for s in &tapes[0] {
            if let Seen::Ops(ops) = s {
                ir::visit::each_op(ops, &mut |op| {
                    if let ir::Op::Call {
                        callee: ir::Callee::Mm(sub),
                        ..
                    } = op
                    {
                        let named = crate::catalog::catalog()
                            .subprograms_of(crate::catalog::Interface::V1)
                            .iter()
                            .chain(
                                crate::catalog::catalog()
                                    .subprograms_of(crate::catalog::Interface::V2),
                            )
                            .any(|c| std::ptr::eq(c, *sub));
                        assert!(named, "{}", sub.name);
                        mm += 1;
                    }
                });
            }
        }
        assert!(mm > 0, "bin_pick calls the Mech-Mind interface");
    }
}
