//! Turns NFF tokens into a [`Scene`]. One function per keyword; each quotes its syntax.

use super::error::{ParseError, ParseErrorKind};
use super::lexer::{Lexer, Token};
use super::limits::{Limits, MAX_WARNINGS};
use crate::math::Vec3;
use crate::scene::{BoxPrim, Cone, Light, Material, Patch, Plane, Polygon, Scene, Sphere, View, Warning};

/// The largest image side a file may ask for.
pub const MAX_RESOLUTION: u32 = 32768;

/// Parses NFF text into a scene. Errors carry the line and column of the offending token.
///
/// ```
/// let scene = nffrt::nff::parse("v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 64 48\n\
///                                f 1 0 0 1 0 1 0 1\ns 0 0 0 1\n").unwrap();
/// assert_eq!(scene.spheres.len(), 1);
/// assert_eq!((scene.view.width, scene.view.height), (64, 48));
/// ```
pub fn parse(src: &str) -> Result<Scene, ParseError> {
    parse_bytes(src.as_bytes())
}

/// Parses NFF from raw bytes (which need not be UTF-8: a non-ASCII token is reported
/// as an error), within the default [`Limits`].
pub fn parse_bytes(src: &[u8]) -> Result<Scene, ParseError> {
    parse_bytes_with(src, &Limits::default())
}

/// Parses NFF from raw bytes, refusing a file that describes more than `limits` allow
/// (at the first primitive, vertex or light past the limit).
pub fn parse_bytes_with(src: &[u8], limits: &Limits) -> Result<Scene, ParseError> {
    let mut p = Parser {
        lexer: Lexer::new(src),
        scene: Scene::default(),
        material: None,
        saw_view: false,
        limits: *limits,
        warnings_left_out: 0,
    };
    p.run()?;
    if p.warnings_left_out > 0 {
        let n = p.warnings_left_out;
        let end = p.lexer.end_location();
        p.scene.warnings.push(Warning {
            line: end.0,
            column: end.1,
            message: format!("... and {n} more warnings"),
        });
    }
    Ok(p.scene)
}

struct Parser<'a> {
    lexer: Lexer<'a>,
    scene: Scene,
    /// Index of the current material, `None` before the first `f`.
    material: Option<u32>,
    saw_view: bool,
    limits: Limits,
    /// Warnings past [`MAX_WARNINGS`], counted instead of kept.
    warnings_left_out: usize,
}

/// A 1-based location.
type Loc = (u32, u32);

fn loc(t: &Token) -> Loc {
    (t.line, t.column)
}

fn err(at: Loc, kind: ParseErrorKind) -> ParseError {
    ParseError::new(at.0, at.1, kind)
}

fn invalid(at: Loc, msg: impl Into<String>) -> ParseError {
    err(at, ParseErrorKind::Invalid(msg.into()))
}

impl<'a> Parser<'a> {
    fn run(&mut self) -> Result<(), ParseError> {
        while let Some(tok) = self.lexer.next() {
            match tok.text {
                b"v" => self.view(&tok)?,
                b"b" => self.background(&tok)?,
                b"l" => self.light(&tok)?,
                b"f" => self.fill(&tok)?,
                b"s" => self.sphere(&tok)?,
                b"c" => self.cone(&tok)?,
                b"p" => self.polygon(&tok)?,
                b"pp" => self.patch(&tok)?,
                b"pl" => self.plane(&tok)?,
                b"aabb" => self.aabb(&tok)?,
                _ => {
                    let kind = if parse_f32(tok.text).is_some() {
                        ParseErrorKind::Expected {
                            expected: "a keyword (v, b, l, f, s, c, p, pp, pl, aabb)".into(),
                            found: format!("the number {}", tok.quoted()),
                        }
                    } else {
                        ParseErrorKind::UnknownKeyword(tok.quoted())
                    };
                    return Err(err(loc(&tok), kind));
                }
            }
        }
        if !self.saw_view {
            self.warn(
                (1, 1),
                "no 'v' block: using the default camera (from 0 0 10, at 0 0 0, up 0 1 0, angle 45, 512x512)"
                    .into(),
            );
        }
        Ok(())
    }

