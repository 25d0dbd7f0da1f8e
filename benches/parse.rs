//! Parsing speed: the largest shared scene when `../shared` is present, and a
//! generated mountain of the same size either way.

mod common;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use nffrt::gen::SpdScene;
use std::hint::black_box;

fn parse(c: &mut Criterion) {
    let mut group = c.benchmark_group("parse");
    let shared = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../shared/scenes/p3d/mount_very_high.nff"
    );
    let mut inputs = vec![(
        "gen_mount_7",
        common::nff_text(&common::scene(SpdScene::Mount, 7)),
    )];
    match std::fs::read_to_string(shared) {
        Ok(text) => inputs.push(("mount_very_high", text)),
        Err(_) => eprintln!("note: {shared} not found: benchmarking the generated mountain only"),
    }
    for (name, text) in &inputs {
        group.throughput(Throughput::Bytes(text.len() as u64));
        group.bench_function(*name, |b| b.iter(|| nffrt::nff::parse(black_box(text)).unwrap()));
    }
    group.finish();
}

criterion_group!(benches, parse);
criterion_main!(benches);
