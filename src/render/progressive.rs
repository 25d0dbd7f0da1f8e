//! Progressive rendering for interactive previews: a coarse picture at once, then
//! the full image refined sample by sample until it is exactly what [`super::render`]
//! makes.
//!
//! [`render_preview`] traces the centre sample of one pixel in every `stride` x
//! `stride` block: a small image, a few thousand rays, for a camera that is moving.
//!
//! An [`Accumulator`] holds, for every pixel, the running sum `Σ trace(s) · (1/N)`
//! over the first `k` of the pixel's `N` samples ([`super::PixelSampler::sample`]: the
//! pattern of the final sample count from the start), added in sample order: the
//! very products, in the very order, that a render adds: both go through the one
//! sample loop ([`super::RowTracer::add_samples`]), eye rays in packets. After the last
//! pass it therefore holds the rendered pixels bit for bit, however the samples were
//! split into passes; before that, [`Accumulator::image`] shows the sum scaled by
//! `N / k`.

use super::rows::{each_row, RowTracer};
use super::{Observer, RenderError, Stats};
use crate::image::{Image, Region};
use crate::math::Vec3;
use crate::options::{check_render, Refused, RenderLimits, RenderOptions, Sampling};
use crate::prepare::RenderScene;
use crate::scene::View;

/// A coarse picture of `opts`'s image of `scene` seen by `view`: pixel `(i, j)` is
/// the centre sample (through the lens centre) of the full image's pixel `(x, y)`,
/// `x = min(i·stride + stride/2, w-1)` and `y` likewise, so the image is
/// `ceil(w/stride)` x `ceil(h/stride)` and stands for the `stride` x `stride` block
/// from `(i·stride, j·stride)`. Rows are reported to the observer as rows of the
/// small image. The options are checked as [`super::render_region`] checks the
/// full image's.
pub fn render_preview(
    scene: &RenderScene,
    view: &View,
    opts: &RenderOptions,
    stride: u32,
    observer: &dyn Observer,
) -> Result<(Image, Stats), RenderError> {
    check_render(
        opts,
        &Region::full(opts.width, opts.height),
        &RenderLimits::default(),
    )?;
    let stride = stride.max(1);
    let (w, h) = (opts.width.div_ceil(stride), opts.height.div_ceil(stride));
    let full = |i: u32, size: u32| (i * stride + stride / 2).min(size - 1);
    let frame = RowTracer::new(scene, view, opts).centres();
    let xs: Vec<u32> = (0..w).map(|i| full(i, opts.width)).collect();
    let mut pixels = vec![Vec3::ZERO; w as usize * h as usize];
    let stats = each_row(&mut pixels, w as usize, observer, |j, row, ctx| {
        frame.add_samples(full(j, opts.height), &xs, 0..1, 1.0, row, ctx);
        observer.row_pixels(j, row);
    })
    .ok_or(RenderError::Cancelled)?;
    Ok((Image::from_pixels(w, h, pixels), stats))
}

/// The full image converging sample by sample (see the module docs).
#[derive(Clone, Debug)]
pub struct Accumulator {
    view: View,
    opts: RenderOptions,
    /// Per pixel, row by row: the sum of its first `done` weighted samples.
    sums: Vec<Vec3>,
    done: u32,
    /// A pass was cancelled half-way: rows hold different sample counts.
    torn: bool,
}

impl Accumulator {
    /// An empty accumulator for the image seen by `view` with `opts` (no samples
    /// yet), checked as [`super::render_region`] checks a render within `limits`;
    /// [`Sampling::SpdCorners`], whose pixels share corner rays, is refused.
    pub fn new(view: &View, opts: &RenderOptions, limits: &RenderLimits) -> Result<Accumulator, RenderError> {
        check_render(opts, &Region::full(opts.width, opts.height), limits)?;
        if opts.sampling == Sampling::SpdCorners {
            let why = "the SPD protocol's pixels share corner rays: they cannot be refined sample by sample";
            return Err(Refused::Setting(why.into()).into());
        }
        Ok(Accumulator {
            view: *view,
            opts: *opts,
            sums: vec![Vec3::ZERO; opts.width as usize * opts.height as usize],
            done: 0,
            torn: false,
        })
    }

    /// Samples per pixel traced so far.
    pub fn samples_done(&self) -> u32 {
        self.done
    }

    /// Samples per pixel of the finished image.
    pub fn samples_per_pixel(&self) -> u32 {
        self.opts.sampling.samples_per_pixel()
    }

    /// True once every sample is in: [`Accumulator::image`] is the rendered image.
    pub fn is_complete(&self) -> bool {
        self.done == self.samples_per_pixel()
    }

    /// The options the image is rendered with.
    pub fn options(&self) -> &RenderOptions {
        &self.opts
    }

