//! The occlusion of a packet of up to eight shadow rays, answered lane by lane with
//! the single-ray walk: a stand-in with the packet query's signature, so that the
//! renderer can send its shadow rays as packets before the coherent walk exists.

use std::cell::Cell;

use super::occlusion::NO_HINT;
use crate::accel::aggregate::{lane_ray, lanes};
use crate::accel::bvh::Bvh;
use crate::accel::leaf::ray8::{Ray8, RAYS};

impl Bvh {
    /// For each active ray of `rays` (bit `k` of `active` for ray `k`), true when
    /// anything lies on it with `0 < t < t_max[k]`: the bits of the occluded ones,
    /// each [`Bvh::occluded`]'s answer (at time 0: a [`Ray8`] carries no time).
    ///
    /// Lane by lane, each ray testing first what blocked the ray before it (the
    /// shadow cache of [`Bvh::occluded_hinted`], which never changes an answer).
    pub fn occluded8(&self, rays: &Ray8, t_max: &[f32; RAYS], active: u32) -> u32 {
        let hint = Cell::new(NO_HINT);
        lanes(active)
            .filter(|&k| self.occluded_hinted(&lane_ray(rays, k), t_max[k], &hint))
            .fold(0, |blocked, k| blocked | 1 << k)
    }
}
