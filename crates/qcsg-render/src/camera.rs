//! Cameras: perspective and orthographic projection, named views fitted to a scene's bounds
//! (OpenSCAD's conventions: Z up), explicit eye/centre cameras, and the image size.

use std::fmt;

use qcsg_csg::Aabb;
use qcsg_quadric::DVec3;

use crate::raytrace::Ray;

/// The largest width or height accepted, so that a typo cannot ask for terabytes.
pub const MAX_DIMENSION: u32 = 16_384;

/// The vertical field of view of perspective cameras, in degrees.
pub const DEFAULT_FOV_DEGREES: f64 = 30.0;

/// How much room fitted views leave around the scene's bounding sphere (1 = touching).
const FIT_MARGIN: f64 = 1.1;

/// Why a camera or an image size cannot be made.
#[derive(Clone, Debug, PartialEq)]
pub enum CameraError {
    /// The eye and the centre coincide, so there is no viewing direction.
    EyeAtCentre,
    /// A coordinate is NaN or infinite.
    NotFinite,
    /// The text is not a named view nor six comma-separated numbers.
    BadCameraSyntax(String),
    /// The text is not `W,H` with positive integers.
    BadSize(String),
    /// Zero, or more than [`MAX_DIMENSION`].
    SizeOutOfRange(u32, u32),
}

impl fmt::Display for CameraError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::EyeAtCentre => write!(f, "the camera's eye and centre coincide"),
            Self::NotFinite => write!(f, "the camera's coordinates must be finite numbers"),
            Self::BadCameraSyntax(text) => write!(
                f,
                "invalid camera `{text}`: expected iso, front, top, right or \
                 eye_x,eye_y,eye_z,center_x,center_y,center_z"
            ),
            Self::BadSize(text) => {
                write!(f, "invalid size `{text}`: expected W,H such as 800,600")
            }
            Self::SizeOutOfRange(w, h) => write!(
                f,
                "image size {w}x{h} is out of range: width and height must be 1 to {MAX_DIMENSION}"
            ),
        }
    }
}

impl std::error::Error for CameraError {}

/// The size of an image in pixels, both at least 1 and at most [`MAX_DIMENSION`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageSize {
    width: u32,
    height: u32,
}

impl ImageSize {
    /// The default size of `qcsg render`.
    pub const DEFAULT: ImageSize = ImageSize {
        width: 800,
        height: 600,
    };

    /// A size, if both dimensions are in range.
    pub fn new(width: u32, height: u32) -> Result<Self, CameraError> {
        if (1..=MAX_DIMENSION).contains(&width) && (1..=MAX_DIMENSION).contains(&height) {
            Ok(Self { width, height })
        } else {
            Err(CameraError::SizeOutOfRange(width, height))
        }
    }

    /// Parses `W,H` (also `WxH`).
    pub fn parse(text: &str) -> Result<Self, CameraError> {
        let bad = || CameraError::BadSize(text.to_string());
        let (w, h) = text.split_once([',', 'x']).ok_or_else(bad)?;
        let w: u32 = w.trim().parse().map_err(|_| bad())?;
        let h: u32 = h.trim().parse().map_err(|_| bad())?;
        Self::new(w, h)
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Number of pixels.
    pub fn pixel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// Width over height.
    pub fn aspect(&self) -> f64 {
        f64::from(self.width) / f64::from(self.height)
    }
}

impl Default for ImageSize {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Where the camera looks from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum View {
    /// OpenSCAD's default view: from the front right, above (+x, −y, +z), fitted to the scene.
    Iso,
    /// From −y towards +y, fitted.
    Front,
    /// From +z down, +y up in the image, fitted.
    Top,
    /// From +x towards −x, fitted.
    Right,
    /// An explicit eye and centre (the point looked at).
    Explicit {
        /// The eye position.
        eye: DVec3,
        /// The point at the image centre.
        center: DVec3,
    },
}

impl View {
    /// Parses a named view or `eye_x,eye_y,eye_z,center_x,center_y,center_z`.
    pub fn parse(text: &str) -> Result<Self, CameraError> {
        match text.trim() {
            "iso" => return Ok(Self::Iso),
            "front" => return Ok(Self::Front),
            "top" => return Ok(Self::Top),
            "right" => return Ok(Self::Right),
            _ => {}
        }
        let numbers: Result<Vec<f64>, _> = text.split(',').map(|s| s.trim().parse()).collect();
        match numbers.as_deref() {
            Ok([ex, ey, ez, cx, cy, cz]) => {
                let eye = DVec3::new(*ex, *ey, *ez);
                let center = DVec3::new(*cx, *cy, *cz);
                if !(eye.is_finite() && center.is_finite()) {
                    return Err(CameraError::NotFinite);
                }
                if eye == center {
                    return Err(CameraError::EyeAtCentre);
                }
                Ok(Self::Explicit { eye, center })
            }
            _ => Err(CameraError::BadCameraSyntax(text.to_string())),
        }
    }

