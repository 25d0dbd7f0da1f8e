//! Writes a [`Scene`] back out as NFF text (used by `nffrt gen` and round-trip tests)
//! or as P3F text.
//!
//! Numbers are printed in Rust's shortest round-trip form (in exponent form when
//! tiny or huge), so parsing the output gives back bit-identical `f32` values.
//! Primitives are written in the order of their `line` (the file order of a parsed
//! scene, the SPD's order for a generated one), kinds in a fixed order where lines
//! tie, with a material line whenever the material changes. Wrap `w` in a
//! `BufWriter`: the writer makes many small writes.
//!
//! P3F is written in the 2024/25 dialect whatever the scene was read from:
//! `spp`, `accel`, `shutter`, `integrator`, `bclr`, `env`, `camera` (with
//! `aperture` and `focal`), `light punctual` and `light quad` (a 2019 `al` becomes
//! the `light quad` with its corner, edges and grid), `mat` (with the emission when
//! it is not zero and `roughness R` when R is not zero), `s sm c p pp pl`, `box` and
//! `mesh`. Reading it back gives the same scene but for its dialect. NFF has no
//! meshes and no time: written as NFF, a mesh's triangles become `p 3` polygons and
//! a moving sphere the `s` where it stands when the shutter opens (and NFF drops
//! what it cannot say: lens, area lights, specular colours, emission, roughness,
//! skybox, `spp`, `shutter`, `integrator`).

use std::io::{self, Write};

use super::p3f::ROUGHNESS;
use super::Format;
use crate::math::Vec3;
use crate::scene::{Accel, Dialect, Material, Scene, View};

/// A number in shortest round-trip form; exponent form below 1e-4 and from 1e9 on,
/// where plain decimals would be long.
struct N(f32);

impl std::fmt::Display for N {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let a = self.0.abs();
        if a != 0.0 && !(1e-4..1e9).contains(&a) {
            write!(f, "{:e}", self.0)
        } else {
            write!(f, "{}", self.0)
        }
    }
}

struct V(Vec3);

impl std::fmt::Display for V {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} {} {}", N(self.0.x), N(self.0.y), N(self.0.z))
    }
}

/// Primitive kinds in the order they are written when their lines tie.
#[derive(Clone, Copy)]
enum Kind {
    Plane,
    Polygon,
    Patch,
    Sphere,
    MovingSphere,
    Cone,
    Box,
    Mesh,
}

const KINDS: [Kind; 8] = [
    Kind::Plane,
    Kind::Polygon,
    Kind::Patch,
    Kind::Sphere,
    Kind::MovingSphere,
    Kind::Cone,
    Kind::Box,
    Kind::Mesh,
];

/// The line of the `i`-th primitive of `kind`, if there is one.
fn line_of(scene: &Scene, kind: Kind, i: usize) -> Option<u32> {
    match kind {
        Kind::Plane => scene.planes.get(i).map(|p| p.line),
        Kind::Polygon => scene.polygons.get(i).map(|p| p.line),
        Kind::Patch => scene.patches.get(i).map(|p| p.line),
        Kind::Sphere => scene.spheres.get(i).map(|p| p.line),
        Kind::MovingSphere => scene.moving_spheres.get(i).map(|p| p.line),
        Kind::Cone => scene.cones.get(i).map(|p| p.line),
        Kind::Box => scene.boxes.get(i).map(|p| p.line),
        Kind::Mesh => scene.meshes.get(i).map(|p| p.line),
    }
}

/// Writes `scene` as NFF to `w`.
pub fn write_nff(scene: &Scene, w: &mut impl Write) -> io::Result<()> {
    write_in(scene, Format::Nff, w)
}

/// Writes `scene` as P3F (the 2024/25 dialect; see the module docs) to `w`.
pub fn write_p3f(scene: &Scene, w: &mut impl Write) -> io::Result<()> {
    write_in(scene, Format::P3f, w)
}

/// Writes `scene` in its own language: NFF for an NFF scene, P3F otherwise.
pub fn write_scene(scene: &Scene, w: &mut impl Write) -> io::Result<()> {
    let format = if scene.dialect.is_p3f() {
        Format::P3f
    } else {
        Format::Nff
    };
    write_in(scene, format, w)
}

