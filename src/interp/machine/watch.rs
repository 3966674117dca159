//! Can a wait ever end? While a `WAIT FOR` condition (or an idle polling loop) is evaluated,
//! the machine records which places it reads. A value only the program writes cannot change
//! while the program waits; only EKI channels (their alive and receive flags and outputs),
//! running timers, running pulses and the inputs that follow those outputs can. When nothing a
//! check read can change, and no interrupt condition read during the same check can either
//! (the interrupt checks run inside it and are recorded too), the check gives the same answer
//! forever: the wait is reported at once instead of after an hour of waiting on a real peer.

use super::{Machine, R, Root, Seg};

/// What one check read.
#[derive(Debug, Default, Clone)]
pub(super) struct Reads {
    /// System arrays and variables read: name and 0-based index (`None`: the whole array or a
    /// SIGNAL group over it).
    places: Vec<(String, Option<usize>)>,
    /// Something outside the machine's model was consulted (an `EKI_*` function): assume it
    /// can change.
    external: bool,
}

impl Reads {
    fn add(&mut self, key: &str, index: Option<usize>) {
        if !self.places.iter().any(|(k, i)| k == key && *i == index) {
            self.places.push((key.to_string(), index));
        }
    }
}

/// Loop header (module, offset) whose current iteration is being recorded, and its reads.
pub(super) type LoopReads = Option<((usize, u32), Reads)>;

impl<'p> Machine<'p> {
    /// Note a read of `root`/`path` for the recordings under way.
    pub(super) fn note_read(&mut self, root: &Root, path: &[Seg]) {
        if self.reads.is_none() && self.loop_reads.is_none() {
            return;
        }
        let (key, index) = match root {
            // Only system variables can change while the program waits.
            Root::Global(k) if self.scopes.globals.name(*k).starts_with('$') => {
                match path.first() {
                    Some(Seg::Index(i)) => (self.scopes.globals.name(*k), Some(*i)),
                    _ => (self.scopes.globals.name(*k), None),
                }
            }
            Root::Group { array, .. } => (self.scopes.globals.name(*array), None),
            _ => return,
        };
        if let Some(r) = &mut self.reads {
            r.add(key, index);
        }
        if let Some((_, r)) = &mut self.loop_reads {
            r.add(key, index);
        }
    }

    /// Note that a check consulted something outside the model (an `EKI_*` call).
    pub(super) fn note_external(&mut self) {
        if let Some(r) = &mut self.reads {
            r.external = true;
        }
        if let Some((_, r)) = &mut self.loop_reads {
            r.external = true;
        }
    }

    /// Run `f`, recording what it reads; the reads count for an enclosing recording too.
    pub(super) fn recording<T>(&mut self, f: impl FnOnce(&mut Self) -> R<T>) -> (R<T>, Reads) {
        let outer = self.reads.replace(Reads::default());
        let result = f(self);
        let reads = std::mem::replace(&mut self.reads, outer).unwrap_or_default();
        if let Some(o) = &mut self.reads {
            for (k, i) in &reads.places {
                o.add(k, *i);
            }
            o.external |= reads.external;
        }
        (result, reads)
    }

    /// Whether anything in `reads` can change while the program does not write.
    pub(super) fn can_change(&self, reads: &Reads) -> bool {
        reads.external
            || reads
                .places
                .iter()
                .any(|(k, i)| self.changeable(k, i.map(|i| i + 1)))
    }

    /// Whether `key[n]` (1-based; `None`: any element) can change without the program.
    fn changeable(&self, key: &str, n: Option<usize>) -> bool {
        match key {
            "$FLAG" => self.eki.sets("$FLAG", n),
            "$OUT" => self.io.pulses_running() || self.eki.sets("$OUT", n),
            "$IN" => self
                .opts
                .input_links
                .iter()
                .filter(|l| n.is_none_or(|n| l.input == n))
                .any(|l| self.changeable("$OUT", Some(l.output))),
            "$TIMER" | "$TIMER_FLAG" => self.io.timer_running(n),
            _ => false,
        }
    }

    /// Where to report a limit the run ran into: inside an `MM_*` subprogram (the package), at
    /// the user's code that called it (the innermost loop around that call, or the call
    /// itself), plus where in the package the run was; elsewhere, the current statement.
    pub(super) fn limit_error(&self, message: String) -> super::Stop {
        let Some(k) = self.scopes.frames.iter().position(|f| f.mm.is_some()) else {
            return self.err(message);
        };
        let inner = self.error("");
        let callee = self.scopes.frames[k].mm.clone().unwrap_or_default();
        let at = self.scopes.frames[k]
            .call_site
            .filter(|_| k > 0)
            .map(|site| {
                self.scopes.frames[k - 1]
                    .loops
                    .last()
                    .copied()
                    .unwrap_or(site)
            });
        let Some(at) = at else {
            return self.err(message);
        };
        let mut e = self.error_at(at, message);
        e.message
            .push_str(&format!(" (in {callee}, at {}:{})", inner.file, inner.line));
        super::Stop::from(e)
    }
}
