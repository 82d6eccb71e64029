//! Shading: colours of the scene (OpenSCAD's "Cornfield" preview scheme) and a camera-attached
//! light rig (a headlight plus a key light from the upper left, over ambient light), so that
//! every face the camera sees is lit and faces at different angles read apart.

use qcsg_quadric::DVec3;

use crate::camera::Camera;

/// A linear RGB colour, components in `[0, 1]`.
pub type Rgb = [f64; 3];

/// The image background: OpenSCAD's light yellow (#FFFFE5).
pub const BACKGROUND: Rgb = [1.0, 1.0, 229.0 / 255.0];
/// Parts without `color()`: OpenSCAD's preview yellow (#F9D72C).
pub const DEFAULT_COLOR: Rgb = [249.0 / 255.0, 215.0 / 255.0, 44.0 / 255.0];
/// `#` highlighted parts: OpenSCAD's highlight pink (#FF5151).
pub const HIGHLIGHT_COLOR: Rgb = [1.0, 81.0 / 255.0, 81.0 / 255.0];
/// How opaque the translucent highlight layer is.
pub const HIGHLIGHT_ALPHA: f64 = 0.5;
/// `%` background parts: OpenSCAD's translucent grey (#B4B4B4).
pub const BACKGROUND_PART_COLOR: Rgb = [180.0 / 255.0, 180.0 / 255.0, 180.0 / 255.0];
/// How opaque the background-part layer is.
pub const BACKGROUND_PART_ALPHA: f64 = 0.35;

const AMBIENT: f64 = 0.3;
const HEADLIGHT: f64 = 0.5;
const KEY: f64 = 0.3;
const SPECULAR: f64 = 0.12;
const SHININESS: i32 = 24;

/// The lit colour of a surface point with base colour `base`, outward unit `normal`, seen along
/// the unit `view` direction (from the eye towards the point). Two-sided: a normal facing
/// away from the eye is flipped, so that grazing rounding never paints a face black.
pub fn shade(base: Rgb, normal: DVec3, view: DVec3, camera: &Camera) -> Rgb {
    let normal = if normal.dot(view) > 0.0 {
        -normal
    } else {
        normal
    };
    let to_eye = -view;
    let key = (to_eye + 0.6 * camera.up() - 0.5 * camera.right()).normalize();
    let diffuse =
        AMBIENT + HEADLIGHT * normal.dot(to_eye).max(0.0) + KEY * normal.dot(key).max(0.0);
    // Blinn-Phong highlight of the key light, white.
    let half = (key + to_eye).normalize();
    let specular = SPECULAR * normal.dot(half).max(0.0).powi(SHININESS);
    base.map(|c| (c * diffuse + specular).clamp(0.0, 1.0))
}

/// `over` with opacity `alpha` composited over `under`.
pub fn blend(under: Rgb, over: Rgb, alpha: f64) -> Rgb {
    [0, 1, 2].map(|k| under[k] * (1.0 - alpha) + over[k] * alpha)
}

/// A colour as 8-bit components, rounded.
pub fn to_rgb8(color: Rgb) -> [u8; 3] {
    color.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{ImageSize, Projection};

    #[test]
    fn faces_towards_the_eye_are_brightest_and_back_faces_are_lit() {
        let camera = Camera::look_at(
            DVec3::new(0.0, -5.0, 0.0),
            DVec3::ZERO,
            Projection::Perspective,
            0.3,
            ImageSize::new(4, 4).unwrap(),
        )
        .unwrap();
        let view = DVec3::Y;
        let facing = shade(DEFAULT_COLOR, -DVec3::Y, view, &camera);
        let grazing = shade(DEFAULT_COLOR, DVec3::X, view, &camera);
        let back = shade(DEFAULT_COLOR, DVec3::Y, view, &camera);
        assert!(facing[0] > grazing[0]);
        assert_eq!(facing, back);
        assert!(grazing.iter().all(|&c| c >= 0.0));
    }

    #[test]
    fn blending_and_quantising() {
        assert_eq!(blend([0.0; 3], [1.0; 3], 0.25), [0.25; 3]);
        assert_eq!(to_rgb8([0.0, 0.5, 2.0]), [0, 128, 255]);
    }
}
