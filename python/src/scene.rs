//! `nffrt.Scene`: a loaded scene made ready to render (one `nffrt::RenderScene`),
//! its description as plain Python values, and `render`, which releases the GIL.

use std::borrow::Cow;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex, OnceLock};
use std::time::Instant;

use nffrt::aff::{AffScene, FramePart, MeshMode};
use nffrt::image::Region;
use nffrt::load::{load_cancellable, Assets, LoadError, LoadOptions, Source};
use nffrt::math::Vec3;
use nffrt::nff::{parse_format_cancellable, Format, Limits};
use nffrt::options::{image_size, RenderLimits, RenderOptions, RenderRequest};
use nffrt::prepare::{prepare, prepare_frame, FixedPart, PrepareOptions, RenderScene};
use nffrt::render::{render_region, Stats};
use nffrt::scene::{Dialect, IntegratorKind, Light, SceneInfo};
use nffrt::words::shortest_f64;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyString};

use crate::array::{encode, to_array};
use crate::errors::{io_error, load_error, render_error, value_error};
use crate::run::{pool, without_gil};
use nffrt::image::ImageFormat;

/// The longest side of the picture `_repr_png_` renders.
const PREVIEW_SIDE: u32 = 256;

/// A parsed scene and its acceleration structure, built once; render it any number
/// of times, from any thread.
#[pyclass(frozen, module = "nffrt", name = "Scene")]
pub struct PyScene {
    prepared: RenderScene,
    path: Option<PathBuf>,
    /// The `str` or `bytes` object parsed (held, not copied; `None` for a file):
    /// what `nffrt.dask.render` sends to the workers.
    text: Option<Py<PyAny>>,
    format: Format,
    /// An AFF scene's animation, which `render(frame=..)` flattens at other times
    /// (`prepared` is its frame 0), with the files it names.
    animation: Option<(Arc<AffScene>, Assets)>,
    /// An AFF scene's fixed part (the objects under no keyframed transform), built
    /// the first time another frame is asked for: each frame then builds only what
    /// moves.
    fixed: OnceLock<Result<FixedPart, String>>,
    last_stats: Mutex<Option<(Stats, f64)>>,
}

/// The language named by `format` (`None` for "by the file's extension").
pub fn parse_format(format: Option<&str>) -> PyResult<Option<Format>> {
    match format.map(str::to_ascii_lowercase).as_deref() {
        None => Ok(None),
        Some("nff") => Ok(Some(Format::Nff)),
        Some("p3f") => Ok(Some(Format::P3f)),
        Some("aff") => Ok(Some(Format::Aff)),
        Some(other) => Err(value_error(format!(
            "format {other:?}: use \"nff\", \"p3f\" or \"aff\""
        ))),
    }
}

/// A scene that did not load, and what its message should add, if anything.
struct Unloaded {
    error: LoadError,
    hint: Option<&'static str>,
}

impl Unloaded {
    /// The Python exception (`path` None for text).
    fn into_py(self, py: Python<'_>, path: Option<&Path>) -> PyErr {
        load_error(py, path, self.error, self.hint)
    }
}

/// Why `load` failed: the file itself, or what it holds.
enum LoadFailure {
    Read(std::io::Error),
    Load(Unloaded),
}

/// What a failed NFF parse adds when the same bytes read as P3F: P3F text given
/// without its format fails at its first P3F keyword, which alone does not say so.
const P3F_HINT: &str = "the scene reads as P3F: pass format=\"p3f\"";

/// A scene prepared for rendering, and an AFF scene's animation.
type Prepared = (RenderScene, Option<(Arc<AffScene>, Assets)>);

