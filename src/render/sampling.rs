//! Where eye rays go through each pixel: the sampling patterns and their seeds.
//!
//! Stratified jittered supersampling with `spp = N` samples per pixel divides the
//! pixel into `cols x rows` equal strata, `cols * rows = N`, with `cols >= rows` the
//! factor pair closest to square (4 -> 2x2, 9 -> 3x3, 8 -> 4x2, 2 -> 2x1, a prime
//! N -> Nx1), and places one sample uniformly at random in each stratum. The pixel
//! value is the plain mean of its samples (a box filter over the pixel).
//!
//! Every random number comes from a hash of the absolute pixel coordinates, the
//! sample index and a *dimension* ([`Dim`]: the pixel position, the lens, each light
//! at each depth), SplitMix64's finalizer, not from a per-thread generator: every
//! run, every thread count and every tile of a split render sees the same samples,
//! so images are identical and tiles merge byte for byte. `spp = 1` is one sample at
//! the pixel centre (and the lens centre), with no jitter.
//!
//! The other dimensions are stratified together with the pixel position: sample `s`
//! of a pixel takes stratum `s` of the pixel, stratum `π(s)` of the lens and stratum
//! `π'(s)` of each light, with `π`, `π'` random permutations of the `spp` strata
//! hashed per pixel and dimension ([`permute`], Kensler's cycle-walking
//! permutation). Each dimension's strata are thus all used once per pixel, in an
//! order unrelated to the others', so 16 samples cover the lens and each area light
//! with a 4x4 grid of jittered points.

use super::camera::CameraSample;
use crate::options::Sampling;

impl Sampling {
    /// The sampler of one pixel's samples in a render (not for
    /// [`Sampling::SpdCorners`], whose rays go through pixel corners); `lens` and
    /// `motion` say whether the lens position and the time must be sampled, `seed`
    /// chooses the pattern (0: the pattern of nffrt's first pictures).
    pub fn pixel_sampler(&self, lens: bool, motion: bool, seed: u32) -> PixelSampler {
        let count = self.samples_per_pixel();
        PixelSampler {
            strata: Strata::new(count),
            order: Permutation::new(count),
            stratified: !matches!(self, Sampling::Independent { .. }),
            jittered: !matches!(self, Sampling::PixelCenters | Sampling::SpdCorners),
            lens,
            motion,
            seed: seed_offset(seed),
        }
    }
}

/// The strata of one pixel for stratified sampling.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Strata {
    /// Strata across the pixel.
    pub cols: u32,
    /// Strata down the pixel.
    pub rows: u32,
}

impl Strata {
    /// The most nearly square `cols x rows = spp` grid with `cols >= rows`
    /// (`spp` of 0 is taken as 1).
    pub fn new(spp: u32) -> Strata {
        let spp = spp.max(1);
        let mut rows = (spp as f64).sqrt() as u32;
        while rows > 1 && !spp.is_multiple_of(rows) {
            rows -= 1;
        }
        let rows = rows.max(1);
        Strata {
            cols: spp / rows,
            rows,
        }
    }

    /// Samples per pixel.
    pub fn samples(&self) -> u32 {
        self.cols * self.rows
    }

    /// Raster position of sample `s` (`0..samples()`) of pixel `(x, y)`: the pixel
    /// centre for a single sample, otherwise a hashed point in stratum `s` (row-major).
    #[inline]
    pub fn position(&self, x: u32, y: u32, s: u32) -> (f32, f32) {
        self.position_hashed(x, y, pixel_hash(pixel_key(x, y)), s)
    }

    /// [`Strata::position`] with the pixel's [`pixel_hash`] worked out already.
    #[inline(always)]
    fn position_hashed(&self, x: u32, y: u32, hash: u64, s: u32) -> (f32, f32) {
        if self.samples() == 1 {
            return (x as f32 + 0.5, y as f32 + 0.5);
        }
        let (u, v) = self.point(s, hashed_2d(hash, s, Dim::Pixel));
        (x as f32 + u, y as f32 + v)
    }

