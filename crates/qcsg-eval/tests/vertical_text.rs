//! `direction = "ttb"` / `"btt"`: glyphs placed with the vertical metrics OpenSCAD 2021.01 gets
//! from FreeType (an advance of the OS/2 typographic ascender minus descender, each glyph's box
//! centred in it), checked at edges measured on OpenSCAD's STL export of the same calls.

mod common;

use common::{membership, p};

#[test]
fn top_to_bottom_glyphs_sit_where_openscad_puts_them() {
    // OpenSCAD: `text("A", size = 10, direction = "ttb")` spans x −4.4962..4.7127, y −11.0269
    // (the flat feet) ..−1.4721 (the flat apex).
    let a = "linear_extrude(1) text(\"A\", size = 10, direction = \"ttb\");";
    membership(
        a,
        &[
            (p(0.108, -1.4921, 0.5), true),
            (p(0.108, -1.4521, 0.5), false),
            (p(-4.30, -11.0069, 0.5), true),
            (p(-4.30, -11.0469, 0.5), false),
        ],
    );
    // The second "A" of "AA" one advance (1922 units of 2048, at 1000/1024 of the outline's
    // scale) lower: its feet at −23.7558.
    let aa = "linear_extrude(1) text(\"AA\", size = 10, direction = \"ttb\");";
    membership(
        aa,
        &[
            (p(-4.30, -23.7358, 0.5), true),
            (p(-4.30, -23.7758, 0.5), false),
            (p(0.108, -14.2210, 0.5), true),
            (p(0.108, -14.1810, 0.5), false),
        ],
    );
    // Bottom to top: the same column, the glyphs in reverse order.
    let btt = "linear_extrude(1) text(\"AV\", size = 10, direction = \"btt\");";
    membership(
        btt,
        &[
            (p(0.108, -1.4921, 0.5), false),
            (p(-4.30, -23.7358, 0.5), true),
        ],
    );
}