/// Loads `bytes` in `format` through the library's one load path, named `name`, the
/// files they name found in `dir`, and prepares the scene; a failed NFF parse comes
/// with [`P3F_HINT`] when the bytes parse as P3F.
fn load_prepared(
    bytes: &[u8],
    format: Format,
    name: &str,
    dir: Option<&Path>,
    cancel: &AtomicBool,
) -> Result<Prepared, Unloaded> {
    let opts = LoadOptions {
        format: Some(format),
        ..LoadOptions::default()
    };
    let source = Source::Text { name, bytes, dir };
    match load_cancellable(source, &opts, cancel) {
        Ok(loaded) => {
            // The skybox's faces decoded now, so that a broken one is an error of
            // the load, as it is for every other file problem here.
            let scene = prepare(loaded.scene, &loaded.assets);
            scene.decode_assets().map_err(|e| Unloaded {
                error: e.into(),
                hint: None,
            })?;
            Ok((scene, loaded.aff.map(|aff| (aff, loaded.assets))))
        }
        Err(e) => {
            let reads_as_p3f = matches!(e, LoadError::Parse { .. })
                && format == Format::Nff
                && parse_format_cancellable(bytes, Format::P3f, &Limits::default(), cancel).is_ok();
            Err(Unloaded {
                error: e,
                hint: reads_as_p3f.then_some(P3F_HINT),
            })
        }
    }
}

/// A `ValueError` when `NFFRT_SIMD` asks for kernels that do not exist or this CPU
/// cannot run, as the command line refuses them (`nffrt::accel::simd`).
fn check_kernels() -> PyResult<()> {
    nffrt::accel::simd::requested().map(drop).map_err(value_error)
}

/// Reads, parses and prepares the scene file at `path`, without the GIL; Ctrl-C
/// stops the parse.
pub fn load(py: Python<'_>, path: PathBuf, format: Option<Format>) -> PyResult<PyScene> {
    check_kernels()?;
    let format = format.unwrap_or_else(|| Format::of_path(&path));
    let prepared = without_gil(py, None, |cancel| {
        // Read here, so that a missing file raises the OSError subclass of its errno.
        let bytes = std::fs::read(&path).map_err(LoadFailure::Read)?;
        let name = path.display().to_string();
        load_prepared(&bytes, format, &name, path.parent(), cancel.flag()).map_err(LoadFailure::Load)
    })?;
    let prepared = prepared.map_err(|e| match e {
        LoadFailure::Read(e) => io_error(&path, &e),
        LoadFailure::Load(u) => u.into_py(py, Some(&path)),
    })?;
    Ok(PyScene::new(prepared, Some(path), None, format))
}

/// Parses and prepares scene text (`str` or `bytes`), without the GIL; Ctrl-C stops
/// the parse. With `path`, the text is that file's: errors name it and the files it
/// names are found in its folder (else in the current directory); `format` defaults
/// to the path's extension's, else NFF. The scene keeps `text` (a reference).
pub fn parse(
    py: Python<'_>,
    text: &Bound<'_, PyAny>,
    format: Option<Format>,
    path: Option<PathBuf>,
) -> PyResult<PyScene> {
    check_kernels()?;
    let bytes = text_bytes(text)?;
    let format = format.unwrap_or_else(|| path.as_deref().map_or(Format::Nff, Format::of_path));
    let name = path
        .as_deref()
        .map_or("<string>".into(), |p| p.display().to_string());
    let dir = path.as_deref().and_then(Path::parent);
    let prepared = without_gil(py, None, |cancel| {
        load_prepared(&bytes, format, &name, dir, cancel.flag())
    })?;
    let prepared = prepared.map_err(|u| u.into_py(py, path.as_deref()))?;
    Ok(PyScene::new(prepared, path, Some(text.clone().unbind()), format))
}

/// The bytes of a `str` (UTF-8) or `bytes` object.
pub fn text_bytes<'a>(text: &'a Bound<'_, PyAny>) -> PyResult<Cow<'a, [u8]>> {
    if let Ok(s) = text.cast::<PyString>() {
        return Ok(match s.to_cow()? {
            Cow::Borrowed(s) => Cow::Borrowed(s.as_bytes()),
            Cow::Owned(s) => Cow::Owned(s.into_bytes()),
        });
    }
    if let Ok(b) = text.cast::<PyBytes>() {
        return Ok(Cow::Borrowed(b.as_bytes()));
    }
    Err(pyo3::exceptions::PyTypeError::new_err(
        "scene text must be str or bytes",
    ))
}

