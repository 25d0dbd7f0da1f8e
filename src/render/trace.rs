//! The Whitted recursion: closest hit, shadows, reflection and refraction.
//!
//! The recursion reports what it does to a [`Recorder`]. The renderer passes
//! [`NoRecord`], whose `ENABLED = false` turns every report into dead code, so the
//! hot path pays nothing; `--pixel` passes a recorder that builds the ray tree
//! (`render::debug`). One code path thus both renders and explains a pixel.

use super::background::Background;
use super::light::{LightSampling, LightSource};
use super::sampling::SampleId;
use super::shade::{local, reflect, Lighting, Model, P3fRules, Rules, SpdRules};
use super::stats::Stats;
use super::RenderOptions;
use std::cell::Cell;

pub use super::shade::Branch;
use crate::accel::{Bvh, NO_HINT, PACKET};
use crate::geometry::{point_error, Hit, Primitive};
use crate::image::skybox::SkyTexel;
use crate::math::{Ray, Vec3};
use crate::scene::{Material, Scene};

/// Everything needed to trace rays through one scene.
pub struct Tracer<'a> {
    bvh: &'a Bvh,
    materials: &'a [Material],
    lighting: Lighting,
    light_sampling: LightSampling,
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

/// What became of one point of a light at a hit (the whole of a point light).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub enum LightOutcome {
    /// The point is behind the surface: no shadow ray (SPD rule).
    Behind,
    /// A shadow ray found an object between the hit and the point.
    Shadowed,
    /// The point's diffuse + specular contribution.
    Lit(Vec3),
}

