//! The load step: a scene from a file, standard input or text, with everything it
//! names. The bytes are read within a size limit, parsed in their format (by the
//! file's extension unless given), then the files the scene refers to — a P3F
//! skybox's six face images — are read from the scene file's directory: decoded for
//! a render, or only their headers checked for a summary. The command line, the
//! viewer and the Python bindings all load through [`load`].
//!
//! The parsed [`Scene`] stays as parsed; what the files it names hold comes back
//! beside it, as [`Assets`]. An AFF scene ([`crate::aff`]: its includes and textures
//! read with it) comes back as its first frame, flattened, beside the animated
//! scene it was flattened from ([`Loaded::aff`]).
//!
//! ```no_run
//! use nffrt::load::{load, LoadOptions, Source};
//! let loaded = load(Source::File("balls_low.p3f".as_ref()), &LoadOptions::default()).unwrap();
//! println!("{} primitives", loaded.scene.primitive_count());
//! ```

use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use rayon::prelude::*;
use thiserror::Error;

use crate::aff::{AffScene, AffSource, FramePart, MeshMode};
use crate::image::skybox::{CubeFace, FaceError, FaceImage, Skybox};
use crate::limits::{DEFAULT_MAX_SCENE_BYTES, MAX_FACE_TEXELS};
use crate::nff::{parse_format_cancellable, Format, Limits, ParseError, ParseErrorKind};
use crate::scene::Scene;

/// Where a scene comes from.
#[derive(Clone, Copy, Debug)]
pub enum Source<'a> {
    /// A file; the files it names are found from its directory.
    File(&'a Path),
    /// Standard input, named `<stdin>`; named files are found from the current directory.
    Stdin,
    /// Text in memory named `name` in messages; named files are found from `dir`
    /// (the current directory when `None`).
    Text {
        /// The name errors give it.
        name: &'a str,
        /// The scene text.
        bytes: &'a [u8],
        /// Where the files it names are.
        dir: Option<&'a Path>,
    },
}

/// What to do with the files a scene names.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AssetMode {
    /// Decode them, for a render.
    #[default]
    Decode,
    /// Only check that they exist and read their image headers (sizes), for a summary.
    Check,
}

/// How to load a scene.
#[derive(Clone, Copy, Debug)]
pub struct LoadOptions {
    /// The language; `None` chooses by the file's extension (`.p3f` is P3F, `.aff`
    /// AFF, else NFF).
    pub format: Option<Format>,
    /// What the file may make the parser allocate.
    pub limits: Limits,
    /// The largest scene accepted, in bytes; larger input is refused before it is parsed.
    pub max_bytes: u64,
    /// Decode the files the scene names, or only check them.
    pub assets: AssetMode,
    /// Work out [`Loaded::fingerprint`] (tiles record it; about a millisecond per megabyte).
    pub fingerprint: bool,
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions {
            format: None,
            limits: Limits::default(),
            max_bytes: DEFAULT_MAX_SCENE_BYTES,
            assets: AssetMode::Decode,
            fingerprint: false,
        }
    }
}

/// What the files a scene names hold.
#[derive(Clone, Debug, Default)]
pub struct Assets {
    /// The decoded skybox ([`AssetMode::Decode`] of a scene with `env`).
    pub skybox: Option<Arc<Skybox>>,
    /// The size of each skybox face, in [`CubeFace::ALL`]'s order, from its header.
    pub skybox_sizes: Option<[(u32, u32); 6]>,
}

/// A loaded scene.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The scene as parsed (of an AFF scene, its first frame flattened).
    pub scene: Scene,
    /// The AFF scene, animated and hierarchical, that `scene` is the first frame of.
    pub aff: Option<Arc<AffScene>>,
    /// What the files it names hold.
    pub assets: Assets,
    /// The name messages give it: the path as given, `<stdin>`, or the text's name.
    pub name: String,
    /// The fingerprint of the scene's bytes and of the files it names
    /// ([`crate::fingerprint::scene_fingerprint_with`]), when asked for.
    pub fingerprint: Option<u64>,
    /// Seconds spent parsing (reading the file excluded).
    pub parse_s: f64,
    /// Seconds spent reading the headers of the files the scene names (a skybox's
    /// faces are decoded later, in the background and as rays need them).
    pub assets_s: f64,
}

