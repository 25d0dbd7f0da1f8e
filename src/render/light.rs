//! Lights as the tracer sees them: resolved intensities, and the points of the light
//! that a hit samples.
//!
//! A point light is one point, sampled once, with the SPD's rules (a shadow ray unless
//! the light is behind the surface; hard shadows). An area light is a parallelogram,
//! shaded as points sampled over its surface — hard shadows per point, soft shadows in
//! the sum — each point carrying `1/M` of the light's intensity for `M` points per hit:
//!
//! - with one eye sample per pixel, the light's own `n x n` regular grid, the centres
//!   of its cells (`n` from the file; `light quad`'s last number, 4 for `al`);
//! - with more, one point per eye sample, a jittered point of stratum `π(s)` of the
//!   light for eye sample `s`, the strata of each light used once per pixel
//!   ([`SampleId::point`]): 16 samples per pixel take a 4 x 4 grid of jittered points;
//! - `--light-samples N` (any sampling): an `N x N` grid per hit, jittered per cell
//!   with more than one eye sample per pixel, cell centres otherwise;
//! - soft shadows off (the viewer's toggle): the light's centre alone.

use crate::math::Vec3;
use crate::prepare::LightSource;

use super::sampling::{Dim, SampleId};

/// How area lights are sampled in a render (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LightSampling {
    /// `--light-samples N`: points per side of the grid at every hit.
    pub grid_override: Option<u32>,
    /// False: every area light is its centre alone.
    pub soft_shadows: bool,
}

impl LightSource {
    /// How many points of this light a hit samples (each carries that fraction of the
    /// intensity); [`LightSource::sample_points`] visits them.
    #[inline]
    pub fn point_count(&self, plan: &LightSampling, id: &SampleId) -> u32 {
        match (self.area, plan.grid_override) {
            (None, _) => 1,
            _ if !plan.soft_shadows => 1,
            (Some(_), Some(n)) => n.max(1) * n.max(1),
            (Some(_), None) if id.count() > 1 => 1,
            (Some(area), None) => area.grid.max(1) * area.grid.max(1),
        }
    }

    /// Calls `visit(point)` for each point of this light (light `index` in file order)
    /// that a hit of ray-tree depth `depth` on the ray tree of eye sample `id`
    /// samples, and returns how many there were (each carries that fraction of the
    /// intensity). A point light is visited once at its position.
    #[inline]
    pub fn sample_points(
        &self,
        plan: &LightSampling,
        id: &SampleId,
        index: usize,
        depth: u32,
        mut visit: impl FnMut(Vec3),
    ) -> u32 {
        let Some(area) = self.area else {
            visit(self.position);
            return 1;
        };
        let at = |(u, v): (f32, f32)| self.position + area.edge1 * u + area.edge2 * v;
        if !plan.soft_shadows {
            visit(at((0.5, 0.5)));
            return 1;
        }
        let dim = Dim::Light {
            light: index as u32,
            depth,
        };
        let jittered = id.count() > 1;
        let n = match plan.grid_override {
            Some(n) => n.max(1),
            None if jittered => {
                visit(at(id.point(dim)));
                return 1;
            }
            None => area.grid.max(1),
        };
        for j in 0..n {
            for i in 0..n {
                let (du, dv) = if jittered {
                    let cell = id.index().wrapping_mul(n * n).wrapping_add(j * n + i);
                    id.numbers(cell, dim)
                } else {
                    (0.5, 0.5)
                };
                visit(at(((i as f32 + du) / n as f32, (j as f32 + dv) / n as f32)));
            }
        }
        n * n
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prepare::LightQuad;

    fn quad(grid: u32) -> LightSource {
        LightSource {
            position: Vec3::new(-1.0, -1.0, 5.0),
            intensity: Vec3::ONE,
            area: Some(LightQuad {
                edge1: Vec3::new(2.0, 0.0, 0.0),
                edge2: Vec3::new(0.0, 2.0, 0.0),
                grid,
            }),
        }
    }

    const PLAN: LightSampling = LightSampling {
        grid_override: None,
        soft_shadows: true,
    };

    fn points(l: &LightSource, plan: &LightSampling, id: &SampleId) -> Vec<Vec3> {
        let mut out = Vec::new();
        let n = l.sample_points(plan, id, 0, 1, |p| out.push(p));
        assert_eq!(n as usize, out.len());
        assert_eq!(l.point_count(plan, id), n);
        out
    }

    #[test]
    fn one_sample_per_pixel_takes_the_regular_grid_of_cell_centres() {
        let p = points(&quad(2), &PLAN, &SampleId::single(3, 4));
        let want = [(-0.5, -0.5), (0.5, -0.5), (-0.5, 0.5), (0.5, 0.5)];
        assert_eq!(p, want.map(|(x, y)| Vec3::new(x, y, 5.0)).to_vec());
    }

    #[test]
    fn more_samples_take_one_point_each_covering_every_stratum() {
        // 16 eye samples: one point each, one in each cell of the 4 x 4 grid.
        let mut cells = [0; 16];
        for index in 0..16 {
            let id = SampleId::new(9, 2, index, 16, true);
            let p = points(&quad(2), &PLAN, &id);
            assert_eq!(p.len(), 1);
            let (cx, cy) = (((p[0].x + 1.0) * 2.0) as usize, ((p[0].y + 1.0) * 2.0) as usize);
            cells[cy * 4 + cx] += 1;
        }
        assert_eq!(cells, [1; 16]);
    }

    #[test]
    fn overrides_and_hard_shadows() {
        let id = SampleId::single(0, 0);
        let three = LightSampling {
            grid_override: Some(3),
            ..PLAN
        };
        assert_eq!(points(&quad(2), &three, &id).len(), 9);
        let hard = LightSampling {
            soft_shadows: false,
            ..PLAN
        };
        assert_eq!(points(&quad(8), &hard, &id), vec![Vec3::new(0.0, 0.0, 5.0)]);
        let point = LightSource {
            area: None,
            ..quad(2)
        };
        assert_eq!(points(&point, &PLAN, &id), vec![Vec3::new(-1.0, -1.0, 5.0)]);
    }
}
