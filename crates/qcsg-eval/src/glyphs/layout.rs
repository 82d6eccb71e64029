//! Where OpenSCAD 2021.01 puts each glyph of a `text()`: shaping (HarfBuzz, here its Rust port
//! rustybuzz, which applies the font's kerning, ligatures and right-to-left order), then the
//! metrics of OpenSCAD's FreeType renderer.
//!
//! OpenSCAD sets FreeType's character size to `size · 1000` (26.6 points at 100 dpi) and
//! divides outline coordinates by 1000, so one em is `size / 0.72` units; but it divides
//! HarfBuzz's advances, offsets and FreeType's glyph boxes by `64 · 16 = 1024`, so advances and
//! the alignment boxes are `1000 / 1024` of the outline's scale. Both were checked against
//! OpenSCAD's exported outlines (`openscad -o x.svg`). The outline points themselves are taken
//! from the font unhinted, as OpenSCAD's exports show them.

use glam::DVec2;
use qcsg_mesh::curved::Segment;

/// The ratio of the scale of advances and boxes to that of outlines (see the module page).
const ADVANCE_RATIO: f64 = 1000.0 / 1024.0;

/// The parameters of a `text()` call that shape and place it.
pub struct TextParams<'t> {
    /// The text.
    pub text: &'t str,
    /// `size`.
    pub size: f64,
    /// `spacing`: a factor on every advance.
    pub spacing: f64,
    /// `halign`: `left`, `center` or `right`.
    pub halign: HAlign,
    /// `valign`: `baseline`, `top`, `center` or `bottom`.
    pub valign: VAlign,
    /// `direction`, when given and valid.
    pub direction: Option<rustybuzz::Direction>,
    /// `language`, when given.
    pub language: Option<&'t str>,
    /// `script` (an ISO 15924 tag), when given.
    pub script: Option<&'t str>,
}

/// Horizontal alignment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HAlign {
    /// The origin at the start.
    Left,
    /// The origin in the middle of the advances.
    Center,
    /// The origin at the end.
    Right,
}

/// Vertical alignment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VAlign {
    /// The origin on the baseline.
    Baseline,
    /// The origin at the top of the glyphs' boxes.
    Top,
    /// The origin halfway between top and bottom.
    Center,
    /// The origin at the bottom of the glyphs' boxes.
    Bottom,
}

/// A glyph placed: its outline about its own origin, and where that origin is.
///
/// The outline is kept about the glyph's origin so that a glyph the text repeats has the same
/// outline, to the bit, wherever it stands: built once, it is placed with a translation.
pub struct PlacedGlyph {
    /// The font's glyph id: glyphs with the same id have the same `contours`.
    pub id: u16,
    /// Closed contours of lines and quadratic arcs, about the glyph's origin.
    pub contours: Vec<Vec<Segment>>,
    /// Where the glyph's origin lies in output coordinates.
    pub origin: DVec2,
    /// The index of the first character the glyph shows (a byte offset in the text).
    pub cluster: u32,
}

impl PlacedGlyph {
    /// The contours in output coordinates.
    pub fn placed_contours(&self) -> Vec<Vec<Segment>> {
        shifted(&self.contours, self.origin)
    }
}

/// The box of the points and control points of `contours` (contours of a placed glyph hold at
/// least one segment).
pub fn control_box(contours: &[Vec<Segment>]) -> (DVec2, DVec2) {
    contours.iter().flatten().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), s| match *s {
            Segment::Line(a, b) => (lo.min(a).min(b), hi.max(a).max(b)),
            Segment::Quad(a, c, b) => (lo.min(a).min(b).min(c), hi.max(a).max(b).max(c)),
        },
    )
}

/// `contours` moved by `shift`.
pub fn shifted(contours: &[Vec<Segment>], shift: DVec2) -> Vec<Vec<Segment>> {
    contours
        .iter()
        .map(|contour| {
            contour
                .iter()
                .map(|s| match *s {
                    Segment::Line(a, b) => Segment::Line(a + shift, b + shift),
                    Segment::Quad(a, c, b) => Segment::Quad(a + shift, c + shift, b + shift),
                })
                .collect()
        })
        .collect()
}

/// Why a text could not be laid out.
#[derive(Debug)]
pub enum LayoutError {
    /// The font has cubic (CFF) outlines.
    Cubic,
    /// The font file cannot be parsed.
    Unreadable(String),
}

