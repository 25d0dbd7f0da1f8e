//! `nffrt convert`: writes a scene as NFF — an AFF scene's frame flattened into
//! plain triangles, spheres and cones in world space (what another renderer or a
//! BVH builder such as Embree's can read), a P3F scene without what NFF cannot say.
//! To standard output or, through a temporary file renamed when complete, to a file
//! that is none of the scene's own.

use std::path::{Path, PathBuf};

use clap::Args;
use nffrt::nff::write_nff;
use nffrt::Scene;

use super::gen::{refuse_image_name, write_file};
use super::image_out::is_stdout;
use super::limits::SceneLimitArgs;
use super::load::{load_scene, print_warnings, Need};
use super::output::{refuse_overwriting, write_stdout, Named};
use super::{frames, CliError};

/// Arguments of `nffrt convert`.
#[derive(Args, Debug)]
#[command(
    after_help = "NFF has no textures, ambient light, meshes or time: an AFF frame's textured triangles are written untextured (said on standard error), meshes as triangles, each object where it stands at the frame's time.\nExamples:\n  nffrt convert kitchen.aff --frame 400 -o kitchen400.nff\n  nffrt convert scene.p3f > scene.nff"
)]
pub struct ConvertArgs {
    /// Scene file (NFF, P3F or AFF; `-` for standard input).
    #[arg(value_name = "SCENE")]
    pub scene: PathBuf,
    /// Write to FILE instead of standard output (`-` is standard output).
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// The frame of an AFF scene to write (default 0).
    #[arg(long, value_name = "N", conflicts_with = "time",
          value_parser = super::values::whole_number::<u32>(0, u32::MAX as u64))]
    pub frame: Option<u32>,
    /// The time of an AFF scene to write.
    #[arg(long, value_name = "T", allow_negative_numbers = true, value_parser = frames::finite_time)]
    pub time: Option<f64>,
    /// Resource limits.
    #[command(flatten)]
    pub limits: SceneLimitArgs,
}

/// Runs `nffrt convert`.
pub fn run(args: ConvertArgs) -> Result<(), CliError> {
    let output = args.output.as_deref().filter(|p| !is_stdout(p));
    if let Some(path) = output {
        refuse_image_name(path, "convert")?;
    }
    let loaded = load_scene(&args.scene, &args.limits, Need::Summary)?;
    print_warnings(&loaded, 20);
    let flattened;
    let scene = match loaded.aff.as_deref() {
        None if args.frame.is_some() || args.time.is_some() => {
            return Err(CliError::usage(format!(
                "{}: {} is not an AFF scene (it reads as {}) and does not move; --frame and --time are for AFF scenes",
                if args.frame.is_some() { "--frame" } else { "--time" },
                loaded.name,
                loaded.scene.dialect.name()
            )))
        }
        None => {
            refuse_own_input(output, &[(&args.scene, "the scene file")])?;
            &loaded.scene
        }
        Some(aff) => {
            refuse_own_input(output, &frames::aff_inputs(aff, &args.scene))?;
            flattened = frame_of(aff, &args, &loaded.name)?;
            &flattened
        }
    };
    say_what_nff_drops(scene);
    match output {
        None => write_stdout(|mut w| write_nff(scene, &mut w)),
        Some(path) => write_file(scene, path),
    }
}

/// The frame (or time) `args` ask of `aff`, flattened.
fn frame_of(aff: &nffrt::aff::AffScene, args: &ConvertArgs, name: &str) -> Result<Scene, CliError> {
    let frames = aff.frames();
    let time = match (args.frame, args.time) {
        (Some(n), _) if n >= frames => {
            return Err(CliError::usage(format!(
                "--frame {n}: {name} has {} (0 to {})",
                nffrt::words::count(frames as usize, "frame", "frames"),
                frames - 1
            )))
        }
        (Some(n), _) => aff.time_of_frame(n),
        (None, Some(t)) => t,
        (None, None) => aff.time_of_frame(0),
    };
    aff.flatten(time)
        .map_err(|e| CliError::scene(format!("{name} at time {time}: {e}")))
}

/// Refuses an output that is one of `inputs`.
fn refuse_own_input(output: Option<&Path>, inputs: &[(&Path, &str)]) -> Result<(), CliError> {
    let Some(path) = output else { return Ok(()) };
    let named = Named {
        path,
        named: format!("-o {}", path.display()),
    };
    refuse_overwriting(&[named], inputs)
}

/// Says on standard error what of `scene` the NFF text leaves out: textures and
/// ambient light (an AFF frame's), so that nobody mistakes the file for the whole
/// scene.
fn say_what_nff_drops(scene: &Scene) {
    let mut dropped = Vec::new();
    if !scene.textures.is_empty() {
        let n = scene.textures.len();
        dropped.push(format!("its {}", nffrt::words::count(n, "texture", "textures")));
    }
    if scene.ambient_light.is_some() {
        dropped.push("its ambient light".to_string());
    }
    if !dropped.is_empty() {
        eprintln!(
            "nffrt: note: NFF has no textures or ambient light: {} left out, the geometry written whole",
            dropped.join(" and ")
        );
    }
}
