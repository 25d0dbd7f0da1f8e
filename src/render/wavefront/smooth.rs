//! Eight paths at once at vertices of one material of smooth lobes (diffuse,
//! mirror: `Bsdf::smooth_lobes`): their light samples and their bounces, with the
//! arithmetic of the scalar steps (`PathTracer::light_query`, `PathTracer::bounce`)
//! lane by lane. The sample's numbers, the emitter's choice and its point are drawn
//! lane by lane (integer hashing, a table search); the rest is one operation for all
//! eight lanes. A lane whose lobe number falls past the smooth lobes (rounding can
//! leave the choices' sum a hair below 1) is bounced by the scalar step instead.

use std::f32::consts::{FRAC_1_PI, PI};

use wide::f32x8;

use super::lanes::{bits, first, gather1, Frame8, V3x8, LANES};
use crate::math::{Ray, Vec3};
use crate::render::bsdf::SmoothLobes;
use crate::render::integrator::{NoRecord, TraceContext};
use crate::render::path::{PathState, PathTracer, Scatter, ShadowQuery, ROULETTE_FROM, SHADOW_SHORTFALL};
use crate::render::sampling::{Dim, SampleId};

/// Up to eight vertices of one material and side, and their paths' samples.
pub(super) struct Vertices8<'a> {
    /// The round's vertices: each path's index in the block and its vertex.
    pub scatter: &'a [(u32, Scatter)],
    /// Those of `scatter` taken, by position.
    pub picks: &'a [u32],
    /// Every path's sample, by index in the block.
    pub ids: &'a [SampleId],
    /// The material's lobes.
    pub lobes: SmoothLobes,
}

impl Vertices8<'_> {
    fn len(&self) -> usize {
        self.picks.len()
    }

    /// Vertex `k`'s path, by index in the block.
    fn path(&self, k: usize) -> usize {
        self.scatter[self.picks[k] as usize].0 as usize
    }

    fn vertex(&self, k: usize) -> &Scatter {
        &self.scatter[self.picks[k] as usize].1
    }

    fn id(&self, k: usize) -> &SampleId {
        &self.ids[self.path(k)]
    }

    fn frame(&self) -> Frame8 {
        let n = self.len();
        let mut axes = [[Vec3::ZERO; 3]; LANES];
        for (k, axes) in axes.iter_mut().enumerate().take(n) {
            *axes = self.vertex(k).frame.axes();
        }
        Frame8 {
            s: V3x8::gather(n, |k| axes[k][0]),
            t: V3x8::gather(n, |k| axes[k][1]),
            n: V3x8::gather(n, |k| axes[k][2]),
        }
    }

    fn side(&self, which: usize) -> V3x8 {
        V3x8::gather(self.len(), |k| self.vertex(k).sides[which])
    }

    /// `f` and the density of the smooth lobes' `eval(wo, wi)`: the diffuse lobe's
    /// (a perfect mirror has no density in any given direction).
    #[inline(always)]
    fn eval(&self, wi: V3x8) -> (V3x8, f32x8) {
        let [pd, _] = self.lobes.choice;
        let on = if pd > 0.0 {
            wi.z.simd_gt(f32x8::ZERO)
        } else {
            f32x8::ZERO
        };
        let f = V3x8::select(
            on,
            V3x8::splat(self.lobes.diffuse * FRAC_1_PI),
            V3x8::splat(Vec3::ZERO),
        );
        let pdf = on.bitselect(f32x8::splat(pd) * wi.z * f32x8::splat(FRAC_1_PI), f32x8::ZERO);
        (f, pdf)
    }
}

