//! Two threads in a row: a producer a bounded number of batches ahead of its consumer. The
//! translation's parses feed the outline and the lowering this way, the second pass's
//! reading of the first pass's ops (`transpile/tape.rs`) feeds the renderer, and `check`'s
//! parse of a big file feeds its first pass (`syntax::parse_pieces_ahead`). [`beside`] runs
//! two pieces of work at once (the translation's flow solve beside its renderer's making, its
//! coverage beside its text's check); [`release_free_memory`] gives a finished thread's
//! freed working space back.

/// What [`pipelined`]'s producer hands on: into the batch of the moment, or (without a second
/// thread) straight to the consumer.
pub enum Sink<'a, T> {
    Batches {
        batch: Vec<T>,
        /// How many items a batch holds before it is sent.
        size: usize,
        send: std::sync::mpsc::SyncSender<Vec<T>>,
        returned: std::sync::mpsc::Receiver<Vec<T>>,
        /// A batch the consumer is done with, being dropped a few items at a time, and an
        /// emptied one to be filled again.
        spent: Vec<T>,
        spare: Option<Vec<T>>,
    },
    Direct(&'a mut dyn FnMut(&T)),
}

/// How many items a batch of [`pipelined`] holds, and how many batches may wait.
pub const BATCH: usize = 256;
pub const BATCHES: usize = 4;

impl<T> Sink<'_, T> {
    pub fn push(&mut self, item: T) {
        match self {
            Sink::Direct(f) => f(&item),
            Sink::Batches {
                batch,
                size,
                send,
                returned,
                spent,
                spare,
            } => {
                // The items the consumer is done with are dropped here, one for each item
                // made: each one's memory is freed just before the next one's is allocated,
                // and glibc's per-thread cache serves most of those allocations (a whole
                // batch freed at once overflowed it). Nothing piles up: an item is made
                // without one dropped only when every item the consumer is done with is
                // dropped, so no more items exist than the batches in flight hold.
                if spent.is_empty()
                    && let Ok(done) = returned.try_recv()
                {
                    let emptied = std::mem::replace(spent, done);
                    if spare.is_none() && emptied.capacity() > 0 {
                        *spare = Some(emptied);
                    }
                }
                drop(spent.pop());
                batch.push(item);
                if batch.len() == *size {
                    let next = spare.take().unwrap_or_else(|| Vec::with_capacity(*size));
                    let full = std::mem::replace(batch, next);
                    // The receiver only stops early when the consumer panicked.
                    let _ = send.send(full);
                }
            }
        }
    }
}