    /// The point `(u, v)` of the unit square's stratum `stratum` (row-major), at
    /// `offset` (in `[0, 1)^2`) within it.
    #[inline]
    pub fn point(&self, stratum: u32, offset: (f32, f32)) -> (f32, f32) {
        let (cx, cy) = (stratum % self.cols, stratum / self.cols);
        (
            (cx as f32 + offset.0) / self.cols as f32,
            (cy as f32 + offset.1) / self.rows as f32,
        )
    }
}

/// The samples of a pixel under one sampling pattern, set up once per render.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PixelSampler {
    strata: Strata,
    /// The strata's random orders (one per pixel and dimension, by its seed); its
    /// [`Permutation::count`] is the number of samples per pixel.
    order: Permutation,
    stratified: bool,
    /// False for one fixed sample per pixel: every dimension at its centre.
    jittered: bool,
    lens: bool,
    motion: bool,
    /// The pattern's seed as it is mixed into pixel keys ([`seed_offset`]).
    seed: u64,
}

impl PixelSampler {
    /// Samples per pixel.
    pub fn count(&self) -> u32 {
        self.order.count()
    }

    /// Sample `index` of pixel `(x, y)`: where its eye ray goes, and its id.
    #[inline(always)]
    pub fn sample(&self, x: u32, y: u32, index: u32) -> (CameraSample, SampleId) {
        self.sample_of(&self.pixel(x, y), index)
    }

    /// The numbers that all samples of pixel `(x, y)` share, for
    /// [`PixelSampler::sample_of`]: a caller taking several samples of a pixel works
    /// them out once.
    #[inline(always)]
    pub fn pixel(&self, x: u32, y: u32) -> PixelSeeds {
        let key = pixel_key(x, y) ^ self.seed;
        PixelSeeds {
            x,
            y,
            key,
            hash: pixel_hash(key),
            lens_seed: if self.lens {
                permutation_seed(key, Dim::Lens)
            } else {
                0
            },
        }
    }

    /// Sample `index` of `pixel` ([`PixelSampler::pixel`]): the same as
    /// [`PixelSampler::sample`] of its coordinates.
    #[inline(always)]
    pub fn sample_of(&self, pixel: &PixelSeeds, index: u32) -> (CameraSample, SampleId) {
        let &PixelSeeds { x, y, key, hash, .. } = pixel;
        let id = SampleId {
            key,
            index,
            order: self.order,
            stratified: self.stratified,
            jittered: self.jittered,
            strata: self.strata,
            hash,
        };
        let raster = if self.stratified {
            self.strata.position_hashed(x, y, hash, index)
        } else {
            let (u, v) = hashed_2d(hash, index, Dim::Pixel);
            (x as f32 + u, y as f32 + v)
        };
        let lens = if self.lens && self.jittered {
            id.point_seeded(Dim::Lens, pixel.lens_seed)
        } else {
            (0.5, 0.5)
        };
        let time = if self.motion { id.value(Dim::Time) } else { 0.5 };
        (CameraSample { raster, lens, time }, id)
    }
}

/// What the samples of one pixel share ([`PixelSampler::pixel`]).
#[derive(Clone, Copy, Debug)]
pub struct PixelSeeds {
    x: u32,
    y: u32,
    /// The pixel's key, with the pattern's seed ([`pixel_key`]).
    key: u64,
    /// [`pixel_hash`] of `key`.
    hash: u64,
    /// The lens dimension's [`permutation_seed`] (0 without a lens).
    lens_seed: u32,
}

