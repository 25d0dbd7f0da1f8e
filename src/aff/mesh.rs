//! Triangle meshes (`m`) and textured triangles (`tt`, `ttp`, each a mesh of one
//! triangle, as the original stores them): geometry stored once in shared pools,
//! every index checked against the list it indexes. A file included again gives the
//! same geometry at the same place, which is kept once ([`super::parser::Builder::mesh_at`]).

use super::error::Read;
use super::parser::{invalid, loc, FileParser, Loc};
use super::scene::{Location, Shape};
use crate::math::Vec3;
use crate::nff::{ParseError, Token};

/// A run of a pool: `first .. first + count`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Span {
    /// The first element.
    pub first: u32,
    /// How many.
    pub count: u32,
}

impl Span {
    /// The span as a range of indices.
    pub fn range(self) -> std::ops::Range<usize> {
        self.first as usize..(self.first + self.count) as usize
    }
}

/// One triangle of a mesh: indices into its own vertices, normals and texture
/// coordinates (0-based, as written; the last two only if the mesh has them).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MeshTriangle {
    /// Its corners.
    pub vertices: [u32; 3],
    /// Their normals.
    pub normals: [u32; 3],
    /// Their texture coordinates.
    pub uvs: [u32; 3],
}

/// One mesh's geometry, in the local space of the nodes that use it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshGeometry {
    /// Its vertices in [`Meshes::positions`].
    pub positions: Span,
    /// Its normals in [`Meshes::normals`] (none: flat).
    pub normals: Span,
    /// Its texture coordinates in [`Meshes::uvs`] (none: untextured).
    pub uvs: Span,
    /// Its triangles in [`Meshes::triangles`].
    pub triangles: Span,
    /// Index into the scene's textures, if textured.
    pub texture: Option<u32>,
    /// Where its keyword stands (the first time it was read).
    pub at: Location,
}

/// Every mesh's geometry.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Meshes {
    /// The meshes.
    pub geometries: Vec<MeshGeometry>,
    /// Vertices of all meshes.
    pub positions: Vec<Vec3>,
    /// Normals of all meshes.
    pub normals: Vec<Vec3>,
    /// Texture coordinates of all meshes.
    pub uvs: Vec<[f32; 2]>,
    /// Triangles of all meshes.
    pub triangles: Vec<MeshTriangle>,
}

impl Meshes {
    /// The lengths of the pools, to go back to.
    fn mark(&self) -> [usize; 4] {
        [
            self.positions.len(),
            self.normals.len(),
            self.uvs.len(),
            self.triangles.len(),
        ]
    }

    /// Drops what was added since `mark`.
    fn truncate(&mut self, mark: [usize; 4]) {
        self.positions.truncate(mark[0]);
        self.normals.truncate(mark[1]);
        self.uvs.truncate(mark[2]);
        self.triangles.truncate(mark[3]);
    }

    /// The span of the elements added to a pool since it held `from`.
    fn span_from(from: usize, len: usize) -> Span {
        Span {
            first: from as u32,
            count: (len - from) as u32,
        }
    }
}

