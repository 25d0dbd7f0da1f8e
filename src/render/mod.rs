//! Whitted ray tracing of a prepared scene into a linear-RGB image.
//!
//! [`render`] splits the image into rows traced in parallel with rayon. Each row is
//! computed independently and the rows are assembled in order, so the image is
//! byte-identical whatever the thread count; per-row [`Stats`] are summed at the end.
//! [`render_region`] renders a crop: every sample position depends only on absolute
//! pixel coordinates, so a crop's pixels equal the full render's there, bit for bit.

mod background;
mod camera;
pub mod debug;
mod light;
mod progressive;
mod sampling;
mod shade;
mod stats;
mod trace;

pub use background::Background;
pub use camera::{Camera, CameraSample};
pub use light::{LightQuad, LightSampling, LightSource};
pub use progressive::{render_preview, Accumulator};
pub use sampling::{permute, sample_2d, Dim, PixelSampler, PixelSeeds, SampleId, Sampling, Strata};
pub use shade::{schlick, Model, P3fRules, Rules, SpdRules};
pub use stats::Stats;
pub use trace::{AreaOutcome, Branch, HitRecord, LightOutcome, NoRecord, Recorder, Tracer};

use rayon::prelude::*;

use crate::accel::Bvh;
use crate::image::{Image, Region};
use crate::limits::DEFAULT_MAX_DEPTH;
use crate::math::{Ray, Vec3};
use crate::scene::Scene;

/// How to render. Every field changes the picture.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct RenderOptions {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Maximum ray-tree depth; the eye ray has depth 1.
    pub max_depth: u32,
    /// Eye-ray placement.
    pub sampling: Sampling,
    /// Lens diameter in pixels of the view plane, replacing the scene's (0: pinhole).
    pub aperture: Option<f32>,
    /// Focal distance as a multiple of `|from - at|`, replacing the scene's.
    pub focal: Option<f32>,
    /// Points per side of the grid every hit samples on each area light, replacing
    /// the default sampling (see `light.rs`).
    pub light_samples: Option<u32>,
    /// False: each area light shines from its centre alone (hard shadows).
    pub soft_shadows: bool,
}

impl Default for RenderOptions {
    /// 512x512, depth 5, pixel centres, the scene's lens.
    fn default() -> Self {
        RenderOptions {
            width: 512,
            height: 512,
            max_depth: DEFAULT_MAX_DEPTH,
            sampling: Sampling::PixelCenters,
            aperture: None,
            focal: None,
            light_samples: None,
            soft_shadows: true,
        }
    }
}

impl RenderOptions {
    /// The scene file's resolution, depth 5, pixel-centre sampling, the scene's lens.
    pub fn from_scene(scene: &Scene) -> Self {
        RenderOptions {
            width: scene.view.width,
            height: scene.view.height,
            ..RenderOptions::default()
        }
    }
}

/// Watches a render as it runs: progress reports, the finished pixels, cancellation.
/// Rows finish in any order and on any of the render's threads.
pub trait Observer: Sync {
    /// Called after each finished row of eye rays, with the rays that row traced.
    fn row_done(&self, _rays: u64) {}
    /// Called with each finished row of the image: row `y` (absolute) and its
    /// pixels, the rendered region's columns in order, exactly the values the
    /// image will hold (for [`Sampling::SpdCorners`], once the corners around it
    /// are traced).
    fn row_pixels(&self, _y: u32, _pixels: &[Vec3]) {}
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
    region_eye_rows(opts, &Region::full(opts.width, opts.height))
}

