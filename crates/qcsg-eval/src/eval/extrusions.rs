//! `linear_extrude` in the evaluator: its arguments, its 2-D children, and the errors at the
//! argument that asks for what no quadric represents (see [`crate::extrude`]).

use glam::DVec2;
use qcsg_csg::{Edge, Source};
use qcsg_diag::{FileId, Span};
use qcsg_syntax::ast::Arg;

use crate::codes;
use crate::extrude::{linear_extrude_args, scaled_extrusion};
use crate::planar::{PlanarError, PlanarExpr, planar_expression};
use crate::primitives::ArgLookup;

use super::dimensions::Dim;
use super::{Evaluator, R};

/// The span of the argument for parameter `name` (by name, or at `position` among the
/// positional ones), else `fallback`.
pub(super) fn argument_span(
    args: &[Arg],
    name: &str,
    position: Option<usize>,
    fallback: Span,
) -> Span {
    if let Some(a) = args
        .iter()
        .rev()
        .find(|a| a.name.as_ref().is_some_and(|n| n.name == name))
    {
        return a.span;
    }
    position
        .and_then(|i| args.iter().filter(|a| a.name.is_none()).nth(i))
        .map_or(fallback, |a| a.span)
}

impl<'a> Evaluator<'a> {
    /// `linear_extrude(…)` of the children `edges`, for the call at `span` in `file`.
    pub(super) fn linear_extrude(
        &mut self,
        named: &dyn ArgLookup<'a>,
        args: &'a [Arg],
        edges: Vec<Edge>,
        file: FileId,
        span: Span,
    ) -> R<Option<Edge>> {
        let source = Source::new(file, span);
        let params = linear_extrude_args(named).map_err(|(param, message)| {
            let at = argument_span(args, param, (param == "height").then_some(0), span);
            self.error(codes::MODULE_ARGUMENT, message, file, at)
        })?;
        if params.twist != 0.0 {
            let at = argument_span(args, "twist", None, span);
            return Err(self.error_with_help(
                qcsg_sema::codes::UNSUPPORTED_MODULE,
                "`linear_extrude` with `twist` is not supported: a twisted edge sweeps a \
                 helicoid, which is no quadric surface",
                "leave out `twist`; a twisted prism can be approximated by a stack of short \
                 extrusions, each turned a little further with `rotate`",
                file,
                at,
            ));
        }
        let (edges, _) = self.keep_dimension(edges, Dim::Two);
        let Some(shape) = self.group(edges, source) else {
            return Ok(None);
        };
        if !(params.height > 0.0 && params.height.is_finite()) {
            self.warn(
                codes::EMPTY_PRIMITIVE,
                format!(
                    "linear_extrude with height {} is empty",
                    crate::value::format_number(params.height)
                ),
                file,
                span,
            );
            return Ok(Some(self.dag.empty(source).into()));
        }
        let (bottom, top) = params.z_range();
        if params.scale == DVec2::ONE {
            return Ok(Some(self.z_slab_cut(shape, bottom, top, source)));
        }
        let b = self.edge_box(shape);
        let (min, max) = (b.min.truncate(), b.max.truncate());
        let shape_box = (min.is_finite() && max.is_finite()).then_some((min, max));
        let expr = self.planar_child_shape(shape, "linear_extrude", file, span)?;
        match scaled_extrusion(
            &mut self.dag,
            &expr,
            shape_box,
            bottom,
            top,
            params.scale,
            source,
        ) {
            Ok(edge) => {
                self.mark_extruded(edge.child);
                Ok(Some(edge))
            }
            Err(e) => {
                let at = argument_span(args, "scale", None, span);
                let diagnostic = qcsg_diag::Diagnostic::error(
                    qcsg_sema::codes::UNSUPPORTED_MODULE,
                    "`linear_extrude` with different scales in x and y is not supported for a \
                     circle or an ellipse: its edge, scaled unevenly, sweeps a surface of degree \
                     4, which is no quadric",
                    file,
                    at,
                )
                .with_label(e.curved.file, e.curved.span, "this shape has a curved edge")
                .with_help(
                    "give one scale for both axes (a circle then sweeps a cone), or make the \
                     curved part from straight edges",
                );
                Err(self.error_diagnostic(diagnostic))
            }
        }
    }
}

impl Evaluator<'_> {
    /// The 2-D expression of `shape`, the children of the 2-D operation `op` (`offset`,
    /// `linear_extrude`, `rotate_extrude`) at `span`: too many parts is the instance limit, a
    /// part that is not 2-D an error.
    pub(super) fn planar_child_shape(
        &mut self,
        shape: Edge,
        op: &str,
        file: FileId,
        span: Span,
    ) -> R<PlanarExpr> {
        let limit = usize::try_from(self.options.max_instances).unwrap_or(usize::MAX);
        let expr = planar_expression(&self.dag, shape, limit);
        expr.map_err(|e| match e {
            PlanarError::TooLarge(limit) => self.error(
                codes::INSTANCE_LIMIT,
                format!(
                    "the shape of this {op} has more than {limit} parts once its transforms \
                     are applied"
                ),
                file,
                span,
            ),
            PlanarError::NotPlanar(_) => self.error(
                codes::UNSUPPORTED,
                format!("the children of this {op} are not a 2-D shape"),
                file,
                span,
            ),
        })
    }
}
