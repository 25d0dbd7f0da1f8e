//! The keywords only P3F has (P3F-SPEC), one function per keyword; each quotes its
//! syntax. The keywords P3F shares with NFF are read in `entities.rs`.

use super::error::ParseError;
use super::lexer::Token;
use super::parser::{invalid, loc, parse_f32, Loc, Parser};
use crate::math::Vec3;
use crate::scene::{
    Accel, BoxPrim, Environment, IntegratorKind, Light, LightArea, Mesh, MeshTriangle, MovingSphere, Plane,
};

use crate::limits::{AREA_LIGHT_GRID, MAX_SPP};

/// The word that introduces a material's roughness (`mat ... roughness R`).
pub(super) const ROUGHNESS: &str = "roughness";

impl Parser<'_> {
    /// `env FOLDER`: a skybox, the six images `right left top bottom front back`
    /// (`.jpg`) in FOLDER, relative to the scene file.
    pub(super) fn environment(&mut self, kw: &Token) -> Result<(), ParseError> {
        let Some(t) = self.lexer.next() else {
            return Err(self.expected(None, "a skybox folder after 'env'"));
        };
        if self.scene.environment.is_some() {
            self.warn(loc(kw), "a second 'env' replaces the first".into());
        }
        self.scene.environment = Some(Environment {
            folder: String::from_utf8_lossy(t.text).into_owned(),
            line: t.line,
            column: t.column,
        });
        Ok(())
    }

    /// `al x y z  ax ay az  w h  [r g b]`: a `w` by `h` rectangular light centred at
    /// the position, facing the point `a`. Its `w` side runs along the horizontal
    /// direction perpendicular to the facing direction (the axis among x, y, z least
    /// aligned with it, crossed with it), its `h` side perpendicular to both.
    pub(super) fn area_light(&mut self, kw: &Token) -> Result<(), ParseError> {
        self.admit_light(kw)?;
        let centre = self.vec3("area light centre x y z")?;
        let facing = self.vec3("area light target x y z")?;
        let size_at = self.next_loc(kw);
        let w = self.number("area light width")?;
        let h = self.number("area light height")?;
        let color = self.optional_color("area light colour r g b")?;
        if !(w > 0.0 && h > 0.0) {
            return Err(invalid(
                size_at,
                format!("area light of size {w} x {h}: both must be positive"),
            ));
        }
        let normal = facing - centre;
        if normal.length_squared() == 0.0 || !normal.length_squared().is_finite() {
            return Err(invalid(
                loc(kw),
                "area light facing its own centre (or too far to normalize)",
            ));
        }
        let normal = normal.normalize();
        let axis = [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ][normal.abs().min_axis()];
        let u = axis.cross(normal).normalize();
        let v = normal.cross(u);
        let (edge1, edge2) = (u * w, v * h);
        let corner = centre - edge1 * 0.5 - edge2 * 0.5;
        let (v1, v2) = (corner + edge1, corner + edge2);
        // A size too small for the centre's magnitude rounds the corners onto a line
        // (a width of 1e-16 at x = -3): refused as `light quad` refuses it.
        if !is_parallelogram(corner, v1, v2) {
            return Err(invalid(
                size_at,
                format!("area light of size {w} x {h} has no area at its position (its corners round onto a line)"),
            ));
        }
        self.scene.lights.push(Light {
            position: corner,
            color,
            area: Some(LightArea {
                v1,
                v2,
                grid: AREA_LIGHT_GRID,
            }),
        });
        Ok(())
    }

    /// `light punctual x y z r g b` or
    /// `light quad x y z r g b v1x v1y v1z v2x v2y v2z n`: a point light, or the
    /// parallelogram with corner `P`, edges `V1 - P` and `V2 - P`, sampled on an
    /// `n x n` grid with one eye sample per pixel.
    pub(super) fn p3f_light(&mut self, kw: &Token) -> Result<(), ParseError> {
        self.saw_p3f_2025 = true;
        self.admit_light(kw)?;
        let Some(kind) = self.lexer.next() else {
            return Err(self.expected(None, "'punctual' or 'quad' after 'light'"));
        };
        match kind.text {
            b"punctual" => {
                let position = self.vec3("light position x y z")?;
                let color = self.vec3("light colour r g b")?;
                self.scene.lights.push(Light::point(position, Some(color)));
                self.skip_numbers_on_line(&kind, "light punctual takes 6 numbers");
            }
            b"quad" => {
                let corner = self.vec3("light corner x y z")?;
                let color = self.vec3("light colour r g b")?;
                let v1 = self.vec3("light quad corner V1 x y z")?;
                let v2 = self.vec3("light quad corner V2 x y z")?;
                let (grid, grid_at) = self.count("light quad grid size n")?;
                if grid == 0 || grid > 1024 {
                    return Err(invalid(
                        grid_at,
                        format!("light quad grid {grid} is outside 1..=1024"),
                    ));
                }
                if !is_parallelogram(corner, v1, v2) {
                    return Err(invalid(
                        loc(kw),
                        "light quad with no area (its corners are collinear)",
                    ));
                }
                self.scene.lights.push(Light {
                    position: corner,
                    color: Some(color),
                    area: Some(LightArea { v1, v2, grid }),
                });
            }
            _ => return Err(self.expected(Some(kind), "'punctual' or 'quad' after 'light'")),
        }
        Ok(())
    }

    /// `box xmin ymin zmin xmax ymax zmax`: a solid axis-aligned box, minimum corner
    /// then maximum corner (NFF's `aabb` orders by axis instead).
    pub(super) fn p3f_box(&mut self, kw: &Token) -> Result<(), ParseError> {
        self.admit_primitive(loc(kw))?;
        let lo = self.vec3("box minimum corner x y z")?;
        let hi = self.vec3("box maximum corner x y z")?;
        let material = self.current_material(loc(kw));
        if lo.to_array().iter().zip(hi.to_array()).any(|(a, b)| *a > b) {
            self.warn(
                loc(kw),
                "box with a minimum above its maximum: limits swapped".into(),
            );
        }
        self.scene.boxes.push(BoxPrim {
            min: lo.min(hi),
            max: lo.max(hi),
            material,
            line: kw.line,
        });
        Ok(())
    }

    /// `npl nx ny nz d`: the infinite plane `n . x + d = 0`, facing `n`.
    pub(super) fn normal_plane(&mut self, kw: &Token) -> Result<(), ParseError> {
        self.admit_primitive(loc(kw))?;
        let n = self.vec3("plane normal nx ny nz")?;
        let d = self.number("plane offset d")?;
        let material = self.current_material(loc(kw));
        let len2 = n.length_squared();
        if len2 == 0.0 || !len2.is_finite() {
            return Err(invalid(loc(kw), "plane normal of zero (or overflowing) length"));
        }
        // A point of the plane and two directions along it, counter-clockwise about n.
        let origin = n * (-d / len2);
        let axis = [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ][n.abs().min_axis()];
        let u = n.cross(axis).normalize();
        let v = n.normalize().cross(u);
        self.scene.planes.push(Plane {
            points: [origin, origin + u, origin + v],
            material,
            line: kw.line,
        });
        Ok(())
    }

    /// `mesh nv nt`, then `nv` vertices `x y z`, then `nt` triangles `i j k`:
    /// vertex indices count from 1, or from the end when negative (-1 is the last).
    /// Triangles with no area are skipped (one warning per mesh).
    pub(super) fn mesh(&mut self, kw: &Token) -> Result<(), ParseError> {
        let (nv, _) = self.count("mesh vertex count")?;
        let (nt, _) = self.count("mesh triangle count")?;
        let first_vertex = self.scene.mesh_vertices.len();
        // No reservation from the counts: a huge count fails where the data runs out.
        for _ in 0..nv {
            self.admit_vertex(kw)?;
            let v = self.vec3("mesh vertex x y z")?;
            self.scene.mesh_vertices.push(v);
        }
        let first_triangle = self.scene.mesh_triangles.len();
        let mut skipped = 0usize;
        for _ in 0..nt {
            self.admit_primitive(self.next_loc(kw))?;
            let line = self.next_loc(kw).0;
            let mut corners = [0u32; 3];
            for c in &mut corners {
                *c = first_vertex as u32 + self.mesh_index(nv)?;
            }
            let p = corners.map(|i| self.scene.mesh_vertices[i as usize]);
            if (p[1] - p[0]).cross(p[2] - p[0]).length_squared() == 0.0 {
                skipped += 1;
                continue;
            }
            self.scene.mesh_triangles.push(MeshTriangle {
                vertices: corners,
                line,
            });
        }
        let material = self.current_material(loc(kw));
        if skipped > 0 {
            self.warn(loc(kw), format!("{skipped} mesh triangles with no area skipped"));
        }
        let index =
            |i: usize| u32::try_from(i).map_err(|_| invalid(loc(kw), "more than 4 billion mesh elements"));
        self.scene.meshes.push(Mesh {
            first_vertex: index(first_vertex)?,
            vertex_count: nv,
            first_triangle: index(first_triangle)?,
            triangle_count: index(self.scene.mesh_triangles.len() - first_triangle)?,
            material,
            line: kw.line,
        });
        Ok(())
    }

    /// `spp n`: samples per pixel (0: one sample at the pixel centre).
    pub(super) fn samples_per_pixel(&mut self, _kw: &Token) -> Result<(), ParseError> {
        self.saw_p3f_2025 = true;
        let (n, at) = self.count("samples per pixel")?;
        if n > MAX_SPP {
            return Err(invalid(at, format!("spp {n} is more than {MAX_SPP}")));
        }
        self.scene.spp = Some(n);
        Ok(())
    }

    /// `accel none|grid|bvh`: the accelerator the file asks for (nffrt reports it and
    /// builds its BVH whatever it says).
    pub(super) fn accelerator(&mut self, _kw: &Token) -> Result<(), ParseError> {
        self.saw_p3f_2025 = true;
        let tok = self.lexer.next();
        self.scene.accel = Some(match tok.as_ref().map(|t| t.text) {
            Some(b"none") => Accel::None,
            Some(b"grid") => Accel::Grid,
            Some(b"bvh") => Accel::Bvh,
            _ => return Err(self.expected(tok, "'none', 'grid' or 'bvh' after 'accel'")),
        });
        Ok(())
    }

    /// `sm cx0 cy0 cz0  cx1 cy1 cz1  r  t0 t1`: a sphere whose centre is `c0` at time
    /// `t0` and `c1` at `t1`, moving linearly (before `t0` and after `t1` too). Its
    /// radius is read as `s`'s (0: skipped with a warning; negative: inside only).
    pub(super) fn moving_sphere(&mut self, kw: &Token) -> Result<(), ParseError> {
        self.admit_primitive(loc(kw))?;
        let center0 = self.vec3("moving sphere centre at t0 x y z")?;
        let center1 = self.vec3("moving sphere centre at t1 x y z")?;
        let radius = self.number("moving sphere radius")?;
        let time0 = self.number("moving sphere time t0")?;
        let time1_at = self.next_loc(kw);
        let time1 = self.number("moving sphere time t1")?;
        let material = self.current_material(loc(kw));
        if time0 == time1 {
            return Err(invalid(
                time1_at,
                format!("moving sphere with t0 = t1 = {time0}: its two times must differ"),
            ));
        }
        let sphere = MovingSphere {
            center0,
            center1,
            radius,
            time0,
            time1,
            material,
            line: kw.line,
        };
        if !sphere.velocity().is_finite() {
            return Err(invalid(
                time1_at,
                "moving sphere too fast: its centres are too far apart for its times (the velocity overflows f32)",
            ));
        }
        if radius == 0.0 {
            self.warn(loc(kw), "moving sphere of radius 0 skipped".into());
            return Ok(());
        }
        self.scene.moving_spheres.push(sphere);
        Ok(())
    }

    /// `shutter t0 t1`: the camera's shutter opens at time `t0` and closes at `t1`
    /// (`t0 <= t1`); without it, it is open from 0 to 1.
    pub(super) fn shutter(&mut self, kw: &Token) -> Result<(), ParseError> {
        let open = self.number("shutter opening time t0")?;
        let close_at = self.next_loc(kw);
        let close = self.number("shutter closing time t1")?;
        if close < open {
            return Err(invalid(
                close_at,
                format!("shutter closing at {close}, before it opens at {open}"),
            ));
        }
        if self.scene.shutter.is_some() {
            self.warn(loc(kw), "a second 'shutter' replaces the first".into());
        }
        self.scene.shutter = Some([open, close]);
        Ok(())
    }

    /// `integrator whitted|path`: the light transport the file asks for (the
    /// command line's choice wins).
    pub(super) fn integrator(&mut self, _kw: &Token) -> Result<(), ParseError> {
        let tok = self.lexer.next();
        let named = tok
            .as_ref()
            .and_then(|t| std::str::from_utf8(t.text).ok()?.parse().ok());
        let Some(kind) = named else {
            let what = format!("{} after 'integrator'", IntegratorKind::choices());
            return Err(self.expected(tok, &what));
        };
        self.scene.integrator = Some(kind);
        Ok(())
    }

    /// A material's optional emitted radiance `r g b` after its 11 numbers: read when
    /// three numbers follow. One or two are left alone, so that the first of them is
    /// reported where a keyword should be (a twelfth number is no part of P3F).
    pub(super) fn emission(&mut self) -> Result<Vec3, ParseError> {
        let mut peek = self.lexer.clone();
        let numbers = (0..3)
            .take_while(|_| peek.next().is_some_and(|t| parse_f32(t.text).is_some()))
            .count();
        if numbers < 3 {
            return Ok(Vec3::ZERO);
        }
        self.vec3("material emission r g b")
    }

    /// A material's optional `roughness R` suffix, `R` in [0, 1]; 0 without it.
    pub(super) fn roughness(&mut self, kw: &Token) -> Result<f32, ParseError> {
        let mut peek = self.lexer.clone();
        match peek.next() {
            Some(t) if t.text == ROUGHNESS.as_bytes() => {}
            _ => return Ok(0.0),
        }
        self.lexer = peek;
        let value_at = self.next_loc(kw);
        let r = self.number("material roughness")?;
        if !(0.0..=1.0).contains(&r) {
            return Err(invalid(value_at, format!("roughness {r} is outside [0, 1]")));
        }
        Ok(r)
    }

    /// `camera eye x y z at x y z up x y z angle a hither h resolution w h aperture A focal F`
    pub(super) fn camera(&mut self, kw: &Token) -> Result<(), ParseError> {
        self.saw_p3f_2025 = true;
        self.view_block(kw, "camera", b"eye")
    }

    /// One mesh vertex index among `nv`: `1..=nv`, or `-nv..=-1` from the end;
    /// returned 0-based.
    fn mesh_index(&mut self, nv: u32) -> Result<u32, ParseError> {
        let tok = self.lexer.next();
        let Some(t) = tok else {
            return Err(self.expected(None, "a mesh vertex index"));
        };
        let parsed = std::str::from_utf8(t.text)
            .ok()
            .and_then(|s| s.parse::<i64>().ok());
        match parsed {
            Some(i) if i >= 1 && i <= nv as i64 => Ok((i - 1) as u32),
            Some(i) if i <= -1 && -i <= nv as i64 => Ok((nv as i64 + i) as u32),
            Some(i) => Err(invalid(
                loc(&t),
                format!("mesh vertex index {i} is outside 1..={nv} (or -{nv}..=-1 from the end)"),
            )),
            None => Err(self.expected(Some(t), "a whole-number mesh vertex index")),
        }
    }

    /// An optional `r g b` after an entity: read if the next token is a number.
    pub(super) fn optional_color(&mut self, what: &str) -> Result<Option<Vec3>, ParseError> {
        let mut peek = self.lexer.clone();
        match peek.next() {
            Some(t) if parse_f32(t.text).is_some() => Ok(Some(self.vec3(what)?)),
            _ => Ok(None),
        }
    }

    /// Skips numbers left on the line of `start` (a quirk of real files: the course's
    /// 2025 `dragon.p3f` has `light punctual` followed by six stray numbers), with a
    /// warning naming them. Numbers on later lines are left to the parser (an error).
    fn skip_numbers_on_line(&mut self, start: &Token, rule: &str) {
        let mut skipped = 0;
        let mut first = None;
        loop {
            let mut peek = self.lexer.clone();
            match peek.next() {
                Some(t) if t.line == start.line && parse_f32(t.text).is_some() => {
                    first.get_or_insert(loc(&t));
                    skipped += 1;
                    self.lexer = peek;
                }
                _ => break,
            }
        }
        if let Some(at) = first {
            self.warn(at, format!("{rule}: {skipped} more numbers on its line ignored"));
        }
    }

    /// Where the next token is (or the entity's keyword, at the end of the file).
    fn next_loc(&self, kw: &Token) -> Loc {
        self.lexer.clone().next().map_or(loc(kw), |t| loc(&t))
    }
}

