//! PNG output: encoding a frame and writing it atomically (a temporary file in the target's
//! directory renamed over it), so that a failed run leaves no partial file.

use std::fmt;
use std::io::Write;
use std::path::{Path, PathBuf};

use image::ImageEncoder;
use image::codecs::png::PngEncoder;

use crate::frame::Frame;

/// Why an image could not be encoded or written.
#[derive(Debug)]
pub enum PngError {
    /// The encoder failed.
    Encode(String),
    /// Writing the file failed.
    Io(PathBuf, std::io::Error),
}

impl fmt::Display for PngError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Encode(message) => write!(f, "cannot encode the PNG: {message}"),
            Self::Io(path, error) => write!(f, "cannot write {}: {error}", path.display()),
        }
    }
}

impl std::error::Error for PngError {}

/// The frame's colours as a PNG file (8-bit RGB), deterministic byte for byte.
pub fn encode(frame: &Frame) -> Result<Vec<u8>, PngError> {
    let mut bytes = Vec::new();
    PngEncoder::new(&mut bytes)
        .write_image(
            &frame.rgb,
            frame.size.width(),
            frame.size.height(),
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| PngError::Encode(e.to_string()))?;
    Ok(bytes)
}

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename, so
/// that readers see the old file or the whole new one, and a failure leaves no partial file.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), PngError> {
    let io = |e| PngError::Io(path.to_path_buf(), e);
    let directory = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path.file_name().ok_or_else(|| {
        io(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a file name",
        ))
    })?;
    let mut temporary_name = std::ffi::OsString::from(".");
    temporary_name.push(name);
    temporary_name.push(format!(".{}.tmp", std::process::id()));
    let temporary = directory.join(temporary_name);
    let result = std::fs::File::create(&temporary)
        .and_then(|mut file| {
            file.write_all(bytes)?;
            file.sync_all()
        })
        .and_then(|()| std::fs::rename(&temporary, path));
    if let Err(error) = result {
        let _ = std::fs::remove_file(&temporary);
        return Err(io(error));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_whole_files_and_leaves_nothing_on_failure() {
        let directory =
            std::env::temp_dir().join(format!("qcsg-render-png-{}", std::process::id()));
        std::fs::create_dir_all(&directory).unwrap();
        let target = directory.join("out.png");
        write_atomically(&target, b"abc").unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"abc");
        let missing = directory.join("no-such-dir").join("out.png");
        assert!(write_atomically(&missing, b"abc").is_err());
        assert!(!missing.exists());
        let leftovers: Vec<_> = std::fs::read_dir(&directory).unwrap().collect();
        assert_eq!(leftovers.len(), 1);
        std::fs::remove_dir_all(&directory).unwrap();
    }
}