    /// Refuses the primitive at `at` if the scene already holds the most allowed.
    fn admit_primitive(&self, at: Loc) -> Result<(), ParseError> {
        let max = self.limits.max_primitives;
        if self.scene.primitive_count() >= max {
            return Err(invalid(
                at,
                format!("more than {max} primitives (the limit; nffrt's --max-primitives raises it)"),
            ));
        }
        Ok(())
    }

    /// Refuses another polygon or patch vertex (of the entity at `kw`) past the limit,
    /// reporting it at the vertex's first token.
    fn admit_vertex(&self, kw: &Token) -> Result<(), ParseError> {
        let max = self.limits.max_vertices;
        if self.scene.polygon_vertices.len() + self.scene.patch_vertices.len() >= max {
            let at = self.lexer.clone().next().map_or(loc(kw), |t| loc(&t));
            return Err(invalid(
                at,
                format!(
                    "more than {max} polygon and patch vertices (the limit; nffrt's --max-vertices raises it)"
                ),
            ));
        }
        Ok(())
    }

    fn warn(&mut self, at: Loc, message: String) {
        if self.scene.warnings.len() >= MAX_WARNINGS {
            self.warnings_left_out += 1;
            return;
        }
        self.scene.warnings.push(Warning {
            line: at.0,
            column: at.1,
            message,
        });
    }

    fn expected(&self, tok: Option<Token>, expected: &str) -> ParseError {
        let (at, found) = match tok {
            Some(t) => (loc(&t), t.quoted()),
            None => (self.lexer.end_location(), "end of file".to_string()),
        };
        err(
            at,
            ParseErrorKind::Expected {
                expected: expected.to_string(),
                found,
            },
        )
    }

    /// Reads one finite number; `what` names it in the error message.
    fn number(&mut self, what: &str) -> Result<f32, ParseError> {
        let tok = self.lexer.next();
        match tok.as_ref().and_then(|t| parse_f32(t.text)) {
            Some(v) if v.is_finite() => Ok(v),
            Some(_) => Err(self.expected(tok, &format!("a finite number ({what})"))),
            None => Err(self.expected(tok, &format!("a number ({what})"))),
        }
    }

    fn vec3(&mut self, what: &str) -> Result<Vec3, ParseError> {
        Ok(Vec3::new(
            self.number(what)?,
            self.number(what)?,
            self.number(what)?,
        ))
    }

    /// Reads a non-negative integer count.
    fn count(&mut self, what: &str) -> Result<(u32, Loc), ParseError> {
        let tok = self.lexer.next();
        let Some(t) = tok else {
            return Err(self.expected(None, &format!("a count ({what})")));
        };
        if t.text.is_empty() || !t.text.iter().all(u8::is_ascii_digit) {
            return Err(self.expected(tok, &format!("a non-negative whole number ({what})")));
        }
        match std::str::from_utf8(t.text)
            .ok()
            .and_then(|s| s.parse::<u32>().ok())
        {
            Some(n) => Ok((n, loc(&t))),
            None => Err(invalid(loc(&t), format!("{what} {} is too large", t.quoted()))),
        }
    }

    /// The material index for a new object, falling back (once, with a warning) to
    /// [`Material::DEFAULT`] before the first `f`.
    fn current_material(&mut self, at: Loc) -> u32 {
        if let Some(m) = self.material {
            return m;
        }
        self.warn(
            at,
            "object before any 'f': using the default material (f 1 1 1 1 0 1 0 1)".into(),
        );
        self.scene.materials.push(Material::DEFAULT);
        let m = (self.scene.materials.len() - 1) as u32;
        self.material = Some(m);
        m
    }

