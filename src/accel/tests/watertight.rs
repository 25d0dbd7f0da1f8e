//! Watertightness: rays aimed exactly at the shared edges and vertices of closed
//! meshes must hit them. The answer is not asked of the triangle test itself (as
//! `edges.rs` compares the tree with a scan that uses the same test): a ray from
//! outside a closed mesh towards a point of its surface, from the side its faces
//! there look to, meets the mesh at that point, or earlier when another part of the
//! mesh stands in front, never later and never not at all.

use super::*;
use crate::gen::{generate, SpdScene};

/// A closed mesh wound outwards: vertices shared by index (so every triangle with a
/// vertex has the very same floats for it), and the triangles.
struct Mesh {
    verts: Vec<Vec3>,
    faces: Vec<[usize; 3]>,
}

impl Mesh {
    fn triangles(&self) -> Vec<[Vec3; 3]> {
        self.faces.iter().map(|f| f.map(|i| self.verts[i])).collect()
    }

    /// The unit outward normal of face `f`.
    fn normal(&self, f: usize) -> Vec3 {
        let [a, b, c] = self.faces[f].map(|i| self.verts[i]);
        (b - a).cross(c - a).normalize()
    }

    /// Each edge (its vertices, lower index first) with the faces around it, and each
    /// vertex with the faces around it.
    #[allow(clippy::type_complexity)]
    fn adjacency(&self) -> (Vec<((usize, usize), Vec<usize>)>, Vec<Vec<usize>>) {
        let mut edges: std::collections::BTreeMap<(usize, usize), Vec<usize>> = Default::default();
        let mut around = vec![Vec::new(); self.verts.len()];
        for (f, face) in self.faces.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (face[k], face[(k + 1) % 3]);
                edges.entry((a.min(b), a.max(b))).or_default().push(f);
                around[a].push(f);
            }
        }
        (edges.into_iter().collect(), around)
    }

    /// Rotated by the unit quaternion of the (not necessarily unit) axis-angle
    /// `(axis, angle)` about the origin, then scaled and moved.
    fn placed(mut self, axis: Vec3, angle: f32, scale: f32, offset: Vec3) -> Mesh {
        let axis = axis.normalize();
        let (s, c) = angle.sin_cos();
        for v in &mut self.verts {
            // Rodrigues' rotation.
            let r = *v * c + axis.cross(*v) * s + axis * (axis.dot(*v) * (1.0 - c));
            *v = r * scale + offset;
        }
        self
    }
}

/// An icosahedron subdivided `levels` times, its vertices pushed out to the unit
/// sphere.
fn icosphere(levels: u32) -> Mesh {
    let p = (1.0 + 5.0f32.sqrt()) / 2.0;
    let mut verts: Vec<Vec3> = [
        (-1.0, p, 0.0),
        (1.0, p, 0.0),
        (-1.0, -p, 0.0),
        (1.0, -p, 0.0),
        (0.0, -1.0, p),
        (0.0, 1.0, p),
        (0.0, -1.0, -p),
        (0.0, 1.0, -p),
        (p, 0.0, -1.0),
        (p, 0.0, 1.0),
        (-p, 0.0, -1.0),
        (-p, 0.0, 1.0),
    ]
    .into_iter()
    .map(|(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut faces: Vec<[usize; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut middle = std::collections::HashMap::new();
        let mut mid = |a: usize, b: usize, verts: &mut Vec<Vec3>| {
            *middle.entry((a.min(b), a.max(b))).or_insert_with(|| {
                verts.push(((verts[a] + verts[b]) * 0.5).normalize());
                verts.len() - 1
            })
        };
        faces = faces
            .iter()
            .flat_map(|&[a, b, c]| {
                let (ab, bc, ca) = (
                    mid(a, b, &mut verts),
                    mid(b, c, &mut verts),
                    mid(c, a, &mut verts),
                );
                [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
            })
            .collect();
    }
    Mesh { verts, faces }
}

/// The cube `[-1, 1]^3`, each face a grid of `n × n` squares cut into two
/// triangles each, the grid points shared between faces.
fn cube(n: usize) -> Mesh {
    let mut index = std::collections::HashMap::new();
    let mut verts = Vec::new();
    let mut faces = Vec::new();
    let mut vertex = |p: [i32; 3], verts: &mut Vec<Vec3>| {
        *index.entry(p).or_insert_with(|| {
            let c = p.map(|k| k as f32 / n as f32 * 2.0 - 1.0);
            verts.push(Vec3::from_array(c));
            verts.len() - 1
        })
    };
    let n_i = n as i32;
    for axis in 0..3 {
        for side in [0, n_i] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            for i in 0..n_i {
                for j in 0..n_i {
                    let corner = |di: i32, dj: i32| {
                        let mut p = [0; 3];
                        p[axis] = side;
                        p[u] = i + di;
                        p[v] = j + dj;
                        p
                    };
                    let q = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)]
                        .map(|p| vertex(p, &mut verts));
                    // (u, v, axis) is right-handed: counter-clockwise in (u, v)
                    // faces +axis, so the low side is wound the other way.
                    if side == n_i {
                        faces.push([q[0], q[1], q[2]]);
                        faces.push([q[0], q[2], q[3]]);
                    } else {
                        faces.push([q[0], q[2], q[1]]);
                        faces.push([q[0], q[3], q[2]]);
                    }
                }
            }
        }
    }
    Mesh { verts, faces }
}

