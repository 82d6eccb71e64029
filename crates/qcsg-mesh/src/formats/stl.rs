//! STL, ASCII and binary.
//!
//! A file whose length is exactly 84 + 50 n bytes, n being the count at byte 80, is binary (some
//! binary files begin with `solid` too); otherwise it must be ASCII, `solid … endsolid` with
//! `vertex x y z` lines read three to a triangle (the normals are ignored, as OpenSCAD does).
//! Equal vertices are merged exactly; triangles are reversed into OpenSCAD's clockwise order.

use glam::DVec3;

use super::{ReadError, ReadLimits, VertexMerger};
use crate::Mesh;

const FORMAT: &str = "STL";

/// Reads an ASCII or binary STL file.
pub fn read_stl(bytes: &[u8], limits: &ReadLimits) -> Result<Mesh, ReadError> {
    if bytes.len() >= 84 {
        let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if count.checked_mul(50).and_then(|b| b.checked_add(84)) == Some(bytes.len()) {
            return read_binary(bytes, count, limits);
        }
    }
    let text = std::str::from_utf8(bytes).map_err(|e| {
        ReadError::new(
            FORMAT,
            format!("byte {}", e.valid_up_to()),
            "neither a binary STL (its length does not match its triangle count) nor ASCII text",
        )
    })?;
    read_ascii(text, limits)
}

fn read_binary(bytes: &[u8], count: usize, limits: &ReadLimits) -> Result<Mesh, ReadError> {
    if count > limits.max_triangles {
        return Err(ReadError::new(
            FORMAT,
            "the header",
            format!(
                "{count} triangles, more than the limit of {}",
                limits.max_triangles
            ),
        ));
    }
    let mut merger = VertexMerger::default();
    let mut faces = Vec::with_capacity(count);
    for t in 0..count {
        let record = &bytes[84 + 50 * t..84 + 50 * (t + 1)];
        let value = |k: usize| {
            let o = 12 + 4 * k;
            f64::from(f32::from_le_bytes([
                record[o],
                record[o + 1],
                record[o + 2],
                record[o + 3],
            ]))
        };
        let mut corners = [0usize; 3];
        for (v, corner) in corners.iter_mut().enumerate() {
            let p = DVec3::new(value(3 * v), value(3 * v + 1), value(3 * v + 2));
            if !p.is_finite() {
                return Err(ReadError::new(
                    FORMAT,
                    format!("triangle {t}"),
                    "a vertex coordinate is not a finite number",
                ));
            }
            *corner = merger.index_of(p);
        }
        faces.push(vec![corners[0], corners[2], corners[1]]);
    }
    Ok(Mesh {
        points: merger.into_points(),
        faces,
    })
}

fn read_ascii(text: &str, limits: &ReadLimits) -> Result<Mesh, ReadError> {
    let mut merger = VertexMerger::default();
    let mut faces = Vec::new();
    let mut pending: Vec<usize> = Vec::with_capacity(3);
    let mut saw_solid = false;
    for (number, line) in text.lines().enumerate() {
        let at = || format!("line {}", number + 1);
        let mut words = line.split_whitespace();
        match words.next() {
            Some("solid") => saw_solid = true,
            Some("vertex") => {
                if !saw_solid {
                    return Err(ReadError::new(FORMAT, at(), "a vertex before `solid`"));
                }
                let mut coordinates = [0.0; 3];
                for c in &mut coordinates {
                    let word = words.next().ok_or_else(|| {
                        ReadError::new(FORMAT, at(), "a vertex needs three coordinates")
                    })?;
                    *c = word
                        .parse::<f64>()
                        .ok()
                        .filter(|v| v.is_finite())
                        .ok_or_else(|| {
                            ReadError::new(FORMAT, at(), format!("`{word}` is not a finite number"))
                        })?;
                }
                pending.push(merger.index_of(DVec3::from_array(coordinates)));
                if pending.len() == 3 {
                    if faces.len() >= limits.max_triangles {
                        return Err(ReadError::new(
                            FORMAT,
                            at(),
                            format!("more than the limit of {} triangles", limits.max_triangles),
                        ));
                    }
                    faces.push(vec![pending[0], pending[2], pending[1]]);
                    pending.clear();
                }
            }
            Some("endloop") if !pending.is_empty() => {
                return Err(ReadError::new(
                    FORMAT,
                    at(),
                    "a facet with other than three vertices",
                ));
            }
            _ => {}
        }
    }
    if !saw_solid {
        return Err(ReadError::new(
            FORMAT,
            "line 1",
            "an ASCII STL file starts with `solid`",
        ));
    }
    Ok(Mesh {
        points: merger.into_points(),
        faces,
    })
}
