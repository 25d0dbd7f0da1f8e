//! The Whitted recursion: closest hit, shadows, reflection and refraction.
//!
//! The recursion reports what it does to a [`Recorder`]. The renderer passes
//! [`NoRecord`], whose `ENABLED = false` turns every report into dead code, so the
//! hot path pays nothing; `--pixel` passes a recorder that builds the ray tree
//! (`render::debug`). One code path thus both renders and explains a pixel.

use super::background::Background;
use super::shade::{reflect, refract, Lighting};
use super::stats::Stats;
use std::cell::Cell;

use crate::accel::{Bvh, NO_HINT, PACKET};
use crate::geometry::{Hit, Primitive};
use crate::image::skybox::SkyTexel;
use crate::math::{Ray, Vec3};
use crate::scene::{Material, Scene};

/// Secondary-ray origins are pushed off the surface by this fraction of the
/// magnitude of the coordinates involved (see [`offset_scale`]).
const OFFSET_REL: f32 = 4e-6;

/// Everything needed to trace rays through one scene.
pub struct Tracer<'a> {
    bvh: &'a Bvh,
    materials: &'a [Material],
    lighting: Lighting,
    background: Background,
    max_depth: u32,
}

/// A hit as reported to a [`Recorder`].
#[derive(Clone, Copy, Debug)]
pub struct HitRecord<'a> {
    /// Ray-tree depth of the ray (the eye ray is 1).
    pub depth: u32,
    /// The primitive hit (with its source kind and line).
    pub primitive: &'a Primitive,
    /// Distance along the (unit-direction) ray.
    pub t: f32,
    /// The hit point.
    pub point: Vec3,
    /// The geometric normal turned to face the ray.
    pub normal: Vec3,
    /// The shading normal turned to face the ray.
    pub shading_normal: Vec3,
    /// True if the ray crosses the surface against the primitive's own normal.
    pub entering: bool,
    /// The ambient term `A * Kd * C`.
    pub ambient: Vec3,
}

/// What became of one light at a hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightOutcome {
    /// The light is behind the surface: no shadow ray (SPD rule).
    Behind,
    /// A shadow ray found an object between the point and the light.
    Shadowed,
    /// The light's diffuse + specular contribution.
    Lit(Vec3),
}

/// The kind of a secondary ray.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Branch {
    /// Mirror reflection (weight Ks).
    Reflection,
    /// Mirror reflection under total internal reflection (weight Ks + T).
    TotalInternalReflection,
    /// Refraction (weight T).
    Refraction,
}

/// Receives the events of the Whitted recursion, depth first: for each ray either
/// `miss`, or `hit`, one `light` per light, then for each secondary ray `branch`
/// followed by that ray's own events, and finally `done` with the hit's colour.
pub trait Recorder {
    /// False for a recorder that ignores everything: the tracer then skips building
    /// the reports altogether.
    const ENABLED: bool = true;
    /// The ray left the scene and sees `background`, from skybox texel `texel` if
    /// the background is a skybox.
    fn miss(&mut self, _ray: &Ray, _background: Vec3, _texel: Option<SkyTexel>) {}
    /// The ray hit a surface.
    fn hit(&mut self, _ray: &Ray, _hit: &HitRecord) {}
    /// Light `index` (in file order) at the current hit.
    fn light(&mut self, _index: usize, _outcome: LightOutcome) {}
    /// A secondary ray with this weight is about to be traced.
    fn branch(&mut self, _kind: Branch, _weight: f32) {}
    /// The current hit's final colour.
    fn done(&mut self, _color: Vec3) {}
}

/// The recorder of ordinary renders: records nothing, costs nothing.
pub struct NoRecord;

impl Recorder for NoRecord {
    const ENABLED: bool = false;
}

/// Lights and ray-tree depths with a shadow cache slot; shadow rays of other lights
/// or deeper bounces simply go without one.
const HINT_LIGHTS: usize = 8;
const HINT_DEPTHS: usize = 8;

