//! What `nffrt info` says of an AFF scene beyond the frame it flattens: the
//! animation, the hierarchy, the objects by kind, the textures, and the triangles
//! stored once (instanced: a mesh read again where a file is included again is kept
//! once) against those a flattened frame holds.

use serde::Serialize;

use super::scene::{AffScene, NodeTransform, Shape};

/// The objects of an AFF scene by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct ObjectCounts {
    /// `m`, `tt` and `ttp`.
    pub meshes: usize,
    /// `p`.
    pub polygons: usize,
    /// `pp`.
    pub patches: usize,
    /// `s`.
    pub spheres: usize,
    /// `c`.
    pub cones: usize,
    /// `tpa`.
    pub animated_triangles: usize,
}

impl ObjectCounts {
    /// Each kind's name (as in JSON) and count.
    pub fn named(&self) -> [(&'static str, usize); 6] {
        [
            ("meshes", self.meshes),
            ("polygons", self.polygons),
            ("patches", self.patches),
            ("spheres", self.spheres),
            ("cones", self.cones),
            ("animated_triangles", self.animated_triangles),
        ]
    }
}

/// A summary of an [`AffScene`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AffSummary {
    /// Frames of the animation (1 for a still scene).
    pub frames: u32,
    /// `a START END` (0 and 0 for a still scene).
    pub time_span: [f32; 2],
    /// The time between two frames (0 for a still scene).
    pub frame_step: f64,
    /// Files read (the top one and each included one once).
    pub files: usize,
    /// Includes followed (a file included twice counts twice).
    pub inclusions: usize,
    /// Includes skipped for their detail level.
    pub skipped_inclusions: usize,
    /// `xs` blocks.
    pub static_transforms: usize,
    /// `x` blocks.
    pub animated_transforms: usize,
    /// `x` blocks without a keyframe block.
    pub unkeyed_transforms: usize,
    /// `k` blocks.
    pub keyframe_blocks: usize,
    /// True if a `k camera` block moves the camera.
    pub animated_camera: bool,
    /// Objects of each kind.
    pub objects: ObjectCounts,
    /// Distinct mesh geometries.
    pub mesh_geometries: usize,
    /// The textures' names.
    pub textures: Vec<String>,
    /// Texels of all textures.
    pub texels: u64,
    /// Triangles stored: each mesh geometry's once, polygons and patches as fans.
    pub instanced_triangles: usize,
    /// Triangles of a flattened frame (before hidden objects and ones without area
    /// are left out): each mesh object's.
    pub flattened_triangles: usize,
    /// `fm` materials.
    pub fill_materials: usize,
}

impl AffScene {
    /// The scene's [`AffSummary`].
    pub fn summary(&self) -> AffSummary {
        let animated = self.animated_triangles.len();
        let mut objects = ObjectCounts {
            animated_triangles: animated,
            ..ObjectCounts::default()
        };
        let (mut fans, mut mesh_triangles) = (0, 0);
        for o in &self.objects {
            match o.shape {
                Shape::Mesh(g) => {
                    mesh_triangles += self.meshes.geometries[g as usize].triangles.count as usize;
                    objects.meshes += 1;
                }
                Shape::Polygon(i) => {
                    fans += self.nff.polygons[i as usize].count as usize - 2;
                    objects.polygons += 1;
                }
                Shape::Patch(i) => {
                    fans += self.nff.patches[i as usize].count as usize - 2;
                    objects.patches += 1;
                }
                Shape::Sphere(_) => objects.spheres += 1,
                Shape::Cone(_) => objects.cones += 1,
            }
        }
        let count = |f: fn(&NodeTransform) -> bool| self.nodes.iter().filter(|n| f(&n.transform)).count();
        AffSummary {
            frames: self.frames(),
            time_span: self.span.map_or([0.0; 2], |s| [s.start, s.end]),
            frame_step: self.span.map_or(0.0, |s| s.step()),
            files: self.files.len(),
            inclusions: self.inclusions,
            skipped_inclusions: self.skipped_inclusions,
            static_transforms: count(|t| matches!(t, NodeTransform::Static(_))),
            animated_transforms: count(|t| matches!(t, NodeTransform::Animated { .. })),
            unkeyed_transforms: count(|t| matches!(t, NodeTransform::Animated { track: None, .. })),
            keyframe_blocks: self.tracks.len(),
            animated_camera: self.camera_track.is_some(),
            objects,
            mesh_geometries: self.meshes.geometries.len(),
            textures: self.textures.iter().map(|t| t.name.clone()).collect(),
            texels: self
                .textures
                .iter()
                .map(|t| t.image.width() as u64 * t.image.height() as u64)
                .sum(),
            instanced_triangles: self.meshes.triangles.len() + fans + animated,
            flattened_triangles: mesh_triangles + fans + animated,
            fill_materials: self.fills.iter().filter(|f| f.is_some()).count(),
        }
    }
}
