//! The path tracer's wavefront: a block of eye samples' paths traced together, one
//! segment of all of them at a time, their state in queues (after pbrt-v4's
//! `WavefrontPathIntegrator`, Laine, Karras and Aila's "Megakernels Considered
//! Harmful" and MoonRay's vectorized path tracing).
//!
//! Each round takes the paths still going through the same stages, each stage over
//! its whole queue:
//!
//! ```text
//! arrive    the segment's closest hit: the background or the emission met,
//!           absorption on the way; the vertex where the path goes on, if any
//! light     each vertex's light sample: a shadow ray into the shadow queue
//! bounce    each vertex's BSDF sample and Russian roulette: the next segment
//! shadows   the shadow queue's occlusion queries; unblocked samples add their light
//! extend    the next segments' closest hits
//! ```
//!
//! The eye rays' hits come with the block (the row loop traces them in packets of
//! neighbouring pixels). Every path takes the very steps of the scalar path tracer
//! ([`PathTracer::arrive`], [`PathTracer::light_query`],
//! [`PathTracer::light_result`], [`PathTracer::bounce`]) in the same order, only
//! interleaved with other paths', so each radiance is bit for bit the scalar
//! one's: the queues change how the work is batched, never its arithmetic. The
//! queues hold one block ([`super::rows::BLOCK_PATHS`] paths at most), so a render's
//! memory per thread is bounded whatever its size and samples.

use std::time::Instant;

mod lanes;
mod smooth;

use lanes::LANES;
use smooth::Vertices8;

use super::bsdf::SmoothLobes;
use super::integrator::{NoRecord, Streams, TraceContext};
use super::path::{PathState, PathTracer, Scatter, ShadowQuery};
use super::rows::EyeBlock;
use super::stats::Stage;
use crate::accel::{Aggregate, Coherence, Ray8, PACKET};
use crate::geometry::Hit;
use crate::math::{Ray, Vec3};

/// One round's queues, reused from round to round.
#[derive(Default)]
struct Queues {
    /// Paths still going, by index into the block, and their segments' hits.
    active: Vec<(u32, Option<(Hit, u32)>)>,
    /// Paths at a vertex where they scatter, as they arrive and grouped by material.
    scatter: Vec<(u32, Scatter)>,
    sorted: Vec<(u32, Scatter)>,
    /// Light samples waiting for their shadow rays.
    shadows: Vec<(u32, ShadowQuery)>,
    /// Whether each shadow ray is blocked.
    blocked: Vec<bool>,
    /// Paths going on to a next segment, its ray and its closest hit.
    next: Vec<u32>,
    rays: Vec<Ray>,
    hits: Vec<Option<(Hit, u32)>>,
}

impl Streams for PathTracer<'_> {
    fn stream_radiances(&self, block: &EyeBlock, ctx: &mut TraceContext, out: &mut Vec<Vec3>) {
        let mut paths: Vec<PathState> = block.rays.iter().map(|&eye| PathState::new(eye)).collect();
        let mut q = Queues::default();
        q.active
            .extend((0..paths.len() as u32).zip(block.found.iter().copied()));
        let accel = self.scene().accel();
        while !q.active.is_empty() {
            ctx.stages.rounds += 1;
            let mut clock = Instant::now();
            // arrive
            let arriving = q.active.len();
            for &(i, found) in &q.active {
                if let Some(at) = self.arrive(&mut paths[i as usize], found, ctx, &mut NoRecord) {
                    q.scatter.push((i, at));
                }
            }
            q.active.clear();
            // Vertices grouped by material (and side), for eight-lane shading.
            sort_by_material(&mut q.scatter, &mut q.sorted);
            clock = ctx.stages.add(Stage::Arrive, arriving, clock);
            // light
            for group in groups(&q.sorted) {
                match self.smooth_lobes(group) {
                    Some(lobes) => {
                        for at in group.chunks(LANES) {
                            let v = Vertices8 {
                                at,
                                ids: &block.ids,
                                lobes,
                            };
                            self.light_queries8(&v, &paths, ctx, &mut q.shadows);
                        }
                    }
                    None => {
                        for (i, at) in group {
                            let i = *i as usize;
                            if let Some(query) = self.light_query(&paths[i], at, &block.ids[i], ctx) {
                                q.shadows.push((i as u32, query));
                            }
                        }
                    }
                }
            }
            clock = ctx.stages.add(Stage::Light, q.sorted.len(), clock);
            // shadows
            occluded(accel, &q.shadows, &mut q.blocked);
            for ((i, query), &blocked) in q.shadows.iter().zip(&q.blocked) {
                self.light_result(&mut paths[*i as usize], query, blocked, ctx, &mut NoRecord);
            }
            clock = ctx.stages.add(Stage::Shadows, q.shadows.len(), clock);
            q.shadows.clear();
            // bounce
            q.next.clear();
            for group in groups(&q.sorted) {
                match self.smooth_lobes(group) {
                    Some(lobes) => {
                        for at in group.chunks(LANES) {
                            let v = Vertices8 {
                                at,
                                ids: &block.ids,
                                lobes,
                            };
                            self.bounces8(&v, &mut paths, ctx, &mut q.next);
                        }
                    }
                    None => {
                        for (i, at) in group {
                            let path = &mut paths[*i as usize];
                            if self.bounce(path, at, &block.ids[*i as usize], ctx, &mut NoRecord) {
                                q.next.push(*i);
                            }
                        }
                    }
                }
            }
            clock = ctx.stages.add(Stage::Bounce, q.sorted.len(), clock);
            // extend
            q.rays.clear();
            q.rays.extend(q.next.iter().map(|&i| paths[i as usize].ray));
            closest_hits(accel, &q.rays, &mut q.hits);
            q.active
                .extend(q.next.iter().copied().zip(q.hits.iter().copied()));
            ctx.stages.add(Stage::Extend, q.rays.len(), clock);
        }
        out.extend(paths.iter().map(|p| p.radiance));
    }
}

