//! A session's renderer: a thread that takes the latest request and turns it into a
//! sequence of frames, coarse to converged.
//!
//! For each request (a *generation*): previews at strides 8, 4, 2 (fewer for small
//! pictures; [`first_stride`]), then the full picture sample by sample
//! ([`Accumulator`]: 1, 1, 2, 4, ... samples per pass), each pass streaming its
//! finished rows over the last picture at most every [`ROW_FRAME_INTERVAL`]. A newer
//! request cancels the work between two rows; only the latest request waits, so
//! the queue holds one job at most. Frames go out through a `watch` channel, which
//! keeps only the newest: a slow socket skips frames instead of queueing them.
//!
//! With the denoise switch on, each finished pass is also denoised (Open Image
//! Denoise's fast network, guided by AOVs traced once per generation) and that
//! picture is shown instead, while the noisy one keeps refining. With a reference
//! picture of the same size, each finished pass's picture as shown is measured
//! against it (FLIP), and the measure and its map go out through a second channel
//! that keeps them all (one per pass: a generation has at most 13).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

use axum::body::Bytes;
use tokio::sync::watch;

use super::protocol::{encode_binary, FlipHeader, FrameHeader};
use super::reference::Reference;
use super::scene::Loaded;
use super::turns::{Turn, Turns};
use nffrt::denoise::{Denoiser, Quality};
use nffrt::image::{Encoding, Image, Region};
use nffrt::math::Vec3;
use nffrt::options::RenderLimits;
use nffrt::options::RenderOptions;
use nffrt::prepare::{PrepareOptions, RenderScene};
use nffrt::render::{render_aovs, render_preview, Accumulator, Aovs, Observer};
use nffrt::scene::View;

/// The most pixels the first, coarsest preview has.
const FIRST_PREVIEW_PIXELS: u64 = 8192;
/// The least time between two frames streamed from one pass's rows.
const ROW_FRAME_INTERVAL: Duration = Duration::from_millis(100);
/// A generation number no request has: the session is over.
const CLOSED: u64 = u64::MAX;

/// One request: render `view` with `opts` on `loaded`.
pub struct Job {
    /// The generation.
    pub gen: u64,
    /// The scene.
    pub loaded: Arc<Loaded>,
    /// The frame of an AFF scene (checked by the session); `None`: the scene as
    /// loaded.
    pub frame: Option<u32>,
    /// Its render-time settings (prepared again when they are not the file's).
    pub prepare: PrepareOptions,
    /// The camera (the scene's own view with the request's position and angle).
    pub view: View,
    /// The settings.
    pub opts: RenderOptions,
    /// How the pictures' 8-bit values hold the linear ones (as `nffrt render`
    /// writes them).
    pub encoding: Encoding,
    /// The denoiser, when the page asks for denoised pictures of a render that has
    /// noise.
    pub denoiser: Option<Arc<Denoiser>>,
    /// The reference the passes are measured against, if any.
    pub reference: Option<Arc<Reference>>,
    /// When the request arrived.
    pub start: Instant,
}

/// A picture ready to send: its generation and the binary message.
pub struct Frame {
    /// The generation.
    pub gen: u64,
    /// The encoded message ([`encode_binary`]), shared without copying.
    pub bytes: Bytes,
}

/// The latest full-resolution picture (for "save PNG").
#[derive(Default)]
pub struct Shown {
    /// The picture, once a pass has finished.
    pub picture: Mutex<Option<ShownPicture>>,
}

/// A full-resolution picture shown.
#[derive(Clone)]
pub struct ShownPicture {
    /// Its generation.
    pub gen: u64,
    /// Its linear values (denoised, if shown so).
    pub image: Arc<Image>,
    /// True once it has every sample.
    pub complete: bool,
    /// How its 8-bit values hold the linear ones.
    pub encoding: Encoding,
}

