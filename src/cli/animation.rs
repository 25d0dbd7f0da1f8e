//! `nffrt render SCENE.aff --frames A..B -o out_%04d.png`: an animation's frames,
//! each rendered at its time and written whole to its own picture. The objects
//! under no keyframed transform (the fixed part) are flattened and built once;
//! each frame flattens and builds only the rest, under one root with the fixed
//! part (`prepare::prepare_frame`), unless `--rebuild-whole` asks for the whole
//! scene every frame. With `--motion-blur K`, each frame is the mean of K
//! sub-frames over its interval, each flattened, built and rendered so (an
//! accumulation buffer). The progress bar counts frames; the closing line splits
//! the time into the fixed part, the per-frame update (flatten and build) and
//! render (with the AOVs and the denoiser, when asked for, and the writing).

use std::time::Instant;

use super::finish::Finishing;
use super::frames::{flatten_part, FrameJob};
use super::image_out::{display_name, format_of, Destination};
use super::progress::Progress;
use super::render::{prepare_options, progress_mode, render_error, resolve, written_encoding, RenderArgs};
use super::{interrupt, CliError};
use nffrt::aff::FramePart;
use nffrt::image::{Accumulator, Region, SOFTWARE_TEXT};
use nffrt::load::Loaded;
use nffrt::prepare::{prepare_frame, prepare_with, FixedPart, RenderScene};
use nffrt::render::{region_eye_rows, render_region};
use nffrt::words::count;

/// Seconds spent on the frames: the fixed part (once), then per frame flattening,
/// building, rendering (and writing).
#[derive(Clone, Copy, Debug, Default)]
struct Seconds {
    fixed: f64,
    flatten: f64,
    build: f64,
    render: f64,
}

/// The times of the `k` sub-frames of the frame shown at `t` (see
/// [`nffrt::aff::AffScene::subframe_times`]); planned for animated AFF scenes only.
fn subframe_times(loaded: &Loaded, t: f64, k: u32) -> Vec<f64> {
    let aff = loaded
        .aff
        .as_deref()
        .expect("frames are planned for AFF scenes only");
    aff.subframe_times(t, k)
        .expect("--motion-blur is planned for animated scenes only")
}

