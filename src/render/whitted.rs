//! Whitted ray tracing: at each hit the local term of every light (shadow rays to
//! each point of the light), then a mirror and a refracted ray as the shading rules
//! say ([`Rules`]: the SPD's for NFF scenes, the P3F course's), down to the
//! render's maximum depth. Distribution effects ride on the eye sample: every ray of
//! its tree sees the scene at the sample's time, a rough surface draws its rays'
//! microfacet normals from the sample's stratified numbers (one dimension per depth
//! and kind), and a ray inside absorbing glass brings back what Beer-Lambert leaves
//! of what it meets.

use std::marker::PhantomData;

use super::integrator::{AreaOutcome, HitRecord, Integrator, LightOutcome, NoRecord, Recorder, TraceContext};
use super::light::LightSampling;
use super::microfacet::{Frame as MicroFrame, TrowbridgeReitz};
use super::optics::beer_lambert;
use super::sampling::{Dim, SampleId};
use super::shade::{local, Branch, Facets, Rules};
use crate::accel::{Coherence, Ray8, RayLanes, PACKET};
use crate::geometry::{point_error, Hit, Primitive};
use crate::math::{lanes, Ray, Vec3};
use crate::prepare::LightSource;
use crate::prepare::RenderScene;
use crate::scene::Material;

/// Whitted ray tracing of one scene under the rules `M`.
pub struct Whitted<'a, M: Rules> {
    scene: &'a RenderScene,
    light_sampling: LightSampling,
    max_depth: u32,
    /// False: every surface smooth.
    roughness: bool,
    /// Shadow rays traced as packets: an area light's points seen from one hit
    /// ([`SHADOW_PACKET`] at a time), a point light seen from a packet of eye hits
    /// ([`Whitted::eye_shadows`]). Each ray keeps its own time, at which the packet
    /// queries see moving spheres. False only in tests that compare with one ray at
    /// a time.
    packets: bool,
    rules: PhantomData<fn() -> M>,
}

/// Shadow rays per packet of an area light's points.
const SHADOW_PACKET: usize = 8;

impl<M: Rules> Integrator for Whitted<'_, M> {
    #[inline]
    fn eye_radiance<R: Recorder>(
        &self,
        ray: &Ray,
        found: Option<(Hit, u32)>,
        id: &SampleId,
        ctx: &mut TraceContext,
        rec: &mut R,
    ) -> Vec3 {
        self.shade(ray, 1, found, None, id, ctx, rec)
    }

    /// With the point lights' shadow rays from the packet's hits traced together
    /// (`Whitted::eye_shadows`).
    fn eye_radiances(
        &self,
        rays: &[Ray],
        found: &[Option<(Hit, u32)>],
        ids: &[SampleId],
        ctx: &mut TraceContext,
        mut done: impl FnMut(usize, Vec3),
    ) {
        debug_assert!(rays.len() <= PACKET && rays.len() == found.len() && rays.len() == ids.len());
        let mut ats = [None; PACKET];
        for ((at, ray), found) in ats.iter_mut().zip(rays).zip(found) {
            *at = found.map(|(hit, index)| self.surface_at(ray, 1, &hit, index, ctx));
        }
        let ats = &ats[..rays.len()];
        let shadows = self.eye_shadows(rays, ats, ctx);
        for (lane, ((ray, at), id)) in rays.iter().zip(ats).zip(ids).enumerate() {
            let radiance = match at {
                None => self.missed(ray, &mut NoRecord),
                Some(at) => {
                    let known = EyeLane {
                        shadows: &shadows,
                        lane,
                    };
                    self.shade_at(ray, 1, at, None, &known, id, ctx, &mut NoRecord)
                }
            };
            done(lane, radiance);
        }
    }
}

impl<'a, M: Rules> Whitted<'a, M> {
    /// Traces `scene` with area lights sampled as `light_sampling` says, down to
    /// ray-tree depth `max_depth`, rough surfaces rough unless `roughness` is false.
    pub fn new(
        scene: &'a RenderScene,
        light_sampling: LightSampling,
        max_depth: u32,
        roughness: bool,
    ) -> Self {
        Whitted {
            scene,
            light_sampling,
            max_depth,
            roughness,
            packets: true,
            rules: PhantomData,
        }
    }

