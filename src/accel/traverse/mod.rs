//! The walks of the tree: the 8-wide nodes and their slab test (`wide`), the same
//! kernels compiled for AVX2 and picked at run time (`avx`), the single-ray closest
//! hit (`single`) and occlusion (`occlusion`) queries, packets of eight coherent rays
//! (`packet`, split by direction octant in `octant`) and their occlusion
//! (`packet_occlusion`), and the nearest hit with its rule for ties (`nearest`).

#[cfg(target_arch = "x86_64")]
pub(super) mod avx;
pub(super) mod nearest;
pub(super) mod occlusion;
pub(super) mod octant;
pub(super) mod packet;
pub(super) mod packet_occlusion;
pub(super) mod single;
pub(super) mod wide;
