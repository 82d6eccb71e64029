//! OpenSCAD's `text()` as an exact 2-D shape: TrueType glyph outlines are straight segments and
//! quadratic Bézier arcs, and each arc is a piece of a parabola, so a glyph is a union of convex
//! cells cut by at most a few parabolic cylinders ([`qcsg_mesh::curved`]), all z-invariant.
//!
//! Fonts are found by fontconfig-style names ([`fonts`]); glyphs are shaped and placed with
//! OpenSCAD 2021.01's metrics ([`layout`]). Each glyph is filled with the non-zero rule, as
//! OpenSCAD's Clipper union of the glyph outlines does, and the glyphs are united; a glyph the
//! text repeats is built once and placed again ([`line`]). Every glyph and every cell declares
//! its box, so pruning leaves a far glyph out of every query. The text also records its exact
//! complement as cells ([`complement`]), for engraving.

mod complement;
pub mod fonts;
pub mod layout;
mod line;

use qcsg_csg::{Dag, Edge, NodeId, Source};
use qcsg_mesh::curved::CurvedRegion;
use qcsg_quadric::Quadric;

use crate::polygon::half_space;
use crate::primitives::ArgLookup;
use crate::primitives_2d::column;
use crate::value::Value;
use layout::{HAlign, LayoutError, TextParams, VAlign};

/// A warning of a `text()` call and the argument it is about.
pub struct TextWarning {
    /// `"font"` for a font that was not found, `"text"` for missing glyphs, or the argument
    /// whose value is ignored.
    pub argument: &'static str,
    /// The message.
    pub message: String,
    /// Whether it is a missing glyph or font (as opposed to an ignored argument value).
    pub kind: TextWarningKind,
}

/// What a [`TextWarning`] is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TextWarningKind {
    /// No installed font has the family: the default font is used.
    FontNotFound,
    /// Characters the font has no glyph for: its missing-glyph shape is drawn.
    MissingGlyph,
    /// An argument value OpenSCAD ignores.
    Ignored,
    /// A size that makes the text empty.
    Empty,
}

/// Why a `text()` call was refused, and at which argument.
pub struct TextFailure {
    /// The argument the message is about (`"font"`, `"size"`, `"text"`).
    pub argument: &'static str,
    /// The message.
    pub message: String,
    /// Whether it is a limit (more glyphs than allowed).
    pub limit: bool,
}

/// A built text: its node (`None` when empty) and the warnings.
pub struct BuiltText {
    /// The union of the glyphs, or `None` when nothing is drawn.
    pub node: Option<NodeId>,
    /// Fonts not found, missing glyphs, ignored values.
    pub warnings: Vec<TextWarning>,
}

fn string_arg<'v>(args: &'v Value<'_>) -> Option<&'v str> {
    match args {
        Value::String(s) => Some(s),
        _ => None,
    }
}

