//! Where a fill places its samples over a rectangle of the sampling plane that is on the surface
//! throughout: in rows, as a square grid or staggered, whichever takes fewer samples.
//!
//! Every point of the rectangle must lie within `ρ` (the sample radius over the rectangle's
//! greatest distortion) of a sample. A square grid of cells with a diagonal of `2ρ`, a sample
//! at each centre, spends `2ρ²` of area on a sample. Staggered rows, every other one shifted by
//! half a spacing, put the samples on a triangular lattice and spend `3√3/2 ρ² ≈ 2.6ρ²`: 23 %
//! fewer samples over a large rectangle. At the sides both waste some, and a shifted row needs
//! one sample more (it ends on both sides), so on small rectangles the square grid can take
//! fewer.
//!
//! Staggered rows, with `s` between neighbours in a row, `g` between rows and `e` from the
//! rectangle's bottom and top to the first and last row: the rows of `m` samples have them at
//! cell centres (`(i + ½) s`, `s = width / m`), the shifted ones `m + 1` at the cells' borders
//! (`i s`, both sides included). Two neighbouring rows cut the band between them into
//! triangles of base `s` and height `g` (and, at each side, half of one); a point of such a
//! triangle is within `(s²/4 + g²) / max(s, 2g)` of one of its corners (the circumradius where
//! the triangle is acute, the reach of a base corner's part of the base where it is obtuse).
//! A point between the rectangle's bottom or top and the nearest row is within
//! `√(s²/4 + e²)` of a sample of that row.

/// The layout of a fill's samples over a rectangle `width × height` (coordinates from its
/// lower corner).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FillGrid {
    /// Samples of an unshifted row: one at the centre of each of `columns` cells of width
    /// `spacing`. A shifted row has `columns + 1`, at the cells' borders.
    pub columns: u32,
    /// Rows.
    pub rows: u32,
    /// Whether every odd row is shifted (staggered rows); none is in a square grid.
    pub staggered: bool,
    /// Distance between neighbours in a row.
    pub spacing: f64,
    /// Row `k` lies at `y = (k + row_shift) · row_gap`.
    row_gap: f64,
    row_shift: f64,
    /// Every point of the rectangle lies within `reach` of a sample, at most `ρ`.
    pub reach: f64,
    /// Every point of the rectangle lies within `spacing / 2` along `x` and `half_height` along
    /// `y` of its nearest sample: a sample may be left out where none of that box around it is
    /// the region's (the box of its square cell in a square grid).
    pub half_height: f64,
}

/// One row of a [`FillGrid`]: sample `i` lies at `x = (i + offset) · spacing` (the last of a
/// shifted row on the rectangle's side) and at `y`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FillRow {
    pub y: f64,
    pub offset: f64,
    pub samples: u32,
}

/// `√3`: neighbours in the rows of a triangular lattice of reach `ρ` are `√3 ρ` apart.
const SQRT_3: f64 = 1.732_050_807_568_877_2;

/// Largest number of rows or of samples in a row of one fill; bigger rectangles are split
/// first.
pub(crate) const MAX_FILL_SIDE: f64 = 1024.0;

impl FillGrid {
    /// The layout with the fewest samples that keeps every point of the rectangle within
    /// `rho` of a sample (the square grid where the two take as many); `None` where a square
    /// grid would exceed [`MAX_FILL_SIDE`] (or `rho` is not positive and finite). The counts are
    /// found in units of `rho`, which keeps their squares in range at any scale.
    pub fn over(width: f64, height: f64, rho: f64) -> Option<Self> {
        let (w, h) = (width / rho, height / rho);
        let (nx, ny) = square_shape(w, h)?;
        let square = nx * ny;
        // Two staggered rows take at least three samples (one row is a square grid's).
        let mut best: Option<(f64, f64)> = None;
        if square > 3.0 {
            // Neighbours in a row less than `2ρ` apart, and near the `√3 ρ` of the triangular
            // lattice: trying one column fewer and one more than it came within 0.2 % of the
            // fewest samples over all column counts, on the fills of three balls and of a
            // dimpled cube. Only the counts in the loop: it runs for every fill.
            let mut fewest = square;
            let lattice = ceil_count(w / SQRT_3);
            let mut columns = (floor_count(0.5 * w) + 1.0).max(lattice - 1.0);
            while columns <= lattice + 1.0 {
                let rows = staggered_rows(w, h, columns);
                let samples = rows * columns + floor_count(0.5 * rows);
                if samples < fewest {
                    (best, fewest) = (Some((columns, rows)), samples);
                }
                columns += 1.0;
            }
        }
        Some(match best {
            Some((columns, rows)) => Self::staggered((width, height, rho), (columns, rows)),
            None => Self::square((width, height), (nx, ny)),
        })
    }

    /// The samples it places.
    pub fn samples(&self) -> u64 {
        let (columns, rows) = (u64::from(self.columns), u64::from(self.rows));
        if self.staggered {
            rows * columns + rows / 2
        } else {
            rows * columns
        }
    }

