//! The BVH over a scene's primitives: built ([`Bvh::new`]) from the stages of
//! `accel::build` and `accel::leaf`, queried by `accel::traverse`.

use super::build::collapse;
use super::build::sah::{self, Pack};
use super::build::split::{self, Copies};
use super::leaf::cone4::Cone4;
use super::leaf::pack::{leaf_kinds, pack_leaves, pack_of, Blocks};
use super::leaf::sphere4::Sphere4;
use super::leaf::tri4::Tri4;
use super::simd::SimdLevel;
#[cfg(target_arch = "x86_64")]
use super::traverse::avx::Avx;
use super::traverse::wide::Node8;
use crate::geometry::{Geometry, GeometryData, Primitive};
use crate::pages::huge_vec;
use rayon::prelude::*;

/// A bounding volume hierarchy over the bounded primitives, with the unbounded ones
/// (planes) kept beside it and tested linearly.
#[derive(Clone, Debug)]
pub struct Bvh {
    /// The binary SAH tree collapsed to 8-wide nodes, used by the queries (the binary
    /// tree is dropped once collapsed). A leaf lane made only of triangles refers to
    /// [`Tri4`] blocks (see [`TRI4_LEAF`](super::leaf::pack::TRI4_LEAF)), one made
    /// only of packable spheres to [`Sphere4`] blocks (see
    /// [`SPHERE4_LEAF`](super::leaf::pack::SPHERE4_LEAF)), one made only of packable
    /// cones to [`Cone4`] blocks (see [`CONE4_LEAF`](super::leaf::pack::CONE4_LEAF)).
    pub(super) wide: Vec<Node8>,
    /// The triangles of all-triangle leaves, four to a block, in leaf order.
    pub(super) tri4: Vec<Tri4>,
    /// The spheres of all-sphere leaves, four to a block, in leaf order.
    pub(super) sphere4: Vec<Sphere4>,
    /// The cones of all-cone leaves, four to a block, in leaf order.
    pub(super) cone4: Vec<Cone4>,
    /// Bounded primitives in leaf order, then the unbounded ones.
    pub(super) primitives: Vec<Primitive>,
    /// Each primitive's rank, by its index in [`Bvh::primitives`]: its source line in
    /// the high 32 bits, its index in the `Geometry` built from in the low ones (a
    /// split cone's copies share theirs). Ties in distance go to the lowest rank
    /// (`traverse::nearest`): the primitive first in the scene file, whatever order
    /// the builder puts the leaves in.
    pub(super) ranks: Vec<u64>,
    pub(super) bounded: usize,
    /// With split cones (`accel::build::split`), which leaf-order entries are copies of one
    /// primitive; `None` when every primitive is in the tree once.
    pub(super) copies: Option<Copies>,
    pub(super) data: GeometryData,
    /// The wide tree's depth (root = 1).
    pub(super) depth: u32,
    /// The kinds of leaf the queries look for (see [`leaf_kinds`]): each set they
    /// dispatch on has a copy of them compiled without the other kinds' tests.
    pub(super) kinds: u32,
    /// 0, or the [`Rootstock`](super::graft::Rootstock) this tree was grafted onto:
    /// its first entries are the stock's, which a later graft may keep.
    pub(super) stock: u64,
    /// 0 for a scene's tree, 1 for a prototype's ([`Bvh::prototype`]): which of a
    /// thread's traversal stacks its queries use, so that a prototype's runs inside
    /// the scene's query that met its instance.
    pub(super) level: u8,
    /// The AVX kernels, when the CPU has them (detected once, at build time).
    #[cfg(target_arch = "x86_64")]
    pub(super) avx: Option<Avx>,
}