impl PathTracer<'_> {
    /// The light samples of up to eight vertices `v` (each as `light_query`), their
    /// shadow rays pushed onto `out` with their paths' indices.
    pub(super) fn light_queries8(
        &self,
        v: &Vertices8,
        paths: &[PathState],
        ctx: &mut TraceContext,
        out: &mut Vec<(u32, ShadowQuery)>,
    ) {
        let n = v.len();
        let scene = self.scene();
        let emitters = scene.emitters();
        if v.lobes.choice[0] == 0.0 || emitters.is_empty() {
            return;
        }
        // The emitters' points, lane by lane.
        let mut drawn = 0u32;
        let (mut point, mut incoming) = ([Vec3::ZERO; LANES], [Vec3::ZERO; LANES]);
        let (mut light_pdf, mut has_pdf) = ([0.0f32; LANES], [0.0f32; LANES]);
        for k in 0..n {
            let (id, depth) = (v.id(k), paths[v.path(k)].depth);
            let Some((emitter, pmf)) = emitters.choose(id.value(Dim::LightChoice { depth })) else {
                continue;
            };
            let u = id.point(Dim::LightPoint { depth });
            let from = v.vertex(k).sides[0];
            let Some(light) = emitters.sample(emitter, pmf, scene.accel().bvh(), from, u) else {
                continue;
            };
            drawn |= 1 << k;
            (point[k], incoming[k]) = (light.point, light.incoming);
            if let Some(pdf) = light.pdf {
                (light_pdf[k], has_pdf[k]) = (pdf, f32::from_bits(u32::MAX));
            }
        }
        if drawn == 0 {
            return;
        }
        let frame = v.frame();
        let (side0, side1) = (v.side(0), v.side(1));
        let normal = V3x8::gather(n, |k| v.vertex(k).n);
        let point8 = V3x8::gather(n, |k| point[k]);
        let wi_world = (point8 - side0).normalize();
        let wi = frame.to_local(wi_world);
        // The geometric and the shading normal must agree on the light's side.
        let above = wi_world.dot(normal).simd_gt(f32x8::ZERO);
        let agree = !(above ^ wi.z.simd_gt(f32x8::ZERO));
        let (f, bsdf_pdf) = v.eval(wi);
        let f_cos = f * wi.z.abs();
        let lit = agree & !f_cos.is_zero();
        let start = V3x8::select(above, side0, side1);
        let weight =
            f32x8::from(has_pdf).bitselect(power_heuristic8(f32x8::from(light_pdf), bsdf_pdf), f32x8::ONE);
        let contribution = f_cos.mul_elem(V3x8::gather(n, |k| incoming[k])) * weight;
        let throughput = V3x8::gather(n, |k| paths[v.path(k)].throughput);
        let gain = throughput.mul_elem(contribution);
        let (start, contribution, gain) = (start.lanes(), contribution.lanes(), gain.lanes());
        let weight = weight.to_array();
        let shoot = drawn & bits(lit);
        for k in (0..n).filter(|k| shoot >> k & 1 != 0) {
            let (i, time) = (v.path(k), paths[v.path(k)].ray.time);
            ctx.stats.shadow_rays += 1;
            out.push((
                i as u32,
                ShadowQuery {
                    ray: Ray::with_time(start[k], point[k] - start[k], time),
                    t_max: 1.0 - SHADOW_SHORTFALL,
                    point: point[k],
                    contribution: contribution[k],
                    weight: weight[k],
                    gain: gain[k],
                },
            ));
        }
    }

    /// The bounces of up to eight vertices `v` (each as `bounce`): each path going on
    /// is pushed onto `next`.
    pub(super) fn bounces8(
        &self,
        v: &Vertices8,
        paths: &mut [PathState],
        ctx: &mut TraceContext,
        next: &mut Vec<u32>,
    ) {
        let n = v.len();
        ctx.stages.lane_calls += 1;
        ctx.stages.lanes_filled += n as u64;
        let [pd, pm] = v.lobes.choice;
        let needs_lobe = !matches!(v.lobes.choice, [1.0, 0.0] | [0.0, 1.0]);
        let depth = paths[v.path(0)].depth;
        debug_assert!((0..n).all(|k| paths[v.path(k)].depth == depth));
        let lobe = gather1(n, |k| {
            if needs_lobe {
                v.id(k).value(Dim::Lobe { depth })
            } else {
                0.0
            }
        });
        let mut u = [(0.0, 0.0); LANES];
        for (k, u) in u.iter_mut().enumerate() {
            *u = v.id(k.min(n - 1)).point(Dim::Bsdf { depth });
        }
        let diffuse = lobe.simd_lt(f32x8::splat(pd));
        let mirror = !diffuse & lobe.simd_lt(f32x8::splat(pd + pm));
        // Lanes past both lobes: the scalar step.
        let elsewhere = bits(first(n) & !diffuse & !mirror);
        // The diffuse lobe: a cosine-weighted direction, weighed as `spread`.
        let wo = V3x8::gather(n, |k| v.vertex(k).wo);
        let wi_diffuse = cosine_hemisphere8(&u);
        let (f, pdf_diffuse) = v.eval(wi_diffuse);
        let weight_diffuse = f * (wi_diffuse.z.abs() / pdf_diffuse);
        let spread = pdf_diffuse.simd_gt(f32x8::ZERO);
        // The mirror lobe.
        let wi_mirror = V3x8 {
            x: -wo.x,
            y: -wo.y,
            z: wo.z,
        };
        let weight_mirror = V3x8::splat(v.lobes.mirror / pm);
        let wi = V3x8::select(diffuse, wi_diffuse, wi_mirror);
        let weight = V3x8::select(diffuse, weight_diffuse, weight_mirror);
        let pdf = diffuse.bitselect(pdf_diffuse, f32x8::splat(pm));
        let sampled = (diffuse & spread) | mirror;
        let frame = v.frame();
        let dir = frame.to_world(wi);
        let mut throughput = V3x8::gather(n, |k| paths[v.path(k)].throughput).mul_elem(weight);
        let normal = V3x8::gather(n, |k| v.vertex(k).n);
        let start = V3x8::select(dir.dot(normal).simd_gt(f32x8::ZERO), v.side(0), v.side(1));
        let mut going = sampled;
        let depth = depth + 1;
        if depth > ROULETTE_FROM {
            let keep = throughput.max_elem().fast_min(f32x8::splat(0.95));
            let u = gather1(n, |k| v.id(k).value(Dim::Roulette { depth }));
            going &= !u.simd_ge(keep);
            throughput = throughput * (f32x8::ONE / keep);
        }
        going &= throughput.is_finite() & !throughput.is_zero();
        let (sampled, going) = (bits(sampled), bits(going));
        let (dir, start, throughput, pdf) = (dir.lanes(), start.lanes(), throughput.lanes(), pdf.to_array());
        let delta = bits(!diffuse);
        for k in 0..n {
            let i = v.path(k);
            let path = &mut paths[i];
            if elsewhere >> k & 1 != 0 {
                if self.bounce(path, v.vertex(k), v.id(k), ctx, &mut NoRecord) {
                    next.push(i as u32);
                }
                continue;
            }
            if sampled >> k & 1 == 0 {
                continue;
            }
            ctx.stats.reflection_rays += 1;
            path.throughput = throughput[k];
            path.last_pdf = (delta >> k & 1 == 0).then_some(pdf[k]);
            path.depth = depth;
            if going >> k & 1 != 0 {
                path.ray = Ray::with_time(start[k], dir[k], path.ray.time);
                next.push(i as u32);
            }
        }
    }
}

/// `bsdf::cosine_hemisphere` of each lane's numbers (the sine and cosine lane by
/// lane, by the same library calls).
#[inline(always)]
fn cosine_hemisphere8(u: &[(f32, f32); LANES]) -> V3x8 {
    let u1 = f32x8::from(u.map(|u| u.0));
    let u2 = f32x8::from(u.map(|u| u.1));
    let r = u1.sqrt();
    let phi = (f32x8::splat(2.0 * PI) * u2).to_array();
    let (cos, sin) = (f32x8::from(phi.map(f32::cos)), f32x8::from(phi.map(f32::sin)));
    V3x8 {
        x: r * cos,
        y: r * sin,
        z: (f32x8::ONE - u1).fast_max(f32x8::ZERO).sqrt(),
    }
}

/// `path::power_heuristic` lane by lane.
#[inline(always)]
fn power_heuristic8(a: f32x8, b: f32x8) -> f32x8 {
    let (a2, b2) = (a * a, b * b);
    let sum = a2 + b2;
    sum.simd_eq(f32x8::ZERO).bitselect(f32x8::ZERO, a2 / sum)
}
