//! Ear-clipping triangulation of simple planar polygons (Meisters 1975; see also
//! Eberly, "Triangulation by Ear Clipping"), done in the polygon's dominant plane.
//!
//! Concave polygons become triangles at build time so the BVH can bound their
//! pieces tightly and each candidate test is a cheap triangle test instead of
//! a crossings test over every edge (the SPD gears have 144-vertex concave faces).
//! Self-intersecting polygons have no such triangulation of their even-odd interior:
//! for them, and for very large polygons, [`ear_clip`] returns `None` and the caller
//! keeps the crossings test.

use crate::math::Vec3;

/// Largest polygon triangulated (the simplicity check is quadratic).
pub const MAX_EAR_CLIP_VERTICES: usize = 1024;

/// Triangles `(a, b, c)` (indices into `pts`, each in the polygon's own winding)
/// covering exactly the polygon, or `None` if it is self-intersecting, too large, or
/// numerically unsuitable. Zero-area pieces are left out.
pub fn ear_clip(pts: &[Vec3], axis: usize) -> Option<Vec<[usize; 3]>> {
    if pts.len() > MAX_EAR_CLIP_VERTICES {
        return None;
    }
    let (a1, a2) = ((axis + 1) % 3, (axis + 2) % 3);
    let xy: Vec<[f64; 2]> = pts.iter().map(|p| [p[a1] as f64, p[a2] as f64]).collect();
    // Vertices without consecutive repeats.
    let mut ring: Vec<usize> = Vec::with_capacity(pts.len());
    for i in 0..xy.len() {
        if ring.last().is_none_or(|&j| xy[j] != xy[i]) {
            ring.push(i);
        }
    }
    while ring.len() > 1 && xy[ring[0]] == xy[*ring.last()?] {
        ring.pop();
    }
    if ring.len() < 3 || self_intersects(&xy, &ring) {
        return None;
    }
    let orientation = signed_area(&xy, &ring).signum();
    if orientation == 0.0 {
        return None;
    }
    // Clip the ear with the shortest new diagonal each time: teeth and notches go
    // first and no fan of long slivers forms (slivers' boxes overlap and slow the
    // BVH down). Only an ear's two neighbours change status when it is clipped.
    let diagonal = |ring: &[usize], i: usize| {
        let n = ring.len();
        let (p, q) = (xy[ring[(i + n - 1) % n]], xy[ring[(i + 1) % n]]);
        (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)
    };
    // An ear's squared new diagonal, or infinity for a vertex that is no ear.
    let score = |ring: &[usize], i: usize| {
        if is_ear(&xy, ring, i, orientation) {
            diagonal(ring, i)
        } else {
            f64::INFINITY
        }
    };
    let mut scores: Vec<f64> = (0..ring.len()).map(|i| score(&ring, i)).collect();
    let mut tris = Vec::with_capacity(ring.len() - 2);
    while ring.len() > 3 {
        let n = ring.len();
        let (best, &s) = scores.iter().enumerate().min_by(|a, b| a.1.total_cmp(b.1))?;
        if s == f64::INFINITY {
            return None;
        }
        tris.push([ring[(best + n - 1) % n], ring[best], ring[(best + 1) % n]]);
        ring.remove(best);
        scores.remove(best);
        let n = ring.len();
        for i in [(best + n - 1) % n, best % n] {
            scores[i] = score(&ring, i);
        }
    }
    tris.push([ring[0], ring[1], ring[2]]);
    tris.retain(|&[a, b, c]| cross(xy[a], xy[b], xy[c]) != 0.0);
    // Keep each triangle's vertices in boundary order so its normal follows the
    // polygon's winding.
    for t in &mut tris {
        t.sort_unstable();
    }
    Some(tris)
}