/// A dimension of the sample space: each draws its own numbers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dim {
    /// The raster position within the pixel.
    Pixel,
    /// The position on the lens.
    Lens,
    /// The point of area light `light` sampled at a hit of ray-tree depth `depth`.
    Light {
        /// The light's index in file order.
        light: u32,
        /// The ray-tree depth of the hit (the eye ray's hit is 1).
        depth: u32,
    },
    /// The time within the shutter.
    Time,
    /// The microfacet normal of a rough reflection at a hit of ray-tree depth `depth`.
    Reflection {
        /// The ray-tree depth of the hit.
        depth: u32,
    },
    /// The microfacet normal of a rough refraction at a hit of ray-tree depth `depth`.
    Refraction {
        /// The ray-tree depth of the hit.
        depth: u32,
    },
    /// A path's choice of BSDF lobe at its vertex after `depth` segments.
    Lobe {
        /// Segments before the vertex.
        depth: u32,
    },
    /// A path's BSDF direction at its vertex after `depth` segments.
    Bsdf {
        /// Segments before the vertex.
        depth: u32,
    },
    /// A path's choice of emitter for the light sample at its vertex after `depth`
    /// segments.
    LightChoice {
        /// Segments before the vertex.
        depth: u32,
    },
    /// The point of that emitter.
    LightPoint {
        /// Segments before the vertex.
        depth: u32,
    },
    /// Russian roulette before a path's segment `depth`.
    Roulette {
        /// The segment.
        depth: u32,
    },
}

impl Dim {
    /// A distinct number per dimension (the pixel's is 0, which keeps the pixel
    /// positions of the sampler before dimensions existed; lights' stay below 2^40,
    /// the later dimensions take the top bits).
    #[inline(always)]
    fn key(self) -> u64 {
        match self {
            Dim::Pixel => 0,
            Dim::Lens => 1,
            Dim::Light { light, depth } => 2 + ((light as u64) << 8) + depth.min(255) as u64,
            Dim::Time => 1 << 60,
            Dim::Reflection { depth } => (2 << 60) + depth as u64,
            Dim::Refraction { depth } => (3 << 60) + depth as u64,
            Dim::Lobe { depth } => (4 << 60) + depth as u64,
            Dim::Bsdf { depth } => (5 << 60) + depth as u64,
            Dim::LightChoice { depth } => (6 << 60) + depth as u64,
            Dim::LightPoint { depth } => (7 << 60) + depth as u64,
            Dim::Roulette { depth } => (8 << 60) + depth as u64,
        }
    }
}

/// The eye sample a ray tree belongs to: its pixel and its place among the pixel's
/// samples, from which every later random choice of the tree is hashed.
#[derive(Clone, Copy, Debug)]
pub struct SampleId {
    /// The pixel's key: its absolute coordinates and the pattern's seed
    /// ([`pixel_key`]).
    key: u64,
    /// Index of this sample among the pixel's.
    index: u32,
    /// The random orders of the pixel's strata (one per dimension, by its seed); its
    /// [`Permutation::count`] is the pixel's number of samples.
    order: Permutation,
    /// False for [`Sampling::Independent`]: no strata, every number independent.
    stratified: bool,
    /// False for one fixed sample per pixel: every dimension at its centre.
    jittered: bool,
    /// The strata of `count` samples ([`Strata::new`]`(count)`), worked out once per
    /// render.
    strata: Strata,
    /// [`pixel_hash`] of `(x, y)`, worked out once per pixel; a single sample draws
    /// no numbers, and [`SampleId::single`] leaves it 0 (hence no `PartialEq`).
    hash: u64,
}

impl SampleId {
    /// Sample `index` of the `count` samples of pixel `(x, y)`, stratified or not
    /// (as [`PixelSampler::sample`] makes them).
    pub fn new(x: u32, y: u32, index: u32, count: u32, stratified: bool) -> SampleId {
        if count <= 1 {
            return SampleId::single(x, y);
        }
        let key = pixel_key(x, y);
        SampleId {
            key,
            index,
            order: Permutation::new(count),
            stratified,
            jittered: true,
            strata: Strata::new(count),
            hash: pixel_hash(key),
        }
    }

    /// The single fixed sample of pixel `(x, y)` (centres, SPD corners, `--pixel`
    /// probes): every dimension at its centre.
    #[inline]
    pub fn single(x: u32, y: u32) -> SampleId {
        SampleId {
            key: pixel_key(x, y),
            index: 0,
            order: Permutation::new(1),
            stratified: true,
            jittered: false,
            strata: Strata { cols: 1, rows: 1 },
            hash: 0,
        }
    }