    /// Traces the next `count` samples of every pixel of `scene` (fewer if fewer are
    /// left) and adds them in. Each finished row goes to the observer as it would
    /// show in [`Accumulator::image`] now. [`RenderError::Cancelled`] if the observer
    /// cancelled the pass, which leaves the accumulator unusable (every later pass is
    /// cancelled too).
    pub fn pass(
        &mut self,
        scene: &RenderScene,
        count: u32,
        observer: &dyn Observer,
    ) -> Result<Stats, RenderError> {
        if self.torn {
            return Err(RenderError::Cancelled);
        }
        let n = self.samples_per_pixel();
        let (first, end) = (self.done, (self.done + count).min(n));
        let frame = RowTracer::new(scene, &self.view, &self.opts);
        let weight = 1.0 / n as f32;
        let scale = n as f32 / end.max(1) as f32;
        let xs: Vec<u32> = (0..self.opts.width).collect();
        let stats = each_row(&mut self.sums, xs.len(), observer, |y, row, ctx| {
            frame.add_samples(y, &xs, first..end, weight, row, ctx);
            if end == n {
                observer.row_pixels(y, row);
            } else {
                let shown: Vec<Vec3> = row.iter().map(|&p| p * scale).collect();
                observer.row_pixels(y, &shown);
            }
        });
        match stats {
            Some(stats) => {
                self.done = end;
                Ok(stats)
            }
            None => {
                self.torn = true;
                Err(RenderError::Cancelled)
            }
        }
    }

