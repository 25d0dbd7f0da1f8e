//! What a render is asked to be, as plain values: [`RenderOptions`] (every setting
//! that changes the picture), [`Sampling`] (where eye rays go through a pixel), the
//! [`RenderRequest`] a front end makes of its flags or arguments and resolves
//! against a scene, and the checks every render passes ([`check_settings`],
//! [`check_render`]) against [`crate::limits`] and the caller's [`RenderLimits`].
//!
//! A leaf of the crate's layers: it reads the scene's summary and the limits, and
//! nothing of preparing or rendering, so the fingerprint of a tile, the command
//! line, the viewer and the Python bindings can all speak of options without
//! reaching into the renderer.

mod check;
mod request;

pub use check::{check_render, check_settings, eye_grid_points, Refused, RenderLimits};
pub use request::{display_encoding, image_size, RenderRequest, Resolved};

use std::fmt;

use crate::limits::DEFAULT_MAX_DEPTH;
use crate::scene::{IntegratorKind, View};

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
    /// the default sampling (see `render/light.rs`).
    pub light_samples: Option<u32>,
    /// False: each area light shines from its centre alone (hard shadows).
    pub soft_shadows: bool,
    /// The sample pattern: 0 is nffrt's first, any other an unrelated one, as
    /// deterministic (independent renders to average, or to compare noise with).
    pub seed: u32,
    /// The light transport: Whitted's rules or path tracing.
    pub integrator: IntegratorKind,
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
            integrator: IntegratorKind::Whitted,
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

/// Where eye rays go through each pixel (the patterns themselves: `render/sampling.rs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Sampling {
    /// One ray through each pixel centre.
    PixelCenters,
    /// The SPD benchmark protocol: one ray through each pixel corner
    /// ((w+1) x (h+1) rays), the four corner values averaged into each pixel.
    SpdCorners,
    /// Stratified jittered supersampling with `spp` samples per pixel, box-filtered.
    /// `spp = 1` is one sample at the pixel centre whose other dimensions (lens,
    /// time, rough directions) are jittered: what an explicit single sample of a
    /// scene with such effects takes.
    Stratified {
        /// Samples per pixel, at least 1.
        spp: u32,
    },
    /// `spp` independent uniform samples per pixel in every dimension, without
    /// strata: the baseline that stratification is measured against (tests).
    Independent {
        /// Samples per pixel, at least 1.
        spp: u32,
    },
}

impl Sampling {
    /// Eye samples per pixel (4 corner rays shared with the neighbours for the SPD
    /// protocol count as 1).
    pub fn samples_per_pixel(&self) -> u32 {
        match *self {
            Sampling::PixelCenters | Sampling::SpdCorners => 1,
            Sampling::Stratified { spp } | Sampling::Independent { spp } => spp.max(1),
        }
    }
}

impl fmt::Display for Sampling {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Sampling::PixelCenters => write!(f, "centres"),
            Sampling::SpdCorners => write!(f, "spd-corners"),
            Sampling::Stratified { spp } => write!(f, "stratified-{spp}"),
            Sampling::Independent { spp } => write!(f, "independent-{spp}"),
        }
    }
}
