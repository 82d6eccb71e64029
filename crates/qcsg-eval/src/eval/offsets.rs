//! `offset(r | delta, chamfer)` in the evaluator: its arguments, its 2-D children and the error
//! for what has no exact offset here (see [`crate::offset`]).

use qcsg_csg::{Edge, Source};
use qcsg_diag::{Diagnostic, FileId, Span};
use qcsg_syntax::ast::Arg;

use crate::codes;
use crate::offset::{Join, Offsetter};
use crate::primitives::ArgLookup;
use crate::value::Value;

use super::dimensions::Dim;
use super::extrusions::argument_span;
use super::{Evaluator, R};

/// OpenSCAD 2021.01's reading of the arguments: `r` when it is a number (rounded), else `delta`
/// (default 1), mitred or, with `chamfer`, chamfered. The parameter at fault on error.
fn offset_args(named: &dyn ArgLookup<'_>) -> Result<(f64, Join), (&'static str, String)> {
    let (name, value, join) = match named.get("r") {
        Value::Number(r) => ("r", r, Join::Round),
        _ => {
            let join = if named.get("chamfer").truthy() {
                Join::Chamfer
            } else {
                Join::Miter
            };
            match named.get("delta") {
                Value::Number(d) => ("delta", d, join),
                Value::Undef => ("delta", 1.0, join),
                other => {
                    return Err((
                        "delta",
                        format!("offset(delta) needs a number, got {}", other.type_name()),
                    ));
                }
            }
        }
    };
    if !value.is_finite() {
        return Err((name, format!("offset({name}) must be finite")));
    }
    Ok((value, join))
}

impl<'a> Evaluator<'a> {
    /// `offset(…)` of the children `edges`, for the call at `span` in `file`.
    pub(super) fn offset(
        &mut self,
        named: &dyn ArgLookup<'a>,
        args: &'a [Arg],
        edges: Vec<Edge>,
        file: FileId,
        span: Span,
    ) -> R<Option<Edge>> {
        let source = Source::new(file, span);
        let (amount, join) = offset_args(named).map_err(|(param, message)| {
            let at = argument_span(args, param, (param == "r").then_some(0), span);
            self.error(codes::MODULE_ARGUMENT, message, file, at)
        })?;
        let (edges, _) = self.keep_dimension(edges, Dim::Two);
        let Some(shape) = self.group(edges, source) else {
            return Ok(None);
        };
        if amount == 0.0 || self.dim(shape) == Dim::Empty {
            return Ok(Some(shape));
        }
        let expr = self.planar_child_shape(shape, "offset", file, span)?;
        let from = self.dag.len();
        let offsetter = Offsetter {
            expr: &expr,
            amount,
            join,
            source,
        };
        match offsetter.build(&mut self.dag) {
            Ok(edge) => {
                self.mark_planar(from, edge.child);
                Ok(Some(edge))
            }
            Err(refusal) => {
                let direction = if amount > 0.0 { "growing" } else { "shrinking" };
                let diagnostic = Diagnostic::error(
                    qcsg_sema::codes::UNSUPPORTED_MODULE,
                    format!(
                        "`offset` {direction} {} is not supported: its outline is not known \
                         exactly as edges and circular arcs",
                        refusal.what
                    ),
                    file,
                    span,
                )
                .with_label(refusal.source.file, refusal.source.span, "this part")
                .with_help(
                    "growing works on unions of convex polygons and circles, shrinking on \
                     intersections of edges and circles; offset the parts before combining them, \
                     or model the offset outline directly",
                );
                Err(self.error_diagnostic(diagnostic))
            }
        }
    }
}
