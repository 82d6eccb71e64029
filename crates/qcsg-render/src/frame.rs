//! Rendering a frame: one ray per pixel through the solid and the translucent layers, shaded,
//! with the depth and primitive id of the solid's hit kept per pixel.
//!
//! Rows are traced in parallel (rayon) but every pixel depends only on its own ray, and rows
//! are collected in order, so the frame is byte-identical for any number of threads.

use rayon::prelude::*;

use crate::camera::Projection;
use crate::camera::{Camera, ImageSize};
use crate::eye::EyeValues;
use crate::raytrace::{Hit, Ray, Scratch, trace_among};
use crate::scene::{Layer, Scene};
use crate::shade::{self, Rgb};
use crate::tiles::FrameTiles;

/// What the solid's surface is at a pixel: the DNF quadric and the term, or nothing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PixelId {
    /// The quadric's index in the solid's DNF, [`PixelId::NONE`] for a face of a term's box
    /// (a solid cut by the region) or a miss.
    pub quadric: u32,
    /// The term's index in the solid's DNF, [`PixelId::NONE`] for a miss.
    pub term: u32,
}

impl PixelId {
    /// The index that means "none".
    pub const NONE: u32 = u32::MAX;
    /// A pixel that shows no solid.
    pub const MISS: PixelId = PixelId {
        quadric: Self::NONE,
        term: Self::NONE,
    };
}

/// Colours and translucency used by [`render`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    /// The image background.
    pub background: Rgb,
    /// The colour of parts without `color()`.
    pub default_color: Rgb,
    /// The tint of `#` highlighted parts.
    pub highlight_color: Rgb,
    /// The opacity of the highlight layer.
    pub highlight_alpha: f64,
    /// The colour of `%` background parts.
    pub background_part_color: Rgb,
    /// The opacity of the background-part layer.
    pub background_part_alpha: f64,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            background: shade::BACKGROUND,
            default_color: shade::DEFAULT_COLOR,
            highlight_color: shade::HIGHLIGHT_COLOR,
            highlight_alpha: shade::HIGHLIGHT_ALPHA,
            background_part_color: shade::BACKGROUND_PART_COLOR,
            background_part_alpha: shade::BACKGROUND_PART_ALPHA,
        }
    }
}

/// A rendered image with the buffers the splat renderer is compared against.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// The image size.
    pub size: ImageSize,
    /// 8-bit RGB, row-major from the top left, three bytes per pixel.
    pub rgb: Vec<u8>,
    /// Per pixel, the ray parameter of the solid's visible surface (distance from the eye, or
    /// from the eye's plane for orthographic cameras); infinite where the ray misses.
    pub depth: Vec<f64>,
    /// Per pixel, which quadric and term of the solid is visible.
    pub ids: Vec<PixelId>,
}

impl Frame {
    /// An empty frame of `size`, with room for all its pixels, to be filled row by row.
    fn with_capacity(size: ImageSize) -> Self {
        Frame {
            size,
            rgb: Vec::with_capacity(3 * size.pixel_count()),
            depth: Vec::with_capacity(size.pixel_count()),
            ids: Vec::with_capacity(size.pixel_count()),
        }
    }

    /// Number of pixels that show the solid.
    pub fn hit_count(&self) -> usize {
        self.ids
            .iter()
            .filter(|id| id.term != PixelId::NONE)
            .count()
    }

    /// The RGB colour at `(x, y)`.
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 3] {
        let i = 3 * (y as usize * self.size.width() as usize + x as usize);
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }

    /// The index of `(x, y)` in the depth and id buffers.
    pub fn index(&self, x: u32, y: u32) -> usize {
        y as usize * self.size.width() as usize + x as usize
    }
}

/// Renders `scene` through `camera`. `progress` is called once per finished row (from worker
/// threads, in no particular order).
pub fn render(
    scene: &Scene,
    camera: &Camera,
    size: ImageSize,
    options: &RenderOptions,
    progress: &(dyn Fn(u32) + Sync),
) -> Frame {
    // Every ray of a perspective frame starts at the eye: the quadrics' values there are
    // computed once per frame; and each term's box is projected once, to the squares of
    // pixels whose rays may cross it.
    let layers = FrameLayers::new(scene, camera, size);
    let rows: Vec<Row> = (0..size.height())
        .into_par_iter()
        .map_init(Scratch::default, |scratch, y| {
            let row = render_row(scene, camera, size, options, y, &layers, scratch);
            progress(y);
            row
        })
        .collect();
    let mut frame = Frame::with_capacity(size);
    for row in rows {
        frame.rgb.extend(row.rgb);
        frame.depth.extend(row.depth);
        frame.ids.extend(row.ids);
    }
    frame
}

struct Row {
    rgb: Vec<u8>,
    depth: Vec<f64>,
    ids: Vec<PixelId>,
}