/// Why a scene could not be loaded.
#[derive(Debug, Error)]
pub enum LoadError {
    /// The scene itself could not be read.
    #[error("{name}: {message}")]
    Io {
        /// The scene as named in messages.
        name: String,
        /// What went wrong.
        message: String,
    },
    /// The scene is larger than [`LoadOptions::max_bytes`].
    #[error("{name}: the scene is larger than {max_bytes} bytes")]
    TooLarge {
        /// The scene as named in messages.
        name: String,
        /// The limit.
        max_bytes: u64,
    },
    /// The text is malformed.
    #[error("{name}:{}:{}: {}", error.line, error.column, error.kind)]
    Parse {
        /// The scene as named in messages.
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
    /// The caller's cancellation flag was raised ([`load_cancellable`]).
    #[error("loading cancelled")]
    Cancelled,
}

impl From<FaceError> for LoadError {
    fn from(e: FaceError) -> LoadError {
        LoadError::Asset {
            path: e.path,
            message: e.message,
        }
    }
}

/// Reads, parses and resolves the scene of `source`.
pub fn load(source: Source<'_>, opts: &LoadOptions) -> Result<Loaded, LoadError> {
    static NEVER: AtomicBool = AtomicBool::new(false);
    load_cancellable(source, opts, &NEVER)
}

/// [`load`] that stops with [`LoadError::Cancelled`] soon after `cancel` is raised:
/// the parser polls it between entities, and no named file is read once it is up
/// (for a viewer that reloads a file being edited, or Ctrl-C in Python).
pub fn load_cancellable(
    source: Source<'_>,
    opts: &LoadOptions,
    cancel: &AtomicBool,
) -> Result<Loaded, LoadError> {
    let (name, read, dir, format) = match source {
        Source::File(path) => (
            path.display().to_string(),
            None,
            path.parent(),
            opts.format.unwrap_or_else(|| Format::of_path(path)),
        ),
        Source::Stdin => (
            "<stdin>".to_string(),
            None,
            None,
            opts.format.unwrap_or(Format::Nff),
        ),
        Source::Text { name, bytes, dir } => (
            name.to_string(),
            Some(bytes),
            dir,
            opts.format.unwrap_or(Format::Nff),
        ),
    };
    let owned;
    let bytes = match (read, source) {
        (Some(bytes), _) if bytes.len() as u64 > opts.max_bytes => {
            return Err(LoadError::TooLarge {
                name,
                max_bytes: opts.max_bytes,
            })
        }
        (Some(bytes), _) => bytes,
        (None, Source::File(path)) => {
            owned = read_file(path, &name, opts.max_bytes)?;
            &owned[..]
        }
        (None, _) => {
            owned = read_stdin(&name, opts.max_bytes)?;
            &owned[..]
        }
    };
    let t0 = Instant::now();
    let (scene, aff, included) = if format == Format::Aff {
        let path = match source {
            Source::File(path) => Some(path),
            _ => None,
        };
        let source = AffSource {
            name: &name,
            path,
            bytes,
            dir: dir.unwrap_or(Path::new("")),
        };
        let (scene, parsed) = load_aff(source, opts, cancel)?;
        (scene, Some(Arc::new(parsed.scene)), parsed.included)
    } else {
        let scene = parse_format_cancellable(bytes, format, &opts.limits, cancel).map_err(|error| {
            if error.kind == ParseErrorKind::Cancelled {
                return LoadError::Cancelled;
            }
            LoadError::Parse {
                name: name.clone(),
                error,
            }
        })?;
        (scene, None, Vec::new())
    };
    let parse_s = t0.elapsed().as_secs_f64();
    if cancel.load(Ordering::Relaxed) {
        return Err(LoadError::Cancelled);
    }
    let t1 = Instant::now();
    let named = NamedFiles::of(&scene, &name, dir.unwrap_or(Path::new("")))?;
    let assets = match &named {
        Some(n) => n.read(opts.assets)?,
        None => Assets::default(),
    };
    let fingerprint = opts
        .fingerprint
        .then(|| {
            // An AFF scene's included files and textures count as files it names.
            let textures = aff.iter().flat_map(|a| a.textures.iter().map(|t| t.image.rgb()));
            let extra: Vec<&[u8]> = included.iter().map(|t| &t[..]).chain(textures).collect();
            fingerprint(bytes, named.as_ref(), &extra)
        })
        .transpose()?;
    Ok(Loaded {
        scene,
        aff,
        assets,
        name,
        fingerprint,
        parse_s,
        assets_s: t1.elapsed().as_secs_f64(),
    })
}

/// Reads at most `max_bytes` of the scene file (one more byte means it is too large,
/// whatever its metadata claims: /proc files have no length).
fn read_file(path: &Path, name: &str, max_bytes: u64) -> Result<Vec<u8>, LoadError> {
    if path.is_dir() {
        return Err(LoadError::Io {
            name: name.to_string(),
            message: "is a directory, not a scene file".into(),
        });
    }
    let cannot_read = |e: std::io::Error| LoadError::Io {
        name: name.to_string(),
        message: format!("cannot read scene: {}", crate::io_reason(&e)),
    };
    let file = std::fs::File::open(path).map_err(cannot_read)?;
    let known = file.metadata().map(|m| m.len()).unwrap_or(0);
    let too_large = || LoadError::TooLarge {
        name: name.to_string(),
        max_bytes,
    };
    if known > max_bytes {
        return Err(too_large());
    }
    // Scenes of tens of megabytes: huge pages take most page faults off the read.
    let mut bytes = crate::pages::huge_vec(known as usize);
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(cannot_read)?;
    if bytes.len() as u64 > max_bytes {
        return Err(too_large());
    }
    Ok(bytes)
}

/// Reads at most `max_bytes` of standard input (one more byte means it is too large).
fn read_stdin(name: &str, max_bytes: u64) -> Result<Vec<u8>, LoadError> {
    let mut bytes = Vec::new();
    std::io::stdin()
        .lock()
        .take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| LoadError::Io {
            name: name.to_string(),
            message: format!("cannot read standard input: {}", crate::io_reason(&e)),
        })?;
    if bytes.len() as u64 > max_bytes {
        return Err(LoadError::TooLarge {
            name: name.to_string(),
            max_bytes,
        });
    }
    Ok(bytes)
}

