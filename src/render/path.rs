//! The path tracer: unidirectional, with next-event estimation and multiple
//! importance sampling (Veach's power heuristic) between light and BSDF sampling
//! wherever both can make a path (emissive primitives that are sampled by area),
//! Russian roulette from the fifth segment on, Beer-Lambert absorption inside glass
//! and the background (colour or skybox) as radiance arriving from infinity.
//!
//! **Depth** counts a path's segments, the camera ray being the first, as Mitsuba
//! 3's `max_depth`: depth 1 sees only what the camera ray meets (emitters and the
//! background), depth 2 adds direct light, and so on. A light sample adds a segment
//! too, so at the last depth none is taken.
//!
//! Materials map to BSDFs as `bsdf.rs` documents (a textured surface's texel
//! multiplies its diffuse albedo); lights and emitters as
//! `prepare/emitters.rs` does. Every number a path draws is the eye sample's, one dimension
//! per segment and use, stratified like the lens's ([`Dim`]).

use std::borrow::Cow;

use super::bsdf::Bsdf;
use super::integrator::{Integrator, PathEvent, Recorder, TraceContext};
use super::microfacet::Frame;
use super::optics::beer_lambert;
use super::sampling::{Dim, SampleId};
use crate::geometry::{point_error, Hit};
use crate::math::{Ray, Vec3};
use crate::prepare::RenderScene;

/// The first segment at which a path may be ended by Russian roulette (Mitsuba 3's
/// default `rr_depth`).
pub(super) const ROULETTE_FROM: u32 = 5;

/// How far short of a sampled light point a shadow ray stops, as a fraction of the
/// way: the point lies on the emitter's own surface.
pub(super) const SHADOW_SHORTFALL: f32 = 1e-4;

/// Path tracing of one scene.
pub struct PathTracer<'a> {
    scene: &'a RenderScene,
    max_depth: u32,
    /// Each material's BSDF seen from outside and from inside (`[leaving,
    /// entering]`: whether the ray meets the side of the primitive's own normal),
    /// worked out once.
    bsdfs: Vec<[Bsdf; 2]>,
    /// Whether rough surfaces are rough (for the BSDFs of textured points).
    roughness: bool,
}

impl<'a> PathTracer<'a> {
    /// The scene traced.
    pub(super) fn scene(&self) -> &'a RenderScene {
        self.scene
    }

    /// Traces `scene` with paths of at most `max_depth` segments, rough surfaces
    /// rough unless `roughness` is false.
    pub fn new(scene: &'a RenderScene, max_depth: u32, roughness: bool) -> Self {
        let bsdfs = scene
            .materials()
            .iter()
            .map(|m| [false, true].map(|entering| Bsdf::new(m, entering, roughness)))
            .collect();
        PathTracer {
            scene,
            max_depth,
            bsdfs,
            roughness,
        }
    }
}

/// Veach's power heuristic for two strategies, `a` the one used.
#[inline]
pub(super) fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 == 0.0 {
        0.0
    } else {
        a2 / (a2 + b2)
    }
}

impl Integrator for PathTracer<'_> {
    /// The path of one eye sample traced alone, one query at a time: the reference
    /// the wavefront (`super::wavefront`) is held to, and `--pixel`'s explainer. Both
    /// take the same steps (`arrive`, `light_query`, `light_result`, `bounce`) in the
    /// same order.
    fn eye_radiance<R: Recorder>(
        &self,
        eye: &Ray,
        found: Option<(Hit, u32)>,
        id: &SampleId,
        ctx: &mut TraceContext,
        rec: &mut R,
    ) -> Vec3 {
        let accel = self.scene.accel();
        let mut path = PathState::new(*eye);
        let mut found = found;
        while let Some(at) = self.arrive(&mut path, found, ctx, rec) {
            if let Some(query) = self.light_query(&path, &at, id, ctx) {
                let blocked = accel.occluded(&query.ray, query.t_max);
                self.light_result(&mut path, &query, blocked, ctx, rec);
            }
            if !self.bounce(&mut path, &at, id, ctx, rec) {
                break;
            }
            found = accel.closest_hit(&path.ray, f32::INFINITY);
        }
        path.radiance
    }
}

