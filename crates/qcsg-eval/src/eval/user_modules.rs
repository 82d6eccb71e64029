//! User modules: a call's own scope (its parameters, `$children`, `$parent_modules`, and its
//! children kept with the caller's scope), `parent_module(n)`, and `children()`, which evaluates the chosen children where the module was
//! instantiated while `$`-variables set by the module reach them, and OpenSCAD's deprecated
//! `child(i)`.

use std::rc::Rc;

use qcsg_csg::{Edge, Source};
use qcsg_diag::{FileId, Span};
use qcsg_syntax::ast::{Arg, Stmt};

use crate::codes;
use crate::env::{Children, Frame, ModuleDef};
use crate::value::Value;

use super::scopes::ScopeItems;
use super::{ArgValue, Cx, Evaluator, R};

impl<'a> Evaluator<'a> {
    pub(super) fn call_module(
        &mut self,
        name: &'a str,
        def: Rc<ModuleDef<'a>>,
        args: &'a [Arg],
        child: Option<&'a Stmt>,
        span: Span,
        cx: &Cx<'a>,
    ) -> R<Option<Edge>> {
        let values = self.eval_args(args, cx)?;
        self.enter(cx.file, span)?;
        self.module_stack.push(name);
        let result = self.call_module_inner(&def, values, child, cx);
        self.module_stack.pop();
        self.depth -= 1;
        result
    }

    fn call_module_inner(
        &mut self,
        def: &Rc<ModuleDef<'a>>,
        values: Vec<ArgValue<'a>>,
        child: Option<&'a Stmt>,
        cx: &Cx<'a>,
    ) -> R<Option<Edge>> {
        let child_items = self.collect_body(cx.file, child);
        let children = Rc::new(Children {
            assignments: child_items.assignments,
            definitions: child_items.definitions,
            items: child_items.items,
            env: cx.frame.clone(),
        });
        let count = children.items.len();
        let frame = Frame::module_instance(&def.env, &cx.frame, children);
        self.bind_params(&frame, def.params, &def.env, def.file, values)?;
        frame.set("$children", Value::Number(count as f64));
        frame.set(
            "$parent_modules",
            Value::Number(self.module_stack.len() as f64),
        );
        let items = self.collect_body(def.file, Some(def.body));
        let edges = self.eval_scope(&items, &frame)?;
        Ok(self.group(edges, Source::new(def.file, def.body.span)))
    }

