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
//! Materials map to BSDFs as `bsdf.rs` documents; lights and emitters as
//! `prepare/emitters.rs` does. Every number a path draws is the eye sample's, one dimension
//! per segment and use, stratified like the lens's ([`Dim`]).

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
const ROULETTE_FROM: u32 = 5;

/// How far short of a sampled light point a shadow ray stops, as a fraction of the
/// way: the point lies on the emitter's own surface.
const SHADOW_SHORTFALL: f32 = 1e-4;

/// Path tracing of one scene.
pub struct PathTracer<'a> {
    scene: &'a RenderScene,
    max_depth: u32,
    /// Each material's BSDF seen from outside and from inside (`[leaving,
    /// entering]`: whether the ray meets the side of the primitive's own normal),
    /// worked out once.
    bsdfs: Vec<[Bsdf; 2]>,
}

impl<'a> PathTracer<'a> {
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
        }
    }
}

/// Veach's power heuristic for two strategies, `a` the one used.
#[inline]
fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 == 0.0 {
        0.0
    } else {
        a2 / (a2 + b2)
    }
}

impl Integrator for PathTracer<'_> {
    fn eye_radiance<R: Recorder>(
        &self,
        eye: &Ray,
        found: Option<(Hit, u32)>,
        id: &SampleId,
        ctx: &mut TraceContext,
        rec: &mut R,
    ) -> Vec3 {
        let scene = self.scene;
        let (mut ray, mut found) = (*eye, found);
        let mut radiance = Vec3::ZERO;
        let mut throughput = Vec3::ONE;
        // The density of the last BSDF sample, `None` after a perfectly specular one
        // (or the camera): an emitter it meets then is counted whole.
        let mut last_pdf: Option<f32> = None;
        // The absorption coefficient of the glass the ray travels in, if any.
        let mut medium: Option<Vec3> = None;
        let mut depth = 1;
        loop {
            let Some((hit, index)) = found else {
                let sky = scene.background().color(ray.dir);
                radiance += throughput.mul_elem(sky);
                if R::ENABLED {
                    rec.path(PathEvent::Escape {
                        ray,
                        radiance: sky,
                        throughput,
                    });
                }
                break;
            };
            if depth == 1 {
                ctx.stats.eye_hits += 1;
            } else {
                ctx.stats.secondary_hits += 1;
            }
            if let Some(sigma) = medium {
                throughput = throughput.mul_elem(beer_lambert(sigma, hit.t * ray.dir.length()));
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
                let weight = match (last_pdf, scene.emitters().of_primitive(index)) {
                    (Some(bsdf_pdf), Some((pmf, area))) => {
                        let d2 = (hit.t * ray.dir.length()).powi(2);
                        let cos_light = -surface.normal.dot(ray.dir.normalize());
                        power_heuristic(bsdf_pdf, pmf * d2 / (cos_light * area))
                    }
                    _ => 1.0,
                };
                radiance += throughput.mul_elem(m.emission) * weight;
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
                    throughput,
                });
            }
            if depth >= self.max_depth {
                break;
            }
            let wo_world = -ray.dir.normalize();
            let frame = Frame::new(if ns.dot(wo_world) > 0.0 { ns } else { n });
            let wo = frame.to_local(wo_world);
            let bsdf = &self.bsdfs[prim.material as usize][usize::from(entering)];
            if bsdf.is_black() {
                break;
            }
            let offset = prim.origin_offset(&surface, point_error(surface.point, &ray, hit.t));
            // Off the surface on the incoming ray's side, and on the far side (the
            // offset is along the primitive's own normal).
            let (toward, away) = (surface.point + offset, surface.point - offset);
            let sides = if entering { [toward, away] } else { [away, toward] };
            if bsdf.has_spread() && !scene.emitters().is_empty() {
                let at = Vertex {
                    frame: &frame,
                    wo,
                    sides,
                    n,
                    time: ray.time,
                    depth,
                };
                let direct = self.light_sample(bsdf, &at, id, ctx, rec);
                radiance += throughput.mul_elem(direct);
            }
            let lobe = if bsdf.needs_lobe_number() {
                id.value(Dim::Lobe { depth })
            } else {
                0.0
            };
            let Some(sample) = bsdf.sample(wo, lobe, id.point(Dim::Bsdf { depth })) else {
                break;
            };
            let dir = frame.to_world(sample.wi);
            throughput = throughput.mul_elem(sample.weight);
            if R::ENABLED {
                rec.path(PathEvent::Bsdf {
                    dir,
                    sample,
                    throughput,
                });
            }
            last_pdf = (!sample.delta).then_some(sample.pdf);
            let start = if dir.dot(n) > 0.0 { sides[0] } else { sides[1] };
            if sample.transmitted {
                medium = if entering { m.absorption() } else { None };
                ctx.stats.refraction_rays += 1;
            } else {
                ctx.stats.reflection_rays += 1;
            }
            depth += 1;
            if depth > ROULETTE_FROM {
                let keep = throughput.max_elem().min(0.95);
                if id.value(Dim::Roulette { depth }) >= keep {
                    break;
                }
                throughput *= 1.0 / keep;
            }
            if !throughput.is_finite() || throughput == Vec3::ZERO {
                break;
            }
            ray = Ray::with_time(start, dir, ray.time);
            found = scene.accel().closest_hit(&ray, f32::INFINITY);
        }
        radiance
    }
}