thread_local! {
    /// Shadow cache (Haines): per light and depth, the primitive or leaf block of four
    /// that last blocked a shadow ray on this thread (`Bvh::occluded_hinted`). It only
    /// changes what is tested first, never an answer; it is cleared at the start of every row (see
    /// [`reset_shadow_cache`]) so each row's work is the same whichever thread runs it.
    static SHADOW_HINTS: [Cell<u32>; HINT_LIGHTS * HINT_DEPTHS] =
        const { [const { Cell::new(NO_HINT) }; HINT_LIGHTS * HINT_DEPTHS] };
}

/// Empties this thread's shadow cache (call before each independent unit of work).
pub fn reset_shadow_cache() {
    SHADOW_HINTS.with(|hints| hints.iter().for_each(|h| h.set(NO_HINT)));
}

/// How far to push a secondary ray's origin off the surface at `p`, hit by `ray`
/// at distance `t`: proportional to the floating-point error of `p = o + t d`, so it
/// works for tiny and huge scenes alike (no global epsilon).
#[inline]
fn offset_scale(p: Vec3, ray: &Ray, t: f32) -> f32 {
    OFFSET_REL * (p.abs().max_elem() + ray.origin.abs().max_elem() + t) + f32::MIN_POSITIVE
}

/// An eye ray's colour for the image: a NaN or infinity never reaches it (black).
#[inline]
fn finite_or_black(c: Vec3) -> Vec3 {
    if c.is_finite() {
        c
    } else {
        Vec3::ZERO
    }
}

impl<'a> Tracer<'a> {
    /// Prepares lighting for `scene`, traced through `bvh`.
    pub fn new(scene: &'a Scene, bvh: &'a Bvh, max_depth: u32) -> Self {
        Tracer {
            bvh,
            materials: &scene.materials,
            lighting: Lighting::new(scene),
            background: Background::of(scene),
            max_depth,
        }
    }

    /// Traces an eye ray (depth 1), counting it.
    #[inline]
    pub fn trace_eye(&self, ray: &Ray, stats: &mut Stats) -> Vec3 {
        self.trace_eye_recorded(ray, stats, &mut NoRecord)
    }

    /// Traces an eye ray like [`Tracer::trace_eye`], reporting to `rec`.
    #[inline]
    pub fn trace_eye_recorded<R: Recorder>(&self, ray: &Ray, stats: &mut Stats, rec: &mut R) -> Vec3 {
        stats.eye_rays += 1;
        finite_or_black(self.trace(ray, 1, stats, rec))
    }

    /// The colour seen along `ray` at ray-tree depth `depth`.
    fn trace<R: Recorder>(&self, ray: &Ray, depth: u32, stats: &mut Stats, rec: &mut R) -> Vec3 {
        let found = self.bvh.closest_hit(ray, f32::INFINITY);
        self.shade(ray, depth, found, stats, rec)
    }

    /// Eye rays (depth 1) a row at a time, [`PACKET`] neighbours traced through the
    /// BVH together, each then shaded as [`Tracer::trace_eye`] shades it (packets find
    /// the very hits single rays find, so the colours are the same); appends the
    /// colours to `out`.
    pub fn trace_eye_row(&self, rays: &[Ray], stats: &mut Stats, out: &mut Vec<Vec3>) {
        let mut hits = [None; PACKET];
        for packet in rays.chunks(PACKET) {
            let hits = &mut hits[..packet.len()];
            self.bvh.closest_hit_packet(packet, f32::INFINITY, hits);
            for (ray, &found) in packet.iter().zip(hits.iter()) {
                stats.eye_rays += 1;
                out.push(finite_or_black(self.shade(ray, 1, found, stats, &mut NoRecord)));
            }
        }
    }

