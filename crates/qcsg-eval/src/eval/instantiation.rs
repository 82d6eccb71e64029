//! Module instantiation: a user module, `echo`, `assert`, `children`, `intersection_for`, or a
//! built-in module (primitives, booleans, transforms, `color`) with its arguments placed on its
//! parameters; meshes (`polyhedron`, `import`) are built in [`super::meshes`].

use glam::DMat4;
use qcsg_csg::{Edge, Source};
use qcsg_diag::{FileId, Span};
use qcsg_syntax::ast::{Arg, Stmt};

use crate::env::Frame;
use crate::primitives::{self, ArgLookup, Built};
use crate::value::Value;
use crate::{codes, color, primitives_2d, transforms};

use super::dimensions::Dim;
use super::{ArgValue, Cx, Evaluator, R};

/// The arguments of a built-in module call by parameter name.
#[derive(Default)]
pub(super) struct BuiltinArgs<'a> {
    values: Vec<(&'a str, Value<'a>)>,
}

impl<'a> Evaluator<'a> {
    #[allow(clippy::too_many_arguments)]
    pub(super) fn instantiate(
        &mut self,
        name: &'a str,
        name_span: Span,
        args: &'a [Arg],
        child: Option<&'a Stmt>,
        span: Span,
        cx: &Cx<'a>,
    ) -> R<Option<Edge>> {
        if let Some(def) = cx.frame.lookup_module(name) {
            return self.call_module(name, def, args, child, span, cx);
        }
        let source = Source::new(cx.file, span);
        match name {
            "echo" => {
                let values = self.eval_args(args, cx)?;
                self.echo(&values, cx.file, span);
                let edges = self.eval_body(child, cx)?;
                return Ok(self.group(edges, source));
            }
            "assert" => {
                let values = self.eval_args(args, cx)?;
                self.assert(&values, args, cx.file, span)?;
                let edges = self.eval_body(child, cx)?;
                return Ok(self.group(edges, source));
            }
            "children" => return self.children(args, span, cx),
            "child" => return self.child(args, span, cx),
            "assign" => return self.assign_module(args, child, span, cx),
            "intersection_for" => return self.intersection_for(args, child, span, cx),
            _ => {}
        }
        let Some(builtin) = qcsg_sema::builtins::module(name) else {
            if let Some(unsupported) = qcsg_sema::builtins::unsupported_module(name) {
                return Err(self.error(
                    codes::UNSUPPORTED,
                    format!("`{name}` is not supported: {}", unsupported.reason),
                    cx.file,
                    name_span,
                ));
            }
            let code = if cx.frame.lookup_function(name).is_some() {
                codes::WRONG_KIND
            } else {
                codes::UNDEFINED_NAME
            };
            return Err(self.error(
                code,
                format!("no module named `{name}`"),
                cx.file,
                name_span,
            ));
        };
        let values = self.eval_args(args, cx)?;
        let named = self.place_builtin_args(builtin.params, &values, args, cx.file)?;
        // `$`-arguments set special variables for the subtree.
        let child_cx = if values
            .iter()
            .any(|a| a.name.is_some_and(|n| n.starts_with('$')))
        {
            let frame = Frame::nested(&cx.frame);
            for a in &values {
                if let Some(n) = a.name.filter(|n| n.starts_with('$')) {
                    frame.set(n, a.value.clone());
                }
            }
            Cx {
                frame,
                file: cx.file,
            }
        } else {
            cx.clone()
        };
        if name == "offset" {
            let edges = self.eval_body(child, &child_cx)?;
            return self.offset(&named, args, edges, cx.file, span);
        }
        if name == "minkowski" {
            let edges = self.eval_body(child, &child_cx)?;
            return self.minkowski(edges, cx.file, span);
        }
        if name == "hull" {
            let edges = self.eval_body(child, &child_cx)?;
            return self.hull(edges, cx.file, span);
        }
        if name == "projection" {
            let edges = self.eval_body(child, &child_cx)?;
            return self.projection(&named, edges, cx.file, span);
        }
        if name == "rotate_extrude" {
            let edges =
                self.extrusion_children(&named, args, builtin.params, child, &child_cx, span)?;
            return self.rotate_extrude(&named, args, edges, cx.file, span);
        }
        if name == "dxf_linear_extrude" || name == "dxf_rotate_extrude" {
            // OpenSCAD's deprecated extrusions of a drawing: the `import` of `file`, `layer`,
            // `origin` and `scale` (OpenSCAD also scales a linear extrusion's top by `scale`).
            let params = builtin.params;
            let edges = self
                .import(&named, args, params, cx.file, span)?
                .into_iter()
                .collect();
            return if name == "dxf_linear_extrude" {
                self.linear_extrude(&named, args, edges, cx.file, span)
            } else {
                self.rotate_extrude(&named, args, edges, cx.file, span)
            };
        }
        if name == "linear_extrude" {
            let edges =
                self.extrusion_children(&named, args, builtin.params, child, &child_cx, span)?;
            return self.linear_extrude(&named, args, edges, cx.file, span);
        }
        match builtin.kind {
            qcsg_sema::builtins::ModuleKind::Primitive => {
                self.instances += 1;
                if self.instances > self.options.max_instances {
                    return Err(self.error(
                        codes::INSTANCE_LIMIT,
                        format!(
                            "more than {} primitive instances",
                            self.options.max_instances
                        ),
                        cx.file,
                        span,
                    ));
                }
                let from = self.dag.len();
                match name {
                    "polygon" => return self.polygon(&named, from, cx.file, span),
                    "text" => {
                        return self.text(&named, args, builtin.params, from, cx.file, span);
                    }
                    "polyhedron" => {
                        return self.polyhedron(&named, args, builtin.params, cx.file, span);
                    }
                    "import" | "import_stl" | "import_off" | "import_dxf" => {
                        return self.import(&named, args, builtin.params, cx.file, span);
                    }
                    "surface" => {
                        return self.surface(&named, args, builtin.params, cx.file, span);
                    }
                    _ => {}
                }
                let built = match name {
                    "square" => primitives_2d::square(&mut self.dag, &named, source),
                    "circle" => primitives_2d::circle(&mut self.dag, &named, source),
                    _ => primitives::build(&mut self.dag, name, &named, source),
                };
                if let Ok(Built::Node(node)) = &built
                    && primitives_2d::is_2d_primitive(name)
                {
                    self.mark_planar(from, *node);
                }
                match built {
                    Ok(Built::Node(node)) => Ok(Some(node.into())),
                    Ok(Built::Empty(reason)) => {
                        self.warn(codes::EMPTY_PRIMITIVE, reason, cx.file, span);
                        Ok(Some(self.dag.empty(source).into()))
                    }
                    Err(message) => Err(self.error(codes::MODULE_ARGUMENT, message, cx.file, span)),
                }
            }
            _ if name == "complement" => {
                let edges = self.eval_body(child, &child_cx)?;
                let inner = match self.group(edges, source) {
                    Some(e) => e,
                    None => self.dag.empty(source).into(),
                };
                Ok(Some(self.dag.complement(inner, source).into()))
            }
            qcsg_sema::builtins::ModuleKind::Boolean => {
                let edges = self.eval_body(child, &child_cx)?;
                let (edges, _) = self.same_dimension(edges);
                if edges.is_empty() {
                    return Ok(None);
                }
                Ok(Some(match name {
                    "intersection" => self.dag.intersection(edges, source).into(),
                    "difference" => self.dag.difference(edges, source).into(),
                    _ => match self.group(edges, source) {
                        Some(e) => e,
                        None => return Ok(None),
                    },
                }))
            }
            qcsg_sema::builtins::ModuleKind::Transform => {
                let edges = self.eval_body(child, &child_cx)?;
                let Some(inner) = self.group(edges, source) else {
                    return Ok(None);
                };
                let planar = self.dim(inner) == Dim::Two;
                let mut warnings = Vec::new();
                let matrix = match name {
                    "translate" => transforms::translate(&named.get("v")),
                    "rotate" => transforms::rotate(&named.get("a"), &named.get("v"), &mut warnings),
                    "scale" => transforms::scale(&named.get("v")),
                    "mirror" => transforms::mirror(&named.get("v")),
                    "multmatrix" => transforms::multmatrix(&named.get("m")),
                    _ if planar => {
                        // The xy box of a 2-D shape; z stays out of the scale.
                        let b = self.edge_box(inner);
                        let bounds = (b.min.truncate().is_finite() && b.max.truncate().is_finite())
                            .then(|| (b.min.truncate().extend(0.0), b.max.truncate().extend(1.0)));
                        let given = named.get("newsize");
                        let newsize = match &given {
                            Value::Vector(v) if v.len() > 2 => {
                                Value::vector(v.iter().take(2).cloned().collect())
                            }
                            Value::Number(n) => Value::vector(vec![Value::Number(*n); 2]),
                            _ => given.clone(),
                        };
                        transforms::resize(&newsize, &named.get("auto"), bounds, &mut warnings)
                    }
                    _ => {
                        let bounds = transforms::bounds_of(&self.dag, inner);
                        transforms::resize(
                            &named.get("newsize"),
                            &named.get("auto"),
                            bounds,
                            &mut warnings,
                        )
                    }
                };
                for w in warnings {
                    let code = if name == "resize" {
                        codes::RESIZE_IGNORED
                    } else {
                        codes::IGNORED_ARGUMENT
                    };
                    self.warn(code, w, cx.file, span);
                }
                let matrix =
                    matrix.map_err(|m| self.error(codes::MODULE_ARGUMENT, m, cx.file, span))?;
                // OpenSCAD applies the xy part of the matrix to a 2-D shape.
                let matrix = if planar {
                    crate::planar::planar_matrix(&matrix)
                } else {
                    matrix
                };
                self.apply_transform(inner, &matrix, cx.file, span)
            }
            _ => {
                let edges = self.eval_body(child, &child_cx)?;
                let Some(inner) = self.group(edges, source) else {
                    return Ok(None);
                };
                if name != "color" {
                    return Ok(Some(inner));
                }
                match self.color_of(&named, cx.file, span)? {
                    Some(rgba) => match self.dag.color(inner, rgba, source) {
                        Ok(node) => Ok(Some(node.into())),
                        Err(e) => {
                            self.warn(codes::UNKNOWN_COLOR, e.to_string(), cx.file, span);
                            Ok(Some(inner))
                        }
                    },
                    None => Ok(Some(inner)),
                }
            }
        }
    }

