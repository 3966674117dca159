//! The bindings of one module's text, found by the start offset of the name. A table by byte
//! offset took four bytes per byte of text and a hash map scatters a routine's names over
//! memory; here a bit per byte marks where a bound name starts, and a name's rank among the
//! marked offsets is its index in the bindings, kept in text order (a quarter byte per byte
//! of text, and a routine's names stay together).

use crate::diag::Span;

use super::Binding;

/// Offsets per block: one bit each in [`Block::starts`].
const BLOCK: usize = 64;

#[derive(Debug, Default, Clone, Copy)]
struct Block {
    /// Bit `i`: a bound name starts at offset `block * 64 + i`.
    starts: u64,
    /// Index in [`Uses::bound`] of the block's first name.
    first: u32,
}

#[derive(Debug, Default)]
pub(crate) struct Uses {
    blocks: Vec<Block>,
    /// Start and end offset of each bound name, and its binding, by start offset.
    bound: Vec<(u32, u32, Binding)>,
}

impl Uses {
    pub(crate) fn get(&self, span: Span) -> Option<Binding> {
        let start = span.start as usize;
        let block = self.blocks.get(start / BLOCK)?;
        let bit = start % BLOCK;
        if block.starts >> bit & 1 == 0 {
            return None;
        }
        let below = (block.starts & ((1u64 << bit) - 1)).count_ones();
        let &(_, end, b) = self.bound.get((block.first + below) as usize)?;
        (end == span.end).then_some(b)
    }
}

/// Collects the bindings of one module in any order; a later one for the same start offset
/// replaces the earlier.
#[derive(Debug, Default)]
pub(crate) struct UsesBuilder {
    bound: Vec<(u32, u32, Binding)>,
}

impl UsesBuilder {
    pub(crate) fn reserve(&mut self, n: usize) {
        self.bound.reserve(n);
    }

    pub(crate) fn put(&mut self, span: Span, b: Binding) {
        self.bound.push((span.start, span.end, b));
    }

    pub(crate) fn finish(self) -> Uses {
        let mut kept = self.bound;
        // Stable: of the bindings of one offset, the last put is the last of its run, and
        // `dedup_by` hands it over to the first, which stays.
        kept.sort_by_key(|&(start, ..)| start);
        kept.dedup_by(|later, first| {
            let same = later.0 == first.0;
            if same {
                *first = *later;
            }
            same
        });
        kept.shrink_to_fit();
        let blocks_len = kept.last().map_or(0, |&(s, ..)| s as usize / BLOCK + 1);
        let mut blocks = vec![Block::default(); blocks_len];
        for (i, &(start, ..)) in kept.iter().enumerate() {
            let block = &mut blocks[start as usize / BLOCK];
            if block.starts == 0 {
                block.first = i as u32;
            }
            block.starts |= 1u64 << (start as usize % BLOCK);
        }
        Uses {
            blocks,
            bound: kept,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn span(start: u32, end: u32) -> Span {
        Span { start, end }
    }

    #[test]
    fn finds_each_name_by_its_span_and_nothing_elsewhere() {
        let mut b = UsesBuilder::default();
        // Out of order, across blocks, neighbours in one block, offset 0 and a block's last.
        let names = [
            (200, 203),
            (0, 2),
            (63, 64),
            (64, 70),
            (5, 9),
            (127, 130),
            (1000, 1001),
        ];
        for (i, &(s, e)) in names.iter().enumerate() {
            b.put(span(s, e), Binding::Global(i as u32));
        }
        let uses = b.finish();
        for (i, &(s, e)) in names.iter().enumerate() {
            assert_eq!(uses.get(span(s, e)), Some(Binding::Global(i as u32)), "{s}");
            // The same start with another end is another text.
            assert_eq!(uses.get(span(s, e + 1)), None);
        }
        for s in [1, 4, 62, 65, 126, 128, 199, 999, 1002, 5000] {
            assert_eq!(uses.get(span(s, s + 1)), None, "{s}");
        }
    }

    #[test]
    fn a_later_binding_of_the_same_name_replaces_the_earlier() {
        let mut b = UsesBuilder::default();
        b.put(span(10, 12), Binding::Global(1));
        b.put(span(3, 4), Binding::Global(7));
        b.put(span(10, 12), Binding::Global(2));
        let uses = b.finish();
        assert_eq!(uses.get(span(10, 12)), Some(Binding::Global(2)));
        assert_eq!(uses.get(span(3, 4)), Some(Binding::Global(7)));
    }
}
