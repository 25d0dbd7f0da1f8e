//! The one checked way to start a render ([`render_region`]): the settings, the
//! region and the caller's limits are checked ([`check_render`]), the render runs,
//! and what it could not do comes back as a [`RenderError`], never a panic.

use thiserror::Error;

use super::{trace_region, Observer, Silent, Stats};
use crate::image::skybox::FaceError;
use crate::image::{Image, Region};
use crate::options::{check_render, Refused, RenderLimits, RenderOptions};
use crate::prepare::RenderScene;
use crate::scene::View;

/// Why a render did not run to the end.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum RenderError {
    /// The options or the region were refused before the render started.
    #[error(transparent)]
    Refused(#[from] Refused),
    /// The observer cancelled the render.
    #[error("the render was cancelled")]
    Cancelled,
    /// A skybox face could not be decoded (the picture is not given).
    #[error("{0}")]
    Asset(FaceError),
}

/// Renders the whole `opts.width` x `opts.height` image of `scene` seen by `view`,
/// within the default [`RenderLimits`], unobserved (see [`render_region`]).
pub fn render(scene: &RenderScene, view: &View, opts: &RenderOptions) -> Result<(Image, Stats), RenderError> {
    let full = Region::full(opts.width, opts.height);
    render_region(scene, view, opts, &full, &RenderLimits::default(), &Silent)
}

/// The one way every front end (the command line, the viewer's tiles, Python, Dask,
/// `nffrt bench`) renders: checks `opts` and `region` against the limits and
/// `limits` ([`check_render`]), then renders the region of the full image of `scene`
/// seen by `view` into a region-sized image whose pixels are exactly those the full
/// render has there, bit for bit, reporting rows to `observer`. Cancelling through
/// the observer gives [`RenderError::Cancelled`]; a skybox face that could not be
/// decoded gives [`RenderError::Asset`] (its rays saw black).
pub fn render_region(
    scene: &RenderScene,
    view: &View,
    opts: &RenderOptions,
    region: &Region,
    limits: &RenderLimits,
    observer: &dyn Observer,
) -> Result<(Image, Stats), RenderError> {
    check_render(opts, region, limits)?;
    let rendered = trace_region(scene, view, opts, region, observer).ok_or(RenderError::Cancelled)?;
    scene.decode_assets().map_err(RenderError::Asset)?;
    Ok(rendered)
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::{AtomicU32, Ordering};

    use super::*;
    use crate::load::Assets;
    use crate::options::Sampling;
    use crate::prepare::prepare;

    /// A red sphere in front of a grey mirror plane, lit from the camera's side.
    const SCENE: &str = "v from 0 0 6 at 0 0 0 up 0 1 0 angle 40 hither 1 resolution 23 17\n\
                         b 0.1 0.2 0.3\nl 2 3 8\nf 1 0 0 0.8 0.2 20 0 1\ns 0 0 0 1.2\n\
                         f 0.5 0.5 0.5 0.5 0.5 10 0 1\npl 0 0 -2 1 0 -2 0 1 -2\n";

    fn prepared() -> RenderScene {
        prepare(crate::nff::parse(SCENE).unwrap(), &Assets::default())
    }

    #[test]
    fn a_region_has_the_full_renders_pixels() {
        let p = prepared();
        let opts = RenderOptions {
            sampling: Sampling::Stratified { spp: 3 },
            ..RenderOptions::from_view(p.view())
        };
        let (full, _) = render(&p, p.view(), &opts).unwrap();
        let r = Region {
            x0: 5,
            y0: 2,
            x1: 19,
            y1: 11,
        };
        let (crop, stats) =
            render_region(&p, p.view(), &opts, &r, &RenderLimits::default(), &Silent).unwrap();
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
        let good = RenderOptions::from_view(p.view());
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
            match render_region(&p, p.view(), &opts, &region, &RenderLimits::default(), &Silent) {
                Err(RenderError::Refused(m)) => assert!(m.to_string().contains(want), "{m:?} lacks {want:?}"),
                other => panic!("{want}: {:?}", other.map(|(_, s)| s)),
            }
        }
        let huge = RenderOptions {
            width: 32768,
            height: 32768,
            ..good
        };
        let e = render(&p, p.view(), &huge).unwrap_err();
        assert!(e.to_string().contains("more than the limit"), "{e}");
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
            ..RenderOptions::from_view(p.view())
        };
        let observer = CancelAfter {
            rows: AtomicU32::new(0),
            after: 2,
        };
        let full = Region::full(23, 400);
        assert_eq!(
            render_region(&p, p.view(), &opts, &full, &RenderLimits::default(), &observer).unwrap_err(),
            RenderError::Cancelled
        );
        assert!(observer.rows.load(Ordering::SeqCst) < 400);
    }
}
