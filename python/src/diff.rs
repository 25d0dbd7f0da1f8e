//! `nffrt.diff`: how far a test picture is from a reference ([`nffrt::compare`]),
//! each given as a file path or an `(H, W, 3)` numpy array: `uint8` arrays are
//! 8-bit pictures (LDR-FLIP reads them as sRGB), float arrays linear values
//! (HDR-FLIP), as `.png` and `.pfm` files are.

use std::path::PathBuf;

use nffrt::compare::{compare, Metric, Picture, Range, ReadError};
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyBytes};

use crate::array::from_array;
use crate::errors::{io_error, value_error};

/// The picture a path or an array holds.
fn picture(py: Python<'_>, source: &Bound<'_, PyAny>) -> PyResult<Picture> {
    if let Ok(path) = source.extract::<PathBuf>() {
        let name = path.display().to_string();
        return py.detach(|| Picture::read(&path)).map_err(|e| match e {
            ReadError::Io(io) => io_error(&path, &io),
            e => value_error(format!("{name}: {e}")),
        });
    }
    let array = py.import("numpy")?.call_method("asarray", (source,), None)?;
    let dtype = array.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    let itemsize: usize = dtype.getattr("itemsize")?.extract()?;
    match (kind.as_str(), itemsize) {
        ("u", 1) => {
            let shape: Vec<usize> = array.getattr("shape")?.extract()?;
            let [h, w, 3] = shape[..] else {
                return Err(value_error(format!(
                    "expected an image array of shape (H, W, 3), got shape {shape:?}"
                )));
            };
            let contiguous = py.import("numpy")?.call_method1("ascontiguousarray", (array,))?;
            let bytes = contiguous.call_method0("tobytes")?;
            let bytes = bytes.cast::<PyBytes>()?.as_bytes();
            let (Ok(w), Ok(h)) = (u32::try_from(w), u32::try_from(h)) else {
                return Err(value_error(format!("a {w}x{h} image is too large")));
            };
            Picture::from_rgb8(w, h, bytes).map_err(value_error)
        }
        ("f", _) => {
            let image = from_array(py, &array)?;
            let values: Vec<f32> = image.pixels.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
            Picture::new(image.width, image.height, &values, Range::Linear).map_err(value_error)
        }
        _ => Err(value_error(format!(
            "an image array of dtype {} (use uint8 for an 8-bit picture, floats for linear values)",
            dtype.str()?
        ))),
    }
}

/// How far `test` is from `ref`: FLIP's mean error (the default; LDR-FLIP for
/// 8-bit pictures, HDR-FLIP for float ones) or `metric` `"mse"`, `"rmse"`,
/// `"relmse"`, `"mae"`, `"psnr"` (dB), as `nffrt diff` measures it. Each is a path
/// (PNG, PPM, PFM, OpenEXR) or an `(H, W, 3)` array. With `map=True`, also each
/// pixel's error as a `float32` array of shape `(H, W)`.
#[pyfunction]
#[pyo3(signature = (test, r#ref, metric="flip", map=false))]
pub fn diff<'py>(
    py: Python<'py>,
    test: &Bound<'py, PyAny>,
    r#ref: &Bound<'py, PyAny>,
    metric: &str,
    map: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let Some(metric) = Metric::from_name(metric) else {
        let names: Vec<&str> = Metric::ALL.iter().map(|m| m.name()).collect();
        return Err(value_error(format!(
            "no metric {metric:?}: one of {}",
            names.join(", ")
        )));
    };
    let (test, reference) = (picture(py, test)?, picture(py, r#ref)?);
    let c = py
        .detach(|| compare(&test, &reference, metric))
        .map_err(|e| value_error(e.to_string()))?;
    let value = c.value.into_pyobject(py)?.into_any();
    if !map {
        return Ok(value);
    }
    let bytes: Vec<u8> = c.map.iter().flat_map(|v| v.to_ne_bytes()).collect();
    let shape = (c.height as usize, c.width as usize);
    let array = py
        .import("numpy")?
        .call_method1("frombuffer", (PyByteArray::new(py, &bytes), "float32"))?
        .call_method1("reshape", (shape,))?;
    Ok((value, array).into_pyobject(py)?.into_any())
}
