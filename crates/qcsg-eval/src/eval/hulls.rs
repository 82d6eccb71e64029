//! `hull()` and `minkowski()` in the evaluator: their children, 3-D ([`crate::hull`],
//! [`crate::minkowski`]) or 2-D ([`crate::hull_2d`]), and the errors for results that are not
//! bounded by quadrics.

use glam::DMat4;
use qcsg_csg::{Edge, Source};
use qcsg_diag::{Diagnostic, FileId, Span};

use crate::codes;
use crate::hull::{
    Collector, Cylinder, HullBuilder, HullLimits, HullRefusal, Piece, common_radius,
};
use crate::hull_2d::{self, Collector2};
use crate::hull_balls;
use crate::hull_discs;
use crate::hull_frusta::{self, AxialDisc};
use crate::minkowski;
use crate::planar::{PlanarError, planar_expression};

use super::dimensions::Dim;
use super::{Evaluator, R};

impl<'a> Evaluator<'a> {
    /// `hull()` of the children `edges`, for the call at `span` in `file`.
    pub(super) fn hull(&mut self, edges: Vec<Edge>, file: FileId, span: Span) -> R<Option<Edge>> {
        let source = Source::new(file, span);
        let dims: Vec<Dim> = edges.iter().map(|e| self.dim(*e)).collect();
        let planar = dims.contains(&Dim::Two) && !dims.contains(&Dim::Three);
        let (edges, _) = self.keep_dimension(edges, if planar { Dim::Two } else { Dim::Three });
        if edges.is_empty() {
            return Ok(None);
        }
        let from = self.dag.len();
        let built = if planar {
            self.hull_2d(edges, source)?
        } else {
            self.hull_3d(&edges, source)
        };
        match built {
            Ok(edge) => {
                if planar {
                    self.mark_planar(from, edge.child);
                }
                Ok(Some(edge))
            }
            Err(refusal) => Err(self.hull_refused("hull", refusal, planar, file, span)),
        }
    }

    /// `minkowski()` of the children `edges`, for the call at `span` in `file`.
    pub(super) fn minkowski(
        &mut self,
        edges: Vec<Edge>,
        file: FileId,
        span: Span,
    ) -> R<Option<Edge>> {
        let source = Source::new(file, span);
        let dims: Vec<Dim> = edges.iter().map(|e| self.dim(*e)).collect();
        if dims.contains(&Dim::Two) && !dims.contains(&Dim::Three) {
            let (edges, _) = self.keep_dimension(edges, Dim::Two);
            if edges.is_empty() {
                return Ok(None);
            }
            let from = self.dag.len();
            return match self.minkowski_2d(&edges, source)? {
                Ok(edge) => {
                    self.mark_planar(from, edge.child);
                    Ok(Some(edge))
                }
                Err(refusal) => Err(self.hull_refused("minkowski", refusal, true, file, span)),
            };
        }
        let (edges, _) = self.keep_dimension(edges, Dim::Three);
        if edges.is_empty() {
            return Ok(None);
        }
        match self.minkowski_3d(&edges, source) {
            Ok(edge) => Ok(Some(edge)),
            Err(refusal) => Err(self.hull_refused("minkowski", refusal, false, file, span)),
        }
    }

    /// The size limits of hulls and sums.
    fn hull_limits(&self) -> HullLimits {
        HullLimits {
            points: self.options.max_hull_points,
            planes: self.options.max_part_planes,
            parts: self.options.max_minkowski_parts,
        }
    }

    fn minkowski_3d(&mut self, edges: &[Edge], source: Source) -> Result<Edge, HullRefusal> {
        let limits = self.hull_limits();
        let mut total: Option<Vec<minkowski::Part>> = None;
        for e in edges {
            let mut collector = Collector::new(&self.dag, limits.planes);
            collector.add(*e, &DMat4::IDENTITY)?;
            let parts = minkowski::parts_of(&collector.pieces, &collector.parts, &limits)?;
            total = Some(match total {
                None => parts,
                Some(sum) => minkowski::sum(&sum, &parts, &limits)?,
            });
        }
        minkowski::build(
            &mut self.dag,
            &total.unwrap_or_default(),
            source,
            limits.points,
        )
    }