    /// The colour seen along `ray` at ray-tree depth `depth`, travelling through a
    /// medium of absorption coefficient `medium` (inside glass) or none.
    fn trace<R: Recorder>(
        &self,
        ray: &Ray,
        depth: u32,
        medium: Option<Vec3>,
        id: &SampleId,
        ctx: &mut TraceContext,
        rec: &mut R,
    ) -> Vec3 {
        let found = self.scene.accel().closest_hit(ray, f32::INFINITY);
        self.shade(ray, depth, found, medium, id, ctx, rec)
    }

    /// The colour seen along `ray` (at ray-tree depth `depth`, through `medium`)
    /// given its closest hit.
    #[allow(clippy::too_many_arguments)]
    fn shade<R: Recorder>(
        &self,
        ray: &Ray,
        depth: u32,
        found: Option<(Hit, u32)>,
        medium: Option<Vec3>,
        id: &SampleId,
        ctx: &mut TraceContext,
        rec: &mut R,
    ) -> Vec3 {
        let Some((hit, index)) = found else {
            return self.missed(ray, rec);
        };
        let at = self.surface_at(ray, depth, &hit, index, ctx);
        self.shade_at(ray, depth, &at, medium, &NoneKnown, id, ctx, rec)
    }

    /// The background seen by a ray that hits nothing, reported to `rec`.
    #[inline(always)]
    fn missed<R: Recorder>(&self, ray: &Ray, rec: &mut R) -> Vec3 {
        if R::ENABLED {
            let (color, texel) = self.scene.background().look(ray.dir);
            rec.miss(ray, color, texel);
            return color;
        }
        self.scene.background().color(ray.dir)
    }

