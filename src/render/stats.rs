//! Ray counters, kept per row and summed at the end so the hot path never shares them.

use std::ops::AddAssign;

/// Exact ray counts of a render (the quantities of the SPD's published tables).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct Stats {
    /// Eye (primary) rays traced.
    pub eye_rays: u64,
    /// Eye rays that hit an object.
    pub eye_hits: u64,
    /// Reflection rays spawned.
    pub reflection_rays: u64,
    /// Refraction rays spawned.
    pub refraction_rays: u64,
    /// Secondary (reflection + refraction) rays that hit an object.
    pub secondary_hits: u64,
    /// Shadow rays cast.
    pub shadow_rays: u64,
    /// Shadow rays that hit an object before the light.
    pub shadow_blocked: u64,
}

impl Stats {
    /// All rays traced: eye, reflection, refraction and shadow.
    pub fn total_rays(&self) -> u64 {
        self.eye_rays + self.reflection_rays + self.refraction_rays + self.shadow_rays
    }
}

impl AddAssign for Stats {
    fn add_assign(&mut self, o: Stats) {
        self.eye_rays += o.eye_rays;
        self.eye_hits += o.eye_hits;
        self.reflection_rays += o.reflection_rays;
        self.refraction_rays += o.refraction_rays;
        self.secondary_hits += o.secondary_hits;
        self.shadow_rays += o.shadow_rays;
        self.shadow_blocked += o.shadow_blocked;
    }
}