/// Where a session's render thread sends its pictures.
pub struct Outlets {
    /// Frames: only the newest is kept.
    pub frames: watch::Sender<Option<Arc<Frame>>>,
    /// Error maps against the reference: every one is kept.
    pub maps: tokio::sync::mpsc::UnboundedSender<Arc<Frame>>,
    /// Renders that could not start, by generation and why (a frame that cannot
    /// be flattened): each is answered with an error.
    pub failed: tokio::sync::mpsc::UnboundedSender<(u64, String)>,
}

/// A session's render thread.
pub struct Worker {
    slot: Arc<(Mutex<Option<Job>>, Condvar)>,
    latest: Arc<AtomicU64>,
    /// The server's queue of renders, which this thread's renders wait in.
    turns: Arc<Turns>,
    /// Its latest picture.
    pub shown: Arc<Shown>,
}

impl Worker {
    /// Starts the thread, whose renders take their turns in `turns`; pictures go
    /// to `out`.
    pub fn spawn(out: Outlets, turns: Arc<Turns>) -> std::io::Result<Worker> {
        let slot = Arc::new((Mutex::new(None::<Job>), Condvar::new()));
        let latest = Arc::new(AtomicU64::new(0));
        let shown = Arc::new(Shown::default());
        let (s, l, sh, t) = (slot.clone(), latest.clone(), shown.clone(), turns.clone());
        std::thread::Builder::new()
            .name("nffrt-view-render".into())
            .spawn(move || {
                while let Some(job) = next_job(&s, &l) {
                    run(&job, &l, &t, &out, &sh);
                }
            })?;
        Ok(Worker {
            slot,
            latest,
            turns,
            shown,
        })
    }

    /// Replaces any waiting request with `job` and cancels the running one (also
    /// while it waits for its turn).
    pub fn submit(&self, job: Job) {
        self.latest.store(job.gen, Ordering::SeqCst);
        let (lock, ready) = &*self.slot;
        if let Ok(mut slot) = lock.lock() {
            *slot = Some(job);
        }
        ready.notify_one();
        self.turns.wake();
    }
}

impl Drop for Worker {
    /// Cancels the work and ends the thread.
    fn drop(&mut self) {
        self.latest.store(CLOSED, Ordering::SeqCst);
        let (lock, ready) = &*self.slot;
        if let Ok(mut slot) = lock.lock() {
            *slot = None;
        }
        ready.notify_one();
        self.turns.wake();
    }
}

/// Waits for a job; `None` once the session is closed.
fn next_job(slot: &(Mutex<Option<Job>>, Condvar), latest: &AtomicU64) -> Option<Job> {
    let (lock, ready) = slot;
    let mut guard = lock.lock().ok()?;
    loop {
        if latest.load(Ordering::SeqCst) == CLOSED {
            return None;
        }
        if let Some(job) = guard.take() {
            return Some(job);
        }
        guard = ready.wait(guard).ok()?;
    }
}

/// The coarsest preview's stride: a power of two that keeps it within
/// [`FIRST_PREVIEW_PIXELS`] (1: the picture is small enough to start at full size).
pub fn first_stride(width: u32, height: u32) -> u32 {
    let mut stride = 1u32;
    while (width as u64 * height as u64) / (stride as u64 * stride as u64) > FIRST_PREVIEW_PIXELS {
        stride *= 2;
    }
    stride
}

/// Watches one generation: cancelled once a newer one is asked for; counts rays;
/// streams finished rows of a pass into `display` and out as frames.
struct Watch<'a> {
    job: &'a Job,
    latest: &'a AtomicU64,
    turns: &'a Turns,
    rays: &'a AtomicU64,
    frames: &'a watch::Sender<Option<Arc<Frame>>>,
    /// The picture being shown (8-bit RGB, full size) and when it last went out.
    display: Option<&'a Mutex<(Vec<u8>, Instant)>>,
    samples: u32,
}