    /// The surface `ray` (at ray-tree depth `depth`) meets at `hit` on primitive
    /// `index`, counted as a hit of its depth.
    #[inline(always)]
    fn surface_at(&self, ray: &Ray, depth: u32, hit: &Hit, index: u32, ctx: &mut TraceContext) -> At<'a> {
        if depth == 1 {
            ctx.stats.eye_hits += 1;
        } else {
            ctx.stats.secondary_hits += 1;
        }
        let scene = self.scene;
        let prim = scene.primitive(index);
        let surface = prim.surface(ray, hit, scene.accel().data());
        let m = &scene.materials()[prim.material as usize];
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
        At {
            prim,
            m,
            hit: *hit,
            p,
            n,
            ns,
            entering,
            offset,
            above,
        }
    }

    /// The colour seen along `ray` (at ray-tree depth `depth`, through `medium`) at
    /// surface `at`, with the point lights `known` tells of already traced.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn shade_at<R: Recorder>(
        &self,
        ray: &Ray,
        depth: u32,
        at: &At,
        medium: Option<Vec3>,
        known: &impl KnownShadows,
        id: &SampleId,
        ctx: &mut TraceContext,
        rec: &mut R,
    ) -> Vec3 {
        let scene = self.scene;
        let At {
            prim,
            m,
            p,
            n,
            ns,
            entering,
            offset,
            above,
            ..
        } = *at;
        let diffuse = m.color * m.kd;
        let lighting = scene.lighting();
        let mut color = lighting.ambient.mul_elem(M::ambient_reflectance(m, diffuse));
        // An emitter shows its radiance on the side of its own normal (it lights
        // nothing here: the path tracer samples emitters as lights).
        if entering {
            color += m.emission;
        }
        // What is left of the light on its way back through the medium (unit
        // directions: t is the distance).
        let left = medium.map(|sigma| beer_lambert(sigma, at.hit.t));
        if R::ENABLED {
            let record = HitRecord {
                depth,
                primitive: prim,
                t: at.hit.t,
                point: p,
                normal: n,
                shading_normal: ns,
                entering,
                ambient: color,
                absorbed: left,
                time: ray.time,
            };
            rec.hit(ray, &record);
        }
        // Made where each light uses it: kept live across the loop it ties up registers.
        let lit_at = || Lit {
            m,
            diffuse,
            above,
            n,
            ns,
            view: -ray.dir,
            depth,
            time: ray.time,
        };
        for (k, light) in lighting.lights.iter().enumerate() {
            if light.area.is_some() {
                color += self.area_light(k, light, &lit_at(), id, ctx, rec);
                continue;
            }
            let outcome = match known.blocked(k) {
                Some(blocked) => point_outcome::<M>(&lit_at(), light.position, light.intensity, blocked),
                None => self.light_point(k, light.position, light.intensity, lit_at(), ctx),
            };
            if R::ENABLED {
                rec.light(k, outcome);
            }
            if let LightOutcome::Lit(c) = outcome {
                color += c;
            }
        }

        if depth >= self.max_depth {
            return Self::done(depth, self.textured(at, color), left, rec);
        }
        let rough = self.roughness && M::is_rough(m) && id.is_jittered();
        let facets = if rough {
            Self::facets(m, ray.dir, n, depth, id)
        } else {
            M::smooth_facets(n, ns)
        };
        let secondary = M::secondary(m, ray.dir, n, entering, &facets);
        if let Some((dir, weight)) = secondary.refraction {
            ctx.stats.refraction_rays += 1;
            if R::ENABLED {
                let smooth = rough.then(|| M::secondary(m, ray.dir, n, entering, &Facets::smooth(n)));
                rec.branch(
                    Branch::Refraction,
                    weight,
                    smooth.and_then(|s| s.refraction).map(|r| r.0),
                );
            }
            // Into the object: its glass absorbs; out of it: the open space.
            let inside = if entering { M::absorption(m) } else { None };
            let below = if entering { p - offset } else { p + offset };
            let r = Ray::with_time(below, dir, ray.time);
            color += self.trace(&r, depth + 1, inside, id, ctx, rec).mul_elem(weight);
        }
        if let Some((kind, weight, dir)) = secondary.reflection {
            ctx.stats.reflection_rays += 1;
            if R::ENABLED {
                let smooth = rough.then(|| M::secondary(m, ray.dir, n, entering, &Facets::smooth(n)));
                rec.branch(kind, weight, smooth.and_then(|s| s.reflection).map(|r| r.2));
            }
            // The mirror ray stays on the incoming ray's side, in its medium.
            let r = Ray::with_time(above, dir, ray.time);
            color += self.trace(&r, depth + 1, medium, id, ctx, rec).mul_elem(weight);
        }
        Self::done(depth, self.textured(at, color), left, rec)
    }

    /// `color` times `at`'s texel if its material is textured: a texel weights
    /// everything the surface sends back, its secondary rays included (AFF's rules).
    #[inline(always)]
    fn textured(&self, at: &At, color: Vec3) -> Vec3 {
        if at.m.texture.is_none() {
            return color;
        }
        match self.scene.texel(at.m, at.prim, &at.hit) {
            Some(texel) => color.mul_elem(texel),
            None => color,
        }
    }

    /// The microfacet normals about which a rough `m` hit by unit direction `d` (unit
    /// normal `n` facing it, ray-tree depth `depth`) sends its secondary rays: drawn
    /// from the normals visible from `-d` with the sample's stratified numbers.
    fn facets(m: &Material, d: Vec3, n: Vec3, depth: u32, id: &SampleId) -> Facets {
        let dist = TrowbridgeReitz::of_roughness(m.roughness);
        let frame = MicroFrame::new(n);
        let wo = frame.to_local(-d);
        let draw = |dim| frame.to_world(dist.sample_visible(wo, id.point(dim)));
        Facets {
            reflection: draw(Dim::Reflection { depth }),
            refraction: if m.t > 0.0 {
                draw(Dim::Refraction { depth })
            } else {
                n
            },
        }
    }

    /// The colour a ray of depth `depth` returns: `color` times what is `left` of it
    /// after the medium it crossed, as the rules return it from a secondary ray
    /// ([`Rules::returned`]), reported to `rec`.
    #[inline(always)]
    fn done<R: Recorder>(depth: u32, color: Vec3, left: Option<Vec3>, rec: &mut R) -> Vec3 {
        let color = left.map_or(color, |f| color.mul_elem(f));
        let color = if depth > 1 { M::returned(color) } else { color };
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
        ctx: &mut TraceContext,
        rec: &mut R,
    ) -> Vec3 {
        let points = light.point_count(&self.light_sampling, id);
        let share = light.intensity * (1.0 / points as f32);
        let mut area = AreaOutcome::default();
        let mut tally = |point, outcome, rec: &mut R| {
            match outcome {
                LightOutcome::Behind => area.behind += 1,
                LightOutcome::Shadowed => area.shadowed += 1,
                LightOutcome::Lit(c) => area.contribution += c,
            }
            if R::ENABLED {
                rec.light_sample(k, point, outcome);
            }
        };
        let count = if self.packets && points > 1 {
            // The points in order, in packets: the same outcomes, summed in the same
            // order, as one shadow ray at a time.
            let mut batch = [Vec3::ZERO; SHADOW_PACKET];
            let mut len = 0;
            let count = light.sample_points(&self.light_sampling, id, k, at.depth, |point| {
                batch[len] = point;
                len += 1;
                if len == SHADOW_PACKET {
                    self.light_points(&batch, share, at, ctx, |p, o| tally(p, o, rec));
                    len = 0;
                }
            });
            self.light_points(&batch[..len], share, at, ctx, |p, o| tally(p, o, rec));
            count
        } else {
            light.sample_points(&self.light_sampling, id, k, at.depth, |point| {
                let outcome = self.light_point(k, point, share, *at, ctx);
                tally(point, outcome, rec);
            })
        };
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
        ctx: &mut TraceContext,
    ) -> LightOutcome {
        let to_light = point - at.above;
        if behind(at.n, to_light) {
            return LightOutcome::Behind;
        }
        ctx.stats.shadow_rays += 1;
        // Aimed at the light unnormalized, blockers sought below t = 1: the ray's
        // reciprocal direction then no longer waits on a square root and a division
        // (the longest chain in setting up a shadow ray); the intersection tests do
        // not need unit directions.
        let shadow_ray = Ray::with_time(at.above, to_light, at.time);
        let accel = self.scene.accel();
        let blocked = match ctx.hint(k, at.depth) {
            Some(hint) => accel.occluded_hinted(&shadow_ray, 1.0, hint),
            None => accel.occluded(&shadow_ray, 1.0),
        };
        if blocked {
            ctx.stats.shadow_blocked += 1;
            return LightOutcome::Shadowed;
        }
        lit::<M>(&at, to_light, intensity)
    }

    /// The shadows of the point lights on the hits of a packet of eye rays (`ats[i]`
    /// the surface eye ray `rays[i]` meets, if any): for each point light, its
    /// shadow rays from the hits it is not behind, counted as
    /// [`Whitted::light_point`] counts them, traced as one packet where the last
    /// packet of them was all lit, else one at a time through the shadow cache
    /// until a packet's worth is all lit again. A packet walks a lit region's
    /// coherent rays faster than one ray at a time (SPD tree: 4 % of its shadow
    /// rays blocked, 8.6 % fewer instructions), but in shadow the cache, which
    /// tries the last blocker first, is faster (SPD balls: 30 % blocked, 3.5 % more
    /// instructions with packets alone).
    /// None are traced when the render traces no packets.
    fn eye_shadows(&self, rays: &[Ray], ats: &[Option<At>], ctx: &mut TraceContext) -> EyeShadows {
        let lights = &self.scene.lighting().lights;
        let mut shadows = EyeShadows {
            lights: if self.packets {
                lights.len().min(PACKET_LIGHTS)
            } else {
                0
            },
            blocked: [0; PACKET_LIGHTS],
        };
        // Made one ray at a time, the form the shadow cache takes them in; a lane
        // without a ray to this light keeps whatever it held (outside `active`).
        let mut shadow_rays = [rays[0]; PACKET];
        for (k, light) in lights.iter().enumerate().take(shadows.lights) {
            if light.area.is_some() {
                continue;
            }
            let mut active = 0u32;
            for (i, (ray, at)) in rays.iter().zip(ats).enumerate() {
                let Some(at) = at else { continue };
                // As `light_point` aims it.
                let to_light = light.position - at.above;
                if !behind(at.n, to_light) {
                    active |= 1 << i;
                    shadow_rays[i] = Ray::with_time(at.above, to_light, ray.time);
                }
            }
            if active == 0 {
                continue;
            }
            let accel = self.scene.accel();
            // (A light without a shadow-cache slot always goes as a packet.)
            let cached = ctx.eye_shadows_cached >> k & 1 != 0;
            let blocked = match ctx.hint(k, 1) {
                Some(hint) if cached => lanes(active)
                    .filter(|&i| accel.occluded_hinted(&shadow_rays[i], 1.0, hint))
                    .fold(0, |bits, i| bits | 1 << i),
                _ => accel.occluded8(
                    &Ray8::new(&shadow_rays[..rays.len()]),
                    &[1.0; PACKET],
                    active,
                    Coherence::Coherent,
                ),
            };
            ctx.eye_shadows_cached = ctx.eye_shadows_cached & !(1 << k) | u32::from(blocked != 0) << k;
            ctx.stats.shadow_rays += u64::from(active.count_ones());
            ctx.stats.shadow_blocked += u64::from(blocked.count_ones());
            shadows.blocked[k] = blocked;
        }
        shadows
    }

    /// Up to [`SHADOW_PACKET`] points of one light, each of the given intensity, seen
    /// from a hit: [`Whitted::light_point`]'s outcome of each, given in order to
    /// `outcome(point, outcome)`, their shadow rays traced as one packet.
    #[inline(always)]
    fn light_points(
        &self,
        points: &[Vec3],
        intensity: Vec3,
        at: &Lit,
        ctx: &mut TraceContext,
        mut outcome: impl FnMut(Vec3, LightOutcome),
    ) {
        if points.is_empty() {
            return;
        }
        let mut to_lights = [Vec3::ZERO; SHADOW_PACKET];
        let mut rays = RayLanes::default();
        let mut active = 0u32;
        for (k, (to_light, &point)) in to_lights.iter_mut().zip(points).enumerate() {
            // As `light_point` aims it (no ray for a point behind the surface).
            *to_light = point - at.above;
            if !behind(at.n, *to_light) {
                active |= 1 << k;
            }
            // Every lane set, traced or not: rays from one hit to one light share
            // their frame's axes, and the packet's leaf tests take the shorter path
            // when all eight do (`Ray8::shared_axes`).
            rays.set(k, at.above, *to_light, at.time);
        }
        let blocked = if active == 0 {
            0
        } else {
            self.scene.accel().occluded8(
                &rays.packet(points.len()),
                &[1.0; SHADOW_PACKET],
                active,
                Coherence::Coherent,
            )
        };
        ctx.stats.shadow_rays += u64::from(active.count_ones());
        ctx.stats.shadow_blocked += u64::from(blocked.count_ones());
        for (k, (&to_light, &point)) in to_lights.iter().zip(points).enumerate() {
            let result = if active >> k & 1 == 0 {
                LightOutcome::Behind
            } else if blocked >> k & 1 != 0 {
                LightOutcome::Shadowed
            } else {
                lit::<M>(at, to_light, intensity)
            };
            outcome(point, result);
        }
    }
}