/// Collects a glyph's outline, scaled.
struct Outline {
    scale: f64,
    contours: Vec<Vec<Segment>>,
    pen: DVec2,
    cubic: bool,
}

impl Outline {
    fn at(&self, x: f32, y: f32) -> DVec2 {
        DVec2::new(f64::from(x), f64::from(y)) * self.scale
    }
}

impl ttf_parser::OutlineBuilder for Outline {
    fn move_to(&mut self, x: f32, y: f32) {
        self.contours.push(Vec::new());
        self.pen = self.at(x, y);
    }
    fn line_to(&mut self, x: f32, y: f32) {
        let to = self.at(x, y);
        if let Some(c) = self.contours.last_mut() {
            c.push(Segment::Line(self.pen, to));
        }
        self.pen = to;
    }
    fn quad_to(&mut self, x1: f32, y1: f32, x: f32, y: f32) {
        let (control, to) = (self.at(x1, y1), self.at(x, y));
        if let Some(c) = self.contours.last_mut() {
            c.push(Segment::Quad(self.pen, control, to));
        }
        self.pen = to;
    }
    fn curve_to(&mut self, _: f32, _: f32, _: f32, _: f32, x: f32, y: f32) {
        self.cubic = true;
        self.pen = self.at(x, y);
    }
    fn close(&mut self) {}
}

/// Whether the face draws its glyphs with cubic curves (CFF or CFF2 outlines, no `glyf`).
pub fn is_cubic(face: &ttf_parser::Face<'_>) -> bool {
    let tables = face.tables();
    tables.glyf.is_none() && (tables.cff.is_some() || tables.cff2.is_some())
}

/// The glyphs of `params.text` in `data`'s face `index`, placed as OpenSCAD places them.
pub fn layout(
    data: &[u8],
    index: u32,
    params: &TextParams<'_>,
) -> Result<Vec<PlacedGlyph>, LayoutError> {
    let face = rustybuzz::Face::from_slice(data, index)
        .ok_or_else(|| LayoutError::Unreadable("the font file cannot be parsed".into()))?;
    if is_cubic(&face) {
        return Err(LayoutError::Cubic);
    }
    let upem = f64::from(face.units_per_em());
    let scale = params.size / 0.72 / upem;
    let advance_scale = scale * ADVANCE_RATIO;
    let mut buffer = rustybuzz::UnicodeBuffer::new();
    buffer.push_str(params.text);
    if let Some(script) = params.script.and_then(|s| {
        let bytes = s.as_bytes();
        (bytes.len() == 4)
            .then(|| {
                rustybuzz::Script::from_iso15924_tag(ttf_parser::Tag::from_bytes(&[
                    bytes[0].to_ascii_uppercase(),
                    bytes[1].to_ascii_lowercase(),
                    bytes[2].to_ascii_lowercase(),
                    bytes[3].to_ascii_lowercase(),
                ]))
            })
            .flatten()
    }) {
        buffer.set_script(script);
    }
    // Language tags are ASCII (BCP 47); rustybuzz's parser slices the text by bytes and panics
    // inside a multi-byte character, so anything else is no language.
    if let Some(language) = params
        .language
        .filter(|l| l.is_ascii())
        .and_then(|l| l.parse().ok())
    {
        buffer.set_language(language);
    }
    buffer.guess_segment_properties();
    if let Some(direction) = params.direction {
        buffer.set_direction(direction);
    }
    let horizontal = matches!(
        buffer.direction(),
        rustybuzz::Direction::LeftToRight
            | rustybuzz::Direction::RightToLeft
            | rustybuzz::Direction::Invalid
    );
    let shaped = rustybuzz::shape(&face, &[], buffer);
    let infos = shaped.glyph_infos();
    let mut positions: Vec<Position> = shaped
        .glyph_positions()
        .iter()
        .map(|p| Position {
            x_advance: f64::from(p.x_advance),
            y_advance: f64::from(p.y_advance),
            x_offset: f64::from(p.x_offset),
            y_offset: f64::from(p.y_offset),
        })
        .collect();
    if !horizontal {
        freetype_vertical_metrics(&face, infos, &mut positions);
    }

    // The extents OpenSCAD aligns by: advances and the glyphs' control boxes, at 1000/1024.
    let (mut width, mut ascend, mut descend) = (0.0_f64, 0.0_f64, 0.0_f64);
    for (info, pos) in infos.iter().zip(&positions) {
        let bbox = face.glyph_bounding_box(ttf_parser::GlyphId(info.glyph_id as u16));
        if horizontal {
            width += pos.x_advance * advance_scale * params.spacing;
            if let Some(b) = bbox {
                ascend = ascend.max(f64::from(b.y_max) * advance_scale);
                descend = descend.max(-f64::from(b.y_min) * advance_scale);
            }
        } else {
            if let Some(b) = bbox {
                width = width.max(f64::from(b.x_max - b.x_min) * advance_scale);
            }
            ascend += pos.y_advance * advance_scale * params.spacing;
        }
    }
    let x_offset = match params.halign {
        HAlign::Left => 0.0,
        HAlign::Center => -width / 2.0,
        HAlign::Right => -width,
    };
    let y_offset = match params.valign {
        VAlign::Baseline => 0.0,
        VAlign::Top => -ascend,
        VAlign::Center => descend / 2.0 - ascend / 2.0,
        VAlign::Bottom => descend,
    };

    let mut placed = Vec::with_capacity(infos.len());
    let mut advance = DVec2::ZERO;
    for (info, pos) in infos.iter().zip(&positions) {
        let offset = DVec2::new(
            x_offset + pos.x_offset * advance_scale,
            y_offset + pos.y_offset * advance_scale,
        ) + advance;
        let mut outline = Outline {
            scale,
            contours: Vec::new(),
            pen: DVec2::ZERO,
            cubic: false,
        };
        let id = info.glyph_id as u16;
        face.outline_glyph(ttf_parser::GlyphId(id), &mut outline);
        if outline.cubic {
            return Err(LayoutError::Cubic);
        }
        advance += DVec2::new(pos.x_advance, pos.y_advance) * advance_scale * params.spacing;
        outline.contours.retain(|c| !c.is_empty());
        if !outline.contours.is_empty() {
            placed.push(PlacedGlyph {
                id,
                contours: outline.contours,
                origin: offset,
                cluster: info.cluster,
            });
        }
    }
    Ok(placed)
}

