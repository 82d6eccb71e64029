//! `rotate_extrude` in the evaluator: its `angle`, its 2-D children, the side of the axis they
//! lie on, and the errors for outlines that sweep no quadric (see [`crate::revolve`]).

use qcsg_csg::{Edge, Source};
use qcsg_diag::{Diagnostic, FileId, Span};
use qcsg_syntax::ast::Arg;

use crate::codes;
use crate::planar::rebuild;
use crate::primitives::ArgLookup;
use crate::revolve::{mirror_x, revolve_conic, swept_box, wedge};
use crate::value::{Value, format_number};

use super::dimensions::Dim;
use super::extrusions::argument_span;
use super::{Evaluator, R};

/// How far, relative to the shape's extent, its box may reach across the axis and still count as
/// on one side (boxes are padded beyond the rounding of their corners).
const AXIS_SLACK: f64 = 1e-9;

/// OpenSCAD 2021.01's reading of `angle`: 360 when missing, and also when above 360 or at or
/// below −360.
fn sweep_angle(value: &Value<'_>) -> Result<f64, String> {
    let angle = match value {
        Value::Undef => return Ok(360.0),
        Value::Number(a) if a.is_finite() => *a,
        Value::Number(_) => return Err("rotate_extrude(angle) must be finite".into()),
        other => {
            return Err(format!(
                "rotate_extrude(angle) needs a number, got {}",
                other.type_name()
            ));
        }
    };
    Ok(if angle <= -360.0 || angle > 360.0 {
        360.0
    } else {
        angle
    })
}

impl<'a> Evaluator<'a> {
    /// `rotate_extrude(angle)` of the children `edges`, for the call at `span` in `file`.
    pub(super) fn rotate_extrude(
        &mut self,
        named: &dyn ArgLookup<'a>,
        args: &'a [Arg],
        edges: Vec<Edge>,
        file: FileId,
        span: Span,
    ) -> R<Option<Edge>> {
        let source = Source::new(file, span);
        let angle = sweep_angle(&named.get("angle")).map_err(|message| {
            let at = argument_span(args, "angle", None, span);
            self.error(codes::MODULE_ARGUMENT, message, file, at)
        })?;
        let (edges, _) = self.keep_dimension(edges, Dim::Two);
        let Some(shape) = self.group(edges, source) else {
            return Ok(None);
        };
        if angle == 0.0 {
            self.warn(
                codes::EMPTY_PRIMITIVE,
                "rotate_extrude with angle 0 is empty",
                file,
                span,
            );
            return Ok(Some(self.dag.empty(source).into()));
        }
        if self.dim(shape) == Dim::Empty {
            return Ok(Some(self.dag.empty(source).into()));
        }
        let b = self.edge_box(shape);
        let (min, max) = (b.min.truncate(), b.max.truncate());
        // OpenSCAD sweeps a shape at x ≤ 0 as its mirror image, starting from −x. Boxes are
        // padded for rounding, so a shape touching the axis may have a box a hair across it.
        let slack = AXIS_SLACK * (min.abs().max_element() + max.abs().max_element());
        let mirrored = if min.x >= -slack {
            false
        } else if max.x <= slack {
            true
        } else {
            return Err(self.error_with_help(
                codes::BOTH_SIDES_OF_AXIS,
                format!(
                    "the shape of this rotate_extrude reaches both sides of the axis (x from {} \
                     to {}): all its points must have the same sign of x, as OpenSCAD requires",
                    format_number(min.x),
                    format_number(max.x)
                ),
                "cut the shape to one side, e.g. `intersection() { shape(); translate([0, -R]) \
                 square(2 * R); }`",
                file,
                span,
            ));
        };
        let expr = self.planar_child_shape(shape, "rotate_extrude", file, span)?;
        let solid = rebuild(
            &mut self.dag,
            &expr,
            |dag, conic, leaf_source| {
                let conic = if mirrored {
                    conic.transformed(&mirror_x()).ok_or(leaf_source)?
                } else {
                    *conic
                };
                revolve_conic(dag, &conic, leaf_source).map_err(|_| leaf_source)
            },
            swept_box,
        );
        let solid = match solid {
            Ok(solid) => solid,
            Err(curve) => {
                let diagnostic = Diagnostic::error(
                    qcsg_sema::codes::UNSUPPORTED_MODULE,
                    "`rotate_extrude` of a circle or ellipse off the axis is not supported: it \
                     sweeps a torus (a surface of degree 4), which is no quadric",
                    curve.file,
                    curve.span,
                )
                .with_label(file, span, "swept about the z axis here")
                .with_help(
                    "straight edges and circles or ellipses centred on the axis (x = 0) sweep \
                     quadrics: cones, cylinders, planes, spheres and ellipsoids; a ring of \
                     rectangular section is a cylinder shell",
                );
                return Err(self.error_diagnostic(diagnostic));
            }
        };
        let bounds = swept_box(min, max);
        let node = if angle == 360.0 {
            self.dag.bounded(solid.child, bounds)
        } else {
            // A positive angle turns counter-clockwise from +x (from −x for a mirrored shape),
            // a negative one clockwise.
            let (start, sweep) = if angle > 0.0 {
                (0.0, angle)
            } else {
                (angle, -angle)
            };
            let start = if mirrored { start + 180.0 } else { start };
            let wedge = wedge(&mut self.dag, start, sweep, source);
            let cut = self.dag.intersection([solid, wedge], source);
            self.dag.bounded(cut, bounds)
        };
        self.mark_extruded(node);
        Ok(Some(node.into()))
    }
}
