//! What `nffrt render` does once the render has returned: the AOVs (`--aov`, and
//! the denoiser's guides) in their own pass over the render's eye samples, the
//! denoising (`--denoise`, Open Image Denoise), and the AOV files written beside a
//! picture that has no layers for them (all formats but OpenEXR). Everything is
//! checked, and every file opened, before the render starts.

use std::path::{Path, PathBuf};
use std::time::Instant;

use super::image_out::{is_stdout, Destination};
use super::render::{render_error, RenderArgs};
use super::CliError;
use nffrt::denoise::{Denoiser, Quality};
use nffrt::image::Region;
use nffrt::image::{Encoding, Image, ImageFormat};
use nffrt::math::Vec3;
use nffrt::options::{RenderLimits, RenderOptions, Sampling};
use nffrt::prepare::RenderScene;
use nffrt::render::{render_aovs, Aov, Aovs, RenderError, Silent};

/// What to do after each render, checked and prepared once for all the pictures
/// of a command (one, or an animation's frames): the denoiser opened.
pub struct Finishing {
    denoiser: Option<(Denoiser, Quality)>,
    /// The AOVs asked for, each once, in [`Aov::ALL`]'s order.
    aovs: Vec<Aov>,
    /// The pictures' format.
    format: ImageFormat,
}

/// What to do after the render of one picture: [`Finishing`]'s work, with the
/// files beside the picture opened.
pub struct Finish<'a> {
    finishing: &'a Finishing,
    /// Files beside the picture, one per AOV, when the picture is not OpenEXR.
    beside: Vec<(Aov, PathBuf, Destination)>,
}

/// What [`Finish::run`] gives back for the picture's file.
pub struct Finished {
    /// The picture to write: the render's, or its denoised copy.
    pub image: Image,
    /// The OpenEXR channels of the AOVs (`albedo.R`, ...), for an `.exr` picture.
    pub exr_channels: Vec<(String, Vec<f32>)>,
    /// Seconds of the AOV pass, if it ran.
    pub aov_s: Option<f64>,
    /// Seconds of the denoiser, if it ran.
    pub denoise_s: Option<f64>,
}

/// The file beside `picture` that holds `aov`: `NAME.albedo.png` for `NAME.png`.
pub fn beside_path(picture: &Path, aov: Aov) -> PathBuf {
    let stem = picture.file_stem().unwrap_or_default().to_string_lossy();
    let ext = picture.extension().unwrap_or_default().to_string_lossy();
    picture.with_file_name(format!("{stem}.{}.{ext}", aov.name()))
}

/// The AOVs `args` ask for, each once, in [`Aov::ALL`]'s order.
pub fn asked_aovs(args: &RenderArgs) -> Vec<Aov> {
    Aov::ALL.into_iter().filter(|a| args.aov.contains(a)).collect()
}

impl Finishing {
    /// Checks `--denoise` and `--aov` against the render of `opts` into `out_path`
    /// (in `format`; for an animation, its pattern) and opens the denoiser: usage
    /// errors for what cannot be done, an I/O error for a denoiser that cannot be
    /// found.
    pub fn plan(
        args: &RenderArgs,
        out_path: &Path,
        format: ImageFormat,
        opts: &RenderOptions,
        threads: usize,
    ) -> Result<Finishing, CliError> {
        let aovs = asked_aovs(args);
        let post = args.denoise.is_some() || !aovs.is_empty();
        if post && args.region.is_some() {
            return Err(CliError::usage(
                "--denoise and --aov work on whole pictures, not on --region tiles \
                 (a tile's denoised edges would not meet its neighbours')",
            ));
        }
        if !aovs.is_empty() && is_stdout(out_path) && format != ImageFormat::Exr {
            return Err(CliError::usage(
                "--aov with -o -: the AOVs go beside the picture's file; name one",
            ));
        }
        if args.denoise.is_some() && matches!(opts.sampling, Sampling::PixelCenters | Sampling::SpdCorners) {
            return Err(CliError::usage(format!(
                "--denoise: a picture of one ray through each pixel {} has no noise to remove; \
                 denoising is for path tracing and sampled effects (--spp, a lens, rough surfaces, \
                 soft shadows, motion)",
                if opts.sampling == Sampling::SpdCorners {
                    "corner"
                } else {
                    "centre"
                }
            )));
        }
        let denoiser = match args.denoise {
            Some(quality) => {
                let opened = Denoiser::open(&[], threads as u32)
                    .map_err(|e| CliError::io(format!("--denoise: {e}")))?;
                Some((opened, quality))
            }
            None => None,
        };
        Ok(Finishing {
            denoiser,
            aovs,
            format,
        })
    }

    /// The work after the render of the picture `picture`, its AOV files opened.
    pub fn open(&self, picture: &Path) -> Result<Finish<'_>, CliError> {
        let mut beside = Vec::new();
        if self.format != ImageFormat::Exr {
            for &aov in &self.aovs {
                let path = beside_path(picture, aov);
                let out = Destination::create(&path)?;
                beside.push((aov, path, out));
            }
        }
        Ok(Finish {
            finishing: self,
            beside,
        })
    }

    /// The denoiser in words for the report: `Open Image Denoise 2.5.1, high (PATH)`.
    pub fn denoiser_text(&self) -> Option<String> {
        let (d, quality) = self.denoiser.as_ref()?;
        Some(format!(
            "Open Image Denoise {}, {} ({})",
            d.version(),
            quality.name(),
            d.library().display()
        ))
    }
}

