//! Rust errors as Python exceptions: a malformed scene is a `SceneError` (a
//! `ValueError`) that carries where it is, a file that cannot be read an `OSError`
//! with its errno and file name (so Python picks `FileNotFoundError` and friends),
//! bad arguments a `ValueError`.

use std::path::Path;

use nffrt::load::LoadError;
use nffrt::render::RenderError;
use pyo3::exceptions::{PyKeyboardInterrupt, PyOSError, PyValueError};
use pyo3::prelude::*;

pyo3::create_exception!(
    nffrt,
    SceneError,
    PyValueError,
    "A malformed scene: `str(e)` is `PATH:LINE:COLUMN: what`, and `e.path` (None for \
     text), `e.line`, `e.column` (1-based) and `e.message` (the what) give its parts."
);

/// A `SceneError` for a parse error at `line`:`column` of `path` (None for text).
pub fn scene_error(py: Python<'_>, path: Option<&str>, line: u32, column: u32, message: String) -> PyErr {
    let shown = path.unwrap_or("<string>");
    let err = SceneError::new_err(format!("{shown}:{line}:{column}: {message}"));
    let value = err.value(py);
    let set = || -> PyResult<()> {
        value.setattr("path", path)?;
        value.setattr("line", line)?;
        value.setattr("column", column)?;
        value.setattr("message", &message)
    };
    match set() {
        Ok(()) => err,
        Err(e) => e,
    }
}

/// The exception for a scene that did not load: `path` is None for text; `hint`,
/// if any, follows a parse error's message in brackets. A word of the other
/// language's is named as such, with Python's way of choosing the format.
pub fn load_error(py: Python<'_>, path: Option<&Path>, e: LoadError, hint: Option<&str>) -> PyErr {
    match e {
        LoadError::Parse { error, .. } => {
            let path = path.map(|p| p.display().to_string());
            let (plain, other) = error.kind.without_language_hint();
            let message = match (hint, other) {
                (Some(hint), _) => format!("{plain} ({hint})"),
                (None, Some(f)) => {
                    let (name, arg) = match f {
                        nffrt::nff::Format::Nff => ("an NFF", "nff"),
                        nffrt::nff::Format::P3f => ("a P3F", "p3f"),
                        nffrt::nff::Format::Aff => ("an AFF", "aff"),
                    };
                    format!(
                        "{plain}: it is {name} keyword (pass format=\"{arg}\" if the scene is {name} file)"
                    )
                }
                (None, None) => plain,
            };
            scene_error(py, path.as_deref(), error.line, error.column, message)
        }
        // A file the scene names (a skybox image) is missing, unreadable or corrupt:
        // an OSError naming it, as the command line treats it.
        LoadError::Asset { path, message } => PyOSError::new_err(format!("{}: {message}", path.display())),
        LoadError::Io { .. } | LoadError::TooLarge { .. } => PyOSError::new_err(e.to_string()),
        LoadError::Cancelled => PyKeyboardInterrupt::new_err("loading was cancelled"),
    }
}

/// An `OSError` for `e` on `path`, with its errno when there is one, so that Python
/// raises the matching subclass (`FileNotFoundError`, `IsADirectoryError`, ...).
pub fn io_error(path: &Path, e: &std::io::Error) -> PyErr {
    let name = path.display().to_string();
    let reason = nffrt::io_reason(e);
    match e.raw_os_error() {
        Some(errno) => PyOSError::new_err((errno, reason, name)),
        None => PyOSError::new_err(format!("{name}: {reason}")),
    }
}

/// The exception for a render that did not finish: bad options are a `ValueError`;
/// a cancelled render is a `KeyboardInterrupt` unless the signal check already
/// raised one.
pub fn render_error(e: RenderError) -> PyErr {
    match e {
        RenderError::Refused(m) => PyValueError::new_err(m.to_string()),
        RenderError::Cancelled => PyKeyboardInterrupt::new_err("the render was cancelled"),
        RenderError::Asset(e) => PyOSError::new_err(e.to_string()),
    }
}

/// A `ValueError` with `message`.
pub fn value_error(message: impl Into<String>) -> PyErr {
    PyValueError::new_err(message.into())
}
