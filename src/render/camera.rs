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

use crate::accel::{Ray8, RayLanes, PACKET};
use crate::limits::DEFAULT_SHUTTER;
use crate::math::{Ray, Vec3};
use crate::options::RenderOptions;
use crate::scene::{AngleSpan, View};

/// Where and when an eye ray goes: a raster position, a position on the lens and a
/// moment of the shutter.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct CameraSample {
    /// Raster position (pixel units, from the top-left corner).
    pub raster: (f32, f32),
    /// Lens position in `[0, 1)^2`, mapped to the lens disc (`(0.5, 0.5)` is its centre).
    pub lens: (f32, f32),
    /// The moment as a fraction of the shutter's opening, in `[0, 1)` (`0.5` is its
    /// middle).
    pub time: f32,
}

impl CameraSample {
    /// The sample at raster position `(x, y)` through the centre of the lens, at the
    /// middle of the shutter's opening.
    pub fn at(x: f32, y: f32) -> CameraSample {
        CameraSample {
            raster: (x, y),
            lens: (0.5, 0.5),
            time: 0.5,
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
    /// When the shutter opens and how long it stays open.
    open: f32,
    exposure: f32,
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
            open: DEFAULT_SHUTTER[0],
            exposure: DEFAULT_SHUTTER[1] - DEFAULT_SHUTTER[0],
        }
    }

    /// The same camera with its shutter open from `shutter[0]` to `shutter[1]`
    /// (scene time; `[0, 1]` by default).
    pub fn with_shutter(self, shutter: [f32; 2]) -> Camera {
        Camera {
            open: shutter[0],
            exposure: shutter[1] - shutter[0],
            ..self
        }
    }

    /// The scene time of the fraction `u` of the shutter's opening.
    #[inline(always)]
    pub fn time(&self, u: f32) -> f32 {
        self.open + u * self.exposure
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
        let mut ray = match &self.lens {
            Some(lens) if s.lens != (0.5, 0.5) => self.lens_ray(lens, s),
            _ => self.ray_at(s.raster.0, s.raster.1),
        };
        ray.time = self.time(s.time);
        ray
    }