fn render_row(
    scene: &Scene,
    camera: &Camera,
    size: ImageSize,
    options: &RenderOptions,
    y: u32,
    layers: &FrameLayers,
    scratch: &mut Scratch,
) -> Row {
    let width = size.width() as usize;
    let mut row = Row {
        rgb: Vec::with_capacity(3 * width),
        depth: Vec::with_capacity(width),
        ids: Vec::with_capacity(width),
    };
    for x in 0..size.width() {
        let ray = camera.ray(f64::from(x) + 0.5, f64::from(y) + 0.5, size);
        let trace = |layer: &Option<Layer>, shared: &LayerFrame, scratch: &mut Scratch| {
            let layer = layer.as_ref()?;
            let square = shared.tiles.as_ref().map(|tiles| tiles.square(x, y));
            trace_among(
                layer.dnf(),
                layer.index(),
                &ray,
                0.0,
                shared.eye.as_ref(),
                square,
                scratch,
            )
        };
        let hits = LayerHits {
            solid: trace(&scene.solid, &layers.solid, scratch),
            highlight: trace(&scene.highlights, &layers.highlights, scratch),
            background: trace(&scene.backgrounds, &layers.backgrounds, scratch),
        };
        let pixel = shade_pixel(scene, camera, options, &ray, &hits);
        row.rgb.extend(pixel.rgb);
        row.depth.push(pixel.depth);
        row.ids.push(pixel.id);
    }
    row
}

/// What one pixel's ray meets first in each layer of a scene.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LayerHits {
    /// The solid's visible surface.
    pub solid: Option<Hit>,
    /// The first surface of the highlighted parts.
    pub highlight: Option<Hit>,
    /// The first surface of the background parts.
    pub background: Option<Hit>,
}

/// One finished pixel: its colour, and the depth and id of the solid there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pixel {
    /// 8-bit RGB.
    pub rgb: [u8; 3],
    /// The solid's ray parameter, infinite for a miss.
    pub depth: f64,
    /// The solid's quadric and term.
    pub id: PixelId,
}

/// Shades one pixel from what its `ray` met in each layer: the solid lit with its colour, then
/// the translucent layers that lie in front of it blended over, the farther one first. Every
/// renderer shades through this function, so that images of the same hits agree exactly.
pub fn shade_pixel(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    ray: &Ray,
    hits: &LayerHits,
) -> Pixel {
    let mut color = options.background;
    let mut depth = f64::INFINITY;
    let mut id = PixelId::MISS;
    if let (Some(solid), Some(hit)) = (&scene.solid, hits.solid) {
        let quadric = hit
            .quadric
            .and_then(|q| solid.dnf().quadrics.get(q as usize));
        let mut base = quadric
            .and_then(|q| q.color)
            .map_or(options.default_color, |c| [c[0], c[1], c[2]]);
        if quadric.is_some_and(|q| q.highlight) {
            base = shade::blend(base, options.highlight_color, options.highlight_alpha);
        }
        color = shade::shade(base, hit.normal, ray.direction, camera);
        depth = hit.t;
        id = PixelId {
            quadric: hit.quadric.unwrap_or(PixelId::NONE),
            term: hit.term,
        };
    }
    // Translucent layers in front of the solid, the farther one first.
    let layers = [
        (
            hits.background,
            options.background_part_color,
            options.background_part_alpha,
        ),
        (
            hits.highlight,
            options.highlight_color,
            options.highlight_alpha,
        ),
    ];
    let mut overlays: [Option<(f64, Rgb, f64)>; 2] = [None, None];
    for (slot, (hit, tint, alpha)) in overlays.iter_mut().zip(layers) {
        if let Some(hit) = hit
            && hit.t < depth
        {
            *slot = Some((
                hit.t,
                shade::shade(tint, hit.normal, ray.direction, camera),
                alpha,
            ));
        }
    }
    // The farther first; a stable sort of the two, without allocating.
    if let [Some(a), Some(b)] = overlays
        && b.0.total_cmp(&a.0).is_gt()
    {
        overlays = [Some(b), Some(a)];
    }
    for (_, over, alpha) in overlays.into_iter().flatten() {
        color = shade::blend(color, over, alpha);
    }
    Pixel {
        rgb: shade::to_rgb8(color),
        depth,
        id,
    }
}

/// Builds a frame from a function of the pixel coordinates, rows in parallel (rayon) and
/// collected in order, so the result does not depend on the number of threads.
pub fn frame_from_pixels(size: ImageSize, pixel: &(dyn Fn(u32, u32) -> Pixel + Sync)) -> Frame {
    let rows: Vec<Vec<Pixel>> = (0..size.height())
        .into_par_iter()
        .map(|y| (0..size.width()).map(|x| pixel(x, y)).collect())
        .collect();
    let mut frame = Frame::with_capacity(size);
    for pixel in rows.into_iter().flatten() {
        frame.rgb.extend(pixel.rgb);
        frame.depth.push(pixel.depth);
        frame.ids.push(pixel.id);
    }
    frame
}

/// What every ray of a frame shares in one layer: the values of its quadrics at a perspective
/// camera's eye (none for orthographic frames, whose rays start at different points), and the
/// terms each square of pixels may see.
#[derive(Default)]
struct LayerFrame {
    eye: Option<EyeValues>,
    tiles: Option<FrameTiles>,
}

/// [`LayerFrame`] of each layer.
struct FrameLayers {
    solid: LayerFrame,
    highlights: LayerFrame,
    backgrounds: LayerFrame,
}

impl FrameLayers {
    fn new(scene: &Scene, camera: &Camera, size: ImageSize) -> Self {
        let at = |layer: &Option<Layer>| {
            layer
                .as_ref()
                .map_or_else(LayerFrame::default, |layer| LayerFrame {
                    eye: (camera.projection() == Projection::Perspective)
                        .then(|| EyeValues::new(layer.dnf(), camera.eye())),
                    tiles: FrameTiles::with_literals(layer.index(), camera, size),
                })
        };
        Self {
            solid: at(&scene.solid),
            highlights: at(&scene.highlights),
            backgrounds: at(&scene.backgrounds),
        }
    }
}
