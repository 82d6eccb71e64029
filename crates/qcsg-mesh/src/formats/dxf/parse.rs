//! The group-code reader: pairs of lines into entities, entities into pieces (segments, arcs,
//! circles, elliptic arcs, ellipses) with origin and scale applied, blocks kept aside and
//! expanded at each INSERT.

use std::collections::HashMap;
use std::f64::consts::TAU;

use glam::DVec2;

use super::join::join;
use super::{
    Dimension, Drawing, DrawingCircle, DrawingCurve, DrawingEllipse, DrawingLimits, DrawingOptions,
    DrawingWarning, degrees_sin_cos,
};
use crate::formats::ReadError;

const FORMAT: &str = "DXF";

/// A piece of geometry from one entity, before joining.
#[derive(Clone, Debug)]
pub(super) enum Piece {
    /// A straight segment.
    Segment { from: DVec2, to: DVec2, line: usize },
    /// An arc, counter-clockwise from `from` to `to` unless `ccw` is false (mirrored by an
    /// INSERT).
    Arc {
        from: DVec2,
        to: DVec2,
        center: DVec2,
        radius: f64,
        ccw: bool,
        line: usize,
    },
    /// A full circle.
    Circle {
        center: DVec2,
        radius: f64,
        line: usize,
    },
    /// An elliptic arc, in the direction of increasing parameter from `from` to `to` unless
    /// `forward` is false (see [`super::EllipticArc`]).
    EllipticArc {
        from: DVec2,
        to: DVec2,
        center: DVec2,
        axes: [DVec2; 2],
        forward: bool,
        line: usize,
    },
    /// A full ellipse.
    Ellipse {
        center: DVec2,
        axes: [DVec2; 2],
        line: usize,
    },
    /// A curve kept aside (see [`DrawingCurve`]).
    Curve { entity: String, line: usize },
}

/// An INSERT: a block mapped by rotation, scale and translation.
#[derive(Clone, Debug)]
struct Insert {
    block: String,
    point: DVec2,
    scale: DVec2,
    rotation: f64,
    line: usize,
}

#[derive(Clone, Debug)]
enum BlockItem {
    Piece(Piece),
    Insert(Insert),
}

/// The group codes of the entity being read.
#[derive(Default)]
struct Fields {
    kind: String,
    line: usize,
    layer: String,
    name: String,
    id: String,
    xs: Vec<f64>,
    ys: Vec<f64>,
    coords: [DVec2; 7],
    radius: f64,
    /// Code 40 as written (an ELLIPSE's axis ratio, which `scale` does not change).
    c40: f64,
    c41: f64,
    c42: f64,
    /// Whether code 42 was given (an ELLIPSE's end parameter defaults to a whole turn).
    has_c42: bool,
    /// An LWPOLYLINE's bulges: the vertex each follows, and its value.
    bulges: Vec<(usize, f64)>,
    c50: f64,
    c51: f64,
    flag: i64,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Section {
    Other,
    Entities,
    Blocks,
}

/// An open POLYLINE collecting its VERTEX entities until SEQEND.
struct Polyline {
    points: Vec<DVec2>,
    /// The bulge of the edge after each point.
    bulges: Vec<f64>,
    closed: bool,
    selected: bool,
    line: usize,
}

struct Reader<'a> {
    options: &'a DrawingOptions,
    limits: &'a DrawingLimits,
    section: Section,
    block: Option<String>,
    blocks: HashMap<String, Vec<BlockItem>>,
    /// The selected entities of the ENTITIES section, INSERTs unexpanded.
    top: Vec<BlockItem>,
    dimensions: Vec<Dimension>,
    unsupported: Vec<(String, usize, usize)>,
    polyline: Option<Polyline>,
    entities: usize,
    /// Polyline edges with a bulge, and the DXF line of the first.
    bulges: (usize, usize),
    /// The DXF line of the first ELLIPSE read with an origin or scale.
    ellipse_options: Option<usize>,
}

fn error(line: usize, message: impl Into<String>) -> ReadError {
    ReadError::new(FORMAT, format!("line {line}"), message)
}

