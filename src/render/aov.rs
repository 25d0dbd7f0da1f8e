//! Arbitrary output variables (AOVs): what each pixel's eye samples meet first —
//! the surface's albedo, its normal and its distance — in a pass of their own over
//! the very eye samples of the render (the same camera, pattern and seed): camera
//! rays and their closest hits, no shading. They guide the denoiser
//! (`crate::denoise`) and are written on request (`--aov`).
//!
//! Per pixel, over its samples in order:
//! - **albedo**: the mean of the first hit's reflectance, in [0, 1] per channel:
//!   the diffuse colour `Kd C` (times the texel on a textured surface, as the path
//!   tracer has it), plus the mirror's `Ks S` (`T = 0`) or 1 for glass
//!   (`T > 0`: Open Image Denoise's advice for dielectrics), clamped to 1; an emitter
//!   with no reflectance of its own takes its emission scaled to a largest channel of
//!   1; a sample that meets nothing takes the background's colour, clamped;
//! - **normal**: the mean of the first hit's shading normal (world space, unit
//!   length), turned to face the ray; zero for a sample that meets nothing;
//! - **depth**: the mean distance from the camera to the first hit over the samples
//!   that meet something; infinity where none does;
//! - **emission** (for the denoiser, not written): the mean of what the first hit
//!   emits towards the camera (its emission on the side of its own normal) or, for a
//!   sample that meets nothing, the background: the part of a path-traced pixel
//!   that its camera rays see directly, without noise.
//!
//! Like every picture nffrt makes, the same whatever the thread count or tiling.

use rayon::prelude::*;

use super::camera::CameraSample;
use super::door::RenderError;
use super::{Camera, Observer};
use crate::accel::{Coherence, Ray8, PACKET};
use crate::geometry::Hit;
use crate::image::{Image, Region};
use crate::math::{Ray, Vec3};
use crate::options::{check_render, RenderLimits, RenderOptions, Sampling};
use crate::prepare::RenderScene;
use crate::scene::{Material, View};

/// The AOVs that can be asked for, in the order they are written.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Aov {
    /// The first hit's reflectance.
    Albedo,
    /// The first hit's shading normal.
    Normal,
    /// The distance to the first hit.
    Depth,
}

impl Aov {
    /// Every AOV.
    pub const ALL: [Aov; 3] = [Aov::Albedo, Aov::Normal, Aov::Depth];

    /// Its name: `albedo`, `normal`, `depth`.
    pub fn name(self) -> &'static str {
        match self {
            Aov::Albedo => "albedo",
            Aov::Normal => "normal",
            Aov::Depth => "depth",
        }
    }

    /// The AOV of that name.
    pub fn from_name(name: &str) -> Option<Aov> {
        Aov::ALL.into_iter().find(|a| a.name() == name)
    }
}

/// The AOVs of a region, each region-sized, rows top first.
#[derive(Clone, Debug, PartialEq)]
pub struct Aovs {
    /// The first hits' mean reflectance, in [0, 1].
    pub albedo: Image,
    /// The first hits' mean shading normal (length up to 1; zero where no sample hit).
    pub normal: Image,
    /// The mean distance to the first hits; infinity where no sample hit.
    pub depth: Vec<f32>,
    /// The mean radiance the first hits emit towards the camera (the background
    /// for misses): what a path tracer adds to the pixel at its first vertex.
    pub emission: Image,
}

/// What one eye sample meets first.
#[derive(Clone, Copy)]
struct FirstHit {
    albedo: Vec3,
    normal: Vec3,
    depth: Option<f32>,
    emission: Vec3,
}

/// One pixel's sums over its samples.
#[derive(Clone, Copy, Default)]
struct Sums {
    albedo: Vec3,
    normal: Vec3,
    depth: f32,
    hits: u32,
    emission: Vec3,
}

