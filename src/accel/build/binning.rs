//! The builder's working types: 32-byte primitive records, four-lane boxes and the
//! per-axis SAH bins, all in `f32x4` so each update is one `minps`/`maxps` pair.
//!
//! Every min/max here is `fast_min`/`fast_max` (`a < b ? a : b`), exactly the scalar
//! [`Aabb::union`]: lane by lane the results are bit-identical to folding `Aabb`s.
//! Lane 3 is scratch (an item keeps its index there, and its kind of block) and
//! never read as a coordinate.

use wide::{f32x4, i32x4};

use super::sah::{Pack, Packs};
use crate::math::{Aabb, Vec3};

/// Bins per axis for the SAH sweep, at most: a node of at least
/// `(BINS - 4) * ITEMS_PER_BIN` items gets them all.
pub const BINS: usize = 16;
/// Bins per axis for the smallest nodes.
const MIN_BINS: usize = 8;
/// A node gets a bin more per this many items, from 4 (Embree's rule,
/// `min(32, 4 + n / 20)`, held between [`MIN_BINS`] and [`BINS`]).
const ITEMS_PER_BIN: usize = 20;

/// Bins per axis for a node of `n` items: fewer for small nodes, whose few items
/// need few planes, so that their sweeps cost less. Not fewer than [`MIN_BINS`]:
/// Embree's 4 or 5 bins at the top of a small scene (the Cornell box's 36
/// primitives) made its tree 5 % costlier by the SAH.
#[inline]
pub fn bins_for(n: usize) -> usize {
    (4 + n / ITEMS_PER_BIN).clamp(MIN_BINS, BINS)
}

/// Clears lane 3, which holds an item's index bits (a denormal as a float).
const XYZ: f32x4 = f32x4::new([
    f32::from_bits(u32::MAX),
    f32::from_bits(u32::MAX),
    f32::from_bits(u32::MAX),
    0.0,
]);

/// One primitive to place: its box, with its input index in lane 3 of `min` and its
/// kind of block ([`Pack`] as a number) in lane 3 of `max`.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub struct Item {
    min: f32x4,
    max: f32x4,
}

const _: () = assert!(std::mem::size_of::<Item>() == 32);

/// Lanes of a box coordinate made safe for the builder: `-0.0` becomes `+0.0` (so
/// min/max never depend on the order the boxes are met in), and NaN becomes the
/// infinity on its side (a primitive with an undefined bound is kept everywhere).
#[inline]
fn clean(v: Vec3, nan: f32) -> [f32; 3] {
    v.to_array().map(|x| if x.is_nan() { nan } else { x + 0.0 })
}

impl Item {
    /// The record of primitive `index` with box `b`.
    #[inline]
    pub fn new(b: &Aabb, index: u32, pack: Pack) -> Item {
        let [x0, y0, z0] = clean(b.min, f32::NEG_INFINITY);
        let [x1, y1, z1] = clean(b.max, f32::INFINITY);
        Item {
            min: f32x4::new([x0, y0, z0, f32::from_bits(index)]),
            max: f32x4::new([x1, y1, z1, f32::from_bits(pack as u32)]),
        }
    }

    /// The primitive's input index.
    #[inline]
    pub fn index(&self) -> u32 {
        self.min.to_array()[3].to_bits()
    }

    /// The primitive's kind of block, as [`Packs`].
    #[inline(always)]
    pub fn packs(&self) -> Packs {
        Packs::of_bits(self.max.to_array()[3].to_bits())
    }

    /// The box's centre, `(min + max) * 0.5` as [`Aabb::centroid`] computes it.
    #[inline(always)]
    pub fn centroid(&self) -> f32x4 {
        ((self.min & XYZ) + (self.max & XYZ)) * f32x4::splat(0.5)
    }

    /// Centroid coordinate on `axis`.
    #[inline]
    pub fn centroid_on(&self, axis: usize) -> f32 {
        self.centroid().to_array()[axis]
    }
}

/// An axis-aligned box in two `f32x4` (lane 3 unused).
#[derive(Clone, Copy, Debug)]
pub struct Box4 {
    /// Lower corner.
    pub min: f32x4,
    /// Upper corner.
    pub max: f32x4,
}

impl Box4 {
    /// The empty box (`+inf .. -inf`), identity of [`Box4::add`].
    pub const EMPTY: Box4 = Box4 {
        min: f32x4::new([f32::INFINITY; 4]),
        max: f32x4::new([f32::NEG_INFINITY; 4]),
    };

    /// Grows the box over an item's box.
    #[inline(always)]
    pub fn add(&mut self, it: &Item) {
        self.min = self.min.fast_min(it.min);
        self.max = self.max.fast_max(it.max);
    }

    /// Grows the box over a point.
    #[inline(always)]
    pub fn add_point(&mut self, p: f32x4) {
        self.min = self.min.fast_min(p);
        self.max = self.max.fast_max(p);
    }

    /// Grows the box over another box.
    #[inline(always)]
    pub fn add_box(&mut self, b: &Box4) {
        self.min = self.min.fast_min(b.min);
        self.max = self.max.fast_max(b.max);
    }

    /// Surface area of a box that is not empty: bit for bit
    /// [`Aabb::surface_area`] of [`Box4::aabb`], without its test for emptiness.
    /// Lane 3 is cleared first: its bits are denormal floats, which x86's multiplier
    /// takes a slow microcode path for (building 524 288 triangles took 1.6 times as
    /// long while the products ran on all four lanes).
    #[inline(always)]
    pub fn surface_area(&self) -> f32 {
        let [x, y, z, _] = ((self.max & XYZ) - (self.min & XYZ)).to_array();
        2.0 * (x * y + y * z + z * x)
    }