    /// Index of this sample among its pixel's.
    pub fn index(&self) -> u32 {
        self.index
    }

    /// The pixel's number of samples.
    pub fn count(&self) -> u32 {
        self.order.count()
    }

    /// False for one fixed sample per pixel ([`SampleId::single`], pixel centres):
    /// its every dimension is at the centre, so effects that need samples (a rough
    /// direction, say) take their centre too.
    pub fn is_jittered(&self) -> bool {
        self.jittered
    }

    /// A point of the unit square for dimension `dim`: for one fixed sample its
    /// centre; otherwise, stratified, a jittered point of stratum `π(index)` of the
    /// pixel's `count` strata ([`Strata::new`]'s grid), `π` a permutation hashed per
    /// pixel and dimension; independent, a uniform point.
    #[inline(always)]
    pub fn point(&self, dim: Dim) -> (f32, f32) {
        if !self.jittered {
            return (0.5, 0.5);
        }
        self.point_seeded(dim, permutation_seed(self.key, dim))
    }

    /// A number in [0, 1) for the one-dimensional `dim`: for one fixed sample 1/2;
    /// otherwise, stratified, a jittered point of stratum `π(index)` of `count` equal
    /// intervals, `π` a permutation hashed per pixel and dimension; independent, a
    /// uniform number.
    #[inline(always)]
    pub fn value(&self, dim: Dim) -> f32 {
        if !self.jittered {
            return 0.5;
        }
        let (offset, _) = hashed_2d(self.hash, self.index, dim);
        if !self.stratified {
            return offset;
        }
        let stratum = self.order.apply(self.index, permutation_seed(self.key, dim));
        // Below 1 even when the float sum rounds up to the count.
        ((stratum as f32 + offset) / self.order.count() as f32).min(ONE_BELOW)
    }

    /// [`sample_2d`] of this sample's pixel for number `s` (not necessarily the
    /// sample's index) in dimension `dim`.
    #[inline]
    pub fn numbers(&self, s: u32, dim: Dim) -> (f32, f32) {
        hashed_2d(self.hash, s, dim)
    }

    /// [`SampleId::point`] of a jittered sample (`count > 1`) with the permutation
    /// seed of the pixel and `dim` ([`permutation_seed`]) worked out already.
    #[inline(always)]
    fn point_seeded(&self, dim: Dim, seed: u32) -> (f32, f32) {
        let offset = hashed_2d(self.hash, self.index, dim);
        if !self.stratified {
            return offset;
        }
        let stratum = self.order.apply(self.index, seed);
        self.strata.point(stratum, offset)
    }
}

/// The largest `f32` below 1.
const ONE_BELOW: f32 = 1.0 - f32::EPSILON / 2.0;

/// The seed of the permutation of the strata of the pixel of key `key` in
/// dimension `dim`.
#[inline]
fn permutation_seed(key: u64, dim: Dim) -> u32 {
    mix(key ^ dim.key().wrapping_mul(0xA24B_AED4_963E_E407)) as u32
}

/// What a pattern's seed mixes into every pixel key: nothing for seed 0 (the
/// pattern of nffrt's first pictures), a hash of the seed otherwise, so that two
/// seeds give unrelated patterns.
#[inline]
fn seed_offset(seed: u32) -> u64 {
    if seed == 0 {
        0
    } else {
        mix(seed as u64 ^ 0x5EED_0000_0000_0000)
    }
}

