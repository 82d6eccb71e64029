//! Preview images of qcsg solids.
//!
//! The pipeline: a [`Scene`] (the solid's [`Dnf`](qcsg_csg::Dnf) plus the translucent layers of
//! `#` highlighted and `%` background parts) is looked at through a [`Camera`] (perspective or
//! orthographic; named views fitted to the scene's bounds, or an explicit eye and centre), each
//! pixel's ray is classified exactly against the DNF by the CPU reference ray tracer
//! ([`raytrace`]), the hit is shaded ([`shade`]) and the frame is written as PNG ([`png`]).
//!
//! The ray tracer works in f64 and computes every pixel independently of the others, so a
//! frame (colour, depth and primitive ids) is byte-identical for any number of threads. Its
//! depth and id buffers are the ground truth that the splat renderer is compared against.
//!
//! ```
//! use qcsg_csg::{Dag, DnfOptions, Source, build_dnf};
//! use qcsg_quadric::{DVec3, Quadric};
//! use qcsg_render::{Camera, ImageSize, RenderOptions, Scene, View, render};
//!
//! let mut dag = Dag::new();
//! let ball = dag.bounded_leaf(
//!     Quadric::sphere(DVec3::ZERO, 1.0).unwrap(),
//!     Source::default(),
//!     qcsg_csg::Aabb::new(DVec3::splat(-1.0), DVec3::splat(1.0)),
//! );
//! dag.set_root(ball.into());
//! let scene = Scene::new(build_dnf(&dag, &DnfOptions::default()).unwrap());
//! let size = ImageSize::new(32, 24).unwrap();
//! let camera = Camera::fit(&View::Iso, Default::default(), &scene.bounds(), size).unwrap();
//! let frame = render(&scene, &camera, size, &RenderOptions::default(), &|_| {});
//! assert!(frame.hit_count() > 0);
//! let png = qcsg_render::png::encode(&frame).unwrap();
//! assert!(png.starts_with(b"\x89PNG"));
//! ```

pub mod camera;
mod cull;
pub mod eye;
pub mod frame;
pub mod interval;
pub mod png;
pub mod raytrace;
pub mod scene;
pub mod shade;
pub mod tiles;

pub use camera::{Camera, CameraError, ImageSize, Projection, View};
pub use frame::{
    Frame, LayerHits, Pixel, PixelId, RenderOptions, frame_from_pixels, render, shade_pixel,
};
pub use raytrace::{Hit, Ray, trace};
pub use scene::Scene;