    /// The unit direction from the scene's centre towards the eye, for named views.
    fn towards_eye(&self) -> Option<DVec3> {
        match self {
            // OpenSCAD's default gimbal: 55° about x, then 25° about z.
            Self::Iso => {
                let (tilt, turn) = (55f64.to_radians(), 25f64.to_radians());
                Some(DVec3::new(
                    turn.sin() * tilt.sin(),
                    -turn.cos() * tilt.sin(),
                    tilt.cos(),
                ))
            }
            Self::Front => Some(-DVec3::Y),
            Self::Top => Some(DVec3::Z),
            Self::Right => Some(DVec3::X),
            Self::Explicit { .. } => None,
        }
    }
}

/// How the scene is projected onto the image.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Projection {
    /// Rays from the eye, [`DEFAULT_FOV_DEGREES`] vertical field of view.
    #[default]
    Perspective,
    /// Parallel rays along the viewing direction.
    Orthographic,
}

/// A camera: an orthonormal frame at the eye and a projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    eye: DVec3,
    forward: DVec3,
    right: DVec3,
    up: DVec3,
    projection: Projection,
    /// Half the image height on the plane at unit distance (perspective) or in world units
    /// (orthographic).
    half_height: f64,
    aspect: f64,
}

impl Camera {
    /// A camera at `eye` looking at `center` with Z up (Y up when looking along Z).
    /// `half_height` is half the visible height: at unit distance for perspective (the tangent
    /// of half the field of view), in world units for orthographic projection.
    pub fn look_at(
        eye: DVec3,
        center: DVec3,
        projection: Projection,
        half_height: f64,
        size: ImageSize,
    ) -> Result<Self, CameraError> {
        if !(eye.is_finite() && center.is_finite() && half_height.is_finite()) {
            return Err(CameraError::NotFinite);
        }
        let forward = (center - eye)
            .try_normalize()
            .ok_or(CameraError::EyeAtCentre)?;
        let world_up = if forward.cross(DVec3::Z).length() < 1e-6 {
            DVec3::Y
        } else {
            DVec3::Z
        };
        let right = forward.cross(world_up).normalize();
        let up = right.cross(forward);
        let half_height = if half_height > 0.0 { half_height } else { 1.0 };
        Ok(Self {
            eye,
            forward,
            right,
            up,
            projection,
            half_height,
            aspect: size.aspect(),
        })
    }

    /// The camera for `view`, fitted so that `bounds` (plus a margin) fills the image; an empty
    /// or unbounded box is replaced by the unit cube around the origin.
    pub fn fit(
        view: &View,
        projection: Projection,
        bounds: &Aabb,
        size: ImageSize,
    ) -> Result<Self, CameraError> {
        let bounds = if bounds.is_empty() || !bounds.is_bounded() {
            Aabb::new(DVec3::splat(-1.0), DVec3::splat(1.0))
        } else {
            *bounds
        };
        let centre = bounds.centre();
        let radius = bounds
            .half_diagonal()
            .max(1e-9 * centre.abs().max_element())
            .max(1e-300);
        let tan_half = (0.5 * DEFAULT_FOV_DEGREES.to_radians()).tan();
        match view {
            View::Explicit { eye, center } => {
                let half_height = match projection {
                    Projection::Perspective => tan_half,
                    Projection::Orthographic => FIT_MARGIN * radius,
                };
                Self::look_at(*eye, *center, projection, half_height, size)
            }
            named => {
                let towards_eye = named.towards_eye().unwrap_or(DVec3::Z);
                // The sphere must fit the narrower of the two fields of view.
                let tan_narrow = tan_half * size.aspect().min(1.0);
                let sin_narrow = tan_narrow / (1.0 + tan_narrow * tan_narrow).sqrt();
                let distance = FIT_MARGIN * radius / sin_narrow;
                let eye = centre + distance * towards_eye;
                let half_height = match projection {
                    Projection::Perspective => tan_half,
                    Projection::Orthographic => FIT_MARGIN * radius / size.aspect().min(1.0),
                };
                Self::look_at(eye, centre, projection, half_height, size)
            }
        }
    }

    /// The eye position.
    pub fn eye(&self) -> DVec3 {
        self.eye
    }

    /// The unit viewing direction.
    pub fn forward(&self) -> DVec3 {
        self.forward
    }

    /// The unit direction of the image's x axis.
    pub fn right(&self) -> DVec3 {
        self.right
    }

    /// The unit direction of the image's upward axis.
    pub fn up(&self) -> DVec3 {
        self.up
    }

    /// The projection.
    pub fn projection(&self) -> Projection {
        self.projection
    }

    /// Half the image height (at unit distance for perspective, in world units for
    /// orthographic projection) and the width over the height: with the axes, how
    /// [`Camera::ray`] maps pixels to rays.
    pub fn screen_scale(&self) -> (f64, f64) {
        (self.half_height, self.aspect)
    }