/// The camera block of `view` as a file of `dialect` writes it, one sub-keyword per
/// line: `v` for NFF (no lens) and P3F 2019/20 (with `aperture` and `focal`),
/// `camera` (with `eye`) for P3F 2024/25.
pub fn view_block(view: &View, dialect: Dialect) -> String {
    let v = view;
    let (head, eye) = match dialect {
        Dialect::P3f2025 => ("camera", "eye"),
        Dialect::Nff | Dialect::P3f2019 | Dialect::Aff => ("v", "from"),
    };
    let mut out = format!(
        "{head}\n{eye} {}\nat {}\nup {}\nangle {}\nhither {}\nresolution {} {}\n",
        V(v.from),
        V(v.at),
        V(v.up),
        N(v.angle),
        N(v.hither),
        v.width,
        v.height
    );
    if dialect.is_p3f() {
        out += &format!("aperture {}\nfocal {}\n", N(v.aperture), N(v.focal));
    }
    out
}

fn write_in(scene: &Scene, format: Format, w: &mut impl Write) -> io::Result<()> {
    let p3f = format == Format::P3f;
    if p3f {
        if let Some(n) = scene.spp {
            writeln!(w, "spp {n}")?;
        }
        if let Some(a) = scene.accel {
            let name = match a {
                Accel::None => "none",
                Accel::Grid => "grid",
                Accel::Bvh => "bvh",
            };
            writeln!(w, "accel {name}")?;
        }
        if let Some([open, close]) = scene.shutter {
            writeln!(w, "shutter {} {}", N(open), N(close))?;
        }
        if let Some(i) = scene.integrator {
            writeln!(w, "integrator {}", i.name())?;
        }
        writeln!(w, "bclr {}", V(scene.background))?;
        if let Some(e) = &scene.environment {
            writeln!(w, "env {}", e.folder)?;
        }
    } else {
        writeln!(w, "b {}", V(scene.background))?;
    }
    let dialect = if p3f { Dialect::P3f2025 } else { Dialect::Nff };
    write!(w, "{}", view_block(&scene.view, dialect))?;
    for l in &scene.lights {
        match (p3f, l.area, l.color) {
            (true, None, c) => writeln!(
                w,
                "light punctual {} {}",
                V(l.position),
                V(c.unwrap_or(Vec3::ONE))
            )?,
            (true, Some(a), c) => writeln!(
                w,
                "light quad {} {} {} {} {}",
                V(l.position),
                V(c.unwrap_or(Vec3::ONE)),
                V(a.v1),
                V(a.v2),
                a.grid
            )?,
            (false, _, Some(c)) => writeln!(w, "l {} {}", V(l.position), V(c))?,
            (false, _, None) => writeln!(w, "l {}", V(l.position))?,
        }
    }
    // Compared by value, bit for bit: two table entries with equal values (a parsed
    // `f A`, `f B`, `f A` whose `B` objects were all skipped) are one material line,
    // so writing a scene read back from this text gives this text again.
    let mut current: Option<[u32; 15]> = None;
    let mut material = |w: &mut dyn Write, m: u32| -> io::Result<()> {
        let f = &scene.materials[m as usize];
        let bits = [
            f.color.x,
            f.color.y,
            f.color.z,
            f.kd,
            f.specular.x,
            f.specular.y,
            f.specular.z,
            f.ks,
            f.shine,
            f.t,
            f.ior,
            f.emission.x,
            f.emission.y,
            f.emission.z,
            f.roughness,
        ]
        .map(f32::to_bits);
        if current != Some(bits) {
            if p3f {
                writeln!(w, "{}", p3f_material(f))?;
            } else {
                writeln!(
                    w,
                    "f {} {} {} {} {} {}",
                    V(f.color),
                    N(f.kd),
                    N(f.ks),
                    N(f.shine),
                    N(f.t),
                    N(f.ior)
                )?;
            }
            current = Some(bits);
        }
        Ok(())
    };
    // Merge the per-kind lists (each in line order) by line.
    let mut next = [0usize; KINDS.len()];
    loop {
        let pick = (0..KINDS.len())
            .filter_map(|k| line_of(scene, KINDS[k], next[k]).map(|l| (l, k)))
            .min();
        let Some((_, k)) = pick else { break };
        let i = next[k];
        next[k] += 1;
        match KINDS[k] {
            Kind::Plane => {
                let p = &scene.planes[i];
                material(w, p.material)?;
                let [a, b, c] = p.points;
                writeln!(w, "pl {} {} {}", V(a), V(b), V(c))?;
            }
            Kind::Polygon => {
                let p = &scene.polygons[i];
                material(w, p.material)?;
                writeln!(w, "p {}", p.count)?;
                for q in scene.polygon_points(p) {
                    writeln!(w, "{}", V(*q))?;
                }
            }
            Kind::Patch => {
                let p = &scene.patches[i];
                material(w, p.material)?;
                writeln!(w, "pp {}", p.count)?;
                let (vs, ns) = scene.patch_points(p);
                for (q, n) in vs.iter().zip(ns) {
                    writeln!(w, "{} {}", V(*q), V(*n))?;
                }
            }
            Kind::Sphere => {
                let s = &scene.spheres[i];
                material(w, s.material)?;
                writeln!(w, "s {} {}", V(s.center), N(s.radius))?;
            }
            Kind::MovingSphere if p3f => {
                let s = &scene.moving_spheres[i];
                material(w, s.material)?;
                writeln!(
                    w,
                    "sm {}  {}  {}  {} {}",
                    V(s.center0),
                    V(s.center1),
                    N(s.radius),
                    N(s.time0),
                    N(s.time1)
                )?;
            }
            Kind::MovingSphere => {
                let s = &scene.moving_spheres[i];
                material(w, s.material)?;
                let [open, _] = scene.shutter_interval();
                writeln!(w, "s {} {}", V(s.center_at(open)), N(s.radius))?;
            }
            Kind::Cone => {
                let c = &scene.cones[i];
                material(w, c.material)?;
                writeln!(
                    w,
                    "c {} {} {} {}",
                    V(c.base),
                    N(c.base_radius),
                    V(c.apex),
                    N(c.apex_radius)
                )?;
            }
            Kind::Box if p3f => {
                let b = &scene.boxes[i];
                material(w, b.material)?;
                writeln!(w, "box {} {}", V(b.min), V(b.max))?;
            }
            Kind::Box => {
                let b = &scene.boxes[i];
                material(w, b.material)?;
                let (lo, hi) = (b.min, b.max);
                writeln!(
                    w,
                    "aabb {} {} {} {} {} {}",
                    N(lo.x),
                    N(hi.x),
                    N(lo.y),
                    N(hi.y),
                    N(lo.z),
                    N(hi.z)
                )?;
            }
            Kind::Mesh => {
                let m = &scene.meshes[i];
                material(w, m.material)?;
                let first = m.first_vertex as usize;
                let vertices = &scene.mesh_vertices[first..first + m.vertex_count as usize];
                let triangles = scene.mesh_triangles_of(m);
                if p3f {
                    writeln!(w, "mesh {} {}", vertices.len(), triangles.len())?;
                    for v in vertices {
                        writeln!(w, "{}", V(*v))?;
                    }
                    for t in triangles {
                        let [a, b, c] = t.vertices.map(|k| k - m.first_vertex + 1);
                        writeln!(w, "{a} {b} {c}")?;
                    }
                } else {
                    for t in triangles {
                        let [a, b, c] = t.vertices.map(|k| V(scene.mesh_vertices[k as usize]));
                        writeln!(w, "p 3\n{a}\n{b}\n{c}")?;
                    }
                }
            }
        }
    }
    Ok(())
}

