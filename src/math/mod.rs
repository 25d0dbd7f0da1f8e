//! Small linear-algebra kit: [`Vec3`], [`Ray`] and [`Aabb`], all `f32` and `Copy`.

mod aabb;
mod ray;
mod vec3;

pub use aabb::Aabb;
pub use ray::Ray;
pub use vec3::Vec3;

/// The floating-point type used crate-wide for geometry.
pub type Float = f32;