/// True if the corners `corner`, `v1`, `v2` of an area light span an area (in f32,
/// as the light samples it): the one test of `al` and `light quad`.
fn is_parallelogram(corner: Vec3, v1: Vec3, v2: Vec3) -> bool {
    (v1 - corner).cross(v2 - corner).length_squared() != 0.0
}

#[cfg(test)]
mod tests {
    use crate::math::Vec3;
    use crate::nff::{parse_format, Format};
    use crate::scene::{IntegratorKind, Scene};

    fn p3f(src: &str) -> Scene {
        parse_format(src.as_bytes(), Format::P3f, &Default::default()).unwrap()
    }

    #[test]
    fn mesh_indices_count_from_one_and_from_the_end() {
        // Two meshes: the second's indices are its own (1 is its first vertex).
        let s = p3f("mat 1 1 1 1 1 1 1 0 10 0 1\n\
             mesh 4 2\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n1 2 3\n-4 -2 -1\n\
             mesh 3 1\n5 5 5\n6 5 5\n5 6 5\n-1 1 2\n");
        let corners: Vec<[u32; 3]> = s.mesh_triangles.iter().map(|t| t.vertices).collect();
        // 1 2 3 -> 0 1 2; -4 -2 -1 of four -> 0 2 3; the second mesh starts at 4:
        // -1 1 2 of three -> 6 4 5.
        assert_eq!(corners, vec![[0, 1, 2], [0, 2, 3], [6, 4, 5]]);
        assert_eq!(s.mesh_vertices[6], Vec3::new(5.0, 6.0, 5.0));
        assert_eq!(s.meshes.len(), 2);
        assert_eq!((s.meshes[1].first_vertex, s.meshes[1].first_triangle), (4, 2));
        // Each triangle keeps the line of its indices.
        let lines: Vec<u32> = s.mesh_triangles.iter().map(|t| t.line).collect();
        assert_eq!(lines, vec![7, 8, 13]);
    }

