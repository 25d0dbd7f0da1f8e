//! The scene being viewed: loaded and built once, then again each time its file
//! changes (live reload), as mdBook's `serve` watches its sources.
//!
//! A watcher on the file's folder (editors often save by writing a new file and
//! renaming it over the old one) wakes a loader thread; events closer together than
//! [`SETTLE`] make one reload, and an event that arrives while a reload is parsing
//! cancels it. A good scene replaces the current one and is broadcast to every
//! session; a bad one is broadcast as an error, and the current scene stays.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc, Mutex, RwLock};
use std::time::{Duration, Instant};

use notify::{EventKind, RecursiveMode, Watcher};
use tokio::sync::broadcast;

use super::protocol::{AnimationMsg, CameraMsg, Counts};
use crate::cli::limits::SceneLimitArgs;
use crate::cli::load::{decoded_assets, load_scene_cancellable, Need};
use crate::cli::CliError;
use nffrt::aff::{AffError, AffScene, FramePart, MeshMode};
use nffrt::load::Assets;
use nffrt::prepare::{prepare, prepare_frame, prepare_with, FixedPart, PrepareOptions, RenderScene};
use nffrt::scene::Scene;

/// The most frames whose cameras the scene message lists; a longer animation's
/// page keeps the camera it has (the message would pass a megabyte).
pub const MAX_ANIMATION_CAMERAS: u32 = 8192;

/// How long the file must stay quiet before it is read.
pub const SETTLE: Duration = Duration::from_millis(60);

/// A loaded, built scene.
pub struct Loaded {
    /// The scene ready to render, prepared as the file says.
    pub scene: Arc<RenderScene>,
    /// The scene as parsed and its assets, kept to prepare it again when the page
    /// asks for other render-time settings (a shutter), since a file may change
    /// and standard input cannot be read twice.
    parsed: (Scene, Assets),
    /// The last scene prepared with other settings than the file's.
    variant: Mutex<Option<(PrepareOptions, Arc<RenderScene>)>>,
    /// An AFF scene as parsed, whose frames the page may ask for (`None` for NFF
    /// and P3F, which do not move).
    pub aff: Option<Arc<AffScene>>,
    /// The last frame asked for, flattened and prepared with those settings: the
    /// passes that refine a paused frame, and its ray trees, reuse it.
    frame: Mutex<Option<(u32, PrepareOptions, Arc<RenderScene>)>>,
    /// An AFF scene's fixed part (the objects under no keyframed transform), built
    /// once with the settings it was asked with: each frame builds only what moves.
    fixed: Mutex<Option<(PrepareOptions, Arc<FixedPart>)>>,
    /// 0 for the first load, then one more for each successful reload.
    pub version: u64,
    /// What the scene holds.
    pub counts: Counts,
    /// The parser's warnings, `LINE:COLUMN: message`.
    pub warnings: Vec<String>,
    /// Seconds spent reading, parsing and building.
    pub load_s: f64,
}

impl Loaded {
    /// The scene prepared with `opts`: the file's own when they change nothing, else
    /// prepared again (and kept until other settings are asked for).
    pub fn prepared(&self, opts: &PrepareOptions) -> Arc<RenderScene> {
        let asked = self.asked(opts);
        if asked == PrepareOptions::default() {
            return self.scene.clone();
        }
        let Ok(mut variant) = self.variant.lock() else {
            return self.scene.clone();
        };
        match variant.as_ref() {
            Some((made, scene)) if *made == asked => scene.clone(),
            _ => {
                let (scene, assets) = &self.parsed;
                let scene = Arc::new(prepare_with(scene.clone(), assets, &asked));
                *variant = Some((asked, scene.clone()));
                scene
            }
        }
    }

    /// The settings of `opts` that are not the file's (`nffrt render` without the
    /// flags that would ask for them prepares with none).
    fn asked(&self, opts: &PrepareOptions) -> PrepareOptions {
        let info = self.scene.info();
        PrepareOptions {
            shutter: opts.shutter.filter(|&s| s != info.shutter),
            accel: opts.accel.filter(|&a| a != self.scene.accel().kind()),
        }
    }

