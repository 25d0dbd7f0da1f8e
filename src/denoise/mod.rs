//! Denoising a rendered picture with Intel Open Image Denoise (OIDN), version 2:
//! its `RT` filter (a neural network trained on path-traced pictures), fed the
//! picture's linear values (high dynamic range) and, as guides, the albedo and the
//! normal of each pixel's first hits (`render::render_aovs`).
//!
//! A front end's step after the render has returned, never part of it: the picture
//! is rendered as always, then denoised here. The library is opened at run time
//! (`libloading`), not linked: nffrt builds and runs without it, and `--denoise`
//! finds the copy pip's `pyoidn` installs ([`search`]) or says how to get one
//! ([`DenoiseError::NotFound`]). docs/denoise.md says why.

mod ffi;
pub mod search;

use std::path::{Path, PathBuf};

use thiserror::Error;

use crate::image::Image;
use crate::math::Vec3;
use crate::options::RenderOptions;
use crate::render::Aovs;
use crate::scene::IntegratorKind;
use ffi::Oidn;

/// The oldest library accepted: version 2.0.0 (`RT` with `cleanAux`, shared images
/// of any stride).
const OLDEST_VERSION: i32 = 20000;

/// How to get the library, for messages.
pub const HOW_TO_GET: &str = "`pip install pyoidn` installs it (into the active virtual environment, \
                              or with --user), or set NFFRT_OIDN to libOpenImageDenoise's file or folder";

/// Why a picture could not be denoised.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum DenoiseError {
    /// No usable library in any place looked at.
    #[error("denoising needs Intel Open Image Denoise 2, which was not found{detail}: {HOW_TO_GET}")]
    NotFound {
        /// What went wrong where `NFFRT_OIDN` points, if it is set (empty otherwise).
        detail: String,
    },
    /// The library is there but older than version 2.
    #[error(
        "{library}: Open Image Denoise {version} is too old (version 2 or later is needed): {HOW_TO_GET}"
    )]
    TooOld {
        /// The library's file.
        library: String,
        /// Its version, `major.minor.patch`.
        version: String,
    },
    /// The picture and its guides differ in size.
    #[error("the picture is {0}x{1} but its albedo or normal is {2}x{3}")]
    Size(u32, u32, u32, u32),
    /// The library reported an error.
    #[error("Open Image Denoise failed: {0}")]
    Failed(String),
}

/// How much time the filter takes for how good a picture: Open Image Denoise's
/// `quality`, each with its own trained network.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Quality {
    /// The small network, for interactive previews (the viewer's).
    Fast,
    /// Between the two (on a CPU much like `High`'s network at lower precision).
    Balanced,
    /// The full network, for final pictures (the library's default).
    #[default]
    High,
}

impl Quality {
    /// Every quality, fastest first.
    pub const ALL: [Quality; 3] = [Quality::Fast, Quality::Balanced, Quality::High];

    /// Its name: `fast`, `balanced`, `high`.
    pub fn name(self) -> &'static str {
        match self {
            Quality::Fast => "fast",
            Quality::Balanced => "balanced",
            Quality::High => "high",
        }
    }

    /// The quality of that name.
    pub fn from_name(name: &str) -> Option<Quality> {
        Quality::ALL.into_iter().find(|q| q.name() == name)
    }

    /// `OIDNQuality`'s value.
    fn code(self) -> i32 {
        match self {
            Quality::Fast => 4,
            Quality::Balanced => 5,
            Quality::High => 6,
        }
    }
}

/// An opened Open Image Denoise library, ready to denoise pictures (from any thread).
pub struct Denoiser {
    oidn: Oidn,
    library: PathBuf,
}

impl std::fmt::Debug for Denoiser {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "Denoiser({}, version {})",
            self.library.display(),
            self.version()
        )
    }
}

impl Denoiser {
    /// Opens the first library found ([`search::candidates`], with `extra_dirs`
    /// after `$NFFRT_OIDN`) on `threads` threads (0: one per core).
    pub fn open(extra_dirs: &[PathBuf], threads: u32) -> Result<Denoiser, DenoiseError> {
        let given = std::env::var_os(search::ENV_VAR).is_some_and(|v| !v.is_empty());
        for (k, path) in search::candidates(extra_dirs).into_iter().enumerate() {
            // A guessed file that is not there is skipped without trying it (a bare
            // name goes to the system's search, and NFFRT_OIDN is tried to say why).
            let bare = path.components().count() == 1;
            let tried = bare || path.exists() || (given && k == 0);
            if !tried {
                continue;
            }
            match Oidn::open(&path, threads) {
                Ok(oidn) => return Denoiser::checked(oidn, path),
                Err(e) if given && k == 0 => {
                    return Err(DenoiseError::NotFound {
                        detail: format!(" at {} (from {}): {e}", path.display(), search::ENV_VAR),
                    })
                }
                Err(_) => continue,
            }
        }
        Err(DenoiseError::NotFound {
            detail: String::new(),
        })
    }

