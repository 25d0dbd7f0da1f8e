//! The load step: a scene file with everything it names. The text is parsed in its
//! format (by the file's extension unless given), then the files the scene refers to
//! — a P3F skybox's six face images — are read from the scene file's directory and
//! decoded, once.
//!
//! ```no_run
//! let scene = nffrt::load::load_file("balls_low.p3f".as_ref(), &Default::default()).unwrap();
//! ```

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use rayon::prelude::*;
use thiserror::Error;

use crate::image::skybox::{CubeFace, FaceImage, Skybox};
use crate::limits::MAX_FACE_TEXELS;
use crate::nff::{parse_format_cancellable, Format, Limits, ParseError, ParseErrorKind};
use crate::scene::Scene;

/// How to load a scene.
#[derive(Clone, Copy, Debug, Default)]
pub struct LoadOptions {
    /// The language; `None` chooses by the file's extension (`.p3f` is P3F).
    pub format: Option<Format>,
    /// What the file may make the parser allocate.
    pub limits: Limits,
}

/// Why a scene could not be loaded.
#[derive(Debug, Error)]
pub enum LoadError {
    /// The scene file itself could not be read.
    #[error("{}: {message}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// The text is malformed.
    #[error("{name}:{}:{}: {}", error.line, error.column, error.kind)]
    Parse {
        /// The file as named in messages (`<stdin>` for standard input).
        name: String,
        /// Where and what.
        error: ParseError,
    },
    /// A file the scene names (a skybox image) is missing, unreadable or corrupt.
    #[error("{}: {message}", path.display())]
    Asset {
        /// The file or folder.
        path: PathBuf,
        /// What went wrong, and which line of the scene named it.
        message: String,
    },
    /// The caller's cancellation flag was raised ([`load_bytes_cancellable`]).
    #[error("loading cancelled")]
    Cancelled,
}

/// Reads, parses and resolves the scene file at `path`.
pub fn load_file(path: &Path, opts: &LoadOptions) -> Result<Scene, LoadError> {
    let bytes = std::fs::read(path).map_err(|e| LoadError::Io {
        path: path.to_path_buf(),
        message: crate::io_reason(&e),
    })?;
    let format = opts.format.unwrap_or_else(|| Format::of_path(path));
    let name = path.display().to_string();
    load_bytes(&bytes, format, &name, path.parent(), &opts.limits)
}

/// Parses `bytes` as a scene in `format` (named `name` in errors) and resolves the
/// files it names against `dir` (the current directory when `None`, as for
/// standard input).
pub fn load_bytes(
    bytes: &[u8],
    format: Format,
    name: &str,
    dir: Option<&Path>,
    limits: &Limits,
) -> Result<Scene, LoadError> {
    static NEVER: AtomicBool = AtomicBool::new(false);
    load_bytes_cancellable(bytes, format, name, dir, limits, &NEVER)
}

/// [`load_bytes`] that stops with [`LoadError::Cancelled`] soon after `cancel` is
/// raised: the parser polls it between entities, and no skybox face is read once it
/// is up (for a viewer that reloads a file being edited).
pub fn load_bytes_cancellable(
    bytes: &[u8],
    format: Format,
    name: &str,
    dir: Option<&Path>,
    limits: &Limits,
    cancel: &AtomicBool,
) -> Result<Scene, LoadError> {
    let mut scene = parse_format_cancellable(bytes, format, limits, cancel).map_err(|error| {
        if error.kind == ParseErrorKind::Cancelled {
            return LoadError::Cancelled;
        }
        LoadError::Parse {
            name: name.to_string(),
            error,
        }
    })?;
    if cancel.load(Ordering::Relaxed) {
        return Err(LoadError::Cancelled);
    }
    resolve(&mut scene, name, dir.unwrap_or(Path::new("")))?;
    Ok(scene)
}