/// The SPD tetra at `size` (its triangles four by four, one small tetrahedron
/// each), as one mesh: the small tetrahedra touch at their corners.
fn spd_tetra(size: u32) -> Mesh {
    let scene = generate(SpdScene::Tetra, size).unwrap();
    let mut index = std::collections::HashMap::new();
    let mut verts = Vec::new();
    let mut faces = Vec::new();
    for (k, p) in scene.polygons.iter().enumerate() {
        let pts = scene.polygon_points(p);
        assert_eq!(pts.len(), 3);
        // Vertices shared within one tetrahedron only: its faces' edges are the
        // ones shared (the tetrahedra meet at single points).
        let group = k / 4;
        let f = [0, 1, 2].map(|i| {
            let key = (group, pts[i].to_array().map(f32::to_bits));
            *index.entry(key).or_insert_with(|| {
                verts.push(pts[i]);
                verts.len() - 1
            })
        });
        faces.push(f);
    }
    Mesh { verts, faces }
}

/// The rays that slipped through, per query.
#[derive(Debug, Default)]
struct Slips {
    rays: usize,
    single: usize,
    /// Of `single`, those aimed at or around a vertex.
    single_around_vertices: usize,
    portable: usize,
    packet: usize,
    scan: usize,
    occluded: usize,
}

impl Slips {
    fn total(&self) -> usize {
        self.single + self.portable + self.packet + self.scan + self.occluded
    }
}

