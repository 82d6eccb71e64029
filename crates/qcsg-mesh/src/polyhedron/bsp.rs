//! The partition of space by the mesh's own triangle planes, and the even–odd parity carried
//! through it.
//!
//! A kd-tree over the triangles (axis-parallel splits at the median of the centroids) down to
//! regions of at most [`LEAF_TRIANGLES`] triangles, then, inside each, a partition by those
//! triangles' own planes in a fixed pseudo-random order, until no triangle passes through a
//! region. (Partitioning by triangle planes from the start, as the polygon does with its edges,
//! fragments far more in 3-D, where one plane crosses many regions: see the crate's README.)
//! Where a kd split cannot separate the triangles (a fan around one point), their planes do.
//! Each region's next splitting plane is the one, among a few candidates, that cuts the fewest
//! of its triangles. Each region keeps the triangles that may reach into it
//! and a reference point of known parity; a child's parity is its parent's flipped once per
//! triangle crossed on the segment between their reference points (exact, with a simulated
//! perturbation), a segment inside the parent, so only the parent's triangles can cross it. A
//! region keeps only the triangles that reach into its interior: one that meets it only on its
//! boundary (every triangle of a fan meets every region around the fan's centre there) cannot
//! change the parity inside.
//! Splitting by a triangle's plane takes it, and every triangle exactly on that plane, out of
//! both children, so the partition progresses; it runs on an explicit stack.

use glam::DVec3;

use super::region::Polytope;
use super::{Cell3, Plane, Triangle};
use crate::exact::{orient3d, segment_crosses_triangle};

/// A region with more faces than this is halved by an axis-parallel plane first (a safety net:
/// a leaf box cut by its few triangles' planes stays below it).
const MAX_FACES: usize = 12;

/// How many triangles' planes are weighed as the next splitter of a region.
const SPLITTER_CANDIDATES: usize = 16;

/// A region with more triangles than this is split like a kd-tree, by an axis-parallel plane at
/// the median of its triangles' centroids; one with fewer, by its triangles' own planes. Triangle
/// planes give fewer cells than axis-parallel walls once a region holds only the triangles that
/// reach into it, so the kd-tree stops early; much larger leaves give hardly fewer cells but
/// take longer (measured in the crate's README).
const LEAF_TRIANGLES: usize = 32;

/// Children that both hold at least this many triangles are partitioned in parallel: enough
/// work to outweigh handing it to another thread.
const PARALLEL_TRIANGLES: usize = 512;

/// A region awaiting its split.
struct Region {
    polytope: Polytope,
    reference: DVec3,
    parity: bool,
    triangles: Vec<u32>,
}

/// The partition's state.
struct Partition<'a> {
    triangles: &'a [Triangle],
    magnitude: f64,
    min: DVec3,
    max: DVec3,
    cells: Vec<Cell3>,
    visits: u64,
}

/// The even–odd solid bounded by `triangles` as convex cells.
pub(super) fn decompose(triangles: &[Triangle]) -> Vec<Cell3> {
    decompose_counted(triangles).0
}

/// [`decompose`], and the work it took: the sum over the regions split of the triangles each
/// region holds (each is tested against both children), which near-linear partitions keep
/// proportional to the triangle count.
fn decompose_counted(triangles: &[Triangle]) -> (Vec<Cell3>, u64) {
    if triangles.is_empty() {
        return (Vec::new(), 0);
    }
    let (min, max) = triangles.iter().flat_map(|t| t.corners).fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    );
    if (max - min).min_element() <= 0.0 {
        return (Vec::new(), 0);
    }
    let mut partition = Partition {
        triangles,
        magnitude: min.abs().max(max.abs()).max_element(),
        min,
        max,
        cells: Vec::new(),
        visits: 0,
    };
    // Outside every triangle's box: no crossing on the way to infinity, so even.
    let outside = min - (max - min) * DVec3::new(0.25, 0.375, 0.3125);
    let polytope = Polytope::from_box(min, max);
    let reference = polytope.interior_point();
    let all: Vec<u32> = (0..triangles.len() as u32).collect();
    let parity = partition.odd_crossings(outside, reference, &all);
    partition.run(Region {
        polytope,
        reference,
        parity,
        triangles: all,
    });
    (partition.cells, partition.visits)
}