/// A vector as Python floats: each f32 as the decimal it prints as (`-1.6`, not
/// the `-1.600000023841858` of its exact value).
fn vec3(v: Vec3) -> (f64, f64, f64) {
    (shortest_f64(v.x), shortest_f64(v.y), shortest_f64(v.z))
}

impl PyScene {
    fn new(prepared: Prepared, path: Option<PathBuf>, text: Option<Py<PyAny>>, format: Format) -> PyScene {
        let (prepared, animation) = prepared;
        PyScene {
            prepared,
            path,
            text,
            format,
            animation,
            fixed: OnceLock::new(),
            last_stats: Mutex::new(None),
        }
    }

    /// `aff` at time `t` prepared with the files it names, `assets`, as
    /// `nffrt render --time` prepares it: its moving part built under one root with
    /// its fixed part, made once.
    fn frame_at(&self, aff: &AffScene, assets: &Assets, t: f64) -> Result<RenderScene, String> {
        let opts = PrepareOptions::default();
        let fixed = self.fixed.get_or_init(|| {
            let scene = aff
                .flatten_part(t, FramePart::Fixed, MeshMode::Instanced)
                .map_err(|e| e.to_string())?;
            Ok(FixedPart::new(scene, &opts))
        });
        let fixed = fixed.as_ref().map_err(String::clone)?;
        let moving = aff
            .flatten_part(t, FramePart::Moving, MeshMode::Instanced)
            .map_err(|e| e.to_string())?;
        Ok(prepare_frame(fixed, moving, None, assets, &opts)
            .expect("a fixed part that never lends its arrays grafts into a copy of them"))
    }

    /// The time `frame` or `time` asks for (`None`: frame 0, the prepared scene); a
    /// `ValueError` for a scene that does not move or a frame past its animation.
    fn time_asked(&self, frame: Option<u32>, time: Option<f64>) -> PyResult<Option<f64>> {
        if frame.is_none() && time.is_none() {
            return Ok(None);
        }
        let Some((aff, _)) = &self.animation else {
            return Err(value_error(format!(
                "frame and time are for AFF scenes; this one reads as {} and does not move",
                self.format()
            )));
        };
        match (frame, time) {
            (Some(_), Some(_)) => Err(value_error("give frame or time, not both")),
            (Some(n), None) if n >= aff.frames() => Err(value_error(format!(
                "frame {n}: the scene has {} frames (0 to {})",
                aff.frames(),
                aff.frames() - 1
            ))),
            (Some(n), None) => Ok(Some(aff.time_of_frame(n))),
            (None, Some(t)) if !t.is_finite() => Err(value_error(format!("time {t}: not a finite number"))),
            (None, t) => Ok(t),
        }
    }

    /// The render settings `request` asks for, as `nffrt render` reads its flags:
    /// the file's resolution and `spp` are the defaults.
    fn options(&self, request: &RenderRequest) -> PyResult<RenderOptions> {
        let resolved = request.resolve(self.info()).map_err(value_error)?;
        Ok(resolved.opts)
    }

    /// The scene's settings and summary.
    fn info(&self) -> &SceneInfo {
        self.prepared.info()
    }

