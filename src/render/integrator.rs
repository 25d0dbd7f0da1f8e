//! The integrator seam: what the row loop asks of a light-transport method, and
//! what a method tells an observer of one pixel.
//!
//! An [`Integrator`] answers one question: the radiance arriving at the camera along
//! an eye ray of one sample, given the ray's closest hit (which the row loop finds
//! for a packet of eye rays at once). Whitted ray tracing ([`super::whitted`], with
//! the SPD's or the P3F course's shading rules) is one implementation, path tracing
//! ([`super::path`]) the other;
//! [`ChosenIntegrator`] is the one a render uses, chosen once from the scene and the
//! options.
//!
//! A method reports what it does to a [`Recorder`]. Renders pass [`NoRecord`], whose
//! `ENABLED = false` turns every report into dead code, so the hot path pays nothing;
//! `--pixel` passes a recorder that keeps the ray tree (`render::debug`). One code
//! path thus both renders and explains a pixel.

use std::cell::Cell;

use super::bsdf::BsdfSample;
use super::light::LightSampling;
use super::path::PathTracer;
use super::rows::EyeBlock;
use super::shade::{AffRules, Branch, P3fRules, SpdRules};
use super::stats::{StageStats, Stats};
use super::whitted::Whitted;
use crate::accel::NO_HINT;
use crate::geometry::{Hit, Primitive};
use crate::image::skybox::SkyTexel;
use crate::math::{Ray, Vec3};
use crate::options::RenderOptions;
use crate::prepare::Model;
use crate::prepare::RenderScene;
use crate::scene::IntegratorKind;

use super::sampling::SampleId;

/// A light-transport method (see the module docs).
pub trait Integrator: Sync {
    /// The radiance arriving along eye ray `ray` of sample `id`, whose closest hit is
    /// `found` (the primitive's index as the scene's acceleration structure reports
    /// it), reported to `rec`. NaN and infinity are the caller's to catch.
    fn eye_radiance<R: Recorder>(
        &self,
        ray: &Ray,
        found: Option<(Hit, u32)>,
        id: &SampleId,
        ctx: &mut TraceContext,
        rec: &mut R,
    ) -> Vec3;

    /// The radiances of a packet of neighbouring eye rays `rays[i]` of samples
    /// `ids[i]`, whose closest hits are `found[i]`, given in order to
    /// `done(i, radiance)`: bit for bit what [`Integrator::eye_radiance`] gives each
    /// (unrecorded), with the same ray counts. The default takes them one at a time;
    /// a method may trace rays of different eye rays together.
    fn eye_radiances(
        &self,
        rays: &[Ray],
        found: &[Option<(Hit, u32)>],
        ids: &[SampleId],
        ctx: &mut TraceContext,
        mut done: impl FnMut(usize, Vec3),
    ) {
        for (i, ((ray, &found), id)) in rays.iter().zip(found).zip(ids).enumerate() {
            done(i, self.eye_radiance(ray, found, id, ctx, &mut NoRecord));
        }
    }
}

/// What the row loop asks of an integrator for a block of eye samples at once (the
/// seam where a method may trace many paths together): each sample's radiance,
/// pushed onto `out` in the block's order, bit for bit what
/// [`Integrator::eye_radiance`] gives it (unrecorded), with the same ray counts. NaN
/// and infinity are the caller's to catch.
pub trait Streams {
    /// The radiances of `block`'s eye samples (see the trait's docs).
    fn stream_radiances(&self, block: &EyeBlock, ctx: &mut TraceContext, out: &mut Vec<Vec3>);
}