    /// An AFF scene's frames as the page's slider shows them (`None` for NFF and
    /// P3F). The cameras are listed when keyframed and not too many.
    pub fn animation(&self) -> Option<AnimationMsg> {
        let aff = self.aff.as_deref()?;
        let frames = aff.frames();
        let cameras = if aff.camera_track.is_some() && frames <= MAX_ANIMATION_CAMERAS {
            let at = |n| aff.camera_at(aff.time_of_frame(n));
            (0..frames).map(|n| CameraMsg::of(&at(n))).collect()
        } else {
            vec![]
        };
        Some(AnimationMsg {
            frames,
            start: aff.time_of_frame(0),
            step: aff.span.map_or(0.0, |s| s.step()),
            cameras,
        })
    }

    /// Refuses a frame the scene does not have: any frame of a scene that is not
    /// AFF, a frame past an AFF scene's last.
    pub fn check_frame(&self, frame: u32) -> Result<(), String> {
        let Some(aff) = self.aff.as_deref() else {
            return Err(format!(
                "frame {frame}: the scene is not AFF (it reads as {}) and does not move",
                self.scene.info().dialect.name()
            ));
        };
        if frame >= aff.frames() {
            return Err(format!(
                "frame {frame}: the scene has {} (0 to {})",
                nffrt::words::count(aff.frames() as usize, "frame", "frames"),
                aff.frames() - 1
            ));
        }
        Ok(())
    }

    /// The scene of `frame` prepared with `opts` (the file's scene, as
    /// [`Loaded::prepared`], for `None`): an AFF scene flattened at the frame's
    /// time, as `nffrt render --frame N` renders it, and kept until another frame
    /// or other settings are asked for.
    pub fn prepared_frame(
        &self,
        frame: Option<u32>,
        opts: &PrepareOptions,
    ) -> Result<Arc<RenderScene>, String> {
        let Some(n) = frame else {
            return Ok(self.prepared(opts));
        };
        self.check_frame(n)?;
        let aff = self.aff.as_deref().expect("checked: an AFF scene");
        let asked = self.asked(opts);
        let mut kept = self
            .frame
            .lock()
            .map_err(|_| "a frame failed to prepare".to_string())?;
        if let Some((made, with, scene)) = kept.as_ref() {
            if (*made, *with) == (n, asked) {
                return Ok(scene.clone());
            }
        }
        let time = aff.time_of_frame(n);
        let failed = |e| format!("frame {n} (time {time}): {e}");
        let fixed = self.fixed_part(aff, time, &asked).map_err(failed)?;
        let moving = aff
            .flatten_part(time, FramePart::Moving, MeshMode::Instanced)
            .map_err(failed)?;
        // The frame it replaces lends its arrays unless a render still holds it.
        let spare = kept
            .take()
            .and_then(|(_, _, old)| Arc::try_unwrap(old).ok())
            .map(RenderScene::into_bvh);
        let scene = prepare_frame(&fixed, moving, spare, &self.parsed.1, &asked)
            .expect("a fixed part that never lends its arrays grafts into a copy of them");
        let scene = Arc::new(scene);
        *kept = Some((n, asked, scene.clone()));
        Ok(scene)
    }

    /// The fixed part of `aff` built with `asked`, made (flattened at `time`: it is
    /// the same at every time) the first time those settings are asked for.
    fn fixed_part(
        &self,
        aff: &AffScene,
        time: f64,
        asked: &PrepareOptions,
    ) -> Result<Arc<FixedPart>, AffError> {
        let mut kept = self.fixed.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        if let Some((with, fixed)) = kept.as_ref() {
            if with == asked {
                return Ok(fixed.clone());
            }
        }
        let scene = aff.flatten_part(time, FramePart::Fixed, MeshMode::Instanced)?;
        let fixed = Arc::new(FixedPart::new(scene, asked));
        *kept = Some((*asked, fixed.clone()));
        Ok(fixed)
    }
}

/// What the loader tells the sessions.
#[derive(Clone)]
pub enum SceneEvent {
    /// The file changed and loaded: the new scene.
    Loaded(Arc<Loaded>),
    /// The file changed and could not be loaded.
    Failed {
        /// `FILE:LINE:COLUMN: what`, or the reason.
        message: String,
        /// Line and column of a parse error.
        at: Option<(u32, u32)>,
    },
}

/// The scene file and how to read it.
pub struct Source {
    /// The file.
    pub path: PathBuf,
    /// How to read it.
    pub limits: SceneLimitArgs,
}