/// A P3F `mat` line: the 11 numbers, the emission unless it is zero, the
/// roughness suffix unless it is zero.
fn p3f_material(f: &Material) -> String {
    let mut line = format!(
        "mat {} {} {} {} {} {} {}",
        V(f.color),
        N(f.kd),
        V(f.specular),
        N(f.ks),
        N(f.shine),
        N(f.t),
        N(f.ior)
    );
    if f.emission != Vec3::ZERO {
        line += &format!(" {}", V(f.emission));
    }
    if f.roughness != 0.0 {
        line += &format!(" {ROUGHNESS} {}", N(f.roughness));
    }
    line
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nff::parse;

    fn round_trip(src: &str) -> (Scene, String) {
        let scene = parse(src).unwrap();
        let mut out = Vec::new();
        write_nff(&scene, &mut out).unwrap();
        (scene, String::from_utf8(out).unwrap())
    }

    #[test]
    fn keeps_file_order_across_kinds() {
        let src = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\n\
                   f 1 0 0 1 0 1 0 1\nc 0 0 0 1 0 0 1 1\ns 0 0 1 1\nf 0 1 0 1 0 1 0 1\nc 0 0 1 1 0 0 2 1\ns 0 0 2 1\n";
        let (scene, text) = round_trip(src);
        let kinds: Vec<&str> = text
            .lines()
            .filter_map(|l| l.split(' ').next())
            .filter(|k| ["c", "s", "f"].contains(k))
            .collect();
        assert_eq!(kinds, ["f", "c", "s", "f", "c", "s"]);
        let back = parse(&text).unwrap();
        assert_eq!(
            back.spheres.iter().map(|s| s.center).collect::<Vec<_>>(),
            scene.spheres.iter().map(|s| s.center).collect::<Vec<_>>()
        );
        assert_eq!(back.materials, scene.materials);
    }

    /// Found by the `parse` fuzz target: a material repeated after one whose only
    /// object was skipped made the written text change on a second round trip.
    #[test]
    fn writing_is_a_fixpoint_when_a_material_repeats_around_a_skipped_object() {
        let src = "f 1 0 0 1 0 1 0 1\ns 0 0 0 1\nf 0 1 0 1 0 1 0 1\ns 0 0 0 0\n\
                   f 1 0 0 1 0 1 0 1\ns 1 0 0 1\n";
        let (scene, first) = round_trip(src);
        assert_eq!(scene.materials.len(), 3);
        assert_eq!(
            first.lines().filter(|l| l.starts_with("f ")).count(),
            1,
            "{first}"
        );
        let (_, second) = round_trip(&first);
        assert_eq!(first, second);
    }

    #[test]
    fn p3f_additions_are_spelled_back_and_nff_keeps_a_moving_sphere_where_the_shutter_opens() {
        let src = "shutter 0.5 2\nintegrator path\ncamera eye 0 0 5 at 0 0 0 up 0 1 0 angle 40\n\
                   mat 1 1 1 1 1 1 1 0 10 0 1 4 5 6 roughness 0.25\nsm 0 0 0 2 4 6 0.5 0 1\n\
                   mat 1 1 1 1 1 1 1 0 10 0 1\ns 1 1 1 1\n";
        let scene = crate::nff::parse_format(src.as_bytes(), Format::P3f, &Default::default()).unwrap();
        let mut p3f = Vec::new();
        write_p3f(&scene, &mut p3f).unwrap();
        let p3f = String::from_utf8(p3f).unwrap();
        for line in [
            "shutter 0.5 2",
            "integrator path",
            "mat 1 1 1 1 1 1 1 0 10 0 1 4 5 6 roughness 0.25",
            "sm 0 0 0  2 4 6  0.5  0 1",
            "mat 1 1 1 1 1 1 1 0 10 0 1",
        ] {
            assert!(p3f.lines().any(|l| l == line), "{line:?} not in\n{p3f}");
        }
        // NFF: the sphere at t = 0.5 (half way from (0, 0, 0) to (2, 4, 6)), no
        // shutter, integrator, emission or roughness.
        let mut nff = Vec::new();
        write_nff(&scene, &mut nff).unwrap();
        let nff = String::from_utf8(nff).unwrap();
        assert!(nff.lines().any(|l| l == "s 1 2 3 0.5"), "{nff}");
        let back = parse(&nff).unwrap();
        assert_eq!(back.spheres.len(), 2);
        assert!(!nff.contains("shutter") && !nff.contains("integrator") && !nff.contains("rough"));
    }

    #[test]
    fn tiny_and_huge_numbers_use_exponents_and_round_trip() {
        assert_eq!(N(-2.55836e-17).to_string(), "-2.55836e-17");
        assert_eq!(N(3e12).to_string(), "3e12");
        assert_eq!(N(0.5).to_string(), "0.5");
        assert_eq!(N(-0.0).to_string(), "-0");
        for x in [
            1e-30f32,
            1.2345678e-5,
            0.1,
            123456.79,
            1e9,
            f32::MAX,
            f32::MIN_POSITIVE,
        ] {
            assert_eq!(N(x).to_string().parse::<f32>().unwrap(), x);
        }
    }
}