    /// Row `k`.
    pub fn row(&self, k: u32) -> FillRow {
        let shifted = self.staggered && k % 2 == 1;
        FillRow {
            y: (f64::from(k) + self.row_shift) * self.row_gap,
            offset: if shifted { 0.0 } else { 0.5 },
            samples: self.columns + u32::from(shifted),
        }
    }

    /// The square grid of `nx × ny` cells ([`square_shape`]).
    fn square((width, height): (f64, f64), (nx, ny): (f64, f64)) -> Self {
        let (dx, dy) = (width / nx, height / ny);
        Self {
            columns: nx as u32,
            rows: ny as u32,
            staggered: false,
            spacing: dx,
            row_gap: dy,
            row_shift: 0.5,
            reach: 0.5 * dx.hypot(dy),
            half_height: 0.5 * dy,
        }
    }

    /// Staggered rows of `columns` and `columns + 1` samples (see the module docs), `rows` of
    /// them ([`staggered_rows`]) spread evenly over the height.
    fn staggered((width, height, rho): (f64, f64, f64), (columns, rows): (f64, f64)) -> Self {
        let s = width / columns;
        // In units of `rho`: half the spacing, and how far the rows are from the bottom and
        // top and from each other.
        let half = 0.5 * s / rho;
        let (edge, gap, between) = if rows == 1.0 {
            (0.5 * height / rho, height / rho, 0.0)
        } else {
            // Both shrink alike to fit the height; the reach of each only falls with them.
            let edge = (1.0 - half * half).sqrt();
            let fit = height / rho / (2.0 * edge + (rows - 1.0) * (1.0 + edge));
            let (edge, gap) = (fit * edge, fit * (1.0 + edge));
            let between = (half * half + gap * gap) / (2.0 * half).max(2.0 * gap);
            (edge, gap, between)
        };
        let reach = rho * between.max(half.hypot(edge));
        Self {
            columns: columns as u32,
            rows: rows as u32,
            staggered: true,
            spacing: s,
            row_gap: rho * gap,
            row_shift: edge / gap,
            reach,
            half_height: reach,
        }
    }
}

/// The square grid `nx × ny` over `w × h` (in units of `ρ`) with the fewest cells whose
/// diagonals are shorter than `2`: a square grid wastes up to half its rows to rounding, while
/// narrowing one side lets the other grow (`dx² + dy² < 4`). `None` where it would exceed
/// [`MAX_FILL_SIDE`].
fn square_shape(w: f64, h: f64) -> Option<(f64, f64)> {
    let square = ceil_count(w.max(h) * std::f64::consts::FRAC_1_SQRT_2).max(1.0);
    if square.is_nan() || square > MAX_FILL_SIDE {
        return None;
    }
    let mut best: Option<(f64, f64)> = None;
    // Columns from the fewest possible to those of the square grid; rows follow.
    let first = floor_count(0.5 * w).max(0.0) + 1.0;
    let last = ceil_count(w * std::f64::consts::FRAC_1_SQRT_2).max(first);
    let mut nx = first;
    while nx <= last {
        let dx = w / nx;
        let dy = (4.0 - dx * dx).sqrt();
        if dy > 0.0 {
            let ny = ceil_count(h / dy).max(1.0);
            if ny <= MAX_FILL_SIDE && best.is_none_or(|(bx, by)| nx * ny < bx * by) {
                best = Some((nx, ny));
            }
        }
        nx += 1.0;
    }
    best
}

/// The fewest staggered rows of `columns` and `columns + 1` samples that keep every point of
/// `w × h` (in units of `ρ`) within `1` (see the module docs): rows up to `e = √(1 − s²/4)`
/// from the bottom and top and `1 + e` apart. Infinite where `columns` samples are too far
/// apart for any, or the rows or the longer rows' samples would exceed [`MAX_FILL_SIDE`].
fn staggered_rows(w: f64, h: f64, columns: f64) -> f64 {
    let half = 0.5 * w / columns;
    let edge = (1.0 - half * half).sqrt();
    if edge.is_nan() || edge <= 0.0 || columns + 1.0 > MAX_FILL_SIDE {
        return f64::INFINITY;
    }
    let rows = if h <= 2.0 * edge {
        1.0
    } else {
        ceil_count((h - 2.0 * edge) / (1.0 + edge)) + 1.0
    };
    if rows > MAX_FILL_SIDE {
        f64::INFINITY
    } else {
        rows
    }
}

/// `x.ceil()` for the counts of a fill; values above [`MAX_FILL_SIDE`], which are rejected,
/// and NaN come back as they are. Without SSE4.1 (not assumed) `ceil` and `floor` are calls
/// into libm, and a fill weighs up to a few dozen layouts.
fn ceil_count(x: f64) -> f64 {
    if x.is_nan() || x > MAX_FILL_SIDE {
        return x;
    }
    let truncated = x as i64 as f64;
    if truncated < x {
        truncated + 1.0
    } else {
        truncated
    }
}