/// `text(text, size, font, halign, valign, spacing, direction, language, script)`, with at most
/// `max_glyphs` glyphs; `font` is looked for among the `registered` fonts first.
pub fn text(
    dag: &mut Dag,
    args: &dyn ArgLookup<'_>,
    max_glyphs: usize,
    registered: &fonts::RegisteredFonts,
    source: Source,
) -> Result<BuiltText, TextFailure> {
    let mut warnings = Vec::new();
    let mut ignored = |argument: &'static str, message: String| {
        warnings.push(TextWarning {
            argument,
            message,
            kind: TextWarningKind::Ignored,
        })
    };
    let text_value = args.get("text");
    let text: String = match &text_value {
        Value::String(s) => s.to_string(),
        Value::Undef => String::new(),
        other => {
            ignored(
                "text",
                format!(
                    "text() needs a string, got {}: nothing is drawn, as in OpenSCAD",
                    other.type_name()
                ),
            );
            String::new()
        }
    };
    let number = |name: &str, default: f64| match args.get(name) {
        Value::Undef => Some(default),
        v => v.as_number(),
    };
    let size = number("size", 10.0);
    let spacing = number("spacing", 1.0);
    let (Some(size), Some(spacing)) = (size, spacing) else {
        return Err(TextFailure {
            argument: if size.is_none() { "size" } else { "spacing" },
            message: "text(size, spacing) need numbers".into(),
            limit: false,
        });
    };
    let halign_value = args.get("halign");
    let halign = match string_arg(&halign_value).unwrap_or("left") {
        "left" => HAlign::Left,
        "center" => HAlign::Center,
        "right" => HAlign::Right,
        other => {
            ignored(
                "halign",
                format!(
                    "unknown halign \"{other}\" (use \"left\", \"right\" or \"center\"): \"left\" is used, as in OpenSCAD"
                ),
            );
            HAlign::Left
        }
    };
    let valign_value = args.get("valign");
    let valign = match string_arg(&valign_value).unwrap_or("baseline") {
        "baseline" => VAlign::Baseline,
        "top" => VAlign::Top,
        "center" => VAlign::Center,
        "bottom" => VAlign::Bottom,
        other => {
            ignored(
                "valign",
                format!(
                    "unknown valign \"{other}\" (use \"baseline\", \"bottom\", \"top\" or \"center\"): \"baseline\" is used, as in OpenSCAD"
                ),
            );
            VAlign::Baseline
        }
    };
    let direction_value = args.get("direction");
    let direction = match string_arg(&direction_value) {
        None => None,
        Some(d) => match d.to_ascii_lowercase().as_str() {
            "ltr" => Some(rustybuzz::Direction::LeftToRight),
            "rtl" => Some(rustybuzz::Direction::RightToLeft),
            "ttb" => Some(rustybuzz::Direction::TopToBottom),
            "btt" => Some(rustybuzz::Direction::BottomToTop),
            _ => {
                ignored(
                    "direction",
                    format!(
                        "unknown direction \"{d}\" (use \"ltr\", \"rtl\", \"ttb\" or \"btt\"): the script's direction is used, as in OpenSCAD"
                    ),
                );
                None
            }
        },
    };
    let language_value = args.get("language");
    let script_value = args.get("script");
    let font_value = args.get("font");
    let font_name = string_arg(&font_value).unwrap_or("");

    if text.is_empty() {
        return Ok(BuiltText {
            node: None,
            warnings,
        });
    }
    if size.is_nan() || size <= 0.0 || !size.is_finite() || !spacing.is_finite() {
        warnings.push(TextWarning {
            argument: "size",
            message: format!(
                "text(size = {size}, spacing = {spacing}) draws nothing: the size must be a positive number"
            ),
            kind: TextWarningKind::Empty,
        });
        return Ok(BuiltText {
            node: None,
            warnings,
        });
    }
    if text.chars().count() > max_glyphs {
        return Err(TextFailure {
            argument: "text",
            message: format!(
                "the text has {} characters, more than the limit of {max_glyphs} glyphs",
                text.chars().count()
            ),
            limit: true,
        });
    }

    let name = fonts::parse_name(font_name);
    let font = match fonts::find_with(&name, registered) {
        Some(found) => found,
        None => {
            warnings.push(TextWarning {
                argument: "font",
                message: format!(
                    "no installed font has the family of \"{font_name}\": {} is used",
                    fonts::DEFAULT_FAMILY
                ),
                kind: TextWarningKind::FontNotFound,
            });
            fonts::bundled()
        }
    };
    if let Ok(face) = ttf_parser::Face::parse(&font.data, font.index) {
        let missing: String = text
            .chars()
            .filter(|&c| !c.is_control() && face.glyph_index(c).is_none())
            .take(16)
            .collect();
        if !missing.is_empty() {
            warnings.push(TextWarning {
                argument: "text",
                message: format!(
                    "the font {} {} has no glyph for \"{missing}\": its missing-glyph shape is drawn, as in OpenSCAD",
                    font.family, font.style
                ),
                kind: TextWarningKind::MissingGlyph,
            });
        }
    }
    let params = TextParams {
        text: &text,
        size,
        spacing,
        halign,
        valign,
        direction,
        language: string_arg(&language_value),
        script: string_arg(&script_value),
    };
    let glyphs = layout::layout(&font.data, font.index, &params).map_err(|e| TextFailure {
        argument: "font",
        message: match e {
            LayoutError::Cubic => format!(
                "the font {} {} draws its glyphs with cubic (CFF) curves, which are not quadrics; use a TrueType font such as \"Liberation Sans\", \"Liberation Serif\" or \"DejaVu Sans\"",
                font.family, font.style
            ),
            LayoutError::Unreadable(m) => format!("the font {} {}: {m}", font.family, font.style),
        },
        limit: false,
    })?;
    let node = match line::build_line(dag, &glyphs, source)? {
        Some((node, complement)) => {
            if let Some(complement) = complement {
                dag.set_complement(node, complement);
            }
            Some(node)
        }
        None => None,
    };
    Ok(BuiltText { node, warnings })
}

