//! A small full render (shading, shadows, reflection, refraction) of generated
//! scenes at 128x128, single thread.

mod common;

use criterion::{criterion_group, criterion_main, Criterion};
use nffrt::accel::Bvh;
use nffrt::gen::SpdScene;
use nffrt::geometry::build_geometry;
use nffrt::render::{render, RenderOptions};
use std::hint::black_box;

fn render_small(c: &mut Criterion) {
    let mut group = c.benchmark_group("render_small");
    group.sample_size(20);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    for (which, size) in [(SpdScene::Balls, 3), (SpdScene::Mount, 5)] {
        let scene = common::scene(which, size);
        let bvh = Bvh::new(build_geometry(&scene));
        let opts = RenderOptions {
            width: 128,
            height: 128,
            ..RenderOptions::from_scene(&scene)
        };
        group.bench_function(which.name(), |b| {
            b.iter(|| pool.install(|| render(black_box(&scene), &bvh, &opts)))
        });
    }
    group.finish();
}

criterion_group!(benches, render_small);
criterion_main!(benches);
