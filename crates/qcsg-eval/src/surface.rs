//! `surface(file)`: a height map (a `.dat` table of numbers or a PNG image) and the closed mesh
//! OpenSCAD 2021.01 builds from it, vertex for vertex, so that the solid is exactly OpenSCAD's.
//!
//! OpenSCAD tells the two formats apart by content, not by name: a file that starts with the PNG
//! signature is an image, anything else a table. In a table each line that is not empty and
//! does not start with `#` (after trimming) is a row of numbers separated by spaces or tabs; row
//! `r`, column `c` is the height at `(x, y) = (c, r)`. In an image each pixel's height is
//! `100 / 255 · (0.2126 R + 0.7152 G + 0.0722 B)` (8-bit channels; a 16-bit channel counts by its
//! high byte, as OpenSCAD's decoder reads it), and the image's top row is the row of largest `y`,
//! so the map seen from above looks like the picture. `invert` (images only) replaces a
//! luminance `L` by `1 − L` on the 0–255 scale, as OpenSCAD 2021.01 does, which puts the surface
//! about 100 units below zero: it is OpenSCAD's result, so it is ours.
//!
//! The mesh: every grid cell is four triangles around its centre, whose height is the mean of
//! the cell's corners (OpenSCAD chooses no diagonal); the four walls stand on the base plane
//! `z = min(0, lowest height − 1)`; the base is one face through every boundary point.
//! `center = true` moves the grid (not the heights) so that its middle is at x = y = 0.
//!
//! OpenSCAD warns and builds what it read of a table with a bad number, and reads missing
//! entries of short rows as 0; here both are errors, as is a map without area (fewer than two
//! rows or columns), where OpenSCAD builds a flat, empty mesh.

use std::io::Cursor;

use glam::DVec3;
use image::{DynamicImage, ImageDecoder, codecs::png::PngDecoder};
use qcsg_mesh::Mesh;

use crate::import::ImportFailure;

/// The eight bytes every PNG file starts with.
const PNG_SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];

/// A grid of heights, row-major: row `r` lies at `y = r`, column `c` at `x = c`.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightMap {
    /// The number of rows (the grid's extent in y, plus one).
    pub rows: usize,
    /// The number of columns (the grid's extent in x, plus one).
    pub columns: usize,
    /// `rows · columns` finite heights, row 0 first.
    pub heights: Vec<f64>,
}

impl HeightMap {
    /// The height at row `r`, column `c`.
    pub fn at(&self, r: usize, c: usize) -> f64 {
        self.heights[r * self.columns + c]
    }
}

/// Whether `bytes` are a PNG file (OpenSCAD's test: the signature only).
pub fn is_png(bytes: &[u8]) -> bool {
    bytes.starts_with(&PNG_SIGNATURE)
}

/// The height map in `bytes`, an image or a table, with at most `max_points` grid points.
/// `invert` applies to images only, as in OpenSCAD.
pub fn read_height_map(
    bytes: &[u8],
    invert: bool,
    max_points: usize,
) -> Result<HeightMap, ImportFailure> {
    let map = if is_png(bytes) {
        read_png(bytes, invert, max_points)?
    } else {
        read_dat(bytes, max_points)?
    };
    if map.rows < 2 || map.columns < 2 {
        return Err(ImportFailure::Malformed(format!(
            "the height map has {} row(s) of {} value(s): surface needs at least 2 rows and 2 \
             columns to enclose a solid",
            map.rows, map.columns
        )));
    }
    Ok(map)
}

fn too_many(max_points: usize) -> ImportFailure {
    ImportFailure::TooManyElements(format!(
        "the height map has more than {max_points} points, the limit (--max-vector-len)"
    ))
}

