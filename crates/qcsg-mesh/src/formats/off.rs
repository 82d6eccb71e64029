//! OFF (Object File Format): `OFF`, then the vertex, face and edge counts, the vertices, and the
//! faces as `n i₁ … iₙ` (anything after the indices, such as a colour, is ignored). `#` starts a
//! comment. Faces are reversed into OpenSCAD's clockwise order; indices are checked by
//! [`polyhedron_cells`](crate::polyhedron_cells), not here, so its error names the face.

use glam::DVec3;

use super::{ReadError, ReadLimits};
use crate::Mesh;

const FORMAT: &str = "OFF";

/// The words of the file with their line numbers, read in order.
struct Words<'a> {
    words: Vec<(usize, &'a str)>,
    cursor: usize,
    last_line: usize,
}

impl Words<'_> {
    fn next(&mut self, what: &str) -> Result<(usize, String), ReadError> {
        let (line, word) = self.words.get(self.cursor).copied().ok_or_else(|| {
            ReadError::new(
                FORMAT,
                format!("line {}", self.last_line),
                format!("the file ends where {what} should be"),
            )
        })?;
        self.cursor += 1;
        Ok((line, word.to_string()))
    }

    /// A count of `what`, at most `limit`.
    fn count(&mut self, what: &str, limit: usize) -> Result<usize, ReadError> {
        let (line, word) = self.next(what)?;
        let value: usize = word.parse().map_err(|_| {
            ReadError::new(
                FORMAT,
                format!("line {line}"),
                format!("{what}: `{word}` is not a count"),
            )
        })?;
        if value > limit {
            return Err(ReadError::new(
                FORMAT,
                format!("line {line}"),
                format!("{value} {what}, more than the limit of {limit}"),
            ));
        }
        Ok(value)
    }
}

/// Reads an OFF file.
pub fn read_off(text: &str, limits: &ReadLimits) -> Result<Mesh, ReadError> {
    // Words with their line numbers, comments dropped.
    let words: Vec<(usize, &str)> = text
        .lines()
        .enumerate()
        .flat_map(|(number, line)| {
            let content = line.split('#').next().unwrap_or("");
            content.split_whitespace().map(move |w| (number + 1, w))
        })
        .collect();
    let mut words = Words {
        words,
        cursor: 0,
        last_line: text.lines().count().max(1),
    };
    let (line, header) = words.next("the `OFF` header")?;
    if header != "OFF" {
        return Err(ReadError::new(
            FORMAT,
            format!("line {line}"),
            format!("expected `OFF`, found `{header}`"),
        ));
    }
    let vertex_count = words.count("vertices", limits.max_vertices)?;
    let face_count = words.count("faces", limits.max_triangles)?;
    words.count("edges", usize::MAX)?;
    let mut points = Vec::with_capacity(vertex_count);
    for _ in 0..vertex_count {
        let mut p = [0.0; 3];
        for c in &mut p {
            let (line, word) = words.next("a vertex coordinate")?;
            *c = word
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    ReadError::new(
                        FORMAT,
                        format!("line {line}"),
                        format!("`{word}` is not a finite number"),
                    )
                })?;
        }
        points.push(DVec3::from_array(p));
    }
    let mut faces = Vec::with_capacity(face_count);
    let mut entries = 0usize;
    let mut previous_line = 0;
    for _ in 0..face_count {
        // A face starts on a new line: words left on the previous face's line are its colour.
        let (mut line, mut word) = words.next("a face")?;
        while line == previous_line {
            (line, word) = words.next("a face")?;
        }
        previous_line = line;
        let n: usize = word.parse().map_err(|_| {
            ReadError::new(
                FORMAT,
                format!("line {line}"),
                format!("`{word}` is not a corner count"),
            )
        })?;
        entries = entries.saturating_add(n);
        if entries > limits.max_triangles.saturating_mul(3) {
            return Err(ReadError::new(
                FORMAT,
                format!("line {line}"),
                "more face corners than the limit allows",
            ));
        }
        let mut face = Vec::with_capacity(n);
        for _ in 0..n {
            let (line, word) = words.next("a face index")?;
            face.push(word.parse::<usize>().map_err(|_| {
                ReadError::new(
                    FORMAT,
                    format!("line {line}"),
                    format!("`{word}` is not a vertex index"),
                )
            })?);
        }
        face.reverse();
        faces.push(face);
    }
    Ok(Mesh { points, faces })
}
