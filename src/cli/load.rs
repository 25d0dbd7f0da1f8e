//! Reading a scene from a file or standard input, with timing and warnings.

use std::io::Read;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use super::limits::SceneLimitArgs;
use super::output::brief;
use super::CliError;
use nffrt::accel::Bvh;
use nffrt::geometry::build_geometry;
use nffrt::load::{load_bytes_cancellable, LoadError};
use nffrt::nff::Format;
use nffrt::Scene;

/// A parsed scene with the name it is reported under and the time parsing took.
pub struct LoadedScene {
    /// The scene.
    pub scene: Scene,
    /// The path as given, or `<stdin>`.
    pub name: String,
    /// Seconds spent parsing (reading excluded).
    pub parse_s: f64,
    /// The scene's fingerprint ([`nffrt::fingerprint::scene_fingerprint`]), if asked for.
    pub fingerprint: Option<u64>,
}

/// Whether to fingerprint the scene as it is read (tiles record it; it costs about a
/// millisecond per megabyte).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fingerprint {
    /// No fingerprint.
    None,
    /// The scene's fingerprint.
    Scene,
}

/// Reads and parses `path` (`-` is standard input) within `limits`, in the format of
/// `--format` or the file's extension, and decodes the files it names (a P3F
/// skybox, relative to the scene file; to the current directory for standard
/// input): a file larger than `--max-scene-bytes` is refused before it is read.
/// Parse errors come back as `PATH:LINE:COL: message` with the bad-scene exit
/// code; a missing or corrupt skybox image with the I/O exit code, naming it.
pub fn load_scene_with(
    path: &Path,
    limits: &SceneLimitArgs,
    fingerprint: Fingerprint,
) -> Result<LoadedScene, CliError> {
    static NEVER: AtomicBool = AtomicBool::new(false);
    load_scene_cancellable(path, limits, fingerprint, &NEVER)
}

/// [`load_scene_with`] that gives up soon after `cancel` is raised (an I/O error
/// saying `loading cancelled`).
pub fn load_scene_cancellable(
    path: &Path,
    limits: &SceneLimitArgs,
    fingerprint: Fingerprint,
    cancel: &AtomicBool,
) -> Result<LoadedScene, CliError> {
    let name = if path == Path::new("-") {
        "<stdin>".to_string()
    } else {
        path.display().to_string()
    };
    let bytes = read_input(path, &name, limits.max_scene_bytes)?;
    let t0 = Instant::now();
    let stdin = path == Path::new("-");
    let format = limits
        .format
        .map(Format::from)
        .unwrap_or_else(|| Format::of_path(path));
    let dir = if stdin { None } else { path.parent() };
    let scene =
        load_bytes_cancellable(&bytes, format, &name, dir, &limits.parse_limits(), cancel).map_err(|e| {
            match e {
                LoadError::Parse { .. } => CliError::scene(e.to_string()),
                LoadError::Io { .. } | LoadError::Asset { .. } | LoadError::Cancelled => {
                    CliError::io(e.to_string())
                }
            }
        })?;
    let parse_s = t0.elapsed().as_secs_f64();
    let fingerprint = (fingerprint == Fingerprint::Scene).then(|| scene_fingerprint(&bytes, &scene));
    Ok(LoadedScene {
        scene,
        name,
        parse_s,
        fingerprint,
    })
}

/// The fingerprint of a loaded scene: its file's bytes and, for a skybox, the size
/// and pixels of each face.
fn scene_fingerprint(bytes: &[u8], scene: &Scene) -> u64 {
    let sky = scene.environment.as_ref().and_then(|e| e.skybox.as_deref());
    let sizes: Vec<[u8; 8]> = sky
        .map(|s| s.faces.iter().map(|f| pack(f.width, f.height)).collect())
        .unwrap_or_default();
    let mut named: Vec<&[u8]> = Vec::new();
    if let Some(s) = sky {
        for (face, size) in s.faces.iter().zip(&sizes) {
            named.push(size);
            named.push(&face.rgb);
        }
    }
    nffrt::fingerprint::scene_fingerprint_with(bytes, &named)
}

fn pack(width: u32, height: u32) -> [u8; 8] {
    ((width as u64) << 32 | height as u64).to_le_bytes()
}

/// Reads at most `max_bytes` (one more byte means the input is too large, whatever
/// its metadata claims: pipes and /proc files have no length).
fn read_input(path: &Path, name: &str, max_bytes: u64) -> Result<Vec<u8>, CliError> {
    let mut bytes = Vec::new();
    let too_large = || {
        CliError::scene(format!(
            "{name}: the scene is larger than {max_bytes} bytes (--max-scene-bytes raises the limit)"
        ))
    };
    if path == Path::new("-") {
        std::io::stdin()
            .lock()
            .take(max_bytes.saturating_add(1))
            .read_to_end(&mut bytes)
            .map_err(|e| CliError::io(format!("reading standard input: {e}")))?;
        return if bytes.len() as u64 > max_bytes {
            Err(too_large())
        } else {
            Ok(bytes)
        };
    }
    if path.is_dir() {
        return Err(CliError::io(format!("{name}: is a directory, not a scene file")));
    }
    let cannot_read = |e: std::io::Error| CliError::io(format!("{name}: cannot read scene: {}", brief(&e)));
    let file = std::fs::File::open(path).map_err(cannot_read)?;
    let known = file.metadata().map(|m| m.len()).unwrap_or(0);
    if known > max_bytes {
        return Err(too_large());
    }
    bytes.reserve(known as usize);
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(cannot_read)?;
    if bytes.len() as u64 > max_bytes {
        return Err(too_large());
    }
    Ok(bytes)
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

/// Builds the render-time geometry and its BVH, emptying the scene's primitive and
/// vertex lists as soon as the geometry no longer needs them, before the BVH build
/// (the memory peak): the tracer reads only the view, lights, materials and background.
pub fn build_bvh(scene: &mut Scene) -> Bvh {
    let geometry = build_geometry(scene);
    for v in [
        &mut scene.polygon_vertices,
        &mut scene.patch_vertices,
        &mut scene.patch_normals,
    ] {
        *v = Vec::new();
    }
    scene.spheres = Vec::new();
    scene.cones = Vec::new();
    scene.polygons = Vec::new();
    scene.patches = Vec::new();
    scene.planes = Vec::new();
    scene.boxes = Vec::new();
    scene.meshes = Vec::new();
    scene.mesh_vertices = Vec::new();
    scene.mesh_triangles = Vec::new();
    Bvh::new(geometry)
}