/// Aims packets of eight rays from points outside `mesh` at points of its shared
/// edges (interpolated along them in f32) and at its vertices, from directions all
/// the faces there look to, and counts the rays each query lets through (or finds
/// hitting beyond the target). `convex`: nothing stands in front of a target, so
/// the hit must be at its distance.
fn slips(mesh: &Mesh, convex: bool, seed: u64, targets: usize) -> Slips {
    let bvh = bvh_of(&scene_with(&[], &mesh.triangles()));
    let (edges, around) = mesh.adjacency();
    for (e, faces) in &edges {
        assert_eq!(faces.len(), 2, "edge {e:?} of a closed mesh");
    }
    let mut rnd = uniform(seed);
    let mut out = Slips::default();
    for n in 0..targets {
        // Targets on one edge (eight points along it; not its ends, where faces
        // other than its two meet) or around one vertex (the vertex and points on the edges from it), seen from one origin.
        let (points, faces): (Vec<Vec3>, Vec<usize>) = if n % 3 != 0 {
            let ((a, b), faces) = &edges[(rnd() * edges.len() as f32) as usize % edges.len()];
            let (a, b) = (mesh.verts[*a], mesh.verts[*b]);
            let points: Vec<Vec3> = (0..8)
                .map(|k| match k {
                    0 => a + (b - a) * 0.5,
                    1 => a * 0.5 + b * 0.5,
                    _ => a + (b - a) * rnd(),
                })
                .collect();
            (points, faces.clone())
        } else {
            let v = (rnd() * mesh.verts.len() as f32) as usize % mesh.verts.len();
            let p = mesh.verts[v];
            let faces = around[v].clone();
            let mut points = vec![p; 2];
            for &f in &faces {
                if points.len() == 8 {
                    break;
                }
                // A point on an edge of `f` from `p`, near `p`.
                let other = mesh.faces[f]
                    .iter()
                    .map(|&i| mesh.verts[i])
                    .find(|&q| q != p)
                    .unwrap();
                points.push(p + (other - p) * (rnd() * 0.1));
            }
            while points.len() < 8 {
                points.push(p);
            }
            (points, faces)
        };
        // An origin from which every face at the targets is seen from the front,
        // not too obliquely.
        let normals: Vec<Vec3> = faces.iter().map(|&f| mesh.normal(f)).collect();
        let mean = normals.iter().fold(Vec3::ZERO, |s, &n| s + n).normalize();
        let dir = loop {
            let d = Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize();
            let d = (d + mean * 0.8).normalize();
            if normals.iter().all(|&n| n.dot(d) > 0.1) {
                break d;
            }
        };
        let origin = points[0] + dir * (1.0 + rnd() * 20.0);
        let rays: Vec<Ray> = points
            .iter()
            .enumerate()
            .map(|(k, &p)| {
                // Unit directions, and for some rays the difference itself (the
                // target at t = 1, as the renderer's shadow rays reach their light).
                let d = p - origin;
                Ray::new(origin, if k % 4 == 3 { d } else { d.normalize() })
            })
            .collect();
        let mut packet = [None; crate::accel::PACKET];
        bvh.closest_hit_packet(&rays, f32::INFINITY, &mut packet[..rays.len()]);
        for (k, (ray, &p)) in rays.iter().zip(&points).enumerate() {
            // The target's distance along the ray.
            let expected = (p - origin).length() / ray.dir.length();
            let wrong = |hit: Option<(Hit, u32)>| match hit {
                None => true,
                Some((h, _)) => {
                    let tol = expected * 1e-4;
                    h.t > expected + tol || (convex && h.t < expected - tol)
                }
            };
            out.rays += 1;
            let single = usize::from(wrong(bvh.closest_hit(ray, f32::INFINITY)));
            out.single += single;
            if n % 3 == 0 {
                out.single_around_vertices += single;
            }
            // (The portable kernels, whichever this CPU runs.)
            let mut counts = Default::default();
            out.portable += usize::from(wrong(bvh.closest_hit_counted(ray, f32::INFINITY, &mut counts)));
            out.packet += usize::from(wrong(packet[k]));
            if k == 0 || mesh.faces.len() < 2000 {
                out.scan += usize::from(wrong(bvh.closest_hit_linear(ray, f32::INFINITY)));
            }
            out.occluded += usize::from(!bvh.occluded(ray, expected * 1.001));
        }
    }
    out
}

#[test]
fn rays_at_shared_edges_and_vertices_of_closed_meshes_never_slip_through() {
    let cases: [(&str, Mesh, bool); 5] = [
        ("icosphere", icosphere(3), true),
        (
            "icosphere, moved and rotated",
            icosphere(4).placed(Vec3::new(0.3, -1.0, 0.7), 0.9, 2.7, Vec3::new(31.0, -17.5, 9.25)),
            true,
        ),
        ("cube", cube(6), true),
        (
            "cube, moved and rotated",
            cube(9).placed(Vec3::new(1.0, 0.4, -0.2), 0.61, 0.37, Vec3::new(-3.3, 5.1, 120.0)),
            true,
        ),
        ("spd tetra", spd_tetra(5), false),
    ];
    let mut failures = Vec::new();
    for (i, (name, mesh, convex)) in cases.iter().enumerate() {
        let s = slips(mesh, *convex, 0x2545_f491_4f6c_dd1d + i as u64, 3000);
        eprintln!("{name}: {s:?}");
        if s.total() != 0 {
            failures.push(format!("{name}: {s:?}"));
        }
    }
    assert!(failures.is_empty(), "rays slipped through: {failures:#?}");
}
