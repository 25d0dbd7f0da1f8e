//! Resource limits on the command line: how large a scene file, how many primitives,
//! vertices and lights, and how many pixels one run may take on. Everything is
//! checked before the memory it guards is allocated; each limit has a flag to raise
//! it (see "Limits" in `docs/command-line.md`). The pixel limit is the renderer's
//! own ([`RenderLimits`]), which `--max-pixels` sets.

use clap::Args;

use super::values::whole_number;
use super::CliError;
use nffrt::image::Region;
use nffrt::limits::{
    DEFAULT_MAX_LIGHTS, DEFAULT_MAX_PIXELS, DEFAULT_MAX_PRIMITIVES, DEFAULT_MAX_SCENE_BYTES,
    DEFAULT_MAX_VERTICES,
};
use nffrt::nff::{Format, Limits};
use nffrt::options::{check_render, Refused, RenderLimits, RenderOptions};
use nffrt::words::count;

/// How a scene file is read, and the limits on what it may make nffrt read and build.
#[derive(Args, Debug, Clone)]
pub struct SceneLimitArgs {
    /// The scene's language; default: by the extension (`.p3f` is P3F, `.aff` AFF,
    /// anything else NFF). Needed for P3F or AFF on standard input.
    #[arg(long, value_enum, value_name = "FORMAT")]
    pub format: Option<FormatArg>,
    /// Refuse scene files larger than N bytes.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_SCENE_BYTES,
          allow_negative_numbers = true, value_parser = whole_number::<u64>(0, u64::MAX))]
    pub max_scene_bytes: u64,
    /// Refuse scenes with more than N primitives.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_PRIMITIVES,
          allow_negative_numbers = true, value_parser = whole_number::<usize>(0, u64::MAX))]
    pub max_primitives: usize,
    /// Refuse scenes with more than N polygon, patch and mesh vertices in all.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_VERTICES,
          allow_negative_numbers = true, value_parser = whole_number::<usize>(0, u64::MAX))]
    pub max_vertices: usize,
    /// Refuse scenes with more than N lights.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_LIGHTS,
          allow_negative_numbers = true, value_parser = whole_number::<usize>(0, u64::MAX))]
    pub max_lights: usize,
}

/// The values of `--format`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum FormatArg {
    /// NFF (the SPD's format, with nffrt's `pl` and `aabb`).
    Nff,
    /// P3F, the IST course's extended NFF (both dialects).
    P3f,
    /// AFF, BART's animated NFF (docs/aff.md).
    Aff,
}

impl From<FormatArg> for Format {
    fn from(f: FormatArg) -> Format {
        match f {
            FormatArg::Nff => Format::Nff,
            FormatArg::P3f => Format::P3f,
            FormatArg::Aff => Format::Aff,
        }
    }
}

impl Default for SceneLimitArgs {
    fn default() -> Self {
        SceneLimitArgs {
            format: None,
            max_scene_bytes: DEFAULT_MAX_SCENE_BYTES,
            max_primitives: DEFAULT_MAX_PRIMITIVES,
            max_vertices: DEFAULT_MAX_VERTICES,
            max_lights: DEFAULT_MAX_LIGHTS,
        }
    }
}

impl SceneLimitArgs {
    /// The parser's share of the limits.
    pub fn parse_limits(&self) -> Limits {
        Limits {
            max_primitives: self.max_primitives,
            max_vertices: self.max_vertices,
            max_lights: self.max_lights,
        }
    }
}

/// The scene limits plus the image size limit of `nffrt render`.
#[derive(Args, Debug, Clone)]
pub struct RenderLimitArgs {
    /// Limits on the scene file.
    #[command(flatten)]
    pub scene: SceneLimitArgs,
    /// Refuse to render more than N pixels (counting the (w+1) x (h+1) corners with --spd).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_PIXELS,
          allow_negative_numbers = true, value_parser = whole_number::<u64>(0, u64::MAX))]
    pub max_pixels: u64,
}

impl RenderLimitArgs {
    /// The limits a render takes from these flags.
    pub fn render_limits(&self) -> RenderLimits {
        RenderLimits {
            max_pixels: self.max_pixels,
        }
    }

    /// Checks a render of `region` with `opts` as the renderer will
    /// ([`check_render`] under `--max-pixels`), before any memory it guards is
    /// allocated; a refusal is an error whose code says whether the size came from
    /// the command line (`from_flags`) or from the file ([`refused`]).
    pub fn check(&self, opts: &RenderOptions, region: &Region, from_flags: bool) -> Result<(), CliError> {
        check_render(opts, region, &self.render_limits()).map_err(|e| refused(e, from_flags))
    }
}

/// A refused render as the command line reports it: too many pixels names the flag
/// that raises the limit and is a usage error if the size came from the command
/// line (`from_flags`), a bad scene if it came from the file; any other refusal is a
/// usage error. Supersampling (`--spp`) takes more time, not more memory, so it does
/// not count.
pub fn refused(e: Refused, from_flags: bool) -> CliError {
    let Refused::TooManyPixels {
        width,
        height,
        points,
        limit,
    } = e
    else {
        return CliError::usage(e.to_string());
    };
    let message = format!(
        "{width}x{height} is {}, more than the limit of {limit} (--max-pixels raises it; \
         the image takes about 24 bytes per pixel while rendering)",
        count(points, "pixel", "pixels"),
    );
    if from_flags {
        CliError::usage(message)
    } else {
        CliError::scene(message)
    }
}
