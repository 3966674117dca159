//! The bindings of one module's text, found by the start offset of the name. A table by byte
//! offset of indices took four bytes per byte of text, and a hash map scatters a routine's
//! names over memory; here a byte per byte of text holds the rank of the name starting there
//! within its 128-byte block (at most 128 names start in one, so a rank fits), and each block
//! where its first name is in the bindings, kept in text order: a byte per byte of text, a
//! routine's names together, two reads per lookup as before.

use crate::diag::Span;

use super::Binding;

/// Bytes per block of [`Uses::first`]: no more names can start in one than a byte can count.
const BLOCK: usize = 128;

#[derive(Debug, Default)]
pub(crate) struct Uses {
    /// Per byte of text up to the last name: 0, or 1 + the rank of the name starting there
    /// among the names starting in its block.
    rank: Vec<u8>,
    /// Per block: the index in `bound` of its first name.
    first: Vec<u32>,
    /// Start and end offset of each bound name, and its binding, by start offset.
    bound: Vec<(u32, u32, Binding)>,
}

impl Uses {
    pub(crate) fn get(&self, span: Span) -> Option<Binding> {
        let start = span.start as usize;
        let rank = *self.rank.get(start)?;
        if rank == 0 {
            return None;
        }
        let i = *self.first.get(start / BLOCK)? as usize + rank as usize - 1;
        let &(_, end, b) = self.bound.get(i)?;
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
        let len = kept.last().map_or(0, |&(s, ..)| s as usize + 1);
        let mut rank = vec![0u8; len];
        let mut first = vec![0u32; len.div_ceil(BLOCK)];
        let mut block = usize::MAX;
        let mut in_block = 0u8;
        for (i, &(start, ..)) in kept.iter().enumerate() {
            let start = start as usize;
            if start / BLOCK != block {
                block = start / BLOCK;
                first[block] = i as u32;
                in_block = 0;
            }
            // Distinct offsets of one block: at most BLOCK of them.
            in_block += 1;
            rank[start] = in_block;
        }
        Uses {
            rank,
            first,
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
    fn a_block_can_hold_a_name_at_every_offset() {
        let mut b = UsesBuilder::default();
        for s in 0..300 {
            b.put(span(s, s + 1), Binding::Global(s));
        }
        let uses = b.finish();
        for s in 0..300 {
            assert_eq!(uses.get(span(s, s + 1)), Some(Binding::Global(s)), "{s}");
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