    /// The colour seen along `ray` (at ray-tree depth `depth`) given its closest hit.
    fn shade<R: Recorder>(
        &self,
        ray: &Ray,
        depth: u32,
        found: Option<(Hit, u32)>,
        stats: &mut Stats,
        rec: &mut R,
    ) -> Vec3 {
        let Some((hit, index)) = found else {
            let (color, texel) = self.background.look(ray.dir);
            if R::ENABLED {
                rec.miss(ray, color, texel);
            }
            return color;
        };
        if depth == 1 {
            stats.eye_hits += 1;
        } else {
            stats.secondary_hits += 1;
        }
        let prim = self.bvh.primitive(index);
        let surface = prim.surface(ray, &hit, self.bvh.data());
        let m = &self.materials[prim.material as usize];
        let p = surface.point;
        // Turn the normals to face the incoming ray; `entering` says whether the ray
        // crosses the surface against the primitive's own normal (into the object).
        let entering = surface.normal.dot(ray.dir) < 0.0;
        let (n, ns) = if entering {
            (surface.normal, surface.shading_normal)
        } else {
            (-surface.normal, -surface.shading_normal)
        };
        let eps = offset_scale(p, ray, hit.t);
        let above = p + n * eps;
        let view = -ray.dir;

        let diffuse = m.color * m.kd;
        let mut color = self.lighting.ambient.mul_elem(diffuse);
        if R::ENABLED {
            let record = HitRecord {
                depth,
                primitive: prim,
                t: hit.t,
                point: p,
                normal: n,
                shading_normal: ns,
                entering,
                ambient: color,
            };
            rec.hit(ray, &record);
        }
        for (k, &(light_pos, intensity)) in self.lighting.lights.iter().enumerate() {
            let to_light = light_pos - above;
            // No shadow ray when the light is behind the surface (SPD rule 6).
            if n.dot(to_light) <= 0.0 {
                if R::ENABLED {
                    rec.light(k, LightOutcome::Behind);
                }
                continue;
            }
            stats.shadow_rays += 1;
            // Aimed at the light unnormalized, blockers sought below t = 1: the ray's
            // reciprocal direction then no longer waits on a square root and a
            // division (the longest chain in setting up a shadow ray); the
            // intersection tests do not need unit directions.
            let shadow_ray = Ray::new(above, to_light);
            let slot = k * HINT_DEPTHS + (depth as usize - 1);
            let blocked = if k < HINT_LIGHTS && (depth as usize) <= HINT_DEPTHS {
                SHADOW_HINTS.with(|hints| self.bvh.occluded_hinted(&shadow_ray, 1.0, &hints[slot]))
            } else {
                self.bvh.occluded(&shadow_ray, 1.0)
            };
            if blocked {
                stats.shadow_blocked += 1;
                if R::ENABLED {
                    rec.light(k, LightOutcome::Shadowed);
                }
                continue;
            }
            let l = to_light / to_light.length();
            let lambert = ns.dot(l).max(0.0);
            let h = (l + view).normalize();
            // A negative exponent would turn a zero cosine into infinity.
            let phong = if m.ks > 0.0 {
                m.ks * ns.dot(h).max(0.0).powf(m.shine.max(0.0))
            } else {
                0.0
            };
            let contribution = intensity.mul_elem(diffuse * lambert + Vec3::splat(phong));
            if R::ENABLED {
                rec.light(k, LightOutcome::Lit(contribution));
            }
            color += contribution;
        }

        if depth >= self.max_depth || (m.ks <= 0.0 && m.t <= 0.0) {
            if R::ENABLED {
                rec.done(color);
            }
            return color;
        }
        let mut reflect_weight = m.ks;
        let mut reflect_kind = Branch::Reflection;
        if m.t > 0.0 {
            // Indices of refraction of 0 or less (seen on opaque materials) mean 1.
            let ior = if m.ior > 0.0 { m.ior } else { 1.0 };
            let eta = if entering { 1.0 / ior } else { ior };
            match refract(ray.dir, n, eta) {
                Some(dir) => {
                    stats.refraction_rays += 1;
                    let below = p - n * eps;
                    if R::ENABLED {
                        rec.branch(Branch::Refraction, m.t);
                    }
                    color += self.trace(&Ray::new(below, dir), depth + 1, stats, rec) * m.t;
                }
                // Total internal reflection: the transmitted share goes to the mirror ray.
                None => {
                    reflect_weight += m.t;
                    reflect_kind = Branch::TotalInternalReflection;
                }
            }
        }
        stats.reflection_rays += 1;
        let r = Ray::new(above, reflect(ray.dir, n));
        if R::ENABLED {
            rec.branch(reflect_kind, reflect_weight);
        }
        let color = color + self.trace(&r, depth + 1, stats, rec) * reflect_weight;
        if R::ENABLED {
            rec.done(color);
        }
        color
    }
}