/// A glyph's advance and offset from shaping, in font units.
struct Position {
    x_advance: f64,
    y_advance: f64,
    x_offset: f64,
    y_offset: f64,
}

/// Vertical text as OpenSCAD's HarfBuzz places it through FreeType, for a font with no vertical
/// metrics table (most Latin fonts): FreeType makes up an advance of `sTypoAscender −
/// sTypoDescender` (hhea's ascender and descender without an OS/2 table) for every glyph and
/// centres the glyph's box within it, and HarfBuzz puts the glyph's vertical origin half its
/// horizontal advance left of it and that far above its top. HarfBuzz's own vertical metrics
/// (rustybuzz's) take hhea's values and the ascender as origin instead, a few tenths of an em
/// away; a font with a `vmtx` table keeps them, as FreeType then reads the same table.
fn freetype_vertical_metrics(
    face: &ttf_parser::Face<'_>,
    infos: &[rustybuzz::GlyphInfo],
    positions: &mut [Position],
) {
    if face.tables().vmtx.is_some() {
        return;
    }
    let (ascender, descender) = match (face.typographic_ascender(), face.typographic_descender()) {
        (Some(a), Some(d)) => (i32::from(a), i32::from(d)),
        _ => (
            i32::from(face.tables().hhea.ascender),
            i32::from(face.tables().hhea.descender),
        ),
    };
    let advance = (ascender - descender).abs();
    for (info, pos) in infos.iter().zip(positions.iter_mut()) {
        let glyph = ttf_parser::GlyphId(info.glyph_id as u16);
        let horizontal = i32::from(face.glyph_hor_advance(glyph).unwrap_or(0));
        let (top, height) = face.glyph_bounding_box(glyph).map_or((0, 0), |b| {
            (i32::from(b.y_max), i32::from(b.y_max) - i32::from(b.y_min))
        });
        // FreeType's top side bearing: half the room the box leaves in the advance, in whole
        // font units (C's division, towards zero); the horizontal half is taken after scaling.
        let bearing = (advance - height) / 2;
        pos.x_offset = -f64::from(horizontal) / 2.0;
        pos.y_offset = -f64::from(top + bearing);
        pos.x_advance = 0.0;
        pos.y_advance = -f64::from(advance);
    }
}
