//! A scene made ready to render: the parsed description and the BVH built from it,
//! owned together so that they can never be mismatched (a [`Bvh`] built from another
//! scene indexes that scene's materials and lights out of bounds).
//!
//! [`PreparedScene::render`] also checks the options before any work, so a caller
//! that takes them from a user (the Python bindings, a server) gets an error for a
//! bad size, depth, sample count, lens or region instead of a panic or an
//! allocation that cannot succeed.
//!
//! ```
//! use nffrt::{render::RenderOptions, PreparedScene};
//! let scene = nffrt::nff::parse("v from 0 0 5 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 8 8\n\
//!                                l 0 0 10\nf 1 1 1 1 0 1 0 1\ns 0 0 0 1\n").unwrap();
//! let prepared = PreparedScene::new(scene);
//! let opts = RenderOptions::from_scene(prepared.scene());
//! let (image, stats) = prepared.render(&opts).unwrap();
//! assert_eq!((image.width, stats.eye_rays), (8, 64));
//! ```

use thiserror::Error;

use crate::accel::Bvh;
use crate::geometry::build_geometry;
use crate::image::{Image, Region};
use crate::limits::{eye_grid_points, MAX_DEPTH, MAX_LIGHT_SAMPLES, MAX_PIXELS, MAX_RESOLUTION, MAX_SPP};
use crate::render::{render_region, Observer, RenderOptions, Sampling, Silent, Stats};
use crate::scene::Scene;

/// Why a prepared scene did not render.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum RenderError {
    /// An option is out of range; the message names it and the range.
    #[error("{0}")]
    Options(String),
    /// The observer cancelled the render.
    #[error("the render was cancelled")]
    Cancelled,
}

/// A scene with its BVH, built once; renders any number of times, from any thread.
pub struct PreparedScene {
    scene: Scene,
    bvh: Bvh,
}

impl PreparedScene {
    /// Builds the render-time geometry and the BVH of `scene` (in rayon's current
    /// pool). The scene is kept whole, primitives included, for its description.
    pub fn new(scene: Scene) -> PreparedScene {
        let bvh = Bvh::new(build_geometry(&scene));
        PreparedScene { scene, bvh }
    }

    /// The scene as parsed.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// Its BVH.
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    /// Renders the whole `opts.width` x `opts.height` image (see [`Self::render_region`]).
    pub fn render(&self, opts: &RenderOptions) -> Result<(Image, Stats), RenderError> {
        let full = Region::full(opts.width, opts.height);
        self.render_region(opts, &full, &Silent)
    }

    /// Checks `opts` and `region` (see [`check_options`]), then renders the region of
    /// the full image, reporting rows to `observer`: the same pixels as the full
    /// render has there, bit for bit.
    pub fn render_region(
        &self,
        opts: &RenderOptions,
        region: &Region,
        observer: &dyn Observer,
    ) -> Result<(Image, Stats), RenderError> {
        check_options(opts, region).map_err(RenderError::Options)?;
        render_region(&self.scene, &self.bvh, opts, region, observer).ok_or(RenderError::Cancelled)
    }
}

/// The image size of a render asked for with `width` and/or `height` of a scene
/// whose file says `scene_w` x `scene_h`: the file's size, or both sides as given,
/// or one side given and the other following the file's aspect ratio (rounded to
/// the nearest pixel, 1 to [`MAX_RESOLUTION`]). `nffrt render --width/--height`
/// and the Python bindings size their images by it.
pub fn image_size(width: Option<u32>, height: Option<u32>, scene_w: u32, scene_h: u32) -> (u32, u32) {
    // `given` pixels along a side of `side` scene pixels: the other side, `other` long.
    let follow = |given: u32, side: u32, other: u32| {
        let (given, side, other) = (given as u64, side.max(1) as u64, other as u64);
        ((given * other + side / 2) / side).clamp(1, MAX_RESOLUTION as u64) as u32
    };
    match (width, height) {
        (Some(w), Some(h)) => (w, h),
        (Some(w), None) => (w, follow(w, scene_w, scene_h)),
        (None, Some(h)) => (follow(h, scene_h, scene_w), h),
        (None, None) => (scene_w, scene_h),
    }
}