impl FileParser<'_, '_, '_> {
    /// ```text
    /// m
    ///   vertices N        x y z ... (N times)
    ///   [normals N        x y z ... (N times)]
    ///   [texturecoords N TEXTURE.ppm   u v ... (N times)]
    ///   triangles N       v0 v1 v2 [n0 n1 n2] [t0 t1 t2] ... (N times)
    /// ```
    /// Indices count from 0; a triangle gives normal indices if the mesh has
    /// normals, then texture coordinate indices if it has texture coordinates.
    pub(super) fn mesh(&mut self, kw: &Token) -> Read {
        let mark = self.b.scene.meshes.mark();
        let positions = self.vectors(b"vertices", true, kw)?;
        let normals = self.vectors(b"normals", false, kw)?;
        let (uvs, texture) = self.texture_coordinates()?;
        match self.p.next_token() {
            Some(t) if t.text == b"triangles" => {}
            tok => {
                return Err(self
                    .p
                    .expected(tok, "'triangles' and the mesh's triangles")
                    .into())
            }
        }
        let (n, _) = self.p.count("the number of triangles")?;
        let from = self.b.scene.meshes.triangles.len();
        for _ in 0..n {
            let vertices = self.indices(positions.count, &VERTEX)?;
            let normals = match normals.count {
                0 => [0; 3],
                n => self.indices(n, &NORMAL)?,
            };
            let uvs = match uvs.count {
                0 => [0; 3],
                n => self.indices(n, &TEXTURE_COORDINATE)?,
            };
            self.admit_triangles(kw)?;
            self.b.scene.meshes.triangles.push(MeshTriangle {
                vertices,
                normals,
                uvs,
            });
        }
        let triangles = Meshes::span_from(from, self.b.scene.meshes.triangles.len());
        self.store_mesh(kw, mark, [positions, normals, uvs, triangles], texture)
    }

    /// `tt TEXTURE.ppm  x y z u v  x y z u v  x y z u v`, and with `ttp` a normal
    /// after each vertex: `x y z nx ny nz u v`.
    pub(super) fn textured_triangle(&mut self, kw: &Token, with_normals: bool) -> Read {
        let mark = self.b.scene.meshes.mark();
        let (name, name_at) = self.name("the triangle's texture file")?;
        let texture = self.texture(&name, name_at)?;
        let meshes = &mut self.b.scene.meshes;
        let start = [meshes.positions.len(), meshes.normals.len(), meshes.uvs.len()];
        for _ in 0..3 {
            let p = self.p.vec3("textured triangle vertex x y z")?;
            self.b.scene.meshes.positions.push(p);
            if with_normals {
                let n = self.p.vec3("textured triangle normal x y z")?;
                self.b.scene.meshes.normals.push(n);
            }
            let u = self.p.number("texture coordinate u")?;
            let v = self.p.number("texture coordinate v")?;
            self.b.scene.meshes.uvs.push([u, v]);
        }
        self.admit_triangles(kw)?;
        let meshes = &mut self.b.scene.meshes;
        let triangles = meshes.triangles.len();
        meshes.triangles.push(MeshTriangle {
            vertices: [0, 1, 2],
            normals: [0, 1, 2],
            uvs: [0, 1, 2],
        });
        let spans = [
            Meshes::span_from(start[0], meshes.positions.len()),
            Meshes::span_from(start[1], meshes.normals.len()),
            Meshes::span_from(start[2], meshes.uvs.len()),
            Meshes::span_from(triangles, meshes.triangles.len()),
        ];
        self.store_mesh(kw, mark, spans, Some(texture))
    }

    /// Keeps the geometry read since `mark` as a mesh, unless this place was read
    /// before (then that mesh), and makes it an object of the innermost node.
    fn store_mesh(&mut self, kw: &Token, mark: [usize; 4], spans: [Span; 4], texture: Option<u32>) -> Read {
        let key = (self.file, kw.line, kw.column);
        let at = self.at(kw);
        let meshes = &mut self.b.scene.meshes;
        let id = match self.b.mesh_at.get(&key) {
            Some(&id) => {
                meshes.truncate(mark);
                id
            }
            None => {
                let [positions, normals, uvs, triangles] = spans;
                meshes.geometries.push(MeshGeometry {
                    positions,
                    normals,
                    uvs,
                    triangles,
                    texture,
                    at,
                });
                let id = (meshes.geometries.len() - 1) as u32;
                self.b.mesh_at.insert(key, id);
                id
            }
        };
        self.place_triangles(
            kw,
            self.b.scene.meshes.geometries[id as usize].triangles.count as usize,
        )?;
        let material = self.p.current_material(loc(kw));
        self.add_object(Shape::Mesh(id), material, kw);
        Ok(())
    }

    /// `SECTION N` then `N` times `x y z` into the vertex or normal pool; an
    /// optional section that is absent gives an empty span.
    fn vectors(&mut self, section: &[u8], required: bool, kw: &Token) -> Result<Span, ParseError> {
        match self.p.peek() {
            Some(t) if t.text == section => {
                self.p.next_token();
            }
            tok if required => {
                let what = format!("'{}' and the mesh's vertices", String::from_utf8_lossy(section));
                return Err(self.p.expected(tok, &what));
            }
            _ => return Ok(Span::default()),
        }
        let normals = section == b"normals";
        let what = if normals {
            "mesh normal x y z"
        } else {
            "mesh vertex x y z"
        };
        let (n, _) = self.p.count(if normals {
            "the number of normals"
        } else {
            "the number of vertices"
        })?;
        let pool_len = |b: &super::parser::Builder| {
            let m = &b.scene.meshes;
            if normals {
                m.normals.len()
            } else {
                m.positions.len()
            }
        };
        let from = pool_len(self.b);
        for _ in 0..n {
            let v = self.p.vec3(what)?;
            let meshes = &mut self.b.scene.meshes;
            if normals {
                meshes.normals.push(v);
            } else {
                self.admit_vertex(kw)?;
                self.b.scene.meshes.positions.push(v);
            }
        }
        Ok(Meshes::span_from(from, pool_len(self.b)))
    }

    /// `[texturecoords N TEXTURE.ppm  u v ... (N times)]`: the span of the
    /// coordinates and the texture (none if the section is absent).
    fn texture_coordinates(&mut self) -> Result<(Span, Option<u32>), ParseError> {
        match self.p.peek() {
            Some(t) if t.text == b"texturecoords" => {
                self.p.next_token();
            }
            _ => return Ok((Span::default(), None)),
        }
        let (n, _) = self.p.count("the number of texture coordinates")?;
        let (name, name_at) = self.name("the mesh's texture file")?;
        let texture = self.texture(&name, name_at)?;
        let from = self.b.scene.meshes.uvs.len();
        for _ in 0..n {
            let u = self.p.number("texture coordinate u")?;
            let v = self.p.number("texture coordinate v")?;
            self.b.scene.meshes.uvs.push([u, v]);
        }
        Ok((
            Meshes::span_from(from, self.b.scene.meshes.uvs.len()),
            Some(texture),
        ))
    }

    /// Three indices, each below `count`, into the mesh's list of `what`.
    fn indices(&mut self, count: u32, what: &Indexed) -> Result<[u32; 3], ParseError> {
        let mut out = [0; 3];
        for slot in &mut out {
            let (i, at) = self.p.count(what.index)?;
            if i >= count {
                return Err(past_the_list(at, what, i, count));
            }
            *slot = i;
        }
        Ok(out)
    }

    /// Refuses a triangle (of a mesh, or animated) past the scene's primitive limit.
    pub(super) fn admit_triangles(&self, kw: &Token) -> Result<(), ParseError> {
        let s = &self.b.scene;
        let triangles = s.meshes.triangles.len() + s.animated_triangles.len();
        self.within_primitives(triangles + 1, kw)
    }

    /// Counts `n` triangles placed by a mesh object, refusing them past the scene's
    /// primitive limit: it bounds a flattened frame, where a mesh stored once may
    /// be placed many times.
    fn place_triangles(&mut self, kw: &Token, n: usize) -> Result<(), ParseError> {
        let placed = self.b.placed_triangles + n;
        self.within_primitives(placed + self.b.scene.animated_triangles.len(), kw)?;
        self.b.placed_triangles = placed;
        Ok(())
    }

    /// Refuses `triangles` and NFF's primitives past the scene's primitive limit.
    pub(super) fn within_primitives(&self, triangles: usize, kw: &Token) -> Result<(), ParseError> {
        let max = self.b.limits.max_primitives;
        if triangles + self.p.scene().primitive_count() > max {
            return Err(invalid(
                loc(kw),
                format!("more than {max} primitives (the limit; nffrt's --max-primitives raises it)"),
            ));
        }
        Ok(())
    }

    /// Refuses a vertex past the scene's vertex limit.
    fn admit_vertex(&self, kw: &Token) -> Result<(), ParseError> {
        let max = self.b.limits.max_vertices;
        let s = self.p.scene();
        let nff = s.polygon_vertices.len() + s.patch_vertices.len();
        if self.b.scene.meshes.positions.len() + nff >= max {
            return Err(invalid(
                loc(kw),
                format!("more than {max} vertices (the limit; nffrt's --max-vertices raises it)"),
            ));
        }
        Ok(())
    }
}

/// What a triangle's indices index, named for messages (written once: a mesh's
/// triangles read millions of indices).
struct Indexed {
    /// The index, as the parser's message names it.
    index: &'static str,
    /// One of them.
    one: &'static str,
    /// More.
    many: &'static str,
}

const VERTEX: Indexed = Indexed {
    index: "a vertex index",
    one: "vertex",
    many: "vertices",
};

const NORMAL: Indexed = Indexed {
    index: "a normal index",
    one: "normal",
    many: "normals",
};

const TEXTURE_COORDINATE: Indexed = Indexed {
    index: "a texture coordinate index",
    one: "texture coordinate",
    many: "texture coordinates",
};

/// The error for index `i` of a list of `count` of `what`.
fn past_the_list(at: Loc, what: &Indexed, i: u32, count: u32) -> ParseError {
    let (one, many) = (what.one, what.many);
    let message = match count.checked_sub(1) {
        None => format!("{one} index {i}, but the mesh has no {many}"),
        Some(last) => format!("{one} index {i} is past the mesh's {count} {many} (0 to {last})"),
    };
    invalid(at, message)
}