fn number(value: &str, line: usize) -> Result<f64, ReadError> {
    value
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| error(line, format!("`{value}` is not a finite number")))
}

/// Reads an ASCII DXF drawing: the selected layer's paths and circles, with `origin` and `scale`
/// applied, joined as OpenSCAD joins them.
pub fn read_dxf(
    bytes: &[u8],
    options: &DrawingOptions,
    limits: &DrawingLimits,
) -> Result<Drawing, ReadError> {
    if !options.scale.is_finite() || !options.origin.is_finite() {
        return Err(ReadError::new(
            FORMAT,
            "the options",
            "origin and scale must be finite",
        ));
    }
    if bytes.starts_with(b"AutoCAD Binary DXF") {
        return Err(ReadError::new(
            FORMAT,
            "the header",
            "binary DXF is not supported; save the drawing as ASCII DXF",
        ));
    }
    let text = String::from_utf8_lossy(bytes);
    let lines: Vec<&str> = text.lines().map(str::trim).collect();
    let mut reader = Reader {
        options,
        limits,
        section: Section::Other,
        block: None,
        blocks: HashMap::new(),
        top: Vec::new(),
        dimensions: Vec::new(),
        unsupported: Vec::new(),
        polyline: None,
        entities: 0,
        bulges: (0, 0),
        ellipse_options: None,
    };
    let mut fields = Fields::default();
    let mut index = 0;
    while index < lines.len() {
        let line = index + 1;
        let code_text = lines[index];
        if code_text.is_empty() && lines[index..].iter().all(|l| l.is_empty()) {
            break;
        }
        let code: i64 = code_text.parse().map_err(|_| {
            error(
                line,
                format!("`{code_text}` is not a group code (a DXF file alternates group codes and values)"),
            )
        })?;
        let Some(&value) = lines.get(index + 1) else {
            return Err(error(line, format!("group code {code} has no value")));
        };
        let value_line = line + 1;
        index += 2;
        if code == 0 {
            reader.finish(std::mem::take(&mut fields))?;
            fields.kind = value.to_string();
            fields.line = line;
            if fields.kind == "INSERT" {
                fields.c41 = 1.0;
                fields.c42 = 1.0;
            }
            if fields.kind == "EOF" {
                break;
            }
            continue;
        }
        reader.field(&mut fields, code, value, value_line)?;
    }
    reader.finish(fields)?;
    reader.into_drawing()
}

