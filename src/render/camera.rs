//! The camera: a pinhole, or a thin lens with depth of field.
//!
//! [`Camera::new`] is the one place a camera is made, from the scene's view and the
//! render options (which may override the lens). [`Camera::ray`] maps a
//! [`CameraSample`] — a raster position and a lens position — to a world-space ray.
//!
//! Raster `(0, 0)` is the top-left corner of the image, pixel `(i, j)` has its centre
//! at `(i + 0.5, j + 0.5)`, x grows to the right and y downwards. The frame is
//! right-handed: `right = forward x up`. Pixels are square; their pitch on the image
//! plane at distance 1 depends on what the view's `angle` spans ([`AngleSpan`]):
//! NFF's angle runs between the centres of the outer pixel rows, so the pitch is
//! `2 tan(angle/2) / (height - 1)`; P3F's runs between the image's edges,
//! `2 tan(angle/2) / height`.
//!
//! The thin lens (P3F-SPEC): the view plane lies at `d = |from - at|`; the lens is a
//! disc of diameter `aperture` pixels of that plane (`aperture * d * pitch` in world
//! units) around `from`, perpendicular to the view direction, and the plane of sharp
//! focus lies at `focal * d` along the view direction. A lens ray starts at its lens
//! point and passes through the point of the focal plane that the pinhole ray of the
//! same raster position meets, so every lens ray of one raster position meets there.

use crate::math::{Ray, Vec3};
use crate::scene::{AngleSpan, View};

use super::RenderOptions;

/// Where an eye ray goes: a raster position and a position on the lens.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct CameraSample {
    /// Raster position (pixel units, from the top-left corner).
    pub raster: (f32, f32),
    /// Lens position in `[0, 1)^2`, mapped to the lens disc (`(0.5, 0.5)` is its centre).
    pub lens: (f32, f32),
}

impl CameraSample {
    /// The sample at raster position `(x, y)` through the centre of the lens.
    pub fn at(x: f32, y: f32) -> CameraSample {
        CameraSample {
            raster: (x, y),
            lens: (0.5, 0.5),
        }
    }
}

/// A thin lens: its radius and the distance of the plane of sharp focus.
#[derive(Clone, Copy, Debug, PartialEq)]
struct ThinLens {
    /// Lens radius in world units.
    radius: f32,
    /// Distance of the focal plane along the view direction.
    focal_distance: f32,
}

/// Maps camera samples to eye rays (see the module docs).
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    origin: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    pitch: f32,
    half_width: f32,
    half_height: f32,
    lens: Option<ThinLens>,
}

impl Camera {
    /// The camera of `view` for the image size and lens of `opts` (`opts.aperture` and
    /// `opts.focal`, when set, replace the view's).
    pub fn new(view: &View, opts: &RenderOptions) -> Camera {
        let (width, height) = (opts.width, opts.height);
        let forward = (view.at - view.from).normalize();
        let right = forward.cross(view.up).normalize();
        let up = right.cross(forward);
        let half_angle = (view.angle as f64).to_radians() * 0.5;
        let spans = match view.angle_span {
            AngleSpan::PixelCentres => height.max(2) - 1,
            AngleSpan::ImageEdges => height,
        };
        let pitch = (2.0 * half_angle.tan() / spans as f64) as f32;
        let aperture = opts.aperture.unwrap_or(view.aperture);
        let focal = opts.focal.unwrap_or(view.focal);
        let d = (view.at - view.from).length();
        let lens = (aperture > 0.0).then_some(ThinLens {
            radius: 0.5 * aperture * d * pitch,
            focal_distance: focal * d,
        });
        Camera {
            origin: view.from,
            forward,
            right,
            up,
            pitch,
            half_width: width as f32 * 0.5,
            half_height: height as f32 * 0.5,
            lens,
        }
    }

    /// True if the camera has a lens of non-zero size (its rays depend on the lens
    /// position).
    pub fn has_lens(&self) -> bool {
        self.lens.is_some()
    }

    /// The eye ray of sample `s` (unit direction). Through the centre of the lens it
    /// is the pinhole ray ([`Camera::ray_at`]).
    #[inline(always)]
    pub fn ray(&self, s: &CameraSample) -> Ray {
        match &self.lens {
            Some(lens) if s.lens != (0.5, 0.5) => self.lens_ray(lens, s),
            _ => self.ray_at(s.raster.0, s.raster.1),
        }
    }

