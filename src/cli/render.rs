//! `nffrt render`: trace a scene into an image file.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;

use super::finish::Finishing;
use super::frames::{self, FrameArgs};
use super::image_out::{display_name, format_of, is_stdout, Destination};
use super::limits::{refused, RenderLimitArgs};
use super::load::{load_scene, print_warnings, Need};
use super::output::{cannot_write, refuse_overwriting, write_stdout, AtomicOutput, Named};
use super::progress::{Progress, ProgressMode};
use super::stats::{self, StatsReport};
use super::values::{self, whole_number};
use super::{animation, interrupt, pixel, CliError};
use nffrt::denoise::Quality;
use nffrt::fingerprint::{options_fingerprint, options_text};
use nffrt::image::tiles::{self, TileFingerprint};
use nffrt::image::Region;
use nffrt::image::{Encoding, ImageFormat, SOFTWARE_TEXT};
use nffrt::limits::{
    DEFAULT_EFFECT_SPP, DEFAULT_MAX_DEPTH, MAX_LIGHT_SAMPLES, MAX_RAY_DEPTH, MAX_RESOLUTION, MAX_SPP,
    MAX_THREADS,
};
use nffrt::options::{RenderOptions, RenderRequest, Resolved};
use nffrt::prepare::{prepare_with, PrepareOptions};
use nffrt::render::Aov;
use nffrt::render::{region_eye_rows, render_region, RenderError};
use nffrt::scene::{Accel, IntegratorKind, SceneInfo};
use nffrt::words::count;