/// The AOVs of `region` of the render of `scene` seen by `view` with `opts`, over
/// the render's own eye samples; checked as [`super::render_region`] checks a render,
/// rows reported to `observer` (which may cancel).
pub fn render_aovs(
    scene: &RenderScene,
    view: &View,
    opts: &RenderOptions,
    region: &Region,
    limits: &RenderLimits,
    observer: &dyn Observer,
) -> Result<Aovs, RenderError> {
    check_render(opts, region, limits)?;
    let camera = Camera::new(view, opts).with_shutter(scene.shutter());
    // The SPD protocol's rays go through pixel corners: its pixels' guides are
    // their centres'.
    let sampling = match opts.sampling {
        Sampling::SpdCorners => Sampling::PixelCenters,
        s => s,
    };
    let sampler = sampling.pixel_sampler(camera.has_lens(), scene.has_motion(), opts.seed);
    let (w, h) = (region.width() as usize, region.height() as usize);
    let n = sampler.count();
    let xs: Vec<u32> = (region.x0..region.x1).collect();
    let mut sums = vec![Sums::default(); w * h];
    let cancelled = sums
        .par_chunks_mut(w)
        .enumerate()
        .with_max_len(1)
        .map(|(j, row)| {
            if observer.cancelled() {
                return true;
            }
            let y = region.y0 + j as u32;
            let pixels: Vec<_> = xs.iter().map(|&x| sampler.pixel(x, y)).collect();
            let mut cams = Vec::with_capacity(w);
            for k in 0..n {
                cams.clear();
                cams.extend(pixels.iter().map(|p| sampler.sample_of(p, k).0));
                for (p, chunk) in cams.chunks(PACKET).enumerate() {
                    first_hits(scene, &camera, chunk, |i, first| row[p * PACKET + i].add(first));
                }
            }
            observer.row_done(w as u64 * n as u64);
            false
        })
        .reduce(|| false, |a, b| a || b);
    if cancelled {
        return Err(RenderError::Cancelled);
    }
    scene.decode_assets().map_err(RenderError::Asset)?;
    let weight = 1.0 / n as f32;
    let image = |f: fn(&Sums) -> Vec3| {
        let pixels = sums.iter().map(|s| f(s) * weight).collect();
        Image::from_pixels(w as u32, h as u32, pixels)
    };
    Ok(Aovs {
        albedo: image(|s| s.albedo),
        normal: image(|s| s.normal),
        depth: sums
            .iter()
            .map(|s| {
                if s.hits == 0 {
                    f32::INFINITY
                } else {
                    s.depth / s.hits as f32
                }
            })
            .collect(),
        emission: image(|s| s.emission),
    })
}

impl Sums {
    fn add(&mut self, first: FirstHit) {
        self.albedo += first.albedo;
        self.normal += first.normal;
        self.emission += first.emission;
        if let Some(d) = first.depth {
            self.depth += d;
            self.hits += 1;
        }
    }
}

/// The first hits of the eye rays of `samples` (one to [`PACKET`]), traced as a
/// packet, given in order to `done(i, first)`.
fn first_hits(
    scene: &RenderScene,
    camera: &Camera,
    samples: &[CameraSample],
    mut done: impl FnMut(usize, FirstHit),
) {
    let packet: Ray8 = camera.rays8(samples);
    let mut hits = [None; PACKET];
    let n = samples.len();
    scene.accel().closest_hits8(
        &packet,
        f32::INFINITY,
        (1 << n) - 1,
        Coherence::Coherent,
        &mut hits,
    );
    for (i, found) in hits[..n].iter().enumerate() {
        done(i, first_hit(scene, &packet.ray(i), *found));
    }
}

/// What `ray`, whose closest hit is `found`, meets first.
fn first_hit(scene: &RenderScene, ray: &Ray, found: Option<(Hit, u32)>) -> FirstHit {
    let Some((hit, index)) = found else {
        let sky = scene.background().color(ray.dir);
        return FirstHit {
            albedo: clamp01(sky),
            normal: Vec3::ZERO,
            depth: None,
            emission: sky,
        };
    };
    let prim = scene.primitive(index);
    let surface = prim.surface(ray, &hit, scene.accel().data());
    let normal = if surface.shading_normal.dot(ray.dir) > 0.0 {
        -surface.shading_normal
    } else {
        surface.shading_normal
    };
    let m = &scene.materials()[prim.material as usize];
    // Emitted on the side of the primitive's own normal, as path tracing has it.
    let facing = surface.normal.dot(ray.dir) < 0.0;
    FirstHit {
        albedo: albedo(m, scene.texel(m, prim, &hit)),
        normal,
        depth: Some(hit.t * ray.dir.length()),
        emission: if facing { m.emission } else { Vec3::ZERO },
    }
}

/// A material's reflectance as the denoiser's guide (see the module's text), its
/// diffuse colour times `texel` at a point of a textured surface.
pub fn albedo(m: &Material, texel: Option<Vec3>) -> Vec3 {
    let specular = if m.t > 0.0 { Vec3::ONE } else { m.specular * m.ks };
    let diffuse = match texel {
        Some(texel) => (m.color * m.kd).mul_elem(texel),
        None => m.color * m.kd,
    };
    let reflectance = clamp01(diffuse + specular);
    let brightest = m.emission.x.max(m.emission.y).max(m.emission.z);
    if reflectance == Vec3::ZERO && brightest > 0.0 {
        return clamp01(m.emission * (1.0 / brightest));
    }
    reflectance
}