impl PathTracer<'_> {
    /// Next-event estimation at a vertex: a point of one emitter, the radiance it
    /// sends towards the vertex through the BSDF, weighted against BSDF sampling.
    fn light_sample<R: Recorder>(
        &self,
        bsdf: &Bsdf,
        at: &Vertex,
        id: &SampleId,
        ctx: &mut TraceContext,
        rec: &mut R,
    ) -> Vec3 {
        let emitters = self.scene.emitters();
        let depth = at.depth;
        let Some((emitter, pmf)) = emitters.choose(id.value(Dim::LightChoice { depth })) else {
            return Vec3::ZERO;
        };
        let u = id.point(Dim::LightPoint { depth });
        let Some(light) = emitters.sample(emitter, pmf, self.scene.accel().bvh(), at.sides[0], u) else {
            return Vec3::ZERO;
        };
        let wi_world = (light.point - at.sides[0]).normalize();
        let wi = at.frame.to_local(wi_world);
        // The geometric and the shading normal must agree on the side the light is
        // on (the light reaches the far side only through a transmissive lobe).
        let above = wi_world.dot(at.n) > 0.0;
        if above != (wi.z > 0.0) {
            return Vec3::ZERO;
        }
        let (f, bsdf_pdf) = bsdf.eval(at.wo, wi);
        let f_cos = f * wi.z.abs();
        if f_cos == Vec3::ZERO {
            return Vec3::ZERO;
        }
        ctx.stats.shadow_rays += 1;
        let start = if above { at.sides[0] } else { at.sides[1] };
        let shadow = Ray::with_time(start, light.point - start, at.time);
        if self.scene.accel().occluded(&shadow, 1.0 - SHADOW_SHORTFALL) {
            ctx.stats.shadow_blocked += 1;
            if R::ENABLED {
                rec.path(PathEvent::Light {
                    point: light.point,
                    contribution: Vec3::ZERO,
                    weight: 0.0,
                    blocked: true,
                });
            }
            return Vec3::ZERO;
        }
        let weight = light
            .pdf
            .map_or(1.0, |light_pdf| power_heuristic(light_pdf, bsdf_pdf));
        let contribution = f_cos.mul_elem(light.incoming) * weight;
        if R::ENABLED {
            rec.path(PathEvent::Light {
                point: light.point,
                contribution,
                weight,
                blocked: false,
            });
        }
        contribution
    }
}

/// A path vertex as next-event estimation needs it.
struct Vertex<'f> {
    /// The shading frame.
    frame: &'f Frame,
    /// Towards where the path came from, in the frame.
    wo: Vec3,
    /// Points off the surface on the incoming side and on the far side.
    sides: [Vec3; 2],
    /// The geometric normal facing the incoming ray.
    n: Vec3,
    time: f32,
    depth: u32,
}