    fn p3f_err(src: &str) -> crate::nff::ParseError {
        parse_format(src.as_bytes(), Format::P3f, &Default::default()).expect_err("should fail")
    }

    const CAMERA: &str = "camera eye 0 0 5 at 0 0 0 up 0 1 0 angle 40\n";

    #[test]
    fn an_area_light_too_small_for_its_position_is_refused() {
        // Found by fuzzing (fuzz/fuzz_targets/p3f.rs): a width of 1e-16 beside x = -3
        // rounds the corners onto a line; the light was kept, and written as `light
        // quad`, which refused it.
        let e = p3f_err("al -3 1 5  0 6 0.6  1.11022e-16 0.166667\n");
        assert_eq!((e.line, e.column), (1, 21));
        assert!(e.to_string().contains("has no area at its position"), "{e}");
        assert_eq!(p3f("al -3 1 5  0 6 0.6  0.1 0.166667\n").lights.len(), 1);
    }

    #[test]
    fn fourteen_material_numbers_end_in_the_emitted_radiance() {
        let s = p3f(&format!(
            "{CAMERA}mat 1 1 1 1 1 1 1 0 10 0 1 2 3 4\ns 0 0 0 1\n\
             f 1 1 1 1 1 1 1 0 10 0 1\ns 0 0 0 1\n"
        ));
        assert_eq!(s.materials[0].emission, Vec3::new(2.0, 3.0, 4.0));
        assert_eq!(s.materials[1].emission, Vec3::ZERO);
        assert_eq!(s.materials[0].ior, 1.0);
        assert_eq!(
            s.materials.iter().map(|m| m.roughness).collect::<Vec<_>>(),
            [0.0, 0.0]
        );
    }

