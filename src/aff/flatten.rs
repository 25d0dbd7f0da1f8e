//! A frame of an AFF scene as a plain [`Scene`] in world space, for the existing
//! pipeline: every shown object placed by its node's transform at the frame's time,
//! meshes with normals and animated triangles as triangular patches (normals by
//! the inverse transpose), meshes without as [`Scene::meshes`], polygons, patches,
//! spheres and cones as themselves (a sphere or cone only under a transform that
//! keeps it one: a similarity). A textured mesh's triangles become patches with
//! texture coordinates ([`Scene::patch_uvs`]; zero normals where the mesh has none,
//! which shade flat) under a copy of their material that names the texture
//! ([`Material::texture`]); the textures themselves are shared, not copied.

use super::error::AffError;
use super::instances::MeshMode;
use super::mesh::MeshGeometry;
use super::scene::{AffScene, Location, NodeTransform, Object, Shape};
use super::transform::Affine;
use crate::math::Vec3;
use crate::nff::{is_degenerate, ParseError, ParseErrorKind};
use crate::scene::{
    Cone, Dialect, Instance, Material, Mesh, MeshTriangle, Patch, Polygon, Scene, Sphere, View, Warning,
};

/// Which of a frame's objects [`AffScene::flatten_part`] places.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FramePart {
    /// Every object shown at the time.
    All,
    /// The objects that never move: those under no keyframed transform (always
    /// shown, and the same at every time).
    Fixed,
    /// The rest: objects under a keyframed transform, and the animated triangles.
    Moving,
}

impl AffScene {
    /// The scene at time `t` (see [`AffScene::time_of_frame`]) in world space. An
    /// error, at the object or the camera block concerned, for a transform that
    /// overflows, a sphere or cone under a non-uniform scale, or a camera left
    /// without a direction.
    pub fn flatten(&self, t: f64) -> Result<Scene, AffError> {
        self.flatten_part(t, FramePart::All, MeshMode::Copied)
    }

    /// [`AffScene::flatten`] keeping only the objects of `part`, its meshes placed as
    /// `meshes` says; the camera, lights and materials are the frame's whatever the
    /// part, and the material table is the same for every part and time (a textured
    /// mesh's material copy has one index), so that a frame's fixed and moving parts
    /// can be built apart. Instances place the same prototypes
    /// ([`Scene::prototypes`], shared) in every frame.
    pub fn flatten_part(&self, t: f64, part: FramePart, meshes: MeshMode) -> Result<Scene, AffError> {
        let world = self.node_transforms(t);
        let shown = self.node_visibility(t);
        let mut out = Scene {
            dialect: Dialect::Aff,
            view: self.checked_camera(t)?,
            background: self.nff.background,
            materials: self.nff.materials.clone(),
            textures: self.textures.iter().map(|t| t.image.clone()).collect(),
            ambient_light: Some(self.ambient),
            warnings: self.plain_warnings(),
            ..Scene::default()
        };
        let textured = self.textured_materials(&mut out.materials);
        let moving = self.moving_nodes();
        let wanted = |node: usize| match part {
            FramePart::All => true,
            FramePart::Fixed => !moving[node],
            FramePart::Moving => moving[node],
        };
        for (i, light) in self.nff.lights.iter().enumerate() {
            let mut light = *light;
            light.position = self.light_position_at(i, t, &world);
            out.lights.push(light);
        }
        let prototypes = match meshes {
            MeshMode::Instanced => {
                let p = self.prototypes();
                out.prototypes = p.scenes.clone();
                Some(&p.of_object)
            }
            MeshMode::Copied => None,
        };
        for (i, object) in self.objects.iter().enumerate() {
            let node = object.node as usize;
            if !(shown[node] && wanted(node)) {
                continue;
            }
            match (prototypes.and_then(|p| p[i]), object.shape) {
                (Some(prototype), Shape::Mesh(g)) => {
                    let g = &self.meshes.geometries[g as usize];
                    let material = self.mesh_material(g, object.material, &textured);
                    self.place_instance(object, prototype, material, &world[node], &mut out)?
                }
                _ => self.place(object, &world[node], &textured, &mut out)?,
            }
        }
        for tri in &self.animated_triangles {
            let node = tri.node as usize;
            if !shown[node] || part == FramePart::Fixed {
                continue;
            }
            let (vertices, normals) = tri.at(t);
            let m = &world[node];
            let before = lengths(&out);
            let corners = Corners {
                points: vertices.map(|p| m.point(p)),
                normals: normals.map(|n| m.normal(n)),
                uvs: [[0.0; 2]; 3],
            };
            push_patch(&mut out, corners, tri.material, tri.at.line);
            self.check_finite(&out, before, tri.at)?;
        }
        Ok(out)
    }

