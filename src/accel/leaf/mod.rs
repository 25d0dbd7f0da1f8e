//! The leaves: primitives packed four to a block in structure-of-arrays form
//! (`tri4`, `sphere4`, `cone4`) and tested a block at a time, two triangle blocks
//! against a ray or one triangle against eight rays in one eight-lane test (`ray8`),
//! and the packing of a tree's leaves into blocks, marked in the wide nodes (`pack`).

pub(super) mod cone4;
pub(super) mod pack;
pub(super) mod ray8;
pub(super) mod sphere4;
pub(super) mod tri4;