    /// The size of one pixel in world units: on the plane at `distance` in front of the eye for
    /// perspective cameras, anywhere for orthographic ones.
    pub fn pixel_footprint(&self, distance: f64, size: ImageSize) -> f64 {
        let pixel = 2.0 * self.half_height / f64::from(size.height());
        match self.projection {
            Projection::Perspective => pixel * distance,
            Projection::Orthographic => pixel,
        }
    }

    /// Half the visible height: at unit distance (perspective) or in world units
    /// (orthographic).
    pub fn half_height(&self) -> f64 {
        self.half_height
    }

    /// Width over height of the image the camera was made for.
    pub fn aspect(&self) -> f64 {
        self.aspect
    }

    /// The ray through the point `(x, y)` of the image, in pixels from the top left corner
    /// (pixel centres at half-integers), with a unit direction; its parameter is the distance
    /// from the eye (perspective) or from the eye's plane (orthographic).
    pub fn ray(&self, x: f64, y: f64, size: ImageSize) -> Ray {
        let sx = (2.0 * x / f64::from(size.width()) - 1.0) * self.half_height * self.aspect;
        let sy = (1.0 - 2.0 * y / f64::from(size.height())) * self.half_height;
        match self.projection {
            Projection::Perspective => Ray {
                origin: self.eye,
                direction: (self.forward + sx * self.right + sy * self.up).normalize(),
            },
            Projection::Orthographic => Ray {
                origin: self.eye + sx * self.right + sy * self.up,
                direction: self.forward,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_and_reject_nonsense() {
        assert_eq!(
            ImageSize::parse("800,600").unwrap(),
            ImageSize::new(800, 600).unwrap()
        );
        assert_eq!(
            ImageSize::parse("64x48").unwrap(),
            ImageSize::new(64, 48).unwrap()
        );
        assert!(ImageSize::parse("0,10").is_err());
        assert!(ImageSize::parse("10").is_err());
        assert!(ImageSize::parse("-1,5").is_err());
        assert!(ImageSize::parse("100000,5").is_err());
    }

    #[test]
    fn views_parse() {
        assert_eq!(View::parse("iso").unwrap(), View::Iso);
        assert_eq!(View::parse("top").unwrap(), View::Top);
        let explicit = View::parse("1,2,3, 0,0,0").unwrap();
        assert_eq!(
            explicit,
            View::Explicit {
                eye: DVec3::new(1.0, 2.0, 3.0),
                center: DVec3::ZERO
            }
        );
        assert_eq!(View::parse("1,1,1,1,1,1"), Err(CameraError::EyeAtCentre));
        assert!(matches!(
            View::parse("sideways"),
            Err(CameraError::BadCameraSyntax(_))
        ));
        assert_eq!(View::parse("nan,0,0,0,0,0"), Err(CameraError::NotFinite));
    }

    #[test]
    fn fitted_views_look_at_the_centre_with_z_up() {
        let size = ImageSize::new(80, 60).unwrap();
        let bounds = Aabb::new(DVec3::new(9.0, 9.0, 9.0), DVec3::new(11.0, 11.0, 11.0));
        for view in [View::Iso, View::Front, View::Top, View::Right] {
            for projection in [Projection::Perspective, Projection::Orthographic] {
                let camera = Camera::fit(&view, projection, &bounds, size).unwrap();
                let centre_ray = camera.ray(40.0, 30.0, size);
                let to_centre = DVec3::splat(10.0) - centre_ray.origin;
                assert!(
                    to_centre.normalize().dot(centre_ray.direction) > 1.0 - 1e-12,
                    "{view:?}"
                );
                assert!(camera.up().z >= 0.0 && camera.up().y >= 0.0, "{view:?}");
            }
        }
        let iso = Camera::fit(&View::Iso, Projection::Perspective, &bounds, size).unwrap();
        let from = iso.eye() - DVec3::splat(10.0);
        assert!(from.x > 0.0 && from.y < 0.0 && from.z > 0.0);
        // The top view's image x axis is +x, its image up is +y.
        let top = Camera::fit(&View::Top, Projection::Perspective, &bounds, size).unwrap();
        assert!(top.right().x > 0.999 && top.up().y > 0.999);
    }

    #[test]
    fn degenerate_bounds_fall_back_to_a_unit_box() {
        let size = ImageSize::new(4, 4).unwrap();
        for bounds in [Aabb::EMPTY, Aabb::EVERYTHING] {
            let camera = Camera::fit(&View::Iso, Projection::Perspective, &bounds, size).unwrap();
            assert!(camera.eye().is_finite());
        }
        let point = Aabb::new(DVec3::ONE, DVec3::ONE);
        let camera = Camera::fit(&View::Front, Projection::Orthographic, &point, size).unwrap();
        assert!(camera.ray(0.0, 0.0, size).origin.is_finite());
    }
}
