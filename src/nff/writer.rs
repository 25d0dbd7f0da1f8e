//! Writes a [`Scene`] back out as NFF text (used by `nffrt gen` and round-trip tests).
//!
//! Numbers are printed in Rust's shortest round-trip form (in exponent form when
//! tiny or huge), so parsing the output gives back bit-identical `f32` values.
//! Primitives are written in the order of their `line` (the file order of a parsed
//! scene, the SPD's order for a generated one), kinds in a fixed order where lines
//! tie, with an `f` line whenever the material changes. Wrap `w` in a
//! `BufWriter`: the writer makes many small writes.

use std::io::{self, Write};

use crate::math::Vec3;
use crate::scene::Scene;

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
    Cone,
    Box,
}

const KINDS: [Kind; 6] = [
    Kind::Plane,
    Kind::Polygon,
    Kind::Patch,
    Kind::Sphere,
    Kind::Cone,
    Kind::Box,
];

/// The line of the `i`-th primitive of `kind`, if there is one.
fn line_of(scene: &Scene, kind: Kind, i: usize) -> Option<u32> {
    match kind {
        Kind::Plane => scene.planes.get(i).map(|p| p.line),
        Kind::Polygon => scene.polygons.get(i).map(|p| p.line),
        Kind::Patch => scene.patches.get(i).map(|p| p.line),
        Kind::Sphere => scene.spheres.get(i).map(|p| p.line),
        Kind::Cone => scene.cones.get(i).map(|p| p.line),
        Kind::Box => scene.boxes.get(i).map(|p| p.line),
    }
}

/// Writes `scene` as NFF to `w`.
pub fn write_nff(scene: &Scene, w: &mut impl Write) -> io::Result<()> {
    let v = &scene.view;
    writeln!(w, "b {}", V(scene.background))?;
    writeln!(w, "v")?;
    writeln!(w, "from {}", V(v.from))?;
    writeln!(w, "at {}", V(v.at))?;
    writeln!(w, "up {}", V(v.up))?;
    writeln!(w, "angle {}", N(v.angle))?;
    writeln!(w, "hither {}", N(v.hither))?;
    writeln!(w, "resolution {} {}", v.width, v.height)?;
    for l in &scene.lights {
        match l.color {
            Some(c) => writeln!(w, "l {} {}", V(l.position), V(c))?,
            None => writeln!(w, "l {}", V(l.position))?,
        }
    }
    // Compared by value, bit for bit: two table entries with equal values (a parsed
    // `f A`, `f B`, `f A` whose `B` objects were all skipped) are one `f` line, so
    // writing a scene read back from this text gives this text again.
    let mut current: Option<[u32; 8]> = None;
    let mut material = |w: &mut dyn Write, m: u32| -> io::Result<()> {
        let f = &scene.materials[m as usize];
        let bits = [f.color.x, f.color.y, f.color.z, f.kd, f.ks, f.shine, f.t, f.ior].map(f32::to_bits);
        if current != Some(bits) {
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
        }
    }
    Ok(())
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
