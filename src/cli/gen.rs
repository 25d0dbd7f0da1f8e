//! `nffrt gen`: writes one of the SPD's classic scenes as NFF, to standard output
//! or, through a temporary file renamed when complete, to a file.

use std::path::{Path, PathBuf};

use clap::Args;
use nffrt::gen::{generate, SpdScene};
use nffrt::image::ImageFormat;
use nffrt::limits::DEFAULT_MAX_PRIMITIVES;
use nffrt::nff::write_nff;
use nffrt::Scene;

use super::output::{cannot_write, write_stdout, AtomicOutput};
use super::CliError;

/// Arguments of `nffrt gen`.
#[derive(Args, Debug)]
#[command(after_help = size_table())]
pub struct GenArgs {
    /// Scene to make: balls, gears, mount, rings, teapot, tetra or tree.
    #[arg(value_name = "NAME", value_parser = parse_scene)]
    pub name: SpdScene,
    /// Size factor with the SPD's meaning, from 1 to the largest size listed below;
    /// default: the SPD's default.
    #[arg(short, long, value_name = "N", allow_negative_numbers = true, value_parser = parse_size)]
    pub size: Option<u32>,
    /// Write to FILE instead of standard output (`-` is standard output).
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
}

fn parse_scene(s: &str) -> Result<SpdScene, String> {
    SpdScene::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = SpdScene::ALL.iter().map(|s| s.name()).collect();
        format!("no SPD scene called '{s}' (try {})", names.join(", "))
    })
}

/// Any whole number: whether it suits the scene is checked with the scene known.
fn parse_size(s: &str) -> Result<u32, String> {
    s.trim()
        .parse()
        .map_err(|_| "must be a whole number from 1 to the scene's largest size".into())
}

/// The table of sizes shown after `nffrt gen --help`.
fn size_table() -> String {
    let mut t = String::from("Sizes (as in the SPD; the limit keeps every scene within ");
    t.push_str(&format!("{DEFAULT_MAX_PRIMITIVES} primitives):\n"));
    for s in SpdScene::ALL {
        t.push_str(&format!(
            "  {:<7} {:<42} default {:>2}, at most {:>3}\n",
            s.name(),
            s.size_meaning(),
            s.default_size(),
            s.max_size()
        ));
    }
    t.push_str("Examples:\n  nffrt gen balls | nffrt render - -o balls.png\n  nffrt gen mount --size 9 -o mount9.nff");
    t
}

/// Runs `nffrt gen`.
pub fn run(args: GenArgs) -> Result<(), CliError> {
    if let Some(path) = &args.output {
        refuse_image_name(path, "gen")?;
    }
    let size = args.size.unwrap_or(args.name.default_size());
    let scene = generate(args.name, size)
        .map_err(|e| CliError::usage(format!("invalid value '{size}' for '--size <N>': {e}")))?;
    match args.output.as_deref() {
        None => write_stdout(|mut w| write_nff(&scene, &mut w)),
        Some(p) if p == Path::new("-") => write_stdout(|mut w| write_nff(&scene, &mut w)),
        Some(p) => write_file(&scene, p),
    }
}

/// Refuses an output named like an image: `command` (`gen`, `convert`) writes scene
/// text, and a picture of that name is more likely than a scene to be what the user
/// meant to keep.
pub fn refuse_image_name(path: &Path, command: &str) -> Result<(), CliError> {
    match ImageFormat::from_extension(path) {
        Some(_) => Err(CliError::usage(format!(
            "-o {}: {command} writes NFF scene text, not an image; name the output .nff",
            path.display()
        ))),
        None => Ok(()),
    }
}

/// Writes beside `dest` and renames into place, so `dest` is never half-written.
pub fn write_file(scene: &Scene, dest: &Path) -> Result<(), CliError> {
    let mut out = AtomicOutput::create(dest)?;
    write_nff(scene, out.writer()).map_err(|e| cannot_write(dest.display(), &e))?;
    out.commit()
}
