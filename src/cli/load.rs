//! Loading a scene for a command: the library's [`nffrt::load`] with the command
//! line's format and limits, its errors mapped to exit codes, its warnings printed.

use std::path::Path;
use std::sync::atomic::AtomicBool;

use super::limits::SceneLimitArgs;
use super::CliError;
use nffrt::load::{load_cancellable, AssetMode, LoadError, LoadOptions, Loaded, Source};
use nffrt::prepare::RenderScene;

/// What a command needs of the files a scene names, and whether to fingerprint it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Need {
    /// A render: the files decoded.
    Render,
    /// A render tile: the files decoded and the scene fingerprinted (tiles record it).
    Tile,
    /// A summary: the files checked, not decoded.
    Summary,
}

/// Reads and parses `path` (`-` is standard input) within `limits`, in the format of
/// `--format` or the file's extension, and reads the files it names (a P3F skybox,
/// relative to the scene file; to the current directory for standard input): a file
/// larger than `--max-scene-bytes` is refused before it is read. Parse errors come
/// back as `PATH:LINE:COL: message` with the bad-scene exit code; a missing or
/// corrupt skybox image with the I/O exit code, naming it.
pub fn load_scene(path: &Path, limits: &SceneLimitArgs, need: Need) -> Result<Loaded, CliError> {
    static NEVER: AtomicBool = AtomicBool::new(false);
    load_scene_cancellable(path, limits, need, &NEVER)
}

/// [`load_scene`] that gives up soon after `cancel` is raised (an I/O error saying
/// `loading cancelled`).
pub fn load_scene_cancellable(
    path: &Path,
    limits: &SceneLimitArgs,
    need: Need,
    cancel: &AtomicBool,
) -> Result<Loaded, CliError> {
    let opts = LoadOptions {
        format: limits.format.map(Into::into),
        limits: limits.parse_limits(),
        max_bytes: limits.max_scene_bytes,
        assets: match need {
            Need::Summary => AssetMode::Check,
            Need::Render | Need::Tile => AssetMode::Decode,
        },
        fingerprint: need == Need::Tile,
    };
    let source = if path == Path::new("-") {
        Source::Stdin
    } else {
        Source::File(path)
    };
    load_cancellable(source, &opts, cancel).map_err(|e| match e {
        LoadError::Parse { .. } => CliError::scene(e.to_string()),
        LoadError::TooLarge { .. } => CliError::scene(format!("{e} (--max-scene-bytes raises the limit)")),
        LoadError::Io { .. } | LoadError::Asset { .. } | LoadError::Cancelled => CliError::io(e.to_string()),
    })
}

/// Waits for the files `scene` names to be decoded (a skybox's faces are decoded while
/// it renders): a face that could not be is an I/O error, as at load. Called after
/// tracing, before anything traced is given out.
pub fn decoded_assets(scene: &RenderScene) -> Result<(), CliError> {
    scene.decode_assets().map_err(|e| CliError::io(e.to_string()))
}

/// Prints the scene's warnings to standard error, at most `limit` of them (an AFF
/// scene's each at its own file).
pub fn print_warnings(loaded: &Loaded, limit: usize) {
    let w = &loaded.scene.warnings;
    if let Some(aff) = &loaded.aff {
        for warning in aff.warnings.iter().take(limit) {
            let (file, at) = (aff.file_name(warning.at.file), warning.at);
            eprintln!("{file}:{}:{}: warning: {}", at.line, at.column, warning.message);
        }
    } else {
        for warning in w.iter().take(limit) {
            eprintln!(
                "{}:{}:{}: warning: {}",
                loaded.name, warning.line, warning.column, warning.message
            );
        }
    }
    if w.len() > limit {
        eprintln!("{}: ... and {} more warnings", loaded.name, w.len() - limit);
    }
}
