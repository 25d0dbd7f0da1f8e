//! `nffrt._nffrt`, the compiled half of the Python package `nffrt`: scenes loaded
//! or parsed into [`scene::PyScene`] (a `nffrt::RenderScene`), rendered into
//! numpy arrays without the GIL; the SPD generators; image files written as the
//! command line writes them; the bands of a split render; pictures compared
//! (`diff`: FLIP and the classic metrics). The Python package
//! (python/nffrt/) re-exports all of it and adds tiles, merging and Dask.
//!
//! Every error is a Python exception (see [`errors`]); nothing here panics on
//! input.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod array;
mod denoise;
mod diff;
mod errors;
mod run;
mod scene;

use std::path::PathBuf;

use nffrt::gen::{generate, SpdScene};
use nffrt::nff::write_nff;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use array::{encode, format_of, from_array, write_atomically};
use errors::value_error;
use nffrt::image::ImageFormat;
use scene::PyScene;

/// Reads the scene file at `path` (NFF, or P3F for a `.p3f` file or
/// `format="p3f"`), with the skybox it names, and builds its BVH. Raises
/// `SceneError` for a malformed scene, `OSError` for a file that cannot be read.
#[pyfunction]
#[pyo3(signature = (path, format=None))]
fn load(py: Python<'_>, path: PathBuf, format: Option<&str>) -> PyResult<PyScene> {
    scene::load(py, path, scene::parse_format(format)?)
}

/// Parses scene text (`str` or `bytes`) in `format` (`"nff"` or `"p3f"`; default:
/// by `path`'s extension, else NFF) and builds its BVH. `path` says which file the
/// text is (errors name it, and a skybox is found in its folder rather than the
/// current directory). Raises `SceneError` for a malformed scene (`path=None` for
/// text without one); P3F text parsed as NFF says to pass `format="p3f"`.
#[pyfunction]
#[pyo3(signature = (text, format=None, path=None))]
fn parse(
    py: Python<'_>,
    text: &Bound<'_, PyAny>,
    format: Option<&str>,
    path: Option<PathBuf>,
) -> PyResult<PyScene> {
    scene::parse(py, text, scene::parse_format(format)?, path)
}

/// The SPD's classic scene `name` (balls, gears, mount, rings, teapot, tetra, tree)
/// at `size` (the SPD's default when `None`), as NFF text.
#[pyfunction]
#[pyo3(signature = (name, size=None))]
fn gen(py: Python<'_>, name: &str, size: Option<u32>) -> PyResult<String> {
    let Some(which) = SpdScene::from_name(name) else {
        let names: Vec<&str> = SpdScene::ALL.iter().map(|s| s.name()).collect();
        return Err(value_error(format!(
            "no SPD scene {name:?}: one of {}",
            names.join(", ")
        )));
    };
    let size = size.unwrap_or_else(|| which.default_size());
    py.detach(|| {
        let scene = generate(which, size).map_err(|e| format!("size={size}: {e}"))?;
        let mut text = Vec::new();
        write_nff(&scene, &mut text).map_err(|e| e.to_string())?;
        String::from_utf8(text).map_err(|e| e.to_string())
    })
    .map_err(value_error)
}

/// Writes an `(H, W, 3)` image array to `path` as PNG or PPM (8-bit: each channel
/// clamped to [0, 1], times 255, rounded) or PFM or OpenEXR (linear floats), by the
/// extension, exactly as `nffrt render` writes the same pixels. The file appears
/// complete or not at all.
#[pyfunction]
fn save(py: Python<'_>, array: &Bound<'_, PyAny>, path: PathBuf) -> PyResult<()> {
    let format = format_of(&path)?;
    let image = from_array(py, array)?;
    let bytes = py.detach(|| encode(&image, format)).map_err(value_error)?;
    py.detach(|| write_atomically(&path, &bytes))
}

/// The PNG file `save` would write for an `(H, W, 3)` image array, as bytes (for
/// `IPython.display.Image`, or a web page).
#[pyfunction]
fn to_png<'py>(py: Python<'py>, array: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyBytes>> {
    let image = from_array(py, array)?;
    let png = py
        .detach(|| encode(&image, ImageFormat::Png))
        .map_err(value_error)?;
    Ok(PyBytes::new(py, &png))
}

/// `n` bands of whole rows of a `width` x `height` image, as `(x0, y0, x1, y1)`
/// tuples (half-open), top to bottom, heights differing by at most one.
#[pyfunction]
fn bands(width: u32, height: u32, n: u32) -> PyResult<Vec<(u32, u32, u32, u32)>> {
    let bands = nffrt::image::bands(width, height, n).map_err(value_error)?;
    Ok(bands.iter().map(|r| (r.x0, r.y0, r.x1, r.y1)).collect())
}

/// The compiled module.
#[pymodule]
fn _nffrt(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("SceneError", m.py().get_type::<errors::SceneError>())?;
    m.add_class::<PyScene>()?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(parse, m)?)?;
    m.add_function(wrap_pyfunction!(gen, m)?)?;
    m.add_function(wrap_pyfunction!(save, m)?)?;
    m.add_function(wrap_pyfunction!(to_png, m)?)?;
    m.add_function(wrap_pyfunction!(bands, m)?)?;
    m.add_function(wrap_pyfunction!(diff::diff, m)?)?;
    Ok(())
}
