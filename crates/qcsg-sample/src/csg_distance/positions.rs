//! Positions of literals by index ([`Positions`]): a table as long as the DNF's literals,
//! kept per thread and cleared entry by entry, so that a view's set-up costs what its own
//! literals cost however many quadrics the DNF has, without hashing each lookup.

use std::cell::Cell;

/// No position.
const NONE: u32 = u32::MAX;

thread_local! {
    /// The tables a thread's [`Positions`] gave back, all [`NONE`].
    static TABLES: Cell<Vec<Vec<u32>>> = const { Cell::new(Vec::new()) };
}

/// Literal indices mapped to positions in a list, for as long as it lives.
pub(super) struct Positions {
    table: Vec<u32>,
    touched: Vec<u32>,
}

impl Positions {
    /// An empty map of indices below `len`: one of the thread's tables, or a new one where all
    /// are in use.
    pub(super) fn new(len: usize) -> Self {
        let mut table = TABLES.with(|kept| {
            let mut tables = kept.take();
            let table = tables.pop();
            kept.set(tables);
            table.unwrap_or_default()
        });
        if table.len() < len {
            table.resize(len, NONE);
        }
        Self {
            table,
            touched: Vec::new(),
        }
    }

    /// The position of index `i`, if it has one.
    #[inline]
    pub(super) fn get(&self, i: u32) -> Option<usize> {
        let at = *self.table.get(i as usize)?;
        (at != NONE).then_some(at as usize)
    }

    /// The position of index `i`, given by `next` where it has none.
    #[inline]
    pub(super) fn get_or_insert_with(&mut self, i: u32, next: impl FnOnce() -> usize) -> usize {
        if let Some(at) = self.get(i) {
            return at;
        }
        let at = next();
        if let Some(entry) = self.table.get_mut(i as usize) {
            *entry = at as u32;
            self.touched.push(i);
        }
        at
    }
}

impl Drop for Positions {
    fn drop(&mut self) {
        for &i in &self.touched {
            self.table[i as usize] = NONE;
        }
        let table = std::mem::take(&mut self.table);
        TABLES.with(|kept| {
            let mut tables = kept.take();
            tables.push(table);
            kept.set(tables);
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_are_cleared_when_dropped() {
        let mut first = Positions::new(10);
        assert_eq!(first.get_or_insert_with(3, || 0), 0);
        assert_eq!(first.get_or_insert_with(3, || 1), 0);
        assert_eq!(first.get(4), None);
        // A second one while the first is out gets a table of its own.
        let mut second = Positions::new(10);
        assert_eq!(second.get(3), None);
        assert_eq!(second.get_or_insert_with(4, || 7), 7);
        drop(second);
        drop(first);
        let third = Positions::new(20);
        assert_eq!((third.get(3), third.get(4)), (None, None));
        assert_eq!(third.get(25), None);
    }
}