    /// `polygon(points, paths)`: its cells' union, marked 2-D; an empty region is an empty shape.
    fn polygon(
        &mut self,
        named: &BuiltinArgs<'a>,
        from: usize,
        file: FileId,
        span: Span,
    ) -> R<Option<Edge>> {
        let source = Source::new(file, span);
        let max_points = usize::try_from(self.options.max_vector_len).unwrap_or(usize::MAX);
        let built = crate::polygon::polygon(&mut self.dag, named, max_points, source);
        match built {
            Ok(built) => {
                for w in built.warnings {
                    self.warn(codes::POLYGON_OUTLINE, w, file, span);
                }
                let node = match built.node {
                    Some(node) => node,
                    None => self.dag.empty(source),
                };
                self.mark_planar(from, node);
                Ok(Some(node.into()))
            }
            Err(crate::polygon::PolygonFailure::Argument(m)) => {
                Err(self.error(codes::MODULE_ARGUMENT, m, file, span))
            }
            Err(crate::polygon::PolygonFailure::TooLarge(m)) => {
                Err(self.error(codes::VECTOR_LIMIT, m, file, span))
            }
        }
    }

    /// `text(…)`: the glyphs as a 2-D shape, with warnings and errors at the argument they are
    /// about.
    fn text(
        &mut self,
        named: &BuiltinArgs<'a>,
        args: &'a [Arg],
        params: &[qcsg_sema::builtins::BuiltinParam],
        from: usize,
        file: FileId,
        span: Span,
    ) -> R<Option<Edge>> {
        let source = Source::new(file, span);
        let max_glyphs = usize::try_from(self.options.max_vector_len).unwrap_or(usize::MAX);
        let at = |name: &str| super::meshes::arg_span(params, args, name).unwrap_or(span);
        match crate::glyphs::text(&mut self.dag, named, max_glyphs, &self.fonts, source) {
            Ok(built) => {
                for w in built.warnings {
                    let code = match w.kind {
                        crate::glyphs::TextWarningKind::FontNotFound => codes::FONT_NOT_FOUND,
                        crate::glyphs::TextWarningKind::MissingGlyph => codes::MISSING_GLYPH,
                        crate::glyphs::TextWarningKind::Ignored => codes::IGNORED_ARGUMENT,
                        crate::glyphs::TextWarningKind::Empty => codes::EMPTY_PRIMITIVE,
                    };
                    self.warn(code, w.message, file, at(w.argument));
                }
                let node = match built.node {
                    Some(node) => node,
                    None => self.dag.empty(source),
                };
                self.mark_planar(from, node);
                Ok(Some(node.into()))
            }
            Err(failure) => {
                let code = if failure.limit {
                    codes::VECTOR_LIMIT
                } else if failure.argument == "font" {
                    codes::FONT_UNUSABLE
                } else {
                    codes::MODULE_ARGUMENT
                };
                Err(self.error(code, failure.message, file, at(failure.argument)))
            }
        }
    }

