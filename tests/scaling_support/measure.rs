//! One run of krlkit, measured from the child's rusage (`wait4`): wall time, CPU time (user +
//! system, all threads) and peak RSS. The ratios use CPU time: the machine the matrix and the
//! guard run on is shared, and its wall time mostly measures the neighbours.
//!
//! The child is started by fork + exec, never by `posix_spawn`: a child spawned with a shared
//! address space (vfork) takes its parent's *peak* resident set into its `ru_maxrss` at exec, so
//! every small command read as the bench's own peak (~128 MB after writing the 50 MB shapes); a
//! forked child starts from the parent's current resident set (a few MB here).

use std::os::unix::process::CommandExt;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// What one run (or the best of several) took.
#[derive(Debug, Clone, Copy)]
pub struct Run {
    /// Seconds on the clock.
    pub wall: f64,
    /// Seconds of CPU, user and system, summed over the threads.
    pub cpu: f64,
    /// Peak resident set, MB.
    pub mb: u64,
}

impl Run {
    /// The fastest times and the largest peak of two runs.
    pub fn best(self, other: Run) -> Run {
        Run {
            wall: self.wall.min(other.wall),
            cpu: self.cpu.min(other.cpu),
            mb: self.mb.max(other.mb),
        }
    }
}

/// Run `bin args` in `cwd`, output discarded; `None` when it was still running after `limit`
/// (it is killed then). Panics when krlkit dies of a signal (a crash).
pub fn measure(bin: &Path, args: &[String], cwd: &Path, limit: Duration) -> Option<Run> {
    let start = Instant::now();
    let mut command = Command::new(bin);
    command
        .args(args)
        .current_dir(cwd)
        .stdout(Stdio::null())
        .stderr(Stdio::null());
    // SAFETY: the hook runs nothing; its presence makes std fork + exec instead of posix_spawn
    // (see the module comment).
    unsafe {
        command.pre_exec(|| Ok(()));
    }
    #[allow(clippy::zombie_processes)] // reaped by wait4 below, which also gives its rusage
    let mut child = command.spawn().expect("start krlkit");
    let pid = child.id() as libc::pid_t;
    let mut status = 0;
    // SAFETY: an all-zero rusage is valid; wait4 fills it for our own child.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let mut timed_out = false;
    loop {
        let r = unsafe { libc::wait4(pid, &mut status, libc::WNOHANG, &mut usage) };
        if r == pid {
            break;
        }
        assert_eq!(r, 0, "wait4 on krlkit failed");
        if !timed_out && start.elapsed() > limit {
            let _ = child.kill();
            timed_out = true;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    // A crash is no measurement: a stack overflow on a deep call chain aborted in a few
    // milliseconds and read as the fastest run of all.
    assert!(
        timed_out || !libc::WIFSIGNALED(status),
        "krlkit {} in {} was killed by signal {}",
        args.join(" "),
        cwd.display(),
        libc::WTERMSIG(status)
    );
    let wall = start.elapsed().as_secs_f64();
    let secs = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 / 1e6;
    (!timed_out).then(|| Run {
        wall,
        cpu: secs(usage.ru_utime) + secs(usage.ru_stime),
        mb: usage.ru_maxrss as u64 / 1024,
    })
}

/// The best of `runs` runs, or `None` when one timed out (the others would too).
pub fn best_of(
    runs: usize,
    bin: &Path,
    args: &[String],
    cwd: &Path,
    limit: Duration,
) -> Option<Run> {
    let mut best: Option<Run> = None;
    for _ in 0..runs.max(1) {
        let run = measure(bin, args, cwd, limit)?;
        best = Some(best.map_or(run, |b| b.best(run)));
    }
    best
}
