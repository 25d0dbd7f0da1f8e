//! BART's three scenes (in `../shared/scenes/bart`, skipped without it): each loads,
//! its camera sits on its keys at their times, its flattened frames differ between
//! two times, and museum7, whose animated sculpture is not shipped, is refused at
//! the include that names it.

mod common;

use std::path::Path;

use common::skip::shared;
use nffrt::aff::AffScene;
use nffrt::load::{load, LoadError, LoadOptions, Source};
use nffrt::math::Vec3;
use nffrt::Scene;

/// The scene at `relative` in `../shared/scenes/bart`, loaded, or `None` (skipped).
fn bart(relative: &str) -> Option<(Scene, std::sync::Arc<AffScene>)> {
    let path = shared(&format!("scenes/bart/{relative}"))?;
    let loaded = load(Source::File(&path), &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    Some((loaded.scene, loaded.aff.expect("an AFF scene")))
}

/// True if two flattened frames place something differently or look from elsewhere.
fn frames_differ(a: &Scene, b: &Scene) -> bool {
    a.view != b.view || a.patch_vertices != b.patch_vertices || a.mesh_vertices != b.mesh_vertices
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-4
}

#[test]
fn kitchen_loads_and_moves() {
    let Some((frame0, aff)) = bart("kitchen/aff/kitchen.aff") else {
        return;
    };
    // a 0.0 20.0 800: frames 1/40 apart.
    assert_eq!(
        (aff.frames(), aff.time_of_frame(0), aff.time_of_frame(400)),
        (800, 0.0, 10.0)
    );
    assert!(aff.warnings.is_empty(), "{:?}", aff.warnings);
    assert_eq!(aff.textures.len(), 8);
    // The camera's translation keys: (3.75, 2.3, 3.6) at t = 0 and (3.5, 0.2, 0.1) at 5.
    assert!(close(aff.camera_at(0.0).from, Vec3::new(3.75, 2.3, 3.6)));
    assert!(close(aff.camera_at(5.0).from, Vec3::new(3.5, 0.2, 0.1)));
    // The frame loaded places the meshes used more than once as instances; frames
    // with every mesh copied into world space compared.
    assert!(!frame0.instances.is_empty());
    let (first, later) = (
        aff.flatten(0.0).unwrap(),
        aff.flatten(aff.time_of_frame(400)).unwrap(),
    );
    assert!(frames_differ(&first, &later));
    // The toy car moves while the rest of the kitchen stands: same triangle count.
    assert_eq!(first.patches.len(), later.patches.len());
}

#[test]
fn robots_load_and_walk() {
    let Some((frame0, aff)) = bart("robot/aff/Robot.aff") else {
        return;
    };
    assert_eq!((aff.frames(), aff.time_of_frame(400)), (800, 25.0));
    // Camera keys: (-3.5, 2, -203) at t = 0, (0.25, 16, -162.6) at 8.4.
    assert!(close(aff.camera_at(0.0).from, Vec3::new(-3.5, 2.0, -203.0)));
    assert!(close(aff.camera_at(8.4).from, Vec3::new(0.25, 16.0, -162.6)));
    // Ten robots of the same parts: the parts' meshes are stored once.
    let s = aff.summary();
    assert!(s.flattened_triangles > 4 * s.instanced_triangles, "{s:?}");
    assert!(!frame0.instances.is_empty());
    let (first, later) = (
        aff.flatten(0.0).unwrap(),
        aff.flatten(aff.time_of_frame(300)).unwrap(),
    );
    assert!(frames_differ(&first, &later));
    assert_eq!(first.patch_vertices.len(), later.patch_vertices.len());
    assert_ne!(first.patch_vertices, later.patch_vertices);
}

#[test]
fn museum5_matches_its_header_and_its_sculpture_moves() {
    let Some((frame0, aff)) = bart("museum/aff/museum5.aff") else {
        return;
    };
    // The file's header: "Polygons: 10143, Spheres: 0, Cones: 8, Anim Tris: 1024"
    // (the polygons counted as written: 'p' entities and mesh triangles).
    let s = aff.summary();
    let mesh_triangles: usize = aff
        .meshes
        .geometries
        .iter()
        .map(|g| g.triangles.count as usize)
        .sum();
    assert_eq!(s.objects.polygons + mesh_triangles, 10143);
    assert_eq!(
        (s.objects.spheres, s.objects.cones, s.objects.animated_triangles),
        (0, 8, 1024)
    );
    // a -1.0 5.0 300; the camera's keys at -1 and 0.5.
    assert_eq!((aff.frames(), aff.time_of_frame(0)), (300, -1.0));
    assert!(close(frame0.view.from, Vec3::new(0.0, 1.8, -9.0)));
    assert!(close(aff.camera_at(0.5).from, Vec3::new(3.0, 2.4, -1.0)));
    // The sculpture's triangles are given at t = 0..4.
    let (a, b) = (aff.flatten(1.0).unwrap(), aff.flatten(2.5).unwrap());
    assert_ne!(a.patch_vertices, b.patch_vertices);
    assert_eq!(a.cones, b.cones);
}

#[test]
fn museum7_is_refused_at_the_include_of_its_missing_sculpture() {
    let Some(path) = shared("scenes/bart/museum/aff/museum7.aff") else {
        return;
    };
    match load(Source::File(&path), &LoadOptions::default()) {
        Err(LoadError::Parse { name, error }) => {
            assert_eq!(Path::new(&name), path);
            // "i 0 animart7.aff" on line 33.
            assert_eq!((error.line, error.column), (33, 5));
            assert!(
                error
                    .kind
                    .to_string()
                    .starts_with("cannot include animart7.aff: no such file"),
                "{}",
                error.kind
            );
        }
        other => panic!("{:?}", other.map(|l| l.name)),
    }
}
