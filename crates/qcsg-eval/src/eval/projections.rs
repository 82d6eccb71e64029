//! `projection` in the evaluator: its 3-D children, their section by z = 0 or their shadow as a
//! 2-D shape (see [`crate::section`]), and the error for shadows not computed exactly.

use qcsg_csg::{Edge, Source};
use qcsg_diag::{Diagnostic, FileId, Span};

use crate::codes;
use crate::planar::{PlanarError, rebuild};
use crate::primitives::ArgLookup;
use crate::primitives_2d::column;
use crate::section::{
    ShadowError, constant_value, ellipse_box, section_expression, shadow_expression,
};

use super::dimensions::Dim;
use super::{Evaluator, R};

impl<'a> Evaluator<'a> {
    /// `projection(cut)` of the children `edges`, for the call at `span` in `file`.
    pub(super) fn projection(
        &mut self,
        named: &dyn ArgLookup<'a>,
        edges: Vec<Edge>,
        file: FileId,
        span: Span,
    ) -> R<Option<Edge>> {
        let source = Source::new(file, span);
        let cut = named.get("cut").truthy();
        let (edges, _) = self.keep_dimension(edges, Dim::Three);
        let Some(solid) = self.group(edges, source) else {
            return Ok(None);
        };
        if self.dim(solid) == Dim::Empty {
            return Ok(Some(self.dag.empty(source).into()));
        }
        let limit = usize::try_from(self.options.max_instances).unwrap_or(usize::MAX);
        let expr = if cut {
            section_expression(&self.dag, solid, limit).map_err(|e| match e {
                PlanarError::TooLarge(n) => ShadowError::TooLarge(n),
                PlanarError::NotPlanar(at) => ShadowError::Inexact(at),
            })
        } else {
            shadow_expression(&self.dag, solid, limit, &self.mesh_faces)
        };
        let expr = match expr {
            Ok(expr) => expr,
            Err(ShadowError::TooLarge(limit)) => {
                return Err(self.error(
                    codes::INSTANCE_LIMIT,
                    format!(
                        "the children of this projection have more than {limit} parts once \
                         their transforms are applied"
                    ),
                    file,
                    span,
                ));
            }
            Err(ShadowError::Inexact(part)) if cut => {
                let diagnostic = Diagnostic::error(
                    codes::UNSUPPORTED,
                    "this part of the projection has a transform that cannot be applied",
                    file,
                    span,
                )
                .with_label(part.file, part.span, "this part");
                return Err(self.error_diagnostic(diagnostic));
            }
            Err(ShadowError::Inexact(part)) => {
                let diagnostic = Diagnostic::error(
                    qcsg_sema::codes::UNSUPPORTED_MODULE,
                    "`projection(cut = false)` of this part is not supported: its shadow is not \
                     known to be bounded by conics (qcsg projects boxes, balls, ellipsoids, \
                     vertical cylinders, meshes and z-invariant parts, their unions, and their \
                     cuts by z-invariant parts)",
                    file,
                    span,
                )
                .with_label(part.file, part.span, "the shadow of this part")
                .with_help("use cut = true or model the outline in 2-D");
                return Err(self.error_diagnostic(diagnostic));
            }
        };
        let from = self.dag.len();
        let shape = rebuild(
            &mut self.dag,
            &expr,
            |dag, conic, at| -> Result<Edge, ()> {
                Ok(match constant_value(conic) {
                    Some(j) if j <= 0.0 => {
                        let none = dag.empty(at);
                        dag.complement(none.into(), at).into()
                    }
                    Some(_) => dag.empty(at).into(),
                    None => match (conic.to_cylinder(), ellipse_box(conic)) {
                        (Some(q), Some((min, max))) => {
                            dag.bounded_leaf(q, at, column(min, max)).into()
                        }
                        (Some(q), None) => dag.leaf(q, at).into(),
                        (None, _) => dag.empty(at).into(),
                    },
                })
            },
            column,
        );
        let Ok(shape) = shape else {
            return Ok(Some(self.dag.empty(source).into()));
        };
        self.mark_planar(from, shape.child);
        Ok(Some(shape))
    }
}