impl Source {
    /// Reads, parses and builds the file (cancelled soon after `cancel` is raised,
    /// except during the BVH build).
    pub fn load(&self, version: u64, cancel: &AtomicBool) -> Result<Loaded, CliError> {
        let t0 = Instant::now();
        let loaded = load_scene_cancellable(&self.path, &self.limits, Need::Render, cancel)?;
        let parsed = (loaded.scene.clone(), loaded.assets.clone());
        let aff = loaded.aff.clone();
        let scene = Arc::new(prepare(loaded.scene, &loaded.assets));
        // The skybox's faces decoded before the first frame, so that a broken one is
        // a failed load the page shows (the current scene stays).
        decoded_assets(&scene)?;
        let info = scene.info();
        let warnings = info.warnings.iter().map(|w| w.to_string()).collect();
        let counts = Counts {
            primitives: info.primitives,
            lights: info.lights.len(),
            materials: info.materials.len(),
        };
        Ok(Loaded {
            scene,
            parsed,
            variant: Mutex::new(None),
            aff,
            frame: Mutex::new(None),
            fixed: Mutex::new(None),
            version,
            counts,
            warnings,
            load_s: t0.elapsed().as_secs_f64(),
        })
    }

    /// A failed load as the page shows it: the message and, for a parse error, the
    /// line and column it starts with after the file's name.
    pub fn failure(&self, e: &CliError) -> SceneEvent {
        let name = self.path.display().to_string();
        let at = e
            .message
            .strip_prefix(name.as_str())
            .and_then(|rest| rest.strip_prefix(':'))
            .and_then(|rest| {
                let mut parts = rest.splitn(3, ':');
                let line = parts.next()?.parse().ok()?;
                let column = parts.next()?.parse().ok()?;
                Some((line, column))
            });
        SceneEvent::Failed {
            message: e.message.clone(),
            at,
        }
    }
}

/// The current scene, shared by the sessions.
pub type Current = Arc<RwLock<Arc<Loaded>>>;

/// Starts watching `source`'s file: each change is loaded on a thread of its own and
/// broadcast on `events`; a good scene also replaces `current`. The watcher runs as
/// long as the returned value is kept.
pub fn watch(
    source: Arc<Source>,
    current: Current,
    events: broadcast::Sender<SceneEvent>,
) -> Result<notify::RecommendedWatcher, String> {
    let file_name = source.path.file_name().map(|n| n.to_os_string());
    let folder = match source.path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let cancel = Arc::new(AtomicBool::new(false));
    let (tx, rx) = mpsc::channel::<()>();
    let raise = cancel.clone();
    let mut watcher = notify::recommended_watcher(move |res: notify::Result<notify::Event>| {
        let Ok(event) = res else { return };
        let ours = event.paths.iter().any(|p| p.file_name() == file_name.as_deref());
        if ours && !matches!(event.kind, EventKind::Access(_)) {
            raise.store(true, Ordering::Relaxed);
            let _ = tx.send(());
        }
    })
    .map_err(|e| format!("cannot watch {}: {e}", source.path.display()))?;
    watcher
        .watch(&folder, RecursiveMode::NonRecursive)
        .map_err(|e| format!("cannot watch {}: {e}", folder.display()))?;
    std::thread::Builder::new()
        .name("nffrt-view-loader".into())
        .spawn(move || reload_loop(&source, &current, &events, &rx, &cancel))
        .map_err(|e| format!("cannot start the loader thread: {e}"))?;
    Ok(watcher)
}

/// Waits for changes and loads the file after each burst of them.
fn reload_loop(
    source: &Source,
    current: &Current,
    events: &broadcast::Sender<SceneEvent>,
    changes: &mpsc::Receiver<()>,
    cancel: &AtomicBool,
) {
    let mut version = current.read().map(|c| c.version).unwrap_or(0);
    while changes.recv().is_ok() {
        while changes.recv_timeout(SETTLE).is_ok() {}
        cancel.store(false, Ordering::Relaxed);
        match source.load(version + 1, cancel) {
            Ok(loaded) => {
                version += 1;
                let loaded = Arc::new(loaded);
                if let Ok(mut c) = current.write() {
                    *c = loaded.clone();
                }
                let _ = events.send(SceneEvent::Loaded(loaded));
            }
            // A newer change is queued: it loads next.
            Err(_) if cancel.load(Ordering::Relaxed) => {}
            Err(e) => {
                let _ = events.send(source.failure(&e));
            }
        }
    }
}
