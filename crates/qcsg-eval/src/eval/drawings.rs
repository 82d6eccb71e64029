//! `import` of a `.dxf` drawing as an exact 2-D shape.
//!
//! [`qcsg_mesh::read_dxf`] reads the drawing with OpenSCAD 2021.01's meaning (the `layer`, then
//! `origin` and `scale`); [`qcsg_mesh::drawing_region`] orders its chord polygons, discs and
//! circular segments (and their elliptic kin) so that each joins the region as a union or a
//! difference. Here each piece becomes a z-invariant solid: the polygon's cells as `polygon`
//! builds them, a disc as a cylinder about z, an elliptic disc as an elliptic cylinder, a segment
//! as that cylinder cut by its chord's half-space. Drawings whose
//! curves cross in ways that need more than that are E0301 at the `file` argument, naming the
//! DXF lines; nothing is tessellated.

use glam::{DVec2, DVec3};
use qcsg_csg::{Edge, NodeId, Source};
use qcsg_mesh::{
    CurvedPiece, DrawingLimits, DrawingOptions, DrawingRegion, Op, PolygonError, PolygonLimits,
    ReadError, RegionError, drawing_region, read_dxf,
};
use qcsg_quadric::Quadric;

use crate::codes;
use crate::polygon::{cells_node, half_space};
use crate::primitives::ArgLookup;
use crate::primitives_2d::column;
use crate::value::Value;

use super::meshes::ImportCall;
use super::{Evaluator, R};

/// The help of a drawing whose curves cannot be composed exactly.
const CROSSING_HELP: &str = "qcsg builds a drawing's arcs and circles exactly when each, taken \
     from the largest, lies wholly inside or wholly outside what the lines and the curves before \
     it enclose; redraw the crossing curves so they meet at end points, or export the region as \
     STL/OFF";

impl<'a> Evaluator<'a> {
    /// `import` of a `.dxf` drawing: the even–odd region of the selected layer's paths and
    /// circles, as a 2-D shape.
    pub(super) fn import_drawing(&mut self, call: &ImportCall<'_, 'a>) -> R<Option<Edge>> {
        let options = self.drawing_options(call)?;
        let bytes = self.import_bytes(call)?;
        let max = usize::try_from(self.options.max_vector_len).unwrap_or(usize::MAX);
        let limits = DrawingLimits {
            max_entities: max,
            max_points: max,
        };
        let drawing =
            read_dxf(&bytes, &options, &limits).map_err(|e| self.dxf_failure(&e, call))?;
        drop(bytes);
        for w in &drawing.warnings {
            self.warn(
                codes::DRAWING_SKIPPED,
                w.to_string(),
                call.file,
                call.file_span,
            );
        }
        let region = drawing_region(&drawing, &PolygonLimits { max_points: max })
            .map_err(|e| self.region_failure(&e, call))?;
        for w in &region.polygon.warnings {
            self.warn(codes::POLYGON_OUTLINE, w.clone(), call.file, call.file_span);
        }
        let source = Source::new(call.file, call.span);
        let from = self.dag.len();
        let node = match build_region(&mut self.dag, &region, source) {
            Ok(Some(node)) => node,
            Ok(None) => self.dag.empty(source),
            Err(m) => {
                return Err(self.error(codes::IMPORT_MALFORMED, m, call.file, call.file_span));
            }
        };
        self.mark_planar(from, node);
        Ok(Some(node.into()))
    }

    /// `layer`, `origin` and `scale`, as OpenSCAD reads them (an empty layer name is every
    /// layer).
    fn drawing_options(&mut self, call: &ImportCall<'_, 'a>) -> R<DrawingOptions> {
        let mut options = DrawingOptions::default();
        match &call.named.get("layer") {
            Value::Undef => {}
            Value::String(s) => options.layer = Some(s.to_string()),
            other => {
                let m = format!(
                    "import(layer) needs a layer name (a string), got {}",
                    other.type_name()
                );
                return Err(self.error(
                    codes::MODULE_ARGUMENT,
                    m,
                    call.file,
                    call.span_of("layer"),
                ));
            }
        }
        match call.named.get("origin") {
            Value::Undef => {}
            v => match v.as_numbers(2) {
                Some(o) if o.iter().all(|x| x.is_finite()) => {
                    options.origin = DVec2::new(o[0], o[1])
                }
                _ => {
                    let m = "import(origin) needs a point [x, y] of finite numbers";
                    return Err(self.error(
                        codes::MODULE_ARGUMENT,
                        m,
                        call.file,
                        call.span_of("origin"),
                    ));
                }
            },
        }
        match call.named.get("scale") {
            Value::Undef => {}
            v => match v.as_number() {
                Some(s) if s.is_finite() => options.scale = s,
                _ => {
                    let m = "import(scale) needs a finite number";
                    return Err(self.error(
                        codes::MODULE_ARGUMENT,
                        m,
                        call.file,
                        call.span_of("scale"),
                    ));
                }
            },
        }
        Ok(options)
    }

