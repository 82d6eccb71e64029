//! Eq. 22 at exact points of a sampling plane, remembered for one walk of the subdivision.
//!
//! Longest-edge splitting comes back to the same plane points: the midpoint of an edge is a
//! corner of the cells on both sides of it, and the centre of a small cell, queried to classify
//! it, becomes a corner of its grandchildren when it is split. On the benchmark scenes a
//! quarter of the distance queries repeated a point of the same region, four in five of those
//! within the last 256 queries, so a small direct-mapped table keyed by the exact bits of the
//! point catches them (paper 000 §7.1 leaves such sharing of queries between branches as future
//! work). A value found here is the one eq. 22 gives again, so the samples do not change.
//!
//! A walk starts from an empty memo ([`QueryMemo::clear`], constant time), so what it finds
//! depends on the walk alone and not on what its thread ran before: the query counts, like the
//! samples, are the same for any thread count.

/// Slots of the table: 20 KiB, within the first-level cache beside a walk's other data.
const SLOTS: usize = 512;

/// One remembered point: eq. 22 there and the heightfield's squared slope (NaN where none).
#[derive(Clone, Copy, Debug, Default)]
struct Slot {
    x: u64,
    y: u64,
    /// The walk that wrote it; 0 is never a walk's, so a new table is empty.
    walk: u32,
    distance: f64,
    slope: f64,
}

/// The values of eq. 22 and of the squared slope at the points of one region that one walk of
/// its subdivision queried lately.
pub struct QueryMemo {
    slots: Box<[Slot]>,
    walk: u32,
}

impl Default for QueryMemo {
    fn default() -> Self {
        Self {
            slots: vec![Slot::default(); SLOTS].into_boxed_slice(),
            walk: 1,
        }
    }
}

impl QueryMemo {
    /// Bytes of its table.
    pub fn heap_bytes(&self) -> usize {
        self.slots.len() * size_of::<Slot>()
    }

    /// Forgets every point: the next walk, possibly of another region, starts empty.
    pub fn clear(&mut self) {
        self.walk = self.walk.wrapping_add(1);
        if self.walk == 0 {
            self.slots.fill(Slot::default());
            self.walk = 1;
        }
    }

    /// `(distance, slope)` at `(x, y)`: remembered, or from `evaluate` and remembered.
    pub fn get_or(&mut self, x: f64, y: f64, evaluate: impl FnOnce() -> (f64, f64)) -> (f64, f64) {
        let (x, y) = (x.to_bits(), y.to_bits());
        let hash = (x ^ y.rotate_left(29)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        let slot = &mut self.slots[(hash >> (u64::BITS - SLOTS.ilog2())) as usize];
        if slot.walk == self.walk && slot.x == x && slot.y == y {
            return (slot.distance, slot.slope);
        }
        let (distance, slope) = evaluate();
        *slot = Slot {
            x,
            y,
            walk: self.walk,
            distance,
            slope,
        };
        (distance, slope)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Counts the evaluations `get_or` makes for `points`.
    fn evaluations(memo: &mut QueryMemo, points: &[(f64, f64)]) -> usize {
        let mut count = 0;
        for &(x, y) in points {
            let (d, s) = memo.get_or(x, y, || {
                count += 1;
                (x - y, x * y)
            });
            assert_eq!(
                (d.to_bits(), s.to_bits()),
                ((x - y).to_bits(), (x * y).to_bits())
            );
        }
        count
    }

    #[test]
    fn remembers_exact_points_within_a_walk() {
        let mut memo = QueryMemo::default();
        let points: Vec<(f64, f64)> = (0..64).map(|i| (f64::from(i) * 0.25, 1.5)).collect();
        assert_eq!(evaluations(&mut memo, &points), 64);
        assert_eq!(evaluations(&mut memo, &points), 0);
        // Points a bit apart are not the same point, nor is zero of the other sign.
        let near: Vec<(f64, f64)> = points.iter().map(|&(x, y)| (x, y.next_up())).collect();
        assert_eq!(evaluations(&mut memo, &near), 64);
        assert_eq!(evaluations(&mut memo, &[(0.0, 0.0), (-0.0, 0.0)]), 2);
    }

    #[test]
    fn a_cleared_memo_evaluates_again() {
        let mut memo = QueryMemo::default();
        let points = [(1.0, 2.0), (3.0, 4.0)];
        assert_eq!(evaluations(&mut memo, &points), 2);
        memo.clear();
        assert_eq!(evaluations(&mut memo, &points), 2);
        // Past the wrap of the walk counter too.
        memo.walk = u32::MAX;
        assert_eq!(evaluations(&mut memo, &points), 2);
        memo.clear();
        assert_eq!(evaluations(&mut memo, &points), 2);
    }

    #[test]
    fn a_full_table_still_answers_right() {
        let mut memo = QueryMemo::default();
        let points: Vec<(f64, f64)> = (0..4 * SLOTS).map(|i| (i as f64, -(i as f64))).collect();
        evaluations(&mut memo, &points);
        evaluations(&mut memo, &points);
    }
}
