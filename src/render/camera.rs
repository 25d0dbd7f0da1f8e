//! The NFF pinhole camera.

use crate::math::{Ray, Vec3};
use crate::scene::View;

/// A pinhole camera that maps raster positions to world-space eye rays.
///
/// NFF defines `angle` between the centres of the outer pixel rows (the top and the
/// bottom row); pixels are square, so the pixel pitch on the image plane at distance 1
/// is `2 tan(angle/2) / (height - 1)`. Raster `(0, 0)` is the top-left corner of the
/// image, pixel `(i, j)` has its centre at `(i + 0.5, j + 0.5)`, x grows to the right
/// and y downwards. The frame is right-handed: `right = forward x up`.
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    origin: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    pitch: f32,
    half_width: f32,
    half_height: f32,
}

impl Camera {
    /// Builds the camera for an image of `width` x `height` pixels.
    pub fn new(view: &View, width: u32, height: u32) -> Camera {
        let forward = (view.at - view.from).normalize();
        let right = forward.cross(view.up).normalize();
        let up = right.cross(forward);
        let half_angle = (view.angle as f64).to_radians() * 0.5;
        let pitch = (2.0 * half_angle.tan() / (height.max(2) - 1) as f64) as f32;
        Camera {
            origin: view.from,
            forward,
            right,
            up,
            pitch,
            half_width: width as f32 * 0.5,
            half_height: height as f32 * 0.5,
        }
    }

    /// The unit-direction eye ray through raster position `(x, y)`.
    #[inline]
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        let sx = (x - self.half_width) * self.pitch;
        let sy = (self.half_height - y) * self.pitch;
        let dir = (self.forward + self.right * sx + self.up * sy).normalize();
        Ray::new(self.origin, dir)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn view() -> View {
        View {
            from: Vec3::new(0.0, 0.0, 0.0),
            at: Vec3::new(0.0, 1.0, 0.0),
            up: Vec3::new(0.0, 0.0, 1.0),
            angle: 90.0,
            hither: 1.0,
            width: 3,
            height: 3,
        }
    }

    #[test]
    fn centre_pixel_looks_at_the_target() {
        let c = Camera::new(&view(), 3, 3);
        let r = c.ray(1.5, 1.5);
        assert!((r.dir - Vec3::new(0.0, 1.0, 0.0)).length() < 1e-6);
    }

    #[test]
    fn angle_spans_the_centres_of_the_outer_rows() {
        // 90 degrees between the centres of the top and bottom rows: the top-centre
        // pixel looks 45 degrees up, the right-centre pixel 45 degrees right.
        let c = Camera::new(&view(), 3, 3);
        let top = c.ray(1.5, 0.5).dir;
        assert!((top - Vec3::new(0.0, 1.0, 1.0).normalize()).length() < 1e-6);
        let right = c.ray(2.5, 1.5).dir;
        // Looking along +y with z up, +x is on the right (right-handed, not mirrored).
        assert!((right - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-6);
    }
}