/// Whether a point of light `to_light` away from a hit, whose geometric normal
/// facing the ray is `n`, lies behind its surface (no shadow ray is traced to it).
#[inline(always)]
fn behind(n: Vec3, to_light: Vec3) -> bool {
    n.dot(to_light) <= 0.0
}

/// [`Whitted::light_point`]'s outcome for a point light at `point` whose shadow ray
/// from the hit `at` was traced beforehand (`blocked` its answer; unused when the
/// light is behind the surface, whose shadow ray is never traced).
#[inline(always)]
fn point_outcome<M: Rules>(at: &Lit, point: Vec3, intensity: Vec3, blocked: bool) -> LightOutcome {
    let to_light = point - at.above;
    if behind(at.n, to_light) {
        LightOutcome::Behind
    } else if blocked {
        LightOutcome::Shadowed
    } else {
        lit::<M>(at, to_light, intensity)
    }
}

/// Point lights (the first of a scene's lights) whose shadow rays from a packet of
/// eye hits are traced together ([`Whitted::eye_shadows`]); later ones, one ray at a
/// time.
const PACKET_LIGHTS: usize = 16;

// A bit per light in `TraceContext::eye_shadows_cached`.
const _: () = assert!(PACKET_LIGHTS <= 32);

/// What the first [`PACKET_LIGHTS`] point lights' shadow rays from a packet of eye
/// hits found.
struct EyeShadows {
    /// Lights `0..lights` were traced (their point lights: area lights have their own
    /// packets).
    lights: usize,
    /// Per light, bit `i` set when the shadow ray from eye hit `i` was blocked.
    blocked: [u32; PACKET_LIGHTS],
}