/// The order in which triangles split: a fixed scramble of their indices.
fn priority(index: u32) -> u64 {
    let mut z = u64::from(index).wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

impl Partition<'_> {
    /// The rounding tolerance of `plane`'s values at points of this mesh's magnitude.
    fn tolerance(&self, plane: &Plane) -> f64 {
        let n = plane.normal.abs();
        64.0 * f64::EPSILON * ((n.x + n.y + n.z) * self.magnitude + plane.offset.abs())
    }

    /// Whether the segment `p`–`q` crosses an odd number of the triangles in `list`.
    fn odd_crossings(&self, p: DVec3, q: DVec3, list: &[u32]) -> bool {
        let (lo, hi) = (p.min(q), p.max(q));
        list.iter()
            .filter(|&&i| {
                let [a, b, c] = self.triangles[i as usize].corners;
                // Boxes apart by a positive gap: no perturbation makes them meet, and the exact
                // test, the costly part of a split, is left for the triangles near the segment.
                let apart = hi.cmplt(a.min(b).min(c)).any() || a.max(b).max(c).cmplt(lo).any();
                !apart && segment_crosses_triangle(p, q, a, b, c)
            })
            .count()
            % 2
            == 1
    }

    fn run(&mut self, root: Region) {
        let mut stack = vec![root];
        let pad = 1e-12 * self.magnitude.max(f64::MIN_POSITIVE);
        while let Some(region) = stack.pop() {
            self.visits += region.triangles.len() as u64;
            if region.polytope.face_count() > MAX_FACES {
                let plane = halving_plane(&region.polytope);
                // A region too thin to halve is treated as it stands.
                if let Some((low, high)) = region.polytope.split(plane, self.tolerance(&plane)) {
                    let children = self.children(&region, plane, low, high, None);
                    self.descend(children, &mut stack);
                    continue;
                }
            }
            if region.triangles.len() > LEAF_TRIANGLES {
                let plane = self.median_plane(&region);
                if let Some((low, high)) = region.polytope.split(plane, self.tolerance(&plane)) {
                    let children = self.children(&region, plane, low, high, None);
                    let total = region.triangles.len();
                    // Where every triangle reaches both sides (a fan around one point), the
                    // triangles' own planes separate them instead.
                    if children.iter().all(|c| c.triangles.len() < total) {
                        self.descend(children, &mut stack);
                        continue;
                    }
                }
            }
            if region.triangles.is_empty() {
                if region.parity {
                    self.cells
                        .push(region.polytope.into_cell(pad, self.min, self.max));
                }
                continue;
            }
            let splitter = self.least_cutting(&region.triangles);
            let plane = self.triangles[splitter as usize].plane;
            match region.polytope.split(plane, self.tolerance(&plane)) {
                Some((low, high)) => {
                    stack.extend(self.children(&region, plane, low, high, Some(splitter)))
                }
                None => {
                    // The plane misses the region's interior: so does the triangle.
                    let mut region = region;
                    region.triangles.retain(|&i| i != splitter);
                    stack.push(region);
                }
            }
        }
    }

    /// Partitions `children` next: on the stack, or, for children of many triangles, each on
    /// its own thread. Either way the cells come out in the same order, the last child's first,
    /// as a region popped off the stack is partitioned whole before the regions beneath it.
    fn descend(&mut self, children: [Region; 2], stack: &mut Vec<Region>) {
        if children
            .iter()
            .any(|c| c.triangles.len() < PARALLEL_TRIANGLES)
        {
            stack.extend(children);
            return;
        }
        let [low, high] = children;
        let part = |region: Region| {
            let mut part = Partition {
                cells: Vec::new(),
                visits: 0,
                ..*self
            };
            part.run(region);
            (part.cells, part.visits)
        };
        let ((high_cells, high_visits), (low_cells, low_visits)) =
            rayon::join(|| part(high), || part(low));
        self.cells.extend(high_cells);
        self.cells.extend(low_cells);
        self.visits += high_visits + low_visits;
    }

    /// The two children of `parent` cut by `plane`, a triangle's (`splitter`) or a free one.
    fn children(
        &self,
        parent: &Region,
        plane: Plane,
        low: Polytope,
        high: Polytope,
        splitter: Option<u32>,
    ) -> [Region; 2] {
        let on_wall = |t: &Triangle| match splitter {
            Some(s) => {
                let splitter = &self.triangles[s as usize];
                let [a, b, c] = splitter.corners;
                // A corner beyond the tolerance of the rounded plane is off the exact one too:
                // the exact test is needed only for the few triangles that pass this one.
                let tolerance = self.tolerance(&splitter.plane);
                t.corners
                    .iter()
                    .all(|&p| splitter.plane.value(p).abs() <= tolerance)
                    && t.corners.iter().all(|&p| orient3d(a, b, c, p) == 0)
            }
            None => false,
        };
        let kept: Vec<u32> = parent
            .triangles
            .iter()
            .copied()
            .filter(|&i| !on_wall(&self.triangles[i as usize]))
            .collect();
        [(low, plane), (high, plane.flipped())].map(|(polytope, side)| {
            let slack = self.tolerance(&side);
            let triangles: Vec<u32> = kept
                .iter()
                .copied()
                .filter(|&i| {
                    let corners = self.triangles[i as usize].corners;
                    // Every triangle of the parent reaches into the parent: one wholly on this
                    // side of the cut reaches into the child too, and one wholly beyond it does
                    // not, so only those the cut crosses need clipping by every face.
                    let beyond = corners
                        .iter()
                        .filter(|&&c| side.value(c) + slack > 0.0)
                        .count();
                    match beyond {
                        0 => true,
                        3 => false,
                        _ => polytope.may_touch(corners, |h| self.tolerance(h)),
                    }
                })
                .collect();
            let reference = polytope.interior_point();
            let parity =
                parent.parity ^ self.odd_crossings(parent.reference, reference, &parent.triangles);
            Region {
                polytope,
                reference,
                parity,
                triangles,
            }
        })
    }
}