/// z of (b - a) x (c - a).
fn cross(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

fn signed_area(xy: &[[f64; 2]], ring: &[usize]) -> f64 {
    let n = ring.len();
    (0..n)
        .map(|i| cross([0.0, 0.0], xy[ring[i]], xy[ring[(i + 1) % n]]))
        .sum::<f64>()
        * 0.5
}

/// Is vertex `i` of `ring` a convex corner whose triangle holds no other vertex?
fn is_ear(xy: &[[f64; 2]], ring: &[usize], i: usize, orientation: f64) -> bool {
    let n = ring.len();
    let (p, c, q) = (xy[ring[(i + n - 1) % n]], xy[ring[i]], xy[ring[(i + 1) % n]]);
    if cross(p, c, q) * orientation <= 0.0 {
        return false;
    }
    // The triangle's bounding box: a vertex outside it is outside the triangle, which
    // costs four comparisons to see instead of three cross products.
    let lo = [p[0].min(c[0]).min(q[0]), p[1].min(c[1]).min(q[1])];
    let hi = [p[0].max(c[0]).max(q[0]), p[1].max(c[1]).max(q[1])];
    ring.iter().enumerate().all(|(k, &j)| {
        let v = xy[j];
        if v[0] < lo[0] || v[0] > hi[0] || v[1] < lo[1] || v[1] > hi[1] {
            return true;
        }
        if k == i || k == (i + 1) % n || k == (i + n - 1) % n || v == p || v == c || v == q {
            return true;
        }
        // Outside (or strictly beyond an edge of) the candidate triangle.
        let s = [cross(p, c, v), cross(c, q, v), cross(q, p, v)].map(|x| x * orientation);
        s.iter().any(|&x| x < 0.0)
    })
}

/// Do any two non-adjacent edges of the ring touch or cross?
///
/// Edges whose x ranges are disjoint are not tested when the coordinates' exponents
/// lie close enough together that every difference of two of them is exact in
/// `f64`: then each computed cross product has the true sign or is zero, so a
/// reported crossing or touch is a real one, and real ones need overlapping ranges.
fn self_intersects(xy: &[[f64; 2]], ring: &[usize]) -> bool {
    let n = ring.len();
    let edge = |i: usize| (xy[ring[i]], xy[ring[(i + 1) % n]]);
    let apart = |i: usize, j: usize| i.abs_diff(j) >= 2 && i.abs_diff(j) != n - 1;
    if !differences_exact(xy, ring) {
        return (0..n).any(|i| (i + 2..n).any(|j| apart(i, j) && touch(edge(i), edge(j))));
    }
    // Sweep the edges by their x ranges (sort by left end, test while they overlap).
    let mut by_x: Vec<(f64, f64, usize)> = (0..n)
        .map(|i| {
            let (a, b) = edge(i);
            (a[0].min(b[0]), a[0].max(b[0]), i)
        })
        .collect();
    by_x.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    for (k, &(_, hi, i)) in by_x.iter().enumerate() {
        for &(lo, _, j) in &by_x[k + 1..] {
            if lo > hi {
                break;
            }
            if apart(i, j) && touch(edge(i), edge(j)) {
                return true;
            }
        }
    }
    false
}

/// Is `a - b` exact in `f64` for any two coordinates on the same axis? True when the
/// non-zero ones (all finite) span at most 2^28 in binary exponent: an `f32`
/// difference then needs at most 53 significant bits.
fn differences_exact(xy: &[[f64; 2]], ring: &[usize]) -> bool {
    (0..2).all(|axis| {
        let (mut lo, mut hi) = (i32::MAX, i32::MIN);
        for &i in ring {
            let v = xy[i][axis];
            if !v.is_finite() {
                return false;
            }
            if v != 0.0 {
                let e = ((v.to_bits() >> 52) & 0x7ff) as i32;
                (lo, hi) = (lo.min(e), hi.max(e));
            }
        }
        hi <= lo.saturating_add(28)
    })
}

fn touch((a, b): ([f64; 2], [f64; 2]), (c, d): ([f64; 2], [f64; 2])) -> bool {
    segments_touch(a, b, c, d)
}

fn segments_touch(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let (d1, d2) = (cross(a, b, c), cross(a, b, d));
    let (d3, d4) = (cross(c, d, a), cross(c, d, b));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let within = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
        r[0] >= p[0].min(q[0]) && r[0] <= p[0].max(q[0]) && r[1] >= p[1].min(q[1]) && r[1] <= p[1].max(q[1])
    };
    (d1 == 0.0 && within(a, b, c))
        || (d2 == 0.0 && within(a, b, d))
        || (d3 == 0.0 && within(c, d, a))
        || (d4 == 0.0 && within(c, d, b))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn poly(xy: &[(f32, f32)]) -> Vec<Vec3> {
        xy.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect()
    }

    fn area(pts: &[Vec3], tris: &[[usize; 3]]) -> f32 {
        tris.iter()
            .map(|&[a, b, c]| 0.5 * (pts[b] - pts[a]).cross(pts[c] - pts[a]).z)
            .sum()
    }

    #[test]
    fn l_shape_is_covered_exactly_with_its_winding() {
        // Area 3 (a 2x2 square minus a unit notch), counter-clockwise.
        let l = poly(&[
            (0.0, 0.0),
            (2.0, 0.0),
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 2.0),
            (0.0, 2.0),
        ]);
        let tris = ear_clip(&l, 2).unwrap();
        assert_eq!(tris.len(), 4);
        // Every piece keeps the counter-clockwise winding, so the areas add up to +3.
        assert!(tris
            .iter()
            .all(|&[a, b, c]| (l[b] - l[a]).cross(l[c] - l[a]).z > 0.0));
        assert!((area(&l, &tris) - 3.0).abs() < 1e-6);
    }

    #[test]
    fn clockwise_comb_keeps_clockwise_pieces() {
        // A comb with three teeth, clockwise: area 5 x 1 base + 3 teeth of 1 x 1.
        let mut comb = poly(&[
            (0.0, 0.0),
            (5.0, 0.0),
            (5.0, 2.0),
            (4.0, 2.0),
            (4.0, 1.0),
            (3.0, 1.0),
            (3.0, 2.0),
            (2.0, 2.0),
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 2.0),
            (0.0, 2.0),
        ]);
        comb.reverse();
        let tris = ear_clip(&comb, 2).unwrap();
        assert_eq!(tris.len(), comb.len() - 2);
        assert!((area(&comb, &tris) + 8.0).abs() < 1e-5);
    }

    #[test]
    fn self_intersecting_polygons_are_refused() {
        let bowtie = poly(&[(0.0, 0.0), (1.0, 1.0), (1.0, 0.0), (0.0, 1.0)]);
        assert!(ear_clip(&bowtie, 2).is_none());
        let pentagram: Vec<Vec3> = (0..5)
            .map(|k| {
                let a = std::f32::consts::TAU * (2 * k) as f32 / 5.0;
                Vec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        assert!(ear_clip(&pentagram, 2).is_none());
    }

    /// Every pair of non-adjacent edges, as the sweep's reference.
    fn all_pairs(xy: &[[f64; 2]], ring: &[usize]) -> bool {
        let n = ring.len();
        let edge = |i: usize| (xy[ring[i]], xy[ring[(i + 1) % n]]);
        (0..n).any(|i| (i + 2..n).any(|j| !(i == 0 && j == n - 1) && touch(edge(i), edge(j))))
    }

    /// Uniform numbers in [0, 1) from a fixed-seed xorshift generator.
    fn uniform(mut state: u64) -> impl FnMut() -> f32 {
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    /// `n` points around the origin at radii `r0 + next()`, at evenly spaced angles or,
    /// when `shuffled`, at random ones (the ring then often crosses itself); with
    /// `grid`, rounded to quarter units so that points fall on others' edges.
    fn star_ring(
        n: usize,
        r0: f32,
        shuffled: bool,
        grid: bool,
        next: &mut impl FnMut() -> f32,
    ) -> Vec<[f64; 2]> {
        (0..n)
            .map(|k| {
                let turn = if shuffled { next() } else { k as f32 / n as f32 };
                let a = std::f32::consts::TAU * turn;
                let r = r0 + next();
                let (mut x, mut y) = (r * a.cos(), r * a.sin());
                if grid {
                    (x, y) = ((x * 4.0).round(), (y * 4.0).round());
                }
                [x as f64, y as f64]
            })
            .collect()
    }

    /// `is_ear` without the bounding-box rejection: every other vertex through the
    /// three cross products.
    fn is_ear_reference(xy: &[[f64; 2]], ring: &[usize], i: usize, orientation: f64) -> bool {
        let n = ring.len();
        let (p, c, q) = (xy[ring[(i + n - 1) % n]], xy[ring[i]], xy[ring[(i + 1) % n]]);
        cross(p, c, q) * orientation > 0.0
            && ring.iter().enumerate().all(|(k, &j)| {
                let v = xy[j];
                let own = [i, (i + 1) % n, (i + n - 1) % n].contains(&k) || [p, c, q].contains(&v);
                own || [cross(p, c, v), cross(c, q, v), cross(q, p, v)]
                    .iter()
                    .any(|&x| x * orientation < 0.0)
            })
    }

    #[test]
    fn box_rejection_keeps_every_ear_decision() {
        let mut next = uniform(0x9e37_79b9_7f4a_7c15_u64);
        let (mut ears, mut blocked) = (0, 0);
        for case in 0..1000 {
            // Star-shaped rings with jittered radii, now and then on a coarse grid so
            // vertices fall on the candidate triangles' edges and corners.
            let n = 4 + case % 60;
            let xy = star_ring(n, 0.05, false, case % 4 == 0, &mut next);
            let ring: Vec<usize> = (0..n).collect();
            let orientation = signed_area(&xy, &ring).signum();
            for i in 0..n {
                let want = is_ear_reference(&xy, &ring, i, orientation);
                assert_eq!(
                    is_ear(&xy, &ring, i, orientation),
                    want,
                    "case {case}, vertex {i}"
                );
                let convex = {
                    let (p, c, q) = (xy[(i + n - 1) % n], xy[i], xy[(i + 1) % n]);
                    cross(p, c, q) * orientation > 0.0
                };
                if want {
                    ears += 1;
                } else if convex {
                    blocked += 1;
                }
            }
        }
        // Both answers came up often, convex corners refused for a vertex inside too.
        assert!(ears > 2000 && blocked > 150, "{ears} ears, {blocked} blocked");
    }

    #[test]
    fn edge_sweep_agrees_with_all_pairs() {
        let mut next = uniform(0x2545_f491_4f6c_dd1d_u64);
        let mut found = [0; 2];
        for case in 0..2000 {
            let n = 3 + case % 40;
            // Star-shaped rings with jittered radii (simple) or shuffled angles (often
            // crossing), on a coarse grid now and then so edges touch and overlap.
            let xy = star_ring(n, 1.0, case % 3 == 0, case % 5 == 0, &mut next);
            let ring: Vec<usize> = (0..n).collect();
            let want = all_pairs(&xy, &ring);
            assert_eq!(self_intersects(&xy, &ring), want, "case {case}");
            found[want as usize] += 1;
        }
        assert!(found[0] > 100 && found[1] > 100, "{found:?}");
    }
}