/// The point lights whose shadow rays from one hit were traced beforehand.
trait KnownShadows {
    /// `Some(blocked)` for point light `k` if its shadow ray was traced (`blocked`
    /// meaningless when the light is behind the surface), `None` to trace it now.
    fn blocked(&self, k: usize) -> Option<bool>;
}

/// No shadow ray traced beforehand.
struct NoneKnown;

impl KnownShadows for NoneKnown {
    #[inline(always)]
    fn blocked(&self, _k: usize) -> Option<bool> {
        None
    }
}

/// The shadows [`EyeShadows`] found for eye hit `lane`.
struct EyeLane<'s> {
    shadows: &'s EyeShadows,
    lane: usize,
}

impl KnownShadows for EyeLane<'_> {
    #[inline(always)]
    fn blocked(&self, k: usize) -> Option<bool> {
        (k < self.shadows.lights).then(|| self.shadows.blocked[k] >> self.lane & 1 != 0)
    }
}

/// The surface a ray meets, as shading sees it.
#[derive(Clone, Copy)]
struct At<'a> {
    prim: &'a Primitive,
    m: &'a Material,
    /// The hit as the primitive found it: the distance along the ray, and the
    /// barycentrics that place texels.
    hit: Hit,
    /// The hit point.
    p: Vec3,
    /// Geometric normal facing the ray.
    n: Vec3,
    /// Shading normal facing the ray.
    ns: Vec3,
    /// True if the ray crosses the surface against the primitive's own normal.
    entering: bool,
    /// How far secondary rays start off the surface.
    offset: Vec3,
    /// Shadow and mirror rays' origin, off the surface on the ray's side.
    above: Vec3,
}