/// Arguments of `nffrt render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Scene file, NFF, P3F or AFF (by its extension or --format); `-` reads standard input.
    pub scene: PathBuf,
    /// Output image: .png (8-bit), .ppm (binary P6, 8-bit), .pfm or .exr (linear
    /// float); `-` writes PNG to standard output. Default: the scene's file stem +
    /// .png in the current directory, or with --region the stem + .X0-Y0-X1-Y1.png
    /// (a tile never takes the full picture's name).
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    #[arg(long, value_name = "N", allow_negative_numbers = true,
          help = format!("Image width, 1 to {MAX_RESOLUTION} (default: the scene's). Given alone, the height \
                          follows the scene's aspect ratio; with --height, both are exact"),
          value_parser = whole_number::<u32>(1, MAX_RESOLUTION as u64))]
    pub width: Option<u32>,
    #[arg(long, value_name = "N", allow_negative_numbers = true,
          help = format!("Image height, 1 to {MAX_RESOLUTION} (default: the scene's). Given alone, the width \
                          follows the scene's aspect ratio; with --width, both are exact"),
          value_parser = whole_number::<u32>(1, MAX_RESOLUTION as u64))]
    pub height: Option<u32>,
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_DEPTH, allow_negative_numbers = true,
          help = format!("Maximum ray-tree depth, 1 to {MAX_RAY_DEPTH}; the eye ray is depth 1"),
          value_parser = whole_number::<u32>(1, MAX_RAY_DEPTH as u64))]
    pub max_depth: u32,
    #[arg(long, value_name = "N", allow_negative_numbers = true,
          help = format!("Worker threads for parsing (files of 1 MiB or more), building and rendering, \
                          1 to {MAX_THREADS} (default: one per core)"),
          value_parser = whole_number::<u32>(1, MAX_THREADS as u64))]
    pub threads: Option<u32>,
    /// SPD benchmark protocol: rays through the (w+1) x (h+1) pixel corners, the four
    /// corners averaged into each pixel.
    #[arg(long)]
    pub spd: bool,
    #[arg(long, value_name = "N", conflicts_with = "spd", allow_negative_numbers = true,
          help = format!("Samples per pixel, 1 to {MAX_SPP}: stratified jittered supersampling, \
                          box-filtered, the same image on every run and thread count (1: pixel centres). \
                          Default: the file's P3F `spp`, else 1, or {DEFAULT_EFFECT_SPP} when an effect \
                          needs samples (a lens, motion, roughness, path tracing)"),
          value_parser = whole_number::<u32>(1, MAX_SPP as u64))]
    pub spp: Option<u32>,
    /// Lens diameter in pixels of the view plane (depth of field; 0 is a pinhole).
    /// Default: the scene's (P3F `aperture`), else 0.
    #[arg(long, value_name = "PIXELS", allow_negative_numbers = true,
          value_parser = values::number_at_least_zero)]
    pub aperture: Option<f32>,
    /// Distance of the plane of sharp focus, as a multiple of the distance from the
    /// camera to its look-at point. Default: the scene's (P3F `focal`), else 1.
    #[arg(long, value_name = "RATIO", allow_negative_numbers = true,
          value_parser = values::number_above_zero)]
    pub focal: Option<f32>,
    #[arg(long, value_name = "N", allow_negative_numbers = true,
          help = format!("Sample every area light on an N x N grid at every hit, whatever the sampling \
                          (default: the light's own grid with one sample per pixel, one point per sample \
                          with more); 1 to {MAX_LIGHT_SAMPLES}"),
          value_parser = whole_number::<u32>(1, MAX_LIGHT_SAMPLES as u64))]
    pub light_samples: Option<u32>,
    /// The sample pattern, 0 to 4294967295: 0 (the default) gives nffrt's usual
    /// pictures, any other number an unrelated pattern, as deterministic (average
    /// renders of several seeds, or compare their noise).
    #[arg(long, value_name = "N", allow_negative_numbers = true,
          value_parser = whole_number::<u32>(0, u32::MAX as u64))]
    pub seed: Option<u32>,
    /// The light transport: `whitted` (recursive ray tracing, the SPD's and the
    /// course's rules) or `path` (path tracing with next-event estimation). Default:
    /// the file's P3F `integrator`, else whitted.
    #[arg(long, value_name = "NAME", value_parser = values::integrator())]
    pub integrator: Option<IntegratorKind>,
    /// The acceleration structure: `bvh`, `grid` (uniform) or `none` (every primitive
    /// tested for every ray). All three give the same picture; --stats shows the
    /// work each does. Default: the file's P3F `accel`, else bvh.
    #[arg(long, value_enum, value_name = "NAME")]
    pub accel: Option<AccelArg>,
    /// Render only the crop X0,Y0,X1,Y1 (X1, Y1 exclusive) of the full image, as a PNG
    /// tile that records its place and a fingerprint of the scene and settings;
    /// `nffrt merge` assembles tiles.
    #[arg(long, value_name = "X0,Y0,X1,Y1", allow_hyphen_values = true, value_parser = values::region)]
    pub region: Option<Region>,
    /// How 8-bit pictures (PNG, PPM) hold the values: `linear` (each channel clamped
    /// to [0, 1] and scaled, as the SPD's and the course's Whitted pictures),
    /// `srgb` (the sRGB curve, as pbrt and Mitsuba write theirs) or `gamma2.2` (the
    /// course's path tracer's toGamma). Default: linear for Whitted's pictures;
    /// path-traced ones gamma2.2 for P3F scenes, srgb for NFF. Not with .pfm or
    /// .exr, which hold the linear values; a tile records it, and merge refuses to mix.
    #[arg(long, value_name = "NAME", value_parser = values::encoding())]
    pub encoding: Option<Encoding>,
    /// The same as --encoding srgb.
    #[arg(long, conflicts_with = "encoding")]
    pub srgb: bool,
    /// Denoise the picture with Intel Open Image Denoise (its RT filter, guided by
    /// the first hits' albedo and normal) once it is rendered: for path tracing and
    /// sampled effects. `--denoise=fast` (or `balanced`) takes the smaller, faster
    /// network; `--denoise` alone is `high`. Needs the library: `pip install
    /// pyoidn`, or NFFRT_OIDN naming it (docs/denoise.md).
    #[arg(long, value_name = "QUALITY", num_args = 0..=1, require_equals = true,
          default_missing_value = "high", value_parser = values::quality())]
    pub denoise: Option<Quality>,
    /// Also write these of each pixel's first hits, comma-separated: `albedo`,
    /// `normal`, `depth`; as layers of an .exr picture, else beside the picture
    /// (NAME.albedo.png for NAME.png).
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = values::aov())]
    pub aov: Vec<Aov>,
    /// Trace only pixel X,Y (column and row, from 0) and print its ray tree to standard
    /// output: no image, so not with --output, --region, --srgb, --encoding,
    /// --denoise, --aov, --stats or --stats-json.
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true, value_parser = values::pixel,
          conflicts_with_all = ["region", "output", "srgb", "encoding", "denoise", "aov", "stats", "stats_json"])]
    pub pixel: Option<(u32, u32)>,
    /// Print the settings (size, region, sampling, depth), ray counts and timings; to
    /// standard error when standard output carries the image or the JSON.
    #[arg(long)]
    pub stats: bool,
    /// Write the same as JSON to FILE; `-` is standard output (not with `-o -`).
    #[arg(long, value_name = "FILE")]
    pub stats_json: Option<PathBuf>,
    /// Report progress as plain lines on standard error (one per tenth of the rows),
    /// also when it is not a terminal, as in a log file.
    #[arg(long, conflicts_with = "quiet")]
    pub progress: bool,
    /// No progress bar and no closing summary line.
    #[arg(short, long)]
    pub quiet: bool,
    /// The frames of an animated (AFF) scene.
    #[command(flatten)]
    pub frames: FrameArgs,
    /// Resource limits (see "Limits" in docs/command-line.md).
    #[command(flatten)]
    pub limits: RenderLimitArgs,
}

