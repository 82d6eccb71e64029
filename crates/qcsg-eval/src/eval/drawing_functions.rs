//! OpenSCAD's `dxf_dim(file, layer, name, origin, scale)` and `dxf_cross(file, layer, origin,
//! scale)`: a dimension's measure and the crossing of two lines, read from a DXF drawing.
//!
//! The drawing is read as `import` reads it ([`qcsg_mesh::read_dxf`], the path relative to the
//! calling file). A file that cannot be read or is malformed is an error at the call, as for
//! `import`; a dimension or cross the drawing lacks is `undef` with warning W0565, as OpenSCAD
//! returns `undef` with a warning.

use glam::DVec2;
use qcsg_diag::{FileId, Span};
use qcsg_mesh::{DrawingLimits, DrawingOptions, read_dxf};
use std::rc::Rc;

use crate::codes;
use crate::import::{self, ImportFailure};
use crate::value::Value;

use super::{Evaluator, R};

impl<'a> Evaluator<'a> {
    /// `dxf_dim` or `dxf_cross` with its arguments in the order of its parameters: `file`,
    /// `layer`, then `name` for `dxf_dim`, then `origin`, `scale`.
    pub(super) fn drawing_function(
        &mut self,
        name: &str,
        args: &[Value<'a>],
        file: FileId,
        span: Span,
    ) -> R<Value<'a>> {
        let undef = Value::Undef;
        let arg = |i: usize| args.get(i).unwrap_or(&undef);
        let is_dim = name == "dxf_dim";
        let (origin_at, scale_at) = if is_dim { (3, 4) } else { (2, 3) };
        let bad = |what: &str| format!("{name}({what})");
        let Value::String(written) = arg(0) else {
            let m = format!("{} needs a file name (a string)", bad("file"));
            return Err(self.error(codes::FUNCTION_ARGUMENT, m, file, span));
        };
        let written = written.to_string();
        let mut options = DrawingOptions::default();
        match arg(1) {
            Value::Undef => {}
            Value::String(s) => options.layer = Some(s.to_string()),
            _ => {
                let m = format!("{} needs a layer name (a string)", bad("layer"));
                return Err(self.error(codes::FUNCTION_ARGUMENT, m, file, span));
            }
        }
        match arg(origin_at) {
            Value::Undef => {}
            v => match v.as_numbers(2) {
                Some(o) if o.iter().all(|x| x.is_finite()) => {
                    options.origin = DVec2::new(o[0], o[1]);
                }
                _ => {
                    let m = format!("{} needs a point [x, y] of finite numbers", bad("origin"));
                    return Err(self.error(codes::FUNCTION_ARGUMENT, m, file, span));
                }
            },
        }
        match arg(scale_at) {
            Value::Undef => {}
            v => match v.as_number() {
                Some(s) if s.is_finite() => options.scale = s,
                _ => {
                    let m = format!("{} needs a finite number", bad("scale"));
                    return Err(self.error(codes::FUNCTION_ARGUMENT, m, file, span));
                }
            },
        }
        let dimension = match (is_dim, arg(2)) {
            (true, Value::String(s)) => Some(s.to_string()),
            (false, _) | (true, Value::Undef) => None,
            (true, _) => {
                let m = format!("{} needs a dimension name (a string)", bad("name"));
                return Err(self.error(codes::FUNCTION_ARGUMENT, m, file, span));
            }
        };
        let caller = self
            .sources
            .iter()
            .find(|(id, _)| *id == file)
            .map_or("", |(_, f)| f.name.as_str());
        let path = import::resolve(caller, &written);
        if !self.imports.contains(&path) {
            self.imports.push(path.clone());
        }
        let bytes = import::read_file(&path, &written, self.options.max_import_bytes)
            .map_err(|f| self.file_failure(f, file, span))?;
        let max = usize::try_from(self.options.max_vector_len).unwrap_or(usize::MAX);
        let limits = DrawingLimits {
            max_entities: max,
            max_points: max,
        };
        let drawing = read_dxf(&bytes, &options, &limits).map_err(|e| {
            let m = format!("`{written}`: {e}");
            self.error(codes::IMPORT_MALFORMED, m, file, span)
        })?;
        let layer = options.layer.as_deref().unwrap_or("");
        if is_dim {
            let name = dimension.as_deref().unwrap_or("");
            match drawing.dimension(dimension.as_deref()) {
                Ok(Some(v)) => Ok(Value::Number(v)),
                Ok(None) => {
                    let m = format!(
                        "no dimension named `{name}` in `{written}`, layer `{layer}`: undef"
                    );
                    self.warn(codes::DRAWING_LOOKUP, m, file, span);
                    Ok(Value::Undef)
                }
                Err(kind) => {
                    let m = format!(
                        "dimension `{name}` in `{written}` has type {kind}, which OpenSCAD does \
                         not measure: undef"
                    );
                    self.warn(codes::DRAWING_LOOKUP, m, file, span);
                    Ok(Value::Undef)
                }
            }
        } else {
            match drawing.cross() {
                Some(p) => Ok(Value::Vector(Rc::new(vec![
                    Value::Number(p.x),
                    Value::Number(p.y),
                ]))),
                None => {
                    let m = format!("no two crossing lines in `{written}`, layer `{layer}`: undef");
                    self.warn(codes::DRAWING_LOOKUP, m, file, span);
                    Ok(Value::Undef)
                }
            }
        }
    }

    /// The diagnostic of a drawing file that could not be read, at the call.
    fn file_failure(&mut self, failure: ImportFailure, file: FileId, span: Span) -> super::Stop {
        match failure {
            ImportFailure::Unreadable(m) | ImportFailure::NotFound(m) => {
                self.error(codes::IMPORT_UNREADABLE, m, file, span)
            }
            ImportFailure::TooLarge(m) => self.error(codes::IMPORT_SIZE_LIMIT, m, file, span),
            ImportFailure::Malformed(m) => self.error(codes::IMPORT_MALFORMED, m, file, span),
            ImportFailure::TooManyElements(m) => self.error(codes::VECTOR_LIMIT, m, file, span),
        }
    }
}