impl Observer for Watch<'_> {
    fn row_done(&self, rays: u64) {
        self.rays.fetch_add(rays, Ordering::Relaxed);
    }

    fn row_pixels(&self, y: u32, pixels: &[Vec3]) {
        let Some(display) = self.display else { return };
        let Ok(mut d) = display.lock() else { return };
        let w = self.job.opts.width as usize;
        let row = &mut d.0[3 * w * y as usize..3 * w * (y as usize + 1)];
        let byte = self.job.encoding.quantizer();
        for (out, p) in row.chunks_exact_mut(3).zip(pixels) {
            out.copy_from_slice(&[byte(p.x), byte(p.y), byte(p.z)]);
        }
        if d.1.elapsed() >= ROW_FRAME_INTERVAL && !self.cancelled() {
            d.1 = Instant::now();
            let frame = frame(self.job, self.rays, (1, self.samples), [false, false], &d.0);
            self.frames.send_replace(Some(frame));
        }
    }

    fn cancelled(&self) -> bool {
        self.latest.load(Ordering::Relaxed) != self.job.gen
    }
}

impl Watch<'_> {
    /// Waits for a turn to render (for the generation's first frame if `first`);
    /// `None` once a newer request cancels this one.
    fn turn(&self, first: bool) -> Option<Turn<'_>> {
        self.turns.take(first, || self.cancelled())
    }
}

/// A frame of `job` whose payload is `rgb` (one pixel per `stride` block) of
/// `samples` per pixel; `[complete, denoised]`.
fn frame(
    job: &Job,
    rays: &AtomicU64,
    (stride, samples): (u32, u32),
    flags: [bool; 2],
    rgb: &[u8],
) -> Arc<Frame> {
    let [complete, denoised] = flags;
    let header = FrameHeader {
        kind: "frame",
        gen: job.gen,
        width: job.opts.width,
        height: job.opts.height,
        stride,
        samples,
        target: job.opts.sampling.samples_per_pixel(),
        rays: rays.load(Ordering::Relaxed),
        ms: job.start.elapsed().as_secs_f64() * 1e3,
        complete,
        denoised,
    };
    Arc::new(Frame {
        gen: job.gen,
        bytes: encode_binary(&header, rgb).into(),
    })
}

/// Renders one generation until it converges or a newer one cancels it, each
/// render in its turn.
fn run(job: &Job, latest: &AtomicU64, turns: &Turns, out: &Outlets, shown: &Shown) {
    // The frame was checked; a frame that cannot be flattened (a transform that
    // overflows at that time, say) renders nothing, as `nffrt render --frame` fails,
    // and the page is told why.
    let prepared = match job.loaded.prepared_frame(job.frame, &job.prepare) {
        Ok(scene) => scene,
        Err(e) => {
            // A page that has gone has no one to tell.
            let _ = out.failed.send((job.gen, e));
            return;
        }
    };
    let scene = &*prepared;
    let opts = &job.opts;
    let frames = &out.frames;
    let rays = AtomicU64::new(0);
    let mut watch = Watch {
        job,
        latest,
        turns,
        rays: &rays,
        frames,
        display: None,
        samples: 0,
    };
    let (w, h) = (opts.width as usize, opts.height as usize);
    let mut display = vec![0u8; 3 * w * h];
    let mut stride = first_stride(opts.width, opts.height);
    // The generation's first render is its first frame.
    let mut first = true;
    while stride > 1 {
        let Some(turn) = watch.turn(std::mem::take(&mut first)) else {
            return;
        };
        // Refused options never get here (the session checks them first): only a
        // newer request cancels.
        let Ok((image, _)) = render_preview(scene, &job.view, opts, stride, &watch) else {
            return;
        };
        drop(turn);
        let rgb = image.to_rgb8_as(job.encoding);
        frames.send_replace(Some(frame(job, &rays, (stride, 0), [false, false], &rgb)));
        upscale(&rgb, image.width as usize, stride as usize, w, &mut display);
        stride /= 2;
    }
    let Ok(mut acc) = Accumulator::new(&job.view, opts, &RenderLimits::default()) else {
        return;
    };
    let display = Mutex::new((display, Instant::now()));
    let mut aovs = None;
    while !acc.is_complete() {
        // A denoised picture is shown whole, once its pass is done: no noisy rows.
        watch.display = job.denoiser.is_none().then_some(&display);
        watch.samples = acc.samples_done();
        let count = acc.samples_done().max(1);
        let Some(turn) = watch.turn(std::mem::take(&mut first)) else {
            return;
        };
        if acc.pass(scene, count, &watch).is_err() {
            return;
        }
        drop(turn);
        let mut image = Arc::new(acc.image());
        let mut denoised = false;
        if let Some(denoiser) = &job.denoiser {
            let Some(turn) = watch.turn(false) else {
                return;
            };
            let clean = denoise(denoiser, scene, job, &image, &mut aovs, &watch);
            drop(turn);
            match clean {
                Some(clean) => (image, denoised) = (Arc::new(clean), true),
                None if watch.cancelled() => return,
                None => {}
            }
        }
        let rgb = image.to_rgb8_as(job.encoding);
        let samples = acc.samples_done();
        if let Ok(mut s) = shown.picture.lock() {
            *s = Some(ShownPicture {
                gen: job.gen,
                image: image.clone(),
                complete: acc.is_complete(),
                encoding: job.encoding,
            });
        }
        if watch.cancelled() {
            return;
        }
        frames.send_replace(Some(frame(
            job,
            &rays,
            (1, samples),
            [acc.is_complete(), denoised],
            &rgb,
        )));
        if let Some(reference) = &job.reference {
            if let Some((mean, map)) = reference.measure(&image, &rgb) {
                let header = FlipHeader {
                    kind: "flip",
                    gen: job.gen,
                    width: opts.width,
                    height: opts.height,
                    samples,
                    mean,
                    denoised,
                };
                let bytes = encode_binary(&header, &map).into();
                let _ = out.maps.send(Arc::new(Frame { gen: job.gen, bytes }));
            }
        }
        if let Ok(mut d) = display.lock() {
            d.0 = rgb;
            d.1 = Instant::now();
        }
    }
}