/// Number of eye-ray rows a render of `region` traces (for progress reporting).
pub fn region_eye_rows(opts: &RenderOptions, region: &Region) -> u64 {
    match opts.sampling {
        Sampling::SpdCorners => region.height() as u64 + 1,
        _ => region.height() as u64,
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
    render_region(scene, bvh, opts, &Region::full(opts.width, opts.height), observer)
}

/// Renders only `region` of the `opts.width` x `opts.height` image (it must lie
/// inside) into a region-sized image whose pixels are exactly those the full render
/// has there. `None` if the observer cancelled the render.
pub fn render_region(
    scene: &Scene,
    bvh: &Bvh,
    opts: &RenderOptions,
    region: &Region,
    observer: &dyn Observer,
) -> Option<(Image, Stats)> {
    assert!(
        region.x0 < region.x1 && region.y0 < region.y1 && region.x1 <= opts.width && region.y1 <= opts.height,
        "region {region} outside the {}x{} image",
        opts.width,
        opts.height
    );
    let camera = Camera::new(&scene.view, opts);
    let tracer = Tracer::new(scene, bvh, opts);
    let (x0, y0) = (region.x0, region.y0);
    let (w, h) = (region.width() as usize, region.height() as usize);
    // A row of eye rays through raster points (x0 + i + offset, y + offset) and the
    // lens centre, traced in packets.
    let eye_row = |offset: f32, cols: usize, y: u32, st: &mut Stats, out: &mut Vec<Vec3>| {
        let rays: Vec<Ray> = (0..cols as u32)
            .map(|i| camera.ray_at((x0 + i) as f32 + offset, y as f32 + offset))
            .collect();
        tracer.trace_eye_row(&rays, (x0, y), st, out);
    };
    let pixels = match opts.sampling {
        Sampling::PixelCenters => {
            trace_rows(y0, w, h, observer, true, |y, st, out| eye_row(0.5, w, y, st, out))
        }
        Sampling::Stratified { .. } | Sampling::Independent { .. } => {
            let sampler = opts.sampling.pixel_sampler(camera.has_lens());
            let (n, weight) = (sampler.count(), 1.0 / sampler.count() as f32);
            trace_rows(y0, w, h, observer, true, |y, st, out| {
                // Sample k of every pixel of the row, traced in packets: each pixel
                // adds its samples in sample order, as `pixel_mean` does, so the sums
                // are the very same.
                let mut sums = vec![Vec3::ZERO; w];
                let pixels: Vec<_> = (x0..x0 + w as u32).map(|x| sampler.pixel(x, y)).collect();
                let (mut samples, mut ids) = (Vec::with_capacity(w), Vec::with_capacity(w));
                let mut rays = Vec::with_capacity(w);
                for k in 0..n {
                    samples.clear();
                    ids.clear();
                    for pixel in &pixels {
                        let (sample, id) = sampler.sample_of(pixel, k);
                        samples.push(sample);
                        ids.push(id);
                    }
                    camera.rays(&samples, &mut rays);
                    tracer.trace_eyes(&rays, &ids, st, |i, c| sums[i] += c * weight);
                }
                out.extend(sums);
            })
        }
        Sampling::SpdCorners => {
            // Corner (i, j) is the raster point (i, j): the region's pixels need the
            // corners x0..=x1, y0..=y1, the same rays the full render traces there.
            let (corners, stats) = trace_rows(y0, w + 1, h + 1, observer, false, |y, st, out| {
                eye_row(0.0, w + 1, y, st, out)
            })?;
            let mut pixels = vec![Vec3::ZERO; w * h];
            pixels.par_chunks_mut(w).enumerate().for_each(|(j, row)| {
                let (top, bottom) = (&corners[j * (w + 1)..], &corners[(j + 1) * (w + 1)..]);
                for (i, p) in row.iter_mut().enumerate() {
                    *p = spd_mean(top[i], top[i + 1], bottom[i], bottom[i + 1]);
                }
                observer.row_pixels(y0 + j as u32, row);
            });
            Some((pixels, stats))
        }
    };
    let (pixels, stats) = pixels?;
    Some((Image::from_pixels(w as u32, h as u32, pixels), stats))
}

/// The SPD protocol's pixel value: the mean of its four corner values.
#[inline]
pub fn spd_mean(top_left: Vec3, top_right: Vec3, bottom_left: Vec3, bottom_right: Vec3) -> Vec3 {
    // Quartered before the sum (exact: a power of two), so four huge but finite
    // corners cannot overflow to infinity.
    top_left * 0.25 + top_right * 0.25 + bottom_left * 0.25 + bottom_right * 0.25
}

/// The box-filtered value of pixel `(x, y)` (not the SPD corners): the mean of
/// `trace` over the pixel's samples, each weighted by `1/n` before the sum (in
/// sample order) so that huge but finite samples cannot overflow to infinity.
#[inline]
pub fn pixel_mean(
    sampler: &PixelSampler,
    x: u32,
    y: u32,
    mut trace: impl FnMut(CameraSample, SampleId) -> Vec3,
) -> Vec3 {
    let n = sampler.count();
    let weight = 1.0 / n as f32;
    let mut sum = Vec3::ZERO;
    for s in 0..n {
        let (sample, id) = sampler.sample(x, y, s);
        sum += trace(sample, id) * weight;
    }
    sum
}

/// Fills `rows` rows of `cols` values, row `y0 + j` by `row(y0 + j, stats, out)`
/// (which appends `cols` values to `out`), rows in parallel ([`each_row`]),
/// assembled in order; each row goes to [`Observer::row_pixels`] if `pixels` (rows
/// of the image, not of SPD corners).
fn trace_rows(
    y0: u32,
    cols: usize,
    rows: usize,
    observer: &dyn Observer,
    pixels: bool,
    row: impl Fn(u32, &mut Stats, &mut Vec<Vec3>) + Sync,
) -> Option<(Vec<Vec3>, Stats)> {
    // Each task copies its row into place, so no thread assembles the image alone.
    let mut out = vec![Vec3::ZERO; cols * rows];
    let stats = each_row(&mut out, cols, observer, |j, place, stats| {
        let mut values = Vec::with_capacity(cols);
        row(y0 + j, stats, &mut values);
        place.copy_from_slice(&values);
        if pixels {
            observer.row_pixels(y0 + j, &values);
        }
    })?;
    Some((out, stats))
}

/// Runs `row(j, place, stats)` on each row `j` of `pixels` (rows of `cols`) in
/// parallel, each writing its row in place with an empty shadow cache; reports
/// each row's rays to the observer and sums the counts. `None` once the observer
/// cancels (rows not started then are left as they were).
///
/// Every row is a task of its own that an idle thread can steal: rayon's default
/// splitting stops once each thread holds a few long runs of rows, and where rows
/// differ much in cost (mount: sky above, glass spheres and terrain below) one thread
/// then worked alone through the end of the image, a third of the render.
fn each_row(
    pixels: &mut [Vec3],
    cols: usize,
    observer: &dyn Observer,
    row: impl Fn(u32, &mut [Vec3], &mut Stats) + Sync,
) -> Option<Stats> {
    let per_row: Option<Vec<Stats>> = pixels
        .par_chunks_mut(cols)
        .enumerate()
        .with_max_len(1)
        .map(|(j, place)| {
            if observer.cancelled() {
                return None;
            }
            let mut stats = Stats::default();
            trace::reset_shadow_cache();
            row(j as u32, place, &mut stats);
            observer.row_done(stats.total_rays());
            Some(stats)
        })
        .collect();
    let mut stats = Stats::default();
    for s in per_row? {
        stats += s;
    }
    Some(stats)
}