    /// `parent_module(n = 1)`: the name of the `n`-th user module instantiation below the
    /// innermost one (`0`: the module being evaluated), as OpenSCAD 2021.01 counts them: only
    /// user modules, `n` truncated towards zero. Out of range is an error where OpenSCAD warns
    /// and yields `undef`.
    pub(super) fn parent_module(
        &mut self,
        n: &Value<'a>,
        file: FileId,
        span: Span,
    ) -> R<Value<'a>> {
        let n = match n {
            Value::Number(x) => x.trunc(),
            other => {
                return Err(self.error(
                    codes::FUNCTION_ARGUMENT,
                    format!("parent_module(n) needs a number, got {}", other.type_name()),
                    file,
                    span,
                ));
            }
        };
        let depth = self.module_stack.len();
        if !(n >= 0.0 && n < depth as f64) {
            let message = if n < 0.0 {
                format!(
                    "parent_module({}): a negative index is not allowed",
                    crate::value::format_number(n)
                )
            } else {
                format!(
                    "parent_module({}): only {depth} module instantiation(s) on the stack",
                    crate::value::format_number(n)
                )
            };
            return Err(self.error(codes::FUNCTION_ARGUMENT, message, file, span));
        }
        let name = self.module_stack[depth - 1 - n as usize];
        Ok(Value::string(name.to_string()))
    }

    pub(super) fn children(&mut self, args: &'a [Arg], span: Span, cx: &Cx<'a>) -> R<Option<Edge>> {
        let values = self.eval_args(args, cx)?;
        let Some(children) = cx.frame.module_children() else {
            return Ok(None);
        };
        let n = children.items.len();
        let selection = values
            .iter()
            .find(|a| a.name.is_none() || a.name == Some("index"))
            .map(|a| a.value.clone());
        let mut indices = Vec::new();
        let mut add = |this: &mut Self, x: f64| -> R<()> {
            if !(x >= 0.0 && x < n as f64) {
                return Err(this.error(
                    codes::MODULE_ARGUMENT,
                    format!(
                        "children index {} out of bounds ({n} children)",
                        crate::value::format_number(x)
                    ),
                    cx.file,
                    span,
                ));
            }
            indices.push(x as usize);
            Ok(())
        };
        match &selection {
            None | Some(Value::Undef) => indices.extend(0..n),
            Some(Value::Number(x)) => add(self, *x)?,
            Some(Value::Vector(v)) => {
                for e in v.iter() {
                    match e {
                        Value::Number(x) => add(self, *x)?,
                        _ => {
                            return Err(self.error(
                                codes::MODULE_ARGUMENT,
                                "children([…]) needs numbers",
                                cx.file,
                                span,
                            ));
                        }
                    }
                }
            }
            Some(Value::Range(r)) => {
                let count = r.len();
                self.tick(count, cx.file, span)?;
                for i in 0..count {
                    add(self, r.at(i))?;
                }
            }
            Some(other) => {
                return Err(self.error(
                    codes::MODULE_ARGUMENT,
                    format!(
                        "children() needs an index, a vector or a range, got {}",
                        other.type_name()
                    ),
                    cx.file,
                    span,
                ));
            }
        }
        self.instantiate_children(&children, indices, span, cx)
    }

    /// `child(i)`, OpenSCAD's deprecated `children(i)` for one child (warning W0109 is static):
    /// OpenSCAD reads the first argument whatever its name, truncates it, and takes child 0 when
    /// there is none or it is not a number.
    pub(super) fn child(&mut self, args: &'a [Arg], span: Span, cx: &Cx<'a>) -> R<Option<Edge>> {
        let values = self.eval_args(args, cx)?;
        let Some(children) = cx.frame.module_children() else {
            return Ok(None);
        };
        let n = children.items.len();
        let index = match (values.first().map(|a| &a.value), args.first()) {
            (Some(Value::Number(x)), _) => x.trunc(),
            (Some(other), Some(arg)) => {
                self.warn(
                    codes::IGNORED_ARGUMENT,
                    format!(
                        "`child` takes a number, got {}: OpenSCAD takes child 0",
                        other.type_name()
                    ),
                    cx.file,
                    arg.span,
                );
                0.0
            }
            _ => 0.0,
        };
        if !(index >= 0.0 && index < n as f64) {
            return Err(self.error(
                codes::MODULE_ARGUMENT,
                format!(
                    "child index {} out of bounds ({n} children)",
                    crate::value::format_number(index)
                ),
                cx.file,
                span,
            ));
        }
        self.instantiate_children(&children, vec![index as usize], span, cx)
    }

    /// Evaluates the chosen children of the current module instance, in order.
    fn instantiate_children(
        &mut self,
        children: &Children<'a>,
        indices: Vec<usize>,
        span: Span,
        cx: &Cx<'a>,
    ) -> R<Option<Edge>> {
        // The children's own scope, entered from here so that `$`-variables set by the module
        // reach them.
        let frame = Frame::child(&children.env, &cx.frame);
        let items = ScopeItems {
            assignments: children.assignments.clone(),
            definitions: children.definitions.clone(),
            ..ScopeItems::default()
        };
        self.define(&items, &frame)?;
        self.assign(&items, &frame)?;
        let mut edges = Vec::new();
        for i in indices {
            let (file, stmt) = children.items[i];
            let made = self.eval_stmt(
                stmt,
                &Cx {
                    frame: frame.clone(),
                    file,
                },
            );
            if let Some(Some(edge)) = Self::recover(made)? {
                edges.push(edge);
            }
        }
        Ok(self.group(edges, Source::new(cx.file, span)))
    }
}