impl Partition<'_> {
    /// Among (at most [`SPLITTER_CANDIDATES`] of) the triangles, the one whose plane cuts the
    /// fewest others, ties broken by the fixed priority: greedy choices fragment far less than
    /// random ones.
    fn least_cutting(&self, list: &[u32]) -> u32 {
        let mut candidates: Vec<u32> = list.to_vec();
        if candidates.len() > SPLITTER_CANDIDATES {
            candidates.select_nth_unstable_by_key(SPLITTER_CANDIDATES, |&i| priority(i));
            candidates.truncate(SPLITTER_CANDIDATES);
        }
        let cuts = |s: u32| {
            let plane = self.triangles[s as usize].plane;
            let tolerance = self.tolerance(&plane);
            list.iter()
                .filter(|&&i| {
                    let values = self.triangles[i as usize].corners.map(|c| plane.value(c));
                    values.iter().any(|&v| v < -tolerance) && values.iter().any(|&v| v > tolerance)
                })
                .count()
        };
        *candidates
            .iter()
            .min_by_key(|&&s| (cuts(s), priority(s)))
            .expect("a region with triangles")
    }

    /// An axis-parallel plane across the region's longest extent at the median of its triangles'
    /// centroids (at the middle when the median lies on the region's border).
    fn median_plane(&self, region: &Region) -> Plane {
        let (lo, hi) = region.polytope.bounds();
        let axis = longest_axis(hi - lo);
        let mut values: Vec<f64> = region
            .triangles
            .iter()
            .map(|&i| {
                let [a, b, c] = self.triangles[i as usize].corners;
                (a[axis] + b[axis] + c[axis]) / 3.0
            })
            .collect();
        let middle = values.len() / 2;
        let mut value = *values.select_nth_unstable_by(middle, f64::total_cmp).1;
        if !(lo[axis] < value && value < hi[axis]) {
            value = 0.5 * (lo[axis] + hi[axis]);
        }
        let mut normal = DVec3::ZERO;
        normal[axis] = 1.0;
        Plane {
            normal,
            offset: value,
        }
    }
}