    /// Renders `region` (the whole image when `None`) of the scene at time `at`
    /// (`None`: frame 0) on `threads` threads without the GIL, cancelled by Ctrl-C;
    /// remembers the ray counts. Gives back the frame prepared for the render when
    /// it is not frame 0 (the denoiser's guides are its own).
    fn render_image(
        &self,
        py: Python<'_>,
        opts: &RenderOptions,
        region: Option<(u32, u32, u32, u32)>,
        threads: Option<usize>,
        at: Option<f64>,
    ) -> PyResult<(nffrt::image::Image, Option<RenderScene>)> {
        let region = match region {
            Some((x0, y0, x1, y1)) => Region { x0, y0, x1, y1 },
            None => Region::full(opts.width, opts.height),
        };
        let pool = pool(threads)?;
        let t0 = Instant::now();
        let rendered = without_gil(py, pool.as_ref(), |cancel| {
            // Another frame: flattened at its time and prepared for this render.
            let frame = match (at, &self.animation) {
                (Some(t), Some((aff, assets))) => Some(self.frame_at(aff, assets, t)),
                _ => None,
            };
            let frame = match frame {
                Some(Ok(prepared)) => Some(prepared),
                Some(Err(e)) => return Err(value_error(format!("time {}: {e}", at.unwrap_or_default()))),
                None => None,
            };
            let scene = frame.as_ref().unwrap_or(&self.prepared);
            let limits = RenderLimits::default();
            let (image, stats) =
                render_region(scene, scene.view(), opts, &region, &limits, cancel).map_err(render_error)?;
            Ok((image, stats, frame))
        })?;
        let (image, stats, frame) = rendered?;
        if let Ok(mut last) = self.last_stats.lock() {
            *last = Some((stats, t0.elapsed().as_secs_f64()));
        }
        Ok((image, frame))
    }
}