impl Reader<'_> {
    fn geometric(&self) -> bool {
        matches!(self.section, Section::Entities | Section::Blocks)
    }

    fn field(
        &mut self,
        f: &mut Fields,
        code: i64,
        value: &str,
        line: usize,
    ) -> Result<(), ReadError> {
        match code {
            1 => f.name = value.to_string(),
            2 => f.id = value.to_string(),
            8 => f.layer = value.to_string(),
            _ => {}
        }
        if !self.geometric() {
            return Ok(());
        }
        let raw = self.section == Section::Blocks;
        let (origin, scale) = (self.options.origin, self.options.scale);
        match code {
            10..=16 | 20..=26 => {
                let v = number(value, line)?;
                let (axis, slot) = if code < 20 {
                    (0, code - 10)
                } else {
                    (1, code - 20)
                };
                let o = if axis == 0 { origin.x } else { origin.y };
                // OpenSCAD shifts by the origin every point but 11, 12 and 16 of a DIMENSION
                // (offsets), then scales; block contents stay raw until inserted.
                let shifted = if raw {
                    v
                } else if matches!(slot, 1 | 2 | 6) {
                    v * scale
                } else {
                    (v - o) * scale
                };
                f.coords[slot as usize][axis] = shifted;
                if slot <= 1 {
                    let point = if raw { v } else { (v - o) * scale };
                    let list = if axis == 0 { &mut f.xs } else { &mut f.ys };
                    if list.len() >= self.limits.max_points {
                        return Err(error(
                            line,
                            format!(
                                "more than {} points in one entity, the limit",
                                self.limits.max_points
                            ),
                        ));
                    }
                    list.push(point);
                }
            }
            40 => {
                f.c40 = number(value, line)?;
                f.radius = f.c40 * if raw { 1.0 } else { scale };
            }
            41 => f.c41 = number(value, line)?,
            // An LWPOLYLINE's bulge follows the point of its vertex.
            42 if f.kind == "LWPOLYLINE" => {
                let bulge = number(value, line)?;
                f.bulges.push((f.xs.len().saturating_sub(1), bulge));
            }
            42 => {
                f.c42 = number(value, line)?;
                f.has_c42 = true;
            }
            50 => f.c50 = number(value, line)?,
            51 => f.c51 = number(value, line)?,
            70 => {
                f.flag = value
                    .parse()
                    .map_err(|_| error(line, format!("`{value}` is not an integer flag")))?
            }
            _ => {}
        }
        Ok(())
    }

    /// Whether an entity of the ENTITIES section with this layer is read.
    fn selected(&self, layer: &str) -> bool {
        match &self.options.layer {
            None => true,
            Some(name) => name.is_empty() || name == layer,
        }
    }

    fn count_entity(&mut self, line: usize) -> Result<(), ReadError> {
        self.entities += 1;
        if self.entities > self.limits.max_entities {
            return Err(error(
                line,
                format!("more than {} entities, the limit", self.limits.max_entities),
            ));
        }
        Ok(())
    }

    /// Stores an item where the current section puts it.
    fn push(&mut self, item: BlockItem, layer: &str) {
        match self.section {
            Section::Entities => {
                if self.selected(layer) {
                    self.top.push(item);
                }
            }
            Section::Blocks => {
                if let Some(block) = &self.block {
                    self.blocks.entry(block.clone()).or_default().push(item);
                }
            }
            Section::Other => {}
        }
    }

    fn finish(&mut self, f: Fields) -> Result<(), ReadError> {
        let line = f.line;
        match f.kind.as_str() {
            "" => return Ok(()),
            "SECTION" => {
                self.section = match f.id.as_str() {
                    "ENTITIES" => Section::Entities,
                    "BLOCKS" => Section::Blocks,
                    _ => Section::Other,
                };
                return Ok(());
            }
            "ENDSEC" => {
                self.section = Section::Other;
                return Ok(());
            }
            _ => {}
        }
        if !self.geometric() {
            return Ok(());
        }
        // A POLYLINE gathers VERTEX entities until SEQEND (or any other entity).
        if let (true, Some(poly)) = (f.kind == "VERTEX", &mut self.polyline) {
            let p = point(&f, 0).ok_or_else(|| error(line, "VERTEX without a point"))?;
            if poly.points.len() >= self.limits.max_points {
                return Err(error(line, "more POLYLINE vertices than the point limit"));
            }
            poly.points.push(p);
            poly.bulges.push(f.c42);
            return Ok(());
        }
        if let Some(poly) = self.polyline.take() {
            self.end_polyline(poly);
            if f.kind == "SEQEND" {
                return Ok(());
            }
        }
        let in_layer = self.section == Section::Blocks || self.selected(&f.layer);
        match f.kind.as_str() {
            "BLOCK" => {
                self.block = Some(f.id.clone());
                return Ok(());
            }
            "ENDBLK" => {
                self.block = None;
                return Ok(());
            }
            _ => {}
        }
        self.count_entity(line)?;
        match f.kind.as_str() {
            "LINE" => {
                let (Some(from), Some(to)) = (point(&f, 0), point(&f, 1)) else {
                    return Err(error(
                        line,
                        "LINE without its two end points (codes 10/20, 11/21)",
                    ));
                };
                self.push(
                    BlockItem::Piece(Piece::Segment { from, to, line }),
                    &f.layer,
                );
            }
            "LWPOLYLINE" => {
                if f.xs.len() != f.ys.len() {
                    return Err(error(
                        line,
                        format!(
                            "LWPOLYLINE with {} x and {} y coordinates",
                            f.xs.len(),
                            f.ys.len()
                        ),
                    ));
                }
                let points: Vec<DVec2> =
                    f.xs.iter()
                        .zip(&f.ys)
                        .map(|(&x, &y)| DVec2::new(x, y))
                        .collect();
                let mut bulges = vec![0.0; points.len()];
                for &(vertex, bulge) in &f.bulges {
                    if let Some(b) = bulges.get_mut(vertex) {
                        *b = bulge;
                    }
                }
                self.polyline_pieces(&points, &bulges, f.flag & 1 != 0, line, &f.layer);
            }
            "POLYLINE" => {
                self.polyline = Some(Polyline {
                    points: Vec::new(),
                    bulges: Vec::new(),
                    closed: f.flag & 1 != 0,
                    selected: in_layer,
                    line,
                });
            }
            "CIRCLE" => {
                let center = point(&f, 0).ok_or_else(|| error(line, "CIRCLE without a centre"))?;
                if f.radius != 0.0 {
                    let radius = f.radius.abs();
                    self.push(
                        BlockItem::Piece(Piece::Circle {
                            center,
                            radius,
                            line,
                        }),
                        &f.layer,
                    );
                }
            }
            "ARC" => {
                let center = point(&f, 0).ok_or_else(|| error(line, "ARC without a centre"))?;
                if let Some(piece) = arc_piece(center, f.radius, f.c50, f.c51, line) {
                    self.push(BlockItem::Piece(piece), &f.layer);
                }
            }
            "ELLIPSE" => {
                if let Some(piece) = self.ellipse_piece(&f)? {
                    self.push(BlockItem::Piece(piece), &f.layer);
                }
            }
            "INSERT" => {
                let point = point(&f, 0).unwrap_or(DVec2::ZERO);
                let insert = Insert {
                    block: f.id.clone(),
                    point,
                    scale: DVec2::new(f.c41, f.c42),
                    rotation: f.c50,
                    line,
                };
                self.push(BlockItem::Insert(insert), &f.layer);
            }
            "DIMENSION" => {
                if self.section == Section::Entities && self.selected(&f.layer) {
                    self.dimensions.push(Dimension {
                        name: f.name.clone(),
                        kind: f.flag,
                        coords: f.coords,
                        angle: f.c50,
                    });
                }
            }
            other => {
                if in_layer {
                    match self.unsupported.iter_mut().find(|(e, _, _)| e == other) {
                        Some(entry) => entry.1 += 1,
                        None => self.unsupported.push((other.to_string(), 1, line)),
                    }
                }
            }
        }
        Ok(())
    }

    /// An ELLIPSE: centre (10/20), major axis relative to it (11/21), axis ratio (40), start
    /// and end parameters (41, 42; a whole turn by default); `None` for no sweep, as OpenSCAD
    /// draws nothing then.
    fn ellipse_piece(&mut self, f: &Fields) -> Result<Option<Piece>, ReadError> {
        let line = f.line;
        let center = point(f, 0).ok_or_else(|| error(line, "ELLIPSE without a centre"))?;
        // Slot 1 holds the axis scaled but not shifted (raw inside a block).
        let axis = f.coords[1];
        if f.xs.len() < 2 || f.ys.len() < 2 || axis == DVec2::ZERO {
            return Err(error(
                line,
                "ELLIPSE without its major axis (codes 11/21, a vector from the centre)",
            ));
        }
        if f.c40 <= 0.0 {
            return Err(error(
                line,
                format!(
                    "ELLIPSE with axis ratio {} (code 40); it must be positive",
                    f.c40
                ),
            ));
        }
        if self.section == Section::Entities
            && (self.options.origin != DVec2::ZERO || self.options.scale != 1.0)
        {
            self.ellipse_options.get_or_insert(line);
        }
        let axes = [axis, axis.perp() * f.c40];
        let start = f.c41;
        let mut stop = if f.has_c42 { f.c42 } else { start + TAU };
        if (stop - start).abs() > 1e6 {
            return Err(error(
                line,
                "ELLIPSE parameters (codes 41, 42) more than a million radians apart",
            ));
        }
        while start > stop {
            stop += TAU;
        }
        let sweep = stop - start;
        if sweep == 0.0 {
            return Ok(None);
        }
        // A sweep a hair short of a turn (digits rounded in the file) is the whole ellipse: its
        // ends would fall in one cell of the joining grid and the arc would vanish.
        if sweep >= TAU - 1e-9 {
            return Ok(Some(Piece::Ellipse { center, axes, line }));
        }
        let at = |t: f64| {
            let (s, c) = t.sin_cos();
            center + axes[0] * c + axes[1] * s
        };
        Ok(Some(Piece::EllipticArc {
            from: at(start),
            to: at(stop),
            center,
            axes,
            forward: true,
            line,
        }))
    }

    fn end_polyline(&mut self, poly: Polyline) {
        // The layer was checked when the POLYLINE began.
        if poly.selected {
            self.polyline_pieces_unchecked(&poly.points, &poly.bulges, poly.closed, poly.line);
        }
    }

    fn polyline_pieces(
        &mut self,
        points: &[DVec2],
        bulges: &[f64],
        closed: bool,
        line: usize,
        layer: &str,
    ) {
        if self.section == Section::Entities && !self.selected(layer) {
            return;
        }
        self.polyline_pieces_unchecked(points, bulges, closed, line);
    }

    /// A polyline's edges: from each point to the next (and the last to the first when closed),
    /// an arc where the first point's bulge is not zero.
    fn polyline_pieces_unchecked(
        &mut self,
        points: &[DVec2],
        bulges: &[f64],
        closed: bool,
        line: usize,
    ) {
        let mut pieces = Vec::new();
        let n = points.len();
        let edges = if closed && n > 1 {
            n
        } else {
            n.saturating_sub(1)
        };
        for i in 0..edges {
            let (from, to) = (points[i], points[(i + 1) % n]);
            let bulge = bulges.get(i).copied().unwrap_or(0.0);
            match bulge_arc(from, to, bulge, line) {
                Some(arc) => {
                    if self.bulges.0 == 0 {
                        self.bulges.1 = line;
                    }
                    self.bulges.0 += 1;
                    pieces.push(arc);
                }
                None => pieces.push(Piece::Segment { from, to, line }),
            }
        }
        for piece in pieces {
            match self.section {
                Section::Entities => self.top.push(BlockItem::Piece(piece)),
                Section::Blocks => {
                    if let Some(block) = &self.block {
                        self.blocks
                            .entry(block.clone())
                            .or_default()
                            .push(BlockItem::Piece(piece));
                    }
                }
                Section::Other => {}
            }
        }
    }

    /// Expands INSERTs, joins the pieces and gathers the drawing.
    fn into_drawing(mut self) -> Result<Drawing, ReadError> {
        if let Some(poly) = self.polyline.take() {
            self.end_polyline(poly);
        }
        let mut pieces = Vec::new();
        let mut stack = Vec::new();
        let mut count = 0usize;
        let top = std::mem::take(&mut self.top);
        for item in &top {
            self.expand(
                item,
                &Map::top(self.options.scale),
                &mut stack,
                &mut pieces,
                &mut count,
            )?;
        }
        let mut drawing = Drawing {
            dimensions: self.dimensions,
            ..Drawing::default()
        };
        let mut edges = Vec::new();
        for piece in pieces {
            match piece {
                Piece::Circle {
                    center,
                    radius,
                    line,
                } => drawing.circles.push(DrawingCircle {
                    center,
                    radius,
                    line,
                }),
                Piece::Ellipse { center, axes, line } => {
                    drawing.ellipses.push(DrawingEllipse { center, axes, line })
                }
                Piece::Curve { entity, line } => drawing.curves.push(DrawingCurve { entity, line }),
                other => edges.push(other),
            }
        }
        if edges.len().saturating_mul(2) > self.limits.max_points {
            return Err(ReadError::new(
                FORMAT,
                "the drawing",
                format!(
                    "{} edge end points, more than the limit of {}",
                    edges.len() * 2,
                    self.limits.max_points
                ),
            ));
        }
        join(&edges, &mut drawing);
        if self.bulges.0 > 0 {
            drawing.warnings.push(DrawingWarning::Bulges {
                count: self.bulges.0,
                line: self.bulges.1,
            });
        }
        if let Some(line) = self.ellipse_options {
            drawing
                .warnings
                .push(DrawingWarning::EllipseOptions { line });
        }
        for (entity, count, line) in self.unsupported {
            drawing.warnings.push(DrawingWarning::Unsupported {
                entity,
                count,
                line,
            });
        }
        Ok(drawing)
    }

    fn expand(
        &self,
        item: &BlockItem,
        map: &Map,
        stack: &mut Vec<String>,
        out: &mut Vec<Piece>,
        count: &mut usize,
    ) -> Result<(), ReadError> {
        *count += 1;
        if *count > self.limits.max_entities {
            return Err(ReadError::new(
                FORMAT,
                "the drawing",
                format!(
                    "more than {} entities once INSERTs are expanded, the limit",
                    self.limits.max_entities
                ),
            ));
        }
        match item {
            BlockItem::Piece(piece) => out.push(map.apply(piece)),
            BlockItem::Insert(insert) => {
                if stack.contains(&insert.block) {
                    return Err(error(
                        insert.line,
                        format!(
                            "INSERT of block `{}` inside itself (blocks {} form a cycle)",
                            insert.block,
                            stack.join(" → ")
                        ),
                    ));
                }
                // OpenSCAD skips an INSERT of an unknown block silently.
                let Some(items) = self.blocks.get(&insert.block) else {
                    return Ok(());
                };
                let inner = map.then_insert(insert);
                stack.push(insert.block.clone());
                for item in items {
                    self.expand(item, &inner, stack, out, count)?;
                }
                stack.pop();
            }
        }
        Ok(())
    }
}

