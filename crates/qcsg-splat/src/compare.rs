//! Agreement of a frame with the reference frame of the same view: coverage, primitive id and
//! depth, pixel by pixel, away from the reference's silhouettes and creases.

use qcsg_render::{Frame, PixelId};

/// How far apart two depths may be, as a fraction of the view's depth range.
pub const DEPTH_TOLERANCE: f64 = 1e-4;

/// Neighbouring reference depths further apart than this fraction of the depth range mark a
/// depth discontinuity (a surface in front of another part of the same quadric), which is
/// banded like a silhouette.
const DEPTH_JUMP: f64 = 5e-3;

/// The outcome of [`compare`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Agreement {
    /// Pixels compared: those outside the band.
    pub compared: usize,
    /// Pixels in the one-pixel band around silhouettes, creases and depth discontinuities.
    pub banded: usize,
    /// Compared pixels where one frame shows the solid and the other does not.
    pub coverage_mismatches: usize,
    /// Compared pixels where both show the solid on different quadrics.
    pub quadric_mismatches: usize,
    /// Compared pixels on the same quadric with depths further apart than the tolerance.
    pub depth_mismatches: usize,
    /// Compared pixels on the same quadric but attributed to a different term (not counted as
    /// a disagreement: where terms overlap, a surface belongs to several of them).
    pub term_differences: usize,
    /// The largest depth difference over compared pixels on the same quadric, as a fraction of
    /// the depth range.
    pub max_depth_error: f64,
    /// The view's depth range: the spread of the reference's finite depths.
    pub depth_range: f64,
}

impl Agreement {
    /// Compared pixels that disagree in coverage, quadric or depth.
    pub fn mismatches(&self) -> usize {
        self.coverage_mismatches + self.quadric_mismatches + self.depth_mismatches
    }

    /// The fraction of compared pixels that agree (1 when nothing was compared).
    pub fn fraction(&self) -> f64 {
        if self.compared == 0 {
            return 1.0;
        }
        1.0 - self.mismatches() as f64 / self.compared as f64
    }
}

/// Compares `frame` with `reference` (same size and camera). A pixel is banded when any of its
/// eight neighbours in the reference differs from it in coverage or quadric, or lies in front
/// of or behind it by more than a small fraction of the depth range.
pub fn compare(reference: &Frame, frame: &Frame) -> Agreement {
    let (width, height) = (reference.size.width(), reference.size.height());
    let finite = reference.depth.iter().copied().filter(|d| d.is_finite());
    let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), d| {
        (lo.min(d), hi.max(d))
    });
    let depth_range = if hi > lo { hi - lo } else { hi.abs().max(1.0) };
    let mut out = Agreement {
        depth_range,
        ..Agreement::default()
    };
    let hit = |id: PixelId| id.term != PixelId::NONE;
    for y in 0..height {
        for x in 0..width {
            let i = reference.index(x, y);
            let (id, depth) = (reference.ids[i], reference.depth[i]);
            let mut edge = false;
            for ny in y.saturating_sub(1)..=(y + 1).min(height - 1) {
                for nx in x.saturating_sub(1)..=(x + 1).min(width - 1) {
                    let j = reference.index(nx, ny);
                    let other = reference.ids[j];
                    if hit(other) != hit(id)
                        || other.quadric != id.quadric
                        || (hit(id)
                            && (reference.depth[j] - depth).abs() > DEPTH_JUMP * depth_range)
                    {
                        edge = true;
                    }
                }
            }
            if edge {
                out.banded += 1;
                continue;
            }
            out.compared += 1;
            let theirs = frame.ids[i];
            if hit(id) != hit(theirs) {
                out.coverage_mismatches += 1;
            } else if hit(id) {
                if id.quadric != theirs.quadric {
                    out.quadric_mismatches += 1;
                    continue;
                }
                if id.term != theirs.term {
                    out.term_differences += 1;
                }
                let error = (frame.depth[i] - depth).abs() / depth_range;
                out.max_depth_error = out.max_depth_error.max(error);
                // NaN (a depth on one side only) counts as a mismatch.
                if error.is_nan() || error > DEPTH_TOLERANCE {
                    out.depth_mismatches += 1;
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use qcsg_render::ImageSize;

    fn frame(ids: &[PixelId], depth: &[f64], size: ImageSize) -> Frame {
        Frame {
            size,
            rgb: vec![0; 3 * ids.len()],
            depth: depth.to_vec(),
            ids: ids.to_vec(),
        }
    }

    #[test]
    fn disagreements_inside_count_and_at_silhouettes_do_not() {
        let size = ImageSize::new(8, 8).unwrap();
        let a = PixelId {
            quadric: 0,
            term: 0,
        };
        // The left half shows quadric 0 at depth 1, the right half misses.
        let ids: Vec<PixelId> = (0..64)
            .map(|i| if i % 8 < 4 { a } else { PixelId::MISS })
            .collect();
        let depth: Vec<f64> = ids
            .iter()
            .map(|&id| if id == a { 1.0 } else { f64::INFINITY })
            .collect();
        let reference = frame(&ids, &depth, size);
        let same = compare(&reference, &reference);
        assert_eq!(same.mismatches(), 0);
        assert_eq!(same.banded, 16, "columns 3 and 4 are the silhouette band");

        // A silhouette one pixel off is forgiven; a hole inside is not; a depth error is not.
        let mut moved = reference.clone();
        for y in 0..8 {
            moved.ids[y * 8 + 4] = a;
            moved.depth[y * 8 + 4] = 1.0;
        }
        moved.ids[8 + 1] = PixelId::MISS;
        moved.depth[16 + 1] += 1e-3;
        let result = compare(&reference, &moved);
        assert_eq!(result.coverage_mismatches, 1);
        assert_eq!(result.depth_mismatches, 1);
        assert!(result.fraction() < 1.0);
    }
}
