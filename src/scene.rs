//! The plain scene description that the parser fills and every later stage reads.
//!
//! Primitives are stored per kind in flat vectors; each keeps a `u32` index into the
//! material table and the file line it came from (for diagnostics and `--pixel`).
//! Polygon and patch vertices live in shared vectors that the primitives index into,
//! so a scene with millions of primitives makes no per-primitive heap allocation.
//! A generated scene ([`crate::gen`]) numbers its primitives with the lines they
//! occupy when [`crate::nff::write_nff`] writes it, which also fixes their order there.

use crate::limits::DEFAULT_SHUTTER;
use crate::math::{Aabb, Vec3};
use std::sync::Arc;

/// A surface material: the operands of NFF's `f` keyword, or of P3F's `f` / `mat`
/// with its specular colour (11 numbers), its emitted radiance (14 numbers) and an
/// optional `roughness R` suffix (docs/p3f.md).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Material {
    /// Base (diffuse) colour (linear RGB).
    pub color: Vec3,
    /// Diffuse weight `Kd`.
    pub kd: f32,
    /// Specular colour: tints the highlight and the mirror reflection (P3F; white in NFF).
    pub specular: Vec3,
    /// Specular weight `Ks`: highlight strength and reflection coefficient.
    pub ks: f32,
    /// Phong exponent.
    pub shine: f32,
    /// Transmittance: the fraction carried by the refracted ray.
    pub t: f32,
    /// Index of refraction (meaningless when `t == 0`).
    pub ior: f32,
    /// Emitted radiance (linear RGB, as given): P3F's 12th to 14th numbers; zero
    /// when the file gives none, and always in NFF.
    pub emission: Vec3,
    /// Roughness in [0, 1] of the mirror reflection and the refraction: 0 is a
    /// perfect mirror and smooth glass (P3F's `roughness R`; 0 when absent and
    /// always in NFF).
    pub roughness: f32,
    /// The ambient reflectance of AFF's `fm` (what the ambient light `am` shows of
    /// the surface under AFF's rules); zero for `f` and in NFF and P3F, whose rules
    /// reflect the ambient light by the diffuse colour.
    pub ambient: Vec3,
    /// The texture (an index into [`Scene::textures`]) whose texel at each hit
    /// multiplies what the surface sends back under Whitted's rules, its diffuse
    /// albedo in the path tracer (AFF's textured meshes); `None` for
    /// a plain colour.
    pub texture: Option<u32>,
}

impl Material {
    /// The material given to objects that come before any `f`: matte white
    /// (`f 1 1 1 1 0 1 0 1`). The parser warns once when it uses it.
    pub const DEFAULT: Material = Material {
        color: Vec3::ONE,
        kd: 1.0,
        specular: Vec3::ONE,
        ks: 0.0,
        shine: 1.0,
        t: 0.0,
        ior: 1.0,
        emission: Vec3::ZERO,
        roughness: 0.0,
        ambient: Vec3::ZERO,
        texture: None,
    };
}

impl Material {
    /// The absorption coefficient per unit length inside a transmissive material,
    /// `1 - C` per channel (at least 0), if it absorbs at all: Beer-Lambert's
    /// `exp(-(1 - C) d)` over a distance `d` inside (P3F-SPEC).
    pub fn absorption(&self) -> Option<Vec3> {
        let sigma = (Vec3::ONE - self.color).max(Vec3::ZERO);
        (self.t > 0.0 && sigma != Vec3::ZERO).then_some(sigma)
    }
}

/// A light: a point (`l x y z [r g b]`, P3F `light punctual`) or a parallelogram
/// (P3F `al`, `light quad`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// The point light's position; an area light's corner.
    pub position: Vec3,
    /// Colour (intensity) if the file gives one; `None` means the SPD's default.
    pub color: Option<Vec3>,
    /// The area light's extent; `None` for a point light.
    pub area: Option<LightArea>,
}