    /// Which nodes move: those under a keyframed transform (theirs or an
    /// ancestor's), in node order.
    pub fn moving_nodes(&self) -> Vec<bool> {
        let mut moving: Vec<bool> = Vec::with_capacity(self.nodes.len());
        for node in &self.nodes {
            let own = matches!(node.transform, NodeTransform::Animated { .. });
            moving.push(own || node.parent.is_some_and(|p| moving[p as usize]));
        }
        moving
    }

    /// The textured copies of materials every textured mesh needs, added to
    /// `materials` in the order of the objects that first need them.
    pub(super) fn textured_materials(&self, materials: &mut Vec<Material>) -> TexturedMaterials {
        let mut textured = TexturedMaterials::default();
        for object in &self.objects {
            if let Shape::Mesh(g) = object.shape {
                let g = &self.meshes.geometries[g as usize];
                if let (Some(texture), true) = (g.texture, g.uvs.count > 0) {
                    textured.add(object.material, texture, materials);
                }
            }
        }
        textured
    }

    /// Adds `object` under `m` to `out` (a textured mesh under its material's
    /// textured copy in `textured`).
    fn place(
        &self,
        object: &Object,
        m: &Affine,
        textured: &TexturedMaterials,
        out: &mut Scene,
    ) -> Result<(), AffError> {
        let (mut material, line) = (object.material, object.at.line);
        let before = lengths(out);
        match object.shape {
            Shape::Mesh(g) => {
                let g = &self.meshes.geometries[g as usize];
                material = self.mesh_material(g, material, textured);
                self.place_mesh(g, m, material, line, out)
            }
            Shape::Polygon(i) => {
                let p = &self.nff.polygons[i as usize];
                let points: Vec<Vec3> = self.nff.polygon_points(p).iter().map(|&v| m.point(v)).collect();
                if has_area(&points) {
                    out.polygons.push(Polygon {
                        first: out.polygon_vertices.len() as u32,
                        ..*p
                    });
                    out.polygon_vertices.extend(points);
                }
            }
            Shape::Patch(i) => {
                let p = &self.nff.patches[i as usize];
                let (points, normals) = self.nff.patch_points(p);
                let points: Vec<Vec3> = points.iter().map(|&v| m.point(v)).collect();
                if has_area(&points) {
                    out.patches.push(Patch {
                        first: out.patch_vertices.len() as u32,
                        ..*p
                    });
                    if !out.textures.is_empty() {
                        out.patch_uvs.resize(out.patch_uvs.len() + points.len(), [0.0; 2]);
                    }
                    out.patch_vertices.extend(points);
                    out.patch_normals.extend(normals.iter().map(|&n| m.normal(n)));
                }
            }
            Shape::Sphere(i) => {
                let s = self.nff.spheres[i as usize];
                let k = self.similarity(m, object.at, "sphere")?;
                let radius = s.radius * k;
                if radius != 0.0 {
                    out.spheres.push(Sphere {
                        center: m.point(s.center),
                        radius,
                        ..s
                    });
                }
            }
            Shape::Cone(i) => {
                let c = self.nff.cones[i as usize];
                let k = self.similarity(m, object.at, "cone")?;
                let (base, apex) = (m.point(c.base), m.point(c.apex));
                if base != apex && (c.base_radius != 0.0 || c.apex_radius != 0.0) {
                    out.cones.push(Cone {
                        base,
                        apex,
                        base_radius: c.base_radius * k,
                        apex_radius: c.apex_radius * k,
                        ..c
                    });
                }
            }
        }
        self.check_finite(out, before, object.at)
    }