/// The default output file: the scene's stem (`stdin` for standard input) + `.png`,
/// or for a tile the stem + `.X0-Y0-X1-Y1.png`.
fn default_output(scene: &Path, region: Option<&Region>) -> PathBuf {
    let stem = scene.file_stem().filter(|_| scene != Path::new("-"));
    let stem = stem
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "stdin".into());
    match region {
        Some(r) => PathBuf::from(format!("{stem}.{}-{}-{}-{}.png", r.x0, r.y0, r.x1, r.y1)),
        None => PathBuf::from(format!("{stem}.png")),
    }
}

/// The 8-bit encoding `--encoding` (or `--srgb`) asks for, if any; refused for the
/// float formats, which hold the linear values.
fn asked_encoding(
    args: &RenderArgs,
    format: ImageFormat,
    out_path: &Path,
) -> Result<Option<Encoding>, CliError> {
    let asked = args.encoding.or(args.srgb.then_some(Encoding::Srgb));
    match asked {
        Some(e) if e != Encoding::Linear && !format.is_8bit() => Err(CliError::usage(format!(
            "--encoding {e}: {} holds linear floats; encodings are for 8-bit .png and .ppm",
            out_path.display()
        ))),
        _ => Ok(asked),
    }
}

/// The encoding a picture in `format` is written with, `resolved` for the scene:
/// float pictures hold the linear values, whatever the 8-bit default.
pub fn written_encoding(format: ImageFormat, resolved: Encoding) -> Encoding {
    if format.is_8bit() {
        resolved
    } else {
        Encoding::Linear
    }
}

/// Refuses an image or stats file that would replace the scene file, or each other.
fn refuse_overwriting_inputs(args: &RenderArgs, out_path: &Path, beside: &[&Path]) -> Result<(), CliError> {
    let image = match &args.output {
        Some(path) => Named::flag("-o", path),
        None => Named {
            path: out_path,
            named: format!("the default output {}", out_path.display()),
        },
    };
    let stats = args.stats_json.as_deref().map(|p| Named::flag("--stats-json", p));
    let aovs = beside.iter().map(|p| Named::flag("--aov", p));
    let outputs: Vec<Named<'_>> = std::iter::once(image).chain(stats).chain(aovs).collect();
    refuse_overwriting(&outputs, &[(&args.scene, "the scene file")])
}

/// The values of `--accel`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum AccelArg {
    /// Every primitive tested for every ray.
    None,
    /// A uniform grid.
    Grid,
    /// The bounding volume hierarchy.
    Bvh,
}

impl From<AccelArg> for Accel {
    fn from(a: AccelArg) -> Accel {
        match a {
            AccelArg::None => Accel::None,
            AccelArg::Grid => Accel::Grid,
            AccelArg::Bvh => Accel::Bvh,
        }
    }
}

/// What `args` ask of the render-time scene.
pub fn prepare_options(args: &RenderArgs) -> PrepareOptions {
    PrepareOptions {
        accel: args.accel.map(Into::into),
        ..PrepareOptions::default()
    }
}

/// What `args` ask of the render.
pub fn request(args: &RenderArgs) -> RenderRequest {
    RenderRequest {
        width: args.width,
        height: args.height,
        spp: args.spp,
        spd: args.spd,
        max_depth: Some(args.max_depth),
        aperture: args.aperture,
        focal: args.focal,
        light_samples: args.light_samples,
        hard_shadows: false,
        seed: args.seed,
        integrator: args.integrator,
        smooth: false,
        encoding: args.encoding.or(args.srgb.then_some(Encoding::Srgb)),
    }
}