impl Finish<'_> {
    /// After the render of `scene` with `opts` gave `image` (the whole picture):
    /// the AOVs of its eye samples, the denoised picture, and the AOV files beside
    /// the picture (8-bit ones in `encoding`, as the picture).
    pub fn run(
        self,
        scene: &RenderScene,
        opts: &RenderOptions,
        limits: &RenderLimits,
        image: Image,
        format: ImageFormat,
        encoding: Encoding,
    ) -> Result<Finished, CliError> {
        let full = Region::full(opts.width, opts.height);
        let guides = || render_aovs(scene, scene.view(), opts, &full, limits, &Silent);
        self.run_with(guides, opts, image, format, encoding)
    }

    /// [`Finish::run`] with the AOVs that `guides` makes, when they are needed.
    pub fn run_with(
        self,
        guides: impl FnOnce() -> Result<Aovs, RenderError>,
        opts: &RenderOptions,
        image: Image,
        format: ImageFormat,
        encoding: Encoding,
    ) -> Result<Finished, CliError> {
        let mut finished = Finished {
            image,
            exr_channels: Vec::new(),
            aov_s: None,
            denoise_s: None,
        };
        let Finishing { denoiser, aovs, .. } = self.finishing;
        if denoiser.is_none() && aovs.is_empty() {
            return Ok(finished);
        }
        let t0 = Instant::now();
        let guides = guides().map_err(|e| render_error(e, false))?;
        finished.aov_s = Some(t0.elapsed().as_secs_f64());
        if let Some((denoiser, quality)) = denoiser {
            let t1 = Instant::now();
            finished.image = denoiser
                .denoise_render(&finished.image, &guides, opts, *quality)
                .map_err(|e| CliError::io(format!("--denoise: {e}")))?;
            finished.denoise_s = Some(t1.elapsed().as_secs_f64());
        }
        if format == ImageFormat::Exr {
            finished.exr_channels = aovs.iter().flat_map(|&a| exr_channels(&guides, a)).collect();
        }
        for (aov, _, out) in self.beside {
            out.write_image(
                &aov_picture(&guides, aov, format),
                format,
                aov_encoding(aov, format, encoding),
                &[],
            )?;
        }
        Ok(finished)
    }
}

impl Finished {
    /// Writes the picture to `output`: in `format` (8-bit in `encoding`, with the
    /// PNG text chunks `text`), or as OpenEXR layers with the AOVs' channels.
    pub fn write(
        &self,
        output: Destination,
        format: ImageFormat,
        encoding: Encoding,
        text: &[(&str, String)],
    ) -> Result<(), CliError> {
        if self.exr_channels.is_empty() {
            output.write_image(&self.image, format, encoding, text)
        } else {
            output.write_exr_layers(&self.image, &self.exr_channels)
        }
    }
}

/// The OpenEXR channels of `aov`: `albedo.R/G/B`, `normal.X/Y/Z`, `depth.Z`.
fn exr_channels(aovs: &Aovs, aov: Aov) -> Vec<(String, Vec<f32>)> {
    let split = |name: &str, image: &Image, axes: [&str; 3]| {
        let channel = |k: usize| image.pixels.iter().map(|p| p.to_array()[k]).collect();
        (0..3)
            .map(|k| (format!("{name}.{}", axes[k]), channel(k)))
            .collect()
    };
    match aov {
        Aov::Albedo => split("albedo", &aovs.albedo, ["R", "G", "B"]),
        Aov::Normal => split("normal", &aovs.normal, ["X", "Y", "Z"]),
        Aov::Depth => vec![("depth.Z".into(), aovs.depth.clone())],
    }
}

/// The picture of `aov` written beside the picture: the values themselves in a
/// float format (the depth in R, G and B alike); in an 8-bit one, the albedo as it
/// is, the normal mapped from [-1, 1] to [0, 1], the depth as a fraction of the
/// farthest hit's (white: that far, or nothing hit).
fn aov_picture(aovs: &Aovs, aov: Aov, format: ImageFormat) -> Image {
    let (w, h) = (aovs.albedo.width, aovs.albedo.height);
    let eight_bit = format.is_8bit();
    match aov {
        Aov::Albedo => aovs.albedo.clone(),
        Aov::Normal if eight_bit => {
            let pixels = aovs
                .normal
                .pixels
                .iter()
                .map(|n| *n * 0.5 + Vec3::splat(0.5))
                .collect();
            Image::from_pixels(w, h, pixels)
        }
        Aov::Normal => aovs.normal.clone(),
        Aov::Depth => {
            let farthest = aovs
                .depth
                .iter()
                .copied()
                .filter(|d| d.is_finite())
                .fold(0.0f32, f32::max);
            let value = |d: f32| match eight_bit {
                true if !d.is_finite() || farthest == 0.0 => 1.0,
                true => d / farthest,
                false => d,
            };
            Image::from_pixels(w, h, aovs.depth.iter().map(|&d| Vec3::splat(value(d))).collect())
        }
    }
}

/// The albedo is a colour and takes the picture's encoding; normals and depths are
/// numbers, written linear.
fn aov_encoding(aov: Aov, format: ImageFormat, encoding: Encoding) -> Encoding {
    match (aov, format.is_8bit()) {
        (Aov::Albedo, true) => encoding,
        _ => Encoding::Linear,
    }
}
