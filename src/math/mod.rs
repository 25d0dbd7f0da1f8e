//! Small linear-algebra kit: [`Vec3`], [`Ray`] and [`Aabb`], all `f32` and `Copy`;
//! and the set bits of a lane mask as lane indices (`lanes`).

mod aabb;
mod lanes;
pub mod mat3;
mod ray;
mod vec3;

pub use aabb::{Aabb, FAR_SCALE};
pub(crate) use lanes::lanes;
pub use ray::{safe_recip, Ray, TINY_DIR};
pub use vec3::Vec3;

/// The floating-point type used crate-wide for geometry.
pub type Float = f32;

/// Minimum by a plain comparison (one instruction; no NaN handling, unlike `f32::min`).
#[inline(always)]
pub fn fast_min(a: f32, b: f32) -> f32 {
    if a < b {
        a
    } else {
        b
    }
}

/// Maximum by a plain comparison (one instruction; no NaN handling, unlike `f32::max`).
#[inline(always)]
pub fn fast_max(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}