/// Reads the files `scene` names, relative to `dir`: decodes its skybox.
pub fn resolve(scene: &mut Scene, name: &str, dir: &Path) -> Result<(), LoadError> {
    let Some(env) = scene.environment.as_mut() else {
        return Ok(());
    };
    let folder = dir.join(&env.folder);
    let named_at = format!("the skybox named at {name}:{}:{}", env.line, env.column);
    env.skybox = Some(Arc::new(load_skybox(&folder, &named_at)?));
    Ok(())
}

/// Decodes the six faces in `folder` (`right left top bottom front back`, each a
/// `.jpg`, `.jpeg` or `.png`), in parallel. `context` says where the scene named it.
pub fn load_skybox(folder: &Path, context: &str) -> Result<Skybox, LoadError> {
    if !folder.is_dir() {
        return Err(LoadError::Asset {
            path: folder.to_path_buf(),
            message: format!("no such skybox folder ({context})"),
        });
    }
    let faces: Vec<FaceImage> = CubeFace::ALL
        .par_iter()
        .map(|face| load_face(folder, *face, context))
        .collect::<Result<_, _>>()?;
    let faces: [FaceImage; 6] = faces.try_into().expect("six faces");
    Ok(Skybox { faces })
}

fn load_face(folder: &Path, face: CubeFace, context: &str) -> Result<FaceImage, LoadError> {
    let candidates = ["jpg", "jpeg", "png"].map(|ext| folder.join(format!("{}.{ext}", face.name())));
    let Some(path) = candidates.iter().find(|p| p.is_file()) else {
        return Err(LoadError::Asset {
            path: folder.to_path_buf(),
            message: format!(
                "skybox face '{}' not found (looked for {0}.jpg, {0}.jpeg and {0}.png; {context})",
                face.name()
            ),
        });
    };
    let fail = |message: String| LoadError::Asset {
        path: path.clone(),
        message: format!("{message} ({context})"),
    };
    let reader = image::ImageReader::open(path)
        .map_err(|e| fail(format!("cannot read skybox image: {}", crate::io_reason(&e))))?
        .with_guessed_format()
        .map_err(|e| fail(format!("cannot read skybox image: {}", crate::io_reason(&e))))?;
    let (w, h) = reader
        .into_dimensions()
        .map_err(|e| fail(format!("not a readable JPEG or PNG image: {e}")))?;
    if w == 0 || h == 0 || w as u64 * h as u64 > MAX_FACE_TEXELS {
        return Err(fail(format!("a {w} x {h} skybox face is empty or too large")));
    }
    let decoded = image::ImageReader::open(path)
        .and_then(|r| r.with_guessed_format())
        .map_err(|e| fail(format!("cannot read skybox image: {}", crate::io_reason(&e))))?
        .decode()
        .map_err(|e| fail(format!("not a readable JPEG or PNG image: {e}")))?;
    let rgb = decoded.into_rgb8();
    Ok(FaceImage {
        width: rgb.width(),
        height: rgb.height(),
        rgb: rgb.into_raw(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_raised_flag_cancels_loading_and_a_lowered_one_changes_nothing() {
        let text = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\n".to_string()
            + &"s 0 0 0 1\n".repeat(2000);
        let limits = Limits::default();
        for format in [Format::Nff, Format::P3f] {
            let up = AtomicBool::new(true);
            let e = load_bytes_cancellable(text.as_bytes(), format, "x", None, &limits, &up).unwrap_err();
            assert!(matches!(e, LoadError::Cancelled), "{e}");
            let down = AtomicBool::new(false);
            let scene = load_bytes_cancellable(text.as_bytes(), format, "x", None, &limits, &down).unwrap();
            assert_eq!(scene.spheres.len(), 2000);
        }
        // A parse error stays a parse error, located.
        let down = AtomicBool::new(false);
        let e =
            load_bytes_cancellable(b"s 0 0 0 1\nq\n", Format::Nff, "x", None, &limits, &down).unwrap_err();
        assert_eq!(e.to_string(), "x:2:1: unknown keyword \"q\"");
    }
}
