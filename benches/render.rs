//! A small full render (shading, shadows, reflection, refraction) of generated
//! scenes at 128x128, single thread; and the viewer's progressive passes against a
//! render of the same samples (`progressive`: both go through the one sample loop, so
//! a sample costs the same in either).

mod common;

use criterion::{criterion_group, criterion_main, Criterion};
use nffrt::gen::SpdScene;
use nffrt::load::Assets;
use nffrt::options::{RenderLimits, RenderOptions, Sampling};
use nffrt::prepare;
use nffrt::render::{render, Accumulator, Silent};
use std::hint::black_box;

fn render_small(c: &mut Criterion) {
    let mut group = c.benchmark_group("render_small");
    group.sample_size(20);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    for (which, size) in [(SpdScene::Balls, 3), (SpdScene::Mount, 5)] {
        let scene = common::scene(which, size);
        let scene = prepare(scene, &Assets::default());
        let opts = RenderOptions {
            width: 128,
            height: 128,
            ..RenderOptions::from_view(scene.view())
        };
        group.bench_function(which.name(), |b| {
            b.iter(|| pool.install(|| render(black_box(&scene), scene.view(), &opts)))
        });
    }
    group.finish();
}

/// Eight samples per pixel of the showcase-like balls scene at 96x96 with a lens:
/// one render, and an accumulator's passes of 1, 1, 2 and 4 samples (the viewer's).
fn progressive(c: &mut Criterion) {
    let mut group = c.benchmark_group("progressive");
    group.sample_size(10);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let scene = prepare(common::scene(SpdScene::Balls, 2), &Assets::default());
    let view = nffrt::scene::View {
        aperture: 4.0,
        ..*scene.view()
    };
    let opts = RenderOptions {
        width: 96,
        height: 96,
        sampling: Sampling::Stratified { spp: 8 },
        ..RenderOptions::from_view(&view)
    };
    group.bench_function("render_8spp", |b| {
        b.iter(|| pool.install(|| render(black_box(&scene), &view, &opts)))
    });
    group.bench_function("passes_8spp", |b| {
        b.iter(|| {
            pool.install(|| {
                let mut acc = Accumulator::new(&view, &opts, &RenderLimits::default()).unwrap();
                for count in [1, 1, 2, 4] {
                    acc.pass(black_box(&scene), count, &Silent)
                        .expect("an unobserved pass runs to the end");
                }
                acc.image()
            })
        })
    });
    group.finish();
}

criterion_group!(benches, render_small, progressive);
criterion_main!(benches);
