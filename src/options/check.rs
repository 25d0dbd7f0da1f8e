//! The checks every render passes, written once: each setting within its range
//! ([`check_settings`]), and a region inside the image with no more eye rays than
//! the caller allows ([`check_render`]). The renderer's one door
//! (`render::render_region`) runs them; a front end may run them earlier too, to
//! refuse a render before it loads or builds anything.

use thiserror::Error;

use super::{RenderOptions, Sampling};
use crate::image::Region;
use crate::limits::{DEFAULT_MAX_PIXELS, MAX_LIGHT_SAMPLES, MAX_RAY_DEPTH, MAX_RESOLUTION, MAX_SPP};

/// What one render may take on, as its caller allows: the most eye-ray grid points
/// ([`eye_grid_points`]) of the region rendered. `--max-pixels` on the command line
/// sets it; the default, [`DEFAULT_MAX_PIXELS`], is every other caller's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RenderLimits {
    /// The most eye-ray grid points a render may have.
    pub max_pixels: u64,
}

impl Default for RenderLimits {
    fn default() -> Self {
        RenderLimits {
            max_pixels: DEFAULT_MAX_PIXELS,
        }
    }
}

/// Why a render was refused before it started.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
pub enum Refused {
    /// A setting is out of its range; the message names it and the range.
    #[error("{0}")]
    Setting(String),
    /// The region is empty or does not fit in the image.
    #[error("{0}")]
    Region(String),
    /// The region has more eye-ray grid points than [`RenderLimits::max_pixels`].
    #[error("{width}x{height} is {points} eye-ray grid points, more than the limit of {limit} (render it in tiles)")]
    TooManyPixels {
        /// The region's width.
        width: u32,
        /// The region's height.
        height: u32,
        /// Its eye-ray grid points.
        points: u64,
        /// The limit.
        limit: u64,
    },
}

/// The eye-ray grid points of a `width` x `height` render (or region) under
/// `sampling`: one per pixel, or the `(w + 1) x (h + 1)` pixel corners of the SPD
/// protocol. The one rule every pixel limit is checked by.
pub fn eye_grid_points(width: u32, height: u32, sampling: Sampling) -> u64 {
    let (w, h) = (width as u64, height as u64);
    match sampling {
        Sampling::SpdCorners => (w + 1) * (h + 1),
        _ => w * h,
    }
}

/// Checks that `opts` can be rendered within [`crate::limits`]: a size of 1 to
/// [`MAX_RESOLUTION`] per side, a depth of 1 to [`MAX_RAY_DEPTH`], 1 to [`MAX_SPP`]
/// samples, a finite lens (aperture at least 0, focal distance above 0), 1 to
/// [`MAX_LIGHT_SAMPLES`] light samples.
pub fn check_settings(opts: &RenderOptions) -> Result<(), String> {
    let (w, h) = (opts.width, opts.height);
    if !(1..=MAX_RESOLUTION).contains(&w) || !(1..=MAX_RESOLUTION).contains(&h) {
        return Err(format!(
            "a {w}x{h} image: width and height go from 1 to {MAX_RESOLUTION}"
        ));
    }
    if !(1..=MAX_RAY_DEPTH).contains(&opts.max_depth) {
        return Err(format!(
            "max depth {} is not between 1 and {MAX_RAY_DEPTH}",
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
/// non-empty and inside the image, with at most `limits.max_pixels` eye-ray grid
/// points.
pub fn check_render(opts: &RenderOptions, region: &Region, limits: &RenderLimits) -> Result<(), Refused> {
    check_settings(opts).map_err(Refused::Setting)?;
    let (w, h) = (opts.width, opts.height);
    let r = region;
    if r.x0 >= r.x1 || r.y0 >= r.y1 || r.x1 > w || r.y1 > h {
        return Err(Refused::Region(format!(
            "region {r} is empty or does not fit in the {w}x{h} image (X1 and Y1 are exclusive)"
        )));
    }
    let points = eye_grid_points(r.width(), r.height(), opts.sampling);
    if points > limits.max_pixels {
        return Err(Refused::TooManyPixels {
            width: r.width(),
            height: r.height(),
            points,
            limit: limits.max_pixels,
        });
    }
    Ok(())
}