/// The extent of an area light: the parallelogram with corners `position`, `v1` and
/// `v2` (P3F `light quad`'s three points): its points are
/// `position + u (v1 - position) + v (v2 - position)`, `u` and `v` in [0, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightArea {
    /// The corner at the end of the first edge from `position`.
    pub v1: Vec3,
    /// The corner at the end of the second edge from `position`.
    pub v2: Vec3,
    /// Points per side of the regular grid sampled with one eye sample per pixel.
    pub grid: u32,
}

impl Light {
    /// A point light.
    pub fn point(position: Vec3, color: Option<Vec3>) -> Light {
        Light {
            position,
            color,
            area: None,
        }
    }
}

/// Which language a scene was written in; it chooses the shading model (the NFF /
/// SPD rules or the P3F course's) and how the writer spells it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub enum Dialect {
    /// NFF, with nffrt's extensions.
    #[default]
    Nff,
    /// P3F as of the 2019/20 course (`v`, `f`, `l`, `al`).
    P3f2019,
    /// P3F as of the 2024/25 course (`camera`, `mat`, `light`, `spp`, `accel`).
    P3f2025,
    /// AFF, BART's animated NFF: a frame of it (docs/aff.md), shaded by its rules.
    Aff,
}

impl Dialect {
    /// True for either P3F dialect.
    pub fn is_p3f(self) -> bool {
        matches!(self, Dialect::P3f2019 | Dialect::P3f2025)
    }

    /// The one name of the dialect, wherever it is shown (`info`, `--stats`, the
    /// viewer, Python): `nff`, `p3f-2019` or `p3f-2025`.
    pub fn name(self) -> &'static str {
        match self {
            Dialect::Nff => "nff",
            Dialect::P3f2019 => "p3f-2019",
            Dialect::P3f2025 => "p3f-2025",
            Dialect::Aff => "aff",
        }
    }
}

/// What a view's `angle` spans, vertically (pixels are square).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AngleSpan {
    /// NFF: from the centre of the top pixel row to the centre of the bottom one.
    #[default]
    PixelCentres,
    /// P3F: from the top edge of the image to its bottom edge.
    ImageEdges,
}

/// The camera of the `v` block (NFF and P3F 2019) or the `camera` block (P3F 2025).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Eye position.
    pub from: Vec3,
    /// Point looked at.
    pub at: Vec3,
    /// Up direction (need not be perpendicular to the view direction).
    pub up: Vec3,
    /// Vertical field of view in degrees (see [`View::angle_span`]).
    pub angle: f32,
    /// Near distance for hidden-surface renderers; a ray tracer ignores it.
    pub hither: f32,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// What `angle` spans: pixel centres in NFF, image edges in P3F.
    pub angle_span: AngleSpan,
    /// Lens diameter in pixels of the view plane (P3F `aperture`); 0 is a pinhole.
    pub aperture: f32,
    /// Distance of the plane of sharp focus as a multiple of `|from - at|` (P3F `focal`).
    pub focal: f32,
}

impl Default for View {
    /// The camera used when a file has no `v` block: looking down -z from z = 10.
    fn default() -> Self {
        View {
            from: Vec3::new(0.0, 0.0, 10.0),
            at: Vec3::ZERO,
            up: Vec3::new(0.0, 1.0, 0.0),
            angle: 45.0,
            hither: 1.0,
            width: 512,
            height: 512,
            angle_span: AngleSpan::PixelCentres,
            aperture: 0.0,
            focal: 1.0,
        }
    }
}

/// A sphere (`s cx cy cz r`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre.
    pub center: Vec3,
    /// Radius as written: negative means only the inside is visible.
    pub radius: f32,
    /// Index into [`Scene::materials`].
    pub material: u32,
    /// Line of the `s` keyword in the source.
    pub line: u32,
}

