//! The boxes of a DNF's terms in an R-tree, so that eq. 22's setup finds the terms near a part
//! without walking all of them: a scene of `n` separate parts then costs `O(n log n)` instead
//! of `O(n²)` in time and memory.

use qcsg_csg::Aabb;
use qcsg_quadric::DVec3;
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{AABB, RTree};

/// A term's box with its index.
type Entry = GeomWithData<Rectangle<[f64; 3]>, u32>;

/// The terms' boxes, searchable by distance from a box.
pub(crate) struct TermBoxes {
    boxes: Vec<Aabb>,
    /// The finite, non-empty boxes.
    tree: RTree<Entry>,
    /// Terms whose box is not finite (an unbounded term): candidates for every search.
    unbounded: Vec<u32>,
}

impl TermBoxes {
    /// The index of `boxes`, one per term in order.
    pub(crate) fn new(boxes: Vec<Aabb>) -> Self {
        let mut unbounded = Vec::new();
        let mut entries = Vec::new();
        for (index, b) in boxes.iter().enumerate() {
            if b.is_empty() {
                continue;
            }
            let finite = b.min.is_finite() && b.max.is_finite();
            if finite {
                let rectangle = Rectangle::from_corners(b.min.to_array(), b.max.to_array());
                entries.push(Entry::new(rectangle, index as u32));
            } else {
                unbounded.push(index as u32);
            }
        }
        Self {
            boxes,
            tree: RTree::bulk_load(entries),
            unbounded,
        }
    }

    /// The number of terms.
    pub(crate) fn len(&self) -> usize {
        self.boxes.len()
    }

    /// The box of term `index` (checked by the caller).
    pub(crate) fn get(&self, index: usize) -> &Aabb {
        &self.boxes[index]
    }

    /// The terms whose box comes within `margin` of `bounds` ([`box_gap`]), in ascending order.
    /// Every term when `bounds` or `margin` is not finite.
    pub(crate) fn near(&self, bounds: &Aabb, margin: f64) -> Vec<u32> {
        let finite = bounds.min.is_finite() && bounds.max.is_finite() && margin.is_finite();
        if !finite {
            return (0..self.boxes.len() as u32).collect();
        }
        if bounds.is_empty() {
            return Vec::new();
        }
        let grown = AABB::from_corners(
            (bounds.min - margin).to_array(),
            (bounds.max + margin).to_array(),
        );
        let mut near: Vec<u32> = self
            .tree
            .locate_in_envelope_intersecting(grown)
            .map(|entry| entry.data)
            .chain(self.unbounded.iter().copied())
            .filter(|&i| box_gap(bounds, &self.boxes[i as usize]) <= margin)
            .collect();
        near.sort_unstable();
        near
    }
}

/// The Euclidean gap between two boxes (0 when they touch or overlap, `+∞` if either is empty).
pub(crate) fn box_gap(a: &Aabb, b: &Aabb) -> f64 {
    if a.is_empty() || b.is_empty() {
        return f64::INFINITY;
    }
    let gap = (a.min - b.max).max(b.min - a.max).max(DVec3::ZERO);
    let gap = gap.length();
    if gap.is_nan() { 0.0 } else { gap }
}