impl PathTracer<'_> {
    /// The smooth lobes of the material of a group of vertices (one material, one
    /// side), if it has only smooth diffuse and mirror lobes.
    fn smooth_lobes(&self, group: &[(u32, Scatter)]) -> Option<SmoothLobes> {
        let at = &group.first()?.1;
        self.bsdf(at.material, at.entering).smooth_lobes()
    }
}

/// The key vertices are grouped by: their material, and the side it is met from.
#[inline(always)]
fn material_key(at: &Scatter) -> usize {
    2 * at.material as usize + usize::from(at.entering)
}

/// `scatter` into `sorted` by material and side (a stable counting sort), emptying
/// `scatter`.
fn sort_by_material(scatter: &mut Vec<(u32, Scatter)>, sorted: &mut Vec<(u32, Scatter)>) {
    sorted.clear();
    let Some(&fill) = scatter.first() else {
        return;
    };
    let keys = scatter
        .iter()
        .map(|(_, at)| material_key(at))
        .max()
        .map_or(0, |k| k + 1);
    let mut starts = vec![0usize; keys + 1];
    for (_, at) in scatter.iter() {
        starts[material_key(at) + 1] += 1;
    }
    for k in 1..=keys {
        starts[k] += starts[k - 1];
    }
    sorted.resize(scatter.len(), fill);
    for entry in scatter.drain(..) {
        let key = material_key(&entry.1);
        sorted[starts[key]] = entry;
        starts[key] += 1;
    }
}

/// The runs of vertices of one material and side in `sorted`.
fn groups(sorted: &[(u32, Scatter)]) -> impl Iterator<Item = &[(u32, Scatter)]> {
    sorted.chunk_by(|a, b| material_key(&a.1) == material_key(&b.1))
}

/// The closest hits of `rays`, eight rays of any directions at a time.
fn closest_hits(accel: &Aggregate, rays: &[Ray], out: &mut Vec<Option<(Hit, u32)>>) {
    out.clear();
    for packet in rays.chunks(PACKET) {
        let mut hits = [None; PACKET];
        let active = (1 << packet.len()) - 1;
        accel.closest_hits8(
            &Ray8::new(packet),
            f32::INFINITY,
            active,
            Coherence::Mixed,
            &mut hits,
        );
        out.extend_from_slice(&hits[..packet.len()]);
    }
}

/// Whether the shadow ray of each of `queries` is blocked, eight rays of any
/// directions at a time.
fn occluded(accel: &Aggregate, queries: &[(u32, ShadowQuery)], out: &mut Vec<bool>) {
    out.clear();
    for packet in queries.chunks(PACKET) {
        let mut rays = [packet[0].1.ray; PACKET];
        let mut t_max = [0.0; PACKET];
        for (k, (_, query)) in packet.iter().enumerate() {
            (rays[k], t_max[k]) = (query.ray, query.t_max);
        }
        let n = packet.len();
        let blocked = accel.occluded8(&Ray8::new(&rays[..n]), &t_max, (1 << n) - 1, Coherence::Mixed);
        out.extend((0..n).map(|k| blocked >> k & 1 != 0));
    }
}
