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

use super::integrator::{NoRecord, Streams, TraceContext};
use super::path::{PathState, PathTracer, Scatter, ShadowQuery};
use super::rows::EyeBlock;
use super::sampling::SampleId;
use super::stats::Stage;
use crate::accel::{Aggregate, Coherence, Ray8, PACKET};
use crate::geometry::Hit;
use crate::math::Vec3;

/// One round's queues, reused from round to round.
#[derive(Default)]
struct Queues {
    /// Paths still going, by index into the block, and their segments' hits.
    active: Vec<(u32, Option<(Hit, u32)>)>,
    /// Paths at a vertex where they scatter, as they arrive, and their positions
    /// ordered by material.
    scatter: Vec<(u32, Scatter)>,
    order: Vec<u32>,
    /// Light samples waiting for their shadow rays.
    shadows: Vec<(u32, ShadowQuery)>,
    /// Whether each shadow ray is blocked.
    blocked: Vec<bool>,
    /// Paths going on to a next segment.
    next: Vec<u32>,
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
            sort_by_material(&q.scatter, &mut q.order);
            clock = ctx.stages.add(Stage::Arrive, arriving, clock);
            // light
            let (scatter, order, ids) = (&q.scatter, &q.order, &block.ids);
            self.each_group(scatter, order, ids, |group| match group {
                Group::Lanes(v) => self.light_queries8(&v, &paths, ctx, &mut q.shadows),
                Group::One(i, at) => {
                    if let Some(query) = self.light_query(&paths[i as usize], at, &ids[i as usize], ctx) {
                        q.shadows.push((i, query));
                    }
                }
            });
            clock = ctx.stages.add(Stage::Light, scatter.len(), clock);
            // shadows
            occluded(accel, &q.shadows, &mut q.blocked);
            for ((i, query), &blocked) in q.shadows.iter().zip(&q.blocked) {
                self.light_result(&mut paths[*i as usize], query, blocked, ctx, &mut NoRecord);
            }
            clock = ctx.stages.add(Stage::Shadows, q.shadows.len(), clock);
            q.shadows.clear();
            // bounce
            q.next.clear();
            self.each_group(scatter, order, ids, |group| match group {
                Group::Lanes(v) => self.bounces8(&v, &mut paths, ctx, &mut q.next),
                Group::One(i, at) => {
                    if self.bounce(&mut paths[i as usize], at, &ids[i as usize], ctx, &mut NoRecord) {
                        q.next.push(i);
                    }
                }
            });
            clock = ctx.stages.add(Stage::Bounce, scatter.len(), clock);
            q.scatter.clear();
            // extend: ray by ray (on incoherent rays the single-ray walk beats the
            // mixed packet walk; `nffrt bench`'s random rays, BENCHMARKS.md)
            q.active.extend(
                q.next
                    .iter()
                    .map(|&i| (i, accel.closest_hit(&paths[i as usize].ray, f32::INFINITY))),
            );
            ctx.stages.add(Stage::Extend, q.next.len(), clock);
        }
        out.extend(paths.iter().map(|p| p.radiance));
    }
}

impl PathTracer<'_> {
    /// Hands the vertices `scatter` to a step, grouped by material and side as
    /// `order` lists them: eight at a time where the material has only smooth
    /// lobes and no texture, else one at a time (with its path's index).
    fn each_group<'v>(
        &self,
        scatter: &'v [(u32, Scatter)],
        order: &'v [u32],
        ids: &'v [SampleId],
        mut step: impl FnMut(Group<'v>),
    ) {
        let key = |&pick: &u32| material_key(&scatter[pick as usize].1);
        let materials = self.scene().materials();
        for group in order.chunk_by(|a, b| key(a) == key(b)) {
            let at = &scatter[group[0] as usize].1;
            // A textured material's BSDF changes from vertex to vertex.
            let textured = materials[at.material as usize].texture.is_some();
            match self
                .bsdf(at.material, at.entering)
                .smooth_lobes()
                .filter(|_| !textured)
            {
                Some(lobes) => {
                    for picks in group.chunks(LANES) {
                        step(Group::Lanes(Vertices8 {
                            scatter,
                            picks,
                            ids,
                            lobes,
                        }));
                    }
                }
                None => {
                    for &pick in group {
                        let (i, at) = &scatter[pick as usize];
                        step(Group::One(*i, at));
                    }
                }
            }
        }
    }
}

/// What [`PathTracer::each_group`] hands a step: up to eight vertices of a smooth
/// material, or one vertex (and its path's index).
enum Group<'v> {
    Lanes(Vertices8<'v>),
    One(u32, &'v Scatter),
}

/// The key vertices are grouped by: their material, and the side it is met from.
#[inline(always)]
fn material_key(at: &Scatter) -> usize {
    2 * at.material as usize + usize::from(at.entering)
}

/// The positions of `scatter`'s vertices ordered by material and side (a stable
/// counting sort), into `order`.
fn sort_by_material(scatter: &[(u32, Scatter)], order: &mut Vec<u32>) {
    order.clear();
    let keys = scatter
        .iter()
        .map(|(_, at)| material_key(at))
        .max()
        .map_or(0, |k| k + 1);
    let mut starts = vec![0usize; keys + 1];
    for (_, at) in scatter {
        starts[material_key(at) + 1] += 1;
    }
    for k in 1..=keys {
        starts[k] += starts[k - 1];
    }
    order.resize(scatter.len(), 0);
    for (pick, (_, at)) in scatter.iter().enumerate() {
        let key = material_key(at);
        order[starts[key]] = pick as u32;
        starts[key] += 1;
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