#[pymethods]
impl PyScene {
    /// Renders the scene into a new numpy `float32` array of shape `(H, W, 3)`, top
    /// row first: linear RGB, unclamped, the values `nffrt render -o X.pfm` writes.
    ///
    /// Every argument left out takes what `nffrt render` takes without its flag:
    /// `width`, `height` and `spp` the file's (P3F `spp`; NFF: one ray through each
    /// pixel centre, 16 samples when an effect needs them); one side given, the
    /// other keeps the file's aspect; `max_depth` 5. `spp > 1` is stratified jittered sampling, `spd` the SPD's corner
    /// protocol (not with `spp`). `region=(x0, y0, x1, y1)` renders
    /// only that crop (half-open), with exactly the full render's pixels. `threads`
    /// defaults to one per core. `aperture` (lens diameter in pixels) and `focal`
    /// (focal distance over |from - at|) replace the scene's lens. `light_samples`
    /// samples every area light on an N x N grid at every hit; `seed` chooses another
    /// sample pattern (0: the usual one); `integrator` is `"whitted"` or `"path"`
    /// (default: the file's `integrator`, else Whitted's). `denoise=True` (or a
    /// quality, `"fast"`, `"balanced"`, `"high"`: True's) denoises the whole picture
    /// with Intel Open Image Denoise as `nffrt render --denoise` does (`OSError` when
    /// the library is not installed: `pip install pyoidn`). An AFF scene renders its
    /// frame 0 unless `frame` (0 to `frames - 1`) or `time` asks for another: the
    /// scene flattened at that time, as `nffrt render --frame`/`--time` renders it
    /// (denoised, if asked, as `--denoise` denoises it). The GIL is released while rendering; Ctrl-C stops the
    /// render with `KeyboardInterrupt`.
    #[pyo3(signature = (width=None, height=None, spp=None, max_depth=None, region=None, threads=None, spd=false, aperture=None, focal=None, light_samples=None, seed=None, integrator=None, denoise=None, frame=None, time=None))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
        py: Python<'py>,
        width: Option<u32>,
        height: Option<u32>,
        spp: Option<u32>,
        max_depth: Option<u32>,
        region: Option<(u32, u32, u32, u32)>,
        threads: Option<usize>,
        spd: bool,
        aperture: Option<f32>,
        focal: Option<f32>,
        light_samples: Option<u32>,
        seed: Option<u32>,
        integrator: Option<&str>,
        denoise: Option<&Bound<'py, PyAny>>,
        frame: Option<u32>,
        time: Option<f64>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let quality = crate::denoise::quality(denoise)?;
        if quality.is_some() && region.is_some() {
            return Err(value_error(
                "denoise works on whole pictures: not with region (a tile's denoised edges would not meet its \
                 neighbours')",
            ));
        }
        let at = self.time_asked(frame, time)?;
        let integrator = integrator
            .map(|name| name.to_ascii_lowercase().parse::<IntegratorKind>())
            .transpose()
            .map_err(value_error)?;
        let opts = self.options(&RenderRequest {
            width,
            height,
            spp,
            spd,
            max_depth,
            aperture,
            focal,
            light_samples,
            seed,
            integrator,
            ..RenderRequest::default()
        })?;
        let (mut image, frame) = self.render_image(py, &opts, region, threads, at)?;
        if let Some(quality) = quality {
            let scene = frame.as_ref().unwrap_or(&self.prepared);
            image = crate::denoise::denoised(py, scene, &opts, image, quality)?;
        }
        to_array(py, &image)
    }

    /// The `(width, height)` that `render(width=..., height=...)` makes: the file's
    /// size, or one side given and the other following the file's aspect ratio.
    #[pyo3(signature = (width=None, height=None))]
    fn image_size(&self, width: Option<u32>, height: Option<u32>) -> PyResult<(u32, u32)> {
        let view = self.prepared.view();
        image_size(width, height, view.width, view.height).map_err(value_error)
    }

    /// The ray counts of the last render that finished (`None` before any):
    /// `eye_rays`, `eye_hits`, `reflection_rays`, `refraction_rays`,
    /// `secondary_hits`, `shadow_rays`, `shadow_blocked`, `total_rays`, and
    /// `render_s`, its wall-clock time in seconds.
    #[getter]
    fn last_stats<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some((s, seconds)) = *self
            .last_stats
            .lock()
            .map_err(|_| value_error("stats lock poisoned"))?
        else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        for (key, v) in [
            ("eye_rays", s.eye_rays),
            ("eye_hits", s.eye_hits),
            ("reflection_rays", s.reflection_rays),
            ("refraction_rays", s.refraction_rays),
            ("secondary_hits", s.secondary_hits),
            ("shadow_rays", s.shadow_rays),
            ("shadow_blocked", s.shadow_blocked),
            ("total_rays", s.total_rays()),
        ] {
            d.set_item(key, v)?;
        }
        d.set_item("render_s", seconds)?;
        Ok(Some(d))
    }

    /// The file the scene was loaded from, or the `path` its text was parsed as
    /// (`None` for text without one).
    #[getter]
    fn path(&self) -> Option<String> {
        self.path.as_ref().map(|p| p.display().to_string())
    }

    /// The `str` or `bytes` the scene was parsed from (`None` for a loaded file).
    #[getter]
    fn text(&self, py: Python<'_>) -> Option<Py<PyAny>> {
        self.text.as_ref().map(|t| t.clone_ref(py))
    }

    /// The language: `"nff"`, `"p3f-2019"` or `"p3f-2025"` (the P3F course's
    /// dialects), or `"aff"`.
    #[getter]
    fn format(&self) -> &'static str {
        match (self.format, self.info().dialect) {
            // (P3F text with no keyword of either dialect's own.)
            (Format::P3f, Dialect::Nff) => "p3f",
            (_, dialect) => dialect.name(),
        }
    }

    /// An AFF scene's number of frames (`a START END FRAMES`; 1 without `a`), or
    /// `None` for a scene that does not move (NFF, P3F).
    #[getter]
    fn frames(&self) -> Option<u32> {
        self.animation.as_ref().map(|(aff, _)| aff.frames())
    }

    /// The time of frame `n` of an AFF scene: `START + n (END - START) / FRAMES`.
    fn frame_time(&self, n: u32) -> PyResult<f64> {
        self.time_asked(Some(n), None).map(Option::unwrap_or_default)
    }

    /// The file's image width in pixels.
    #[getter]
    fn width(&self) -> u32 {
        self.info().view.width
    }

    /// The file's image height in pixels.
    #[getter]
    fn height(&self) -> u32 {
        self.info().view.height
    }

    /// The file's samples per pixel (P3F `spp`), or `None`.
    #[getter]
    fn spp(&self) -> Option<u32> {
        self.info().spp
    }

    /// Primitive counts by kind, with `primitives` (all of them), `lights` and
    /// `materials`.
    #[getter]
    fn counts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = self.info();
        let d = PyDict::new(py);
        for (key, n) in s.kind_counts.iter().copied().chain([
            ("meshes", s.meshes),
            ("mesh_triangles", s.mesh_triangles),
            ("primitives", s.primitives),
            ("lights", s.lights.len()),
            ("materials", s.materials.len()),
        ]) {
            d.set_item(key, n)?;
        }
        Ok(d)
    }

    /// The camera: `from`, `at`, `up` (3-tuples), `angle` (vertical, degrees),
    /// `hither`, `width`, `height`, `aperture` (pixels), `focal` (over |from - at|).
    #[getter]
    fn camera<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let v = &self.info().view;
        let d = PyDict::new(py);
        d.set_item("from", vec3(v.from))?;
        d.set_item("at", vec3(v.at))?;
        d.set_item("up", vec3(v.up))?;
        d.set_item("angle", shortest_f64(v.angle))?;
        d.set_item("hither", shortest_f64(v.hither))?;
        d.set_item("width", v.width)?;
        d.set_item("height", v.height)?;
        d.set_item("aperture", shortest_f64(v.aperture))?;
        d.set_item("focal", shortest_f64(v.focal))?;
        Ok(d)
    }

    /// The lights in file order, each a dict: `position` (an area light's corner),
    /// `color` (`None`: the SPD's default intensity) and, for an area light, `v1`
    /// and `v2` (the corners at the ends of its two edges from `position`) and
    /// `grid`.
    #[getter]
    fn lights<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let light = |l: &Light| -> PyResult<Bound<'py, PyDict>> {
            let d = PyDict::new(py);
            d.set_item("position", vec3(l.position))?;
            d.set_item("color", l.color.map(vec3))?;
            if let Some(a) = &l.area {
                d.set_item("v1", vec3(a.v1))?;
                d.set_item("v2", vec3(a.v2))?;
                d.set_item("grid", a.grid)?;
            }
            Ok(d)
        };
        self.info().lights.iter().map(light).collect()
    }

    /// The background colour.
    #[getter]
    fn background(&self) -> (f64, f64, f64) {
        vec3(self.info().background)
    }

    /// `(min, max)` corners of the bounded primitives (planes excluded), or `None`.
    #[getter]
    #[allow(clippy::type_complexity)]
    fn bounds(&self) -> Option<((f64, f64, f64), (f64, f64, f64))> {
        let b = self.info().bounds;
        (!b.is_empty()).then(|| (vec3(b.min), vec3(b.max)))
    }

    /// What the parser tolerated: `(line, column, message)` tuples.
    #[getter]
    fn warnings(&self) -> Vec<(u32, u32, String)> {
        let w = &self.info().warnings;
        w.iter().map(|w| (w.line, w.column, w.message.clone())).collect()
    }

    /// A PNG preview for Jupyter: the scene at most 256 pixels on a side.
    fn _repr_png_<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let (w, h) = (self.width(), self.height());
        let scale = (PREVIEW_SIDE as f64 / w.max(h) as f64).min(1.0);
        let side = |n: u32| ((n as f64 * scale).round() as u32).max(1);
        let opts = self.options(&RenderRequest {
            width: Some(side(w)),
            height: Some(side(h)),
            spp: Some(1),
            ..RenderRequest::default()
        })?;
        let (image, _) = self.render_image(py, &opts, None, None, None)?;
        let png = encode(&image, ImageFormat::Png).map_err(value_error)?;
        Ok(PyBytes::new(py, &png))
    }

    fn __repr__(&self) -> String {
        let s = self.info();
        let name = self.path.as_deref().map(Path::display);
        let name = name.map(|n| format!("{n}: ")).unwrap_or_default();
        format!(
            "<nffrt.Scene {name}{} primitives, {} lights, {}x{}>",
            s.primitives,
            s.lights.len(),
            s.view.width,
            s.view.height
        )
    }
}
