//! The render's progress bar (only on a terminal, never with `--quiet`) and its
//! cancellation check.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::interrupt;
use nffrt::render::Observer;

/// Shows progress on standard error and stops the render on Ctrl-C / SIGTERM.
pub struct Progress {
    bar: Option<ProgressBar>,
    rays: AtomicU64,
    start: Instant,
}

impl Progress {
    /// A progress bar over `rows` rows, shown only if standard error is a terminal
    /// and `quiet` is false.
    pub fn new(rows: u64, quiet: bool) -> Progress {
        let bar = (!quiet && std::io::stderr().is_terminal()).then(|| {
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
            rays: AtomicU64::new(0),
            start: Instant::now(),
        }
    }

    /// Removes the bar from the terminal.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

impl Observer for Progress {
    fn row_done(&self, rays: u64) {
        let total = self.rays.fetch_add(rays, Ordering::Relaxed) + rays;
        if let Some(bar) = &self.bar {
            let mrays = total as f64 / self.start.elapsed().as_secs_f64().max(1e-9) / 1e6;
            bar.set_message(format!("{mrays:.1} Mrays/s"));
            bar.inc(1);
        }
    }

    fn cancelled(&self) -> bool {
        interrupt::interrupted()
    }
}