    /// The pinhole ray through raster position `(x, y)`, which is also the ray through
    /// the centre of the lens.
    #[inline(always)]
    pub fn ray_at(&self, x: f32, y: f32) -> Ray {
        Ray::new(self.origin, self.through(x, y).normalize())
    }

    /// The direction of the pinhole ray through raster `(x, y)`, scaled so its forward
    /// component is 1.
    #[inline(always)]
    fn through(&self, x: f32, y: f32) -> Vec3 {
        let sx = (x - self.half_width) * self.pitch;
        let sy = (self.half_height - y) * self.pitch;
        self.forward + self.right * sx + self.up * sy
    }

    /// The ray of sample `s` from its point on the lens through the focal-plane point
    /// of its pinhole ray.
    #[inline(never)]
    fn lens_ray(&self, lens: &ThinLens, s: &CameraSample) -> Ray {
        let (lx, ly) = concentric_disc(s.lens);
        let start = self.origin + (self.right * lx + self.up * ly) * lens.radius;
        let focus = self.origin + self.through(s.raster.0, s.raster.1) * lens.focal_distance;
        Ray::new(start, (focus - start).normalize())
    }
}

/// Shirley and Chiu's concentric map of the unit square onto the unit disc: strata
/// of the square stay compact on the disc, so stratified lens samples stay stratified.
#[inline]
pub fn concentric_disc((u, v): (f32, f32)) -> (f32, f32) {
    let (a, b) = (2.0 * u - 1.0, 2.0 * v - 1.0);
    if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    }
    let quarter = std::f32::consts::FRAC_PI_4;
    let (r, phi) = if a.abs() > b.abs() {
        (a, quarter * (b / a))
    } else {
        (b, 2.0 * quarter - quarter * (a / b))
    };
    (r * phi.cos(), r * phi.sin())
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
            ..View::default()
        }
    }

    fn camera(view: &View, w: u32, h: u32) -> Camera {
        let opts = RenderOptions {
            width: w,
            height: h,
            ..RenderOptions::default()
        };
        Camera::new(view, &opts)
    }

    #[test]
    fn centre_pixel_looks_at_the_target() {
        let c = camera(&view(), 3, 3);
        let r = c.ray_at(1.5, 1.5);
        assert!((r.dir - Vec3::new(0.0, 1.0, 0.0)).length() < 1e-6);
    }

    #[test]
    fn angle_spans_the_centres_of_the_outer_rows() {
        // 90 degrees between the centres of the top and bottom rows: the top-centre
        // pixel looks 45 degrees up, the right-centre pixel 45 degrees right.
        let c = camera(&view(), 3, 3);
        let top = c.ray_at(1.5, 0.5).dir;
        assert!((top - Vec3::new(0.0, 1.0, 1.0).normalize()).length() < 1e-6);
        let right = c.ray_at(2.5, 1.5).dir;
        // Looking along +y with z up, +x is on the right (right-handed, not mirrored).
        assert!((right - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-6);
    }

    #[test]
    fn p3f_angle_spans_the_image_edges() {
        let v = View {
            angle_span: AngleSpan::ImageEdges,
            ..view()
        };
        let c = camera(&v, 4, 4);
        // The top edge (raster y = 0) is 45 degrees up, the left edge 45 degrees left.
        let top = c.ray_at(2.0, 0.0).dir;
        assert!((top - Vec3::new(0.0, 1.0, 1.0).normalize()).length() < 1e-6);
        let left = c.ray_at(0.0, 2.0).dir;
        assert!((left - Vec3::new(-1.0, 1.0, 0.0).normalize()).length() < 1e-6);
    }

    #[test]
    fn concentric_map_stays_in_the_disc_and_keeps_the_centre() {
        assert_eq!(concentric_disc((0.5, 0.5)), (0.0, 0.0));
        for i in 0..=20 {
            for j in 0..=20 {
                let (x, y) = concentric_disc((i as f32 / 20.0, j as f32 / 20.0));
                assert!(x * x + y * y <= 1.0 + 1e-6);
            }
        }
        // The square's corners land on the circle, on the diagonals.
        let (x, y) = concentric_disc((1.0, 1.0));
        assert!((x - 0.5f32.sqrt()).abs() < 1e-6 && (y - 0.5f32.sqrt()).abs() < 1e-6);
    }
}