/// A moving sphere (P3F `sm cx0 cy0 cz0  cx1 cy1 cz1  r  t0 t1`): its centre is
/// `center0` at `time0` and `center1` at `time1`, and moves in a straight line at
/// constant speed, before `time0` and after `time1` too (see
/// [`MovingSphere::center_at`]).
///
/// Invariant (the parser's): `time0 != time1`, and the velocity is finite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MovingSphere {
    /// Centre at `time0`.
    pub center0: Vec3,
    /// Centre at `time1`.
    pub center1: Vec3,
    /// Radius as written: negative means only the inside is visible (as `s`'s).
    pub radius: f32,
    /// The time of `center0`.
    pub time0: f32,
    /// The time of `center1`.
    pub time1: f32,
    /// Index into [`Scene::materials`].
    pub material: u32,
    /// Line of the `sm` keyword in the source.
    pub line: u32,
}

impl MovingSphere {
    /// The centre's displacement per unit of time, `(center1 - center0) / (time1 - time0)`.
    #[inline]
    pub fn velocity(&self) -> Vec3 {
        (self.center1 - self.center0) / (self.time1 - self.time0)
    }

    /// The centre at `time`: `center0 + (time - time0) * velocity` (linear in between
    /// the two times and beyond them; the render-time shape computes it the same way,
    /// `geometry::MovingSphereShape`).
    #[inline]
    pub fn center_at(&self, time: f32) -> Vec3 {
        self.center0 + self.velocity() * (time - self.time0)
    }
}

/// An open cone or cylinder (`c bx by bz br ax ay az ar`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone {
    /// Centre of the base disc.
    pub base: Vec3,
    /// Base radius as written (both radii negative: inside visible).
    pub base_radius: f32,
    /// Centre of the apex disc.
    pub apex: Vec3,
    /// Apex radius as written.
    pub apex_radius: f32,
    /// Index into [`Scene::materials`].
    pub material: u32,
    /// Line of the `c` keyword in the source.
    pub line: u32,
}

/// A planar polygon (`p n` then n vertices); its vertices are
/// `scene.polygon_vertices[first .. first + count]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polygon {
    /// Index of the first vertex in [`Scene::polygon_vertices`].
    pub first: u32,
    /// Number of vertices (at least 3).
    pub count: u32,
    /// Index into [`Scene::materials`].
    pub material: u32,
    /// Line of the `p` keyword in the source.
    pub line: u32,
}

/// A polygonal patch (`pp n` then n vertex-normal pairs); its vertices and normals
/// are `scene.patch_vertices[first .. first + count]` and the same range of
/// `scene.patch_normals`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Patch {
    /// Index of the first vertex in [`Scene::patch_vertices`] / [`Scene::patch_normals`].
    pub first: u32,
    /// Number of vertices (at least 3).
    pub count: u32,
    /// Index into [`Scene::materials`].
    pub material: u32,
    /// Line of the `pp` keyword in the source.
    pub line: u32,
}

/// An infinite plane through three points (`pl`, an extension).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// The three points as written; the normal follows their counter-clockwise order.
    pub points: [Vec3; 3],
    /// Index into [`Scene::materials`].
    pub material: u32,
    /// Line of the `pl` keyword in the source.
    pub line: u32,
}

/// A solid axis-aligned box (`aabb xmin xmax ymin ymax zmin zmax`, an extension).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxPrim {
    /// Lower corner.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
    /// Index into [`Scene::materials`].
    pub material: u32,
    /// Line of the `aabb` keyword in the source.
    pub line: u32,
}

/// A triangle mesh (P3F `mesh nv nt`); its vertices are
/// `scene.mesh_vertices[first_vertex .. first_vertex + vertex_count]` and its
/// triangles `scene.mesh_triangles[first_triangle .. first_triangle + triangle_count]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mesh {
    /// Index of its first vertex in [`Scene::mesh_vertices`].
    pub first_vertex: u32,
    /// Number of vertices.
    pub vertex_count: u32,
    /// Index of its first triangle in [`Scene::mesh_triangles`].
    pub first_triangle: u32,
    /// Number of triangles kept (degenerate ones are skipped).
    pub triangle_count: u32,
    /// Index into [`Scene::materials`].
    pub material: u32,
    /// Line of the `mesh` keyword in the source.
    pub line: u32,
}