/// The local term of a point of light `to_light` away from a hit it reaches unblocked.
#[inline(always)]
fn lit<M: Rules>(at: &Lit, to_light: Vec3, intensity: Vec3) -> LightOutcome {
    let l = to_light / to_light.length();
    LightOutcome::Lit(intensity.mul_elem(local::<M>(at.m, at.diffuse, at.ns, l, at.view)))
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
    /// The moment the ray sees the scene at (its shadow rays see it then too).
    time: f32,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::shade::P3fRules;

    /// The facets a rough hit draws, over the 4096 stratified samples of one pixel at
    /// normal incidence, have the distribution's moments: u = tan^2(tm) / (a^2 +
    /// tan^2(tm)) is uniform (mean 1/2, variance 1/12), the azimuth too; stratified,
    /// closer than independent numbers would be.
    #[test]
    fn rough_facets_of_a_pixels_samples_have_the_distributions_moments() {
        let m = Material {
            roughness: 0.6,
            ks: 0.5,
            ..Material::DEFAULT
        };
        let alpha = TrowbridgeReitz::of_roughness(m.roughness).alpha() as f64;
        let n = Vec3::new(0.0, 0.0, 1.0);
        let count = 4096;
        let (mut s1, mut s2, mut cx) = (0.0f64, 0.0f64, 0.0f64);
        for index in 0..count {
            let id = SampleId::new(3, 7, index, count, true);
            let f = Whitted::<P3fRules>::facets(&m, -n, n, 2, &id);
            assert_eq!(f.refraction, n, "opaque: no refraction facet");
            let c = f.reflection.z as f64;
            let tan2 = (1.0 - c * c) / (c * c);
            let u = tan2 / (alpha * alpha + tan2);
            s1 += u;
            s2 += u * u;
            cx += (f.reflection.y as f64).atan2(f.reflection.x as f64).cos();
        }
        let mean = s1 / count as f64;
        let var = s2 / count as f64 - mean * mean;
        assert!((mean - 0.5).abs() < 0.002, "mean {mean}");
        assert!((var - 1.0 / 12.0).abs() < 0.002, "variance {var}");
        assert!((cx / count as f64).abs() < 0.01);
    }
}

#[cfg(test)]
mod packet_tests {
    use super::*;
    use crate::load::Assets;
    use crate::nff::{parse_format, Format};
    use crate::options::RenderOptions;
    use crate::prepare::prepare;
    use crate::render::integrator::NoRecord;
    use crate::render::shade::{P3fRules, SpdRules};
    use crate::render::Camera;

    /// `text`, a scene in `format`, prepared to render.
    fn scene_of(text: &str, format: Format) -> RenderScene {
        prepare(
            parse_format(text.as_bytes(), format, &Default::default()).unwrap(),
            &Assets::default(),
        )
    }

    /// Each area light's own grid of points, soft shadows.
    const SOFT: LightSampling = LightSampling {
        grid_override: None,
        soft_shadows: true,
    };

    /// A closest hit and the primitive's index, if any.
    type Found = Option<(Hit, u32)>;

    /// The eye rays through the centres of pixels `xs` of row `y`, each at time
    /// `time(x)`, their samples and their closest hits.
    fn eye_packet(
        scene: &RenderScene,
        camera: &Camera,
        y: u32,
        xs: &[u32],
        time: impl Fn(u32) -> f32,
    ) -> (Vec<Ray>, Vec<SampleId>, Vec<Found>) {
        let rays: Vec<Ray> = xs
            .iter()
            .map(|&x| {
                let r = camera.ray_at(x as f32 + 0.5, y as f32 + 0.5);
                Ray::with_time(r.origin, r.dir, time(x))
            })
            .collect();
        let ids = xs.iter().map(|&x| SampleId::single(x, y)).collect();
        let found = rays
            .iter()
            .map(|r| scene.accel().closest_hit(r, f32::INFINITY))
            .collect();
        (rays, ids, found)
    }

    /// Eye rays' colours as bits, each with the ray's place in its packet.
    type Shaded = Vec<(usize, [u32; 3])>;