/// A path under way: the segment it travels next and what it has gathered.
#[derive(Clone, Copy, Debug)]
pub(super) struct PathState {
    /// The segment the path travels next (the eye ray first).
    pub ray: Ray,
    /// The radiance gathered so far.
    pub radiance: Vec3,
    /// The path's weight: what radiance arriving at its next vertex counts for.
    pub throughput: Vec3,
    /// The density of the last BSDF sample, `None` after a perfectly specular one
    /// (or the camera): an emitter it meets then is counted whole.
    pub last_pdf: Option<f32>,
    /// The absorption coefficient of the glass the ray travels in, if any.
    pub medium: Option<Vec3>,
    /// Segments so far (the eye ray is 1).
    pub depth: u32,
}

impl PathState {
    /// A path starting with the eye ray `eye`.
    pub fn new(eye: Ray) -> PathState {
        PathState {
            ray: eye,
            radiance: Vec3::ZERO,
            throughput: Vec3::ONE,
            last_pdf: None,
            medium: None,
            depth: 1,
        }
    }
}

/// A vertex where a path scatters: what its light sample and its bounce need.
#[derive(Clone, Copy, Debug)]
pub(super) struct Scatter {
    /// The shading frame.
    pub frame: Frame,
    /// Towards where the path came from, in the frame.
    pub wo: Vec3,
    /// Points off the surface on the incoming side and on the far side.
    pub sides: [Vec3; 2],
    /// The geometric normal facing the incoming ray.
    pub n: Vec3,
    /// The material's index.
    pub material: u32,
    /// True if the segment crosses into the object.
    pub entering: bool,
    /// The texel at the vertex, on a textured surface: it multiplies the diffuse
    /// albedo ([`Bsdf::textured`]).
    pub texel: Option<Vec3>,
}

/// A light sample's shadow ray, still to be tested, and what it adds unless blocked.
#[derive(Clone, Copy, Debug)]
pub(super) struct ShadowQuery {
    /// The shadow ray, aimed at the light's point.
    pub ray: Ray,
    /// Blockers count below this distance along it.
    pub t_max: f32,
    /// The light's point.
    pub point: Vec3,
    /// `f cos Li / pdf`, weighted: the light sample's contribution before the
    /// path's throughput.
    pub contribution: Vec3,
    /// Its multiple-importance weight.
    pub weight: f32,
    /// The path's throughput times `contribution`: what the radiance gains unless
    /// the ray is blocked.
    pub gain: Vec3,
}