    /// Adds `object`, a mesh, as an instance of `prototype` under `material`, placed
    /// by `m`: refused, as a copy would be, where `m` takes it past f32's range.
    fn place_instance(
        &self,
        object: &Object,
        prototype: u32,
        material: u32,
        m: &Affine,
        out: &mut Scene,
    ) -> Result<(), AffError> {
        let placed = out.prototypes[prototype as usize].bounds().placed(&m.rows);
        if !(m.is_finite() && placed.min.is_finite() && placed.max.is_finite()) {
            return Err(self.error(
                object.at,
                "its transforms take it past the range of numbers (f32)".into(),
            ));
        }
        out.instances.push(Instance {
            prototype,
            to_world: m.rows,
            material,
            line: object.at.line,
        });
        Ok(())
    }

    /// The material a mesh's triangles take: `material`, or its textured copy in
    /// `textured` for a textured mesh.
    pub(super) fn mesh_material(&self, g: &MeshGeometry, material: u32, textured: &TexturedMaterials) -> u32 {
        match (g.texture, g.uvs.count > 0) {
            (Some(texture), true) => textured.of(material, texture),
            _ => material,
        }
    }

    /// Adds one mesh's triangles under `m`: as patches if it has normals or is
    /// textured (with its texture coordinates), else as a mesh. Triangles left
    /// without area (under a zero scale) are left out.
    pub(super) fn place_mesh(&self, g: &MeshGeometry, m: &Affine, material: u32, line: u32, out: &mut Scene) {
        let pool = &self.meshes;
        let points: Vec<Vec3> = pool.positions[g.positions.range()]
            .iter()
            .map(|&p| m.point(p))
            .collect();
        let triangles = &pool.triangles[g.triangles.range()];
        let textured = g.texture.is_some() && g.uvs.count > 0;
        if g.normals.count > 0 || textured {
            let normals: Vec<Vec3> = pool.normals[g.normals.range()]
                .iter()
                .map(|&n| m.normal(n))
                .collect();
            let uvs = &pool.uvs[g.uvs.range()];
            for t in triangles {
                let corners = Corners {
                    points: t.vertices.map(|i| points[i as usize]),
                    // No normals: zero ones, which the triangle shades flat.
                    normals: match g.normals.count {
                        0 => [Vec3::ZERO; 3],
                        _ => t.normals.map(|i| normals[i as usize]),
                    },
                    uvs: match textured {
                        true => t.uvs.map(|i| uvs[i as usize]),
                        false => [[0.0; 2]; 3],
                    },
                };
                push_patch(out, corners, material, line);
            }
            return;
        }
        let first_vertex = out.mesh_vertices.len() as u32;
        let first_triangle = out.mesh_triangles.len() as u32;
        for t in triangles {
            if has_area(&t.vertices.map(|i| points[i as usize])) {
                out.mesh_triangles.push(MeshTriangle {
                    vertices: t.vertices.map(|i| first_vertex + i),
                    line,
                });
            }
        }
        let triangle_count = out.mesh_triangles.len() as u32 - first_triangle;
        if triangle_count > 0 {
            out.mesh_vertices.extend(points);
            out.meshes.push(Mesh {
                first_vertex,
                vertex_count: out.mesh_vertices.len() as u32 - first_vertex,
                first_triangle,
                triangle_count,
                material,
                line,
            });
        }
    }

    /// The uniform scale of `m`, which a sphere or cone at `at` needs.
    fn similarity(&self, m: &Affine, at: Location, what: &str) -> Result<f32, AffError> {
        m.uniform_scale().map(|k| k as f32).ok_or_else(|| {
            let message =
                format!("a {what} under a non-uniform scale or a shear (it would not stay a {what})");
            self.error(at, message)
        })
    }

    /// Refuses a frame whose object at `at`, placed after `before` ([`lengths`]),
    /// came out with a coordinate past f32's range.
    fn check_finite(&self, out: &Scene, before: [usize; 6], at: Location) -> Result<(), AffError> {
        let all = |v: &[Vec3], from: usize| v[from..].iter().all(|p| p.is_finite());
        let finite = all(&out.polygon_vertices, before[0])
            && all(&out.patch_vertices, before[1])
            && all(&out.patch_normals, before[2])
            && all(&out.mesh_vertices, before[3])
            && out.spheres[before[4]..]
                .iter()
                .all(|s| s.center.is_finite() && s.radius.is_finite())
            && out.cones[before[5]..].iter().all(|c| {
                c.base.is_finite()
                    && c.apex.is_finite()
                    && c.base_radius.is_finite()
                    && c.apex_radius.is_finite()
            });
        if finite {
            Ok(())
        } else {
            Err(self.error(
                at,
                "its transforms take it past the range of numbers (f32)".into(),
            ))
        }
    }