/// One triangle of a [`Mesh`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshTriangle {
    /// Its corners, as indices into [`Scene::mesh_vertices`] (resolved from the
    /// file's 1-based or from-the-end indices).
    pub vertices: [u32; 3],
    /// Line of its first index in the source.
    pub line: u32,
}

/// The acceleration structure a render uses: what a P3F file asks for (`accel`),
/// `--accel`, [`crate::prepare::PrepareOptions::accel`]. All three give the same
/// pictures (see [`crate::accel::Aggregate`]); the BVH is the default.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Accel {
    /// `accel none`
    None,
    /// `accel grid`
    Grid,
    /// `accel bvh`
    #[default]
    Bvh,
}

/// A light transport, by name: what a P3F file asks for (`integrator`), what
/// `--integrator`, the viewer and Python choose (their choice wins over the
/// file's). Its names are written and read here alone ([`IntegratorKind::name`],
/// [`std::str::FromStr`]), and serde and every front end go through them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(into = "&'static str", try_from = "String")]
pub enum IntegratorKind {
    /// `whitted`: Whitted's recursive ray tracing (distribution ray tracing with
    /// more than one sample per pixel), the default.
    #[default]
    Whitted,
    /// `path`: path tracing.
    Path,
}

impl IntegratorKind {
    /// Every light transport, in the order help texts list them.
    pub const ALL: [IntegratorKind; 2] = [IntegratorKind::Whitted, IntegratorKind::Path];

    /// The light transport's name, as files, flags and messages spell it.
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::Whitted => "whitted",
            IntegratorKind::Path => "path",
        }
    }

    /// The names for a message: `'whitted' or 'path'`.
    pub fn choices() -> String {
        let names: Vec<String> = Self::ALL.iter().map(|k| format!("'{}'", k.name())).collect();
        names.join(" or ")
    }
}

impl std::fmt::Display for IntegratorKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for IntegratorKind {
    type Err = String;

    /// The light transport named `name` (exactly as [`IntegratorKind::name`] spells
    /// it), or a message naming the choices.
    fn from_str(name: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| format!("unknown integrator {name:?}: use {}", Self::choices()))
    }
}

impl TryFrom<String> for IntegratorKind {
    type Error = String;
    fn try_from(name: String) -> Result<Self, String> {
        name.parse()
    }
}

impl From<IntegratorKind> for &'static str {
    fn from(k: IntegratorKind) -> &'static str {
        k.name()
    }
}

/// A skybox named by the scene (P3F `env FOLDER`).
#[derive(Clone, Debug, PartialEq)]
pub struct Environment {
    /// The folder as written, relative to the scene file's directory.
    pub folder: String,
    /// Line of the `env` keyword.
    pub line: u32,
    /// Column of the folder's name.
    pub column: u32,
}

/// Something the parser tolerated, with where it was.
#[derive(Clone, Debug, PartialEq)]
pub struct Warning {
    /// 1-based line.
    pub line: u32,
    /// 1-based column.
    pub column: u32,
    /// What was tolerated and what was done about it.
    pub message: String,
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}: {}", self.line, self.column, self.message)
    }
}