/// The point of codes 1x/2x number `slot` (0 for 10/20, 1 for 11/21).
fn point(f: &Fields, slot: usize) -> Option<DVec2> {
    Some(DVec2::new(*f.xs.get(slot)?, *f.ys.get(slot)?))
}

/// An ARC as OpenSCAD reads it: counter-clockwise from the start angle to the stop angle, the stop
/// angle raised by turns until it is not below the start; no sweep gives nothing, a full turn a
/// circle.
fn arc_piece(center: DVec2, radius: f64, start: f64, stop: f64, line: usize) -> Option<Piece> {
    let radius = radius.abs();
    if radius == 0.0 {
        return None;
    }
    let mut stop = stop;
    while start > stop {
        stop += 360.0;
    }
    let sweep = stop - start;
    if sweep == 0.0 {
        return None;
    }
    if sweep >= 360.0 {
        return Some(Piece::Circle {
            center,
            radius,
            line,
        });
    }
    let (s0, c0) = degrees_sin_cos(start);
    let (s1, c1) = degrees_sin_cos(stop);
    Some(Piece::Arc {
        from: center + DVec2::new(c0, s0) * radius,
        to: center + DVec2::new(c1, s1) * radius,
        center,
        radius,
        ccw: true,
        line,
    })
}

/// The arc of a polyline edge with a bulge: `bulge = tan(θ/4)` for the included angle `θ`,
/// counter-clockwise from `from` to `to` when positive; `None` (a straight edge) for no bulge or
/// no length.
fn bulge_arc(from: DVec2, to: DVec2, bulge: f64, line: usize) -> Option<Piece> {
    let chord = to - from;
    if bulge == 0.0 || chord == DVec2::ZERO {
        return None;
    }
    // The centre lies on the chord's perpendicular bisector, at (c/2)(1 − b²)/(2b) to the left
    // of the chord (to the right for a negative bulge); the radius is c(1 + b²)/(4|b|).
    let length = chord.length();
    let center = 0.5 * (from + to) + chord.perp() * ((1.0 - bulge * bulge) / (4.0 * bulge));
    let radius = length * (1.0 + bulge * bulge) / (4.0 * bulge.abs());
    (center.is_finite() && radius.is_finite() && radius > 0.0).then_some(Piece::Arc {
        from,
        to,
        center,
        radius,
        ccw: bulge > 0.0,
        line,
    })
}