/// SplitMix64's output function (Steele, Lea and Flood 2014): a bijective 64-bit mix.
#[inline]
fn mix(z: u64) -> u64 {
    let z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    let z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The pixel's coordinates as one 64-bit key.
#[inline]
fn pixel_key(x: u32, y: u32) -> u64 {
    ((x as u64) << 32) | y as u64
}

/// Two numbers in [0, 1) for sample `s` of pixel `(x, y)` in dimension `dim`, from
/// 24 bits each.
#[inline]
pub fn sample_2d(x: u32, y: u32, s: u32, dim: Dim) -> (f32, f32) {
    hashed_2d(pixel_hash(pixel_key(x, y)), s, dim)
}

/// The hash of the pixel of key `key` that [`sample_2d`] starts from.
#[inline]
fn pixel_hash(key: u64) -> u64 {
    mix(key)
}

/// [`sample_2d`] with the pixel's [`pixel_hash`] worked out already.
#[inline(always)]
fn hashed_2d(pixel_hash: u64, s: u32, dim: Dim) -> (f32, f32) {
    let h = mix(pixel_hash ^ s as u64 ^ (dim.key() << 32));
    let scale = 1.0 / (1u32 << 24) as f32;
    // Through u32, exact for 24 bits: x86-64 has no single u64 -> f32 conversion.
    let (hi, lo) = ((h >> 40) as u32, ((h >> 8) & 0xFF_FFFF) as u32);
    (hi as f32 * scale, lo as f32 * scale)
}

/// Element `i` of a random permutation of `0..n` chosen by `seed` (`i < n`):
/// [`Permutation::apply`] of `Permutation::new(n)`.
#[inline]
pub fn permute(i: u32, n: u32, seed: u32) -> u32 {
    Permutation::new(n).apply(i, seed)
}

/// The random permutations of `0..n`, one per seed (see [`Permutation::apply`]), with
/// what their hash needs of `n` worked out once: a sampler draws every permutation of
/// a render for the same `n`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Permutation {
    n: u32,
    /// All ones below `n`'s next power of two: the bits the hash works on.
    mask: u32,
    /// The hash's right shifts: by half of `mask`'s bits and a third (each at least
    /// one), and by one more than half.
    shifts: [u32; 3],
}

impl Permutation {
    /// The permutations of `0..n` (`n` at most 2^31).
    pub fn new(n: u32) -> Permutation {
        let mask = n.max(1).next_power_of_two() - 1;
        // The bits of `mask` (all ones): by its leading zeros, as baseline x86-64 has
        // no popcount instruction.
        let bits = u32::BITS - mask.leading_zeros();
        Permutation {
            n,
            mask,
            shifts: [(bits / 2).max(1), (bits / 3).max(1), 1 + bits / 2],
        }
    }

    /// How many elements are permuted.
    pub fn count(&self) -> u32 {
        self.n
    }