/// A whole scene (NFF or P3F).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scene {
    /// The language it was written in.
    pub dialect: Dialect,
    /// The camera.
    pub view: View,
    /// Background colour (`b`, P3F `bclr`), seen where no skybox is.
    pub background: Vec3,
    /// The skybox, which replaces the background colour (its images are read by
    /// [`crate::load`], beside the scene).
    pub environment: Option<Environment>,
    /// Point lights in file order.
    pub lights: Vec<Light>,
    /// Material table; primitives refer to it by index.
    pub materials: Vec<Material>,
    /// Spheres.
    pub spheres: Vec<Sphere>,
    /// Moving spheres (P3F `sm`).
    pub moving_spheres: Vec<MovingSphere>,
    /// Cones and cylinders.
    pub cones: Vec<Cone>,
    /// Polygons.
    pub polygons: Vec<Polygon>,
    /// Vertices of all polygons.
    pub polygon_vertices: Vec<Vec3>,
    /// Patches.
    pub patches: Vec<Patch>,
    /// Vertices of all patches.
    pub patch_vertices: Vec<Vec3>,
    /// Vertex normals of all patches, parallel to `patch_vertices`.
    pub patch_normals: Vec<Vec3>,
    /// Texture coordinates `(u, v)` of all patches' vertices: empty, or parallel
    /// to `patch_vertices` (AFF's textured triangles; zeros for the others).
    pub patch_uvs: Vec<[f32; 2]>,
    /// The images that textured materials sample ([`Material::texture`]): AFF's,
    /// read with the scene and shared by every frame of it.
    pub textures: Vec<std::sync::Arc<crate::image::Texture>>,
    /// AFF's global ambient light (`am`); `None` elsewhere.
    pub ambient_light: Option<Vec3>,
    /// Infinite planes.
    pub planes: Vec<Plane>,
    /// Boxes.
    pub boxes: Vec<BoxPrim>,
    /// Triangle meshes.
    pub meshes: Vec<Mesh>,
    /// Vertices of all meshes.
    pub mesh_vertices: Vec<Vec3>,
    /// Triangles of all meshes.
    pub mesh_triangles: Vec<MeshTriangle>,
    /// Samples per pixel asked for by the file (P3F `spp`; 0 is one sample at the
    /// pixel centre), the default of `--spp`.
    pub spp: Option<u32>,
    /// The acceleration structure the file asks for (P3F `accel`).
    pub accel: Option<Accel>,
    /// The times the camera's shutter opens and closes, `[open, close]` with
    /// `open <= close` (P3F `shutter`); `None` when the file does not say, which
    /// means [`DEFAULT_SHUTTER`] (see [`Scene::shutter_interval`]).
    pub shutter: Option<[f32; 2]>,
    /// The integrator the file asks for (P3F `integrator`).
    pub integrator: Option<IntegratorKind>,
    /// What the parser tolerated.
    pub warnings: Vec<Warning>,
    /// Groups of primitives in their own space, each a scene of which only the
    /// primitives count, that [`Scene::instances`] place: built once, and shared by
    /// every frame of an animation.
    pub prototypes: Arc<Vec<Scene>>,
    /// Prototypes placed in the scene.
    pub instances: Vec<Instance>,
}

/// A prototype ([`Scene::prototypes`]) placed in a scene by an affine transform:
/// AFF's meshes, built once in their own space rather than copied per placement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instance {
    /// Index into [`Scene::prototypes`].
    pub prototype: u32,
    /// The transform into the scene: rows of the linear part with the translation as
    /// a fourth column.
    pub to_world: [[f64; 4]; 3],
    /// The material of the prototype's primitives.
    pub material: u32,
    /// Line of the entity it came from.
    pub line: u32,
}

/// What remains of a [`Scene`] once its primitives are in a render-time structure
/// ([`crate::prepare()`]): its settings, lights and materials as parsed, and a summary
/// of its primitives. `nffrt info`, `--stats`, the viewer and the Python bindings
/// report from it.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneInfo {
    /// The language it was written in.
    pub dialect: Dialect,
    /// The camera.
    pub view: View,
    /// Background colour.
    pub background: Vec3,
    /// The skybox it names.
    pub environment: Option<Environment>,
    /// Lights in file order.
    pub lights: Vec<Light>,
    /// The material table.
    pub materials: Vec<Material>,
    /// Samples per pixel asked for by the file (P3F `spp`).
    pub spp: Option<u32>,
    /// The acceleration structure the file asks for (P3F `accel`).
    pub accel: Option<Accel>,
    /// When the camera's shutter opens and closes ([`Scene::shutter_interval`]).
    pub shutter: [f32; 2],
    /// The integrator the file asks for (P3F `integrator`).
    pub integrator: Option<IntegratorKind>,
    /// AFF's global ambient light (`am`).
    pub ambient_light: Option<Vec3>,
    /// What the parser tolerated.
    pub warnings: Vec<Warning>,
    /// The number of primitives of each kind outside meshes ([`Scene::kind_counts`]).
    pub kind_counts: Vec<(&'static str, usize)>,
    /// Triangle meshes.
    pub meshes: usize,
    /// Triangles of all meshes.
    pub mesh_triangles: usize,
    /// All primitives ([`Scene::primitive_count`]).
    pub primitives: usize,
    /// Bounding box of the bounded primitives ([`Scene::bounds`]).
    pub bounds: Aabb,
}

