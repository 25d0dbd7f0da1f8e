//! Reading a scene from a file or standard input, with timing and warnings.

use std::io::Read;
use std::path::Path;
use std::time::Instant;

use super::CliError;
use nffrt::Scene;

/// A parsed scene with the name it is reported under and the time parsing took.
pub struct LoadedScene {
    /// The scene.
    pub scene: Scene,
    /// The path as given, or `<stdin>`.
    pub name: String,
    /// Seconds spent parsing (reading excluded).
    pub parse_s: f64,
}

/// Reads and parses `path` (`-` is standard input). Parse errors come back as
/// `PATH:LINE:COL: message` with the bad-scene exit code.
pub fn load_scene(path: &Path) -> Result<LoadedScene, CliError> {
    let name = if path == Path::new("-") {
        "<stdin>".to_string()
    } else {
        path.display().to_string()
    };
    let bytes = read_input(path, &name)?;
    let t0 = Instant::now();
    let scene = nffrt::nff::parse_bytes(&bytes)
        .map_err(|e| CliError::scene(format!("{name}:{}:{}: {}", e.line, e.column, e.kind)))?;
    Ok(LoadedScene {
        scene,
        name,
        parse_s: t0.elapsed().as_secs_f64(),
    })
}

fn read_input(path: &Path, name: &str) -> Result<Vec<u8>, CliError> {
    let mut bytes = Vec::new();
    if path == Path::new("-") {
        std::io::stdin()
            .lock()
            .read_to_end(&mut bytes)
            .map_err(|e| CliError::io(format!("reading standard input: {e}")))?;
        return Ok(bytes);
    }
    if path.is_dir() {
        return Err(CliError::io(format!("{name}: is a directory, not a scene file")));
    }
    std::fs::read(path).map_err(|e| {
        let why = match e.kind() {
            std::io::ErrorKind::NotFound => "no such file".to_string(),
            std::io::ErrorKind::PermissionDenied => "permission denied".to_string(),
            _ => e.to_string(),
        };
        CliError::io(format!("{name}: cannot read scene: {why}"))
    })
}

/// Prints the scene's warnings to standard error, at most `limit` of them.
pub fn print_warnings(loaded: &LoadedScene, limit: usize) {
    let w = &loaded.scene.warnings;
    for warning in w.iter().take(limit) {
        eprintln!(
            "{}:{}:{}: warning: {}",
            loaded.name, warning.line, warning.column, warning.message
        );
    }
    if w.len() > limit {
        eprintln!("{}: ... and {} more warnings", loaded.name, w.len() - limit);
    }
}