    /// The picture so far: the sums scaled by `N / k` after `k` of `N` samples,
    /// exactly the rendered image once complete (black before the first pass).
    pub fn image(&self) -> Image {
        let scale = self.samples_per_pixel() as f32 / self.done.max(1) as f32;
        let pixels = if self.is_complete() {
            self.sums.clone()
        } else {
            self.sums.iter().map(|&p| p * scale).collect()
        };
        Image::from_pixels(self.opts.width, self.opts.height, pixels)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::load::Assets;
    use crate::nff::{parse_format, Format, Limits};
    use crate::prepare::prepare;
    use crate::render::{render, render_region, NoRecord, Silent, TraceContext};
    use std::sync::Mutex;

    /// A lens, a quad light and glass: every random dimension a sample has.
    const P3F: &str = "spp 4\nbclr 0.1 0.2 0.3\n\
        camera eye 0 -6 2 at 0 0 0.5 up 0 0 1 angle 50 hither 1 resolution 12 9 aperture 3 focal 1\n\
        light quad -1 -1 5 1 1 1 1 -1 5 -1 1 5 2\nlight punctual 4 -2 5 0.5 0.5 0.5\n\
        mat 0.8 0.8 0.8 0.8 1 1 1 0.2 10 0 1\npl 0 0 0 1 0 0 0 1 0\n\
        mat 1 1 1 0.1 1 1 1 0.1 50 1 1.5\ns -0.8 0 1 0.8\n\
        mat 0.9 0.5 0.5 0.7 1 1 1 0.3 50 0 1\ns 1 0.8 1 0.7\n";

    fn scene() -> RenderScene {
        let scene = parse_format(P3F.as_bytes(), Format::P3f, &Limits::default()).unwrap();
        prepare(scene, &Assets::default())
    }

    fn opts(scene: &RenderScene, sampling: Sampling) -> RenderOptions {
        RenderOptions {
            sampling,
            ..RenderOptions::from_view(scene.view())
        }
    }

    /// Records the rows an observer is given.
    #[derive(Default)]
    struct Rows(Mutex<Vec<(u32, Vec<Vec3>)>>);

    impl Observer for Rows {
        fn row_pixels(&self, y: u32, pixels: &[Vec3]) {
            self.0.lock().unwrap().push((y, pixels.to_vec()));
        }
    }

    impl Rows {
        fn image(&self, w: u32, h: u32) -> Image {
            let mut rows = self.0.lock().unwrap().clone();
            rows.sort_by_key(|r| r.0);
            assert_eq!(rows.len(), h as usize, "one report per row");
            Image::from_pixels(w, h, rows.into_iter().flat_map(|r| r.1).collect())
        }
    }

    #[test]
    fn passes_of_any_size_end_in_the_rendered_image() {
        let scene = scene();
        for sampling in [
            Sampling::PixelCenters,
            Sampling::Stratified { spp: 5 },
            Sampling::Stratified { spp: 16 },
            Sampling::Independent { spp: 3 },
        ] {
            let opts = opts(&scene, sampling);
            let (rendered, stats) = render(&scene, scene.view(), &opts).unwrap();
            for split in [vec![1, 1, 2, 4, 8], vec![16], vec![3, 100]] {
                let mut acc = Accumulator::new(scene.view(), &opts, &RenderLimits::default()).unwrap();
                let mut traced = Stats::default();
                for count in split {
                    if !acc.is_complete() {
                        traced += acc.pass(&scene, count, &Silent).unwrap();
                    }
                }
                assert!(acc.is_complete(), "{sampling}");
                assert_eq!(acc.image(), rendered, "{sampling}");
                assert_eq!(traced, stats, "{sampling}");
            }
        }
    }

    #[test]
    fn a_partial_image_is_the_sum_so_far_rescaled_and_rows_are_reported_as_shown() {
        let scene = scene();
        let opts = opts(&scene, Sampling::Stratified { spp: 4 });
        let mut acc = Accumulator::new(scene.view(), &opts, &RenderLimits::default()).unwrap();
        let rows = Rows::default();
        acc.pass(&scene, 1, &rows).unwrap();
        assert_eq!(acc.samples_done(), 1);
        assert_eq!(rows.image(12, 9), acc.image());
        // One sample of four, weighted 1/4 and shown times 4: the sample itself.
        let frame = RowTracer::new(&scene, scene.view(), &opts);
        let (sample, id) = frame.sampler().sample(5, 4, 0);
        let one = frame.sample_radiance(&sample, &id, &mut TraceContext::default(), &mut NoRecord);
        assert!((acc.image().get(5, 4) - one).length() < 1e-5);
    }

    /// Cancels after a given number of rows.
    struct CancelAfter(std::sync::atomic::AtomicU32, u32);

    impl Observer for CancelAfter {
        fn row_done(&self, _rays: u64) {
            self.0.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        }
        fn cancelled(&self) -> bool {
            self.0.load(std::sync::atomic::Ordering::SeqCst) >= self.1
        }
    }

    #[test]
    fn a_cancelled_pass_leaves_the_accumulator_unusable() {
        let scene = scene();
        let opts = opts(&scene, Sampling::Stratified { spp: 4 });
        let mut acc = Accumulator::new(scene.view(), &opts, &RenderLimits::default()).unwrap();
        let stop = CancelAfter(0.into(), 0);
        assert_eq!(acc.pass(&scene, 2, &stop), Err(RenderError::Cancelled));
        assert_eq!(acc.pass(&scene, 2, &Silent), Err(RenderError::Cancelled));
        assert_eq!(acc.samples_done(), 0);
        let spd = RenderOptions {
            sampling: Sampling::SpdCorners,
            ..opts
        };
        assert!(matches!(
            Accumulator::new(scene.view(), &spd, &RenderLimits::default()),
            Err(RenderError::Refused(_))
        ));
    }

    #[test]
    fn a_preview_of_stride_one_is_the_centre_sampled_render_and_larger_strides_subsample_it() {
        let scene = scene();
        let opts = opts(&scene, Sampling::PixelCenters);
        let (full, _) = render(&scene, scene.view(), &opts).unwrap();
        let pinhole = RenderOptions {
            aperture: Some(0.0),
            ..opts
        };
        let (pinhole_full, _) = render(&scene, scene.view(), &pinhole).unwrap();
        let rows = Rows::default();
        let (image, stats) = render_preview(&scene, scene.view(), &opts, 1, &rows).unwrap();
        // With one sample per pixel the lens is sampled at its centre: the render's
        // picture exactly, and a pinhole's up to rounding (the lens ray's direction
        // goes through the focal plane).
        assert_eq!(image, full);
        let near = |a: &Image, b: &Image| {
            a.pixels
                .iter()
                .zip(&b.pixels)
                .all(|(p, q)| (*p - *q).length() < 1e-5)
        };
        assert!(near(&image, &pinhole_full));
        assert_eq!(rows.image(12, 9), image);
        assert_eq!(stats.eye_rays, 12 * 9);
        let (small, _) = render_preview(&scene, scene.view(), &opts, 4, &Silent).unwrap();
        assert_eq!((small.width, small.height), (3, 3));
        assert_eq!(small.get(0, 0), image.get(2, 2));
        assert_eq!(
            small.get(2, 2),
            image.get(10, 8),
            "the last block's pixel is clamped"
        );
    }

    #[test]
    fn render_reports_every_row_with_the_image_pixels() {
        let scene = scene();
        for sampling in [
            Sampling::PixelCenters,
            Sampling::Stratified { spp: 2 },
            Sampling::SpdCorners,
        ] {
            let opts = opts(&scene, sampling);
            let rows = Rows::default();
            let full = crate::image::Region::full(opts.width, opts.height);
            let (image, _) = render_region(
                &scene,
                scene.view(),
                &opts,
                &full,
                &RenderLimits::default(),
                &rows,
            )
            .unwrap();
            assert_eq!(rows.image(12, 9), image, "{sampling}");
        }
    }
}