    /// As an [`Aabb`].
    #[inline]
    pub fn aabb(&self) -> Aabb {
        let (a, b) = (self.min.to_array(), self.max.to_array());
        Aabb::new(Vec3::new(a[0], a[1], a[2]), Vec3::new(b[0], b[1], b[2]))
    }

    /// Bounds and centroid bounds of `items`, folded in order.
    pub fn of(items: &[Item]) -> (Box4, Box4) {
        let (mut b, mut c) = (Box4::EMPTY, Box4::EMPTY);
        for it in items {
            b.add(it);
            c.add_point(it.centroid());
        }
        (b, c)
    }
}

/// Maps centroids to bin indices along all three axes at once, with the arithmetic of
/// the scalar `((c - lo) * (count / extent)) as usize`, clamped to the last bin.
#[derive(Clone, Copy)]
pub struct Binner {
    lo: f32x4,
    scale: f32x4,
    last: f32x4,
    /// Bins per axis, at most [`BINS`].
    pub count: usize,
}

impl Binner {
    /// The binning of centroid bounds `cb` into `count` bins per axis.
    pub fn new(cb: &Box4, count: usize) -> Binner {
        debug_assert!((2..=BINS).contains(&count));
        let (lo, hi) = (cb.min.to_array(), cb.max.to_array());
        let scale: [f32; 4] = std::array::from_fn(|a| count as f32 / (hi[a] - lo[a]));
        Binner {
            lo: cb.min,
            scale: f32x4::new(scale),
            last: f32x4::splat((count - 1) as f32),
            count,
        }
    }

    /// Bin indices of centroid `c` on x, y, z (lane 3 meaningless). NaN maps to bin 0
    /// and anything past the last bin to it, as the saturating `as usize` does.
    #[inline(always)]
    pub fn bins(&self, c: f32x4) -> [i32; 4] {
        let f = ((c - self.lo) * self.scale).fast_max(f32x4::ZERO);
        let f = f.fast_min(self.last);
        let i: i32x4 = f.fast_trunc_int();
        i.to_array()
    }
}

/// Per-axis bins, kept empty between uses so a node pays only for the bins it fills.
pub struct Bins {
    /// `bounds[axis][bin]`.
    pub bounds: [[Box4; BINS]; 3],
    /// `count[axis][bin]`.
    pub count: [[u32; BINS]; 3],
    /// `packs[axis][bin]`: the kinds of block among the bin's items, when tracked.
    packs: [[Packs; BINS]; 3],
    /// The one kind of every item of the build, when they are all of one kind (as
    /// in a mesh of triangles): then the bins do not track kinds, which saves an
    /// `or` per axis and item binned.
    uniform: Option<Packs>,
}

impl Bins {
    /// All bins empty, for items all of kind `uniform` if given, else of any kinds.
    pub fn new(uniform: Option<Packs>) -> Box<Bins> {
        Box::new(Bins {
            bounds: [[Box4::EMPTY; BINS]; 3],
            count: [[0; BINS]; 3],
            packs: [[Packs::default(); BINS]; 3],
            uniform,
        })
    }

    /// Empty bins for the same items as these.
    pub fn like(&self) -> Box<Bins> {
        Bins::new(self.uniform)
    }

    /// The kinds of block among the items of bin `bin` of `axis`.
    #[inline(always)]
    pub fn packs(&self, axis: usize, bin: usize) -> Packs {
        self.uniform.unwrap_or(self.packs[axis][bin])
    }

    /// Bins every item on all three axes in one pass.
    #[inline]
    pub fn fill(&mut self, items: &[Item], binner: &Binner) {
        match self.uniform {
            Some(_) => self.fill_tracking::<false>(items, binner),
            None => self.fill_tracking::<true>(items, binner),
        }
    }

    /// [`Bins::fill`], tracking each bin's kinds of block or not.
    #[inline(always)]
    fn fill_tracking<const KINDS: bool>(&mut self, items: &[Item], binner: &Binner) {
        for it in items {
            let b = binner.bins(it.centroid());
            for (axis, &bin) in b[..3].iter().enumerate() {
                let bin = bin as usize & (BINS - 1);
                self.bounds[axis][bin].add(it);
                self.count[axis][bin] += 1;
                if KINDS {
                    self.packs[axis][bin].add(it.packs());
                }
            }
        }
    }

    /// Adds the items binned in `other` (with the same binner): for bins filled
    /// from consecutive runs of items, in the runs' order, the bins of all of them.
    pub fn merge(&mut self, other: &Bins) {
        for axis in 0..3 {
            for bin in 0..BINS {
                if other.count[axis][bin] > 0 {
                    self.bounds[axis][bin].add_box(&other.bounds[axis][bin]);
                    self.count[axis][bin] += other.count[axis][bin];
                    self.packs[axis][bin].add(other.packs[axis][bin]);
                }
            }
        }
    }

    /// Empties bin `bin` of `axis` again.
    #[inline]
    pub fn clear(&mut self, axis: usize, bin: usize) {
        self.bounds[axis][bin] = Box4::EMPTY;
        self.count[axis][bin] = 0;
        self.packs[axis][bin] = Packs::default();
    }
}