/// The z-invariant solid `Q ≤ 0` of one side of an arc's parabola.
fn parabola_side(arc: &qcsg_mesh::curved::BezierArc, inside: bool) -> Option<Quadric> {
    // The parabola does not depend on the arc's direction; its ends in a fixed order give the
    // same coefficients, bit for bit, to an arc and its reverse (the text's complement may trace
    // a glyph backwards).
    let mut arc = *arc;
    if (arc.p2.x, arc.p2.y) < (arc.p0.x, arc.p0.y) {
        std::mem::swap(&mut arc.p0, &mut arc.p2);
    }
    let origin = (arc.p0 + arc.p1 + arc.p2) / 3.0;
    let [xx, yy, xy, x, y, c] = arc.conic(origin);
    let s = if inside { 1.0 } else { -1.0 };
    Quadric::new(
        origin.extend(0.0),
        [
            s * xx,
            s * yy,
            0.0,
            s * xy / 2.0,
            0.0,
            0.0,
            s * x / 2.0,
            s * y / 2.0,
            0.0,
            s * c,
        ],
    )
}

/// The part of the plane between two values of one coordinate.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Strip {
    /// The coordinate: 0 for x, 1 for y.
    pub axis: usize,
    /// Its least value in the strip.
    pub lo: f64,
    /// Its greatest value in the strip.
    pub hi: f64,
}

/// The union of a curved region's cells, each the intersection of its half-spaces and parabola
/// sides within its box, cut back to `clip` where given; `None` for an empty region.
pub(crate) fn region_node(
    dag: &mut Dag,
    region: &CurvedRegion,
    clip: Option<Strip>,
    source: Source,
) -> Result<Option<NodeId>, String> {
    let (mut region_min, mut region_max) = (region.min, region.max);
    if let Some(Strip { axis, lo, hi }) = clip {
        region_min[axis] = region_min[axis].max(lo);
        region_max[axis] = region_max[axis].min(hi);
    }
    let mut cells: Vec<Edge> = Vec::with_capacity(region.cells.len());
    for cell in &region.cells {
        let (mut min, mut max) = (cell.min, cell.max);
        let mut sides: Vec<Edge> =
            Vec::with_capacity(cell.half_planes.len() + cell.sides.len() + 2);
        if let Some(Strip { axis, lo, hi }) = clip {
            if max[axis] <= lo || min[axis] >= hi {
                continue;
            }
            let unrepresentable = "a wall of the text's complement is not representable";
            if min[axis] < lo {
                sides.push(
                    complement::axis_wall(dag, axis, false, lo, source).ok_or(unrepresentable)?,
                );
                min[axis] = lo;
            }
            if max[axis] > hi {
                sides.push(
                    complement::axis_wall(dag, axis, true, hi, source).ok_or(unrepresentable)?,
                );
                max[axis] = hi;
            }
        }
        for h in &cell.half_planes {
            let q = half_space(h).ok_or("an edge of the glyph is not representable")?;
            sides.push(dag.leaf(q, source).into());
        }
        for side in &cell.sides {
            let q = parabola_side(&region.arcs[side.arc], side.inside)
                .ok_or("an arc of the glyph is not representable")?;
            sides.push(dag.leaf(q, source).into());
        }
        let node = dag.intersection(sides, source);
        cells.push(dag.bounded(node, column(min, max)).into());
    }
    Ok(match cells.len() {
        0 => None,
        1 => Some(cells[0].child),
        _ => {
            let node = dag.union(cells, source);
            Some(dag.bounded(node, column(region_min, region_max)))
        }
    })
}
