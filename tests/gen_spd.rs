//! `nffrt gen NAME` at the default size against the SPD 3.14 output in
//! `../shared/scenes/spd/NAME.nff`: camera, background, lights, per-primitive
//! materials and file lines exactly; every coordinate, radius and normal within
//! 1e-4 (scaled by the number's magnitude when above 1). Each test is skipped,
//! saying so, when `../shared` is absent.

#[path = "common/skip.rs"]
mod skip;

use nffrt::gen::{generate, SpdScene};
use nffrt::math::Vec3;
use nffrt::Scene;

fn reference(which: SpdScene) -> Option<Scene> {
    let path = skip::shared(&format!("scenes/spd/{which}.nff"))?;
    let text = std::fs::read_to_string(&path).unwrap();
    let scene = nffrt::nff::parse(&text).expect("the SPD's scene parses");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    Some(scene)
}

/// Compares numbers one by one, naming the first that differs by more than the tolerance.
struct Checker {
    what: &'static str,
    worst: f32,
}

impl Checker {
    fn num(&mut self, ours: f32, theirs: f32, at: &str) {
        let err = (ours - theirs).abs() / theirs.abs().max(1.0);
        assert!(err <= 1e-4, "{}: {at}: ours {ours}, SPD {theirs}", self.what);
        self.worst = self.worst.max(err);
    }

    fn vec(&mut self, ours: Vec3, theirs: Vec3, at: &str) {
        for k in 0..3 {
            self.num(ours[k], theirs[k], at);
        }
    }
}

fn compare(which: SpdScene) {
    let Some(spd) = reference(which) else { return };
    let ours = generate(which, which.default_size()).unwrap();

    assert_eq!(ours.view, spd.view, "camera");
    assert_eq!(ours.background, spd.background, "background");
    assert_eq!(ours.lights, spd.lights, "lights");
    let counts = |s: &Scene| {
        [
            s.spheres.len(),
            s.cones.len(),
            s.polygons.len(),
            s.patches.len(),
            s.planes.len(),
            s.boxes.len(),
        ]
    };
    assert_eq!(
        counts(&ours),
        counts(&spd),
        "spheres, cones, polygons, patches, planes, boxes"
    );
    assert_eq!(ours.polygon_vertices.len(), spd.polygon_vertices.len());
    assert_eq!(ours.patch_vertices.len(), spd.patch_vertices.len());

    let mat = |s: &Scene, m: u32| s.materials[m as usize];
    let mut c = Checker {
        what: which.name(),
        worst: 0.0,
    };
    for (i, (a, b)) in ours.spheres.iter().zip(&spd.spheres).enumerate() {
        let at = format!("sphere {i} (line {})", b.line);
        assert_eq!(
            (a.line, mat(&ours, a.material)),
            (b.line, mat(&spd, b.material)),
            "{at}"
        );
        c.vec(a.center, b.center, &at);
        c.num(a.radius, b.radius, &at);
    }
    for (i, (a, b)) in ours.cones.iter().zip(&spd.cones).enumerate() {
        let at = format!("cone {i} (line {})", b.line);
        assert_eq!(
            (a.line, mat(&ours, a.material)),
            (b.line, mat(&spd, b.material)),
            "{at}"
        );
        c.vec(a.base, b.base, &at);
        c.num(a.base_radius, b.base_radius, &at);
        c.vec(a.apex, b.apex, &at);
        c.num(a.apex_radius, b.apex_radius, &at);
    }
    for (i, (a, b)) in ours.polygons.iter().zip(&spd.polygons).enumerate() {
        let at = format!("polygon {i} (line {})", b.line);
        assert_eq!(
            (a.line, a.count, mat(&ours, a.material)),
            (b.line, b.count, mat(&spd, b.material)),
            "{at}"
        );
        for (p, q) in ours.polygon_points(a).iter().zip(spd.polygon_points(b)) {
            c.vec(*p, *q, &at);
        }
    }
    for (i, (a, b)) in ours.patches.iter().zip(&spd.patches).enumerate() {
        let at = format!("patch {i} (line {})", b.line);
        assert_eq!(
            (a.line, a.count, mat(&ours, a.material)),
            (b.line, b.count, mat(&spd, b.material)),
            "{at}"
        );
        let ((pa, na), (pb, nb)) = (ours.patch_points(a), spd.patch_points(b));
        for k in 0..pa.len() {
            c.vec(pa[k], pb[k], &at);
            c.vec(na[k], nb[k], &at);
        }
    }
    // The SPD prints six significant digits: anything much worse is a real difference.
    assert!(c.worst < 1e-5, "{}: worst relative difference {}", which, c.worst);
    eprintln!("{which}: worst relative difference from the SPD {:.2e}", c.worst);
}

#[test]
fn balls_matches_spd() {
    compare(SpdScene::Balls);
}

#[test]
fn gears_matches_spd() {
    compare(SpdScene::Gears);
}

/// The mountain's displacements come from the SPD's own hash and random generator,
/// reproduced, so the mountain matches point for point like the other scenes.
#[test]
fn mount_matches_spd() {
    compare(SpdScene::Mount);
}

#[test]
fn rings_matches_spd() {
    compare(SpdScene::Rings);
}

#[test]
fn teapot_matches_spd() {
    compare(SpdScene::Teapot);
}

#[test]
fn tetra_matches_spd() {
    compare(SpdScene::Tetra);
}

#[test]
fn tree_matches_spd() {
    compare(SpdScene::Tree);
}
