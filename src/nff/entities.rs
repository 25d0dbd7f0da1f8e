//! The NFF keywords, most of them shared with P3F, one function per keyword; each
//! quotes its syntax.

use super::error::ParseError;
use super::lexer::Token;
use super::parser::{invalid, loc, Loc, Parser};
use super::Format;
use crate::limits::MAX_RESOLUTION;
use crate::math::Vec3;
use crate::scene::{AngleSpan, BoxPrim, Cone, Light, Material, Patch, Plane, Polygon, Sphere, View};

impl Parser<'_> {
    /// `v from x y z at x y z up x y z angle deg hither d resolution w h`
    /// (sub-keywords in any order; `hither` and `resolution` optional); in P3F also
    /// `aperture A focal F` (optional, default 0 and 1).
    pub(super) fn view(&mut self, kw: &Token) -> Result<(), ParseError> {
        self.view_block(kw, "v", b"from")
    }

    /// The camera block of `v` (`from`) or P3F's `camera` (`eye`).
    pub(super) fn view_block(&mut self, kw: &Token, name: &str, eye: &[u8]) -> Result<(), ParseError> {
        let at = loc(kw);
        if self.saw_view {
            self.warn(at, format!("a second '{name}' block replaces the first"));
        }
        self.saw_view = true;
        let p3f = self.format == Format::P3f;
        let mut v = View {
            angle_span: if p3f {
                AngleSpan::ImageEdges
            } else {
                AngleSpan::PixelCentres
            },
            ..View::default()
        };
        let (mut from, mut look_at, mut up, mut angle) = (None, None, None, None);
        loop {
            let mut peek = self.lexer.clone();
            let Some(t) = peek.next() else { break };
            let known = match t.text {
                b"at" | b"up" | b"angle" | b"hither" | b"resolution" => true,
                b"aperture" | b"focal" => p3f,
                other => other == eye,
            };
            if !known {
                break;
            }
            self.lexer = peek;
            match t.text {
                b"aperture" => {
                    let value_at = self.lexer.clone().next().map_or(loc(&t), |n| loc(&n));
                    v.aperture = self.number("'aperture' in pixels")?;
                    if v.aperture < 0.0 {
                        return Err(invalid(value_at, format!("aperture {} is negative", v.aperture)));
                    }
                }
                b"focal" => {
                    let value_at = self.lexer.clone().next().map_or(loc(&t), |n| loc(&n));
                    v.focal = self.number("'focal' distance ratio")?;
                    if v.focal <= 0.0 {
                        return Err(invalid(
                            value_at,
                            format!("focal ratio {} is not positive", v.focal),
                        ));
                    }
                }
                field if field == eye => {
                    let what = format!("'{}' x y z", String::from_utf8_lossy(eye));
                    from = Some(self.vec3(&what)?);
                }
                b"at" => look_at = Some(self.vec3("'at' x y z")?),
                b"up" => up = Some(self.vec3("'up' x y z")?),
                b"angle" => {
                    // A bad angle is reported at its value, not at the sub-keyword.
                    let value_at = self.lexer.clone().next().map_or(loc(&t), |n| loc(&n));
                    angle = Some((self.number("'angle' in degrees")?, value_at));
                }
                b"hither" => v.hither = self.number("'hither' distance")?,
                _ => {
                    let (w, wl) = self.count("'resolution' width")?;
                    let (h, hl) = self.count("'resolution' height")?;
                    for (n, l) in [(w, wl), (h, hl)] {
                        if n == 0 || n > MAX_RESOLUTION {
                            return Err(invalid(
                                l,
                                format!("resolution {n} is outside 1..={MAX_RESOLUTION}"),
                            ));
                        }
                    }
                    (v.width, v.height) = (w, h);
                }
            }
        }
        let missing = |field: &str| invalid(at, format!("the '{name}' block lacks '{field}'"));
        v.from = from.ok_or_else(|| missing(&String::from_utf8_lossy(eye)))?;
        v.at = look_at.ok_or_else(|| missing("at"))?;
        v.up = up.ok_or_else(|| missing("up"))?;
        let (angle, angle_at) = angle.ok_or_else(|| missing("angle"))?;
        if !(angle > 0.0 && angle < 180.0) {
            return Err(invalid(
                angle_at,
                format!("camera angle {angle} is outside (0, 180) degrees"),
            ));
        }
        v.angle = angle;
        let dir = v.at - v.from;
        let dist2 = dir.length_squared();
        if dist2 == 0.0 {
            return Err(invalid(at, "camera 'from' and 'at' are the same point"));
        }
        // Finite points can still be too far apart for f32: the direction would normalize to NaN.
        if !dist2.is_finite() {
            return Err(invalid(
                at,
                "camera 'from' and 'at' are too far apart (their distance overflows f32)",
            ));
        }
        // `partial_cmp`, not `<`, so that a NaN (an up vector too long to normalize) is refused too.
        let sin2 = dir.normalize().cross(v.up.normalize()).length_squared();
        if sin2.partial_cmp(&1e-12) != Some(std::cmp::Ordering::Greater) {
            return Err(invalid(
                at,
                "camera 'up' is zero or parallel to the viewing direction",
            ));
        }
        self.scene.view = v;
        Ok(())
    }

    /// `b r g b`
    pub(super) fn background(&mut self, _kw: &Token) -> Result<(), ParseError> {
        self.scene.background = self.vec3("background colour r g b")?;
        self.saw_background = true;
        Ok(())
    }

    /// `l x y z [r g b]`
    pub(super) fn light(&mut self, kw: &Token) -> Result<(), ParseError> {
        self.admit_light(kw)?;
        let position = self.vec3("light position x y z")?;
        let color = self.optional_color("light colour r g b")?;
        // P3F lights carry colours; one without is white.
        let color = match self.format {
            Format::P3f => Some(color.unwrap_or(Vec3::ONE)),
            Format::Nff | Format::Aff => color,
        };
        self.scene.lights.push(Light::point(position, color));
        Ok(())
    }

    /// `f r g b Kd Ks shine T ior`; in P3F (`f` and `mat`)
    /// `f dr dg db Kd sr sg sb Ks shine T ior [er eg eb] [roughness R]`, with the
    /// specular colour, then optionally the emitted radiance and the roughness.
    pub(super) fn fill(&mut self, kw: &Token) -> Result<(), ParseError> {
        if kw.text == b"mat" {
            self.saw_p3f_2025 = true;
        }
        let p3f = self.format == Format::P3f;
        let color = self.vec3("material colour r g b")?;
        let kd = self.number("material Kd")?;
        let specular = if p3f {
            self.vec3("material specular colour r g b")?
        } else {
            Vec3::ONE
        };
        let mut m = Material {
            color,
            kd,
            specular,
            ks: self.number("material Ks")?,
            shine: self.number("material shine")?,
            t: self.number("material T")?,
            ior: self.number("material ior")?,
            ..Material::DEFAULT
        };
        if p3f {
            m.emission = self.emission()?;
            m.roughness = self.roughness(kw)?;
        }
        // Consecutive identical `f` lines share one table entry.
        let idx = match self.scene.materials.last() {
            Some(last) if *last == m => self.scene.materials.len() - 1,
            _ => {
                self.scene.materials.push(m);
                self.scene.materials.len() - 1
            }
        };
        self.material = Some(idx as u32);
        Ok(())
    }

    /// `s cx cy cz r`
    pub(super) fn sphere(&mut self, kw: &Token) -> Result<(), ParseError> {
        self.admit_primitive(loc(kw))?;
        let center = self.vec3("sphere centre x y z")?;
        let radius = self.number("sphere radius")?;
        let material = self.current_material(loc(kw));
        if radius == 0.0 {
            self.warn(loc(kw), "sphere of radius 0 skipped".into());
            return Ok(());
        }
        self.scene.spheres.push(Sphere {
            center,
            radius,
            material,
            line: kw.line,
        });
        Ok(())
    }

    /// `c bx by bz br ax ay az ar`
    pub(super) fn cone(&mut self, kw: &Token) -> Result<(), ParseError> {
        self.admit_primitive(loc(kw))?;
        let base = self.vec3("cone base x y z")?;
        let base_radius = self.number("cone base radius")?;
        let apex = self.vec3("cone apex x y z")?;
        let apex_radius = self.number("cone apex radius")?;
        let material = self.current_material(loc(kw));
        if (apex - base).length_squared() == 0.0 {
            self.warn(loc(kw), "cone whose base and apex coincide skipped".into());
            return Ok(());
        }
        if base_radius == 0.0 && apex_radius == 0.0 {
            self.warn(loc(kw), "cone with both radii 0 skipped".into());
            return Ok(());
        }
        if (base_radius < 0.0) != (apex_radius < 0.0) && base_radius != 0.0 && apex_radius != 0.0 {
            self.warn(
                loc(kw),
                "cone radii of opposite signs: treated as an outside-visible cone".into(),
            );
        }
        self.scene.cones.push(Cone {
            base,
            base_radius,
            apex,
            apex_radius,
            material,
            line: kw.line,
        });
        Ok(())
    }

    /// `p n` then n times `x y z`
    pub(super) fn polygon(&mut self, kw: &Token) -> Result<(), ParseError> {
        self.admit_primitive(loc(kw))?;
        let (n, n_at) = self.count("polygon vertex count")?;
        if n < 3 {
            return Err(invalid(
                n_at,
                format!("a polygon needs at least 3 vertices, not {n}"),
            ));
        }
        let first = self.scene.polygon_vertices.len();
        // No reservation from `n`: a huge count fails at the end of the file, not in the allocator.
        for _ in 0..n {
            self.admit_vertex(kw)?;
            let v = self.vec3("polygon vertex x y z")?;
            self.scene.polygon_vertices.push(v);
        }
        let material = self.current_material(loc(kw));
        if is_degenerate(&self.scene.polygon_vertices[first..]) {
            self.scene.polygon_vertices.truncate(first);
            self.warn(
                loc(kw),
                "polygon with no area (collinear or coincident vertices) skipped".into(),
            );
            return Ok(());
        }
        let first = index_u32(first, loc(kw))?;
        self.scene.polygons.push(Polygon {
            first,
            count: n,
            material,
            line: kw.line,
        });
        Ok(())
    }

    /// `pp n` then n times `x y z nx ny nz`
    pub(super) fn patch(&mut self, kw: &Token) -> Result<(), ParseError> {
        self.admit_primitive(loc(kw))?;
        let (n, n_at) = self.count("patch vertex count")?;
        if n < 3 {
            return Err(invalid(
                n_at,
                format!("a patch needs at least 3 vertices, not {n}"),
            ));
        }
        let first = self.scene.patch_vertices.len();
        for _ in 0..n {
            self.admit_vertex(kw)?;
            let v = self.vec3("patch vertex x y z")?;
            let nrm = self.vec3("patch normal nx ny nz")?;
            self.scene.patch_vertices.push(v);
            self.scene.patch_normals.push(nrm);
        }
        let material = self.current_material(loc(kw));
        if is_degenerate(&self.scene.patch_vertices[first..]) {
            self.scene.patch_vertices.truncate(first);
            self.scene.patch_normals.truncate(first);
            self.warn(
                loc(kw),
                "patch with no area (collinear or coincident vertices) skipped".into(),
            );
            return Ok(());
        }
        let first = index_u32(first, loc(kw))?;
        self.scene.patches.push(Patch {
            first,
            count: n,
            material,
            line: kw.line,
        });
        Ok(())
    }

    /// `pl x1 y1 z1 x2 y2 z2 x3 y3 z3`
    pub(super) fn plane(&mut self, kw: &Token) -> Result<(), ParseError> {
        self.admit_primitive(loc(kw))?;
        let points = [
            self.vec3("plane point 1 x y z")?,
            self.vec3("plane point 2 x y z")?,
            self.vec3("plane point 3 x y z")?,
        ];
        let material = self.current_material(loc(kw));
        if is_degenerate(&points) {
            self.warn(loc(kw), "plane through collinear points skipped".into());
            return Ok(());
        }
        self.scene.planes.push(Plane {
            points,
            material,
            line: kw.line,
        });
        Ok(())
    }

    /// `aabb xmin xmax ymin ymax zmin zmax`
    pub(super) fn aabb(&mut self, kw: &Token) -> Result<(), ParseError> {
        self.admit_primitive(loc(kw))?;
        let mut lo = [0.0; 3];
        let mut hi = [0.0; 3];
        for (axis, name) in ["x", "y", "z"].iter().enumerate() {
            lo[axis] = self.number(&format!("box {name}min"))?;
            hi[axis] = self.number(&format!("box {name}max"))?;
        }
        let material = self.current_material(loc(kw));
        let (min, max) = (Vec3::from_array(lo), Vec3::from_array(hi));
        if lo.iter().zip(&hi).any(|(a, b)| a > b) {
            self.warn(
                loc(kw),
                "box with a minimum above its maximum: limits swapped".into(),
            );
        }
        self.scene.boxes.push(BoxPrim {
            min: min.min(max),
            max: min.max(max),
            material,
            line: kw.line,
        });
        Ok(())
    }
}

