//! Rendering a [`RenderScene`] into a linear-RGB image.
//!
//! The pieces: the camera ([`Camera`]: pinhole or thin lens), the samples' pattern
//! and their dimensions (`sampling`), the light sources and their sample points
//! (`light`), the background, the shading rules (`shade`), the integrators behind
//! one seam (`integrator`, `whitted`), the one sample loop over rows (`rows`), and
//! the users of that loop: [`render_region`] here, progressive passes and previews
//! (`progressive`) and one pixel's ray tree (`debug`).
//!
//! [`render`] splits the image into rows traced in parallel with rayon. Each row is
//! computed independently and the rows are assembled in order, so the image is
//! byte-identical whatever the thread count; per-row [`Stats`] are summed at the end.
//! [`render_region`] renders a crop: every sample position depends only on absolute
//! pixel coordinates, so a crop's pixels equal the full render's there, bit for bit.

mod aov;
pub mod bsdf;
mod camera;
pub mod debug;
mod door;
pub mod integrator;
mod light;
pub mod microfacet;
pub mod optics;
pub mod path;
pub mod path_log;
mod progressive;
mod rows;
mod sampling;
mod shade;
mod stats;
mod wavefront;
pub mod whitted;

pub use aov::{albedo, render_aovs, Aov, Aovs};
pub use camera::{Camera, CameraSample};
pub use door::{render, render_region, RenderError};
pub use integrator::{
    AreaOutcome, HitRecord, Integrator, LightOutcome, NoRecord, PathEvent, Recorder, TraceContext,
};
pub use light::LightSampling;
pub use optics::{beer_lambert, reflect, refract, schlick};
pub use progressive::{render_preview, Accumulator};
pub use rows::{EyeBlock, RowTracer, BLOCK_PATHS};
pub use sampling::{permute, sample_2d, Dim, Permutation, PixelSampler, PixelSeeds, SampleId, Strata};
pub use shade::{AffRules, Branch, Facets, P3fRules, Rules, SpdRules};
pub use stats::{Stage, StageStats, Stats};

use rayon::prelude::*;

use crate::image::{Image, Region};
use crate::math::Vec3;
use crate::options::{RenderOptions, Sampling};
use crate::prepare::RenderScene;
use crate::scene::View;
use rows::each_row;

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
    /// Called after each finished row with what the path tracer's wavefront stages
    /// did for it (nothing for other integrators).
    fn row_stages(&self, _stages: &StageStats) {}
    /// Polled between rows: returning true abandons the render.
    fn cancelled(&self) -> bool {
        false
    }
}

/// An observer that ignores everything.
pub struct Silent;

impl Observer for Silent {}

/// Number of eye-ray rows a render of `region` traces (for progress reporting).
pub fn region_eye_rows(opts: &RenderOptions, region: &Region) -> u64 {
    match opts.sampling {
        Sampling::SpdCorners => region.height() as u64 + 1,
        _ => region.height() as u64,
    }
}

/// Renders only `region` of the `opts.width` x `opts.height` image of `scene` seen by
/// `view` (the region must lie inside: [`render_region`] checks it) into a
/// region-sized image whose pixels are exactly those the full render has there.
/// `None` if the observer cancelled the render.
fn trace_region(
    scene: &RenderScene,
    view: &View,
    opts: &RenderOptions,
    region: &Region,
    observer: &dyn Observer,
) -> Option<(Image, Stats)> {
    debug_assert!(
        region.x0 < region.x1 && region.y0 < region.y1 && region.x1 <= opts.width && region.y1 <= opts.height,
        "region {region} outside the {}x{} image",
        opts.width,
        opts.height
    );
    let frame = RowTracer::new(scene, view, opts);
    let (x0, y0) = (region.x0, region.y0);
    let (w, h) = (region.width() as usize, region.height() as usize);
    let (pixels, stats) = match opts.sampling {
        Sampling::SpdCorners => {
            // Corner (i, j) is the raster point (i, j): the region's pixels need the
            // corners x0..=x1, y0..=y1, the same rays the full render traces there.
            let xs: Vec<u32> = (x0..=region.x1).collect();
            let mut corners = vec![Vec3::ZERO; (w + 1) * (h + 1)];
            let stats = each_row(&mut corners, w + 1, observer, |j, place, ctx| {
                let mut values = Vec::with_capacity(w + 1);
                frame.corners(y0 + j, &xs, &mut values, ctx);
                place.copy_from_slice(&values);
            })?;
            let mut pixels = vec![Vec3::ZERO; w * h];
            pixels.par_chunks_mut(w).enumerate().for_each(|(j, row)| {
                let (top, bottom) = (&corners[j * (w + 1)..], &corners[(j + 1) * (w + 1)..]);
                for (i, p) in row.iter_mut().enumerate() {
                    *p = spd_mean(top[i], top[i + 1], bottom[i], bottom[i + 1]);
                }
                observer.row_pixels(y0 + j as u32, row);
            });
            (pixels, stats)
        }
        _ => {
            let xs: Vec<u32> = (x0..region.x1).collect();
            let n = frame.sampler().count();
            let weight = 1.0 / n as f32;
            let mut pixels = vec![Vec3::ZERO; w * h];
            let stats = each_row(&mut pixels, w, observer, |j, row, ctx| {
                frame.add_samples(y0 + j, &xs, 0..n, weight, row, ctx);
                observer.row_pixels(y0 + j, row);
            })?;
            (pixels, stats)
        }
    };
    Some((Image::from_pixels(w as u32, h as u32, pixels), stats))
}

/// The SPD protocol's pixel value: the mean of its four corner values.
#[inline]
pub fn spd_mean(top_left: Vec3, top_right: Vec3, bottom_left: Vec3, bottom_right: Vec3) -> Vec3 {
    // Quartered before the sum (exact: a power of two), so four huge but finite
    // corners cannot overflow to infinity.
    top_left * 0.25 + top_right * 0.25 + bottom_left * 0.25 + bottom_right * 0.25
}