    fn apply_transform(
        &mut self,
        inner: Edge,
        m: &DMat4,
        file: FileId,
        span: Span,
    ) -> R<Option<Edge>> {
        let det = m.determinant();
        if det == 0.0 || !det.is_finite() || !m.is_finite() {
            self.warn(
                codes::SINGULAR_TRANSFORM,
                "the transform is singular or not finite: the object is removed",
                file,
                span,
            );
            return Ok(None);
        }
        match self.dag.transformed(inner, m) {
            Ok(edge) => Ok(Some(edge)),
            Err(e) => {
                self.warn(
                    codes::SINGULAR_TRANSFORM,
                    format!("{e}: the object is removed"),
                    file,
                    span,
                );
                Ok(None)
            }
        }
    }

    fn color_of(
        &mut self,
        named: &BuiltinArgs<'a>,
        file: FileId,
        span: Span,
    ) -> R<Option<[f64; 4]>> {
        let mut rgba = match &named.get("c") {
            Value::Vector(v) => {
                let mut out = [1.0; 4];
                for (o, e) in out.iter_mut().zip(v.iter()) {
                    *o = e.as_number().unwrap_or(1.0);
                }
                out
            }
            Value::String(s) => match color::parse_color(s) {
                Some(c) => c,
                None => {
                    self.warn(
                        codes::UNKNOWN_COLOR,
                        format!("unknown colour \"{s}\""),
                        file,
                        span,
                    );
                    return Ok(None);
                }
            },
            _ => return Ok(None),
        };
        if let Value::Number(alpha) = named.get("alpha") {
            rgba[3] = alpha;
        }
        Ok(Some(rgba))
    }

