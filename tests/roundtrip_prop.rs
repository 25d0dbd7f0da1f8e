//! Random scenes written to NFF or P3F text and parsed back give the same scene
//! (property test; the fixed corpora are in `roundtrip.rs`). Numbers range from tiny
//! to huge, every primitive kind and optional field appears, and materials are shared
//! at random; P3F scenes add specular colours, emission, roughness, moving spheres, a
//! lens, the shutter and the integrator.

mod common;

use common::compare::same_scene;
use nffrt::math::Vec3;
use nffrt::nff::{parse_bytes, parse_format, write_nff, write_p3f, Format};
use nffrt::scene::{
    AngleSpan, BoxPrim, Cone, Dialect, IntegratorKind, Light, Material, MovingSphere, Patch, Plane, Polygon,
    Scene, Sphere, View,
};
use proptest::prelude::*;

/// Any finite float, mostly moderate, sometimes tiny or huge.
fn num() -> impl Strategy<Value = f32> {
    prop_oneof![
        4 => -1e3f32..1e3,
        1 => (-30i32..30, -9.99f32..9.99).prop_map(|(e, m)| m * 10f32.powi(e)),
        1 => Just(0.0f32),
    ]
}

fn vec3() -> impl Strategy<Value = Vec3> {
    (num(), num(), num()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// Unit axis `k` (0, 1, 2) scaled by `s`.
fn axis(k: usize, s: f32) -> Vec3 {
    let mut a = [0.0; 3];
    a[k] = s;
    Vec3::from_array(a)
}

/// A regular `n`-gon in an axis plane: never degenerate.
fn ngon() -> impl Strategy<Value = Vec<Vec3>> {
    (
        3usize..7,
        -1e3f32..1e3,
        -1e3f32..1e3,
        -1e3f32..1e3,
        0.01f32..100.0,
        0usize..3,
    )
        .prop_map(|(n, x, y, z, r, k)| {
            let c = Vec3::new(x, y, z);
            (0..n)
                .map(|i| {
                    let a = std::f32::consts::TAU * i as f32 / n as f32;
                    c + axis(k, r * a.cos()) + axis((k + 1) % 3, r * a.sin())
                })
                .collect()
        })
}

fn material() -> impl Strategy<Value = Material> {
    (vec3(), num(), num(), num(), num(), num()).prop_map(|(color, kd, ks, shine, t, ior)| Material {
        color,
        kd,
        specular: Vec3::ONE,
        ks,
        shine,
        t,
        ior,
        ..Material::DEFAULT
    })
}

fn view() -> impl Strategy<Value = View> {
    (
        (-1e3f32..1e3, -1e3f32..1e3, -1e3f32..1e3),
        (-10f32..10.0, -10f32..10.0, 0.5f32..10.0),
        0.5f32..179.5,
        0.0f32..10.0,
        (1u32..=4096, 1u32..=4096),
    )
        .prop_map(|((x, y, z), (dx, dy, dz), angle, hither, (width, height))| {
            let from = Vec3::new(x, y, z);
            View {
                from,
                at: from + Vec3::new(dx, dy, dz),
                up: Vec3::new(0.0, 1.0, 0.0),
                angle,
                hither,
                width,
                height,
                ..View::default()
            }
        })
}

/// One primitive of a random kind, added to `s` with material `m` at line `line`.
#[derive(Clone, Debug)]
enum Prim {
    Sphere(Vec3, f32),
    Cone(Vec3, f32, Vec3, f32),
    Polygon(Vec<Vec3>),
    Patch(Vec<Vec3>, Vec<Vec3>),
    Plane(Vec<Vec3>),
    Box(Vec3, Vec3),
}

fn prim() -> impl Strategy<Value = Prim> {
    let nonzero = num().prop_filter("non-zero radius", |r| *r != 0.0);
    prop_oneof![
        (vec3(), nonzero).prop_map(|(c, r)| Prim::Sphere(c, r)),
        (vec3(), 0.01f32..10.0, vec3(), 0.0f32..10.0, any::<bool>())
            // The parser skips a cone whose axis has no length in f32 (ends closer
            // than about 1e-22 square to zero), not only one whose ends are equal.
            .prop_filter("an axis of non-zero length", |(b, _, a, _, _)| {
                (*a - *b).length_squared() > 0.0
            })
            .prop_map(|(b, rb, a, ra, inside)| {
                let sign = if inside { -1.0 } else { 1.0 };
                Prim::Cone(b, sign * rb, a, sign * ra)
            }),
        ngon().prop_map(Prim::Polygon),
        ngon()
            .prop_flat_map(|v| {
                let n = v.len();
                (Just(v), prop::collection::vec(vec3(), n))
            })
            .prop_map(|(v, n)| Prim::Patch(v, n)),
        ngon().prop_map(|v| Prim::Plane(v[..3].to_vec())),
        (vec3(), vec3()).prop_map(|(a, b)| Prim::Box(a.min(b), a.max(b))),
    ]
}

fn scene() -> impl Strategy<Value = Scene> {
    (
        view(),
        vec3(),
        prop::collection::vec((vec3(), prop::option::of(vec3())), 0..4),
        prop::collection::vec(material(), 1..5),
        prop::collection::vec((prim(), any::<prop::sample::Index>()), 0..24),
    )
        .prop_map(|(view, background, lights, materials, prims)| {
            let mut s = Scene {
                view,
                background,
                lights: lights
                    .into_iter()
                    .map(|(position, color)| Light::point(position, color))
                    .collect(),
                ..Scene::default()
            };
            let n_mat = materials.len();
            s.materials = materials;
            for (i, (p, m)) in prims.into_iter().enumerate() {
                let (material, line) = (m.index(n_mat) as u32, i as u32 + 1);
                match p {
                    Prim::Sphere(center, radius) => s.spheres.push(Sphere {
                        center,
                        radius,
                        material,
                        line,
                    }),
                    Prim::Cone(base, base_radius, apex, apex_radius) => s.cones.push(Cone {
                        base,
                        base_radius,
                        apex,
                        apex_radius,
                        material,
                        line,
                    }),
                    Prim::Polygon(v) => {
                        let first = s.polygon_vertices.len() as u32;
                        let count = v.len() as u32;
                        s.polygon_vertices.extend(v);
                        s.polygons.push(Polygon {
                            first,
                            count,
                            material,
                            line,
                        });
                    }
                    Prim::Patch(v, n) => {
                        let first = s.patch_vertices.len() as u32;
                        let count = v.len() as u32;
                        s.patch_vertices.extend(v);
                        s.patch_normals.extend(n);
                        s.patches.push(Patch {
                            first,
                            count,
                            material,
                            line,
                        });
                    }
                    Prim::Plane(v) => s.planes.push(Plane {
                        points: [v[0], v[1], v[2]],
                        material,
                        line,
                    }),
                    Prim::Box(min, max) => s.boxes.push(BoxPrim {
                        min,
                        max,
                        material,
                        line,
                    }),
                }
            }
            s
        })
}

/// What P3F adds to a material: a specular colour, an emission (often none) and a
/// roughness (often none).
fn p3f_finish() -> impl Strategy<Value = (Vec3, Vec3, f32)> {
    (
        vec3(),
        prop_oneof![Just(Vec3::ZERO), vec3()],
        prop_oneof![Just(0.0f32), 0.0f32..=1.0, Just(1.0f32)],
    )
}

/// A moving sphere's operands: centres, a non-zero radius, two different times
/// whose velocity stays finite.
fn moving_sphere() -> impl Strategy<Value = (Vec3, Vec3, f32, f32, f32)> {
    let nonzero = num().prop_filter("non-zero radius", |r| *r != 0.0);
    (vec3(), vec3(), nonzero, num(), num())
        .prop_filter("two times, a finite velocity", |&(c0, c1, _, t0, t1)| {
            t0 != t1 && ((c1 - c0) / (t1 - t0)).is_finite()
        })
}

/// A scene as P3F says it: [`scene`]'s, with coloured lights, a lens and image-edge
/// angle, P3F materials, moving spheres, and maybe a shutter and an integrator.
fn p3f_scene() -> impl Strategy<Value = Scene> {
    (
        scene(),
        prop::collection::vec(p3f_finish(), 4),
        prop::collection::vec((moving_sphere(), any::<prop::sample::Index>()), 0..6),
        (0.0f32..10.0, 0.1f32..10.0),
        prop::option::of((num(), num())),
        prop::option::of(prop_oneof![
            Just(IntegratorKind::Whitted),
            Just(IntegratorKind::Path)
        ]),
    )
        .prop_map(
            |(mut s, finishes, moving, (aperture, focal), shutter, integrator)| {
                s.dialect = Dialect::P3f2025;
                s.view.angle_span = AngleSpan::ImageEdges;
                (s.view.aperture, s.view.focal) = (aperture, focal);
                for l in &mut s.lights {
                    l.color.get_or_insert(Vec3::ONE);
                }
                for (i, m) in s.materials.iter_mut().enumerate() {
                    (m.specular, m.emission, m.roughness) = finishes[i % finishes.len()];
                }
                // After every other primitive's line.
                let n_mat = s.materials.len();
                for (k, ((center0, center1, radius, time0, time1), m)) in moving.into_iter().enumerate() {
                    s.moving_spheres.push(MovingSphere {
                        center0,
                        center1,
                        radius,
                        time0,
                        time1,
                        material: m.index(n_mat) as u32,
                        line: 1000 + k as u32,
                    });
                }
                s.shutter = shutter.map(|(a, b)| [a.min(b), a.max(b)]);
                s.integrator = integrator;
                s
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn random_p3f_scenes_survive_write_and_parse(scene in p3f_scene()) {
        let mut text = Vec::new();
        write_p3f(&scene, &mut text).unwrap();
        let back = parse_format(&text, Format::P3f, &Default::default()).map_err(|e| {
            TestCaseError::fail(format!("{e}\n{}", String::from_utf8_lossy(&text)))
        })?;
        prop_assert!(back.warnings.is_empty(), "{:?}", back.warnings);
        prop_assert_eq!(same_scene(&scene, &back), Ok(()), "{}", String::from_utf8_lossy(&text));
    }

    #[test]
    fn random_scenes_survive_write_and_parse(scene in scene()) {
        let mut text = Vec::new();
        write_nff(&scene, &mut text).unwrap();
        let back = parse_bytes(&text).map_err(|e| {
            TestCaseError::fail(format!("{e}\n{}", String::from_utf8_lossy(&text)))
        })?;
        prop_assert!(back.warnings.is_empty(), "{:?}", back.warnings);
        prop_assert_eq!(same_scene(&scene, &back), Ok(()), "{}", String::from_utf8_lossy(&text));
    }
}
