//! `polyhedron(points, faces)`, `import(file)` and `surface(file)`: meshes as solids, with every
//! failure a diagnostic at the argument it is about.
//!
//! All end in [`crate::polyhedron::build`]; `surface` reads its height map with
//! [`crate::surface`] and builds the mesh OpenSCAD builds. `import` resolves its path against the calling
//! file ([`crate::import::resolve`]), then dispatches on the extension: STL, OFF and 3MF are read
//! into meshes here (a 3MF file's objects united); `.dxf` goes to [`Evaluator::import_dxf`]; anything else is E0301 at the
//! `file` argument, naming the format, before the file is touched. A mesh file's cells are kept
//! for the evaluation, so a part imported in a loop or at several places is read and cut once.

use std::path::PathBuf;
use std::rc::Rc;

use qcsg_csg::{Edge, Source};
use qcsg_diag::{FileId, Span};
use qcsg_sema::builtins::BuiltinParam;
use qcsg_syntax::ast::Arg;

use crate::codes;
use crate::import::{self, Format, ImportFailure};
use crate::polyhedron::{self as mesh, MeshFailure, MeshPart, MeshShape};
use crate::primitives::ArgLookup;
use crate::value::Value;

use super::instantiation::BuiltinArgs;
use super::{Evaluator, R};

/// The span of the value given for parameter `name` of a built-in call (the last one, as
/// [`BuiltinArgs::get`] takes the last), placed as the evaluator places arguments.
pub(super) fn arg_span(params: &[BuiltinParam], args: &[Arg], name: &str) -> Option<Span> {
    let mut positional = params.iter().filter(|p| p.positional);
    let mut found = None;
    for a in args {
        let param = match &a.name {
            Some(n) if n.name.starts_with('$') => continue,
            Some(n) => Some(n.name.as_str()),
            None => positional.next().map(|p| p.name),
        };
        if param == Some(name) {
            found = Some(a.value.span);
        }
    }
    found
}

/// One `import(…)` call, resolved: what a format's reader needs. The meshes use the path and
/// the `file` span; a drawing's reader also reads `layer`, `origin`, `scale` and their spans.
#[allow(dead_code)]
pub(super) struct ImportCall<'n, 'a> {
    /// The path as the program wrote it.
    pub written: String,
    /// Where it was looked for (see [`crate::import::resolve`]).
    pub path: PathBuf,
    /// The file of the call.
    pub file: FileId,
    /// The whole call.
    pub span: Span,
    /// The `file` argument (the call when it was not given by name or position).
    pub file_span: Span,
    /// Every argument by parameter name: `layer`, `origin`, `scale`, `center`, `dpi`, `id`, ….
    pub named: &'n BuiltinArgs<'a>,
    /// The call's arguments and the parameters they were placed on, for [`ImportCall::span_of`].
    args: &'a [Arg],
    params: &'static [BuiltinParam],
}

#[allow(dead_code)]
impl ImportCall<'_, '_> {
    /// The span of argument `name`, or of the call when it was not given.
    pub fn span_of(&self, name: &str) -> Span {
        arg_span(self.params, self.args, name).unwrap_or(self.span)
    }
}

impl<'a> Evaluator<'a> {
    /// `polyhedron(points, faces)` (or the deprecated `triangles`): the solid the mesh bounds.
    pub(super) fn polyhedron(
        &mut self,
        named: &BuiltinArgs<'a>,
        args: &'a [Arg],
        params: &'static [BuiltinParam],
        file: FileId,
        span: Span,
    ) -> R<Option<Edge>> {
        let span_of = |name: &str| arg_span(params, args, name).unwrap_or(span);
        // OpenSCAD 2021.01 reads `triangles` only when `faces` is undefined, with a warning.
        let mut faces_param = "faces";
        let mut faces = named.get("faces");
        if matches!(faces, Value::Undef) {
            let triangles = named.get("triangles");
            if !matches!(triangles, Value::Undef) {
                self.warn(
                    codes::DEPRECATED_ARGUMENT,
                    "polyhedron(triangles = …) is deprecated: use polyhedron(faces = …)",
                    file,
                    span_of("triangles"),
                );
                faces_param = "triangles";
                faces = triangles;
            }
        }
        let max_len = usize::try_from(self.options.max_vector_len).unwrap_or(usize::MAX);
        let part_span = |part: MeshPart| match part {
            MeshPart::Points => span_of("points"),
            MeshPart::Faces => span_of(faces_param),
        };
        let built = mesh::mesh_of(&named.get("points"), &faces, max_len)
            .and_then(|m| mesh::build(&mut self.dag, &m, max_len, Source::new(file, span)));
        match built {
            Ok(built) => self.mesh_solid(built, file, span, span),
            Err(failure) => Err(self.mesh_failure(failure, file, &part_span)),
        }
    }