    fn checked(oidn: Oidn, library: PathBuf) -> Result<Denoiser, DenoiseError> {
        let denoiser = Denoiser { oidn, library };
        if denoiser.oidn.version() < OLDEST_VERSION {
            return Err(DenoiseError::TooOld {
                library: denoiser.library.display().to_string(),
                version: denoiser.version(),
            });
        }
        Ok(denoiser)
    }

    /// The library's file, as found.
    pub fn library(&self) -> &Path {
        &self.library
    }

    /// The library's version, `major.minor.patch`.
    pub fn version(&self) -> String {
        let v = self.oidn.version();
        format!("{}.{}.{}", v / 10000, v / 100 % 100, v % 100)
    }

    /// `color` denoised, guided by `albedo` (in [0, 1]) and `normal` (world-space,
    /// any length up to 1) of the same size: linear values in, linear values out
    /// (values above 1 kept: the filter runs in its high-dynamic-range mode), the
    /// guides taken as noise-free (they are averages over the pixel's samples of
    /// first hits, whose only noise is that of edges, lenses and motion), by the
    /// network of `quality`.
    pub fn denoise(
        &self,
        color: &Image,
        albedo: &Image,
        normal: &Image,
        quality: Quality,
    ) -> Result<Image, DenoiseError> {
        let (w, h) = (color.width, color.height);
        for guide in [albedo, normal] {
            if (guide.width, guide.height) != (w, h) {
                return Err(DenoiseError::Size(w, h, guide.width, guide.height));
            }
        }
        let flat =
            |image: &Image| -> Vec<f32> { image.pixels.iter().flat_map(|p| [p.x, p.y, p.z]).collect() };
        let mut output = vec![0.0; 3 * color.pixels.len()];
        self.oidn
            .filter_rt(
                (w as usize, h as usize),
                &flat(color),
                &flat(albedo),
                &flat(normal),
                &mut output,
                true,
                true,
                quality.code(),
            )
            .map_err(DenoiseError::Failed)?;
        let pixels = output
            .chunks_exact(3)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect();
        Ok(Image::from_pixels(w, h, pixels))
    }

    /// `image`, rendered with `opts`, denoised with its `aovs` as guides. A
    /// path-traced picture's directly seen emitters and background
    /// ([`Aovs::emission`]: what its camera rays meet and add as they are, without
    /// noise) are set apart and added back after the filter, which would otherwise
    /// spread a lamp's bright edge over the wall beside it.
    pub fn denoise_render(
        &self,
        image: &Image,
        aovs: &Aovs,
        opts: &RenderOptions,
        quality: Quality,
    ) -> Result<Image, DenoiseError> {
        if opts.integrator != IntegratorKind::Path {
            return self.denoise(image, &aovs.albedo, &aovs.normal, quality);
        }
        let emitted = &aovs.emission;
        if (emitted.width, emitted.height) != (image.width, image.height) {
            return Err(DenoiseError::Size(
                image.width,
                image.height,
                emitted.width,
                emitted.height,
            ));
        }
        let zero_floor = |v: Vec3| Vec3::new(v.x.max(0.0), v.y.max(0.0), v.z.max(0.0));
        let rest = image
            .pixels
            .iter()
            .zip(&emitted.pixels)
            .map(|(&c, &e)| zero_floor(c - e))
            .collect();
        let rest = Image::from_pixels(image.width, image.height, rest);
        let mut clean = self.denoise(&rest, &aovs.albedo, &aovs.normal, quality)?;
        for (c, &e) in clean.pixels.iter_mut().zip(&emitted.pixels) {
            *c += e;
        }
        Ok(clean)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_library_is_an_error_that_says_how_to_get_it() {
        let e = DenoiseError::NotFound {
            detail: String::new(),
        };
        let text = e.to_string();
        assert!(
            text.contains("pip install pyoidn") && text.contains("NFFRT_OIDN"),
            "{text}"
        );
    }
}
