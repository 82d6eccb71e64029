//! The matrices of `translate`, `rotate`, `scale`, `mirror`, `multmatrix` and `resize`, with
//! OpenSCAD 2021.01's conventions and fallbacks.
//!
//! Rotations use the degree functions of [`crate::math`], so multiples of 90° give matrices with
//! entries exactly 0 and ±1 and `rotate(90)` maps axis-aligned quadrics to axis-aligned ones.

use glam::{DMat4, DVec3, DVec4};
use qcsg_csg::{Dag, Edge, NodeKind};

use crate::math::{cos_degrees, sin_degrees};
use crate::value::Value;

/// A transform's matrix, or why the arguments are unusable. Warnings go to `warnings`.
pub type MatrixResult = Result<DMat4, String>;

fn from_rows(r: [[f64; 4]; 4]) -> DMat4 {
    DMat4::from_cols(
        DVec4::new(r[0][0], r[1][0], r[2][0], r[3][0]),
        DVec4::new(r[0][1], r[1][1], r[2][1], r[3][1]),
        DVec4::new(r[0][2], r[1][2], r[2][2], r[3][2]),
        DVec4::new(r[0][3], r[1][3], r[2][3], r[3][3]),
    )
}

fn linear(m: [[f64; 3]; 3]) -> DMat4 {
    from_rows([
        [m[0][0], m[0][1], m[0][2], 0.0],
        [m[1][0], m[1][1], m[1][2], 0.0],
        [m[2][0], m[2][1], m[2][2], 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ])
}

/// `translate(v)`: a 2-vector moves in the XY plane.
pub fn translate(v: &Value<'_>) -> MatrixResult {
    let t = v
        .as_vec3(0.0)
        .ok_or("translate(v) needs a vector of 2 or 3 numbers")?;
    Ok(DMat4::from_translation(DVec3::from_array(t)))
}

/// `scale(v)`: a number scales uniformly; a 2-vector leaves Z alone.
pub fn scale(v: &Value<'_>) -> MatrixResult {
    let s = match v {
        Value::Number(s) => [*s; 3],
        Value::Undef => [1.0; 3],
        other => other
            .as_vec3(1.0)
            .ok_or("scale(v) needs a number or a vector of 2 or 3 numbers")?,
    };
    Ok(DMat4::from_scale(DVec3::from_array(s)))
}

/// `mirror(v)`: reflection across the plane through the origin with normal `v`; a zero
/// normal is the identity, as in OpenSCAD.
pub fn mirror(v: &Value<'_>) -> MatrixResult {
    let [mut x, mut y, mut z] = v
        .as_vec3(0.0)
        .ok_or("mirror(v) needs a vector of 2 or 3 numbers")?;
    if x == 0.0 && y == 0.0 && z == 0.0 {
        return Ok(DMat4::IDENTITY);
    }
    let sn = 1.0 / (x * x + y * y + z * z).sqrt();
    x *= sn;
    y *= sn;
    z *= sn;
    Ok(linear([
        [1.0 - 2.0 * x * x, -2.0 * y * x, -2.0 * z * x],
        [-2.0 * x * y, 1.0 - 2.0 * y * y, -2.0 * z * y],
        [-2.0 * x * z, -2.0 * y * z, 1.0 - 2.0 * z * z],
    ]))
}

/// `Rz(z) · Ry(y) · Rx(x)` in degrees.
pub fn rotate_xyz(x: f64, y: f64, z: f64) -> DMat4 {
    let (sx, cx) = (sin_degrees(x), cos_degrees(x));
    let (sy, cy) = (sin_degrees(y), cos_degrees(y));
    let (sz, cz) = (sin_degrees(z), cos_degrees(z));
    linear([
        [cy * cz, cz * sx * sy - cx * sz, cx * cz * sy + sx * sz],
        [cy * sz, cx * cz + sx * sy * sz, -cz * sx + cx * sy * sz],
        [-sy, cy * sx, cx * cy],
    ])
}

/// The rotation by `a` degrees about `axis` (Rodrigues, as OpenSCAD writes it: exact for
/// axis-aligned axes and multiples of 90°). A zero axis gives the identity.
pub fn rotate_axis(a: f64, axis: DVec3) -> DMat4 {
    let s = sin_degrees(a);
    let c = cos_degrees(a);
    let m = axis.length_squared();
    if m <= 0.0 {
        return DMat4::IDENTITY;
    }
    let v = axis;
    let cv = v * ((1.0 - c) / m);
    let us = v.normalize() * s;
    linear([
        [cv.x * v.x + c, cv.x * v.y - us.z, cv.x * v.z + us.y],
        [cv.y * v.x + us.z, cv.y * v.y + c, cv.y * v.z - us.x],
        [cv.z * v.x - us.y, cv.z * v.y + us.x, cv.z * v.z + c],
    ])
}

/// `rotate(a, v)`: a vector `a` rotates about X, Y, then Z (and `v` is ignored, with a
/// warning); a number rotates about `v` (default Z).
pub fn rotate(a: &Value<'_>, v: &Value<'_>, warnings: &mut Vec<String>) -> MatrixResult {
    match a {
        Value::Vector(items) => {
            let n = |i: usize| -> Result<f64, String> {
                items
                    .get(i)
                    .and_then(Value::as_number)
                    .ok_or_else(|| "rotate(a) needs numbers as angles".to_string())
            };
            let (x, y, z) = match items.len() {
                0 => (0.0, 0.0, 0.0),
                1 => (n(0)?, 0.0, 0.0),
                2 => (n(0)?, n(1)?, 0.0),
                3 => (n(0)?, n(1)?, n(2)?),
                _ => return Err("rotate(a) needs at most three angles".into()),
            };
            if !matches!(v, Value::Undef) {
                warnings.push("when `a` is a vector of angles, `v` is ignored".into());
            }
            Ok(rotate_xyz(x, y, z))
        }
        Value::Number(angle) => {
            let axis = match v {
                Value::Undef => DVec3::Z,
                other => DVec3::from_array(
                    other
                        .as_vec3(0.0)
                        .ok_or("rotate(a, v) needs an axis of 2 or 3 numbers")?,
                ),
            };
            if axis == DVec3::ZERO {
                warnings.push("rotation about a zero axis is the identity".into());
            }
            Ok(rotate_axis(*angle, axis))
        }
        Value::Undef => Ok(DMat4::IDENTITY),
        other => Err(format!(
            "rotate(a) needs a number or a vector of angles, got {}",
            other.type_name()
        )),
    }
}

/// `multmatrix(m)`: rows of a 4×4 (or 3×4) matrix, missing entries taken from the identity;
/// the matrix is divided by `m[3][3]` when that is not 1, as OpenSCAD does.
pub fn multmatrix(m: &Value<'_>) -> MatrixResult {
    let rows = m
        .as_vector()
        .ok_or("multmatrix(m) needs a matrix (a vector of rows)")?;
    if rows.len() > 4 {
        return Err("multmatrix(m) needs at most 4 rows".into());
    }
    let mut r = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ];
    for (i, row) in rows.iter().enumerate() {
        let row = row
            .as_vector()
            .ok_or("multmatrix(m) needs rows that are vectors")?;
        if row.len() > 4 {
            return Err("multmatrix(m) needs rows of at most 4 numbers".into());
        }
        for (j, e) in row.iter().enumerate() {
            r[i][j] = e
                .as_number()
                .ok_or("multmatrix(m) needs a matrix of numbers")?;
        }
    }
    let w = r[3][3];
    let m = from_rows(r);
    Ok(if w != 1.0 { m * (1.0 / w) } else { m })
}

