//! `nffrt render`: trace a scene into an image file.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use serde::Serialize;

use super::image_out::{display_name, format_of, Destination, Format, SOFTWARE_TEXT};
use super::limits::RenderLimitArgs;
use super::load::{build_bvh, load_scene_with, print_warnings};
use super::output::AtomicOutput;
use super::progress::Progress;
use super::{interrupt, pixel, CliError};
use nffrt::image::{tiles, Region};
use nffrt::render::{region_eye_rows, render_region, RenderOptions, Sampling, Stats, DEFAULT_MAX_DEPTH};
use nffrt::Scene;

/// The deepest ray tree allowed (keeps the recursion far from the stack limit).
pub const MAX_DEPTH_CAP: u32 = 64;
/// The most samples per pixel `--spp` accepts.
pub const MAX_SPP: u32 = 4096;

/// Arguments of `nffrt render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Scene file (NFF); `-` reads standard input.
    pub scene: PathBuf,
    /// Output image: .png (8-bit), .ppm (binary P6) or .pfm (linear float); `-` writes
    /// PNG to standard output. Default: the scene's file stem + .png in the current
    /// directory.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Image width (default: the scene's resolution).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=32768))]
    pub width: Option<u32>,
    /// Image height (default: the scene's resolution).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=32768))]
    pub height: Option<u32>,
    /// Maximum ray-tree depth; the eye ray is depth 1.
    #[arg(long, default_value_t = DEFAULT_MAX_DEPTH, value_parser = clap::value_parser!(u32).range(1..=MAX_DEPTH_CAP as i64))]
    pub max_depth: u32,
    /// Worker threads for parsing (files of 1 MiB or more), building and rendering
    /// (default: one per core).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// SPD benchmark protocol: rays through the (w+1) x (h+1) pixel corners, the four
    /// corners averaged into each pixel.
    #[arg(long)]
    pub spd: bool,
    /// Samples per pixel: stratified jittered supersampling, box-filtered, the same
    /// image on every run and thread count (1: pixel centres).
    #[arg(long, value_name = "N", conflicts_with = "spd", value_parser = clap::value_parser!(u32).range(1..=MAX_SPP as i64))]
    pub spp: Option<u32>,
    /// Lens diameter in pixels of the view plane (depth of field; 0 is a pinhole).
    /// Default: the scene's (P3F `aperture`), else 0.
    #[arg(long, value_name = "PIXELS", value_parser = non_negative)]
    pub aperture: Option<f32>,
    /// Distance of the plane of sharp focus, as a multiple of the distance from the
    /// camera to its look-at point. Default: the scene's (P3F `focal`), else 1.
    #[arg(long, value_name = "RATIO", value_parser = positive)]
    pub focal: Option<f32>,
    /// Sample every area light on an N x N grid at every hit, whatever the sampling
    /// (default: the light's own grid with one sample per pixel, one point per
    /// sample with more); 1 to 64.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=64))]
    pub light_samples: Option<u32>,
    /// Render only the crop X0,Y0,X1,Y1 (X1, Y1 exclusive) of the full image, as a PNG
    /// tile that records its place; `nffrt merge` assembles tiles.
    #[arg(long, value_name = "X0,Y0,X1,Y1")]
    pub region: Option<String>,
    /// Trace only pixel X,Y and print its ray tree to standard output (no image).
    #[arg(long, value_name = "X,Y", conflicts_with = "region")]
    pub pixel: Option<String>,
    /// Print a summary of ray counts and timings.
    #[arg(long)]
    pub stats: bool,
    /// Write ray counts and timings as JSON to this file.
    #[arg(long, value_name = "FILE")]
    pub stats_json: Option<PathBuf>,
    /// No progress bar and no closing summary line.
    #[arg(short, long)]
    pub quiet: bool,
    /// Resource limits (see "Limits" in docs/command-line.md).
    #[command(flatten)]
    pub limits: RenderLimitArgs,
}

/// Counts and timings, as written by `--stats-json`.
#[derive(Serialize)]
struct StatsJson {
    #[serde(flatten)]
    rays: Stats,
    total_rays: u64,
    width: u32,
    height: u32,
    max_depth: u32,
    threads: usize,
    primitives: usize,
    parse_s: f64,
    build_s: f64,
    render_s: f64,
    mrays_per_s: f64,
}

fn default_output(scene: &Path) -> PathBuf {
    let stem = scene.file_stem().filter(|_| scene != Path::new("-"));
    let stem = stem
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "stdin".into());
    PathBuf::from(format!("{stem}.png"))
}

/// The render settings `args` ask for on `scene`.
pub fn render_options(args: &RenderArgs, scene: &Scene) -> RenderOptions {
    RenderOptions {
        width: args.width.unwrap_or(scene.view.width),
        height: args.height.unwrap_or(scene.view.height),
        max_depth: args.max_depth,
        // The file's `spp` (P3F) is the default; the flag wins.
        sampling: match (args.spd, args.spp.or(scene.spp)) {
            (true, _) => Sampling::SpdCorners,
            (false, Some(n)) if n > 1 => Sampling::Stratified { spp: n },
            _ => Sampling::PixelCenters,
        },
        aperture: args.aperture,
        focal: args.focal,
        light_samples: args.light_samples,
        ..Default::default()
    }
}

