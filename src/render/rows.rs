//! The one sample loop. Every picture nffrt makes — a full render, a tile, a
//! progressive pass of the viewer, a preview, a Python call — is rows of pixels,
//! each adding a range of its samples into its sums through [`RowTracer::add_samples`]:
//! sample `k` of every pixel of the row is taken together, its eye rays made in
//! blocks by the camera and traced through the acceleration structure in packets,
//! then handed to the integrator. So the viewer renders as fast per sample as
//! `nffrt render`, and the two cannot drift apart.
//!
//! Rows run in parallel ([`each_row`]), each a task of its own with a fresh
//! [`TraceContext`]; everything a sample draws is hashed from absolute pixel
//! coordinates, so images are the same whatever the thread count or the tiling.

use std::ops::Range;
use std::time::Instant;

use rayon::prelude::*;

use super::camera::{Camera, CameraSample};
use super::integrator::{ChosenIntegrator, Integrator, Recorder, Streams, TraceContext};
use super::sampling::{PixelSampler, PixelSeeds, SampleId};
use super::{Observer, Stage, Stats};
use crate::accel::{Coherence, Ray8, PACKET};
use crate::geometry::Hit;
use crate::math::{Ray, Vec3};
use crate::options::{RenderOptions, Sampling};
use crate::prepare::RenderScene;
use crate::scene::View;

/// The tracer of one picture's rows, holding what they share: the scene, the
/// camera, the samples' pattern and the integrator.
pub struct RowTracer<'a> {
    scene: &'a RenderScene,
    camera: Camera,
    sampler: PixelSampler,
    integrator: ChosenIntegrator<'a>,
}

impl<'a> RowTracer<'a> {
    /// The frame of a render of `scene` seen by `view` with `opts`.
    pub fn new(scene: &'a RenderScene, view: &View, opts: &RenderOptions) -> Self {
        let camera = Camera::new(view, opts).with_shutter(scene.shutter());
        RowTracer {
            sampler: opts
                .sampling
                .pixel_sampler(camera.has_lens(), scene.has_motion(), opts.seed),
            camera,
            scene,
            integrator: ChosenIntegrator::new(scene, opts),
        }
    }

    /// The same frame with the centre sample of each pixel through the centre of the
    /// lens (a preview).
    pub fn centres(mut self) -> Self {
        self.sampler = Sampling::PixelCenters.pixel_sampler(false, false, 0);
        self
    }

    /// The camera.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// The pattern of each pixel's samples.
    pub fn sampler(&self) -> &PixelSampler {
        &self.sampler
    }