impl PathTracer<'_> {
    /// A path's segment meets `found` (or nothing): the background seen, absorption
    /// on the way, the emission met (weighted against light sampling), and the
    /// vertex where the path goes on, unless it ends there (it left the scene, or
    /// reached the last depth, or meets a black surface).
    pub(super) fn arrive<R: Recorder>(
        &self,
        path: &mut PathState,
        found: Option<(Hit, u32)>,
        ctx: &mut TraceContext,
        rec: &mut R,
    ) -> Option<Scatter> {
        let scene = self.scene;
        let ray = path.ray;
        let Some((hit, index)) = found else {
            let sky = scene.background().color(ray.dir);
            path.radiance += path.throughput.mul_elem(sky);
            if R::ENABLED {
                rec.path(PathEvent::Escape {
                    ray,
                    radiance: sky,
                    throughput: path.throughput,
                });
            }
            return None;
        };
        if path.depth == 1 {
            ctx.stats.eye_hits += 1;
        } else {
            ctx.stats.secondary_hits += 1;
        }
        if let Some(sigma) = path.medium {
            path.throughput = path
                .throughput
                .mul_elem(beer_lambert(sigma, hit.t * ray.dir.length()));
        }
        let prim = scene.primitive(index);
        let surface = prim.surface(&ray, &hit, scene.accel().data());
        let m = &scene.materials()[prim.material as usize];
        let entering = surface.normal.dot(ray.dir) < 0.0;
        let (n, ns) = if entering {
            (surface.normal, surface.shading_normal)
        } else {
            (-surface.normal, -surface.shading_normal)
        };
        // Emission, on the side of the primitive's own normal.
        if entering && m.emission != Vec3::ZERO {
            let weight = match (path.last_pdf, scene.emitters().of_primitive(index)) {
                (Some(bsdf_pdf), Some((pmf, area))) => {
                    let d2 = (hit.t * ray.dir.length()).powi(2);
                    let cos_light = -surface.normal.dot(ray.dir.normalize());
                    power_heuristic(bsdf_pdf, pmf * d2 / (cos_light * area))
                }
                _ => 1.0,
            };
            path.radiance += path.throughput.mul_elem(m.emission) * weight;
            if R::ENABLED {
                rec.path(PathEvent::Emitted {
                    radiance: m.emission,
                    weight,
                });
            }
        }
        if R::ENABLED {
            rec.path(PathEvent::Vertex {
                ray,
                primitive: prim,
                t: hit.t,
                point: surface.point,
                normal: n,
                entering,
                throughput: path.throughput,
            });
        }
        if path.depth >= self.max_depth {
            return None;
        }
        let wo_world = -ray.dir.normalize();
        let frame = Frame::new(if ns.dot(wo_world) > 0.0 { ns } else { n });
        let wo = frame.to_local(wo_world);
        let texel = scene.texel(m, prim, &hit);
        if self.bsdf_at(prim.material, entering, texel).is_black() {
            return None;
        }
        let offset = prim.origin_offset(&surface, point_error(surface.point, &ray, hit.t));
        // Off the surface on the incoming ray's side, and on the far side (the
        // offset is along the primitive's own normal).
        let (toward, away) = (surface.point + offset, surface.point - offset);
        Some(Scatter {
            frame,
            wo,
            sides: if entering { [toward, away] } else { [away, toward] },
            n,
            material: prim.material,
            entering,
            texel,
        })
    }

    /// The BSDF of material `material` seen from outside (`entering`) or inside.
    #[inline(always)]
    pub(super) fn bsdf(&self, material: u32, entering: bool) -> &Bsdf {
        &self.bsdfs[material as usize][usize::from(entering)]
    }

    /// The BSDF at a point of material `material` seen from outside (`entering`)
    /// or inside, whose texture (if any) gives `texel` there: the material's own,
    /// or one with the texel in its diffuse albedo.
    #[inline(always)]
    pub(super) fn bsdf_at(&self, material: u32, entering: bool, texel: Option<Vec3>) -> Cow<'_, Bsdf> {
        match texel {
            None => Cow::Borrowed(self.bsdf(material, entering)),
            Some(texel) => {
                let m = &self.scene.materials()[material as usize];
                Cow::Owned(Bsdf::textured(m, entering, self.roughness, texel))
            }
        }
    }

    /// The BSDF at vertex `at`.
    #[inline(always)]
    pub(super) fn scatter_bsdf(&self, at: &Scatter) -> Cow<'_, Bsdf> {
        self.bsdf_at(at.material, at.entering, at.texel)
    }

    /// Next-event estimation at vertex `at` of `path`: a point of one emitter and the
    /// radiance it sends towards the vertex through the BSDF, weighted against BSDF
    /// sampling, as a shadow ray still to test; `None` where the vertex takes no
    /// light sample or the sample adds nothing.
    pub(super) fn light_query(
        &self,
        path: &PathState,
        at: &Scatter,
        id: &SampleId,
        ctx: &mut TraceContext,
    ) -> Option<ShadowQuery> {
        let bsdf = self.scatter_bsdf(at);
        let emitters = self.scene.emitters();
        if !bsdf.has_spread() || emitters.is_empty() {
            return None;
        }
        let depth = path.depth;
        let (emitter, pmf) = emitters.choose(id.value(Dim::LightChoice { depth }))?;
        let u = id.point(Dim::LightPoint { depth });
        let light = emitters.sample(emitter, pmf, self.scene.accel().bvh(), at.sides[0], u)?;
        let wi_world = (light.point - at.sides[0]).normalize();
        let wi = at.frame.to_local(wi_world);
        // The geometric and the shading normal must agree on the side the light is
        // on (the light reaches the far side only through a transmissive lobe).
        let above = wi_world.dot(at.n) > 0.0;
        if above != (wi.z > 0.0) {
            return None;
        }
        let (f, bsdf_pdf) = bsdf.eval(at.wo, wi);
        let f_cos = f * wi.z.abs();
        if f_cos == Vec3::ZERO {
            return None;
        }
        ctx.stats.shadow_rays += 1;
        let start = if above { at.sides[0] } else { at.sides[1] };
        let weight = light
            .pdf
            .map_or(1.0, |light_pdf| power_heuristic(light_pdf, bsdf_pdf));
        let contribution = f_cos.mul_elem(light.incoming) * weight;
        Some(ShadowQuery {
            ray: Ray::with_time(start, light.point - start, path.ray.time),
            t_max: 1.0 - SHADOW_SHORTFALL,
            point: light.point,
            contribution,
            weight,
            gain: path.throughput.mul_elem(contribution),
        })
    }

    /// The light sample `query` of `path`'s last vertex, its shadow ray `blocked` or
    /// not: what it adds to the radiance.
    pub(super) fn light_result<R: Recorder>(
        &self,
        path: &mut PathState,
        query: &ShadowQuery,
        blocked: bool,
        ctx: &mut TraceContext,
        rec: &mut R,
    ) {
        if blocked {
            ctx.stats.shadow_blocked += 1;
        } else {
            path.radiance += query.gain;
        }
        if R::ENABLED {
            rec.path(PathEvent::Light {
                point: query.point,
                contribution: if blocked { Vec3::ZERO } else { query.contribution },
                weight: if blocked { 0.0 } else { query.weight },
                blocked,
            });
        }
    }

    /// The BSDF sample that continues `path` from vertex `at`, and Russian roulette:
    /// true with the path's next segment in `path.ray`, false if the path ends.
    pub(super) fn bounce<R: Recorder>(
        &self,
        path: &mut PathState,
        at: &Scatter,
        id: &SampleId,
        ctx: &mut TraceContext,
        rec: &mut R,
    ) -> bool {
        let depth = path.depth;
        let bsdf = self.scatter_bsdf(at);
        let lobe = if bsdf.needs_lobe_number() {
            id.value(Dim::Lobe { depth })
        } else {
            0.0
        };
        let Some(sample) = bsdf.sample(at.wo, lobe, id.point(Dim::Bsdf { depth })) else {
            return false;
        };
        let dir = at.frame.to_world(sample.wi);
        path.throughput = path.throughput.mul_elem(sample.weight);
        if R::ENABLED {
            rec.path(PathEvent::Bsdf {
                dir,
                sample,
                throughput: path.throughput,
            });
        }
        path.last_pdf = (!sample.delta).then_some(sample.pdf);
        let start = if dir.dot(at.n) > 0.0 {
            at.sides[0]
        } else {
            at.sides[1]
        };
        if sample.transmitted {
            let m = &self.scene.materials()[at.material as usize];
            path.medium = if at.entering { m.absorption() } else { None };
            ctx.stats.refraction_rays += 1;
        } else {
            ctx.stats.reflection_rays += 1;
        }
        path.depth += 1;
        if path.depth > ROULETTE_FROM {
            let keep = path.throughput.max_elem().min(0.95);
            if id.value(Dim::Roulette { depth: path.depth }) >= keep {
                return false;
            }
            path.throughput *= 1.0 / keep;
        }
        if !path.throughput.is_finite() || path.throughput == Vec3::ZERO {
            return false;
        }
        path.ray = Ray::with_time(start, dir, path.ray.time);
        true
    }
}