/// A finite number of at least 0 (for `--aperture`).
fn non_negative(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(format!("'{s}' is not a finite number of at least 0")),
    }
}

/// A finite number above 0 (for `--focal`).
fn positive(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("'{s}' is not a finite number above 0")),
    }
}

/// Runs `nffrt render`.
pub fn run(args: RenderArgs) -> Result<(), CliError> {
    if args.pixel.is_some() {
        return pixel::run(&args);
    }
    let out_path = args.output.clone().unwrap_or_else(|| default_output(&args.scene));
    let format = format_of(&out_path)?;
    if args.region.is_some() && format != Format::Png {
        return Err(CliError::usage(format!(
            "{}: --region writes PNG tiles (their place is kept in a PNG text chunk)",
            out_path.display()
        )));
    }
    // One pool for parsing (large files go in pieces), building and rendering.
    let threads = args.threads.map(|t| t as usize).unwrap_or_else(num_cpus);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| CliError::io(format!("cannot start {threads} threads: {e}")))?;
    let mut loaded = pool.install(|| load_scene_with(&args.scene, &args.limits.scene))?;
    print_warnings(&loaded, 20);
    let scene = &loaded.scene;
    let opts = render_options(&args, scene);
    let full = Region::full(opts.width, opts.height);
    let region = match &args.region {
        Some(s) => Region::parse_within(s, opts.width, opts.height).map_err(CliError::usage)?,
        None => full,
    };
    let sized_by_flags = args.width.is_some() || args.height.is_some() || args.region.is_some();
    (args.limits).check_pixels(region.width(), region.height(), opts.sampling, sized_by_flags)?;
    // Open the output (and the stats file) before the work, to fail fast.
    let output = Destination::create(&out_path)?;
    let mut stats_out = args.stats_json.as_deref().map(AtomicOutput::create).transpose()?;

    let t0 = Instant::now();
    let bvh = pool.install(|| build_bvh(&mut loaded.scene));
    let scene = &loaded.scene;
    let build_s = t0.elapsed().as_secs_f64();
    interrupt::check()?;
    let t1 = Instant::now();
    let progress = Progress::new(region_eye_rows(&opts, &region), args.quiet);
    let rendered = pool.install(|| render_region(scene, &bvh, &opts, &region, &progress));
    progress.finish();
    let (image, stats) =
        rendered.ok_or_else(|| interrupt::check().expect_err("cancelled only on a signal"))?;
    let render_s = t1.elapsed().as_secs_f64();

    let mut text = vec![(SOFTWARE_TEXT.0, SOFTWARE_TEXT.1.to_string())];
    if args.region.is_some() {
        text.push((
            tiles::REGION_KEY,
            tiles::region_text(&region, opts.width, opts.height),
        ));
        text.push((tiles::OPTIONS_KEY, tile_options(&opts)));
    }
    output.write_image(&image, format, &text)?;

    let report = StatsJson {
        rays: stats,
        total_rays: stats.total_rays(),
        width: opts.width,
        height: opts.height,
        max_depth: opts.max_depth,
        threads,
        primitives: bvh.primitive_count(),
        parse_s: loaded.parse_s,
        build_s,
        render_s,
        mrays_per_s: stats.total_rays() as f64 / render_s.max(1e-9) / 1e6,
    };
    if let Some(mut out) = stats_out.take() {
        let json = serde_json::to_string_pretty(&report).expect("plain data serializes");
        writeln!(out.writer(), "{json}").map_err(|e| CliError::io(format!("writing stats: {e}")))?;
        out.commit()?;
    }
    if args.stats {
        print_stats(&report);
    }
    if !args.quiet {
        let crop = if region == full {
            String::new()
        } else {
            format!(" (region {region})")
        };
        eprintln!(
            "rendered {} in {:.2} s: {} rays, {:.1} Mrays/s, {}x{}{crop}, {}, {} threads",
            display_name(&out_path),
            build_s + render_s,
            report.total_rays,
            report.mrays_per_s,
            opts.width,
            opts.height,
            opts.sampling,
            threads
        );
    }
    Ok(())
}

/// The settings that change a tile's pixels; `nffrt merge` refuses tiles that differ.
fn tile_options(opts: &RenderOptions) -> String {
    format!("sampling={} max-depth={}", opts.sampling, opts.max_depth)
}

fn print_stats(r: &StatsJson) {
    let s = &r.rays;
    outln!(
        "image            {} x {}, depth {}, {} threads",
        r.width,
        r.height,
        r.max_depth,
        r.threads
    );
    outln!("primitives       {}", r.primitives);
    outln!("eye rays         {} ({} hit)", s.eye_rays, s.eye_hits);
    outln!("reflection rays  {}", s.reflection_rays);
    outln!("refraction rays  {}", s.refraction_rays);
    outln!(
        "shadow rays      {} ({} blocked)",
        s.shadow_rays,
        s.shadow_blocked
    );
    outln!("total rays       {}", r.total_rays);
    outln!(
        "parse / build / render  {:.3} / {:.3} / {:.3} s",
        r.parse_s,
        r.build_s,
        r.render_s
    );
    outln!("speed            {:.2} Mrays/s", r.mrays_per_s);
}

fn num_cpus() -> usize {
    std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1)
}