/// The render settings `args` ask for on `scene` and the 8-bit encoding, its notes
/// printed to standard error (unless `--quiet`); a request the scene cannot take is
/// a usage error.
pub fn resolve(args: &RenderArgs, scene: &SceneInfo) -> Result<(RenderOptions, Encoding), CliError> {
    let Resolved {
        opts,
        encoding,
        notes,
    } = request(args).resolve(scene).map_err(CliError::usage)?;
    if !args.quiet {
        for note in notes {
            eprintln!("note: {note}");
        }
    }
    Ok((opts, encoding))
}

/// Runs `nffrt render`.
pub fn run(args: RenderArgs) -> Result<(), CliError> {
    if let Some(xy) = args.pixel {
        return pixel::run(&args, xy);
    }
    let out_path = (args.output.clone()).unwrap_or_else(|| default_output(&args.scene, args.region.as_ref()));
    let format = format_of(&out_path)?;
    asked_encoding(&args, format, &out_path)?;
    let beside: Vec<PathBuf> = super::finish::asked_aovs(&args)
        .into_iter()
        .filter(|_| format != ImageFormat::Exr && !is_stdout(&out_path))
        .map(|a| super::finish::beside_path(&out_path, a))
        .collect();
    refuse_overwriting_inputs(
        &args,
        &out_path,
        &beside.iter().map(PathBuf::as_path).collect::<Vec<_>>(),
    )?;
    if args.region.is_some() && format != ImageFormat::Png {
        return Err(CliError::usage(format!(
            "{}: --region writes PNG tiles (their place is kept in a PNG text chunk)",
            out_path.display()
        )));
    }
    let json_to_stdout = args.stats_json.as_deref().is_some_and(is_stdout);
    if json_to_stdout && is_stdout(&out_path) {
        return Err(CliError::usage(
            "--stats-json - and -o - both ask for standard output; send one of them to a file",
        ));
    }
    // One pool for parsing (large files go in pieces), building and rendering.
    let threads = args.threads.map(|t| t as usize).unwrap_or_else(num_cpus);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| {
            CliError::io(format!(
                "cannot start {}: {e}",
                count(threads, "thread", "threads")
            ))
        })?;
    let need = if args.region.is_some() {
        Need::Tile
    } else {
        Need::Render
    };
    let t0 = Instant::now();
    let mut loaded = pool.install(|| load_scene(&args.scene, &args.limits.scene, need))?;
    let load_s = t0.elapsed().as_secs_f64();
    print_warnings(&loaded, 20);
    let mut out_path = out_path;
    let aovs = super::finish::asked_aovs(&args);
    match frames::plan(&args.frames, &loaded, &args.scene, args.output.as_deref(), &aovs)?.as_deref() {
        None => {}
        Some([one]) if args.frames.motion_blur.is_none() => {
            loaded.scene = frames::flatten(&loaded, one)?;
            // A tile records the time it shows: tiles of two frames never merge.
            loaded.fingerprint = loaded.fingerprint.map(|f| frames::fingerprint_at(f, one.time));
            out_path = one.output.clone();
        }
        // Several frames, or one blurred over its interval.
        Some(several) => return animation::run(&args, &pool, &loaded, several),
    }
    let info = loaded.scene.info();
    let (opts, encoding) = resolve(&args, &info)?;
    let encoding = written_encoding(format, encoding);
    let full = Region::full(opts.width, opts.height);
    let region = args.region.unwrap_or(full);
    let sized_by_flags = args.width.is_some() || args.height.is_some() || args.region.is_some();
    args.limits.check(&opts, &region, sized_by_flags)?;
    let finishing = Finishing::plan(&args, &out_path, format, &opts, threads)?;
    let finish = finishing.open(&out_path)?;
    // Open the output (and the stats file) before the work, to fail fast.
    let output = Destination::create(&out_path)?;
    let stats_file = args.stats_json.as_deref().filter(|p| !is_stdout(p));
    let mut stats_out = stats_file.map(AtomicOutput::create).transpose()?;

    let t1 = Instant::now();
    let skybox = loaded.assets.skybox.is_some();
    let scene = pool.install(|| prepare_with(loaded.scene, &loaded.assets, &prepare_options(&args)));
    let build_s = t1.elapsed().as_secs_f64();
    interrupt::check()?;
    let t2 = Instant::now();
    let progress = Progress::new(region_eye_rows(&opts, &region), progress_mode(&args));
    let limits = args.limits.render_limits();
    let rendered = pool.install(|| render_region(&scene, scene.view(), &opts, &region, &limits, &progress));
    progress.finish();
    let (image, rays) = rendered.map_err(|e| render_error(e, sized_by_flags))?;
    let render_s = t2.elapsed().as_secs_f64();
    interrupt::check()?;
    let denoiser = finishing.denoiser_text();
    let finished = pool.install(|| finish.run(&scene, &opts, &limits, image, format, encoding))?;

    let mut text = vec![(SOFTWARE_TEXT.0, SOFTWARE_TEXT.1.to_string())];
    if let Some(scene_print) = loaded.fingerprint {
        text.extend(tile_text(&region, &opts, scene_print));
        text.extend(tiles::encoding_text(encoding));
    }
    finished.write(output, format, encoding, &text)?;

    let wants_stats = args.stats || args.stats_json.is_some();
    let accel = wants_stats.then(|| pool.install(|| stats::accel_work(&scene, &opts, &region)));
    let mut report = StatsReport::new(
        stats::settings(&opts, &region, threads, &info, skybox),
        scene.primitive_count(),
        accel,
        rays,
        [load_s, loaded.parse_s, build_s, render_s],
    );
    report.skybox_decode_s = skybox.then(|| scene.background().decode_seconds());
    report.stages = stats::StagesReport::of(&progress.stages());
    report.settings.push("encoding", encoding.name().into());
    report.settings.push("denoise", denoiser.into());
    report.aov_s = finished.aov_s;
    report.denoise_s = finished.denoise_s;
    if let (Some(mut out), Some(path)) = (stats_out.take(), stats_file) {
        writeln!(out.writer(), "{}", report.json()).map_err(|e| cannot_write(path.display(), &e))?;
        out.commit()?;
    } else if json_to_stdout {
        write_stdout(|w| writeln!(w, "{}", report.json()))?;
    }
    if args.stats {
        // Standard output carrying an image or JSON holds nothing else.
        if is_stdout(&out_path) || json_to_stdout {
            eprintln!("{}", report.text());
        } else {
            outln!("{}", report.text());
        }
    }
    if !args.quiet {
        let crop = if region == full {
            String::new()
        } else {
            format!(" (region {region})")
        };
        eprintln!(
            "rendered {} in {:.2} s (load {:.2}, build {:.2}, render {:.2} s): {}, {:.1} Mrays/s, {}x{}{crop}, {}, {}",
            display_name(&out_path),
            load_s + build_s + render_s,
            load_s,
            build_s,
            render_s,
            count(report.total_rays, "ray", "rays"),
            report.mrays_per_s,
            opts.width,
            opts.height,
            opts.sampling,
            count(threads, "thread", "threads")
        );
    }
    Ok(())
}