fn clamp01(v: Vec3) -> Vec3 {
    Vec3::new(v.x.clamp(0.0, 1.0), v.y.clamp(0.0, 1.0), v.z.clamp(0.0, 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::load::Assets;
    use crate::prepare::prepare;
    use crate::render::Silent;

    /// A red matte sphere of radius 1 at the origin, seen from z = 5, on a blue
    /// background: the centre pixel's ray meets it at distance 4, with normal +z.
    const SCENE: &str = "v from 0 0 5 at 0 0 0 up 0 1 0 angle 30 hither 1 resolution 9 9\n\
                         b 0 0 0.5\nl 0 0 10\nf 0.8 0.1 0.1 0.5 0.3 10 0 1\ns 0 0 0 1\n";

    fn aovs(opts: impl Fn(RenderOptions) -> RenderOptions, region: Region) -> Aovs {
        let p = prepare(crate::nff::parse(SCENE).unwrap(), &Assets::default());
        let opts = opts(RenderOptions::from_view(p.view()));
        render_aovs(&p, p.view(), &opts, &region, &RenderLimits::default(), &Silent).unwrap()
    }

    #[test]
    fn the_centre_meets_the_sphere_and_the_corner_the_background() {
        let a = aovs(|o| o, Region::full(9, 9));
        // Kd C + Ks S = (0.4, 0.05, 0.05) + 0.3 (white specular) = (0.7, 0.35, 0.35).
        let c = a.albedo.get(4, 4);
        assert!((c - Vec3::new(0.7, 0.35, 0.35)).length() < 1e-6, "{c:?}");
        let n = a.normal.get(4, 4);
        assert!((n - Vec3::new(0.0, 0.0, 1.0)).length() < 1e-6, "{n:?}");
        assert!((a.depth[4 * 9 + 4] - 4.0).abs() < 1e-5, "{}", a.depth[40]);
        assert_eq!(a.albedo.get(0, 0), Vec3::new(0.0, 0.0, 0.5));
        assert_eq!(a.normal.get(0, 0), Vec3::ZERO);
        assert_eq!(a.depth[0], f32::INFINITY);
        assert_eq!(
            a.emission.get(0, 0),
            Vec3::new(0.0, 0.0, 0.5),
            "a miss sees the background"
        );
        assert_eq!(a.emission.get(4, 4), Vec3::ZERO, "the sphere emits nothing");
    }

    #[test]
    fn a_region_has_the_full_passes_values_and_samples_average() {
        let spp = |o| RenderOptions {
            sampling: Sampling::Stratified { spp: 4 },
            ..o
        };
        let full = aovs(spp, Region::full(9, 9));
        let crop = aovs(
            spp,
            Region {
                x0: 2,
                y0: 3,
                x1: 7,
                y1: 8,
            },
        );
        for y in 0..5 {
            for x in 0..5 {
                assert_eq!(crop.albedo.get(x, y), full.albedo.get(x + 2, y + 3));
                assert_eq!(crop.normal.get(x, y), full.normal.get(x + 2, y + 3));
                assert_eq!(
                    crop.depth[(y * 5 + x) as usize],
                    full.depth[((y + 3) * 9 + x + 2) as usize]
                );
            }
        }
        // Each pixel mixes the sphere's albedo and the background's in the share
        // of its samples that meet the sphere, and some pixels (the edge) do both.
        let mut mixed = 0;
        for (i, a) in full.albedo.pixels.iter().enumerate() {
            let share = a.x / 0.7;
            assert!(
                (a.z - (share * 0.35 + (1.0 - share) * 0.5)).abs() < 1e-5,
                "pixel {i}: {a:?}"
            );
            mixed += usize::from(share > 0.1 && share < 0.9);
            assert_eq!(full.depth[i].is_finite(), share > 0.0, "pixel {i}");
        }
        assert!(mixed > 4, "{mixed} edge pixels");
    }

    #[test]
    fn glass_is_white_and_a_pure_emitter_its_normalised_colour() {
        let mut m = crate::scene::Material::DEFAULT;
        m.t = 0.9;
        m.kd = 0.1;
        assert_eq!(albedo(&m, None), Vec3::ONE);
        let lamp = crate::scene::Material {
            kd: 0.0,
            emission: Vec3::new(10.0, 5.0, 0.0),
            ..crate::scene::Material::DEFAULT
        };
        assert_eq!(albedo(&lamp, None), Vec3::new(1.0, 0.5, 0.0));
    }
}