/// What became of an area light at a hit: its points' outcomes summed up.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct AreaOutcome {
    /// Points sampled.
    pub samples: u32,
    /// Of those, points behind the surface (no shadow ray).
    pub behind: u32,
    /// Of those, points whose shadow ray was blocked.
    pub shadowed: u32,
    /// The light's total contribution.
    pub contribution: Vec3,
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
    /// Point light `index` (in file order) at the current hit.
    fn light(&mut self, _index: usize, _outcome: LightOutcome) {}
    /// One point of area light `index` at the current hit, with that point's share.
    fn light_sample(&mut self, _index: usize, _point: Vec3, _outcome: LightOutcome) {}
    /// Area light `index` at the current hit, after its points.
    fn area_light(&mut self, _index: usize, _outcome: AreaOutcome) {}
    /// A secondary ray with this weight is about to be traced.
    fn branch(&mut self, _kind: Branch, _weight: Vec3) {}
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
    /// Prepares lighting for `scene`, traced through `bvh` with the depth and light
    /// sampling of `opts`.
    pub fn new(scene: &'a Scene, bvh: &'a Bvh, opts: &RenderOptions) -> Self {
        Tracer {
            bvh,
            materials: &scene.materials,
            lighting: Lighting::new(scene),
            light_sampling: LightSampling {
                grid_override: opts.light_samples,
                soft_shadows: opts.soft_shadows,
            },
            background: Background::of(scene),
            max_depth: opts.max_depth,
        }
    }

    /// Traces the eye ray of sample `id` (depth 1), counting it.
    #[inline]
    pub fn trace_eye(&self, ray: &Ray, id: &SampleId, stats: &mut Stats) -> Vec3 {
        self.trace_eye_recorded(ray, id, stats, &mut NoRecord)
    }

    /// Traces an eye ray like [`Tracer::trace_eye`], reporting to `rec`.
    #[inline]
    pub fn trace_eye_recorded<R: Recorder>(
        &self,
        ray: &Ray,
        id: &SampleId,
        stats: &mut Stats,
        rec: &mut R,
    ) -> Vec3 {
        stats.eye_rays += 1;
        finite_or_black(match self.lighting.model {
            Model::Spd => self.trace::<R, SpdRules>(ray, 1, id, stats, rec),
            Model::P3f => self.trace::<R, P3fRules>(ray, 1, id, stats, rec),
        })
    }

    /// The colour seen along `ray` at ray-tree depth `depth`, under model `M`.
    fn trace<R: Recorder, M: Rules>(
        &self,
        ray: &Ray,
        depth: u32,
        id: &SampleId,
        stats: &mut Stats,
        rec: &mut R,
    ) -> Vec3 {
        let found = self.bvh.closest_hit(ray, f32::INFINITY);
        self.shade::<R, M>(ray, depth, found, id, stats, rec)
    }

    /// Eye rays (depth 1) a row at a time, [`PACKET`] neighbours traced through the
    /// BVH together, each then shaded as [`Tracer::trace_eye`] shades it (packets find
    /// the very hits single rays find, so the colours are the same); appends the
    /// colours to `out`. Ray `i` is the single sample of pixel `(x0 + i, y)`.
    pub fn trace_eye_row(&self, rays: &[Ray], (x0, y): (u32, u32), stats: &mut Stats, out: &mut Vec<Vec3>) {
        let mut hits = [None; PACKET];
        let mut x = x0;
        for packet in rays.chunks(PACKET) {
            let hits = &mut hits[..packet.len()];
            self.bvh.closest_hit_packet(packet, f32::INFINITY, hits);
            for (ray, &found) in packet.iter().zip(hits.iter()) {
                stats.eye_rays += 1;
                let id = SampleId::single(x, y);
                let color = match self.lighting.model {
                    Model::Spd => self.shade::<NoRecord, SpdRules>(ray, 1, found, &id, stats, &mut NoRecord),
                    Model::P3f => self.shade::<NoRecord, P3fRules>(ray, 1, found, &id, stats, &mut NoRecord),
                };
                out.push(finite_or_black(color));
                x += 1;
            }
        }
    }

    /// Eye rays `rays[i]` of samples `ids[i]` (depth 1), [`PACKET`] neighbours traced
    /// through the BVH together, each then shaded as [`Tracer::trace_eye`] shades it
    /// (packets find the very hits single rays find, so the colours are the same);
    /// calls `done(i, colour)` for each in order.
    pub fn trace_eyes(
        &self,
        rays: &[Ray],
        ids: &[SampleId],
        stats: &mut Stats,
        mut done: impl FnMut(usize, Vec3),
    ) {
        debug_assert_eq!(rays.len(), ids.len());
        let mut hits = [None; PACKET];
        for (c, (packet, ids)) in rays.chunks(PACKET).zip(ids.chunks(PACKET)).enumerate() {
            let hits = &mut hits[..packet.len()];
            self.bvh.closest_hit_packet(packet, f32::INFINITY, hits);
            for (i, ((ray, &found), id)) in packet.iter().zip(hits.iter()).zip(ids).enumerate() {
                stats.eye_rays += 1;
                let color = match self.lighting.model {
                    Model::Spd => self.shade::<NoRecord, SpdRules>(ray, 1, found, id, stats, &mut NoRecord),
                    Model::P3f => self.shade::<NoRecord, P3fRules>(ray, 1, found, id, stats, &mut NoRecord),
                };
                done(c * PACKET + i, finite_or_black(color));
            }
        }
    }

    /// The colour seen along `ray` (at ray-tree depth `depth`) given its closest hit.
    fn shade<R: Recorder, M: Rules>(
        &self,
        ray: &Ray,
        depth: u32,
        found: Option<(Hit, u32)>,
        id: &SampleId,
        stats: &mut Stats,
        rec: &mut R,
    ) -> Vec3 {
        let Some((hit, index)) = found else {
            if R::ENABLED {
                let (color, texel) = self.background.look(ray.dir);
                rec.miss(ray, color, texel);
                return color;
            }
            return self.background.color(ray.dir);
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
        // Secondary rays start off the surface by the point's error bound, on the
        // ray's side (shadow and mirror rays) or the far side (refracted rays).
        let offset = prim.origin_offset(&surface, point_error(p, ray, hit.t));
        let above = if entering { p + offset } else { p - offset };
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
        // Made where each light uses it: kept live across the loop it ties up registers.
        let at = || Lit {
            m,
            diffuse,
            above,
            n,
            ns,
            view: -ray.dir,
            depth,
        };
        for (k, light) in self.lighting.lights.iter().enumerate() {
            if light.area.is_some() {
                color += self.area_light(k, light, &at(), id, stats, rec);
                continue;
            }
            let outcome = self.light_point(k, light.position, light.intensity, at(), stats);
            if R::ENABLED {
                rec.light(k, outcome);
            }
            if let LightOutcome::Lit(c) = outcome {
                color += c;
            }
        }

        if depth >= self.max_depth {
            if R::ENABLED {
                rec.done(color);
            }
            return color;
        }
        let secondary = M::secondary(m, ray.dir, n, entering);
        if let Some((dir, weight)) = secondary.refraction {
            stats.refraction_rays += 1;
            if R::ENABLED {
                rec.branch(Branch::Refraction, weight);
            }
            let below = if entering { p - offset } else { p + offset };
            color += self
                .trace::<R, M>(&Ray::new(below, dir), depth + 1, id, stats, rec)
                .mul_elem(weight);
        }
        if let Some((kind, weight)) = secondary.reflection {
            stats.reflection_rays += 1;
            let r = Ray::new(above, reflect(ray.dir, n));
            if R::ENABLED {
                rec.branch(kind, weight);
            }
            color += self.trace::<R, M>(&r, depth + 1, id, stats, rec).mul_elem(weight);
        }
        if R::ENABLED {
            rec.done(color);
        }
        color
    }

    /// The contribution of area light `k` at a hit: its points' shadow rays and
    /// local terms, each point with its share of the intensity.
    fn area_light<R: Recorder>(
        &self,
        k: usize,
        light: &LightSource,
        at: &Lit,
        id: &SampleId,
        stats: &mut Stats,
        rec: &mut R,
    ) -> Vec3 {
        let share = light.intensity * (1.0 / light.point_count(&self.light_sampling, id) as f32);
        let mut area = AreaOutcome::default();
        let count = light.sample_points(&self.light_sampling, id, k, at.depth, |point| {
            let outcome = self.light_point(k, point, share, *at, stats);
            match outcome {
                LightOutcome::Behind => area.behind += 1,
                LightOutcome::Shadowed => area.shadowed += 1,
                LightOutcome::Lit(c) => area.contribution += c,
            }
            if R::ENABLED {
                rec.light_sample(k, point, outcome);
            }
        });
        if R::ENABLED {
            area.samples = count;
            rec.area_light(k, area);
        }
        area.contribution
    }

    /// One point of light `k`, of the given intensity, seen from a hit: behind the
    /// surface (no shadow ray), shadowed, or its local term.
    #[inline(always)]
    fn light_point(
        &self,
        k: usize,
        point: Vec3,
        intensity: Vec3,
        at: Lit,
        stats: &mut Stats,
    ) -> LightOutcome {
        let to_light = point - at.above;
        if at.n.dot(to_light) <= 0.0 {
            return LightOutcome::Behind;
        }
        stats.shadow_rays += 1;
        // Aimed at the light unnormalized, blockers sought below t = 1: the ray's
        // reciprocal direction then no longer waits on a square root and a division
        // (the longest chain in setting up a shadow ray); the intersection tests do
        // not need unit directions.
        let shadow_ray = Ray::new(at.above, to_light);
        let blocked = if k < HINT_LIGHTS && (at.depth as usize) <= HINT_DEPTHS {
            let slot = k * HINT_DEPTHS + (at.depth as usize - 1);
            SHADOW_HINTS.with(|hints| self.bvh.occluded_hinted(&shadow_ray, 1.0, &hints[slot]))
        } else {
            self.bvh.occluded(&shadow_ray, 1.0)
        };
        if blocked {
            stats.shadow_blocked += 1;
            return LightOutcome::Shadowed;
        }
        let l = to_light / to_light.length();
        LightOutcome::Lit(intensity.mul_elem(local(at.m, at.diffuse, at.ns, l, at.view)))
    }
}

/// What the lights see of one hit.
#[derive(Clone, Copy)]
struct Lit<'m> {
    m: &'m Material,
    /// `Kd * C`.
    diffuse: Vec3,
    /// The shadow rays' origin, off the surface on the ray's side.
    above: Vec3,
    /// Geometric normal facing the ray.
    n: Vec3,
    /// Shading normal facing the ray.
    ns: Vec3,
    /// Towards the ray's origin.
    view: Vec3,
    depth: u32,
}