    /// The colours `w` gives eye rays `rays` (samples `ids`, closest hits `found`) as
    /// one packet (`together`), or each eye ray shaded alone.
    fn shaded<M: Rules>(
        w: &Whitted<M>,
        rays: &[Ray],
        found: &[Found],
        ids: &[SampleId],
        ctx: &mut TraceContext,
        together: bool,
    ) -> Shaded {
        let bits = |c: Vec3| c.to_array().map(f32::to_bits);
        let mut shaded = Vec::new();
        if together {
            w.eye_radiances(rays, found, ids, ctx, |i, c| shaded.push((i, bits(c))));
            return shaded;
        }
        for (i, ((ray, &found), id)) in rays.iter().zip(found).zip(ids).enumerate() {
            shaded.push((i, bits(w.eye_radiance(ray, found, id, ctx, &mut NoRecord))));
        }
        shaded
    }

    /// Whitted under the P3F rules down to depth 4, tracing shadow rays in packets,
    /// and the same one shadow ray at a time.
    fn with_and_without_packets(scene: &RenderScene) -> (Whitted<'_, P3fRules>, Whitted<'_, P3fRules>) {
        let packets = Whitted::<P3fRules>::new(scene, SOFT, 4, true);
        assert!(packets.packets);
        let single = Whitted {
            packets: false,
            ..Whitted::<P3fRules>::new(scene, SOFT, 4, true)
        };
        (packets, single)
    }

    /// Two quad lights (4 x 4 and 3 x 3 points: packets of eight, and a last one of
    /// one) over balls on a floor, partly shadowed, mirrors for deeper hits.
    const SCENE: &str = "spp 0\nbclr 0.1 0.3 0.7\n\
        camera\neye 2.1 1.3 1.7\nat 0 0 0\nup 0 0 1\nangle 45\nhither 0.01\nresolution 24 18\n\
        light quad 4 3 2 1 1 1 4 2 2 3 3 2 4\nlight quad 1 -4 4 1 1 1 0 -4 4 1 -3 4 3\n\
        mat 1 0.75 0.33 1 1 1 0.8 0 10 0 1\npl 12 12 -0.5 -12 12 -0.5 -12 -12 -0.5\n\
        mat 1 0.9 0.7 0.5 1 1 1 0.5 30 0 1\ns 0 0 0 0.5\ns 0.27 0.27 0.54 0.17\ns 0.64 0.17 0 0.17\n";

    /// Each eye ray's colour and ray counts are the same, bit for bit, with the area
    /// lights' shadow rays traced as packets or one by one.
    #[test]
    fn area_lights_in_packets_shade_as_one_ray_at_a_time() {
        let scene = scene_of(SCENE, Format::P3f);
        let (packets, single) = with_and_without_packets(&scene);
        let camera = Camera::new(scene.view(), &RenderOptions::from_view(scene.view()));
        let (mut a, mut b) = (TraceContext::default(), TraceContext::default());
        for y in 0..18 {
            for x in 0..24 {
                let ray = camera.ray_at(x as f32 + 0.5, y as f32 + 0.5);
                let id = SampleId::single(x, y);
                let found = scene.accel().closest_hit(&ray, f32::INFINITY);
                let bits = |c: Vec3| c.to_array().map(f32::to_bits);
                assert_eq!(
                    bits(packets.eye_radiance(&ray, found, &id, &mut a, &mut NoRecord)),
                    bits(single.eye_radiance(&ray, found, &id, &mut b, &mut NoRecord)),
                    "pixel ({x}, {y})"
                );
            }
        }
        assert_eq!(a.stats, b.stats);
        assert!(a.stats.shadow_blocked > 0 && a.stats.shadow_blocked < a.stats.shadow_rays);
    }

    /// Ten point lights (more than have a shadow-cache slot) over a mirror ball and a
    /// glass ball on a floor, in NFF; one light below the floor (behind every hit on
    /// it), one inside the mirror ball (blocked from everywhere but its inside).
    const POINT_LIGHTS: &str = "v\nfrom 2.1 1.3 1.7\nat 0 0 0\nup 0 0 1\nangle 45\nhither 0.01\n\
        resolution 40 30\nb 0.1 0.3 0.7\n\
        l 4 3 2\nl -3 4 4\nl 0 0 -3\nl 0.1 0 0\nl 1 -4 3\nl -4 -1 1\nl 2 2 5\nl -1 3 2\nl 3 -2 1\nl 0 5 1\n\
        f 1 0.75 0.33 0.8 0 10 0 1\np 4 12 12 -0.5 -12 12 -0.5 -12 -12 -0.5 12 -12 -0.5\n\
        f 0.9 0.9 0.9 0.2 0.8 30 0 1\ns 0 0 0 0.5\n\
        f 1 1 1 0.1 0.4 60 0.8 1.5\ns 0.64 0.17 0 0.17\ns 0.27 0.27 0.54 0.17\n";

