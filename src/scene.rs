//! The plain scene description that the parser fills and every later stage reads.
//!
//! Primitives are stored per kind in flat vectors; each keeps a `u32` index into the
//! material table and the file line it came from (for diagnostics and `--pixel`).
//! Polygon and patch vertices live in shared vectors that the primitives index into,
//! so a scene with millions of primitives makes no per-primitive heap allocation.
//! A generated scene ([`crate::gen`]) numbers its primitives with the lines they
//! occupy when [`crate::nff::write_nff`] writes it, which also fixes their order there.

use std::sync::Arc;

use crate::image::skybox::Skybox;
use crate::math::{Aabb, Vec3};

/// A surface material: the operands of NFF's `f` keyword, or of P3F's 11-number
/// `f` / `mat` with its specular colour.
#[derive(Clone, Copy, Debug, PartialEq)]
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
    };
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

/// The extent of an area light: the points `position + u edge1 + v edge2`, `u` and
/// `v` in [0, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightArea {
    /// First edge, from the corner.
    pub edge1: Vec3,
    /// Second edge, from the corner.
    pub edge2: Vec3,
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
}

impl Dialect {
    /// True for either P3F dialect.
    pub fn is_p3f(self) -> bool {
        self != Dialect::Nff
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

/// A skybox named by the scene (P3F `env FOLDER`).
#[derive(Clone, Debug, PartialEq)]
pub struct Environment {
    /// The folder as written, relative to the scene file's directory.
    pub folder: String,
    /// Line of the `env` keyword.
    pub line: u32,
    /// Column of the folder's name.
    pub column: u32,
    /// The six decoded faces, once the scene's files have been read
    /// ([`crate::load`]); `None` for a scene parsed from text alone.
    pub skybox: Option<Arc<Skybox>>,
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
    /// The skybox, which replaces the background colour once loaded.
    pub environment: Option<Environment>,
    /// Point lights in file order.
    pub lights: Vec<Light>,
    /// Material table; primitives refer to it by index.
    pub materials: Vec<Material>,
    /// Spheres.
    pub spheres: Vec<Sphere>,
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
    /// Infinite planes.
    pub planes: Vec<Plane>,
    /// Boxes.
    pub boxes: Vec<BoxPrim>,
    /// What the parser tolerated.
    pub warnings: Vec<Warning>,
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

    /// Number of bounded primitives plus planes.
    pub fn primitive_count(&self) -> usize {
        self.spheres.len()
            + self.cones.len()
            + self.polygons.len()
            + self.patches.len()
            + self.planes.len()
            + self.boxes.len()
    }

    /// Bounding box of every bounded primitive (planes excluded); empty if none.
    pub fn bounds(&self) -> Aabb {
        let mut b = Aabb::EMPTY;
        for s in &self.spheres {
            let r = Vec3::splat(s.radius.abs());
            b = b.union(Aabb::new(s.center - r, s.center + r));
        }
        for c in &self.cones {
            let rb = Vec3::splat(c.base_radius.abs());
            let ra = Vec3::splat(c.apex_radius.abs());
            b = b
                .union(Aabb::new(c.base - rb, c.base + rb))
                .union(Aabb::new(c.apex - ra, c.apex + ra));
        }
        for v in self.polygon_vertices.iter().chain(&self.patch_vertices) {
            b = b.grow(*v);
        }
        for x in &self.boxes {
            b = b.union(Aabb::new(x.min, x.max));
        }
        b
    }
}