    /// The camera at `t`, refused if its direction or up vector is unusable.
    fn checked_camera(&self, t: f64) -> Result<View, AffError> {
        let view = self.camera_at(t);
        let dir = view.at - view.from;
        let usable = dir.length_squared() > 0.0
            && dir.length_squared().is_finite()
            && view.up.is_finite()
            && dir.normalize().cross(view.up.normalize()).length_squared() > 1e-12;
        if usable {
            return Ok(view);
        }
        let at = self
            .camera_track
            .map_or(Location::default(), |i| self.tracks[i as usize].at);
        Err(self.error(
            at,
            format!("at time {t} the camera has no usable direction and up vector"),
        ))
    }

    /// The scene's warnings as a plain scene keeps them: those of included files
    /// name their file.
    fn plain_warnings(&self) -> Vec<Warning> {
        let mut warnings: Vec<Warning> = self
            .warnings
            .iter()
            .map(|w| Warning {
                line: w.at.line,
                column: w.at.column,
                message: match w.at.file {
                    0 => w.message.clone(),
                    f => format!("(in {}) {}", self.file_name(f), w.message),
                },
            })
            .collect();
        warnings.truncate(crate::limits::MAX_WARNINGS);
        warnings
    }

    /// An error at `at`.
    pub(super) fn error(&self, at: Location, message: String) -> AffError {
        AffError {
            file: self.file_name(at.file).to_string(),
            error: ParseError::new(at.line, at.column, ParseErrorKind::Invalid(message)),
        }
    }
}

/// The lengths of what [`AffScene::check_finite`] checks: polygon vertices, patch
/// vertices and normals, mesh vertices, spheres, cones.
fn lengths(s: &Scene) -> [usize; 6] {
    [
        s.polygon_vertices.len(),
        s.patch_vertices.len(),
        s.patch_normals.len(),
        s.mesh_vertices.len(),
        s.spheres.len(),
        s.cones.len(),
    ]
}

/// A triangle's corners: points, normals and texture coordinates.
struct Corners {
    points: [Vec3; 3],
    normals: [Vec3; 3],
    uvs: [[f32; 2]; 3],
}

/// Adds a triangular patch unless it has no area; its texture coordinates too if
/// the scene has textures (then every patch has them).
fn push_patch(out: &mut Scene, corners: Corners, material: u32, line: u32) {
    if !has_area(&corners.points) {
        return;
    }
    out.patches.push(Patch {
        first: out.patch_vertices.len() as u32,
        count: 3,
        material,
        line,
    });
    out.patch_vertices.extend(corners.points);
    out.patch_normals.extend(corners.normals);
    if !out.textures.is_empty() {
        out.patch_uvs.extend(corners.uvs);
    }
}

/// The textured copies of materials: `(material, texture)` to the copy's index.
#[derive(Default)]
pub(super) struct TexturedMaterials(std::collections::HashMap<(u32, u32), u32>);

impl TexturedMaterials {
    /// Adds a copy of `material` textured with `texture` to `materials`, unless
    /// there is one.
    fn add(&mut self, material: u32, texture: u32, materials: &mut Vec<Material>) {
        self.0.entry((material, texture)).or_insert_with(|| {
            materials.push(Material {
                texture: Some(texture),
                ..materials[material as usize]
            });
            (materials.len() - 1) as u32
        });
    }

    /// The index of `material` textured with `texture` (made by
    /// [`TexturedMaterials::add`]).
    fn of(&self, material: u32, texture: u32) -> u32 {
        self.0[&(material, texture)]
    }
}

/// True unless the points lie (nearly) on a line or at one point: NFF's test of a
/// polygon worth keeping.
fn has_area(points: &[Vec3]) -> bool {
    !is_degenerate(points)
}
