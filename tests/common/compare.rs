//! Comparing two parsed scenes for meaning: everything must match except the source
//! `line` of each primitive, the warnings, how the material table is numbered, and
//! the P3F dialect (nffrt writes P3F in the 2024/25 one).

use std::fmt::Debug;

use nffrt::scene::{Dialect, Material};
use nffrt::Scene;

/// `scene` with every `line` set to 0, no warnings, and a material table rebuilt in
/// order of first use (kinds in a fixed order), equal entries merged, indices remapped.
/// Two scenes that mean the same thing have equal canonical forms.
pub fn canonical(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    s.warnings.clear();
    if s.dialect.is_p3f() {
        s.dialect = Dialect::P3f2025;
    }
    for t in &mut s.mesh_triangles {
        t.line = 0;
    }
    let old = std::mem::take(&mut s.materials);
    let mut table: Vec<Material> = Vec::new();
    let mut remap = |m: &mut u32| {
        let value = old[*m as usize];
        let i = table.iter().position(|t| *t == value).unwrap_or_else(|| {
            table.push(value);
            table.len() - 1
        });
        *m = i as u32;
    };
    for p in &mut s.planes {
        remap(&mut p.material);
        p.line = 0;
    }
    for p in &mut s.polygons {
        remap(&mut p.material);
        p.line = 0;
    }
    for p in &mut s.patches {
        remap(&mut p.material);
        p.line = 0;
    }
    for p in &mut s.spheres {
        remap(&mut p.material);
        p.line = 0;
    }
    for p in &mut s.moving_spheres {
        remap(&mut p.material);
        p.line = 0;
    }
    for p in &mut s.cones {
        remap(&mut p.material);
        p.line = 0;
    }
    for p in &mut s.boxes {
        remap(&mut p.material);
        p.line = 0;
    }
    for p in &mut s.meshes {
        remap(&mut p.material);
        p.line = 0;
    }
    s.materials = table;
    s
}

/// The first difference between two slices, described briefly (scenes are too big to
/// print whole in a failure message).
fn first_difference<T: PartialEq + Debug>(what: &str, a: &[T], b: &[T]) -> Option<String> {
    if a.len() != b.len() {
        return Some(format!("{what}: {} vs {} entries", a.len(), b.len()));
    }
    let i = a.iter().zip(b).position(|(x, y)| x != y)?;
    Some(format!("{what}[{i}]: {:?} vs {:?}", a[i], b[i]))
}

/// `Ok` when the scenes mean the same (see [`canonical`]), else the first difference.
pub fn same_scene(a: &Scene, b: &Scene) -> Result<(), String> {
    let (a, b) = (canonical(a), canonical(b));
    if a.view != b.view {
        return Err(format!("view: {:?} vs {:?}", a.view, b.view));
    }
    if a.background != b.background {
        return Err(format!("background: {:?} vs {:?}", a.background, b.background));
    }
    if (a.shutter, a.integrator) != (b.shutter, b.integrator) {
        return Err(format!(
            "shutter, integrator: {:?} vs {:?}",
            (a.shutter, a.integrator),
            (b.shutter, b.integrator)
        ));
    }
    let diff = first_difference("lights", &a.lights, &b.lights)
        .or_else(|| first_difference("materials", &a.materials, &b.materials))
        .or_else(|| first_difference("spheres", &a.spheres, &b.spheres))
        .or_else(|| first_difference("moving_spheres", &a.moving_spheres, &b.moving_spheres))
        .or_else(|| first_difference("cones", &a.cones, &b.cones))
        .or_else(|| first_difference("polygons", &a.polygons, &b.polygons))
        .or_else(|| first_difference("polygon_vertices", &a.polygon_vertices, &b.polygon_vertices))
        .or_else(|| first_difference("patches", &a.patches, &b.patches))
        .or_else(|| first_difference("patch_vertices", &a.patch_vertices, &b.patch_vertices))
        .or_else(|| first_difference("patch_normals", &a.patch_normals, &b.patch_normals))
        .or_else(|| first_difference("planes", &a.planes, &b.planes))
        .or_else(|| first_difference("boxes", &a.boxes, &b.boxes))
        .or_else(|| first_difference("meshes", &a.meshes, &b.meshes))
        .or_else(|| first_difference("mesh_vertices", &a.mesh_vertices, &b.mesh_vertices))
        .or_else(|| first_difference("mesh_triangles", &a.mesh_triangles, &b.mesh_triangles));
    match diff {
        Some(d) => Err(d),
        // Everything is compared above; this catches a field added to Scene later.
        None if a != b => Err("scenes differ in a field the comparison does not list".into()),
        None => Ok(()),
    }
}
