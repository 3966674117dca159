//! Where each run of a statement's ops runs, recorded by the first pass so that the second
//! resolves the same ops without the statement's tree.
//!
//! [`super::ops::feed`] hands a statement's ops to its [`Parts`] in runs (slices of the op tree:
//! of the statement's ops, or of a block nested in one of them), each with the block of the
//! routine's graph it runs in. The first pass records each run as that block and the run's
//! place in the op tree (the path of op indices and child blocks, [`visit::children`]'s order,
//! to the slice, and the slice's start and length); the second pass reads the same ops back
//! and hands the same slices, in the same order, to its resolver ([`super::Resolver::replay`]).
//! Empty runs are not recorded: no [`Parts`] does anything with one.

use serde::{Deserialize, Serialize};

use super::ops::Parts;
use crate::cfg::BlockId;
use crate::transpile::ir::{Stmt, visit};

/// The runs of one statement's ops, in the order they were handed out.
#[derive(Debug, Default, Clone, PartialEq, Serialize, Deserialize)]
pub struct Runs {
    runs: Vec<Run>,
    /// The runs' paths, one after another (a vector per run was made and dropped for every
    /// nested run of the first pass).
    paths: Vec<u32>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct Run {
    /// The block it runs in (`None`: no path reaches it).
    block: Option<u32>,
    /// How many entries of [`Runs::paths`] it takes, after the runs before it: from the
    /// statement's ops to the slice's block, an op's index, then which of its child blocks,
    /// and so on (none: the statement's ops).
    path: u32,
    start: u32,
    len: u32,
}

impl Runs {
    pub(super) fn clear(&mut self) {
        self.runs.clear();
        self.paths.clear();
    }

    /// Each run as a block and its slice of `ops` (the ops the runs were recorded on, as read
    /// back), in order.
    pub(super) fn each(&self, ops: &mut [Stmt], mut f: impl FnMut(Option<BlockId>, &mut [Stmt])) {
        let mut at = 0;
        for r in &self.runs {
            let mut block = &mut *ops;
            let path = &self.paths[at..at + r.path as usize];
            at += r.path as usize;
            for step in path.chunks_exact(2) {
                let (i, c) = (step[0] as usize, step[1] as usize);
                block = visit::nth_child_mut(&mut block[i].op, c)
                    .expect("the recorded child block")
                    .as_mut_slice();
            }
            let (start, len) = (r.start as usize, r.len as usize);
            f(
                r.block.map(|b| b as BlockId),
                &mut block[start..start + len],
            );
        }
    }
}

/// Every non-empty block of a statement's op tree, for [`Record`]: kept from statement to
/// statement (made anew per statement, with a path per block, it was a fifth of the graphs'
/// time).
#[derive(Default)]
pub(super) struct Blocks {
    /// Per block: its first op's address, its length, and its path's range in `paths`;
    /// sorted by address.
    at: Vec<(usize, usize, u32, u32)>,
    paths: Vec<u32>,
    /// Scratch: the path being walked.
    path: Vec<u32>,
}

impl Blocks {
    /// Indexes the blocks of `ops` (a statement's, before they are handed out).
    fn index(&mut self, ops: &[Stmt]) {
        self.at.clear();
        self.paths.clear();
        self.path.clear();
        self.add(ops);
        self.at.sort_unstable_by_key(|b| b.0);
    }

    /// Adds `ops` and the non-empty blocks nested in it.
    fn add(&mut self, ops: &[Stmt]) {
        if ops.is_empty() {
            return;
        }
        let start = self.paths.len() as u32;
        self.paths.extend_from_slice(&self.path);
        self.at.push((
            ops.as_ptr() as usize,
            ops.len(),
            start,
            self.path.len() as u32,
        ));
        for (i, s) in ops.iter().enumerate() {
            let mut c = 0u32;
            visit::each_child(&s.op, |child| {
                self.path.extend([i as u32, c]);
                self.add(child);
                self.path.truncate(self.path.len() - 2);
                c += 1;
            });
        }
    }
}

/// [`Parts`] that records each run in [`Runs`] and hands it on to `inner`.
pub(super) struct Record<'a, P> {
    inner: &'a mut P,
    runs: &'a mut Runs,
    blocks: &'a Blocks,
}

impl<'a, P: Parts> Record<'a, P> {
    /// For the runs of `ops` (the statement's, before they are handed out), its blocks
    /// indexed in `blocks`.
    pub(super) fn new(
        ops: &[Stmt],
        blocks: &'a mut Blocks,
        inner: &'a mut P,
        runs: &'a mut Runs,
    ) -> Record<'a, P> {
        blocks.index(ops);
        Record {
            inner,
            runs,
            blocks,
        }
    }
}

impl<P: Parts> Parts for Record<'_, P> {
    fn run(&mut self, b: Option<BlockId>, ops: &mut [Stmt]) {
        if !ops.is_empty() {
            let at = ops.as_ptr() as usize;
            let size = std::mem::size_of::<Stmt>();
            // The block holding the run: the last one starting at or before it.
            let blocks = &self.blocks.at;
            let k = blocks.partition_point(|blk| blk.0 <= at);
            let &(first, len, path, depth) = k
                .checked_sub(1)
                .map(|k| &blocks[k])
                .filter(|blk| at < blk.0 + blk.1 * size)
                .expect("a run is a slice of the statement's ops");
            debug_assert_eq!((at - first) % size, 0);
            let start = (at - first) / size;
            debug_assert!(start + ops.len() <= len);
            self.runs
                .paths
                .extend_from_slice(&self.blocks.paths[path as usize..(path + depth) as usize]);
            self.runs.runs.push(Run {
                block: b.map(|b| b as u32),
                path: depth,
                start: start as u32,
                len: ops.len() as u32,
            });
        }
        self.inner.run(b, ops);
    }
}