/// `image` of `job` denoised at the fast quality, its guides traced on first use
/// into `aovs`; `None` if cancelled or the denoiser failed.
fn denoise(
    denoiser: &Denoiser,
    scene: &RenderScene,
    job: &Job,
    image: &Image,
    aovs: &mut Option<Aovs>,
    watch: &Watch<'_>,
) -> Option<Image> {
    if aovs.is_none() {
        let full = Region::full(job.opts.width, job.opts.height);
        *aovs = render_aovs(
            scene,
            &job.view,
            &job.opts,
            &full,
            &RenderLimits::default(),
            watch,
        )
        .ok();
    }
    let guides = aovs.as_ref()?;
    denoiser
        .denoise_render(image, guides, &job.opts, Quality::Fast)
        .ok()
}

/// Spreads a preview (`cols` pixels a row, each for a `stride` block) over the
/// full-size `display` (`width` pixels a row), block by block.
fn upscale(rgb: &[u8], cols: usize, stride: usize, width: usize, display: &mut [u8]) {
    for (y, row) in display.chunks_exact_mut(3 * width).enumerate() {
        let src = &rgb[3 * cols * (y / stride)..];
        for (x, px) in row.chunks_exact_mut(3).enumerate() {
            px.copy_from_slice(&src[3 * (x / stride)..3 * (x / stride) + 3]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_preview_stays_small() {
        assert_eq!(first_stride(12, 9), 1);
        assert_eq!(first_stride(90, 90), 1);
        assert_eq!(first_stride(512, 512), 8);
        assert_eq!(first_stride(800, 600), 8);
        assert_eq!(first_stride(1920, 1080), 16);
        assert_eq!(first_stride(4096, 4096), 64);
    }

    #[test]
    fn previews_spread_over_their_blocks() {
        // A 2x2 preview of a 3x3 picture at stride 2.
        let rgb = [1, 1, 1, 2, 2, 2, 3, 3, 3, 4, 4, 4];
        let mut display = vec![0u8; 27];
        upscale(&rgb, 2, 2, 3, &mut display);
        let firsts: Vec<u8> = display.chunks(3).map(|p| p[0]).collect();
        assert_eq!(firsts, [1, 1, 2, 1, 1, 2, 3, 3, 4]);
    }
}
