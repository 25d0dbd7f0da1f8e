//! `Scene.render(denoise=...)`: the rendered picture denoised by Intel Open Image
//! Denoise (`nffrt::denoise`), guided by the AOVs of the same eye samples, as
//! `nffrt render --denoise` does. The library is looked for where the command line
//! looks, and first in the `pyoidn` package this interpreter imports.

use std::path::PathBuf;
use std::sync::OnceLock;

use nffrt::denoise::{Denoiser, Quality};
use nffrt::image::{Image, Region};
use nffrt::options::{RenderLimits, RenderOptions, Sampling};
use nffrt::prepare::RenderScene;
use nffrt::render::render_aovs;
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use pyo3::types::PyBool;

use crate::errors::{render_error, value_error};
use crate::run::without_gil;

/// The process's denoiser, opened by the first render that asks for one.
static DENOISER: OnceLock<Denoiser> = OnceLock::new();

/// The quality `denoise` asks for: `None` or `False` for none, `True` for `high`,
/// or a quality's name (`"fast"`, `"balanced"`, `"high"`).
pub fn quality(denoise: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Quality>> {
    let Some(arg) = denoise.filter(|a| !a.is_none()) else {
        return Ok(None);
    };
    if let Ok(flag) = arg.cast::<PyBool>() {
        return Ok(flag.is_true().then_some(Quality::High));
    }
    let name: String = arg
        .extract()
        .map_err(|_| value_error("denoise must be True, False or a quality: 'fast', 'balanced' or 'high'"))?;
    Quality::from_name(&name.to_ascii_lowercase())
        .map(Some)
        .ok_or_else(|| {
            value_error(format!(
                "denoise={name:?}: the qualities are 'fast', 'balanced' and 'high'"
            ))
        })
}

/// The folder of the library the `pyoidn` package ships, if this interpreter
/// finds that package.
fn pyoidn_dir(py: Python<'_>) -> Option<PathBuf> {
    let spec = py
        .import("importlib.util")
        .ok()?
        .call_method1("find_spec", ("pyoidn",))
        .ok()?;
    let locations = spec.getattr("submodule_search_locations").ok()?;
    let first: String = locations.get_item(0).ok()?.extract().ok()?;
    Some(PathBuf::from(first).join("oidn").join("lib"))
}

/// The denoiser, opened once per process; an `OSError` saying how to get the
/// library when it is nowhere.
fn denoiser(py: Python<'_>) -> PyResult<&'static Denoiser> {
    if let Some(d) = DENOISER.get() {
        return Ok(d);
    }
    let extra: Vec<PathBuf> = pyoidn_dir(py).into_iter().collect();
    let opened = Denoiser::open(&extra, 0).map_err(|e| PyOSError::new_err(e.to_string()))?;
    Ok(DENOISER.get_or_init(|| opened))
}

/// `image`, the whole render of `scene` with `opts`, denoised at `quality`: the
/// AOV pass and the filter run without the GIL.
pub fn denoised(
    py: Python<'_>,
    scene: &RenderScene,
    opts: &RenderOptions,
    image: Image,
    quality: Quality,
) -> PyResult<Image> {
    if matches!(opts.sampling, Sampling::PixelCenters | Sampling::SpdCorners) {
        return Err(value_error(
            "denoise: a picture of one ray through each pixel has no noise to remove; denoising is \
             for path tracing and sampled effects (spp, a lens, rough surfaces, soft shadows, motion)",
        ));
    }
    let denoiser = denoiser(py)?;
    let full = Region::full(opts.width, opts.height);
    let done = without_gil(py, None, |cancel| {
        let aovs = render_aovs(scene, scene.view(), opts, &full, &RenderLimits::default(), cancel)?;
        Ok(denoiser.denoise_render(&image, &aovs, opts, quality))
    })?;
    done.map_err(render_error)?
        .map_err(|e| PyOSError::new_err(e.to_string()))
}
