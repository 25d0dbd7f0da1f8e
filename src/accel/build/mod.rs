//! The builder: primitives' boxes to a binary SAH tree (`sah`, working on the
//! records of `binning`), long thin cones entered as several pieces (`split`), and
//! the binary tree (`node`) collapsed into the 8-wide nodes the queries walk
//! (`collapse`; the BVH keeps only those). The biggest nodes' passes over their
//! items run on several threads (`parallel`), and so do the collapse's big subtrees
//! (its table filled and its wide nodes emitted by `rayon::join`).

pub(super) mod binning;
pub(super) mod collapse;
pub(super) mod node;
pub(super) mod parallel;
pub(super) mod sah;
pub(super) mod split;