    fn hull_3d(&mut self, edges: &[Edge], source: Source) -> Result<Edge, HullRefusal> {
        let limits = self.hull_limits();
        let mut collector = Collector::new(&self.dag, limits.planes);
        for e in edges {
            collector.add(*e, &DMat4::IDENTITY)?;
        }
        let pieces = collector.pieces;
        let cylinders: Vec<Cylinder> = pieces
            .iter()
            .filter_map(|p| match p {
                Piece::Cylinder(c) => Some(*c),
                _ => None,
            })
            .collect();
        if cylinders.is_empty() {
            let builder = HullBuilder {
                source,
                max_points: limits.points,
            };
            return match common_radius(&pieces) {
                Ok(r) => builder.build(&mut self.dag, &pieces, r),
                Err(HullRefusal::UnequalRadii(_)) => {
                    hull_balls::build(&mut self.dag, &builder, &pieces)
                }
                Err(refusal) => Err(refusal),
            };
        }
        if let Some(at) = pieces.iter().find_map(|p| match *p {
            Piece::Ball(_, _, s) => Some(s),
            Piece::Point(..) | Piece::Cylinder(_) => None,
        }) {
            return Err(HullRefusal::Pair(
                [at, cylinders[0].source],
                "a ball together with a cylinder or cone (the hull of a ball and a disc in \
                 general has a developable surface that is not quadric)",
                "hull the cylinders alone and unite the result with the other parts, where that \
                 is the same solid",
            ));
        }
        let first = cylinders[0];
        if let Some(c) = cylinders
            .iter()
            .find(|c| c.axis.cross(first.axis).length() > 1e-9)
        {
            return Err(HullRefusal::Pair(
                [first.source, c.source],
                "two cylinders whose axes are not parallel (the hull has ruled surfaces that \
                 are not quadric)",
                "turn the cylinders parallel, or unite the hulls of parallel groups where that is \
                 the same solid",
            ));
        }
        let prism = cylinders.len() == pieces.len()
            && cylinders.iter().all(|c| {
                let tol = 1e-9 * (c.high - c.low + c.radius);
                c.radius == c.radius_high
                    && (c.low - first.low).abs() <= tol
                    && (c.high - first.high).abs() <= tol
            });
        if prism {
            // Cylinders between the same two planes: their discs' hull extruded.
            return hull_2d::build_prism(&mut self.dag, &cylinders, source, limits.points);
        }
        let builder = HullBuilder {
            source,
            max_points: limits.points,
        };
        let discs: Vec<AxialDisc> = pieces
            .iter()
            .flat_map(|p| match *p {
                Piece::Point(centre, _) => vec![AxialDisc {
                    centre,
                    radius: 0.0,
                }],
                Piece::Cylinder(c) => {
                    let at = |h: f64| c.centre + (h - c.axis.dot(c.centre)) * c.axis;
                    vec![
                        AxialDisc {
                            centre: at(c.low),
                            radius: c.radius,
                        },
                        AxialDisc {
                            centre: at(c.high),
                            radius: c.radius_high,
                        },
                    ]
                }
                Piece::Ball(..) => Vec::new(),
            })
            .collect();
        hull_frusta::build(&mut self.dag, &builder, &discs, first.axis)
    }

    fn minkowski_2d(&mut self, edges: &[Edge], source: Source) -> R<Result<Edge, HullRefusal>> {
        let limit = usize::try_from(self.options.max_instances).unwrap_or(usize::MAX);
        let limits = self.hull_limits();
        let mut total: Option<Vec<hull_2d::Part2>> = None;
        for e in edges {
            let expr = match planar_expression(&self.dag, *e, limit) {
                Ok(expr) => expr,
                Err(PlanarError::TooLarge(limit)) => {
                    return Err(self.error(
                        codes::INSTANCE_LIMIT,
                        format!(
                            "the children of this minkowski have more than {limit} parts once \
                             their transforms are applied"
                        ),
                        source.file,
                        source.span,
                    ));
                }
                Err(PlanarError::NotPlanar(at)) => {
                    return Ok(Err(HullRefusal::Part(at, "a part that is not a 2-D shape")));
                }
            };
            let mut collector = Collector2::new(&expr);
            if let Err(refusal) = collector.add(expr.root) {
                return Ok(Err(refusal));
            }
            let parts = hull_2d::parts_of(&collector.pieces, &collector.parts);
            total = Some(match total {
                None => parts,
                Some(sum) => match hull_2d::sum(&sum, &parts, &limits) {
                    Ok(sum) => sum,
                    Err(refusal) => return Ok(Err(refusal)),
                },
            });
        }
        Ok(hull_2d::build_parts(
            &mut self.dag,
            &total.unwrap_or_default(),
            source,
            limits.points,
        ))
    }