    /// Element `i` of the permutation chosen by `seed` (`i < n`): a bijective hash of
    /// the bits below `n`'s next power of two, applied again until the value falls
    /// below `n` (cycle walking; Kensler, "Correlated Multi-Jittered Sampling", 2013).
    /// Every step below is invertible on those bits, so the result is a permutation,
    /// and cycle walking stays inside the cycle of `i`.
    #[inline(always)]
    pub fn apply(&self, i: u32, seed: u32) -> u32 {
        let Permutation { n, mask, shifts } = *self;
        debug_assert!(i < n);
        if n <= 1 {
            return 0;
        }
        let mut v = i;
        loop {
            v ^= seed & mask;
            v = v.wrapping_mul(0xE170_893D) & mask;
            v ^= (seed >> 16) & mask;
            v ^= v >> shifts[0];
            v = v.wrapping_add(seed >> 8) & mask;
            v = v.wrapping_mul(0x0929_EB3F) & mask;
            v ^= v >> shifts[1];
            v = v.wrapping_mul(1 | (seed >> 27)) & mask;
            v ^= v >> shifts[2];
            if v < n {
                return v;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strata_are_the_squarest_factor_pair() {
        let shape = |n| {
            let s = Strata::new(n);
            (s.cols, s.rows)
        };
        assert_eq!(shape(1), (1, 1));
        assert_eq!(shape(2), (2, 1));
        assert_eq!(shape(4), (2, 2));
        assert_eq!(shape(7), (7, 1));
        assert_eq!(shape(8), (4, 2));
        assert_eq!(shape(12), (4, 3));
        assert_eq!(shape(16), (4, 4));
        assert_eq!(shape(0), (1, 1));
    }

    #[test]
    fn one_sample_is_the_pixel_centre() {
        assert_eq!(Strata::new(1).position(7, 3, 0), (7.5, 3.5));
    }

    #[test]
    fn every_sample_lies_in_its_own_stratum() {
        for spp in [2, 4, 6, 9, 16] {
            let st = Strata::new(spp);
            for (x, y) in [(0, 0), (5, 9), (511, 0), (1000, 1000)] {
                for s in 0..spp {
                    let (px, py) = st.position(x, y, s);
                    let (cx, cy) = (s % st.cols, s / st.cols);
                    let fx = (px - x as f32) * st.cols as f32 - cx as f32;
                    let fy = (py - y as f32) * st.rows as f32 - cy as f32;
                    assert!((0.0..1.0).contains(&fx) && (0.0..1.0).contains(&fy), "{spp} {s}");
                }
            }
        }
    }

    fn jitter(x: u32, y: u32, s: u32) -> (f32, f32) {
        sample_2d(x, y, s, Dim::Pixel)
    }

    /// `mix` is SplitMix64's output function: the generator seeded with 0 returns
    /// `mix` of its state before each step of the golden gamma, and its published
    /// first outputs (Vigna's splitmix64.c) are these.
    #[test]
    fn mix_gives_splitmix64s_published_outputs() {
        let gamma = 0x9E37_79B9_7F4A_7C15u64;
        let outputs: Vec<u64> = (0..3u64).map(|k| mix(k.wrapping_mul(gamma))).collect();
        assert_eq!(
            outputs,
            [
                0xE220_A839_7B1D_CDAF,
                0x6E78_9E6A_A1B9_65F4,
                0x06C4_5D18_8009_454F
            ]
        );
    }

    #[test]
    fn jitter_depends_on_pixel_and_sample_only() {
        // Swapped coordinates, neighbours, other samples and dimensions get other offsets.
        let lens = sample_2d(3, 4, 2, Dim::Lens);
        let light = sample_2d(3, 4, 2, Dim::Light { light: 0, depth: 1 });
        let all = [
            jitter(3, 4, 2),
            jitter(4, 3, 2),
            jitter(3, 5, 2),
            jitter(3, 4, 3),
            lens,
            light,
        ];
        for i in 0..all.len() {
            for j in i + 1..all.len() {
                assert_ne!(all[i], all[j]);
            }
        }
        // Roughly uniform: the mean of many offsets is near 1/2.
        let n = 10_000;
        let mean: f32 = (0..n).map(|i| jitter(i, 0, 0).0).sum::<f32>() / n as f32;
        assert!((mean - 0.5).abs() < 0.02, "{mean}");
    }

    #[test]
    fn permutations_are_permutations() {
        for n in [1, 2, 3, 4, 5, 9, 16, 17, 100, 1024, 4096] {
            for seed in [0, 1, 0xDEAD_BEEF, u32::MAX] {
                let mut seen = vec![false; n as usize];
                for i in 0..n {
                    let p = permute(i, n, seed);
                    assert!(p < n && !seen[p as usize], "n {n} seed {seed}");
                    seen[p as usize] = true;
                }
            }
        }
        // Different seeds give different orders.
        let order = |seed| (0..16).map(|i| permute(i, 16, seed)).collect::<Vec<_>>();
        assert_ne!(order(1), order(2));
        assert_ne!(order(1), (0..16).collect::<Vec<_>>());
    }

    #[test]
    fn every_dimension_uses_each_stratum_once_per_pixel() {
        for spp in [4, 9, 16, 12] {
            let strata = Strata::new(spp);
            for dim in [Dim::Lens, Dim::Light { light: 3, depth: 2 }] {
                let mut hits = vec![0; spp as usize];
                for index in 0..spp {
                    let id = SampleId::new(17, 5, index, spp, true);
                    let (u, v) = id.point(dim);
                    let cell =
                        (v * strata.rows as f32) as u32 * strata.cols + (u * strata.cols as f32) as u32;
                    hits[cell as usize] += 1;
                }
                assert!(hits.iter().all(|&h| h == 1), "{spp} {dim:?}: {hits:?}");
            }
        }
    }
}