/// A table of numbers: rows of numbers separated by spaces or tabs, `#` comment lines.
fn read_dat(bytes: &[u8], max_points: usize) -> Result<HeightMap, ImportFailure> {
    let mut heights = Vec::new();
    let mut rows = 0usize;
    let mut columns = 0usize;
    let mut first_line = 0usize;
    for (n, raw) in bytes.split(|&b| b == b'\n').enumerate() {
        let line_no = n + 1;
        let Ok(text) = std::str::from_utf8(raw) else {
            return Err(ImportFailure::Malformed(format!(
                "height map, line {line_no}: not text (not valid UTF-8)"
            )));
        };
        let line = text.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let mut count = 0usize;
        for token in line.split([' ', '\t']).filter(|t| !t.is_empty()) {
            let value = token.parse::<f64>().ok().filter(|v| v.is_finite());
            let Some(value) = value else {
                return Err(ImportFailure::Malformed(format!(
                    "height map, line {line_no}: `{}` is not a finite number",
                    shorten(token)
                )));
            };
            if heights.len() >= max_points {
                return Err(too_many(max_points));
            }
            heights.push(value);
            count += 1;
        }
        if rows == 0 {
            columns = count;
            first_line = line_no;
        } else if count != columns {
            return Err(ImportFailure::Malformed(format!(
                "height map, line {line_no}: a row of {count} value(s), but the first row (line \
                 {first_line}) has {columns}; every row needs the same number of values \
                 (OpenSCAD reads missing values as 0: write them out)"
            )));
        }
        rows += 1;
    }
    if heights.is_empty() {
        return Err(ImportFailure::Malformed(
            "the height map has no numbers (only empty or `#` comment lines)".into(),
        ));
    }
    Ok(HeightMap {
        rows,
        columns,
        heights,
    })
}

/// A token as quoted in a message: at most 40 characters.
fn shorten(token: &str) -> String {
    match token.char_indices().nth(40) {
        Some((i, _)) => format!("{}…", &token[..i]),
        None => token.to_owned(),
    }
}

/// A PNG image: each pixel's luminance, scaled to 0–100, the top row at the largest y.
fn read_png(bytes: &[u8], invert: bool, max_points: usize) -> Result<HeightMap, ImportFailure> {
    let bad = |e: image::ImageError| ImportFailure::Malformed(format!("PNG image: {e}"));
    let decoder = PngDecoder::new(Cursor::new(bytes)).map_err(bad)?;
    let (width, height) = decoder.dimensions();
    let (columns, rows) = (width as usize, height as usize);
    if columns.saturating_mul(rows) > max_points {
        return Err(too_many(max_points));
    }
    let image = DynamicImage::from_decoder(decoder).map_err(bad)?;
    // OpenSCAD's decoder gives 8-bit RGBA, a 16-bit sample by its high byte (not rounded).
    let rgb: Vec<[u8; 3]> = match image {
        DynamicImage::ImageLuma16(_)
        | DynamicImage::ImageLumaA16(_)
        | DynamicImage::ImageRgb16(_)
        | DynamicImage::ImageRgba16(_) => image
            .to_rgba16()
            .pixels()
            .map(|p| [(p[0] >> 8) as u8, (p[1] >> 8) as u8, (p[2] >> 8) as u8])
            .collect(),
        _ => image
            .to_rgba8()
            .pixels()
            .map(|p| [p[0], p[1], p[2]])
            .collect(),
    };
    let mut heights = vec![0.0; rows * columns];
    for (i, [r, g, b]) in rgb.into_iter().enumerate() {
        let (y, x) = (i / columns, i % columns);
        // OpenSCAD's formula and order of operations, so the heights agree to the bit.
        let pixel = 0.2126 * f64::from(r) + 0.7152 * f64::from(g) + 0.0722 * f64::from(b);
        let z = 100.0 / 255.0 * (if invert { 1.0 - pixel } else { pixel });
        heights[(rows - 1 - y) * columns + x] = z;
    }
    Ok(HeightMap {
        rows,
        columns,
        heights,
    })
}

/// The base plane's height: one below the lowest height, and never above 0.
pub fn base_height(map: &HeightMap) -> f64 {
    map.heights.iter().fold(0.0_f64, |m, &h| m.min(h - 1.0))
}

