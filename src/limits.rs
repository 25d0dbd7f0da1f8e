//! Every limit and default of nffrt in one place: what a scene file may describe,
//! what one render may ask for, and the defaults a render takes when neither the
//! file nor the caller says. The parser, the renderer, the command line, the viewer
//! and the Python bindings all read them from here, so each is written once.

// What a scene file may make the parser allocate (`nff::Limits`; raised on the
// command line by `--max-primitives`, `--max-vertices`, `--max-lights`).

/// Default of `nff::Limits::max_primitives`, and the most primitives a generated
/// scene ([`crate::gen`]) may have.
pub const DEFAULT_MAX_PRIMITIVES: usize = 10_000_000;
/// Default of `nff::Limits::max_vertices`.
pub const DEFAULT_MAX_VERTICES: usize = 40_000_000;
/// Default of `nff::Limits::max_lights`.
pub const DEFAULT_MAX_LIGHTS: usize = 100_000;
/// The most warnings a scene keeps; past it one final warning gives the number left out.
pub const MAX_WARNINGS: usize = 1000;
/// Default of `--max-scene-bytes`: 2 GiB of scene text.
pub const DEFAULT_MAX_SCENE_BYTES: u64 = 2 << 30;
/// The largest skybox face accepted, in texels (a 16384 x 16384 image).
pub const MAX_FACE_TEXELS: u64 = 1 << 28;
/// How deep an AFF scene's includes may nest (the file loaded is depth 1); BART's
/// scenes reach 3.
pub const MAX_INCLUDE_DEPTH: usize = 32;
/// The most includes an AFF scene may follow in all (a file included twice counts
/// twice); BART's robot scene follows 835. Bounds a scene whose files include each
/// other many times over without a cycle.
pub const MAX_INCLUSIONS: usize = 1 << 16;
/// The largest AFF texture accepted, in texels (an 8192 x 8192 image).
pub const MAX_TEXTURE_TEXELS: u64 = 1 << 26;

// What one render may ask for.

/// The largest image side, in the file's `resolution` and in every render.
pub const MAX_RESOLUTION: u32 = 32768;
/// The most samples per pixel, from a file's `spp` or a caller.
pub const MAX_SPP: u32 = 4096;
/// The deepest ray tree (the eye ray is depth 1): the recursion stays far from the
/// stack limit of rayon's worker threads.
pub const MAX_RAY_DEPTH: u32 = 64;
/// The largest area-light grid side (`--light-samples`).
pub const MAX_LIGHT_SAMPLES: u32 = 64;
/// The most eye-ray grid points (`options::eye_grid_points`) a render may have
/// unless its caller raises the limit (`options::RenderLimits`, which
/// `--max-pixels` sets): 64 Mi (8192 x 8192), about 1.6 GB of float image while
/// rendering.
pub const DEFAULT_MAX_PIXELS: u64 = 1 << 26;
/// The most worker threads a caller may ask for.
pub const MAX_THREADS: u32 = 1024;

/// The most sub-frames `--motion-blur` averages into one frame of an animation.
pub const MAX_MOTION_BLUR_SUBFRAMES: u32 = 1024;

// Defaults.

/// The default maximum ray-tree depth (the SPD's).
pub const DEFAULT_MAX_DEPTH: u32 = 5;
/// Samples per pixel of a render whose camera or scene has an effect that one
/// centred sample would drop (a lens) when neither the file nor the caller says
/// how many: enough to show it (the viewer's default too).
pub const DEFAULT_EFFECT_SPP: u32 = 16;
/// The shutter interval `[open, close]` of a scene that gives none (P3F `shutter`):
/// the course's templates open the camera from time 0 to 1.
pub const DEFAULT_SHUTTER: [f32; 2] = [0.0, 1.0];
/// Grid side of a P3F 2019 `al` area light, whose file gives none: 16 points with
/// one eye sample per pixel.
pub const AREA_LIGHT_GRID: u32 = 4;
