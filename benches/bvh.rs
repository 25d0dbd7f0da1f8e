//! BVH build, closest-hit and occlusion queries on generated SPD scenes
//! (one primary ray per pixel centre at 256x256, single thread), and closest hits in
//! packets of 8 consecutive rays.

mod common;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use nffrt::accel::{Bvh, PACKET};
use nffrt::gen::SpdScene;
use nffrt::geometry::build_geometry;
use std::hint::black_box;

/// Triangles, spheres, triangles again, and cones (rings: thin oblique cylinders,
/// filed in the tree in two pieces, `accel::build::split`).
const SCENES: [(SpdScene, u32); 4] = [
    (SpdScene::Tetra, 6),
    (SpdScene::Balls, 4),
    (SpdScene::Mount, 6),
    (SpdScene::Rings, 4),
];

fn bvh_build(c: &mut Criterion) {
    let mut group = c.benchmark_group("bvh_build");
    for (which, size) in SCENES {
        let scene = common::scene(which, size);
        group.bench_function(which.name(), |b| {
            b.iter(|| Bvh::new(build_geometry(black_box(&scene))))
        });
    }
    group.finish();
}

/// The BVH of a generated scene and its primary rays at 256x256.
fn bvh_and_rays(which: SpdScene, size: u32) -> (Bvh, Vec<nffrt::math::Ray>) {
    let scene = common::scene(which, size);
    let rays = common::primary_rays(&scene, 256, 256);
    (Bvh::new(build_geometry(&scene)), rays)
}

fn queries(c: &mut Criterion) {
    for (group_name, occlusion) in [("closest_hit", false), ("occluded", true)] {
        let mut group = c.benchmark_group(group_name);
        for (which, size) in SCENES {
            let (bvh, rays) = bvh_and_rays(which, size);
            group.throughput(Throughput::Elements(rays.len() as u64));
            group.bench_function(which.name(), |b| {
                b.iter(|| {
                    rays.iter()
                        .filter(|r| {
                            if occlusion {
                                bvh.occluded(r, f32::INFINITY)
                            } else {
                                bvh.closest_hit(r, f32::INFINITY).is_some()
                            }
                        })
                        .count()
                })
            });
        }
        group.finish();
    }
}

fn packets(c: &mut Criterion) {
    let mut group = c.benchmark_group("closest_hit_packet");
    for (which, size) in SCENES {
        let (bvh, rays) = bvh_and_rays(which, size);
        group.throughput(Throughput::Elements(rays.len() as u64));
        group.bench_function(which.name(), |b| {
            let mut out = [None; PACKET];
            b.iter(|| {
                rays.chunks(PACKET)
                    .map(|packet| {
                        let out = &mut out[..packet.len()];
                        bvh.closest_hit_packet(packet, f32::INFINITY, out);
                        out.iter().filter(|h| h.is_some()).count()
                    })
                    .sum::<usize>()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bvh_build, queries, packets);
criterion_main!(benches);
