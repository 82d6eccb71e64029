//! Call arguments: evaluated in the caller's scope, then bound to a user module's or function's
//! parameters (defaults evaluated in the definition's scope, `$`-arguments set for the callee).

use std::rc::Rc;

use qcsg_diag::FileId;
use qcsg_syntax::ast::{Arg, Param};

use crate::env::Frame;
use crate::value::Value;

use super::{ArgValue, Cx, Evaluator, R};

impl<'a> Evaluator<'a> {
    pub(super) fn eval_args(&mut self, args: &'a [Arg], cx: &Cx<'a>) -> R<Vec<ArgValue<'a>>> {
        let mut out = Vec::with_capacity(args.len());
        for a in args {
            out.push(ArgValue {
                name: a.name.as_ref().map(|n| n.name.as_str()),
                value: self.eval_expr(&a.value, cx)?,
            });
        }
        Ok(out)
    }

    /// Binds call arguments to parameters in `frame`; defaults are evaluated in the
    /// definition's scope, as OpenSCAD 2021.01 does.
    pub(super) fn bind_params(
        &mut self,
        frame: &Rc<Frame<'a>>,
        params: &'a [Param],
        def_env: &Rc<Frame<'a>>,
        def_file: FileId,
        values: Vec<ArgValue<'a>>,
    ) -> R<()> {
        let mut given: Vec<Option<Value<'a>>> = vec![None; params.len()];
        let mut position = 0;
        for a in values {
            match a.name {
                Some(n) if n.starts_with('$') => frame.set(n, a.value),
                Some(n) => {
                    if let Some(i) = params.iter().position(|p| p.name.name == n) {
                        given[i] = Some(a.value);
                    }
                }
                None => {
                    if position < params.len() {
                        given[position] = Some(a.value);
                    }
                    position += 1;
                }
            }
        }
        for (param, value) in params.iter().zip(given) {
            let value = match (value, &param.default) {
                (Some(v), _) => v,
                (None, Some(default)) => self.eval_expr(
                    default,
                    &Cx {
                        frame: def_env.clone(),
                        file: def_file,
                    },
                )?,
                (None, None) => Value::Undef,
            };
            frame.set(&param.name.name, value);
        }
        Ok(())
    }
}
