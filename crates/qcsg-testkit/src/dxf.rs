//! DXF drawings written by tests: an ENTITIES section of lines, arcs, circles and ellipses, each
//! on a layer. Every value is written with `{:?}`, which reads back as the same `f64`, so that a
//! test states the exact geometry the reader sees.

/// One entity: its kind, its layer and its `(group code, value)` pairs.
#[derive(Clone, Debug, PartialEq)]
pub struct Entity {
    kind: &'static str,
    layer: String,
    pairs: Vec<(i32, f64)>,
}

impl Entity {
    /// The entity on `layer` instead of layer `0`.
    pub fn on(mut self, layer: &str) -> Self {
        self.layer = layer.to_owned();
        self
    }

    fn new(kind: &'static str, pairs: Vec<(i32, f64)>) -> Self {
        Self {
            kind,
            layer: "0".to_owned(),
            pairs,
        }
    }
}

/// A LINE from `a` to `b` on layer `0`.
pub fn line(a: [f64; 2], b: [f64; 2]) -> Entity {
    Entity::new("LINE", vec![(10, a[0]), (20, a[1]), (11, b[0]), (21, b[1])])
}

/// An ARC about `centre` from angle `start` to `stop` (degrees, counter-clockwise) on layer `0`.
pub fn arc(centre: [f64; 2], radius: f64, start: f64, stop: f64) -> Entity {
    Entity::new(
        "ARC",
        vec![
            (10, centre[0]),
            (20, centre[1]),
            (40, radius),
            (50, start),
            (51, stop),
        ],
    )
}

/// A CIRCLE on layer `0`.
pub fn circle(centre: [f64; 2], radius: f64) -> Entity {
    Entity::new(
        "CIRCLE",
        vec![(10, centre[0]), (20, centre[1]), (40, radius)],
    )
}

/// An ELLIPSE on layer `0`: its centre, the vector from the centre to the end of its major axis,
/// the ratio of its minor axis to its major one, and the parameters (radians) where it starts
/// and stops.
pub fn ellipse(centre: [f64; 2], major: [f64; 2], ratio: f64, start: f64, stop: f64) -> Entity {
    Entity::new(
        "ELLIPSE",
        vec![
            (10, centre[0]),
            (20, centre[1]),
            (11, major[0]),
            (21, major[1]),
            (40, ratio),
            (41, start),
            (42, stop),
        ],
    )
}

/// The text of a DXF file holding `entities`.
pub fn dxf(entities: &[Entity]) -> String {
    let mut text = String::from("  0\nSECTION\n  2\nENTITIES\n");
    for Entity { kind, layer, pairs } in entities {
        text.push_str(&format!("  0\n{kind}\n  8\n{layer}\n"));
        for (code, value) in pairs {
            text.push_str(&format!(" {code}\n{value:?}\n"));
        }
    }
    text.push_str("  0\nENDSEC\n  0\nEOF\n");
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entities_are_written_as_group_code_pairs() {
        let text = dxf(&[
            circle([1.0, -2.5], 0.1),
            line([0.0, 0.0], [3.0, 4.0]).on("b"),
        ]);
        assert_eq!(
            text,
            "  0\nSECTION\n  2\nENTITIES\n\
             \x20 0\nCIRCLE\n  8\n0\n 10\n1.0\n 20\n-2.5\n 40\n0.1\n\
             \x20 0\nLINE\n  8\nb\n 10\n0.0\n 20\n0.0\n 11\n3.0\n 21\n4.0\n\
             \x20 0\nENDSEC\n  0\nEOF\n"
        );
    }
}