/// Runs `produce` on a second thread and `consume` on this one, on each item `produce` pushes,
/// in order: the producer runs a bounded number of batches ahead, so only a few items exist at
/// once. Each batch goes back to the producer's thread to be dropped there: glibc frees a
/// block another thread's arena allocated under that arena's lock, and the two threads
/// contending for it were a tenth of a translation's CPU. Without a thread to be had, both run
/// here, one item at a time. Returns what `produce` returns.
pub fn pipelined<T: Send, R: Send>(
    produce: impl FnOnce(&mut Sink<'_, T>) -> R + Send,
    consume: impl FnMut(&T),
) -> R {
    pipelined_on(true, produce, consume)
}

/// [`pipelined`], on a second thread only when `thread` (tests compare the two ways).
pub fn pipelined_on<T: Send, R: Send>(
    thread: bool,
    produce: impl FnOnce(&mut Sink<'_, T>) -> R + Send,
    consume: impl FnMut(&T),
) -> R {
    pipelined_ahead(thread, BATCHES, produce, consume)
}

/// [`pipelined_on`] with up to `ahead` batches waiting (a consumer that starts with work of
/// its own lets the producer run further ahead meanwhile).
pub fn pipelined_ahead<T: Send, R: Send>(
    thread: bool,
    ahead: usize,
    produce: impl FnOnce(&mut Sink<'_, T>) -> R + Send,
    consume: impl FnMut(&T),
) -> R {
    pipelined_batches(thread, ahead, BATCH, produce, consume)
}

/// [`pipelined_ahead`] with batches of `size` items (items that are batches themselves,
/// and large ones, go in a few at a time: the pipeline holds `(ahead + 2) * size` of them).
pub fn pipelined_batches<T: Send, R: Send>(
    thread: bool,
    ahead: usize,
    size: usize,
    produce: impl FnOnce(&mut Sink<'_, T>) -> R + Send,
    mut consume: impl FnMut(&T),
) -> R {
    let size = size.max(1);
    if !thread {
        return produce(&mut Sink::Direct(&mut consume));
    }
    let (send, receive) = std::sync::mpsc::sync_channel::<Vec<T>>(ahead.max(1));
    let (give_back, returned) = std::sync::mpsc::channel::<Vec<T>>();
    let work = TakenOnce::new(produce);
    std::thread::scope(|scope| {
        let producer = std::thread::Builder::new().spawn_scoped(scope, || {
            let produce = work.take();
            let mut sink = Sink::Batches {
                batch: Vec::with_capacity(size),
                size,
                send,
                returned,
                spent: Vec::new(),
                spare: None,
            };
            let out = produce(&mut sink);
            let Sink::Batches {
                batch,
                send,
                returned,
                spent,
                spare,
                ..
            } = sink
            else {
                unreachable!("the sink sends batches")
            };
            let _ = send.send(batch);
            drop(send);
            drop((spent, spare));
            // The last batches, once the consumer is done with them.
            for done in returned {
                drop(done);
            }
            out
        });
        match producer {
            Ok(producer) => {
                for batch in receive {
                    batch.iter().for_each(&mut consume);
                    let _ = give_back.send(batch);
                }
                drop(give_back);
                producer
                    .join()
                    .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
            }
            Err(_) => {
                let produce = work.take();
                produce(&mut Sink::Direct(&mut consume))
            }
        }
    })
}

/// Runs `there` on a thread of its own (when `thread` and one can be had) and `here` on this
/// one, at the same time; without a thread, `here` and then `there` run here. A panic of
/// `there` reaches the caller.
pub fn beside<A: Send, B>(
    thread: bool,
    there: impl FnOnce() -> A + Send,
    here: impl FnOnce() -> B,
) -> (A, B) {
    let work = TakenOnce::new(there);
    std::thread::scope(|scope| {
        let spawned = thread
            .then(|| {
                std::thread::Builder::new()
                    .spawn_scoped(scope, || work.take()())
                    .ok()
            })
            .flatten();
        let b = here();
        let a = match spawned {
            Some(spawned) => spawned
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic)),
            None => work.take()(),
        };
        (a, b)
    })
}

/// Gives the allocator's free memory back to the system (glibc: every arena's free pages;
/// elsewhere nothing). Memory a thread freed stays in its own arena, where another thread's
/// allocations never reuse it: after a thread's large working space is freed, that is
/// memory the process holds and no one uses.
pub fn release_free_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: `malloc_trim` only reads and changes the allocator's own state, under its locks.
    unsafe {
        libc::malloc_trim(0);
    }
}

/// Work for a thread that may not be had: the thread takes it, or the caller does when none
/// could be spawned (a closure handed to a spawn that failed is gone).
struct TakenOnce<F>(std::sync::Mutex<Option<F>>);

impl<F> TakenOnce<F> {
    fn new(work: F) -> TakenOnce<F> {
        TakenOnce(std::sync::Mutex::new(Some(work)))
    }

    fn take(&self) -> F {
        self.0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .take()
            .expect("the work is taken once")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Across many batches, the consumer sees every item in the order made, the same as
    /// without a thread, and the producer's result comes back.
    #[test]
    fn items_arrive_in_order_as_without_a_thread() {
        let n = BATCH * (BATCHES + 3) + 17;
        let run = |thread: bool| {
            let mut seen = Vec::new();
            let made = pipelined_on(
                thread,
                |sink| {
                    for i in 0..n {
                        sink.push(i.to_string());
                    }
                    n
                },
                |s: &String| seen.push(s.parse::<usize>().unwrap()),
            );
            (made, seen)
        };
        let (made, seen) = run(true);
        assert_eq!(made, n);
        assert_eq!(seen, (0..n).collect::<Vec<_>>());
        assert_eq!(run(false), (made, seen));
    }

    /// With many batches allowed to wait while the consumer is busy at its start, the
    /// consumer still sees every item in order, and the producer ran ahead meanwhile.
    #[test]
    fn a_producer_further_ahead_hands_out_the_same_items() {
        let n = BATCH * 40 + 3;
        let made = std::sync::atomic::AtomicUsize::new(0);
        let mut seen = Vec::new();
        let mut ahead_at_start = None;
        pipelined_ahead(
            true,
            32,
            |sink| {
                for i in 0..n {
                    sink.push(i);
                    made.store(i + 1, std::sync::atomic::Ordering::Relaxed);
                }
            },
            |&i| {
                if ahead_at_start.is_none() {
                    // The consumer's own work at its start: the producer goes on meanwhile.
                    let until = std::time::Instant::now() + std::time::Duration::from_secs(5);
                    while made.load(std::sync::atomic::Ordering::Relaxed) < BATCH * 20
                        && std::time::Instant::now() < until
                    {
                        std::thread::yield_now();
                    }
                    ahead_at_start = Some(made.load(std::sync::atomic::Ordering::Relaxed));
                }
                seen.push(i);
            },
        );
        assert_eq!(seen, (0..n).collect::<Vec<_>>());
        assert!(ahead_at_start.unwrap() >= BATCH * 20, "{ahead_at_start:?}");
    }

    /// A producer's panic reaches the caller.
    #[test]
    #[should_panic(expected = "producer failed")]
    fn a_producers_panic_reaches_the_caller() {
        pipelined(
            |sink: &mut Sink<'_, usize>| {
                sink.push(1);
                panic!("producer failed")
            },
            |_| {},
        );
    }
}