/// Checks that `opts` can be rendered over `region` within this module's limits:
/// a size of 1 to [`MAX_RESOLUTION`] per side, a depth of 1 to [`MAX_DEPTH`], 1 to
/// [`MAX_SPP`] samples, a finite lens (aperture at least 0, focal distance above
/// 0), 1 to [`MAX_LIGHT_SAMPLES`] light samples, a non-empty region inside the
/// image, and at most [`MAX_PIXELS`] eye-ray grid points in it.
pub fn check_options(opts: &RenderOptions, region: &Region) -> Result<(), String> {
    let (w, h) = (opts.width, opts.height);
    if !(1..=MAX_RESOLUTION).contains(&w) || !(1..=MAX_RESOLUTION).contains(&h) {
        return Err(format!(
            "a {w}x{h} image: width and height go from 1 to {MAX_RESOLUTION}"
        ));
    }
    if !(1..=MAX_DEPTH).contains(&opts.max_depth) {
        return Err(format!(
            "max depth {} is not between 1 and {MAX_DEPTH}",
            opts.max_depth
        ));
    }
    if let Sampling::Stratified { spp } | Sampling::Independent { spp } = opts.sampling {
        if !(1..=MAX_SPP).contains(&spp) {
            return Err(format!("{spp} samples per pixel is not between 1 and {MAX_SPP}"));
        }
    }
    if let Some(a) = opts.aperture.filter(|a| !(a.is_finite() && *a >= 0.0)) {
        return Err(format!("aperture {a} is not a finite number of at least 0"));
    }
    if let Some(f) = opts.focal.filter(|f| !(f.is_finite() && *f > 0.0)) {
        return Err(format!("focal distance {f} is not a finite number above 0"));
    }
    if let Some(n) = opts
        .light_samples
        .filter(|n| !(1..=MAX_LIGHT_SAMPLES).contains(n))
    {
        return Err(format!(
            "{n} light samples is not between 1 and {MAX_LIGHT_SAMPLES}"
        ));
    }
    let r = region;
    if r.x0 >= r.x1 || r.y0 >= r.y1 || r.x1 > w || r.y1 > h {
        return Err(format!(
            "region {r} is empty or does not fit in the {w}x{h} image (X1 and Y1 are exclusive)"
        ));
    }
    let grid = eye_grid_points(r.width(), r.height(), opts.sampling);
    if grid > MAX_PIXELS {
        let (rw, rh) = (r.width(), r.height());
        return Err(format!(
            "{rw}x{rh} is {grid} eye-ray grid points, more than the limit of {MAX_PIXELS} (render it in tiles)"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::{AtomicU32, Ordering};

    use super::*;
    use crate::render::render;

    /// A red sphere in front of a grey mirror plane, lit from the camera's side.
    const SCENE: &str = "v from 0 0 6 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 23 17\n\
                         b 0.1 0.2 0.3\nl 2 3 8\nf 1 0 0 0.8 0.2 20 0 1\ns 0 0 0 1.2\n\
                         f 0.5 0.5 0.5 0.5 0.5 10 0 1\npl 0 0 -2 1 0 -2 0 1 -2\n";

    fn prepared() -> PreparedScene {
        PreparedScene::new(crate::nff::parse(SCENE).unwrap())
    }

    #[test]
    fn renders_what_a_separately_built_pair_renders() {
        let p = prepared();
        let scene = crate::nff::parse(SCENE).unwrap();
        let bvh = Bvh::new(build_geometry(&scene));
        for sampling in [
            Sampling::PixelCenters,
            Sampling::SpdCorners,
            Sampling::Stratified { spp: 4 },
        ] {
            let opts = RenderOptions {
                sampling,
                ..RenderOptions::from_scene(&scene)
            };
            assert_eq!(
                p.render(&opts).unwrap(),
                render(&scene, &bvh, &opts),
                "{sampling}"
            );
        }
    }

    #[test]
    fn a_region_has_the_full_renders_pixels() {
        let p = prepared();
        let opts = RenderOptions {
            sampling: Sampling::Stratified { spp: 3 },
            ..RenderOptions::from_scene(p.scene())
        };
        let (full, _) = p.render(&opts).unwrap();
        let r = Region {
            x0: 5,
            y0: 2,
            x1: 19,
            y1: 11,
        };
        let (crop, stats) = p.render_region(&opts, &r, &Silent).unwrap();
        assert_eq!((crop.width, crop.height), (14, 9));
        assert_eq!(stats.eye_rays, 14 * 9 * 3);
        for y in 0..9 {
            for x in 0..14 {
                assert_eq!(crop.get(x, y), full.get(x + 5, y + 2), "({x}, {y})");
            }
        }
    }

    #[test]
    fn bad_options_are_errors_not_panics() {
        let p = prepared();
        let good = RenderOptions::from_scene(p.scene());
        let full = Region::full(23, 17);
        let cases: [(RenderOptions, Region, &str); 10] = [
            (RenderOptions { width: 0, ..good }, full, "width and height"),
            (
                RenderOptions {
                    height: 40000,
                    ..good
                },
                full,
                "width and height",
            ),
            (RenderOptions { max_depth: 0, ..good }, full, "max depth 0"),
            (
                RenderOptions {
                    max_depth: 65,
                    ..good
                },
                full,
                "max depth 65",
            ),
            (
                RenderOptions {
                    sampling: Sampling::Stratified { spp: 0 },
                    ..good
                },
                full,
                "0 samples",
            ),
            (
                RenderOptions {
                    aperture: Some(f32::NAN),
                    ..good
                },
                full,
                "aperture NaN",
            ),
            (
                RenderOptions {
                    focal: Some(0.0),
                    ..good
                },
                full,
                "focal distance 0",
            ),
            (
                RenderOptions {
                    light_samples: Some(0),
                    ..good
                },
                full,
                "0 light samples",
            ),
            (
                good,
                Region {
                    x0: 0,
                    y0: 0,
                    x1: 24,
                    y1: 17,
                },
                "does not fit",
            ),
            (
                good,
                Region {
                    x0: 3,
                    y0: 0,
                    x1: 3,
                    y1: 17,
                },
                "is empty",
            ),
        ];
        for (opts, region, want) in cases {
            match p.render_region(&opts, &region, &Silent) {
                Err(RenderError::Options(m)) => assert!(m.contains(want), "{m:?} lacks {want:?}"),
                other => panic!("{want}: {:?}", other.map(|(_, s)| s)),
            }
        }
        let huge = RenderOptions {
            width: 32768,
            height: 32768,
            ..good
        };
        let e = p.render(&huge).unwrap_err();
        assert!(e.to_string().contains("more than the limit"), "{e}");
    }

    #[test]
    fn one_side_given_keeps_the_aspect_ratio() {
        assert_eq!(image_size(None, None, 640, 480), (640, 480));
        assert_eq!(image_size(Some(320), None, 640, 480), (320, 240));
        assert_eq!(image_size(None, Some(100), 640, 480), (133, 100)); // 133.3
        assert_eq!(image_size(Some(5), None, 23, 17), (5, 4)); // 3.7
        assert_eq!(image_size(Some(7), Some(9), 640, 480), (7, 9));
        assert_eq!(image_size(Some(1), None, 32768, 1), (1, 1)); // never 0
        assert_eq!(image_size(None, Some(32768), 1, 2), (16384, 32768));
        assert_eq!(image_size(Some(32768), None, 1, 2), (32768, 32768)); // capped
    }

    /// Cancels once `after` rows are done.
    struct CancelAfter {
        rows: AtomicU32,
        after: u32,
    }

    impl Observer for CancelAfter {
        fn row_done(&self, _rays: u64) {
            self.rows.fetch_add(1, Ordering::SeqCst);
        }
        fn cancelled(&self) -> bool {
            self.rows.load(Ordering::SeqCst) >= self.after
        }
    }

    #[test]
    fn an_observer_cancels() {
        let p = prepared();
        // Tall, so that rows already started when it cancels cannot be all of them.
        let opts = RenderOptions {
            height: 400,
            ..RenderOptions::from_scene(p.scene())
        };
        let observer = CancelAfter {
            rows: AtomicU32::new(0),
            after: 2,
        };
        let full = Region::full(23, 400);
        assert_eq!(
            p.render_region(&opts, &full, &observer).unwrap_err(),
            RenderError::Cancelled
        );
        assert!(observer.rows.load(Ordering::SeqCst) < 400);
    }
}