/// The files a scene names: its skybox's six faces, and where the scene named them.
struct NamedFiles {
    faces: [PathBuf; 6],
    /// `the skybox named at FILE:LINE:COLUMN`, for messages.
    context: String,
}

impl NamedFiles {
    /// The files `scene` names, found from `dir`; `None` if it names none.
    fn of(scene: &Scene, name: &str, dir: &Path) -> Result<Option<NamedFiles>, LoadError> {
        let Some(env) = scene.environment.as_ref() else {
            return Ok(None);
        };
        let folder = dir.join(&env.folder);
        let context = format!("the skybox named at {name}:{}:{}", env.line, env.column);
        let faces = find_faces(&folder, &context)?;
        Ok(Some(NamedFiles { faces, context }))
    }

    /// Reads the faces' headers (in parallel), and in [`AssetMode::Decode`] makes the
    /// skybox, whose faces are decoded in the background and on first use
    /// ([`Skybox`]): a render does not wait for them to start.
    fn read(&self, mode: AssetMode) -> Result<Assets, LoadError> {
        let sizes: Vec<(u32, u32)> = self
            .faces
            .par_iter()
            .map(|path| face_size(path, &self.context))
            .collect::<Result<_, _>>()?;
        let sizes: [(u32, u32); 6] = sizes.try_into().expect("six faces");
        let skybox = match mode {
            AssetMode::Check => None,
            AssetMode::Decode => {
                let (faces, context) = (self.faces.clone(), self.context.clone());
                let decoder = move |face: CubeFace| {
                    let i = face as usize;
                    decode_face(&faces[i], sizes[i], &context)
                };
                let sky = Arc::new(Skybox::lazy(sizes, Box::new(decoder)));
                sky.decode_in_background();
                Some(sky)
            }
        };
        Ok(Assets {
            skybox,
            skybox_sizes: Some(sizes),
        })
    }
}

/// An AFF scene's first frame, and the scene with the text of the files it
/// includes (for the fingerprint).
fn load_aff(
    source: AffSource<'_>,
    opts: &LoadOptions,
    cancel: &AtomicBool,
) -> Result<(Scene, crate::aff::Parsed), LoadError> {
    let located = |e: crate::aff::AffError| match e.is_cancelled() {
        true => LoadError::Cancelled,
        false => LoadError::Parse {
            name: e.file,
            error: e.error,
        },
    };
    let parsed = crate::aff::parse(source, &opts.limits, opts.max_bytes, cancel).map_err(located)?;
    let aff = &parsed.scene;
    let scene = aff
        .flatten_part(aff.time_of_frame(0), FramePart::All, MeshMode::Instanced)
        .map_err(located)?;
    Ok((scene, parsed))
}

/// The fingerprint of a scene's `bytes`, of the files it names and of those it
/// includes, each after its length (see
/// [`crate::fingerprint::scene_fingerprint_with`]).
fn fingerprint(bytes: &[u8], named: Option<&NamedFiles>, included: &[&[u8]]) -> Result<u64, LoadError> {
    let mut files = Vec::new();
    for path in named.map(|n| &n.faces[..]).unwrap_or_default() {
        let context = named.map(|n| n.context.as_str()).unwrap_or_default();
        files.push(std::fs::read(path).map_err(|e| LoadError::from(cannot_read_face(path, &e, context)))?);
    }
    let pieces: Vec<&[u8]> = included
        .iter()
        .copied()
        .chain(files.iter().map(Vec::as_slice))
        .collect();
    Ok(crate::fingerprint::scene_fingerprint_with(bytes, &pieces))
}