    fn dxf_failure(&mut self, e: &ReadError, call: &ImportCall<'_, 'a>) -> super::Stop {
        let (file, span) = (call.file, call.file_span);
        let message = format!("`{}`: {e}", call.written);
        // The reader's limit messages all end in "the limit": those are E0558, with its flag.
        if e.message.contains("the limit") {
            self.error_with_help(
                codes::VECTOR_LIMIT,
                message,
                "raise the limit with --max-vector-len",
                file,
                span,
            )
        } else {
            self.error(codes::IMPORT_MALFORMED, message, file, span)
        }
    }

    fn region_failure(&mut self, e: &RegionError, call: &ImportCall<'_, 'a>) -> super::Stop {
        let (file, span) = (call.file, call.file_span);
        let message = format!("`{}`: {e}", call.written);
        match e {
            RegionError::Polygon(PolygonError::TooManyPoints { .. }) => self.error_with_help(
                codes::VECTOR_LIMIT,
                message,
                "raise the limit with --max-vector-len",
                file,
                span,
            ),
            RegionError::Polygon(_) => self.error(codes::IMPORT_MALFORMED, message, file, span),
            RegionError::Curve { .. } => self.error_with_help(
                qcsg_sema::codes::UNSUPPORTED_MODULE,
                format!("{message}: qcsg reads lines, arcs and circles of DXF drawings exactly"),
                "replace the curve by arcs, or export the region as STL/OFF",
                file,
                span,
            ),
            RegionError::Crossing { .. } | RegionError::TooComplex { .. } => self.error_with_help(
                qcsg_sema::codes::UNSUPPORTED_MODULE,
                format!("{message}: this drawing has no exact form in qcsg yet"),
                CROSSING_HELP,
                file,
                span,
            ),
        }
    }
}

/// The region: the polygon's cells, then each step's union or difference; `None` when empty.
fn build_region(
    dag: &mut qcsg_csg::Dag,
    region: &DrawingRegion,
    source: Source,
) -> Result<Option<NodeId>, String> {
    let mut node = cells_node(dag, &region.polygon, source)?;
    for step in &region.steps {
        let piece = piece_node(dag, &step.piece, source).ok_or_else(|| {
            format!(
                "the curve at DXF line {} is too small or too large to represent",
                step.line
            )
        })?;
        node = match (step.op, node) {
            (Op::Union, None) => Some(piece),
            (Op::Union, Some(n)) => Some(dag.union([n.into(), piece.into()], source)),
            // A difference is chosen only inside the region, so `None` does not meet one; an
            // empty region would stay empty.
            (Op::Difference, None) => None,
            (Op::Difference, Some(n)) => Some(dag.difference([n.into(), piece.into()], source)),
        };
    }
    Ok(node)
}

/// A disc (a cylinder about z), an elliptic disc (an elliptic cylinder) or a segment of either
/// (the cylinder cut by the chord's half-space), with its box; `None` when the size or the chord
/// is not representable.
fn piece_node(dag: &mut qcsg_csg::Dag, piece: &CurvedPiece, source: Source) -> Option<NodeId> {
    let (quadric, center, half) = match *piece {
        CurvedPiece::Disc { center, radius } | CurvedPiece::Segment { center, radius, .. } => (
            Quadric::cylinder(center.extend(0.0), DVec3::Z, radius)?,
            center,
            DVec2::splat(radius),
        ),
        CurvedPiece::Ellipse { center, axes }
        | CurvedPiece::EllipticSegment { center, axes, .. } => elliptic_cylinder(center, axes)?,
    };
    let bounds = column(center - half, center + half);
    let disc = dag.bounded_leaf(quadric, source, bounds);
    match piece {
        CurvedPiece::Disc { .. } | CurvedPiece::Ellipse { .. } => Some(disc),
        CurvedPiece::Segment { chord, .. } | CurvedPiece::EllipticSegment { chord, .. } => {
            let side = dag.leaf(half_space(chord)?, source);
            let node = dag.intersection([disc.into(), side.into()], source);
            Some(dag.bounded(node, bounds))
        }
    }
}

/// The elliptic cylinder about z through the ellipse `center + axes[0] cos t + axes[1] sin t`,
/// `|E⁻¹ (p − center)|² − 1` for `E = [axes[0] axes[1]]`, with the ellipse's centre and
/// half-size; `None` when the axes are (nearly) parallel or not finite.
fn elliptic_cylinder(center: DVec2, axes: [DVec2; 2]) -> Option<(Quadric, DVec2, DVec2)> {
    let [a, b] = axes;
    let det = a.perp_dot(b);
    if !det.is_finite() || det.abs() <= 1e-12 * a.length() * b.length() {
        return None;
    }
    // The rows of E⁻¹; the quadric's matrix is their outer products' sum.
    let r0 = DVec2::new(b.y, -b.x) / det;
    let r1 = DVec2::new(-a.y, a.x) / det;
    let xx = r0.x * r0.x + r1.x * r1.x;
    let xy = r0.x * r0.y + r1.x * r1.y;
    let yy = r0.y * r0.y + r1.y * r1.y;
    let matrix = [[xx, xy, 0.0], [xy, yy, 0.0], [0.0, 0.0, 0.0]];
    let quadric = Quadric::from_matrix(center.extend(0.0), &matrix, DVec3::ZERO, -1.0)?;
    let half = DVec2::new(a.x.hypot(b.x), a.y.hypot(b.y));
    Some((quadric, center, half))
}
