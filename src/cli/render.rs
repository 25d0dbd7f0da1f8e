//! `nffrt render`: trace a scene into an image file.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use serde::Serialize;

use super::limits::RenderLimitArgs;
use super::load::{build_bvh, load_scene_with, print_warnings};
use super::output::AtomicOutput;
use super::progress::Progress;
use super::{interrupt, CliError};
use nffrt::image::{encode_png, Image};
use nffrt::render::{eye_rows, render_observed, RenderOptions, Sampling, Stats, DEFAULT_MAX_DEPTH};

/// The deepest ray tree allowed (keeps the recursion far from the stack limit).
pub const MAX_DEPTH_CAP: u32 = 64;

/// Arguments of `nffrt render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Scene file (NFF); `-` reads standard input.
    pub scene: PathBuf,
    /// Output image: .png (8-bit), .ppm (binary P6) or .pfm (linear float).
    /// Default: the scene's file stem + .png in the current directory.
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
    /// Worker threads (default: one per core).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// SPD benchmark protocol: rays through the (w+1) x (h+1) pixel corners, the four
    /// corners averaged into each pixel.
    #[arg(long)]
    pub spd: bool,
    /// Print a summary of ray counts and timings.
    #[arg(long)]
    pub stats: bool,
    /// Write ray counts and timings as JSON to this file.
    #[arg(long, value_name = "FILE")]
    pub stats_json: Option<PathBuf>,
    /// No progress bar and no closing summary line.
    #[arg(short, long)]
    pub quiet: bool,
    /// Resource limits (see "Limits" in the README).
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

#[derive(Clone, Copy, PartialEq)]
enum Format {
    Png,
    Ppm,
    Pfm,
}

fn format_of(path: &Path) -> Result<Format, CliError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("png") => Ok(Format::Png),
        Some("ppm") => Ok(Format::Ppm),
        Some("pfm") => Ok(Format::Pfm),
        _ => Err(CliError::usage(format!(
            "{}: unknown image format (use .png, .ppm or .pfm)",
            path.display()
        ))),
    }
}

fn default_output(scene: &Path) -> PathBuf {
    let stem = scene.file_stem().filter(|_| scene != Path::new("-"));
    let stem = stem
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "stdin".into());
    PathBuf::from(format!("{stem}.png"))
}

/// Runs `nffrt render`.
pub fn run(args: RenderArgs) -> Result<(), CliError> {
    let out_path = args.output.clone().unwrap_or_else(|| default_output(&args.scene));
    let format = format_of(&out_path)?;
    let mut loaded = load_scene_with(&args.scene, &args.limits.scene)?;
    print_warnings(&loaded, 20);
    // Open the output (and the stats file) before the work, to fail fast.
    let mut output = AtomicOutput::create(&out_path)?;
    let mut stats_out = args.stats_json.as_deref().map(AtomicOutput::create).transpose()?;

    let scene = &loaded.scene;
    let opts = RenderOptions {
        width: args.width.unwrap_or(scene.view.width),
        height: args.height.unwrap_or(scene.view.height),
        max_depth: args.max_depth,
        sampling: if args.spd {
            Sampling::SpdCorners
        } else {
            Sampling::PixelCenters
        },
    };
    args.limits
        .check_pixels(&opts, args.width.is_some() || args.height.is_some())?;
    let threads = args.threads.map(|t| t as usize).unwrap_or_else(num_cpus);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| CliError::io(format!("cannot start {threads} threads: {e}")))?;

    let t0 = Instant::now();
    let bvh = pool.install(|| build_bvh(&mut loaded.scene));
    let scene = &loaded.scene;
    let build_s = t0.elapsed().as_secs_f64();
    interrupt::check()?;
    let t1 = Instant::now();
    let progress = Progress::new(eye_rows(&opts), args.quiet);
    let rendered = pool.install(|| render_observed(scene, &bvh, &opts, &progress));
    progress.finish();
    let (image, stats) =
        rendered.ok_or_else(|| interrupt::check().expect_err("cancelled only on a signal"))?;
    let render_s = t1.elapsed().as_secs_f64();

    write_image(&image, format, output.writer())
        .map_err(|e| CliError::io(format!("{}: cannot write output: {e}", out_path.display())))?;
    output.commit()?;

    let report = StatsJson {
        rays: stats,
        total_rays: stats.total_rays(),
        width: opts.width,
        height: opts.height,
        max_depth: opts.max_depth,
        threads,
        primitives: bvh.primitives().len(),
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
        eprintln!(
            "rendered {} in {:.2} s: {} rays, {:.1} Mrays/s, {}x{}, {} threads",
            out_path.display(),
            build_s + render_s,
            report.total_rays,
            report.mrays_per_s,
            opts.width,
            opts.height,
            threads
        );
    }
    Ok(())
}

fn print_stats(r: &StatsJson) {
    let s = &r.rays;
    println!(
        "image            {} x {}, depth {}, {} threads",
        r.width, r.height, r.max_depth, r.threads
    );
    println!("primitives       {}", r.primitives);
    println!("eye rays         {} ({} hit)", s.eye_rays, s.eye_hits);
    println!("reflection rays  {}", s.reflection_rays);
    println!("refraction rays  {}", s.refraction_rays);
    println!(
        "shadow rays      {} ({} blocked)",
        s.shadow_rays, s.shadow_blocked
    );
    println!("total rays       {}", r.total_rays);
    println!(
        "parse / build / render  {:.3} / {:.3} / {:.3} s",
        r.parse_s, r.build_s, r.render_s
    );
    println!("speed            {:.2} Mrays/s", r.mrays_per_s);
}

fn num_cpus() -> usize {
    std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1)
}

fn write_image(image: &Image, format: Format, w: &mut impl Write) -> Result<(), String> {
    match format {
        Format::Png => encode_png(image, &[("Software", "nffrt".into())], w).map_err(|e| e.to_string()),
        Format::Ppm => {
            write!(w, "P6\n{} {}\n255\n", image.width, image.height).map_err(|e| e.to_string())?;
            w.write_all(&image.to_rgb8()).map_err(|e| e.to_string())
        }
        Format::Pfm => {
            // Portable float map: little-endian (scale -1), rows bottom to top.
            write!(w, "PF\n{} {}\n-1.0\n", image.width, image.height).map_err(|e| e.to_string())?;
            let mut bytes = Vec::with_capacity(image.pixels.len() * 12);
            for row in image.pixels.chunks(image.width as usize).rev() {
                for p in row {
                    for c in [p.x, p.y, p.z] {
                        bytes.extend_from_slice(&c.to_le_bytes());
                    }
                }
            }
            w.write_all(&bytes).map_err(|e| e.to_string())
        }
    }
}
