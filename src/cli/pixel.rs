//! `nffrt render --pixel X,Y`: trace one pixel with the render's settings and print
//! its ray tree (every hit's primitive and source line, distance, normal, material,
//! each light's contribution or shadow, the secondary rays and their weights).

use std::io::Write;

use super::frames;
use super::load::{load_scene, print_warnings, Need};
use super::render::{prepare_options, render_error, resolve, RenderArgs};
use super::CliError;
use nffrt::prepare::prepare_with;
use nffrt::render::debug::trace_pixel;

/// Runs `nffrt render SCENE --pixel X,Y [--width/--height/--max-depth/--spp/--spd]`
/// on pixel `(x, y)`.
pub fn run(args: &RenderArgs, (x, y): (u32, u32)) -> Result<(), CliError> {
    let mut loaded = load_scene(&args.scene, &args.limits.scene, Need::Render)?;
    print_warnings(&loaded, 20);
    // `--frame` or `--time` (`--frames` asks for pictures, not a pixel).
    if let Some(jobs) = frames::plan(&args.frames, &loaded, &args.scene, None, &[])? {
        loaded.scene = frames::flatten(&loaded, &jobs[0])?;
    }
    let (opts, _) = resolve(args, &loaded.scene.info())?;
    if x >= opts.width || y >= opts.height {
        return Err(CliError::usage(format!(
            "--pixel {x},{y} is outside the {}x{} image (columns 0..{}, rows 0..{})",
            opts.width,
            opts.height,
            opts.width - 1,
            opts.height - 1
        )));
    }
    let scene = prepare_with(loaded.scene, &loaded.assets, &prepare_options(args));
    let trace = trace_pixel(&scene, scene.view(), &opts, x, y).map_err(|e| render_error(e, true))?;
    let mut out = std::io::stdout().lock();
    match write!(out, "{trace}").and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(CliError::io(format!("writing standard output: {e}")))
        }
        _ => Ok(()),
    }
}