    /// The integrator.
    pub fn integrator(&self) -> &ChosenIntegrator<'a> {
        &self.integrator
    }

    /// Adds samples `samples` of the pixels at columns `xs` of row `y`, each times
    /// `weight`, to `sums` (one per column), sample by sample in order: the very
    /// products, in the very order, whatever the split of the samples into calls.
    ///
    /// The samples go to the integrator in blocks of at most [`BLOCK_PATHS`] eye
    /// samples (all the pixels' samples of a run of sample numbers, or one sample of
    /// a run of pixels when a row alone is larger), each block's eye rays traced in
    /// packets of eight neighbouring pixels first ([`EyeBlock`]).
    pub fn add_samples(
        &self,
        y: u32,
        xs: &[u32],
        samples: Range<u32>,
        weight: f32,
        sums: &mut [Vec3],
        ctx: &mut TraceContext,
    ) {
        debug_assert_eq!(xs.len(), sums.len());
        let span = xs.len().clamp(1, BLOCK_PATHS);
        let per_block = (BLOCK_PATHS / span).max(1) as u32;
        let mut block = EyeBlock::default();
        let mut radiances = Vec::new();
        for (xs, sums) in xs.chunks(span).zip(sums.chunks_mut(span)) {
            let pixels: Vec<_> = xs.iter().map(|&x| self.sampler.pixel(x, y)).collect();
            let mut k0 = samples.start;
            while k0 < samples.end {
                let k1 = samples.end.min(k0.saturating_add(per_block));
                block.clear();
                let start = Instant::now();
                for k in k0..k1 {
                    self.eye_rays(&pixels, k, &mut block, ctx);
                }
                ctx.stages.add(Stage::Camera, block.len(), start);
                radiances.clear();
                self.integrator.stream_radiances(&block, ctx, &mut radiances);
                // Sample by sample, each pixel's in order.
                for (row, _) in radiances.chunks(xs.len()).zip(k0..k1) {
                    for (sum, &c) in sums.iter_mut().zip(row) {
                        *sum += finite_or_black(c) * weight;
                    }
                }
                k0 = k1;
            }
        }
    }

    /// Sample `k` of `pixels` added to `block`: its eye rays made by the camera and
    /// traced through the acceleration structure in packets of eight neighbours
    /// (packets find the very hits single rays find).
    fn eye_rays(&self, pixels: &[PixelSeeds], k: u32, block: &mut EyeBlock, ctx: &mut TraceContext) {
        for pixels in pixels.chunks(PACKET) {
            let (mut cams, mut ids) = (
                [CameraSample::at(0.0, 0.0); PACKET],
                [SampleId::single(0, 0); PACKET],
            );
            for (i, pixel) in pixels.iter().enumerate() {
                (cams[i], ids[i]) = self.sampler.sample_of(pixel, k);
            }
            let n = pixels.len();
            let packet = self.camera.rays8(&cams[..n]);
            let mut hits = [None; PACKET];
            self.scene.accel().closest_hits8(
                &packet,
                f32::INFINITY,
                (1 << n) - 1,
                Coherence::Coherent,
                &mut hits,
            );
            ctx.stats.eye_rays += n as u64;
            block.push_packet(&packet, &hits[..n], &ids[..n]);
        }
    }

    /// The values of the pinhole rays through the raster points `(x, y)`, `x` in
    /// `xs`, for the SPD protocol's pixel corners (single samples, no jitter), into
    /// `out`.
    pub fn corners(&self, y: u32, xs: &[u32], out: &mut Vec<Vec3>, ctx: &mut TraceContext) {
        let rays: Vec<Ray> = xs
            .iter()
            .map(|&x| self.camera.ray_at(x as f32, y as f32))
            .collect();
        let ids: Vec<SampleId> = xs.iter().map(|&x| SampleId::single(x, y)).collect();
        for (rays, ids) in rays.chunks(PACKET).zip(ids.chunks(PACKET)) {
            self.trace_packet(&Ray8::new(rays), rays, ids, ctx, |_, c| out.push(c));
        }
    }

    /// Eye rays `rays[i]` of samples `ids[i]` (one to [`PACKET`] of them), packed in
    /// `packet` too, traced through the acceleration structure together (packets find
    /// the very hits single rays find), each then given to the integrator; calls
    /// `done(i, radiance)` in order, a NaN or infinite radiance as black. (The SPD
    /// protocol's corners; samples go through [`RowTracer::add_samples`].)
    fn trace_packet(
        &self,
        packet: &Ray8,
        rays: &[Ray],
        ids: &[SampleId],
        ctx: &mut TraceContext,
        mut done: impl FnMut(usize, Vec3),
    ) {
        let n = rays.len();
        debug_assert!((1..=PACKET).contains(&n) && ids.len() == n);
        let mut hits = [None; PACKET];
        self.scene.accel().closest_hits8(
            packet,
            f32::INFINITY,
            (1 << n) - 1,
            Coherence::Coherent,
            &mut hits,
        );
        ctx.stats.eye_rays += n as u64;
        self.integrator
            .eye_radiances(rays, &hits[..n], ids, ctx, |i, radiance| {
                done(i, finite_or_black(radiance))
            });
    }

    /// The radiance of one eye sample, reported to `rec` (`--pixel`): the ray of
    /// `sample` traced alone, as [`RowTracer::add_samples`] traces it in a packet.
    pub fn sample_radiance<R: Recorder>(
        &self,
        sample: &CameraSample,
        id: &SampleId,
        ctx: &mut TraceContext,
        rec: &mut R,
    ) -> Vec3 {
        self.ray_radiance(&self.camera.ray(sample), id, ctx, rec)
    }

    /// The radiance along `ray` traced as the eye ray of sample `id`, reported to
    /// `rec`.
    pub fn ray_radiance<R: Recorder>(
        &self,
        ray: &Ray,
        id: &SampleId,
        ctx: &mut TraceContext,
        rec: &mut R,
    ) -> Vec3 {
        ctx.stats.eye_rays += 1;
        let found = self.scene.accel().closest_hit(ray, f32::INFINITY);
        finite_or_black(self.integrator.eye_radiance(ray, found, id, ctx, rec))
    }
}

