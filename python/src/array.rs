//! Images as numpy arrays and files: a render becomes a writable `float32` array of
//! shape `(H, W, 3)`, top row first; any `(H, W, 3)` array of numbers is encoded as
//! PNG, PPM or PFM exactly as the command line encodes its renders.
//!
//! numpy is reached through Python calls (`frombuffer`, `ascontiguousarray`), not its
//! C API, so the module stays within the stable ABI; the one copy each way is a
//! memcpy-sized cost beside a render.

use std::path::Path;

use nffrt::image::{Encoding, Image, ImageFormat, SOFTWARE_TEXT};
use nffrt::math::Vec3;
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyBytes, PyDict};

use crate::errors::{io_error, value_error};

/// `image` as a new, writable numpy `float32` array of shape `(H, W, 3)`.
pub fn to_array<'py>(py: Python<'py>, image: &Image) -> PyResult<Bound<'py, PyAny>> {
    let buffer = PyByteArray::new_with(py, image.pixels.len() * 12, |bytes| {
        for (out, p) in bytes.chunks_exact_mut(12).zip(&image.pixels) {
            out[0..4].copy_from_slice(&p.x.to_ne_bytes());
            out[4..8].copy_from_slice(&p.y.to_ne_bytes());
            out[8..12].copy_from_slice(&p.z.to_ne_bytes());
        }
        Ok(())
    })?;
    let shape = (image.height as usize, image.width as usize, 3usize);
    py.import("numpy")?
        .call_method1("frombuffer", (buffer, "float32"))?
        .call_method1("reshape", (shape,))
}

/// The image an `(H, W, 3)` array of numbers holds (converted to `float32`).
pub fn from_array(py: Python<'_>, array: &Bound<'_, PyAny>) -> PyResult<Image> {
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", "float32")?;
    let a = py
        .import("numpy")?
        .call_method("ascontiguousarray", (array,), Some(&kwargs))?;
    let shape: Vec<usize> = a.getattr("shape")?.extract()?;
    let (h, w) = match shape[..] {
        [h, w, 3] if h > 0 && w > 0 => (h, w),
        _ => {
            return Err(value_error(format!(
                "expected an image array of shape (H, W, 3) with H, W >= 1, got shape {shape:?}"
            )))
        }
    };
    let (Ok(width), Ok(height)) = (u32::try_from(w), u32::try_from(h)) else {
        return Err(value_error(format!("a {w}x{h} image is too large")));
    };
    let bytes = a.call_method0("tobytes")?;
    let bytes = bytes.cast::<PyBytes>()?.as_bytes();
    let f = |b: &[u8]| f32::from_ne_bytes([b[0], b[1], b[2], b[3]]);
    let pixels = bytes
        .chunks_exact(12)
        .map(|c| Vec3::new(f(&c[0..4]), f(&c[4..8]), f(&c[8..12])))
        .collect();
    Ok(Image::from_pixels(width, height, pixels))
}

/// The format of `path` by its extension, as the command line chooses it.
pub fn format_of(path: &Path) -> PyResult<ImageFormat> {
    ImageFormat::from_extension(path).ok_or_else(|| value_error(ImageFormat::unknown(path)))
}

/// `image` encoded in `format`, with the text chunk of the command line's PNGs.
pub fn encode(image: &Image, format: ImageFormat) -> Result<Vec<u8>, String> {
    let mut bytes = Vec::new();
    format
        .encode(
            image,
            Encoding::Linear,
            &[(SOFTWARE_TEXT.0, SOFTWARE_TEXT.1.to_string())],
            &mut bytes,
        )
        .map_err(|e| e.to_string())?;
    Ok(bytes)
}

/// Writes `bytes` to `path` through a temporary file beside it, renamed into place
/// once complete (`nffrt::output`, as the command line writes): a failed write
/// leaves no partial file and the old one intact.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> PyResult<()> {
    nffrt::output::write_atomically(path, bytes).map_err(|e| io_error(path, &e))
}