    /// `v from x y z at x y z up x y z angle deg hither d resolution w h`
    /// (sub-keywords in any order; `hither` and `resolution` optional).
    fn view(&mut self, kw: &Token) -> Result<(), ParseError> {
        let at = loc(kw);
        if self.saw_view {
            self.warn(at, "a second 'v' block replaces the first".into());
        }
        self.saw_view = true;
        let mut v = View::default();
        let (mut from, mut look_at, mut up, mut angle) = (None, None, None, None);
        loop {
            let mut peek = self.lexer.clone();
            let Some(t) = peek.next() else { break };
            let field = match t.text {
                b"from" | b"at" | b"up" | b"angle" | b"hither" | b"resolution" => t.text,
                _ => break,
            };
            self.lexer = peek;
            match field {
                b"from" => from = Some(self.vec3("'from' x y z")?),
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
        let missing = |name: &str| invalid(at, format!("the 'v' block lacks '{name}'"));
        v.from = from.ok_or_else(|| missing("from"))?;
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
    fn background(&mut self, _kw: &Token) -> Result<(), ParseError> {
        self.scene.background = self.vec3("background colour r g b")?;
        Ok(())
    }

    /// `l x y z [r g b]`
    fn light(&mut self, kw: &Token) -> Result<(), ParseError> {
        let max = self.limits.max_lights;
        if self.scene.lights.len() >= max {
            return Err(invalid(
                loc(kw),
                format!("more than {max} lights (the limit; nffrt's --max-lights raises it)"),
            ));
        }
        let position = self.vec3("light position x y z")?;
        let mut peek = self.lexer.clone();
        let color = match peek.next() {
            Some(t) if parse_f32(t.text).is_some() => Some(self.vec3("light colour r g b")?),
            _ => None,
        };
        self.scene.lights.push(Light { position, color });
        Ok(())
    }

    /// `f r g b Kd Ks shine T ior`
    fn fill(&mut self, _kw: &Token) -> Result<(), ParseError> {
        let m = Material {
            color: self.vec3("material colour r g b")?,
            kd: self.number("material Kd")?,
            ks: self.number("material Ks")?,
            shine: self.number("material shine")?,
            t: self.number("material T")?,
            ior: self.number("material ior")?,
        };
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
    fn sphere(&mut self, kw: &Token) -> Result<(), ParseError> {
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
    fn cone(&mut self, kw: &Token) -> Result<(), ParseError> {
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
    fn polygon(&mut self, kw: &Token) -> Result<(), ParseError> {
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
    fn patch(&mut self, kw: &Token) -> Result<(), ParseError> {
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
    fn plane(&mut self, kw: &Token) -> Result<(), ParseError> {
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
    fn aabb(&mut self, kw: &Token) -> Result<(), ParseError> {
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
fn is_degenerate(pts: &[Vec3]) -> bool {
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

/// Parses a C-style float (`1`, `-0.5`, `.5`, `1E-3`). Returns `None` for anything
/// else, including Rust-only spellings such as `inf` and `nan` (which would parse but
/// are rejected later as non-finite anyway).
#[inline]
fn parse_f32(text: &[u8]) -> Option<f32> {
    let first = *text.first()?;
    if !(first.is_ascii_digit() || matches!(first, b'-' | b'+' | b'.')) {
        return None;
    }
    std::str::from_utf8(text).ok()?.parse::<f32>().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    const VIEW: &str = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 64 48\n";

    fn parse_err(src: &str) -> ParseError {
        parse(src).expect_err("should fail")
    }

    #[test]
    fn parses_every_keyword() {
        let src = format!(
            "{VIEW}b 0.1 0.2 0.3\nl 1 2 3\nl 1 2 3 0.5 0.5 0.5\nf 1 0 0 1 0 1 0 1\n\
             s 0 0 0 1\nc 0 0 0 1 0 1 0 0.5\np 3 0 0 0 1 0 0 0 1 0\n\
             pp 3 0 0 0 0 0 1 1 0 0 0 0 1 0 1 0 0 0 1\npl 0 0 0 1 0 0 0 1 0\naabb -1 1 -2 2 -3 3\n"
        );
        let s = parse(&src).unwrap();
        assert_eq!(s.background, Vec3::new(0.1, 0.2, 0.3));
        assert_eq!(s.lights.len(), 2);
        assert_eq!(s.lights[0].color, None);
        assert_eq!(s.lights[1].color, Some(Vec3::splat(0.5)));
        assert_eq!(
            (
                s.spheres.len(),
                s.cones.len(),
                s.polygons.len(),
                s.patches.len(),
                s.planes.len(),
                s.boxes.len()
            ),
            (1, 1, 1, 1, 1, 1)
        );
        assert_eq!(s.boxes[0].min, Vec3::new(-1.0, -2.0, -3.0));
        assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    }

    #[test]
    fn unknown_keyword_names_line_and_column() {
        let e = parse_err(&format!("{VIEW}\n  zz 1 2 3"));
        assert_eq!((e.line, e.column), (3, 3));
        assert!(e.to_string().contains("unknown keyword \"zz\""), "{e}");
    }

    #[test]
    fn truncated_sphere_reports_end_of_file() {
        let e = parse_err(&format!("{VIEW}f 1 1 1 1 0 1 0 1\ns 1 2"));
        assert!(e.to_string().contains("end of file"), "{e}");
        assert_eq!(e.line, 3);
    }

    #[test]
    fn non_finite_numbers_are_refused() {
        for bad in ["nan", "inf", "1e39", "-infinity"] {
            let e = parse_err(&format!("{VIEW}s 0 0 {bad} 1"));
            assert!(e.to_string().contains("number"), "{bad}: {e}");
        }
    }

    #[test]
    fn huge_count_fails_without_allocating() {
        let e = parse_err(&format!("{VIEW}p 4000000000 1 2 3"));
        assert!(e.to_string().contains("end of file"), "{e}");
        let e = parse_err(&format!("{VIEW}p 99999999999"));
        assert!(e.to_string().contains("too large"), "{e}");
    }

    #[test]
    fn degenerate_cameras_are_refused() {
        for cam in [
            "v from 0 0 0 at 0 0 0 up 0 1 0 angle 40",
            "v from 0 0 5 at 0 0 0 up 0 0 1 angle 40",
            "v from 0 0 5 at 0 0 0 up 0 1 0 angle 180",
            "v from 0 0 5 at 0 0 0 up 0 1 0 angle 0",
            "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 resolution 40000 10",
            "v from 0 0 5 at 0 0 0 up 0 1 0",
        ] {
            assert!(matches!(parse_err(cam).kind, ParseErrorKind::Invalid(_)), "{cam}");
        }
    }

    #[test]
    fn default_material_and_degenerate_geometry_warn_with_lines() {
        let s = parse(&format!("{VIEW}s 0 0 0 1\ns 0 0 0 0\np 3 0 0 0 1 1 1 2 2 2\n")).unwrap();
        assert_eq!(s.spheres.len(), 1);
        assert!(s.polygons.is_empty() && s.polygon_vertices.is_empty());
        let lines: Vec<u32> = s.warnings.iter().map(|w| w.line).collect();
        assert_eq!(lines, vec![2, 3, 4]);
        assert_eq!(s.materials, vec![Material::DEFAULT]);
    }

    #[test]
    fn bad_angle_is_reported_at_its_value() {
        let e = parse_err("v from 0 0 5 at 0 0 0 up 0 1 0\n  angle -5");
        assert_eq!((e.line, e.column), (2, 9));
    }

    #[test]
    fn cameras_that_overflow_f32_are_refused() {
        for cam in [
            "v from 0 0 3e38 at 0 0 -3e38 up 0 1 0 angle 40",
            "v from 0 0 3e19 at 0 0 0 up 0 1 0 angle 40",
            "v from 0 0 5 at 0 0 0 up 3e38 3e38 0 angle 40",
        ] {
            assert!(matches!(parse_err(cam).kind, ParseErrorKind::Invalid(_)), "{cam}");
        }
    }

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

    #[test]
    fn light_colour_is_optional_even_before_a_keyword() {
        let s = parse(&format!("{VIEW}l 1 2 3\nl 4 5 6 1 1 1 l 7 8 9")).unwrap();
        let colors: Vec<_> = s.lights.iter().map(|l| l.color.is_some()).collect();
        assert_eq!(colors, vec![false, true, false]);
    }
}
