//! The parsed AFF scene, kept hierarchical: each static object's geometry in the
//! local space of the transform node it sits in, the tree of nodes (static `xs`,
//! keyframed `x`), the keyframe tracks, the animated triangles (`tpa`), the
//! textures, the camera's track and the animation's span. [`super::animate`]
//! evaluates it at a time; [`super::flatten`] makes a plain [`Scene`] of a frame.

use std::path::PathBuf;

use super::mesh::Meshes;
use super::spline::{PositionSpline, RotationSpline};
use super::transform::Affine;
use crate::math::Vec3;
use crate::scene::Scene;

/// Where something stands in the scene's files.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Location {
    /// Index into [`AffScene::files`].
    pub file: u32,
    /// 1-based line.
    pub line: u32,
    /// 1-based column, in bytes.
    pub column: u32,
}

/// One file of the scene: the one loaded, or one it includes.
#[derive(Clone, Debug, PartialEq)]
pub struct SourceFile {
    /// Its name in messages: the path as given for the top file, an included one's
    /// path from the including file's directory.
    pub name: String,
    /// Its path on disk (`None` for text not read from a file).
    pub path: Option<PathBuf>,
}

/// Something the parser tolerated, with where it was.
#[derive(Clone, Debug, PartialEq)]
pub struct AffWarning {
    /// Where.
    pub at: Location,
    /// What was tolerated and what was done about it.
    pub message: String,
}

/// Where a light hangs: lights move with the transform they are in, and an `la`
/// light also with its keyframe block's translation.
#[derive(Clone, Debug, PartialEq)]
pub struct LightPlace {
    /// Index into [`AffScene::nodes`].
    pub node: u32,
    /// The name of an `la` light.
    pub name: Option<String>,
    /// Index into [`AffScene::tracks`] of the block of that name.
    pub track: Option<u32>,
}

/// A material of `fm`: the original's extended material, kept as written for a
/// later shading that follows the original code (`ambient` times the scene's
/// ambient light, Phong with `specular` colour and `4 * shine`, mirror reflection
/// weighted by `specular * (1 - t)`, refraction by `t`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FillMaterial {
    /// Ambient reflectance (RGB).
    pub ambient: Vec3,
    /// Diffuse reflectance (RGB).
    pub diffuse: Vec3,
    /// Specular reflectance (RGB).
    pub specular: Vec3,
    /// Phong exponent as written (the original uses four times it).
    pub shine: f32,
    /// Transmittance.
    pub t: f32,
    /// Index of refraction.
    pub ior: f32,
}

/// How a node places its contents in its parent's space.
#[derive(Clone, Debug, PartialEq)]
pub enum NodeTransform {
    /// The scene's root: world space.
    Root,
    /// `xs`: a fixed transform.
    Static(Affine),
    /// `x NAME`: the transform of the keyframe block `NAME` at each time, or the
    /// identity if there is none (a warning says so).
    Animated {
        /// The name.
        name: String,
        /// Index into [`AffScene::tracks`] of the block of that name.
        track: Option<u32>,
    },
}

/// A transform node: its contents are in its own space.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// Index of the enclosing node (always lower than this one's); `None` for the root.
    pub parent: Option<u32>,
    /// Its transform.
    pub transform: NodeTransform,
    /// Indices into [`AffScene::objects`] of the static objects directly in it.
    pub objects: Vec<u32>,
    /// Where it opens (the root: the top file's start).
    pub at: Location,
}

/// The geometry of a static object.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// Index into [`AffScene::meshes`]' geometries (`m`, `tt`, `ttp`).
    Mesh(u32),
    /// Index into the polygons of [`AffScene::nff`] (`p`).
    Polygon(u32),
    /// Index into its patches (`pp`).
    Patch(u32),
    /// Index into its spheres (`s`).
    Sphere(u32),
    /// Index into its cones (`c`).
    Cone(u32),
}

/// A static object: geometry in the local space of a node, with a material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Object {
    /// Index into [`AffScene::nodes`].
    pub node: u32,
    /// Index into the materials of [`AffScene::nff`].
    pub material: u32,
    /// Its geometry.
    pub shape: Shape,
    /// Where its keyword stands.
    pub at: Location,
}

/// The corners of an animated triangle at one time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleKey {
    /// The time.
    pub time: f32,
    /// The three vertices.
    pub vertices: [Vec3; 3],
    /// Their normals.
    pub normals: [Vec3; 3],
}

/// A triangle given at several times (`tpa`), in the local space of a node: between
/// two of its times its corners move in a straight line, and it stays as at its
/// first time before it and as at its last after (the original's definition).
#[derive(Clone, Debug, PartialEq)]
pub struct AnimatedTriangle {
    /// Index into [`AffScene::nodes`].
    pub node: u32,
    /// Index into the materials of [`AffScene::nff`].
    pub material: u32,
    /// Its keys, times non-decreasing (at least one).
    pub keys: Vec<TriangleKey>,
    /// Where its keyword stands.
    pub at: Location,
}

/// A visibility key: from `time` on (to the next key), the node shows or not.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VisibilityKey {
    /// When it takes effect.
    pub time: f32,
    /// Visible from then on.
    pub visible: bool,
}