    /// The node of a built mesh (an empty solid for an empty mesh), its warnings at `warn_span`;
    /// its triangles are kept for `projection`.
    fn mesh_solid(
        &mut self,
        built: mesh::BuiltMesh,
        file: FileId,
        span: Span,
        warn_span: Span,
    ) -> R<Option<Edge>> {
        for w in built.warnings {
            self.warn(codes::MESH_FACES, w, file, warn_span);
        }
        Ok(Some(match built.node {
            Some(node) => {
                self.mesh_faces.insert(node, built.faces);
                node.into()
            }
            None => self.dag.empty(Source::new(file, span)).into(),
        }))
    }

    fn mesh_failure(
        &mut self,
        failure: MeshFailure,
        file: FileId,
        span_of: &dyn Fn(MeshPart) -> Span,
    ) -> super::Stop {
        match failure {
            MeshFailure::Argument(part, m) => {
                self.error(codes::MODULE_ARGUMENT, m, file, span_of(part))
            }
            MeshFailure::Invalid(part, m) => self.error_with_help(
                codes::INVALID_MESH,
                m,
                "a polyhedron's faces must close a surface: every edge shared by exactly two \
                 faces that run along it in opposite directions, each face listed clockwise \
                 seen from outside",
                file,
                span_of(part),
            ),
            MeshFailure::TooLarge(part, m) => {
                self.error(codes::VECTOR_LIMIT, m, file, span_of(part))
            }
        }
    }

    /// `import(file, …)`: an STL, OFF or 3MF mesh as a solid, a DXF drawing as a 2-D shape;
    /// other formats are E0301.
    pub(super) fn import(
        &mut self,
        named: &BuiltinArgs<'a>,
        args: &'a [Arg],
        params: &'static [BuiltinParam],
        file: FileId,
        span: Span,
    ) -> R<Option<Edge>> {
        let file_span = arg_span(params, args, "file").unwrap_or(span);
        let written = match &named.get("file") {
            Value::String(s) => s.to_string(),
            Value::Undef => {
                return Err(self.error(
                    codes::MODULE_ARGUMENT,
                    "import needs the name of the file to import: import(\"part.stl\")",
                    file,
                    file_span,
                ));
            }
            other => {
                return Err(self.error(
                    codes::MODULE_ARGUMENT,
                    format!(
                        "import(file) needs a file name (a string), got {}",
                        other.type_name()
                    ),
                    file,
                    file_span,
                ));
            }
        };
        let call = self.import_call(written, (file, span, file_span), named, args, params);
        let format = Format::of(&call.written);
        match format {
            Format::Stl | Format::Off | Format::ThreeMf => {
                let shapes = match self.imported_meshes.get(&call.path) {
                    Some(shapes) => shapes.clone(),
                    None => {
                        let shapes: Rc<[MeshShape]> = self.import_mesh(&format, &call)?.into();
                        self.imported_meshes
                            .insert(call.path.clone(), shapes.clone());
                        shapes
                    }
                };
                // A 3MF file's objects are united, as OpenSCAD unites them.
                let mut solids = Vec::with_capacity(shapes.len());
                for shape in shapes.iter() {
                    if let Some(solid) = self.file_mesh_solid(shape, file, span, file_span)? {
                        solids.push(solid);
                    }
                }
                Ok(match solids.len() {
                    0 => None,
                    1 => solids.pop(),
                    _ => Some(self.dag.union(solids, Source::new(file, span)).into()),
                })
            }
            Format::Dxf => self.import_dxf(&call),
            Format::Other(ext) => {
                let what = if ext.is_empty() {
                    "a file without an extension".to_owned()
                } else {
                    format!("`.{ext}` files")
                };
                Err(self.error_with_help(
                    qcsg_sema::codes::UNSUPPORTED_MODULE,
                    format!(
                        "importing {what} is not supported: qcsg imports STL, OFF and 3MF \
                         meshes and DXF drawings"
                    ),
                    "convert the part to STL, OFF or 3MF (OpenSCAD and most mesh tools export \
                     them)",
                    file,
                    file_span,
                ))
            }
        }
    }