    /// Places the arguments of a built-in module call on its parameters.
    fn place_builtin_args(
        &mut self,
        params: &'static [qcsg_sema::builtins::BuiltinParam],
        values: &[ArgValue<'a>],
        args: &'a [Arg],
        file: FileId,
    ) -> R<BuiltinArgs<'a>> {
        let mut out = BuiltinArgs::default();
        let mut positional = params.iter().filter(|p| p.positional);
        for (a, syntax) in values.iter().zip(args) {
            match a.name {
                Some(n) if n.starts_with('$') => {}
                Some(n) => out.values.push((n, a.value.clone())),
                None => match positional.next() {
                    Some(p) => out.values.push((p.name, a.value.clone())),
                    None => {
                        return Err(self.error(
                            codes::MODULE_ARGUMENT,
                            "too many positional arguments",
                            file,
                            syntax.span,
                        ));
                    }
                },
            }
        }
        Ok(out)
    }

    fn intersection_for(
        &mut self,
        args: &'a [Arg],
        child: Option<&'a Stmt>,
        span: Span,
        cx: &Cx<'a>,
    ) -> R<Option<Edge>> {
        let mut bindings = Vec::new();
        for a in args {
            match &a.name {
                Some(name) => bindings.push((name.name.as_str(), &a.value)),
                None => {
                    return Err(self.error(
                        codes::MODULE_ARGUMENT,
                        "intersection_for needs `name = values` arguments",
                        cx.file,
                        a.span,
                    ));
                }
            }
        }
        let mut parts = Vec::new();
        let body_source = Source::new(cx.file, child.map_or(span, |c| c.span));
        self.for_each(&bindings, cx, &mut |this, frame| {
            let edges = this.eval_body(
                child,
                &Cx {
                    frame,
                    file: cx.file,
                },
            )?;
            if let Some(edge) = this.group(edges, body_source) {
                parts.push(edge);
            }
            Ok(())
        })?;
        let (parts, _) = self.same_dimension(parts);
        if parts.is_empty() {
            return Ok(None);
        }
        Ok(Some(
            self.dag
                .intersection(parts, Source::new(cx.file, span))
                .into(),
        ))
    }
}

impl<'a> ArgLookup<'a> for BuiltinArgs<'a> {
    fn get(&self, name: &str) -> Value<'a> {
        self.values
            .iter()
            .rev()
            .find(|(n, _)| *n == name)
            .map_or(Value::Undef, |(_, v)| v.clone())
    }
}

impl<'a> Evaluator<'a> {
    /// The 2-D children of `linear_extrude` or `rotate_extrude`: their child statements, or, with
    /// OpenSCAD's deprecated `file` argument (warning W0109 is static), the `import` of `file`,
    /// `layer`, `origin` and `scale` in their place, as OpenSCAD 2021.01 reads it (the children
    /// are then ignored).
    fn extrusion_children(
        &mut self,
        named: &BuiltinArgs<'a>,
        args: &'a [Arg],
        params: &'static [qcsg_sema::builtins::BuiltinParam],
        child: Option<&'a Stmt>,
        cx: &Cx<'a>,
        span: Span,
    ) -> R<Vec<Edge>> {
        if matches!(named.get("file"), Value::Undef) {
            return self.eval_body(child, cx);
        }
        Ok(self
            .import(named, args, params, cx.file, span)?
            .into_iter()
            .collect())
    }
}