/// A keyframe block (`k NAME { ... }`): the curves of a transform, the camera
/// (`camera`) or a light (`la NAME`).
#[derive(Clone, Debug, PartialEq)]
pub struct Track {
    /// The name it animates.
    pub name: String,
    /// `transl` keys.
    pub translation: Option<PositionSpline>,
    /// `rot` keys.
    pub rotation: Option<RotationSpline>,
    /// `scale` keys.
    pub scale: Option<PositionSpline>,
    /// `visibility` keys (visible before the first).
    pub visibility: Vec<VisibilityKey>,
    /// Where its `k` stands.
    pub at: Location,
}

/// A texture: an 8-bit RGB image from a binary PPM file.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Its name as the scene writes it.
    pub name: String,
    /// The file read.
    pub path: PathBuf,
    /// The image, shared by every frame flattened from the scene.
    pub image: std::sync::Arc<crate::image::Texture>,
    /// Where the scene first names it.
    pub at: Location,
}

/// `a START END FRAMES`: the animation runs from `start` to `end` in `frames` steps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnimationSpan {
    /// The time of the first frame.
    pub start: f32,
    /// The time of the last frame.
    pub end: f32,
    /// The number of frames (at least 1).
    pub frames: u32,
    /// Where the `a` stands.
    pub at: Location,
}

impl AnimationSpan {
    /// The time between two frames: `(end - start) / frames`.
    pub fn step(&self) -> f64 {
        (self.end as f64 - self.start as f64) / self.frames as f64
    }

    /// The time of frame `n`: `start + n (end - start) / frames`. The original
    /// renderer steps so and numbers its pictures from 1 (its picture `n` shows
    /// this time, `end` the last); nffrt numbers frames from 0, at `start`, so
    /// that frame `n` is the original's picture `n`. (The format's comment says
    /// `(end - start) / (frames - 1)`; the pictures distributed with BART follow
    /// the code: docs/aff.md.) Frames past the last continue at the same step.
    pub fn time_of_frame(&self, n: u32) -> f64 {
        self.start as f64 + n as f64 * self.step()
    }
}

/// A whole AFF scene as parsed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AffScene {
    /// The files read: the top one first, then each included file once, in the
    /// order they were first read.
    pub files: Vec<SourceFile>,
    /// NFF's entities as written: the camera (`v`), background, lights (in their
    /// nodes' spaces, see [`AffScene::light_places`]), the material table (`f` and
    /// `fm`), and the spheres, cones, polygons and patches of [`Shape`] in their
    /// nodes' spaces.
    pub nff: Scene,
    /// Per material of `nff`, the `fm` it came from (`None` for an `f` or the default).
    pub fills: Vec<Option<FillMaterial>>,
    /// Per light of `nff`, where it hangs in the tree.
    pub light_places: Vec<LightPlace>,
    /// The transform tree, the root first; a node's parent comes before it.
    pub nodes: Vec<Node>,
    /// Static objects in file order.
    pub objects: Vec<Object>,
    /// The meshes' geometry, each stored once however many objects use it.
    pub meshes: Meshes,
    /// Animated triangles in file order.
    pub animated_triangles: Vec<AnimatedTriangle>,
    /// The textures the meshes name.
    pub textures: Vec<Texture>,
    /// The keyframe blocks, by name (a later block of a name replaces an earlier one).
    pub tracks: Vec<Track>,
    /// Index into [`AffScene::tracks`] of the block named `camera`.
    pub camera_track: Option<u32>,
    /// `am r g b`, the global ambient light (1 1 1 when absent).
    pub ambient: Vec3,
    /// `a START END FRAMES`; `None` for a still scene (one frame at time 0).
    pub span: Option<AnimationSpan>,
    /// Includes followed (a file included twice counts twice).
    pub inclusions: usize,
    /// Includes skipped for a detail level above the scene's (`d`).
    pub skipped_inclusions: usize,
    /// What the parser tolerated.
    pub warnings: Vec<AffWarning>,
    /// The meshes' prototypes, worked out when a frame first places them.
    pub(super) lazy_prototypes: super::instances::LazyPrototypes,
}

impl AffScene {
    /// The number of frames (1 for a still scene).
    pub fn frames(&self) -> u32 {
        self.span.map_or(1, |s| s.frames)
    }

    /// The time of frame `n` ([`AnimationSpan::time_of_frame`]; 0 for a still scene).
    pub fn time_of_frame(&self, n: u32) -> f64 {
        self.span.map_or(0.0, |s| s.time_of_frame(n))
    }

    /// The times of the `k` sub-frames that blur the frame shown at time `t` over
    /// its interval `[t, t + step)`: the middles of `k` equal parts, `t + (i + 0.5)
    /// / k * step` for `i` in `0..k`. `None` for a still scene (no `a`), whose one
    /// frame has no interval.
    pub fn subframe_times(&self, t: f64, k: u32) -> Option<Vec<f64>> {
        let step = self.span?.step();
        Some((0..k).map(|i| t + (i as f64 + 0.5) / k as f64 * step).collect())
    }

    /// The name of file `file` in messages.
    pub fn file_name(&self, file: u32) -> &str {
        self.files.get(file as usize).map_or("?", |f| f.name.as_str())
    }
}