/// True when the points span no area: Newell's normal (robust for concave polygons, zero
/// for collinear ones) is negligible against the polygon's squared extent. Computed in f64
/// so that neither huge (1e13) nor tiny (1e-13) but valid f32 polygons overflow or underflow.
pub(crate) fn is_degenerate(pts: &[Vec3]) -> bool {
    let f64s = |p: Vec3| [p.x as f64, p.y as f64, p.z as f64];
    let p0 = f64s(pts[0]);
    let rel = |p: Vec3| {
        let q = f64s(p);
        [q[0] - p0[0], q[1] - p0[1], q[2] - p0[2]]
    };
    let len2 = |a: [f64; 3]| a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
    let scale = pts.iter().fold(0.0f64, |m, p| m.max(len2(rel(*p))));
    if scale == 0.0 {
        return true;
    }
    let mut n = [0.0f64; 3];
    for (i, a) in pts.iter().enumerate() {
        let (a, b) = (rel(*a), rel(pts[(i + 1) % pts.len()]));
        n[0] += a[1] * b[2] - a[2] * b[1];
        n[1] += a[2] * b[0] - a[0] * b[2];
        n[2] += a[0] * b[1] - a[1] * b[0];
    }
    len2(n) <= 1e-12 * scale * scale
}

fn index_u32(i: usize, at: Loc) -> Result<u32, ParseError> {
    u32::try_from(i).map_err(|_| invalid(at, "more than 4 billion vertices"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn degeneracy_does_not_depend_on_scale() {
        for k in [1e-15f32, 1e-6, 1.0, 1e6, 1e15, 1e18] {
            let tri = [Vec3::ZERO, Vec3::new(k, 0.0, 0.0), Vec3::new(0.0, k, 0.0)];
            assert!(!is_degenerate(&tri), "{k}");
            let line = [
                Vec3::ZERO,
                Vec3::new(k, k, k),
                Vec3::new(2.0 * k, 2.0 * k, 2.0 * k),
            ];
            assert!(is_degenerate(&line), "{k}");
        }
    }
}