/// An affine map of the plane: `p ↦ linear · p + offset`.
#[derive(Clone, Copy, Debug)]
struct Map {
    x: DVec2,
    y: DVec2,
    offset: DVec2,
    /// The factor an INSERT's block contents get on top of the INSERT's own scale: the import
    /// scale in the ENTITIES section (whose points are already scaled), 1 inside blocks.
    insert_scale: f64,
}

impl Map {
    /// The map of the ENTITIES section: identity (origin and scale are already applied), but
    /// block contents inserted there are scaled by the import scale, as OpenSCAD scales them.
    fn top(scale: f64) -> Map {
        Map {
            x: DVec2::X,
            y: DVec2::Y,
            offset: DVec2::ZERO,
            insert_scale: scale,
        }
    }

    fn linear(&self, p: DVec2) -> DVec2 {
        self.x * p.x + self.y * p.y
    }

    fn point(&self, p: DVec2) -> DVec2 {
        self.linear(p) + self.offset
    }

    fn determinant(&self) -> f64 {
        self.x.perp_dot(self.y)
    }

    /// This map after an INSERT's own map (`R(rotation) · diag(sx, sy)` then the insertion point).
    fn then_insert(&self, insert: &Insert) -> Map {
        let (s, c) = degrees_sin_cos(insert.rotation);
        let x = DVec2::new(c, s) * (insert.scale.x * self.insert_scale);
        let y = DVec2::new(-s, c) * (insert.scale.y * self.insert_scale);
        Map {
            x: self.linear(x),
            y: self.linear(y),
            offset: self.point(insert.point),
            insert_scale: 1.0,
        }
    }

