//! AFF, the Animated File Format of BART (Lext, Assarsson and Möller, "BART: A
//! Benchmark for Animated Ray Tracing", 2001): NFF with includes, meshes,
//! textures, transform hierarchies and keyframed motion. Read into an [`AffScene`]
//! that keeps the hierarchy (each object's geometry in its node's space), evaluated
//! at a time ([`AffScene::node_transforms`], [`AffScene::camera_at`]) and flattened
//! into a plain [`crate::Scene`] of one frame ([`AffScene::flatten`]). The
//! reference is the original distribution's parser (`parse.c`, `animation.c`,
//! `kbsplpos.c`, `kbsplrot.c`); docs/aff.md says what nffrt reads of it.
//!
//! The accepted syntax (whitespace-separated tokens; `#` and `%` start comments):
//!
//! ```text
//! v b l f s c p pp                        NFF's entities, as NFF reads them
//! la NAME x y z [r g b]                   a light that keyframes 'k NAME' move
//! fm ar ag ab dr dg db sr sg sb shine T ior   extended material
//! am r g b                                ambient light (default 1 1 1)
//! a START END FRAMES                      animation span: frame n at START + n (END - START) / FRAMES
//! i DETAIL FILE                           include FILE (from this file's folder)
//! d DETAIL                                detail level: includes above it are skipped
//! m vertices N ... [normals N ...] [texturecoords N TEX.ppm ...] triangles N ...   mesh
//! tt TEX.ppm (x y z u v) x3               textured triangle; ttp: (x y z nx ny nz u v) x3
//! tpa N (time (x y z nx ny nz) x3) xN     triangle animated by linear interpolation
//! xs sx sy sz rx ry rz deg tx ty tz { ... }   static transform T*R*S of its contents
//! x NAME { ... }                          keyframed transform of its contents
//! k NAME { transl N ... rot N ... scale N ... visibility N ... }   keyframes
//! ```
//!
//! ```
//! let scene = nffrt::aff::parse_text(
//!     "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\n\
//!      a 0 1 10\n\
//!      x spin { p 3 0 0 0 1 0 0 0 1 0 }\n\
//!      k spin { rot 4  -1 0 0 1 0 0 0 0  0 0 0 1 0 0 0 0  1 0 0 1 90 0 0 0  2 0 0 1 90 0 0 0 }\n",
//! ).unwrap();
//! assert_eq!((scene.frames(), scene.time_of_frame(5)), (10, 0.5));
//! let last = scene.flatten(1.0).unwrap();
//! // At time 1 the triangle has turned 90 degrees about z: (1, 0, 0) is at (0, 1, 0).
//! let v = last.polygon_vertices[1];
//! assert!(v.x.abs() < 1e-6 && (v.y - 1.0).abs() < 1e-6);
//! ```

mod animate;
mod entities;
mod error;
mod flatten;
mod hierarchy;
mod include;
mod instances;
mod keyframes;
mod keywords;
mod mesh;
mod parser;
mod resolve;
mod scene;
mod spline;
mod summary;
#[cfg(test)]
mod tests;
mod texture;
mod transform;

use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

pub use error::AffError;
pub use flatten::FramePart;
pub use instances::MeshMode;
pub use mesh::{MeshGeometry, MeshTriangle, Meshes, Span};
pub use scene::{
    AffScene, AffWarning, AnimatedTriangle, AnimationSpan, FillMaterial, LightPlace, Location, Node,
    NodeTransform, Object, Shape, SourceFile, Texture, Track, TriangleKey, VisibilityKey,
};
pub use spline::{PositionKey, PositionSpline, RotationKey, RotationSpline, Tcb};
pub use summary::{AffSummary, ObjectCounts};
pub use transform::{Affine, Quat};

use crate::limits::DEFAULT_MAX_SCENE_BYTES;
use crate::nff::{EntityState, Limits};

/// The text of an AFF scene's top file.
#[derive(Clone, Copy, Debug)]
pub struct AffSource<'a> {
    /// Its name in messages.
    pub name: &'a str,
    /// The file it was read from, if any (an include of it is then a cycle).
    pub path: Option<&'a Path>,
    /// Its bytes.
    pub bytes: &'a [u8],
    /// The folder its includes and textures are found from.
    pub dir: &'a Path,
}

/// A parsed scene, with the prepared text of every file it included (the top
/// file's bytes are the caller's), in the order first read.
#[derive(Clone, Debug)]
pub struct Parsed {
    /// The scene.
    pub scene: AffScene,
    /// The included files' text.
    pub included: Vec<Arc<[u8]>>,
}

/// Parses the scene of `source` and every file it includes, within `limits`, the
/// files adding up to at most `max_bytes`; gives up soon after `cancel` is raised
/// (an error whose [`AffError::is_cancelled`] is true).
pub fn parse(
    source: AffSource<'_>,
    limits: &Limits,
    max_bytes: u64,
    cancel: &AtomicBool,
) -> Result<Parsed, AffError> {
    let mut builder = parser::Builder::new(limits, max_bytes, cancel);
    let top = builder
        .sources
        .open_top(source.name, source.path, source.bytes, source.dir)?;
    let state = builder.read_file(&top, EntityState::default())?;
    let included = builder.sources.texts();
    Ok(Parsed {
        scene: builder.finish(state),
        included,
    })
}

/// Parses AFF text within the default limits; its includes and textures are found
/// from the current directory.
pub fn parse_text(text: &str) -> Result<AffScene, AffError> {
    static NEVER: AtomicBool = AtomicBool::new(false);
    let source = AffSource {
        name: "<text>",
        path: None,
        bytes: text.as_bytes(),
        dir: Path::new(""),
    };
    parse(source, &Limits::default(), DEFAULT_MAX_SCENE_BYTES, &NEVER).map(|p| p.scene)
}