    /// The call of `import` or `surface` reading `written`, resolved against the directory of
    /// the calling file.
    fn import_call<'n>(
        &self,
        written: String,
        (file, span, file_span): (FileId, Span, Span),
        named: &'n BuiltinArgs<'a>,
        args: &'a [Arg],
        params: &'static [BuiltinParam],
    ) -> ImportCall<'n, 'a> {
        let caller = self
            .sources
            .iter()
            .find(|(id, _)| *id == file)
            .map_or("", |(_, f)| f.name.as_str());
        ImportCall {
            path: import::resolve(caller, &written),
            written,
            file,
            span,
            file_span,
            named,
            args,
            params,
        }
    }

    /// The solid of a mesh read from a file, its failures reported at the `file` argument.
    fn file_mesh_solid(
        &mut self,
        shape: &MeshShape,
        file: FileId,
        span: Span,
        file_span: Span,
    ) -> R<Option<Edge>> {
        match mesh::solid(&mut self.dag, shape, Source::new(file, span)) {
            Ok(built) => self.mesh_solid(built, file, span, file_span),
            Err(failure) => Err(self.mesh_failure(failure, file, &|_| file_span)),
        }
    }

    /// `surface(file, center, convexity, invert)`: the closed mesh of a height map (a `.dat`
    /// table or a PNG image), as OpenSCAD builds it. As in OpenSCAD, `center` and `invert` count
    /// only when they are booleans; `convexity` has no effect.
    pub(super) fn surface(
        &mut self,
        named: &BuiltinArgs<'a>,
        args: &'a [Arg],
        params: &'static [BuiltinParam],
        file: FileId,
        span: Span,
    ) -> R<Option<Edge>> {
        let file_span = arg_span(params, args, "file").unwrap_or(span);
        let written = match &named.get("file") {
            Value::String(s) => s.to_string(),
            other => {
                let got = match other {
                    Value::Undef => String::new(),
                    other => format!(", got {}", other.type_name()),
                };
                return Err(self.error(
                    codes::MODULE_ARGUMENT,
                    format!("surface needs the name of a height map file (a string){got}"),
                    file,
                    file_span,
                ));
            }
        };
        let flag = |name: &str| matches!(named.get(name), Value::Bool(true));
        let (center, invert) = (flag("center"), flag("invert"));
        let call = self.import_call(written, (file, span, file_span), named, args, params);
        let key = (call.path.clone(), invert, center);
        let shape = match self.surfaces.get(&key) {
            Some(shape) => shape.clone(),
            None => {
                let shape = Rc::new(self.surface_cells(&call, invert, center)?);
                self.surfaces.insert(key, shape.clone());
                shape
            }
        };
        self.file_mesh_solid(&shape, file, span, file_span)
    }

    /// The cells of the surface of the height map `call` names.
    fn surface_cells(
        &mut self,
        call: &ImportCall<'_, 'a>,
        invert: bool,
        center: bool,
    ) -> R<MeshShape> {
        let bytes = self.import_bytes(call)?;
        let max_len = usize::try_from(self.options.max_vector_len).unwrap_or(usize::MAX);
        let map = crate::surface::read_height_map(&bytes, invert, max_len)
            .map_err(|f| self.import_failure(f, call))?;
        drop(bytes);
        let shape = crate::surface::mesh(&map, center);
        drop(map);
        // The grid limit above bounds the mesh: some 2 points and 13 face entries per grid
        // point, which the mesh limits must let through.
        mesh::shape(&shape, max_len.saturating_mul(16))
            .map_err(|failure| self.mesh_failure(failure, call.file, &|_| call.file_span))
    }

    /// The cells of the STL, OFF or 3MF mesh `call` names: one shape per mesh object.
    fn import_mesh(&mut self, format: &Format, call: &ImportCall<'_, 'a>) -> R<Vec<MeshShape>> {
        let bytes = self.import_bytes(call)?;
        let max_len = usize::try_from(self.options.max_vector_len).unwrap_or(usize::MAX);
        let meshes = import::read_meshes(format, &bytes, max_len, self.options.max_import_bytes)
            .map_err(|f| self.import_failure(f, call))?;
        drop(bytes);
        meshes
            .iter()
            .map(|mesh| {
                mesh::shape(mesh, max_len)
                    .map_err(|failure| self.mesh_failure(failure, call.file, &|_| call.file_span))
            })
            .collect()
    }

    /// `import` of a `.dxf` drawing: the even–odd region of its layer as a 2-D shape (see
    /// `drawings`).
    fn import_dxf(&mut self, call: &ImportCall<'_, 'a>) -> R<Option<Edge>> {
        self.import_drawing(call)
    }

    /// The bytes of the imported file, at most `--max-import-bytes`; the path is recorded for
    /// viewers whether or not it could be read.
    pub(super) fn import_bytes(&mut self, call: &ImportCall<'_, 'a>) -> R<Vec<u8>> {
        if !self.imports.contains(&call.path) {
            self.imports.push(call.path.clone());
        }
        import::read_file(&call.path, &call.written, self.options.max_import_bytes)
            .map_err(|f| self.import_failure(f, call))
    }

    /// The diagnostic of an import that gave no mesh, at the `file` argument.
    pub(super) fn import_failure(
        &mut self,
        failure: ImportFailure,
        call: &ImportCall<'_, 'a>,
    ) -> super::Stop {
        let (file, span) = (call.file, call.file_span);
        match failure {
            ImportFailure::Unreadable(m) => self.error(codes::IMPORT_UNREADABLE, m, file, span),
            ImportFailure::NotFound(m) => self.error_with_help(
                codes::IMPORT_UNREADABLE,
                m,
                "a relative path is relative to the directory of the file that calls import",
                file,
                span,
            ),
            ImportFailure::TooLarge(m) => self.error(codes::IMPORT_SIZE_LIMIT, m, file, span),
            ImportFailure::Malformed(m) => self.error(codes::IMPORT_MALFORMED, m, file, span),
            ImportFailure::TooManyElements(m) => self.error(codes::VECTOR_LIMIT, m, file, span),
        }
    }
}