    /// Each eye ray's colour and the ray counts are the same, bit for bit, with the
    /// point lights' shadow rays from a packet of eye hits traced together (as a
    /// packet or through the shadow cache) or each eye ray shaded alone, under the
    /// SPD's rules and the P3F course's.
    #[test]
    fn eye_packets_shade_as_one_eye_ray_at_a_time() {
        let scene = scene_of(POINT_LIGHTS, Format::Nff);
        let camera = Camera::new(scene.view(), &RenderOptions::from_view(scene.view()));
        let spd = Whitted::<SpdRules>::new(&scene, SOFT, 5, true);
        let p3f = Whitted::<P3fRules>::new(&scene, SOFT, 5, true);
        let (mut a, mut b) = (TraceContext::default(), TraceContext::default());
        for y in 0..30 {
            for xs in (0..40).collect::<Vec<u32>>().chunks(PACKET) {
                let (rays, ids, found) = eye_packet(&scene, &camera, y, xs, |_| 0.0);
                let mut together = shaded(&spd, &rays, &found, &ids, &mut a, true);
                together.extend(shaded(&p3f, &rays, &found, &ids, &mut a, true));
                let mut alone = shaded(&spd, &rays, &found, &ids, &mut b, false);
                alone.extend(shaded(&p3f, &rays, &found, &ids, &mut b, false));
                assert_eq!(together, alone, "row {y}, columns {xs:?}");
            }
        }
        assert_eq!(a.stats, b.stats);
        let blocked = a.stats.shadow_blocked;
        assert!(
            blocked > 0 && blocked < a.stats.shadow_rays / 2,
            "{blocked} of {}",
            a.stats.shadow_rays
        );
    }

    /// A quad light and two point lights over balls on a floor, two of the balls
    /// moving across the shutter (one through another ball's shadow).
    const MOVING: &str = "spp 0\nbclr 0.1 0.3 0.7\nshutter 0 1\n\
        camera\neye 2.1 1.3 1.7\nat 0 0 0\nup 0 0 1\nangle 45\nhither 0.01\nresolution 32 24\n\
        light quad 4 3 2 1 1 1 4 2 2 3 3 2 3\nl 1 -4 4 1 1 1\nl -3 1 5 1 1 1\n\
        mat 1 0.75 0.33 1 1 1 0.8 0 10 0 1\npl 12 12 -0.5 -12 12 -0.5 -12 -12 -0.5\n\
        mat 1 0.9 0.7 0.5 1 1 1 0.5 30 0 1\ns 0 0 0 0.5\n\
        sm 0.64 -0.6 -0.3 0.64 0.6 -0.3 0.2 0 1\nsm -0.7 0.5 0.2 -0.2 0.5 0.2 0.15 0.2 0.8\n";

    /// With moving spheres, each eye ray at its own time: the colours and ray counts
    /// of packets of eye rays, their shadow rays in packets (each ray at its eye
    /// ray's time), are those of one eye ray at a time with one shadow ray at a time.
    #[test]
    fn moving_spheres_in_packets_shade_as_one_ray_at_a_time() {
        let scene = scene_of(MOVING, Format::P3f);
        assert!(scene.info().has_moving_spheres());
        let (packets, single) = with_and_without_packets(&scene);
        let camera = Camera::new(scene.view(), &RenderOptions::from_view(scene.view()));
        let (mut a, mut b) = (TraceContext::default(), TraceContext::default());
        for y in 0..24 {
            for xs in (0..32).collect::<Vec<u32>>().chunks(PACKET) {
                let time = |x: u32| ((x * 7 + y * 3) % 11) as f32 / 10.0;
                let (rays, ids, found) = eye_packet(&scene, &camera, y, xs, time);
                let together = shaded(&packets, &rays, &found, &ids, &mut a, true);
                let alone = shaded(&single, &rays, &found, &ids, &mut b, false);
                assert_eq!(together, alone, "row {y}, columns {xs:?}");
            }
        }
        assert_eq!(a.stats, b.stats);
        assert!(a.stats.shadow_blocked > 0 && a.stats.shadow_blocked < a.stats.shadow_rays / 2);
    }
}