/// A render that did not run to the end as the command line reports it: a refusal
/// ([`refused`]), an interruption (the only cancellation), or a skybox face that
/// could not be read (an I/O error).
pub fn render_error(e: RenderError, from_flags: bool) -> CliError {
    match e {
        RenderError::Refused(e) => refused(e, from_flags),
        RenderError::Cancelled => interrupt::error(),
        RenderError::Asset(e) => CliError::io(e.to_string()),
    }
}

/// The text chunks of a tile: its place, its fingerprint (the scene's and that of
/// every option), and the options in words.
fn tile_text(region: &Region, opts: &RenderOptions, scene: u64) -> [(&'static str, String); 3] {
    let fingerprint = TileFingerprint {
        scene,
        options: options_fingerprint(opts),
    };
    [
        (
            tiles::REGION_KEY,
            tiles::region_text(region, opts.width, opts.height),
        ),
        (tiles::FINGERPRINT_KEY, fingerprint.to_string()),
        (tiles::OPTIONS_KEY, options_text(opts)),
    ]
}

pub fn progress_mode(args: &RenderArgs) -> ProgressMode {
    match (args.quiet, args.progress) {
        (true, _) => ProgressMode::Off,
        (false, true) => ProgressMode::Lines,
        (false, false) => ProgressMode::Terminal,
    }
}

fn num_cpus() -> usize {
    std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1)
}