    #[test]
    fn a_twelfth_or_thirteenth_number_is_where_a_keyword_should_be() {
        // Line 2, the twelfth number at column 27 (after `mat ` and eleven
        // one-character numbers); one or two extra numbers, at the end or before an entity.
        for tail in ["0.3", "0.3 0.4", "0.3\ns 0 0 0 1", "0.3 0.4\ns 0 0 0 1"] {
            let e = p3f_err(&format!("{CAMERA}mat 1 1 1 1 1 1 1 0 9 0 1 {tail}\n"));
            assert_eq!((e.line, e.column), (2, 27), "{tail}: {e}");
            assert!(e.to_string().contains("expected a keyword"), "{tail}: {e}");
            assert!(e.to_string().contains("found the number \"0.3\""), "{tail}: {e}");
        }
        // A fifteenth number after the emission: there.
        let e = p3f_err(&format!("{CAMERA}mat 1 1 1 1 1 1 1 0 9 0 1 2 3 4 5\n"));
        assert_eq!((e.line, e.column), (2, 33), "{e}");
    }

    #[test]
    fn roughness_is_an_optional_named_suffix_within_zero_and_one() {
        let s = p3f(&format!(
            "{CAMERA}mat 1 1 1 1 1 1 1 0 10 0 1 roughness 0.25\ns 0 0 0 1\n\
             mat 1 1 1 1 1 1 1 0 10 1 1.5 5 5 5 roughness 1\ns 0 0 0 1\n"
        ));
        assert_eq!(s.materials[0].roughness, 0.25);
        assert_eq!(s.materials[0].emission, Vec3::ZERO);
        assert_eq!(
            (s.materials[1].roughness, s.materials[1].emission),
            (1.0, Vec3::splat(5.0))
        );
        // Out of range: at the value (line 2: `f`, 11 numbers, `roughness`).
        for bad in ["-0.1", "1.5"] {
            let e = p3f_err(&format!("{CAMERA}f 1 1 1 1 1 1 1 0 9 0 1 roughness {bad}\n"));
            assert_eq!((e.line, e.column), (2, 35), "{e}");
            assert!(e.to_string().contains("outside [0, 1]"), "{e}");
        }
        let e = p3f_err(&format!("{CAMERA}f 1 1 1 1 1 1 1 0 9 0 1 roughness\ns 0 0 0 1\n"));
        assert_eq!((e.line, e.column), (3, 1), "{e}");
        assert!(e.to_string().contains("material roughness"), "{e}");
        // Before the emission it is no suffix: the emission's numbers are stray.
        let e = p3f_err(&format!("{CAMERA}f 1 1 1 1 1 1 1 0 9 0 1 roughness 0 1 1 1\n"));
        assert_eq!((e.line, e.column), (2, 37), "{e}");
    }

