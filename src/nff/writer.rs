//! Writes a [`Scene`] back out as NFF text (used by `nffrt gen` and round-trip tests).
//!
//! Numbers are printed in Rust's shortest round-trip form, so parsing the output gives
//! back bit-identical `f32` values. Primitives are written kind by kind, with an `f`
//! line whenever the material changes.

use std::io::{self, Write};

use crate::math::Vec3;
use crate::scene::Scene;

struct V(Vec3);

impl std::fmt::Display for V {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} {} {}", self.0.x, self.0.y, self.0.z)
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
    writeln!(w, "angle {}", v.angle)?;
    writeln!(w, "hither {}", v.hither)?;
    writeln!(w, "resolution {} {}", v.width, v.height)?;
    for l in &scene.lights {
        match l.color {
            Some(c) => writeln!(w, "l {} {}", V(l.position), V(c))?,
            None => writeln!(w, "l {}", V(l.position))?,
        }
    }
    let mut current: Option<u32> = None;
    let mut material = |w: &mut dyn Write, m: u32| -> io::Result<()> {
        if current != Some(m) {
            let f = &scene.materials[m as usize];
            writeln!(
                w,
                "f {} {} {} {} {} {}",
                V(f.color),
                f.kd,
                f.ks,
                f.shine,
                f.t,
                f.ior
            )?;
            current = Some(m);
        }
        Ok(())
    };
    for p in &scene.planes {
        material(w, p.material)?;
        let [a, b, c] = p.points;
        writeln!(w, "pl {} {} {}", V(a), V(b), V(c))?;
    }
    for p in &scene.polygons {
        material(w, p.material)?;
        writeln!(w, "p {}", p.count)?;
        for q in scene.polygon_points(p) {
            writeln!(w, "{}", V(*q))?;
        }
    }
    for p in &scene.patches {
        material(w, p.material)?;
        writeln!(w, "pp {}", p.count)?;
        let (vs, ns) = scene.patch_points(p);
        for (q, n) in vs.iter().zip(ns) {
            writeln!(w, "{} {}", V(*q), V(*n))?;
        }
    }
    for s in &scene.spheres {
        material(w, s.material)?;
        writeln!(w, "s {} {}", V(s.center), s.radius)?;
    }
    for c in &scene.cones {
        material(w, c.material)?;
        writeln!(
            w,
            "c {} {} {} {}",
            V(c.base),
            c.base_radius,
            V(c.apex),
            c.apex_radius
        )?;
    }
    for b in &scene.boxes {
        material(w, b.material)?;
        let (lo, hi) = (b.min, b.max);
        writeln!(w, "aabb {} {} {} {} {} {}", lo.x, hi.x, lo.y, hi.y, lo.z, hi.z)?;
    }
    Ok(())
}
