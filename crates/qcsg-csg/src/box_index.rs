//! An R-tree over boxes (a DNF's term boxes): the boxes near a box, or those a ray meets, found
//! without walking all of them. Eq. 22's setup and the reference ray tracer look at every term
//! otherwise, which makes a scene of `n` separate parts cost `O(n²)`.

use qcsg_quadric::DVec3;
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{AABB, RTree, SelectionFunction};

use crate::Aabb;

/// A box with its index.
type Entry = GeomWithData<Rectangle<[f64; 3]>, u32>;

/// Boxes, searchable by where they are.
#[derive(Clone, Debug)]
pub struct BoxIndex {
    boxes: Vec<Aabb>,
    /// The finite, non-empty boxes.
    tree: RTree<Entry>,
    /// Boxes that are not finite (an unbounded term's): candidates for every search.
    unbounded: Vec<u32>,
}

impl BoxIndex {
    /// The index of `boxes`; searches answer with their positions in it.
    pub fn new(boxes: Vec<Aabb>) -> Self {
        let mut unbounded = Vec::new();
        let mut entries = Vec::new();
        for (index, b) in boxes.iter().enumerate() {
            if b.is_empty() {
                continue;
            }
            if b.min.is_finite() && b.max.is_finite() {
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

    /// The boxes, as given.
    pub fn boxes(&self) -> &[Aabb] {
        &self.boxes
    }

    /// The boxes that come within `margin` of `bounds` ([`Aabb::gap`]), in ascending order;
    /// all of them when `bounds` or `margin` is not finite.
    pub fn near(&self, bounds: &Aabb, margin: f64) -> Vec<u32> {
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
            .filter(|&i| bounds.gap(&self.boxes[i as usize]) <= margin)
            .collect();
        near.sort_unstable();
        near
    }

    /// Appends to `out` the boxes for which `meets` holds, in no particular order. `meets` must
    /// hold for every box containing one it holds for (a ray crossing a box crosses any larger
    /// one): the tree's inner boxes are only opened where it holds.
    pub fn select(&self, meets: impl Fn(&Aabb) -> bool, out: &mut Vec<u32>) {
        let selection = Meets {
            meets: &meets,
            boxes: &self.boxes,
        };
        out.extend(
            self.tree
                .locate_with_selection_function(selection)
                .map(|entry| entry.data),
        );
        out.extend(
            self.unbounded
                .iter()
                .copied()
                .filter(|&i| meets(&self.boxes[i as usize])),
        );
    }
}

/// [`BoxIndex::select`]'s search: inner boxes by their envelope, leaves by their own box.
struct Meets<'a, F> {
    meets: &'a F,
    boxes: &'a [Aabb],
}

impl<F: Fn(&Aabb) -> bool> SelectionFunction<Entry> for Meets<'_, F> {
    fn should_unpack_parent(&self, envelope: &AABB<[f64; 3]>) -> bool {
        let envelope = Aabb {
            min: DVec3::from_array(envelope.lower()),
            max: DVec3::from_array(envelope.upper()),
        };
        (self.meets)(&envelope)
    }

    fn should_unpack_leaf(&self, leaf: &Entry) -> bool {
        (self.meets)(&self.boxes[leaf.data as usize])
    }
}