/// The most eye samples [`RowTracer::add_samples`] hands the integrator at once: it
/// bounds a render's memory per thread (the wavefront's queues hold one block's
/// paths), whatever the picture's size and samples per pixel.
pub const BLOCK_PATHS: usize = 4096;

/// Eye samples handed to an integrator together: their eye rays, the rays' closest
/// hits and the samples, in packets of up to eight neighbouring pixels of one
/// sample number, packets in the order they were traced.
#[derive(Default)]
pub struct EyeBlock {
    /// The eye rays.
    pub rays: Vec<Ray>,
    /// Their closest hits.
    pub found: Vec<Option<(Hit, u32)>>,
    /// Their samples.
    pub ids: Vec<SampleId>,
    /// Where each packet ends in the lists.
    ends: Vec<usize>,
}

impl EyeBlock {
    /// Empties the block, keeping its memory.
    pub fn clear(&mut self) {
        self.rays.clear();
        self.found.clear();
        self.ids.clear();
        self.ends.clear();
    }

    /// Adds a packet: its rays, their hits and their samples.
    pub fn push_packet(&mut self, packet: &Ray8, found: &[Option<(Hit, u32)>], ids: &[SampleId]) {
        for (k, (hit, id)) in found.iter().zip(ids).enumerate() {
            self.rays.push(packet.ray(k));
            self.found.push(*hit);
            self.ids.push(*id);
        }
        self.ends.push(self.rays.len());
    }

    /// The packets as ranges of the lists, in order.
    pub fn packets(&self) -> impl Iterator<Item = Range<usize>> + '_ {
        let starts = std::iter::once(0).chain(self.ends.iter().copied());
        starts.zip(self.ends.iter().copied()).map(|(a, b)| a..b)
    }

    /// The number of eye samples.
    pub fn len(&self) -> usize {
        self.rays.len()
    }

    /// True for a block without samples.
    pub fn is_empty(&self) -> bool {
        self.rays.is_empty()
    }
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

/// Runs `row(j, place, ctx)` on each row `j` of `pixels` (rows of `cols`) in
/// parallel, each writing its row in place with a fresh [`TraceContext`]; reports
/// each row's rays to the observer and sums the counts. `None` once the observer
/// cancels (rows not started then are left as they were).
///
/// Every row is a task of its own that an idle thread can steal: rayon's default
/// splitting stops once each thread holds a few long runs of rows, and where rows
/// differ much in cost (mount: sky above, glass spheres and terrain below) one thread
/// then worked alone through the end of the image, a third of the render.
pub fn each_row(
    pixels: &mut [Vec3],
    cols: usize,
    observer: &dyn Observer,
    row: impl Fn(u32, &mut [Vec3], &mut TraceContext) + Sync,
) -> Option<Stats> {
    let per_row: Option<Vec<Stats>> = pixels
        .par_chunks_mut(cols)
        .enumerate()
        .with_max_len(1)
        .map(|(j, place)| {
            if observer.cancelled() {
                return None;
            }
            let mut ctx = TraceContext::default();
            row(j as u32, place, &mut ctx);
            if !ctx.stages.is_empty() {
                observer.row_stages(&ctx.stages);
            }
            observer.row_done(ctx.stats.total_rays());
            Some(ctx.stats)
        })
        .collect();
    let mut stats = Stats::default();
    for s in per_row? {
        stats += s;
    }
    Some(stats)
}