/// The axis of the largest component.
fn longest_axis(size: DVec3) -> usize {
    if size.x >= size.y && size.x >= size.z {
        0
    } else if size.y >= size.z {
        1
    } else {
        2
    }
}

/// An axis-parallel plane through the middle of the polytope's longest extent.
fn halving_plane(polytope: &Polytope) -> Plane {
    let (lo, hi) = polytope.bounds();
    let axis = longest_axis(hi - lo);
    let mut normal = DVec3::ZERO;
    normal[axis] = 1.0;
    Plane {
        normal,
        offset: 0.5 * (lo[axis] + hi[axis]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sphere whose radius undulates with latitude and longitude, on a `slices` × `slices + 1`
    /// latitude-longitude grid: each pole is a fan of `slices` thin triangles around one vertex,
    /// whose planes all pass through it.
    fn fanned_sphere(slices: usize) -> Vec<Triangle> {
        use std::f64::consts::PI;
        let stacks = slices + 1;
        let radius = |theta: f64, phi: f64| {
            10.0 * (1.0
                + 0.15 * (5.0 * theta).sin() * (4.0 * phi).sin()
                + 0.05 * (13.0 * phi).sin())
        };
        let point = |i: usize, j: usize| {
            let theta = PI * i as f64 / stacks as f64;
            let phi = 2.0 * PI * (j % slices) as f64 / slices as f64;
            let r = if i == 0 || i == stacks {
                radius(theta, 0.0)
            } else {
                radius(theta, phi)
            };
            r * DVec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            )
        };
        let triangle = |a: DVec3, b: DVec3, c: DVec3| Triangle {
            corners: [a, b, c],
            plane: Plane::through(a, b, c),
        };
        let mut out = Vec::new();
        for j in 0..slices {
            out.push(triangle(point(0, 0), point(1, j), point(1, j + 1)));
            for i in 1..stacks - 1 {
                let (a, b, c, d) = (
                    point(i, j),
                    point(i + 1, j),
                    point(i + 1, j + 1),
                    point(i, j + 1),
                );
                out.push(triangle(a, b, c));
                out.push(triangle(a, c, d));
            }
            out.push(triangle(
                point(stacks - 1, j),
                point(stacks, 0),
                point(stacks - 1, j + 1),
            ));
        }
        out
    }

    #[test]
    fn fans_around_a_vertex_keep_the_work_linear() {
        // A triangle that meets a region only at a shared vertex (every triangle of a pole's fan
        // meets every region around the pole there) used to stay in the region's list, so the
        // regions around each pole grew with the square of the fan and each held the whole fan:
        // 8.9 times the work for 4 times the triangles here, and 290 visits per triangle.
        let (small, large) = (fanned_sphere(25), fanned_sphere(50));
        let ((small_cells, small_work), (large_cells, large_work)) =
            (decompose_counted(&small), decompose_counted(&large));
        let (n_small, n_large) = (small.len() as f64, large.len() as f64);
        let work_ratio = large_work as f64 / small_work as f64;
        assert!(
            work_ratio <= 1.5 * n_large / n_small,
            "work {small_work} for {n_small} triangles, {large_work} for {n_large}"
        );
        assert!(
            large_work as f64 <= 60.0 * n_large,
            "work {large_work} for {n_large} triangles"
        );
        assert!(
            large_cells.len() as f64 <= 5.0 * n_large,
            "{} cells for {n_large} triangles ({} for {n_small})",
            large_cells.len(),
            small_cells.len()
        );
        // The pole is the fans' shared vertex: just inside it, and just outside, are decided.
        let top = fanned_sphere(50)[0].corners[0];
        let inside = |p: DVec3| large_cells.iter().any(|c| c.contains(p));
        assert!(inside(top * 0.999));
        assert!(!inside(top * 1.001));
    }
}