/// The six face images in `folder` (`right left top bottom front back`, each a
/// `.jpg`, `.jpeg` or `.png`). `context` says where the scene named it.
fn find_faces(folder: &Path, context: &str) -> Result<[PathBuf; 6], LoadError> {
    if !folder.is_dir() {
        return Err(LoadError::Asset {
            path: folder.to_path_buf(),
            message: format!("no such skybox folder ({context})"),
        });
    }
    let mut faces = Vec::with_capacity(6);
    for face in CubeFace::ALL {
        let candidates = ["jpg", "jpeg", "png"].map(|ext| folder.join(format!("{}.{ext}", face.name())));
        let Some(path) = candidates.into_iter().find(|p| p.is_file()) else {
            return Err(LoadError::Asset {
                path: folder.to_path_buf(),
                message: format!(
                    "skybox face '{}' not found (looked for {0}.jpg, {0}.jpeg and {0}.png; {context})",
                    face.name()
                ),
            });
        };
        faces.push(path);
    }
    Ok(faces.try_into().expect("six faces"))
}

fn cannot_read_face(path: &Path, e: &std::io::Error, context: &str) -> FaceError {
    FaceError {
        path: path.to_path_buf(),
        message: format!("cannot read skybox image: {} ({context})", crate::io_reason(e)),
    }
}

fn not_an_image(path: &Path, e: &image::ImageError, context: &str) -> FaceError {
    FaceError {
        path: path.to_path_buf(),
        message: format!("not a readable JPEG or PNG image: {e} ({context})"),
    }
}

/// A face image's size from its header: at least one texel, at most
/// [`MAX_FACE_TEXELS`].
fn face_size(path: &Path, context: &str) -> Result<(u32, u32), LoadError> {
    let (w, h) = image::ImageReader::open(path)
        .and_then(|r| r.with_guessed_format())
        .map_err(|e| cannot_read_face(path, &e, context))?
        .into_dimensions()
        .map_err(|e| LoadError::from(not_an_image(path, &e, context)))?;
    if w == 0 || h == 0 || w as u64 * h as u64 > MAX_FACE_TEXELS {
        return Err(LoadError::Asset {
            path: path.to_path_buf(),
            message: format!("a {w} x {h} skybox face is empty or too large ({context})"),
        });
    }
    Ok((w, h))
}

/// Decodes a face image, whose header said `size` ([`face_size`]).
fn decode_face(path: &Path, size: (u32, u32), context: &str) -> Result<FaceImage, FaceError> {
    let decoded = image::ImageReader::open(path)
        .and_then(|r| r.with_guessed_format())
        .map_err(|e| cannot_read_face(path, &e, context))?
        .decode()
        .map_err(|e| not_an_image(path, &e, context))?;
    let rgb = decoded.into_rgb8();
    if rgb.dimensions() != size {
        return Err(FaceError {
            path: path.to_path_buf(),
            message: format!(
                "decoded to {} x {} texels, not the {} x {} of its header ({context})",
                rgb.width(),
                rgb.height(),
                size.0,
                size.1
            ),
        });
    }
    Ok(FaceImage {
        width: rgb.width(),
        height: rgb.height(),
        rgb: rgb.into_raw(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text(bytes: &[u8]) -> Source<'_> {
        Source::Text {
            name: "x",
            bytes,
            dir: None,
        }
    }

    #[test]
    fn a_raised_flag_cancels_loading_and_a_lowered_one_changes_nothing() {
        let text_ = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\n".to_string()
            + &"s 0 0 0 1\n".repeat(2000);
        for format in [Format::Nff, Format::P3f] {
            let opts = LoadOptions {
                format: Some(format),
                ..LoadOptions::default()
            };
            let up = AtomicBool::new(true);
            let e = load_cancellable(text(text_.as_bytes()), &opts, &up).unwrap_err();
            assert!(matches!(e, LoadError::Cancelled), "{e}");
            let down = AtomicBool::new(false);
            let loaded = load_cancellable(text(text_.as_bytes()), &opts, &down).unwrap();
            assert_eq!(loaded.scene.spheres.len(), 2000);
        }
        // A parse error stays a parse error, located.
        let e = load(text(b"s 0 0 0 1\nq\n"), &LoadOptions::default()).unwrap_err();
        assert_eq!(e.to_string(), "x:2:1: unknown keyword \"q\"");
    }

    #[test]
    fn text_over_the_byte_limit_is_refused_before_parsing() {
        let opts = LoadOptions {
            max_bytes: 9,
            ..LoadOptions::default()
        };
        // Ten bytes of nonsense: the size, not the parse, is the error.
        let e = load(text(b"q q q q q "), &opts).unwrap_err();
        assert_eq!(e.to_string(), "x: the scene is larger than 9 bytes");
        assert!(load(text(b"s 0 0 0 1"), &opts).is_ok());
    }
}