    #[test]
    fn nff_materials_have_neither_emission_nor_roughness() {
        let s = crate::nff::parse("f 1 1 1 1 0 1 0 1\ns 0 0 0 1\n").unwrap();
        assert_eq!(
            (s.materials[0].emission, s.materials[0].roughness),
            (Vec3::ZERO, 0.0)
        );
        let e = crate::nff::parse("f 1 1 1 1 0 1 0 1 roughness 0.5\n").unwrap_err();
        assert_eq!((e.line, e.column), (1, 19));
        assert!(e.to_string().contains("unknown keyword \"roughness\""), "{e}");
    }

    #[test]
    fn a_moving_sphere_keeps_its_two_centres_and_times() {
        let s = p3f(&format!(
            "{CAMERA}f 1 1 1 1 1 1 1 0 9 0 1\nsm 1 2 3  4 6 8  -0.5  0.25 1.25\n"
        ));
        let m = s.moving_spheres[0];
        assert_eq!(
            (m.center0, m.center1),
            (Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.0, 6.0, 8.0))
        );
        assert_eq!((m.radius, m.time0, m.time1, m.line), (-0.5, 0.25, 1.25, 3));
        // One unit of time apart: the velocity is the displacement; centres at the
        // times given, half way and beyond (0.5 before t0: half a step back).
        assert_eq!(m.velocity(), Vec3::new(3.0, 4.0, 5.0));
        assert_eq!(m.center_at(0.25), m.center0);
        assert_eq!(m.center_at(1.25), m.center1);
        assert_eq!(m.center_at(0.75), Vec3::new(2.5, 4.0, 5.5));
        assert_eq!(m.center_at(-0.25), Vec3::new(-0.5, 0.0, 0.5));
        assert!(s.spheres.is_empty());
        assert_eq!(s.primitive_count(), 1);
        assert!(s.kind_counts().contains(&("moving_spheres", 1)));
    }

    #[test]
    fn a_moving_sphere_needs_two_times_and_a_radius() {
        let e = p3f_err(&format!("{CAMERA}sm 0 0 0 1 1 1 0.5 2 2\n"));
        assert_eq!((e.line, e.column), (2, 22), "{e}");
        assert!(e.to_string().contains("times must differ"), "{e}");
        // Far apart in space, close in time: the velocity overflows.
        let e = p3f_err(&format!("{CAMERA}sm -3e38 0 0 3e38 0 0 1 0 1e-30\n"));
        assert_eq!((e.line, e.column), (2, 27), "{e}");
        let s = p3f(&format!("{CAMERA}sm 0 0 0 1 1 1 0 0 1\n"));
        assert!(s.moving_spheres.is_empty());
        let messages: Vec<&str> = s.warnings.iter().map(|w| w.message.as_str()).collect();
        assert!(
            messages.contains(&"moving sphere of radius 0 skipped"),
            "{messages:?}"
        );
        let e = crate::nff::parse("sm 0 0 0 1 1 1 0.5 0 1\n").unwrap_err();
        assert!(e.to_string().contains("unknown keyword \"sm\""), "{e}");
    }

    #[test]
    fn the_shutter_is_open_from_zero_to_one_unless_the_file_says() {
        let s = p3f(&format!("{CAMERA}s 0 0 0 1\n"));
        assert_eq!((s.shutter, s.shutter_interval()), (None, [0.0, 1.0]));
        let s = p3f(&format!("{CAMERA}shutter 0.25 0.5\ns 0 0 0 1\n"));
        assert_eq!(
            (s.shutter, s.shutter_interval()),
            (Some([0.25, 0.5]), [0.25, 0.5])
        );
        // An instant is a shutter too.
        assert_eq!(p3f(&format!("{CAMERA}shutter 3 3\n")).shutter, Some([3.0, 3.0]));
        let e = p3f_err(&format!("{CAMERA}shutter 1 0.5\n"));
        assert_eq!((e.line, e.column), (2, 11), "{e}");
        let e = p3f_err(&format!("{CAMERA}shutter 0 1e39\n"));
        assert!(e.to_string().contains("finite"), "{e}");
        // A shutter and an integrator do not make a 2019 file a 2025 one.
        let s = p3f("v from 0 0 5 at 0 0 0 up 0 1 0 angle 40\nshutter 0 2\nintegrator path\n");
        assert_eq!(s.dialect, crate::scene::Dialect::P3f2019);
    }

    #[test]
    fn the_integrator_is_whitted_or_path() {
        assert_eq!(
            p3f(&format!("{CAMERA}integrator whitted\n")).integrator,
            Some(IntegratorKind::Whitted)
        );
        assert_eq!(
            p3f(&format!("{CAMERA}integrator path\n")).integrator,
            Some(IntegratorKind::Path)
        );
        assert_eq!(p3f(CAMERA).integrator, None);
        let e = p3f_err(&format!("{CAMERA}integrator bdpt\n"));
        assert_eq!((e.line, e.column), (2, 12), "{e}");
        assert!(e.to_string().contains("'whitted' or 'path'"), "{e}");
    }

    #[test]
    fn a_moving_sphere_is_bounded_over_the_shutter() {
        // Centre (0, 0, 0) at t = 0 to (4, 0, 0) at t = 2, radius 1: over the default
        // shutter [0, 1] it reaches x = 2; over [-1, 2], from x = -2 to x = 4.
        let sm = "sm 0 0 0 4 0 0 1 0 2\n";
        let b = p3f(&format!("{CAMERA}{sm}")).bounds();
        assert_eq!(
            (b.min, b.max),
            (Vec3::new(-1.0, -1.0, -1.0), Vec3::new(3.0, 1.0, 1.0))
        );
        let b = p3f(&format!("{CAMERA}shutter -1 2\n{sm}")).bounds();
        assert_eq!(
            (b.min, b.max),
            (Vec3::new(-3.0, -1.0, -1.0), Vec3::new(5.0, 1.0, 1.0))
        );
    }

    #[test]
    fn an_area_light_is_centred_and_faces_its_target() {
        let s = p3f("al 1 2 3 1 2 0 2 1 0.5 0.5 0.5\n");
        let l = &s.lights[0];
        let a = l.area.unwrap();
        let (e1, e2) = (a.v1 - l.position, a.v2 - l.position);
        // Centre (1, 2, 3); sides 2 and 1; facing -z, so both edges lie in z = 3.
        let centre = l.position + e1 * 0.5 + e2 * 0.5;
        assert!((centre - Vec3::new(1.0, 2.0, 3.0)).length() < 1e-6);
        assert!((e1.length() - 2.0).abs() < 1e-6 && (e2.length() - 1.0).abs() < 1e-6);
        assert!(e1.z.abs() < 1e-6 && e2.z.abs() < 1e-6 && e1.dot(e2).abs() < 1e-6);
        assert_eq!(l.color, Some(Vec3::splat(0.5)));
    }
}