/// Renders `jobs` (two frames or more, or frames blurred by `--motion-blur`) of
/// `loaded` as `args` say, on `pool`.
pub fn run(
    args: &RenderArgs,
    pool: &rayon::ThreadPool,
    loaded: &Loaded,
    jobs: &[FrameJob],
) -> Result<(), CliError> {
    let format = format_of(&jobs[0].output)?;
    // The settings of the first frame (its notes printed once); every frame has the
    // same size and sampling, whatever its camera.
    let (opts, encoding) = resolve(args, &loaded.scene.info())?;
    let encoding = written_encoding(format, encoding);
    let region = Region::full(opts.width, opts.height);
    let sized_by_flags = args.width.is_some() || args.height.is_some();
    args.limits.check(&opts, &region, sized_by_flags)?;
    // The denoiser is opened once; each frame's AOV files open with its picture.
    let finishing = Finishing::plan(args, &jobs[0].output, format, &opts, pool.current_num_threads())?;
    let rows = region_eye_rows(&opts, &region);
    let subframes = args.frames.motion_blur.unwrap_or(1);
    let progress = Progress::frames(rows * subframes as u64, jobs.len() as u64, progress_mode(args));
    let limits = args.limits.render_limits();
    let mut seconds = Seconds::default();
    let mut rays = 0;
    let start = Instant::now();
    let prepare = prepare_options(args);
    let mut fixed = match args.frames.rebuild_whole {
        true => None,
        false => {
            let scene = flatten_part(loaded, &jobs[0], FramePart::Fixed)?;
            Some(pool.install(|| FixedPart::new(scene, &prepare)))
        }
    };
    let part = match fixed {
        Some(_) => FramePart::Moving,
        None => FramePart::All,
    };
    seconds.fixed = start.elapsed().as_secs_f64();
    // The fixed part's arrays, then the last frame's tree, in which the next frame's
    // graft is made.
    let mut spare = fixed.as_mut().and_then(FixedPart::lend);
    for job in jobs {
        let output = Destination::create(&job.output)?;
        let finish = finishing.open(&job.output)?;
        // The frame's moments: its time, or the middles of its interval's parts.
        let times = match args.frames.motion_blur {
            Some(k) => subframe_times(loaded, job.time, k),
            None => vec![job.time],
        };
        let mut sum = Accumulator::new();
        let mut last = None;
        for time in times {
            // The last sub-frame's tree (its picture summed) is this one's spare.
            if let (Some(done), Some(_)) = (last.take(), &fixed) {
                spare = Some(RenderScene::into_bvh(done));
            }
            let t0 = Instant::now();
            let scene = flatten_part(loaded, &FrameJob { time, ..job.clone() }, part)?;
            let t1 = Instant::now();
            let scene = pool.install(|| match &fixed {
                Some(fixed) => prepare_frame(fixed, scene, spare.take(), &loaded.assets, &prepare),
                None => Some(prepare_with(scene, &loaded.assets, &prepare)),
            });
            let scene =
                scene.expect("each frame's tree, the first the lent arrays, is the next frame's spare");
            let t2 = Instant::now();
            interrupt::check()?;
            let rendered =
                pool.install(|| render_region(&scene, scene.view(), &opts, &region, &limits, &progress));
            let (image, stats) = rendered.map_err(|e| render_error(e, sized_by_flags))?;
            sum.add(image);
            rays += stats.total_rays();
            seconds.flatten += (t1 - t0).as_secs_f64();
            seconds.build += (t2 - t1).as_secs_f64();
            seconds.render += t2.elapsed().as_secs_f64();
            last = Some(scene);
        }
        let t3 = Instant::now();
        let (image, scene) = (sum.mean(), last);
        let (Some(image), Some(scene)) = (image, scene) else {
            unreachable!("a frame has one moment at least");
        };
        interrupt::check()?;
        // --denoise and --aov (never with --motion-blur): the frame's one scene.
        let finished = pool.install(|| finish.run(&scene, &opts, &limits, image, format, encoding))?;
        let text = [(SOFTWARE_TEXT.0, SOFTWARE_TEXT.1.to_string())];
        finished.write(output, format, encoding, &text)?;
        spare = fixed.is_some().then(|| scene.into_bvh());
        seconds.render += t3.elapsed().as_secs_f64();
    }
    progress.finish();
    if !args.quiet {
        let total = start.elapsed().as_secs_f64();
        let (first, last) = (&jobs[0], &jobs[jobs.len() - 1]);
        let pictures = match jobs {
            [one] => display_name(&one.output),
            _ => format!(
                "{} .. {}",
                display_name(&first.output),
                display_name(&last.output)
            ),
        };
        let blur = match args.frames.motion_blur {
            Some(k) => format!(
                ", each the mean of {}",
                count(k as usize, "sub-frame", "sub-frames")
            ),
            None => String::new(),
        };
        eprintln!(
            "rendered {}{blur} ({pictures}) in {total:.2} s, {:.2} frames/s: fixed part {:.2} s + flatten {:.2} s + build {:.2} s (update {:.1} %), render and write {:.2} s; {}, {}x{}, {}, {}",
            count(jobs.len(), "frame", "frames"),
            jobs.len() as f64 / total.max(1e-9),
            seconds.fixed,
            seconds.flatten,
            seconds.build,
            100.0 * (seconds.fixed + seconds.flatten + seconds.build) / total.max(1e-9),
            seconds.render,
            count(rays as usize, "ray", "rays"),
            opts.width,
            opts.height,
            opts.sampling,
            count(pool.current_num_threads(), "thread", "threads")
        );
    }
    Ok(())
}