/// The closed mesh OpenSCAD builds from `map`, faces clockwise seen from outside (the order of
/// [`qcsg_mesh::Mesh`]); OpenSCAD lists them counter-clockwise, so each is reversed. A map of
/// fewer than 2 rows or columns gives an empty mesh.
pub fn mesh(map: &HeightMap, center: bool) -> Mesh {
    let (rows, cols) = (map.rows, map.columns);
    if rows < 2 || cols < 2 || map.heights.len() != rows * cols {
        // No area (read_height_map refuses such maps): no solid.
        return Mesh {
            points: Vec::new(),
            faces: Vec::new(),
        };
    }
    let ox = if center {
        -((cols - 1) as f64) / 2.0
    } else {
        0.0
    };
    let oy = if center {
        -((rows - 1) as f64) / 2.0
    } else {
        0.0
    };
    let base = base_height(map);
    let x = |c: usize| ox + c as f64;
    let y = |r: usize| oy + r as f64;
    let mut points: Vec<DVec3> = Vec::with_capacity(2 * rows * cols + 2 * (rows + cols));
    for r in 0..rows {
        for c in 0..cols {
            points.push(DVec3::new(x(c), y(r), map.at(r, c)));
        }
    }
    let top = |r: usize, c: usize| r * cols + c;
    // The base points, on the boundary only, numbered as they are first needed.
    let mut base_index = vec![usize::MAX; rows * cols];
    let mut bottom = |r: usize, c: usize, points: &mut Vec<DVec3>| {
        let k = r * cols + c;
        if base_index[k] == usize::MAX {
            base_index[k] = points.len();
            points.push(DVec3::new(x(c), y(r), base));
        }
        base_index[k]
    };
    let mut faces: Vec<Vec<usize>> = Vec::with_capacity(4 * rows * cols + 2 * (rows + cols));
    for i in 1..rows {
        for j in 1..cols {
            let (v1, v2, v3, v4) = (
                map.at(i - 1, j - 1),
                map.at(i - 1, j),
                map.at(i, j - 1),
                map.at(i, j),
            );
            let vx = (v1 + v2 + v3 + v4) / 4.0;
            let centre = points.len();
            points.push(DVec3::new(ox + j as f64 - 0.5, oy + i as f64 - 0.5, vx));
            let (a, b, c, d) = (top(i - 1, j - 1), top(i - 1, j), top(i, j - 1), top(i, j));
            // OpenSCAD: (a, b, centre), (b, d, centre), (d, c, centre), (c, a, centre).
            faces.push(vec![centre, b, a]);
            faces.push(vec![centre, d, b]);
            faces.push(vec![centre, c, d]);
            faces.push(vec![centre, a, c]);
        }
    }
    let last_c = cols - 1;
    let last_r = rows - 1;
    for i in 1..rows {
        // x = 0 (OpenSCAD appends it) and x = last (inserts, which reverses it).
        let (b0, b1) = (bottom(i - 1, 0, &mut points), bottom(i, 0, &mut points));
        faces.push(vec![b1, top(i, 0), top(i - 1, 0), b0]);
        let (b0, b1) = (
            bottom(i - 1, last_c, &mut points),
            bottom(i, last_c, &mut points),
        );
        faces.push(vec![b0, top(i - 1, last_c), top(i, last_c), b1]);
    }
    for i in 1..cols {
        // y = 0 (inserted, reversed) and y = last (appended).
        let (b0, b1) = (bottom(0, i - 1, &mut points), bottom(0, i, &mut points));
        faces.push(vec![b0, top(0, i - 1), top(0, i), b1]);
        let (b0, b1) = (
            bottom(last_r, i - 1, &mut points),
            bottom(last_r, i, &mut points),
        );
        faces.push(vec![b1, top(last_r, i), top(last_r, i - 1), b0]);
    }
    // The base: OpenSCAD inserts each point at the front, so this forward walk is its reverse.
    let mut base_face = Vec::with_capacity(2 * (rows + cols));
    for i in 0..last_c {
        base_face.push(bottom(0, i, &mut points));
    }
    for i in 0..last_r {
        base_face.push(bottom(i, last_c, &mut points));
    }
    for i in (1..cols).rev() {
        base_face.push(bottom(last_r, i, &mut points));
    }
    for i in (1..rows).rev() {
        base_face.push(bottom(i, 0, &mut points));
    }
    faces.push(base_face);
    Mesh { points, faces }
}
