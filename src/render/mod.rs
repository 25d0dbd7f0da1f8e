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

mod background;
pub mod bsdf;
mod camera;
pub mod debug;
pub mod emitters;
pub mod integrator;
mod light;
pub mod microfacet;
pub mod optics;
pub mod path;
pub mod path_log;
mod progressive;
pub mod request;
mod rows;
mod sampling;
mod shade;
mod stats;
pub mod whitted;

pub use background::Background;
pub use camera::{Camera, CameraSample};
pub use integrator::{
    AreaOutcome, HitRecord, Integrator, LightOutcome, NoRecord, PathEvent, Recorder, TraceContext,
};
pub use light::{LightQuad, LightSampling, LightSource};
pub use optics::{beer_lambert, reflect, refract, schlick};
pub use progressive::{render_preview, Accumulator};
pub use request::{image_size, RenderRequest, Resolved};
pub use rows::Frame;
pub use sampling::{
    permute, sample_2d, Dim, Permutation, PixelSampler, PixelSeeds, SampleId, Sampling, Strata,
};
pub use shade::{Branch, Facets, Lighting, Model, P3fRules, Rules, SpdRules};
pub use stats::Stats;

use rayon::prelude::*;

use crate::image::{Image, Region};
use crate::limits::{
    eye_grid_points, DEFAULT_MAX_DEPTH, MAX_DEPTH, MAX_LIGHT_SAMPLES, MAX_PIXELS, MAX_RESOLUTION, MAX_SPP,
};
use crate::math::Vec3;
use crate::prepare::RenderScene;
use crate::scene::{Integrator as Method, View};
use rows::each_row;

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
    /// The sample pattern: 0 is nffrt's first, any other an unrelated one, as
    /// deterministic (independent renders to average, or to compare noise with).
    pub seed: u32,
    /// The light transport: Whitted's rules or path tracing.
    pub integrator: Method,
    /// False: every surface smooth, whatever its material's roughness (the viewer's
    /// toggle).
    pub roughness: bool,
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
            seed: 0,
            integrator: Method::Whitted,
            roughness: true,
        }
    }
}

impl RenderOptions {
    /// The view's resolution, depth 5, pixel-centre sampling, the view's lens.
    pub fn from_view(view: &View) -> Self {
        RenderOptions {
            width: view.width,
            height: view.height,
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

/// Renders `scene` seen by `view` and returns the image and ray counts.
pub fn render(scene: &RenderScene, view: &View, opts: &RenderOptions) -> (Image, Stats) {
    render_region(scene, view, opts, &Region::full(opts.width, opts.height), &Silent)
        .expect("a silent render is never cancelled")
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

/// Checks that `opts` can be rendered within [`crate::limits`]: a size of 1 to
/// [`MAX_RESOLUTION`] per side, a depth of 1 to [`MAX_DEPTH`], 1 to [`MAX_SPP`]
/// samples, a finite lens (aperture at least 0, focal distance above 0), 1 to
/// [`MAX_LIGHT_SAMPLES`] light samples.
pub fn check_settings(opts: &RenderOptions) -> Result<(), String> {
    let (w, h) = (opts.width, opts.height);
    if !(1..=MAX_RESOLUTION).contains(&w) || !(1..=MAX_RESOLUTION).contains(&h) {
        return Err(format!(
            "a {w}x{h} image: width and height go from 1 to {MAX_RESOLUTION}"
        ));
    }
    if !(1..=MAX_DEPTH).contains(&opts.max_depth) {
        return Err(format!(
            "max depth {} is not between 1 and {MAX_DEPTH}",
            opts.max_depth
        ));
    }
    if let Sampling::Stratified { spp } | Sampling::Independent { spp } = opts.sampling {
        if !(1..=MAX_SPP).contains(&spp) {
            return Err(format!("{spp} samples per pixel is not between 1 and {MAX_SPP}"));
        }
    }
    if let Some(a) = opts.aperture.filter(|a| !(a.is_finite() && *a >= 0.0)) {
        return Err(format!("aperture {a} is not a finite number of at least 0"));
    }
    if let Some(f) = opts.focal.filter(|f| !(f.is_finite() && *f > 0.0)) {
        return Err(format!("focal distance {f} is not a finite number above 0"));
    }
    if let Some(n) = opts
        .light_samples
        .filter(|n| !(1..=MAX_LIGHT_SAMPLES).contains(n))
    {
        return Err(format!(
            "{n} light samples is not between 1 and {MAX_LIGHT_SAMPLES}"
        ));
    }
    Ok(())
}

/// Checks that `opts` can be rendered over `region` ([`check_settings`]), the region
/// non-empty and inside the image, with at most [`MAX_PIXELS`] eye-ray grid points.
pub fn check_options(opts: &RenderOptions, region: &Region) -> Result<(), String> {
    check_settings(opts)?;
    let (w, h) = (opts.width, opts.height);
    let r = region;
    if r.x0 >= r.x1 || r.y0 >= r.y1 || r.x1 > w || r.y1 > h {
        return Err(format!(
            "region {r} is empty or does not fit in the {w}x{h} image (X1 and Y1 are exclusive)"
        ));
    }
    let grid = eye_grid_points(r.width(), r.height(), opts.sampling);
    if grid > MAX_PIXELS {
        let (rw, rh) = (r.width(), r.height());
        return Err(format!(
            "{rw}x{rh} is {grid} eye-ray grid points, more than the limit of {MAX_PIXELS} (render it in tiles)"
        ));
    }
    Ok(())
}

/// Renders only `region` of the `opts.width` x `opts.height` image of `scene` seen by
/// `view` (the region must lie inside) into a region-sized image whose pixels are
/// exactly those the full render has there. `None` if the observer cancelled the
/// render.
pub fn render_region(
    scene: &RenderScene,
    view: &View,
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
    let frame = Frame::new(scene, view, opts);
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
