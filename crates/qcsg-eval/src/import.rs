//! `import(file)`: where the file is, what format it is, reading it safely and reading meshes
//! (STL, OFF, 3MF) from it. The evaluator turns each mesh into a solid as it does
//! `polyhedron`'s (see [`crate::polyhedron`]).
//!
//! As in OpenSCAD, a relative path is relative to the directory of the file that contains the
//! call (not the including file, not the working directory), an absolute path is used as given,
//! and the format is told by the extension, whatever its case (`.STL` is STL). The file is read
//! by `qcsg_sema::read_bytes_with_limit`, which refuses devices, directories and files over the
//! limit before reading, so `/dev/zero` is an error, not a hang.

use std::path::{Path, PathBuf};

use qcsg_mesh::{Mesh, ReadLimits, read_3mf, read_off, read_stl};
use qcsg_sema::SourceError;

/// The format of an imported file, from its extension.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Format {
    /// `.stl`: ASCII or binary STL, a 3-D mesh.
    Stl,
    /// `.off`: Object File Format, a 3-D mesh.
    Off,
    /// `.3mf`: a zipped XML package of 3-D meshes.
    ThreeMf,
    /// `.dxf`: a 2-D drawing.
    Dxf,
    /// Any other extension, lower-cased (`"3mf"`, `"svg"`), or `""` for none.
    Other(String),
}

impl Format {
    /// The format of `path`, from its extension in any case.
    pub fn of(path: &str) -> Self {
        let ext = Path::new(path)
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        match ext.as_str() {
            "stl" => Format::Stl,
            "off" => Format::Off,
            "3mf" => Format::ThreeMf,
            "dxf" => Format::Dxf,
            _ => Format::Other(ext),
        }
    }
}

/// Where `import(path)` called in the file named `caller` looks: `path` itself when absolute,
/// else `path` in the directory of `caller` (the current directory for standard input or a
/// file name without a directory).
pub fn resolve(caller: &str, path: &str) -> PathBuf {
    let path = Path::new(path);
    if path.is_absolute() || caller == qcsg_sema::STDIN_NAME {
        return path.to_path_buf();
    }
    match Path::new(caller).parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir.join(path),
        _ => path.to_path_buf(),
    }
}

/// Why an imported file gave no mesh.
#[derive(Debug)]
pub enum ImportFailure {
    /// No file at the path.
    NotFound(String),
    /// A directory or device, unreadable.
    Unreadable(String),
    /// Over the size limit, in bytes.
    TooLarge(String),
    /// Not a well-formed file of its format.
    Malformed(String),
    /// More triangles or vertices than the vector-length limit.
    TooManyElements(String),
}

/// The bytes of the file at `path` (as `written` in the program), at most `max_bytes`.
pub fn read_file(path: &Path, written: &str, max_bytes: u64) -> Result<Vec<u8>, ImportFailure> {
    qcsg_sema::read_bytes_with_limit(path, max_bytes).map_err(|e| match e {
        SourceError::TooLarge { size, limit } => ImportFailure::TooLarge(match size {
            Some(size) => format!(
                "cannot import \"{written}\": it has {size} bytes, more than the limit of {limit}"
            ),
            None => format!("cannot import \"{written}\": it has more than {limit} bytes"),
        }),
        SourceError::Io(io) if io.kind() == std::io::ErrorKind::NotFound => {
            ImportFailure::NotFound(format!(
                "cannot import \"{written}\": no such file ({})",
                path.display()
            ))
        }
        other => ImportFailure::Unreadable(format!("cannot import \"{written}\": {other}")),
    })
}

/// The meshes in `bytes`, an STL, OFF or 3MF file, with at most `max_len` triangles and
/// vertices: one mesh, or one per mesh object of a 3MF file. A 3MF file's model part may unpack
/// to at most `max_bytes`, the limit on the file itself.
pub fn read_meshes(
    format: &Format,
    bytes: &[u8],
    max_len: usize,
    max_bytes: u64,
) -> Result<Vec<Mesh>, ImportFailure> {
    let limits = ReadLimits {
        max_triangles: max_len,
        max_vertices: max_len,
    };
    let read = match format {
        Format::ThreeMf => read_3mf(bytes, &limits, max_bytes),
        Format::Stl => read_stl(bytes, &limits).map(|m| vec![m]),
        Format::Off => match std::str::from_utf8(bytes) {
            Ok(text) => read_off(text, &limits).map(|m| vec![m]),
            Err(e) => {
                return Err(ImportFailure::Malformed(format!(
                    "OFF file, byte {}: not text (not valid UTF-8)",
                    e.valid_up_to()
                )));
            }
        },
        _ => {
            return Err(ImportFailure::Malformed(
                "not a mesh format (STL, OFF or 3MF)".into(),
            ));
        }
    };
    read.map_err(|e| {
        // The readers state a crossed limit in their message; it is a limit, with its flag: the
        // byte limit for a 3MF part that unpacks too large, else the vector-length limit.
        if e.message.contains("unpacks to") {
            ImportFailure::TooLarge(e.to_string())
        } else if e.message.contains("the limit") {
            ImportFailure::TooManyElements(e.to_string())
        } else {
            ImportFailure::Malformed(e.to_string())
        }
    })
}
