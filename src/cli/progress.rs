//! The render's progress: a bar on a terminal, plain lines for logs with
//! `--progress`, nothing with `--quiet`; and the render's cancellation check.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::interrupt;
use nffrt::render::{Observer, StageStats};
use nffrt::words::count;

/// How progress is shown on standard error.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProgressMode {
    /// Not at all (`--quiet`).
    Off,
    /// A bar, only when standard error is a terminal.
    Terminal,
    /// A line per tenth of the rows (per frame of an animation), wherever standard
    /// error goes (`--progress`).
    Lines,
}

/// Shows progress on standard error and stops the render on Ctrl-C / SIGTERM.
pub struct Progress {
    bar: Option<ProgressBar>,
    lines: bool,
    rows: u64,
    /// The frames the rows are cut into (1 for a still picture).
    frames: u64,
    rows_done: AtomicU64,
    /// The last tenth (of an animation, the last frame) reported as a line (a lock,
    /// so lines come out in order).
    tenths_shown: Mutex<u64>,
    rays: AtomicU64,
    start: Instant,
    /// What the path tracer's stages did, summed over the rows.
    stages: Mutex<StageStats>,
}

impl Progress {
    /// Progress over `rows` rows, shown as `mode` says.
    pub fn new(rows: u64, mode: ProgressMode) -> Progress {
        Progress::frames(rows, 1, mode)
    }

    /// Progress over `frames` frames of `rows` rows each, counted in frames.
    pub fn frames(rows: u64, frames: u64, mode: ProgressMode) -> Progress {
        let (rows, frames) = (rows * frames.max(1), frames.max(1));
        let on_terminal = mode == ProgressMode::Terminal && std::io::stderr().is_terminal();
        let bar = on_terminal.then(|| {
            let bar = ProgressBar::with_draw_target(Some(rows), ProgressDrawTarget::stderr_with_hz(10));
            bar.set_style(
                ProgressStyle::with_template(
                    "{spinner} [{elapsed_precise}] [{bar:40}] {percent:>3}%  ETA {eta}  {msg}",
                )
                .expect("valid template")
                .progress_chars("=> "),
            );
            bar
        });
        Progress {
            bar,
            lines: mode == ProgressMode::Lines,
            rows,
            frames,
            rows_done: AtomicU64::new(0),
            tenths_shown: Mutex::new(0),
            rays: AtomicU64::new(0),
            start: Instant::now(),
            stages: Mutex::new(StageStats::default()),
        }
    }

    /// What the path tracer's wavefront stages did over the rows done.
    pub fn stages(&self) -> StageStats {
        self.stages.lock().map(|s| *s).unwrap_or_default()
    }

    /// Removes the bar from the terminal.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }

    fn mrays_per_s(&self, rays: u64) -> f64 {
        rays as f64 / self.start.elapsed().as_secs_f64().max(1e-9) / 1e6
    }

    /// The frames completed after `rows_done` rows.
    fn frames_done(&self, rows_done: u64) -> u64 {
        rows_done * self.frames / self.rows.max(1)
    }

    /// Prints a line for each tenth of the rows (each frame of an animation)
    /// completed since the last one printed.
    fn report_line(&self, rows_done: u64, rays: u64) {
        if self.frames > 1 {
            return self.report_frame_line(rows_done, rays);
        }
        let tenths = rows_done * 10 / self.rows.max(1);
        let Ok(mut shown) = self.tenths_shown.lock() else {
            return;
        };
        if tenths > *shown {
            *shown = tenths;
            eprintln!(
                "progress: {}% ({rows_done} of {}), {:.1} Mrays/s",
                tenths * 10,
                count(self.rows, "row", "rows"),
                self.mrays_per_s(rays)
            );
        }
    }
}

impl Progress {
    /// Prints a line for each frame completed since the last one printed.
    fn report_frame_line(&self, rows_done: u64, rays: u64) {
        let done = self.frames_done(rows_done);
        let Ok(mut shown) = self.tenths_shown.lock() else {
            return;
        };
        if done > *shown {
            *shown = done;
            eprintln!(
                "progress: {done} of {} done, {:.1} Mrays/s",
                count(self.frames, "frame", "frames"),
                self.mrays_per_s(rays)
            );
        }
    }
}

impl Observer for Progress {
    fn row_stages(&self, stages: &StageStats) {
        if let Ok(mut sum) = self.stages.lock() {
            *sum += *stages;
        }
    }

    fn row_done(&self, rays: u64) {
        let total = self.rays.fetch_add(rays, Ordering::Relaxed) + rays;
        let rows_done = self.rows_done.fetch_add(1, Ordering::Relaxed) + 1;
        if let Some(bar) = &self.bar {
            let rate = format!("{:.1} Mrays/s", self.mrays_per_s(total));
            match self.frames {
                1 => bar.set_message(rate),
                n => bar.set_message(format!(
                    "frame {} of {n}, {rate}",
                    (self.frames_done(rows_done) + 1).min(n)
                )),
            }
            bar.inc(1);
        }
        if self.lines {
            self.report_line(rows_done, total);
        }
    }

    fn cancelled(&self) -> bool {
        interrupt::interrupted()
    }
}