/// The integrator of one render: chosen once from the render's options and the
/// scene's shading rules, then asked per eye ray (one predictable branch).
pub enum ChosenIntegrator<'a> {
    /// Whitted ray tracing under the SPD's rules (NFF scenes).
    WhittedSpd(Whitted<'a, SpdRules>),
    /// Whitted ray tracing under the P3F course's rules.
    WhittedP3f(Whitted<'a, P3fRules>),
    /// Whitted ray tracing under BART's original renderer's rules (AFF scenes).
    WhittedAff(Whitted<'a, AffRules>),
    /// Path tracing.
    Path(PathTracer<'a>),
}

impl<'a> ChosenIntegrator<'a> {
    /// The integrator for rendering `scene` with `opts`.
    pub fn new(scene: &'a RenderScene, opts: &RenderOptions) -> Self {
        let sampling = LightSampling {
            grid_override: opts.light_samples,
            soft_shadows: opts.soft_shadows,
        };
        match (opts.integrator, scene.lighting().model) {
            (IntegratorKind::Path, _) => {
                ChosenIntegrator::Path(PathTracer::new(scene, opts.max_depth, opts.roughness))
            }
            (IntegratorKind::Whitted, Model::Spd) => {
                ChosenIntegrator::WhittedSpd(Whitted::new(scene, sampling, opts.max_depth, opts.roughness))
            }
            (IntegratorKind::Whitted, Model::P3f) => {
                ChosenIntegrator::WhittedP3f(Whitted::new(scene, sampling, opts.max_depth, opts.roughness))
            }
            (IntegratorKind::Whitted, Model::Aff) => {
                ChosenIntegrator::WhittedAff(Whitted::new(scene, sampling, opts.max_depth, opts.roughness))
            }
        }
    }
}

impl Integrator for ChosenIntegrator<'_> {
    #[inline]
    fn eye_radiance<R: Recorder>(
        &self,
        ray: &Ray,
        found: Option<(Hit, u32)>,
        id: &SampleId,
        ctx: &mut TraceContext,
        rec: &mut R,
    ) -> Vec3 {
        match self {
            ChosenIntegrator::WhittedSpd(w) => w.eye_radiance(ray, found, id, ctx, rec),
            ChosenIntegrator::WhittedP3f(w) => w.eye_radiance(ray, found, id, ctx, rec),
            ChosenIntegrator::WhittedAff(w) => w.eye_radiance(ray, found, id, ctx, rec),
            ChosenIntegrator::Path(p) => p.eye_radiance(ray, found, id, ctx, rec),
        }
    }

    #[inline]
    fn eye_radiances(
        &self,
        rays: &[Ray],
        found: &[Option<(Hit, u32)>],
        ids: &[SampleId],
        ctx: &mut TraceContext,
        done: impl FnMut(usize, Vec3),
    ) {
        match self {
            ChosenIntegrator::WhittedSpd(w) => w.eye_radiances(rays, found, ids, ctx, done),
            ChosenIntegrator::WhittedP3f(w) => w.eye_radiances(rays, found, ids, ctx, done),
            ChosenIntegrator::WhittedAff(w) => w.eye_radiances(rays, found, ids, ctx, done),
            ChosenIntegrator::Path(p) => p.eye_radiances(rays, found, ids, ctx, done),
        }
    }
}

impl Streams for ChosenIntegrator<'_> {
    /// Whitted's packet by packet ([`Integrator::eye_radiances`]: its point lights'
    /// shadow rays from a packet's hits go together), the path tracer's as one
    /// wavefront (`super::wavefront`).
    fn stream_radiances(&self, block: &EyeBlock, ctx: &mut TraceContext, out: &mut Vec<Vec3>) {
        match self {
            ChosenIntegrator::WhittedSpd(w) => packet_by_packet(w, block, ctx, out),
            ChosenIntegrator::WhittedP3f(w) => packet_by_packet(w, block, ctx, out),
            ChosenIntegrator::WhittedAff(w) => packet_by_packet(w, block, ctx, out),
            ChosenIntegrator::Path(p) => p.stream_radiances(block, ctx, out),
        }
    }
}

/// `block`'s radiances through `integrator`'s [`Integrator::eye_radiances`], one
/// packet at a time.
fn packet_by_packet(
    integrator: &impl Integrator,
    block: &EyeBlock,
    ctx: &mut TraceContext,
    out: &mut Vec<Vec3>,
) {
    for packet in block.packets() {
        let (rays, found, ids) = (
            &block.rays[packet.clone()],
            &block.found[packet.clone()],
            &block.ids[packet],
        );
        integrator.eye_radiances(rays, found, ids, ctx, |_, c| out.push(c));
    }
}

/// Lights and ray-tree depths with a shadow-cache slot; shadow rays of other lights
/// or deeper bounces simply go without one.
pub const HINT_LIGHTS: usize = 8;
/// See [`HINT_LIGHTS`].
pub const HINT_DEPTHS: usize = 8;

/// What one unit of work (a row of a render) carries from ray to ray: its ray counts
/// and its shadow cache. A fresh context per row keeps each row's work the same
/// whichever thread runs it.
pub struct TraceContext {
    /// Ray counts.
    pub stats: Stats,
    /// The wavefront's stages: their work and time (reported, not rendered).
    pub stages: StageStats,
    /// Shadow cache (Haines): per light and depth, the primitive or leaf block of four
    /// that last blocked a shadow ray (`Bvh::occluded_hinted`). It only changes what
    /// is tested first, never an answer.
    hints: [Cell<u32>; HINT_LIGHTS * HINT_DEPTHS],
    /// Bit `k` set: the shadow rays of point light `k` from a packet of eye hits go
    /// one at a time through the shadow cache rather than as a packet (see
    /// `Whitted::eye_shadows`). Only changes how the answers are found.
    pub(super) eye_shadows_cached: u32,
}

impl Default for TraceContext {
    fn default() -> Self {
        TraceContext {
            stats: Stats::default(),
            stages: StageStats::default(),
            hints: [const { Cell::new(NO_HINT) }; HINT_LIGHTS * HINT_DEPTHS],
            eye_shadows_cached: 0,
        }
    }
}

impl TraceContext {
    /// The shadow-cache slot of light `light` at ray-tree depth `depth` (from 1), if
    /// it has one.
    #[inline(always)]
    pub fn hint(&self, light: usize, depth: u32) -> Option<&Cell<u32>> {
        let depth = depth as usize;
        (light < HINT_LIGHTS && (1..=HINT_DEPTHS).contains(&depth))
            .then(|| &self.hints[light * HINT_DEPTHS + depth - 1])
    }
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
    /// For a ray inside absorbing glass, the fraction of light left after its way
    /// there (Beer-Lambert), which its colour is multiplied by.
    pub absorbed: Option<Vec3>,
    /// The moment the ray sees the scene at.
    pub time: f32,
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

/// Receives the events of an integrator, depth first: for each ray either `miss`,
/// or `hit`, one `light` per light, then for each secondary ray `branch` followed by
/// that ray's own events, and finally `done` with the hit's colour.
pub trait Recorder {
    /// False for a recorder that ignores everything: the integrator then skips
    /// building the reports altogether.
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
    /// A secondary ray with this weight is about to be traced; on a rough surface,
    /// with the direction a smooth one would have given it.
    fn branch(&mut self, _kind: Branch, _weight: Vec3, _smooth: Option<Vec3>) {}
    /// The current hit's final colour.
    fn done(&mut self, _color: Vec3) {}
    /// An event of a path (the path tracer's, in order along the path).
    fn path(&mut self, _event: PathEvent) {}
}

/// What a path tracer reports of a path, in order along it.
#[derive(Clone, Copy, Debug)]
pub enum PathEvent<'a> {
    /// The path's segment `ray` met `primitive` at distance `t`: a vertex at
    /// `point`, geometric normal `normal` facing the ray; `throughput` is the path's
    /// weight arriving there.
    Vertex {
        /// The segment.
        ray: Ray,
        /// What it met.
        primitive: &'a Primitive,
        /// How far along.
        t: f32,
        /// The vertex.
        point: Vec3,
        /// Its normal, facing the segment.
        normal: Vec3,
        /// True if the segment crosses into the object.
        entering: bool,
        /// The path's weight there.
        throughput: Vec3,
    },
    /// The vertex is on an emitter: its radiance, counted with this MIS weight.
    Emitted {
        /// The emitted radiance.
        radiance: Vec3,
        /// Its multiple-importance weight (1 when no other strategy could find it).
        weight: f32,
    },
    /// A light sample at the vertex: the point drawn, what it adds (before the
    /// path's throughput) with its MIS weight, or that a shadow ray was blocked.
    Light {
        /// The light's point.
        point: Vec3,
        /// `f cos Li / pdf`, weighted.
        contribution: Vec3,
        /// Its multiple-importance weight.
        weight: f32,
        /// A blocker was found.
        blocked: bool,
    },
    /// The BSDF sample that continues the path: its direction, the sample, and the
    /// throughput after it.
    Bsdf {
        /// The new direction (world).
        dir: Vec3,
        /// The sample (local direction, weight, pdf, kind).
        sample: BsdfSample,
        /// The throughput after it.
        throughput: Vec3,
    },
    /// The segment `ray` left the scene and sees `radiance` from infinity.
    Escape {
        /// The segment.
        ray: Ray,
        /// The background's radiance.
        radiance: Vec3,
        /// The path's weight.
        throughput: Vec3,
    },
}

/// The recorder of ordinary renders: records nothing, costs nothing.
pub struct NoRecord;

impl Recorder for NoRecord {
    const ENABLED: bool = false;
}