impl SceneInfo {
    /// Counts `other`'s primitives in with this scene's (kinds, meshes, triangles,
    /// bounds): the summary of a frame built from two parts.
    pub fn include_counts(&mut self, other: &SceneInfo) {
        for (count, (name, more)) in self.kind_counts.iter_mut().zip(&other.kind_counts) {
            debug_assert_eq!(count.0, *name, "both summaries list the kinds in one order");
            count.1 += more;
        }
        self.meshes += other.meshes;
        self.mesh_triangles += other.mesh_triangles;
        self.primitives += other.primitives;
        self.bounds = self.bounds.union(other.bounds);
    }

    /// The number of area lights.
    pub fn area_lights(&self) -> usize {
        self.lights.iter().filter(|l| l.area.is_some()).count()
    }

    /// True if the scene has moving spheres.
    pub fn has_moving_spheres(&self) -> bool {
        self.kind_counts
            .iter()
            .any(|&(kind, n)| kind == "moving_spheres" && n > 0)
    }

    /// True if some material is rough.
    pub fn has_rough_materials(&self) -> bool {
        self.materials.iter().any(|m| m.roughness > 0.0)
    }
}

impl Scene {
    /// The vertices of one polygon.
    pub fn polygon_points(&self, p: &Polygon) -> &[Vec3] {
        &self.polygon_vertices[p.first as usize..(p.first + p.count) as usize]
    }

    /// The vertices and normals of one patch.
    pub fn patch_points(&self, p: &Patch) -> (&[Vec3], &[Vec3]) {
        let r = p.first as usize..(p.first + p.count) as usize;
        (&self.patch_vertices[r.clone()], &self.patch_normals[r])
    }

    /// The triangles of one mesh (their corners index [`Scene::mesh_vertices`]).
    pub fn mesh_triangles_of(&self, m: &Mesh) -> &[MeshTriangle] {
        &self.mesh_triangles[m.first_triangle as usize..(m.first_triangle + m.triangle_count) as usize]
    }

    /// The shutter interval `[open, close]`: the file's, else [`DEFAULT_SHUTTER`].
    pub fn shutter_interval(&self) -> [f32; 2] {
        self.shutter.unwrap_or(DEFAULT_SHUTTER)
    }

