//! Where a translation's text goes, so no renderer holds the whole program's text.
//!
//! A renderer writes each ended routine to the [`Spool`] (memory for the library's
//! `Translation.text`, an unnamed temporary file for the CLI) and keeps only what is known at
//! the end: the text before the routines (the header with the name map, a module's data) and
//! after them ([`Framed`]). The driver then writes the text in order — before, the spooled
//! routines, after — into the destination, and the target's structural check reads it line by
//! line on the way ([`LineCheck`]).

use std::fs::File;
use std::io::{self, BufRead, BufReader, BufWriter, Seek, Write};

/// A target's structural check, fed the translated text one line at a time (without its line
/// break, as `str::lines` gives them).
pub trait LineCheck {
    fn line(&mut self, line: &str);
    /// The problems that would keep the text from loading; none when it is sound.
    fn finish(self: Box<Self>) -> Vec<String>;
}

/// A target without a structural check.
pub struct NoCheck;

impl LineCheck for NoCheck {
    fn line(&mut self, _: &str) {}

    fn finish(self: Box<Self>) -> Vec<String> {
        Vec::new()
    }
}

/// What a renderer holds back until the end: the text before and after the spooled routines.
#[derive(Debug, Default)]
pub struct Framed {
    pub before: String,
    pub after: String,
}

/// The routines' text, written as each routine ends.
pub struct Spool {
    to: To,
    /// The first write error (reported when the text is assembled: rendering goes on).
    error: Option<io::Error>,
}

enum To {
    Memory(String),
    File(BufWriter<File>),
}

impl Spool {
    pub fn memory() -> Spool {
        Spool {
            to: To::Memory(String::new()),
            error: None,
        }
    }

    /// Into `file` (e.g. an unnamed temporary file), read back when the text is assembled.
    pub fn file(file: File) -> Spool {
        Spool {
            to: To::File(BufWriter::with_capacity(1 << 16, file)),
            error: None,
        }
    }

    pub fn push_str(&mut self, s: &str) {
        match &mut self.to {
            To::Memory(text) => text.push_str(s),
            To::File(w) => {
                if self.error.is_none()
                    && let Err(e) = w.write_all(s.as_bytes())
                {
                    self.error = Some(e);
                }
            }
        }
    }

    pub fn push(&mut self, c: char) {
        self.push_str(c.encode_utf8(&mut [0; 4]));
    }

    /// The whole text, `framed` around the spooled routines, checked line by line.
    pub fn into_text(self, framed: Framed, check: &mut dyn LineCheck) -> io::Result<String> {
        match self.to {
            To::Memory(mut text) => {
                // One buffer: the routines' text grows at both ends.
                text.reserve(framed.before.len() + framed.after.len());
                text.insert_str(0, &framed.before);
                text.push_str(&framed.after);
                text.lines().for_each(|l| check.line(l));
                Ok(text)
            }
            To::File(_) => {
                let mut bytes = Vec::new();
                self.write_to(framed, check, &mut bytes)?;
                String::from_utf8(bytes).map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e))
            }
        }
    }

    /// Writes the whole text, `framed` around the spooled routines, into `out`, checked line by
    /// line on the way.
    pub fn write_to(
        self,
        framed: Framed,
        check: &mut dyn LineCheck,
        out: &mut dyn Write,
    ) -> io::Result<()> {
        if let Some(e) = self.error {
            return Err(e);
        }
        let mut lines = Lines {
            out,
            check,
            partial: Vec::new(),
        };
        lines.write(framed.before.as_bytes())?;
        drop(framed.before);
        match self.to {
            To::Memory(text) => lines.write(text.as_bytes())?,
            To::File(w) => {
                let mut file = w.into_inner().map_err(io::IntoInnerError::into_error)?;
                file.rewind()?;
                let mut reader = BufReader::with_capacity(1 << 16, file);
                loop {
                    let chunk = reader.fill_buf()?;
                    if chunk.is_empty() {
                        break;
                    }
                    lines.write(chunk)?;
                    let n = chunk.len();
                    reader.consume(n);
                }
            }
        }
        lines.write(framed.after.as_bytes())?;
        lines.end();
        Ok(())
    }
}

/// Passes bytes on and hands each complete line to the check (a line cut between two writes
/// is joined first).
struct Lines<'a> {
    out: &'a mut dyn Write,
    check: &'a mut dyn LineCheck,
    partial: Vec<u8>,
}

impl Lines<'_> {
    fn write(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.out.write_all(bytes)?;
        let mut rest = bytes;
        while let Some(i) = memchr::memchr(b'\n', rest) {
            let (line, after) = rest.split_at(i);
            if self.partial.is_empty() {
                self.line(line, true);
            } else {
                let mut joined = std::mem::take(&mut self.partial);
                joined.extend_from_slice(line);
                self.line(&joined, true);
                joined.clear();
                self.partial = joined;
            }
            rest = &after[1..];
        }
        self.partial.extend_from_slice(rest);
        Ok(())
    }

    /// The last line, when the text does not end in a line break.
    fn end(&mut self) {
        if !self.partial.is_empty() {
            let last = std::mem::take(&mut self.partial);
            self.line(&last, false);
        }
    }

    /// As `str::lines`: a line ended by `\r\n` loses its `\r`.
    fn line(&mut self, line: &[u8], ended: bool) {
        let line = match line {
            [l @ .., b'\r'] if ended => l,
            l => l,
        };
        self.check.line(&String::from_utf8_lossy(line));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Records the lines it is fed.
    #[derive(Default)]
    struct Seen(Vec<String>);

    impl LineCheck for &mut Seen {
        fn line(&mut self, line: &str) {
            self.0.push(line.to_owned());
        }

        fn finish(self: Box<Self>) -> Vec<String> {
            Vec::new()
        }
    }

    fn framed(before: &str, after: &str) -> Framed {
        Framed {
            before: before.into(),
            after: after.into(),
        }
    }

    /// Memory or file, the text and the lines checked are those of the framed whole, also with
    /// lines cut between the parts, `\r\n` ends and no final line break.
    #[test]
    fn every_spool_gives_the_framed_text_and_its_lines() {
        for (before, routines, after) in [
            ("head\n", "a\nb\r\n", "tail\n"),
            ("he", "ad\nrou", "tines\r\nlast"),
            ("", "", ""),
            ("x\r", "\n", "\r"),
        ] {
            let whole = format!("{before}{routines}{after}");
            let want: Vec<String> = whole.lines().map(str::to_owned).collect();
            let spools = [Spool::memory(), Spool::file(tempfile::tempfile().unwrap())];
            for mut spool in spools {
                spool.push_str(routines);
                let mut seen = Seen::default();
                let mut check = &mut seen;
                let text = spool.into_text(framed(before, after), &mut check).unwrap();
                assert_eq!(text, whole);
                assert_eq!(seen.0, want, "{whole:?}");
            }
            let mut spool = Spool::file(tempfile::tempfile().unwrap());
            spool.push_str(routines);
            let (mut seen, mut out) = (Seen::default(), Vec::new());
            spool
                .write_to(framed(before, after), &mut &mut seen, &mut out)
                .unwrap();
            assert_eq!(String::from_utf8(out).unwrap(), whole);
            assert_eq!(seen.0, want, "{whole:?}");
        }
    }
}