impl Bvh {
    /// Builds the hierarchy over `geometry`, reordering its bounded primitives into
    /// leaf order.
    pub fn new(geometry: Geometry) -> Bvh {
        let Geometry {
            primitives: mut bounded,
            data,
        } = geometry;
        // Each primitive's rank (`Bvh::ranks`), taken before anything moves.
        let mut ranks: Vec<u64> = bounded
            .par_iter()
            .enumerate()
            .map(|(i, p)| u64::from(p.line) << 32 | i as u64)
            .collect();
        // Unbounded primitives (planes) set aside in place, with their ranks: with none,
        // as in most scenes, nothing moves. The big arrays below are filled in parallel
        // (their first-touch page faults were a third of building 600 000 spheres).
        let is_unbounded = |p: &Primitive| p.bounds(&data).is_none();
        let mut unbounded = Vec::new();
        let mut unbounded_ranks = Vec::new();
        if bounded.par_iter().any(is_unbounded) {
            for (p, &rank) in bounded.iter().zip(&ranks).filter(|(p, _)| is_unbounded(p)) {
                unbounded.push(*p);
                unbounded_ranks.push(rank);
            }
            let mut kept = bounded.iter().map(|p| !is_unbounded(p));
            ranks.retain(|_| kept.next() == Some(true));
            bounded.retain(|p| !is_unbounded(p));
        }
        let bounds = |i: usize| bounded[i].bounds(&data).expect("unbounded primitives set aside");
        // Triangles and spheres are intersected several at a time (in blocks), which
        // the SAH knows.
        let packs: Vec<Pack> = bounded.par_iter().map(pack_of).collect();
        // Long oblique cones enter the tree as several pieces (`accel::build::split`).
        let refs = split::split_long_cones(&bounded, bounds, &packs);
        let built = match &refs {
            Some(r) => sah::build(|i| r.bounds[i], &r.packs),
            None => sah::build(bounds, &packs),
        };
        let copies = refs.as_ref().map(|r| Copies::new(r, &built.order, bounded.len()));
        let order: Vec<u32> = match &refs {
            Some(r) => built.order.iter().map(|&i| r.primitive[i as usize]).collect(),
            None => built.order,
        };
        drop(refs);
        let mut ranks: Vec<u64> = order.par_iter().map(|&i| ranks[i as usize]).collect();
        ranks.extend(unbounded_ranks);
        // The primitives in leaf order, then the unbounded ones.
        let mut ordered: Vec<Primitive> = huge_vec(order.len() + unbounded.len());
        order
            .par_iter()
            .map(|&i| bounded[i as usize])
            .collect_into_vec(&mut ordered);
        drop(bounded);
        let leaf_packs: Vec<Pack> = order.par_iter().map(|&i| packs[i as usize]).collect();
        let n_bounded = ordered.len();
        ordered.extend(unbounded);
        let (mut wide, depth) = if n_bounded > 0 {
            collapse::collapse(&built.nodes, &leaf_packs)
        } else {
            (Vec::new(), 0)
        };
        debug_assert!(
            depth <= built.depth,
            "the wide tree is no deeper than the binary one"
        );
        drop(built.nodes);
        let canonical = copies.as_ref().map(|c| c.canonical.as_slice());
        let Blocks { tri4, sphere4, cone4 } = pack_leaves(&mut wide, &ordered, &leaf_packs, canonical);
        let kinds = leaf_kinds::copy_for(&wide);
        Bvh {
            wide,
            tri4,
            sphere4,
            cone4,
            primitives: ordered,
            ranks,
            bounded: n_bounded,
            copies,
            data,
            depth,
            kinds,
            stock: 0,
            level: 0,
            #[cfg(target_arch = "x86_64")]
            avx: Avx::detect(),
        }
    }

    /// Builds the hierarchy over a prototype's primitives, which instances place
    /// ([`crate::geometry::Prototype`]): queried from inside a scene's queries.
    pub fn prototype(geometry: Geometry) -> Bvh {
        Bvh {
            level: 1,
            ..Bvh::new(geometry)
        }
    }

    /// The index the queries report for leaf-order entry `index`: the first copy's
    /// when the entry is a copy of a split cone (`accel::build::split`).
    #[inline(always)]
    pub(super) fn canonical(&self, index: usize) -> u32 {
        match &self.copies {
            Some(c) => c.canonical[index],
            None => index as u32,
        }
    }

    /// Primitive `index` as returned by the queries.
    #[inline]
    pub fn primitive(&self, index: u32) -> &Primitive {
        &self.primitives[index as usize]
    }

    /// The number of distinct primitives (a split cone counts once, though
    /// [`Bvh::primitives`] holds it once per piece).
    pub fn primitive_count(&self) -> usize {
        let copies = self.copies.as_ref().map_or(0, |c| self.bounded - c.distinct);
        self.primitives.len() - copies
    }

    /// All primitives: bounded ones in leaf order (a split cone once per piece, see
    /// `accel::build::split`), then unbounded ones.
    pub fn primitives(&self) -> &[Primitive] {
        &self.primitives
    }

    /// The shared geometry arrays.
    pub fn data(&self) -> &GeometryData {
        &self.data
    }

    /// The traversal kernels the queries run (`accel::simd`).
    pub fn kernels(&self) -> SimdLevel {
        #[cfg(target_arch = "x86_64")]
        if self.avx.is_some() {
            return SimdLevel::Avx2;
        }
        SimdLevel::Portable
    }
}