/// `resize(newsize, auto)`: the scale that gives the child's bounding box the new size; zero
/// entries keep the size, or follow the largest scale where `auto` asks for it.
pub fn resize(
    newsize: &Value<'_>,
    auto: &Value<'_>,
    bounds: Option<(DVec3, DVec3)>,
    warnings: &mut Vec<String>,
) -> MatrixResult {
    let size = match newsize {
        Value::Number(n) => [*n; 3],
        other => other
            .as_vec3(0.0)
            .ok_or("resize(newsize) needs a number or a vector of 2 or 3 numbers")?,
    };
    let autosize = match auto {
        Value::Bool(b) => [*b; 3],
        Value::Vector(v) => {
            let mut out = [false; 3];
            for (o, e) in out.iter_mut().zip(v.iter()) {
                *o = e.truthy();
            }
            out
        }
        _ => [false; 3],
    };
    let Some((min, max)) = bounds else {
        warnings.push("resize of a child without finite bounds is not applied".into());
        return Ok(DMat4::IDENTITY);
    };
    let extent = (max - min).to_array();
    let mut scale = [1.0; 3];
    for i in 0..3 {
        if size[i] != 0.0 {
            if extent[i] == 0.0 {
                warnings
                    .push("resize in a direction normal to a flat object is not applied".into());
                return Ok(DMat4::IDENTITY);
            }
            scale[i] = size[i] / extent[i];
        }
    }
    let autoscale = scale[0].max(scale[1]).max(scale[2]);
    for i in 0..3 {
        if size[i] == 0.0 && autosize[i] {
            scale[i] = autoscale;
        }
    }
    Ok(DMat4::from_scale(DVec3::from_array(scale)))
}