    /// The pinhole ray through raster position `(x, y)`, which is also the ray through
    /// the centre of the lens, at the middle of the shutter's opening.
    #[inline(always)]
    pub fn ray_at(&self, x: f32, y: f32) -> Ray {
        Ray::with_time(self.origin, self.through(x, y).normalize(), self.time(0.5))
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
    #[inline]
    fn lens_ray(&self, lens: &ThinLens, s: &CameraSample) -> Ray {
        let (start, towards) = self.lens_start_and_direction(lens, s);
        Ray::new(start, towards.normalize())
    }

    /// Where the lens ray of `s` starts and its direction before normalization.
    #[inline(always)]
    fn lens_start_and_direction(&self, lens: &ThinLens, s: &CameraSample) -> (Vec3, Vec3) {
        let (lx, ly) = concentric_disc(s.lens);
        let start = self.origin + (self.right * lx + self.up * ly) * lens.radius;
        let focus = self.origin + self.through(s.raster.0, s.raster.1) * lens.focal_distance;
        (start, focus - start)
    }

    /// The eye rays of one to eight `samples`, as a packet: bit for bit
    /// [`Camera::ray`] of each, made in lanes (one array per coordinate; a lens ray
    /// chooses its start and direction without a branch), which lets the compiler
    /// use vector instructions for the lens map's and the normalization's divisions
    /// and square roots, most of a lens ray's cost, and hands the packet to the
    /// acceleration structure as it is.
    pub fn rays8(&self, samples: &[CameraSample]) -> Ray8 {
        let n = samples.len();
        assert!((1..=PACKET).contains(&n), "one to {PACKET} samples");
        // Padded, so that the loops run a whole packet every time.
        let mut lanes = [CameraSample::at(0.0, 0.0); PACKET];
        lanes[..n].copy_from_slice(samples);
        let mut rays = RayLanes::default();
        match &self.lens {
            Some(lens) => {
                for (i, s) in lanes.iter().enumerate() {
                    // The lens centre takes the pinhole ray, as `ray` does: both are
                    // worked out and one is chosen, so that no lane branches.
                    let (lens_start, towards) = self.lens_start_and_direction(lens, s);
                    let centre = s.lens == (0.5, 0.5);
                    let start = if centre { self.origin } else { lens_start };
                    let pinhole = self.through(s.raster.0, s.raster.1);
                    let dir = if centre { pinhole } else { towards }.normalize();
                    rays.set(i, start, dir, self.time(s.time));
                }
            }
            None => {
                for (i, s) in lanes.iter().enumerate() {
                    let dir = self.through(s.raster.0, s.raster.1).normalize();
                    rays.set(i, self.origin, dir, self.time(s.time));
                }
            }
        }
        rays.packet(n)
    }
}

/// Shirley and Chiu's concentric map of the unit square onto the unit disc: strata
/// of the square stay compact on the disc, so stratified lens samples stay stratified.
#[inline]
pub fn concentric_disc((u, v): (f32, f32)) -> (f32, f32) {
    let (a, b) = (2.0 * u - 1.0, 2.0 * v - 1.0);
    // The angle is a quarter turn times the ratio of the smaller coordinate to the
    // larger, within [-pi/4, pi/4], measured from the x axis for |a| > |b| and from the
    // y axis otherwise (there cos and sin trade places). Written as selections rather
    // than branches (the axis is a coin toss per sample, and `Camera::rays` maps
    // several samples at once); the centre's 0 / 0 is computed and not chosen.
    let x_axis = a.abs() > b.abs();
    let (major, minor) = if x_axis { (a, b) } else { (b, a) };
    let (s, c) = sin_cos_quarter(std::f32::consts::FRAC_PI_4 * (minor / major));
    let (along, across) = (major * c, major * s);
    if a == 0.0 && b == 0.0 {
        (0.0, 0.0)
    } else if x_axis {
        (along, across)
    } else {
        (across, along)
    }
}

/// `(sin x, cos x)` for `|x| <= pi/4` by their Taylor polynomials, to degree 7 and 8:
/// the first term left out is below 3.2e-7 and 2.5e-8 there, within the rounding of
/// `f32` (and several times faster than libm's `sincosf`, a third of a lens ray's cost).
#[inline]
fn sin_cos_quarter(x: f32) -> (f32, f32) {
    let x2 = x * x;
    let sin = x * (1.0 + x2 * (-1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0))));
    let cos = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40320.0))));
    (sin, cos)
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
    fn rays_in_packets_are_the_single_rays_bit_for_bit() {
        // Away from the origin, where a lens-centre ray through the focal plane
        // would round differently from the pinhole ray.
        let lens = View {
            from: Vec3::new(1.3, -2.7, 0.9),
            aperture: 40.0,
            focal: 0.7,
            ..view()
        };
        let bits = |r: &Ray| {
            let v = [r.origin, r.dir, r.inv_dir].map(|v| [v.x, v.y, v.z].map(f32::to_bits));
            (v, r.time.to_bits())
        };
        for v in [view(), lens] {
            let c = camera(&v, 7, 5).with_shutter([0.25, 2.0]);
            // 13 samples: a full block of eight and a partial one; lens points at the
            // centre (the pinhole ray), the square's corners and edges, and between.
            let lens_points = [0.0, 0.25, 0.5, 0.75, 0.999_999_94];
            let samples: Vec<CameraSample> = (0..13)
                .map(|i| CameraSample {
                    raster: (i as f32 * 0.53, 4.9 - i as f32 * 0.37),
                    lens: (lens_points[i % 5], lens_points[(i + i / 5) % 5]),
                    time: i as f32 / 13.0,
                })
                .collect();
            for block in samples.chunks(PACKET) {
                let rays = c.rays8(block);
                for (k, s) in block.iter().enumerate() {
                    assert_eq!(bits(&rays.ray(k)), bits(&c.ray(s)), "{s:?}");
                }
                // A partial packet repeats its last ray.
                let last = c.ray(&block[block.len() - 1]);
                for k in block.len()..PACKET {
                    assert_eq!(bits(&rays.ray(k)), bits(&last));
                }
            }
        }
    }

    #[test]
    fn the_quarter_turn_sine_and_cosine_match_the_library() {
        for i in -1000..=1000 {
            let x = std::f32::consts::FRAC_PI_4 * i as f32 / 1000.0;
            let (s, c) = sin_cos_quarter(x);
            assert!((s - x.sin()).abs() < 5e-7 && (c - x.cos()).abs() < 5e-7, "{x}");
        }
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