    fn hull_2d(&mut self, edges: Vec<Edge>, source: Source) -> R<Result<Edge, HullRefusal>> {
        let Some(shape) = self.group(edges, source) else {
            return Ok(Ok(self.dag.empty(source).into()));
        };
        let limit = usize::try_from(self.options.max_instances).unwrap_or(usize::MAX);
        let expr = match planar_expression(&self.dag, shape, limit) {
            Ok(expr) => expr,
            Err(PlanarError::TooLarge(limit)) => {
                return Err(self.error(
                    codes::INSTANCE_LIMIT,
                    format!(
                        "the children of this hull have more than {limit} parts once their \
                         transforms are applied"
                    ),
                    source.file,
                    source.span,
                ));
            }
            Err(PlanarError::NotPlanar(at)) => {
                return Ok(Err(HullRefusal::Part(at, "a part that is not a 2-D shape")));
            }
        };
        let mut collector = Collector2::new(&expr);
        if let Err(refusal) = collector.add(expr.root) {
            return Ok(Err(refusal));
        }
        let pieces = collector.pieces;
        let max_points = self.options.max_hull_points;
        Ok(match hull_2d::common_radius(&pieces) {
            Ok(r) => hull_2d::build(&mut self.dag, &pieces, r, source, max_points),
            Err(HullRefusal::UnequalRadii(_)) => {
                hull_discs::build(&mut self.dag, &pieces, source, max_points)
            }
            Err(refusal) => Err(refusal),
        })
    }

    fn hull_refused(
        &mut self,
        op: &str,
        refusal: HullRefusal,
        planar: bool,
        file: FileId,
        span: Span,
    ) -> super::Stop {
        let (ball, point) = if planar {
            ("circle", "point")
        } else {
            ("ball", "point")
        };
        let diagnostic = match refusal {
            HullRefusal::Part(at, what) => Diagnostic::error(
                qcsg_sema::codes::UNSUPPORTED_MODULE,
                if op == "hull" {
                    format!(
                        "`hull` of {what} is not supported: qcsg computes hulls of convex \
                         polytopes, {ball}s and parallel cylinders and cones, whose hulls are \
                         bounded by quadrics"
                    )
                } else {
                    format!(
                        "`{op}` of {what} is not supported: qcsg computes Minkowski sums of \
                         convex polytopes with balls or with parallel cylinders and cones, which \
                         are bounded by quadrics"
                    )
                },
                file,
                span,
            )
            .with_label(at.file, at.span, "this part")
            .with_help(if op != "hull" {
                "use unions of cubes, polyhedra, spheres, cylinders and cones as the children; \
                 round a box's edges with the sum of the box and a sphere or a cylinder"
            } else if planar {
                "use squares, polygons and circles as the hull's children"
            } else {
                "use cubes, polyhedra, spheres and parallel cylinders or cones as the hull's \
                 children; an ellipsoid's hull can be modelled with intersections and unions"
            }),
            HullRefusal::UnequalRadii([(s1, r1), (s2, r2)]) => {
                let name = |r: f64| {
                    if r == 0.0 {
                        format!("a {point} (radius 0)")
                    } else {
                        format!("a {ball} of radius {r}")
                    }
                };
                Diagnostic::error(
                    qcsg_sema::codes::UNSUPPORTED_MODULE,
                    format!(
                        "`hull` of {ball}s of different radii is not supported: it is bounded \
                         by cones tangent to pairs of {ball}s, which qcsg does not build yet"
                    ),
                    file,
                    span,
                )
                .with_label(s1.file, s1.span, name(r1))
                .with_label(s2.file, s2.span, name(r2))
                .with_help(format!(
                    "give every {ball} the same radius (a corner of a box is a {ball} of the \
                     box's rounding radius), or write the tapered part explicitly"
                ))
            }
            HullRefusal::Pair([a, b], what, help) => Diagnostic::error(
                qcsg_sema::codes::UNSUPPORTED_MODULE,
                format!("`{op}` of {what} is not supported: the result is not bounded by quadrics"),
                file,
                span,
            )
            .with_label(a.file, a.span, "this part")
            .with_label(b.file, b.span, "with this part")
            .with_help(help),
            HullRefusal::Limit(code, message) => {
                return self.error(code, format!("`{op}` is too large: {message}"), file, span);
            }
            HullRefusal::Unrepresentable(message) => Diagnostic::error(
                qcsg_sema::codes::UNSUPPORTED_MODULE,
                format!("`{op}` is not supported here: {message}"),
                file,
                span,
            )
            .with_help("bring the parts nearer the origin or to a size qcsg can represent"),
        };
        self.error_diagnostic(diagnostic)
    }
}