/// A box containing the solid behind `edge` (`None` if unbounded or empty): declared node
/// boxes, unions of children, the first child of a difference, transformed corner by corner.
pub fn bounds_of(dag: &Dag, edge: Edge) -> Option<(DVec3, DVec3)> {
    let node = dag.node(edge.child)?;
    let own = node
        .bounds
        .filter(|b| b.is_bounded() && !b.is_empty())
        .map(|b| (b.min, b.max));
    let local = match (&node.kind, own) {
        (_, Some(b)) => Some(b),
        (NodeKind::Union(c), None) => {
            let mut acc: Option<(DVec3, DVec3)> = None;
            for e in c {
                let b = bounds_of(dag, *e)?;
                acc = Some(match acc {
                    Some((lo, hi)) => (lo.min(b.0), hi.max(b.1)),
                    None => b,
                });
            }
            acc
        }
        (NodeKind::Intersection(c), None) => {
            let mut acc: Option<(DVec3, DVec3)> = None;
            for e in c {
                if let Some(b) = bounds_of(dag, *e) {
                    acc = Some(match acc {
                        Some((lo, hi)) => (lo.max(b.0), hi.min(b.1)),
                        None => b,
                    });
                }
            }
            acc
        }
        (NodeKind::Difference(c), None) => c.first().and_then(|e| bounds_of(dag, *e)),
        (NodeKind::Color(_, e) | NodeKind::Highlight(e), None) => bounds_of(dag, *e),
        _ => None,
    }?;
    let m = dag.matrix(edge.transform);
    if m == DMat4::IDENTITY {
        return Some(local);
    }
    if m.row(3) != DVec4::W {
        return None;
    }
    let (lo, hi) = local;
    let mut out_lo = DVec3::splat(f64::INFINITY);
    let mut out_hi = DVec3::splat(f64::NEG_INFINITY);
    for i in 0..8 {
        let corner = DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        );
        let p = m.transform_point3(corner);
        out_lo = out_lo.min(p);
        out_hi = out_hi.max(p);
    }
    Some((out_lo, out_hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn exact(m: &DMat4) -> bool {
        m.to_cols_array()
            .iter()
            .all(|&x| x == 0.0 || x == 1.0 || x == -1.0)
    }

    #[test]
    fn right_angles_are_exact() {
        for a in [90.0, 180.0, 270.0, -90.0, 360.0, 450.0] {
            assert!(exact(&rotate_xyz(a, 0.0, 0.0)), "{a}");
            assert!(exact(&rotate_xyz(0.0, a, a)), "{a}");
            assert!(exact(&rotate_axis(a, DVec3::X)), "{a}");
            assert!(exact(&rotate_axis(a, DVec3::new(0.0, 0.0, 2.0))), "{a}");
        }
        let m = rotate_xyz(0.0, 0.0, 90.0);
        assert_eq!(m.transform_point3(DVec3::X), DVec3::Y);
        let m = rotate_xyz(90.0, 0.0, 0.0);
        assert_eq!(m.transform_point3(DVec3::Y), DVec3::Z);
        // X first, then Z: the X axis goes to Y.
        let m = rotate_xyz(90.0, 0.0, 90.0);
        assert_eq!(m.transform_point3(DVec3::X), DVec3::Y);
        assert_eq!(m.transform_point3(DVec3::Y), DVec3::Z);
    }

    #[test]
    fn mirror_and_matrix_forms() {
        let m = mirror(&Value::vector(vec![Value::Number(1.0), Value::Number(0.0)])).unwrap();
        assert_eq!(
            m.transform_point3(DVec3::new(2.0, 3.0, 4.0)),
            DVec3::new(-2.0, 3.0, 4.0)
        );
        let zero = Value::vector(vec![Value::Number(0.0); 3]);
        assert_eq!(mirror(&zero).unwrap(), DMat4::IDENTITY);
        let row = |xs: &[f64]| Value::vector(xs.iter().map(|x| Value::Number(*x)).collect());
        let m = multmatrix(&Value::vector(vec![
            row(&[1.0, 0.0, 0.0, 5.0]),
            row(&[0.0, 1.0, 0.0, 6.0]),
            row(&[0.0, 0.0, 1.0, 7.0]),
        ]))
        .unwrap();
        assert_eq!(m.transform_point3(DVec3::ZERO), DVec3::new(5.0, 6.0, 7.0));
        let m = multmatrix(&Value::vector(vec![
            row(&[2.0, 0.0, 0.0, 0.0]),
            row(&[0.0, 2.0, 0.0, 0.0]),
            row(&[0.0, 0.0, 2.0, 0.0]),
            row(&[0.0, 0.0, 0.0, 2.0]),
        ]))
        .unwrap();
        assert_eq!(m, DMat4::IDENTITY);
    }

    #[test]
    fn resize_scales_to_the_new_size() {
        let bounds = Some((DVec3::ZERO, DVec3::new(2.0, 4.0, 8.0)));
        let size = Value::vector(vec![
            Value::Number(4.0),
            Value::Number(0.0),
            Value::Number(0.0),
        ]);
        let m = resize(&size, &Value::Bool(true), bounds, &mut Vec::new()).unwrap();
        assert_eq!(m, DMat4::from_scale(DVec3::new(2.0, 2.0, 2.0)));
        let m = resize(&size, &Value::Undef, bounds, &mut Vec::new()).unwrap();
        assert_eq!(m, DMat4::from_scale(DVec3::new(2.0, 1.0, 1.0)));
    }
}
