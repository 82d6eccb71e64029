//! A uniform grid of boxes, so that the composition of a drawing looks only at the edges, pieces
//! and cells near each piece instead of all of them (thousands of holes in a plate would
//! otherwise cost a quadratic number of tests).

use glam::DVec2;

/// Boxes by id in the cells of a grid over a fixed area; a box over more than [`MAX_CELLS`] cells
/// goes to a list every query returns.
pub(super) struct BoxGrid {
    lo: DVec2,
    cell: f64,
    nx: usize,
    ny: usize,
    cells: Vec<Vec<usize>>,
    big: Vec<usize>,
    seen: Vec<u32>,
    epoch: u32,
}

/// The most cells a box is entered in.
const MAX_CELLS: usize = 64;

impl BoxGrid {
    /// A grid over `lo..hi` sized for about `count` boxes.
    pub(super) fn new(lo: DVec2, hi: DVec2, count: usize) -> Self {
        let extent = (hi - lo).max_element();
        let side = (count.max(1) as f64).sqrt().ceil().min(1024.0);
        let cell = if extent.is_finite() && extent > 0.0 {
            extent / side
        } else {
            1.0
        };
        let n = |d: f64| ((d / cell).floor() as usize).saturating_add(1).min(1025);
        let (nx, ny) = (n(hi.x - lo.x), n(hi.y - lo.y));
        Self {
            lo,
            cell,
            nx,
            ny,
            cells: vec![Vec::new(); nx * ny],
            big: Vec::new(),
            seen: Vec::new(),
            epoch: 0,
        }
    }

    fn range(&self, min: DVec2, max: DVec2) -> (usize, usize, usize, usize) {
        let index = |v: f64, o: f64, n: usize| {
            let i = ((v - o) / self.cell).floor();
            if i.is_nan() || i < 0.0 {
                0
            } else {
                (i as usize).min(n - 1)
            }
        };
        (
            index(min.x, self.lo.x, self.nx),
            index(max.x, self.lo.x, self.nx),
            index(min.y, self.lo.y, self.ny),
            index(max.y, self.lo.y, self.ny),
        )
    }

    /// Enters box `id` (ids are small integers, each entered once).
    pub(super) fn insert(&mut self, id: usize, min: DVec2, max: DVec2) {
        if self.seen.len() <= id {
            self.seen.resize(id + 1, 0);
        }
        let (x0, x1, y0, y1) = self.range(min, max);
        if (x1 - x0 + 1) * (y1 - y0 + 1) > MAX_CELLS {
            self.big.push(id);
            return;
        }
        for y in y0..=y1 {
            for x in x0..=x1 {
                self.cells[y * self.nx + x].push(id);
            }
        }
    }

    /// The ids of the boxes that may meet `min..max`, each once.
    pub(super) fn query(&mut self, min: DVec2, max: DVec2) -> Vec<usize> {
        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 {
            self.seen.iter_mut().for_each(|s| *s = 0);
            self.epoch = 1;
        }
        let mut out = self.big.clone();
        let (x0, x1, y0, y1) = self.range(min, max);
        for y in y0..=y1 {
            for x in x0..=x1 {
                for &id in &self.cells[y * self.nx + x] {
                    if self.seen[id] != self.epoch {
                        self.seen[id] = self.epoch;
                        out.push(id);
                    }
                }
            }
        }
        out
    }
}
