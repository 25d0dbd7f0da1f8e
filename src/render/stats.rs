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

/// The stages of the path tracer's wavefront, in the order a round runs them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Stage {
    /// The eye rays' closest hits, in packets of neighbouring pixels.
    Camera,
    /// Each segment's hit: background, emission, absorption, the vertex.
    Arrive,
    /// The vertices' light samples.
    Light,
    /// The shadow queue's occlusion queries.
    Shadows,
    /// The vertices' BSDF samples and Russian roulette.
    Bounce,
    /// The next segments' closest hits.
    Extend,
}

impl Stage {
    /// Every stage, in order.
    pub const ALL: [Stage; 6] = [
        Stage::Camera,
        Stage::Arrive,
        Stage::Light,
        Stage::Shadows,
        Stage::Bounce,
        Stage::Extend,
    ];

    /// The stage's name, as `--stats` prints it.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Camera => "camera",
            Stage::Arrive => "arrive",
            Stage::Light => "light",
            Stage::Shadows => "shadows",
            Stage::Bounce => "bounce",
            Stage::Extend => "extend",
        }
    }
}

/// What the wavefront's stages did in a render: per stage the items through it
/// (rays for the queries, vertices for shading) and the time it took, and how full
/// the eight-lane shading ran. Timings, unlike [`Stats`], differ from run to run;
/// they are reported, never part of a picture.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StageStats {
    /// Per stage (in [`Stage::ALL`]'s order): items, and nanoseconds.
    pub stages: [(u64, u64); 6],
    /// Rounds of the wavefront (segments of the longest path, block by block).
    pub rounds: u64,
    /// Eight-lane shading calls, and the lanes they filled.
    pub lane_calls: u64,
    /// See [`StageStats::lane_calls`].
    pub lanes_filled: u64,
}

impl StageStats {
    /// Counts `items` and the time since `since` for `stage`; returns now.
    #[inline]
    pub fn add(&mut self, stage: Stage, items: usize, since: std::time::Instant) -> std::time::Instant {
        let now = std::time::Instant::now();
        let entry = &mut self.stages[stage as usize];
        entry.0 += items as u64;
        entry.1 += now.duration_since(since).as_nanos() as u64;
        now
    }

    /// True if no stage ran (a Whitted render, say).
    pub fn is_empty(&self) -> bool {
        self.rounds == 0
    }
}

impl AddAssign for StageStats {
    fn add_assign(&mut self, o: StageStats) {
        for (a, b) in self.stages.iter_mut().zip(o.stages) {
            a.0 += b.0;
            a.1 += b.1;
        }
        self.rounds += o.rounds;
        self.lane_calls += o.lane_calls;
        self.lanes_filled += o.lanes_filled;
    }
}