    /// The number of primitives of each kind outside meshes, named as `nffrt info`
    /// names them.
    pub fn kind_counts(&self) -> [(&'static str, usize); 8] {
        [
            ("spheres", self.spheres.len()),
            ("moving_spheres", self.moving_spheres.len()),
            ("polygons", self.polygons.len()),
            ("patches", self.patches.len()),
            ("cones", self.cones.len()),
            ("planes", self.planes.len()),
            ("boxes", self.boxes.len()),
            ("instances", self.instances.len()),
        ]
    }

    /// Number of primitives: bounded ones, planes and mesh triangles.
    pub fn primitive_count(&self) -> usize {
        self.kind_counts().iter().map(|&(_, n)| n).sum::<usize>() + self.mesh_triangles.len()
    }

    /// Appends the primitives, their vertices and the lights of `other`, a scene
    /// parsed from a later piece of the same file: each primitive's material index is
    /// mapped by `material`, and vertex and triangle ranges are shifted past this
    /// scene's. The camera, background, environment, materials, settings and
    /// warnings of `other` are the caller's to merge: the exhaustive destructuring
    /// below makes whoever adds a field to [`Scene`] decide how it joins.
    pub fn append(&mut self, other: Scene, material: &mut impl FnMut(u32) -> u32) {
        let Scene {
            dialect: _,
            view: _,
            background: _,
            environment: _,
            lights,
            materials: _,
            spheres,
            moving_spheres,
            cones,
            polygons,
            polygon_vertices,
            patches,
            patch_vertices,
            patch_normals,
            patch_uvs,
            textures: _,
            ambient_light: _,
            planes,
            boxes,
            meshes,
            mesh_vertices,
            mesh_triangles,
            spp: _,
            accel: _,
            shutter: _,
            integrator: _,
            warnings: _,
            prototypes: _,
            instances,
        } = other;
        let polygon_base = self.polygon_vertices.len() as u32;
        let patch_base = self.patch_vertices.len() as u32;
        let (vertex_base, triangle_base) =
            (self.mesh_vertices.len() as u32, self.mesh_triangles.len() as u32);
        let remap = |m: &mut u32, material: &mut dyn FnMut(u32) -> u32| *m = material(*m);
        self.spheres.extend(spheres.into_iter().map(|mut x| {
            remap(&mut x.material, material);
            x
        }));
        self.moving_spheres
            .extend(moving_spheres.into_iter().map(|mut x| {
                remap(&mut x.material, material);
                x
            }));
        self.cones.extend(cones.into_iter().map(|mut x| {
            remap(&mut x.material, material);
            x
        }));
        self.polygons.extend(polygons.into_iter().map(|mut x| {
            remap(&mut x.material, material);
            x.first += polygon_base;
            x
        }));
        self.patches.extend(patches.into_iter().map(|mut x| {
            remap(&mut x.material, material);
            x.first += patch_base;
            x
        }));
        self.planes.extend(planes.into_iter().map(|mut x| {
            remap(&mut x.material, material);
            x
        }));
        self.boxes.extend(boxes.into_iter().map(|mut x| {
            remap(&mut x.material, material);
            x
        }));
        self.meshes.extend(meshes.into_iter().map(|mut x| {
            remap(&mut x.material, material);
            x.first_vertex += vertex_base;
            x.first_triangle += triangle_base;
            x
        }));
        self.mesh_triangles
            .extend(mesh_triangles.into_iter().map(|mut t| {
                t.vertices = t.vertices.map(|i| i + vertex_base);
                t
            }));
        self.polygon_vertices.extend(polygon_vertices);
        // Texture coordinates stay empty or parallel to the vertices: zeros for the
        // side without them.
        if !(self.patch_uvs.is_empty() && patch_uvs.is_empty()) {
            self.patch_uvs.resize(self.patch_vertices.len(), [0.0; 2]);
            self.patch_uvs.extend(patch_uvs);
            self.patch_uvs
                .resize(self.patch_vertices.len() + patch_vertices.len(), [0.0; 2]);
        }
        self.patch_vertices.extend(patch_vertices);
        self.patch_normals.extend(patch_normals);
        self.mesh_vertices.extend(mesh_vertices);
        // Both pieces place the same prototypes (the caller's to see to).
        self.instances.extend(instances.into_iter().map(|mut x| {
            remap(&mut x.material, material);
            x
        }));
        self.lights.extend(lights);
    }

    /// The scene's [`SceneInfo`].
    pub fn info(&self) -> SceneInfo {
        SceneInfo {
            dialect: self.dialect,
            view: self.view,
            background: self.background,
            environment: self.environment.clone(),
            lights: self.lights.clone(),
            materials: self.materials.clone(),
            spp: self.spp,
            accel: self.accel,
            shutter: self.shutter_interval(),
            integrator: self.integrator,
            ambient_light: self.ambient_light,
            warnings: self.warnings.clone(),
            kind_counts: self.kind_counts().to_vec(),
            meshes: self.meshes.len(),
            mesh_triangles: self.mesh_triangles.len(),
            primitives: self.primitive_count(),
            bounds: self.bounds(),
        }
    }

    /// Bounding box of every bounded primitive (planes excluded), moving spheres over
    /// their motion while the shutter is open ([`Scene::shutter_interval`]); empty if
    /// none.
    pub fn bounds(&self) -> Aabb {
        let ball = |c: Vec3, radius: f32| {
            let r = Vec3::splat(radius.abs());
            Aabb::new(c - r, c + r)
        };
        let mut b = Aabb::EMPTY;
        for s in &self.spheres {
            b = b.union(ball(s.center, s.radius));
        }
        // The centre moves in a straight line: its extremes are at the shutter's ends.
        let [open, close] = self.shutter_interval();
        for s in &self.moving_spheres {
            b = b
                .union(ball(s.center_at(open), s.radius))
                .union(ball(s.center_at(close), s.radius));
        }
        for c in &self.cones {
            // The end discs' boxes (a cone lies between them), not their spheres':
            // a cone standing on z = 0 reaches no lower.
            let axis = (c.apex - c.base).normalize();
            b = b
                .union(Aabb::of_disc(c.base, axis, c.base_radius.abs()))
                .union(Aabb::of_disc(c.apex, axis, c.apex_radius.abs()));
        }
        for v in self.polygon_vertices.iter().chain(&self.patch_vertices) {
            b = b.grow(*v);
        }
        for t in &self.mesh_triangles {
            for &i in &t.vertices {
                b = b.grow(self.mesh_vertices[i as usize]);
            }
        }
        for x in &self.boxes {
            b = b.union(Aabb::new(x.min, x.max));
        }
        for x in &self.instances {
            b = b.union(self.prototypes[x.prototype as usize].bounds().placed(&x.to_world));
        }
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scene of `body` after a camera and a material.
    fn scene(body: &str) -> Scene {
        let view = "v from 0 -9 3 at 0 0 1 up 0 0 1 angle 40 hither 1 resolution 8 8\n";
        crate::nff::parse(&format!("{view}f 1 1 1 1 0 1 0 1\n{body}")).unwrap()
    }

    #[test]
    fn cone_bounds_hold_its_end_discs_and_no_more() {
        // Standing on z = 0, radius 0.7 at the base: its discs are flat in z.
        let b = scene("c -3.2 2.2 0 0.7 -3.2 2.2 2.2 0\n").bounds();
        assert_eq!(b.min.z, 0.0);
        assert_eq!(b.max.z, 2.2);
        assert!(
            (b.min.x - -3.9).abs() < 1e-6 && (b.max.x - -2.5).abs() < 1e-6,
            "{b:?}"
        );
        // A cylinder of radius 1 along (1, 1, 0)/√2 from the origin to (2, 2, 0):
        // each disc reaches 1/√2 in x and y, 1 in z.
        let b = scene("c 0 0 0 1 2 2 0 1\n").bounds();
        let k = 0.5f32.sqrt();
        let close = |a: Vec3, b: Vec3| (a - b).length() < 1e-5;
        assert!(close(b.min, Vec3::new(-k, -k, -1.0)), "{b:?}");
        assert!(close(b.max, Vec3::new(2.0 + k, 2.0 + k, 1.0)), "{b:?}");
    }

    #[test]
    fn integrator_names_are_read_and_written_in_one_place() {
        for (kind, name) in [
            (IntegratorKind::Whitted, "whitted"),
            (IntegratorKind::Path, "path"),
        ] {
            assert_eq!(kind.name(), name);
            assert_eq!(kind.to_string(), name);
            assert_eq!(name.parse::<IntegratorKind>(), Ok(kind));
            let json = serde_json::to_string(&kind).unwrap();
            assert_eq!(json, format!("\"{name}\""));
            assert_eq!(serde_json::from_str::<IntegratorKind>(&json).unwrap(), kind);
        }
        let e = "Path".parse::<IntegratorKind>().unwrap_err();
        assert_eq!(e, "unknown integrator \"Path\": use 'whitted' or 'path'");
        assert!(serde_json::from_str::<IntegratorKind>("\"bdpt\"").is_err());
        // An escaped name reads as its text.
        assert_eq!(
            serde_json::from_str::<IntegratorKind>("\"p\\u0061th\"").unwrap(),
            IntegratorKind::Path
        );
    }
}
