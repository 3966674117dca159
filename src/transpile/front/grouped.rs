//! Items grouped by a small index (a routine's), each group in the order given: one list and
//! its offsets, where a map of lists made an allocation per group (a file of many routines
//! made tens of thousands).

/// The groups; an index without items has an empty group.
#[derive(Debug, Default)]
pub struct Grouped<T> {
    items: Vec<T>,
    /// `starts[k]..starts[k + 1]`: group `k` in `items`.
    starts: Vec<u32>,
}

impl<T> Grouped<T> {
    /// Groups `pairs` (index, item) by index, each group in the order of `pairs`.
    pub fn new(pairs: impl IntoIterator<Item = (usize, T)>) -> Grouped<T> {
        let mut pairs: Vec<(usize, T)> = pairs.into_iter().collect();
        // Stable: a group keeps the order given.
        pairs.sort_by_key(|p| p.0);
        let groups = pairs.last().map_or(0, |p| p.0 + 1);
        let mut starts = vec![0u32; groups + 1];
        for p in &pairs {
            starts[p.0 + 1] += 1;
        }
        for k in 0..groups {
            starts[k + 1] += starts[k];
        }
        Grouped {
            items: pairs.into_iter().map(|p| p.1).collect(),
            starts,
        }
    }

    /// The items of group `k`.
    pub fn get(&self, k: usize) -> &[T] {
        match (self.starts.get(k), self.starts.get(k + 1)) {
            (Some(&a), Some(&b)) => &self.items[a as usize..b as usize],
            _ => &[],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Grouped;

    #[test]
    fn groups_keep_their_order() {
        let g = Grouped::new([(2, 'a'), (0, 'b'), (2, 'c'), (0, 'd')]);
        assert_eq!(g.get(0), ['b', 'd']);
        assert!(g.get(1).is_empty());
        assert_eq!(g.get(2), ['a', 'c']);
        assert!(g.get(3).is_empty());
        assert!(Grouped::<char>::new([]).get(0).is_empty());
    }
}