/// `x.floor()` as [`ceil_count`] takes its ceiling.
fn floor_count(x: f64) -> f64 {
    let up = ceil_count(x);
    if up > x { up - 1.0 } else { up }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The samples of `grid` over `width × height`, as a fill places them.
    fn positions(grid: &FillGrid, width: f64) -> Vec<(f64, f64)> {
        (0..grid.rows)
            .flat_map(|k| {
                let row = grid.row(k);
                (0..row.samples).map(move |i| {
                    let x = ((f64::from(i) + row.offset) * grid.spacing).min(width);
                    (x, row.y)
                })
            })
            .collect()
    }

    /// Checks `grid` over `width × height`: every point is within `reach` (at most `rho`) of a
    /// sample, proven over boxes that halve until the distance from the centre to the nearest
    /// sample plus the half-diagonal is within it (the distance to the nearest sample changes
    /// no faster than the point moves), to `1e-9 ρ`; and on a grid of points, each lies inside
    /// the box the module promises around its nearest sample.
    fn assert_covers(grid: &FillGrid, width: f64, height: f64, rho: f64) {
        let samples = positions(grid, width);
        assert_eq!(samples.len() as u64, grid.samples());
        assert!(grid.reach <= rho * (1.0 + 1e-12), "{grid:?} for {rho}");
        let nearest = |p: (f64, f64)| {
            let distance = |s: &(f64, f64)| (s.0 - p.0).hypot(s.1 - p.1);
            let nearest = samples
                .iter()
                .min_by(|s, t| distance(s).total_cmp(&distance(t)))
                .expect("a fill has samples");
            (*nearest, distance(nearest))
        };
        let slack = 1e-9 * rho;
        let mut boxes = vec![((0.0, width), (0.0, height))];
        while let Some(((x0, x1), (y0, y1))) = boxes.pop() {
            let centre = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
            let half_diagonal = 0.5 * (x1 - x0).hypot(y1 - y0);
            let (_, distance) = nearest(centre);
            assert!(
                distance <= grid.reach + slack,
                "{centre:?} is {distance} from the nearest sample, reach {} ({grid:?})",
                grid.reach
            );
            if distance + half_diagonal > grid.reach + slack {
                let (xm, ym) = centre;
                boxes.extend([
                    ((x0, xm), (y0, ym)),
                    ((xm, x1), (y0, ym)),
                    ((x0, xm), (ym, y1)),
                    ((xm, x1), (ym, y1)),
                ]);
            }
        }
        let steps = 40;
        for a in 0..=steps {
            for b in 0..=steps {
                let p = (
                    width * f64::from(a) / f64::from(steps),
                    height * f64::from(b) / f64::from(steps),
                );
                let (sample, _) = nearest(p);
                assert!((sample.0 - p.0).abs() <= 0.5 * grid.spacing + slack);
                assert!((sample.1 - p.1).abs() <= grid.half_height + slack);
            }
        }
    }

    #[test]
    fn staggered_rows_save_a_fifth_on_large_rectangles() {
        let grid = FillGrid::over(100.0, 100.0, 1.0).expect("small enough");
        assert!(grid.staggered);
        let square = square_shape(100.0, 100.0).expect("small enough");
        // `2 / (3√3/2) = 0.77` of the square grid's samples, and some at the sides.
        let ratio = grid.samples() as f64 / (square.0 * square.1);
        assert!((0.76..0.80).contains(&ratio), "{ratio}");
        let grid = FillGrid::over(25.0, 20.0, 1.0).expect("small enough");
        assert!(grid.staggered);
        assert_covers(&grid, 25.0, 20.0, 1.0);
    }

    #[test]
    fn small_and_thin_rectangles_keep_the_square_grid_where_it_takes_fewer() {
        for (width, height) in [(0.5, 0.5), (3.0, 3.0), (40.0, 0.3), (0.3, 40.0), (2.0, 1.0)] {
            let grid = FillGrid::over(width, height, 1.0).expect("small enough");
            let (nx, ny) = square_shape(width, height).expect("small enough");
            assert!(grid.samples() as f64 <= nx * ny);
            assert_covers(&grid, width, height, 1.0);
        }
        // One sample covers a rectangle of diagonal up to `2ρ`.
        assert_eq!(FillGrid::over(1.2, 1.6, 1.0).map(|g| g.samples()), Some(1));
    }

    #[test]
    fn too_large_or_invalid_rectangles_have_no_grid() {
        assert!(FillGrid::over(1e6, 1.0, 1.0).is_none());
        assert!(FillGrid::over(1.0, 1.0, f64::NAN).is_none());
        assert!(FillGrid::over(1.0, 1.0, 0.0).is_none());
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]
        #[test]
        fn every_point_is_covered(
            width in 0.01f64..12.0,
            height in 0.01f64..12.0,
            rho in prop_oneof![Just(1.0), Just(1e-200), Just(1e200), 1e-6f64..1e3],
        ) {
            let (width, height) = (width * rho, height * rho);
            let grid = FillGrid::over(width, height, rho).expect("small enough");
            let (nx, ny) = square_shape(width / rho, height / rho).expect("small enough");
            prop_assert!(grid.samples() as f64 <= nx * ny);
            assert_covers(&grid, width, height, rho);
        }
    }
}
