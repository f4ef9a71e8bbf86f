//! [`Csr`]: rows of items stored back to back (compressed sparse rows), the one layout behind
//! vertex-to-triangle incidence, rings' triangles and rings' vertices.

use std::ops::Range;

/// Rows of items stored back to back: row `r` is `items[offsets[r]..offsets[r + 1]]`. Offsets
/// are `u32` because every item count dvh stores is bounded by a triangle or vertex count.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Csr<T> {
    offsets: Vec<u32>,
    items: Vec<T>,
}

impl<T> Default for Csr<T> {
    fn default() -> Self {
        Csr {
            offsets: vec![0],
            items: Vec::new(),
        }
    }
}

/// Heap bytes a vector holds (its capacity, used or not).
pub(crate) fn heap_bytes<T>(v: &Vec<T>) -> usize {
    v.capacity() * std::mem::size_of::<T>()
}

impl<T> Csr<T> {
    /// Heap bytes held.
    pub fn heap_bytes(&self) -> usize {
        heap_bytes(&self.offsets) + heap_bytes(&self.items)
    }
}

impl<T: Copy> Csr<T> {
    /// An empty table with room for `rows` rows and `items` items.
    pub fn with_capacity(rows: usize, items: usize) -> Csr<T> {
        let mut offsets = Vec::with_capacity(rows + 1);
        offsets.push(0);
        Csr {
            offsets,
            items: Vec::with_capacity(items),
        }
    }

    /// Groups items by row in two passes (a counting sort): `entries()` yields `(row, item)` for
    /// rows below `rows`, and must yield the same sequence both times it is called. Items keep
    /// their order within a row.
    pub fn from_entries<I>(rows: usize, entries: impl Fn() -> I) -> Csr<T>
    where
        I: Iterator<Item = (u32, T)>,
        T: Default,
    {
        let mut offsets = vec![0u32; rows + 1];
        for (r, _) in entries() {
            offsets[r as usize + 1] += 1;
        }
        for r in 0..rows {
            offsets[r + 1] += offsets[r];
        }
        let total = offsets[rows] as usize;
        let mut cursor = offsets[..rows].to_vec();
        let mut items = vec![T::default(); total];
        for (r, item) in entries() {
            items[cursor[r as usize] as usize] = item;
            cursor[r as usize] += 1;
        }
        Csr { offsets, items }
    }

    /// Appends an item to the row being built (closed by [`Csr::end_row`]).
    #[inline]
    pub fn push(&mut self, item: T) {
        self.items.push(item);
    }

    /// Closes the row being built.
    #[inline]
    pub fn end_row(&mut self) {
        self.offsets.push(self.items.len() as u32);
    }

    /// Number of rows.
    #[inline]
    pub fn rows(&self) -> usize {
        self.offsets.len() - 1
    }

    /// The items of row `r`.
    #[inline(always)]
    pub fn row(&self, r: usize) -> &[T] {
        &self.items[self.span(r..r + 1)]
    }

    /// The items of rows `rows`, back to back.
    #[inline]
    pub fn row_range(&self, rows: Range<usize>) -> &[T] {
        &self.items[self.span(rows)]
    }

    /// Where the items of rows `rows` sit in [`Csr::items`].
    #[inline(always)]
    pub fn span(&self, rows: Range<usize>) -> Range<usize> {
        self.offsets[rows.start] as usize..self.offsets[rows.end] as usize
    }

    /// Number of items in row `r`.
    #[inline]
    pub fn row_len(&self, r: usize) -> usize {
        (self.offsets[r + 1] - self.offsets[r]) as usize
    }

    /// Every item, row after row.
    #[inline]
    pub fn items(&self) -> &[T] {
        &self.items
    }

    /// The row boundaries: `rows() + 1` offsets, the first 0, the last `items().len()`.
    pub fn offsets(&self) -> &[u32] {
        &self.offsets
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn built_row_by_row_or_by_entries_alike() {
        let mut a = Csr::with_capacity(3, 4);
        for row in [&[5u32, 6][..], &[], &[7, 8]] {
            for &x in row {
                a.push(x);
            }
            a.end_row();
        }
        let entries = [(2u32, 7u32), (0, 5), (2, 8), (0, 6)];
        let b = Csr::from_entries(3, || entries.iter().copied());
        assert_eq!(a, b);
        assert_eq!(a.rows(), 3);
        assert_eq!(a.row(0), &[5, 6]);
        assert!(a.row(1).is_empty());
        assert_eq!(a.row_len(2), 2);
        assert_eq!(a.row_range(1..3), &[7, 8]);
        assert_eq!(a.span(0..2), 0..2);
        assert_eq!(a.offsets(), &[0, 2, 2, 4]);
        assert_eq!(a.items(), &[5, 6, 7, 8]);
    }
}