    fn apply(&self, piece: &Piece) -> Piece {
        let det = self.determinant();
        // A circle stays a circle under a similarity: both columns of equal length, orthogonal.
        let similar = (self.x.length() - self.y.length()).abs() <= 1e-12 * self.x.length()
            && self.x.dot(self.y).abs() <= 1e-12 * self.x.length_squared();
        let k = self.x.length();
        match piece {
            Piece::Segment { from, to, line } => Piece::Segment {
                from: self.point(*from),
                to: self.point(*to),
                line: *line,
            },
            Piece::Arc {
                from,
                to,
                center,
                radius,
                ccw,
                line,
            } if similar => Piece::Arc {
                from: self.point(*from),
                to: self.point(*to),
                center: self.point(*center),
                radius: radius * k,
                ccw: if det < 0.0 { !ccw } else { *ccw },
                line: *line,
            },
            Piece::Circle {
                center,
                radius,
                line,
            } if similar => Piece::Circle {
                center: self.point(*center),
                radius: radius * k,
                line: *line,
            },
            // Any other invertible map turns a circle into an ellipse: its semi-diameters are the
            // images of two perpendicular radii, and each point keeps its parameter (its angle).
            Piece::Arc { line, .. }
            | Piece::Circle { line, .. }
            | Piece::EllipticArc { line, .. }
            | Piece::Ellipse { line, .. }
                if det == 0.0 || !det.is_finite() =>
            {
                Piece::Curve {
                    entity: "curve in an INSERT of zero scale".into(),
                    line: *line,
                }
            }
            Piece::Arc {
                from,
                to,
                center,
                radius,
                ccw,
                line,
            } => Piece::EllipticArc {
                from: self.point(*from),
                to: self.point(*to),
                center: self.point(*center),
                axes: [
                    self.linear(DVec2::X * *radius),
                    self.linear(DVec2::Y * *radius),
                ],
                forward: *ccw,
                line: *line,
            },
            Piece::Circle {
                center,
                radius,
                line,
            } => Piece::Ellipse {
                center: self.point(*center),
                axes: [
                    self.linear(DVec2::X * *radius),
                    self.linear(DVec2::Y * *radius),
                ],
                line: *line,
            },
            Piece::EllipticArc {
                from,
                to,
                center,
                axes,
                forward,
                line,
            } => Piece::EllipticArc {
                from: self.point(*from),
                to: self.point(*to),
                center: self.point(*center),
                axes: axes.map(|a| self.linear(a)),
                forward: *forward,
                line: *line,
            },
            Piece::Ellipse { center, axes, line } => Piece::Ellipse {
                center: self.point(*center),
                axes: axes.map(|a| self.linear(a)),
                line: *line,
            },
            Piece::Curve { .. } => piece.clone(),
        }
    }
}
