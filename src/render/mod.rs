//! Whitted ray tracing of a prepared scene into a linear-RGB image.
//!
//! [`render`] splits the image into rows traced in parallel with rayon. Each row is
//! computed independently and the rows are assembled in order, so the image is
//! byte-identical whatever the thread count; per-row [`Stats`] are summed at the end.

mod camera;
mod shade;
mod stats;
mod trace;

pub use camera::Camera;
pub use stats::Stats;
pub use trace::Tracer;

use rayon::prelude::*;

use crate::accel::Bvh;
use crate::image::Image;
use crate::math::Vec3;
use crate::scene::Scene;

/// Where eye rays go through each pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sampling {
    /// One ray through each pixel centre.
    PixelCenters,
    /// The SPD benchmark protocol: one ray through each pixel corner
    /// ((w+1) x (h+1) rays), the four corner values averaged into each pixel.
    SpdCorners,
}

/// How to render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Maximum ray-tree depth; the eye ray has depth 1.
    pub max_depth: u32,
    /// Eye-ray placement.
    pub sampling: Sampling,
}

impl RenderOptions {
    /// The scene file's resolution, depth 5, pixel-centre sampling.
    pub fn from_scene(scene: &Scene) -> Self {
        RenderOptions {
            width: scene.view.width,
            height: scene.view.height,
            max_depth: DEFAULT_MAX_DEPTH,
            sampling: Sampling::PixelCenters,
        }
    }
}

/// The default maximum ray depth (the SPD's).
pub const DEFAULT_MAX_DEPTH: u32 = 5;

/// Watches a render as it runs: progress reports and cancellation.
pub trait Observer: Sync {
    /// Called after each finished row of eye rays, with the rays that row traced.
    fn row_done(&self, _rays: u64) {}
    /// Polled between rows: returning true abandons the render.
    fn cancelled(&self) -> bool {
        false
    }
}

/// An observer that ignores everything.
pub struct Silent;

impl Observer for Silent {}

/// Renders `scene` (already built into `bvh`) and returns the image and ray counts.
pub fn render(scene: &Scene, bvh: &Bvh, opts: &RenderOptions) -> (Image, Stats) {
    render_observed(scene, bvh, opts, &Silent).expect("a silent render is never cancelled")
}

/// Number of eye-ray rows a render traces (for progress reporting).
pub fn eye_rows(opts: &RenderOptions) -> u64 {
    match opts.sampling {
        Sampling::PixelCenters => opts.height as u64,
        Sampling::SpdCorners => opts.height as u64 + 1,
    }
}

/// Renders like [`render`], reporting each finished row to `observer`; `None` if the
/// observer cancelled the render.
pub fn render_observed(
    scene: &Scene,
    bvh: &Bvh,
    opts: &RenderOptions,
    observer: &dyn Observer,
) -> Option<(Image, Stats)> {
    let camera = Camera::new(&scene.view, opts.width, opts.height);
    let tracer = Tracer::new(scene, bvh, opts.max_depth);
    let (w, h) = (opts.width as usize, opts.height as usize);
    match opts.sampling {
        Sampling::PixelCenters => {
            let (rows, stats) = trace_grid(&tracer, &camera, w, h, 0.5, observer)?;
            Some((Image::from_pixels(opts.width, opts.height, rows), stats))
        }
        Sampling::SpdCorners => {
            let (corners, stats) = trace_grid(&tracer, &camera, w + 1, h + 1, 0.0, observer)?;
            let mut pixels = Vec::with_capacity(w * h);
            for j in 0..h {
                for i in 0..w {
                    let c = |x: usize, y: usize| corners[y * (w + 1) + x];
                    // Quartered before the sum (exact: a power of two), so four huge but
                    // finite corners cannot overflow to infinity.
                    let q = |x: usize, y: usize| c(x, y) * 0.25;
                    pixels.push(q(i, j) + q(i + 1, j) + q(i, j + 1) + q(i + 1, j + 1));
                }
            }
            Some((Image::from_pixels(opts.width, opts.height, pixels), stats))
        }
    }
}

/// Traces a `cols` x `rows` grid of eye rays through raster points `(i + offset, j + offset)`.
fn trace_grid(
    tracer: &Tracer,
    camera: &Camera,
    cols: usize,
    rows: usize,
    offset: f32,
    observer: &dyn Observer,
) -> Option<(Vec<Vec3>, Stats)> {
    let per_row: Option<Vec<(Vec<Vec3>, Stats)>> = (0..rows)
        .into_par_iter()
        .map(|j| {
            if observer.cancelled() {
                return None;
            }
            let mut stats = Stats::default();
            let row = (0..cols)
                .map(|i| {
                    let ray = camera.ray(i as f32 + offset, j as f32 + offset);
                    tracer.trace_eye(&ray, &mut stats)
                })
                .collect();
            observer.row_done(stats.total_rays());
            Some((row, stats))
        })
        .collect();
    let per_row = per_row?;
    let mut stats = Stats::default();
    let mut out = Vec::with_capacity(cols * rows);
    for (row, s) in per_row {
        out.extend(row);
        stats += s;
    }
    Some((out, stats))
}
