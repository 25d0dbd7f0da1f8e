//! AFF's entities that are neither geometry nor transforms, and NFF's, read by NFF's
//! readers and filed into the transform node they stand in: one function per
//! keyword, each quoting its syntax.

use super::error::Read;
use super::parser::{invalid, loc, FileParser};
use super::scene::{AnimationSpan, FillMaterial, LightPlace, Shape};
use crate::math::Vec3;
use crate::nff::Token;
use crate::scene::Material;

impl FileParser<'_, '_, '_> {
    /// NFF's `v b l f s c p pp`, as NFF reads them. Objects join the innermost
    /// transform node, in its local space; a light without a colour is white (the
    /// original's default, where NFF's is an intensity shared by all lights).
    pub(super) fn nff_entity(&mut self, kw: &Token) -> Read {
        let before = counts(self.p.scene());
        match self.p.read_entity(kw) {
            Some(read) => read?,
            None => return Err(super::keywords::unknown(kw).into()),
        }
        let scene = self.p.scene();
        let mut added = Vec::new();
        added.extend(
            (before[0]..scene.spheres.len()).map(|i| (Shape::Sphere(i as u32), scene.spheres[i].material)),
        );
        added
            .extend((before[1]..scene.cones.len()).map(|i| (Shape::Cone(i as u32), scene.cones[i].material)));
        added.extend(
            (before[2]..scene.polygons.len()).map(|i| (Shape::Polygon(i as u32), scene.polygons[i].material)),
        );
        added.extend(
            (before[3]..scene.patches.len()).map(|i| (Shape::Patch(i as u32), scene.patches[i].material)),
        );
        for (shape, material) in added {
            self.add_object(shape, material, kw);
        }
        let triangles = self.b.placed_triangles + self.b.scene.animated_triangles.len();
        self.within_primitives(triangles, kw)?;
        let node = self.b.node();
        for light in &mut self.p.scene_mut().lights[before[4]..] {
            light.color.get_or_insert(Vec3::ONE);
            self.b.scene.light_places.push(LightPlace {
                node,
                name: None,
                track: None,
            });
        }
        self.sync_fills();
        Ok(())
    }

    /// `la NAME x y z [r g b]`: a light that the keyframe block `NAME` moves (its
    /// translation places it).
    pub(super) fn named_light(&mut self, kw: &Token) -> Read {
        let (name, _) = self.name("the light's name")?;
        let l = Token { text: b"l", ..*kw };
        self.nff_entity(&l)?;
        if let Some(last) = self.b.scene.light_places.last_mut() {
            last.name = Some(name);
        }
        Ok(())
    }

    /// `fm ar ag ab  dr dg db  sr sg sb  shine T ior`: ambient, diffuse and specular
    /// colours, Phong exponent, transmittance and index of refraction.
    ///
    /// Kept as the material `f dr dg db 1 Ks 4*shine T ior` with `Ks` the largest
    /// specular component, the specular colour over `Ks` as its tint (so `Ks` times
    /// the tint is the specular colour) and the ambient colour as its ambient
    /// reflectance, which AFF's rules shade as the original does (`render/shade.rs`).
    pub(super) fn fill_material(&mut self, _kw: &Token) -> Read {
        let fill = FillMaterial {
            ambient: self.p.vec3("'fm' ambient r g b")?,
            diffuse: self.p.vec3("'fm' diffuse r g b")?,
            specular: self.p.vec3("'fm' specular r g b")?,
            shine: self.p.number("'fm' Phong exponent")?,
            t: self.p.number("'fm' transmittance")?,
            ior: self.p.number("'fm' index of refraction")?,
        };
        let ks = fill.specular.max_elem().max(0.0);
        let material = Material {
            color: fill.diffuse,
            kd: 1.0,
            specular: if ks > 0.0 { fill.specular / ks } else { Vec3::ONE },
            ks,
            shine: 4.0 * fill.shine,
            t: fill.t,
            ior: fill.ior,
            ambient: fill.ambient,
            ..Material::DEFAULT
        };
        self.sync_fills();
        // One entry per distinct material: the robot scene's 291 includes of one
        // material file make one.
        let known = self
            .b
            .scene
            .fills
            .iter()
            .zip(&self.p.scene().materials)
            .position(|(f, m)| *f == Some(fill) && *m == material);
        match known {
            Some(i) => self.p.use_material(i as u32),
            None => {
                self.p.set_material(material);
                self.b.scene.fills.push(Some(fill));
            }
        }
        Ok(())
    }

    /// Pads [`super::AffScene::fills`] to the material table (`f` and the default
    /// material have no `fm`).
    fn sync_fills(&mut self) {
        let n = self.p.scene().materials.len();
        self.b.scene.fills.resize(n, None);
    }

    /// `am r g b`: the global ambient light.
    pub(super) fn ambient(&mut self, _kw: &Token) -> Read {
        self.b.scene.ambient = self.p.vec3("ambient light r g b")?;
        Ok(())
    }

    /// `a START END FRAMES`: the animation's span, frames evenly spaced from `START`
    /// to `END` inclusive.
    pub(super) fn animation_span(&mut self, kw: &Token) -> Read {
        let start = self.p.number("the animation's start time")?;
        let end_at = self.p.peek().map(|t| loc(&t));
        let end = self.p.number("the animation's end time")?;
        let (frames, frames_at) = self.p.count("the animation's frame count")?;
        if frames == 0 {
            return Err(invalid(frames_at, "an animation needs at least one frame").into());
        }
        if end < start {
            return Err(invalid(
                end_at.unwrap_or(loc(kw)),
                format!("the animation ends ({end}) before it starts ({start})"),
            )
            .into());
        }
        if self.b.scene.span.is_some() {
            self.warn(kw, "a second 'a' replaces the first".into());
        }
        self.b.scene.span = Some(AnimationSpan {
            start,
            end,
            frames,
            at: self.at(kw),
        });
        Ok(())
    }

    /// `i DETAIL NAME`: the file `NAME` (from this file's directory), read here, if
    /// `DETAIL` is at most the scene's detail level (`d`, 0 by default).
    pub(super) fn include(&mut self, _kw: &Token) -> Read {
        let (detail, _) = self.integer("the include's detail level")?;
        let (name, name_at) = self.name("the name of the file to include")?;
        if detail > self.b.detail {
            self.b.scene.skipped_inclusions += 1;
            return Ok(());
        }
        self.include_file(&name, name_at)
    }

    /// `d LEVEL`: the detail level; later includes of a higher one are skipped.
    pub(super) fn detail_level(&mut self, _kw: &Token) -> Read {
        self.b.detail = self.integer("the detail level")?.0;
        Ok(())
    }
}

/// The numbers of spheres, cones, polygons, patches and lights of `s`.
fn counts(s: &crate::scene::Scene) -> [usize; 5] {
    [
        s.spheres.len(),
        s.cones.len(),
        s.polygons.len(),
        s.patches.len(),
        s.lights.len(),
    ]
}
