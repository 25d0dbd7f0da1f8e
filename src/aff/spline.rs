//! Kochanek-Bartels splines as BART's original code builds and evaluates them (the
//! distribution's `kbsplpos` and `kbsplrot`, after Dave Eberly's): a key is a time, a
//! value and the tension `T`, continuity `C` and bias `B` of the curve through it.
//!
//! Of `n >= 4` keys the first and the last only shape tangents: the curve runs from
//! key 1 to key `n - 2`, one cubic per pair of neighbouring keys, and is clamped
//! outside (before key 1's time it stays at key 1, after key `n - 2`'s at key
//! `n - 2`). At time `t` it follows the first segment whose end is after `t`: with
//! times out of order (BART's robot scene has a run of keys that goes back in
//! time), the segments a time reaches again are never used. Between keys `P1` (at `t1`) and `P2` (at `t2`), with neighbours `P0` and
//! `P3`, `D = P2 - P1` and `u = (t - t1) / (t2 - t1)`:
//!
//! ```text
//! out tangent at P1:  T1 = a1 (1-T1)(1-C1)(1-B1)/2 * D + a1 (1-T1)(1+C1)(1+B1)/2 * (P1 - P0)
//!   a1 = 2 (t2 - t1) / (t2 - t0)
//! in tangent at P2:   T2 = a2 (1-T2)(1+C2)(1-B2)/2 * (P3 - P2) + a2 (1-T2)(1-C2)(1+B2)/2 * D
//!   a2 = 2 (t2 - t1) / (t3 - t1)
//! P(u) = P1 + T1 u + (3D - 2 T1 - T2) u² + (T1 + T2 - 2D) u³      (Hermite)
//! ```
//!
//! (In the tangents, `Tk`, `Ck`, `Bk` are the key's tension, continuity and bias.)
//! Rotations take the same multipliers on quaternion logarithms and are interpolated
//! by `squad` (see [`RotationSpline`]).

use super::transform::Quat;

/// Tension, continuity and bias of a key.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tcb {
    /// Tension: 1 makes the curve stop at the key, -1 overshoot.
    pub tension: f64,
    /// Continuity: 0 keeps the tangent continuous through the key.
    pub continuity: f64,
    /// Bias: towards the previous key (positive) or the next (negative).
    pub bias: f64,
}

/// The multipliers of a segment from key 1 to key 2 (times `t[0..4]`, the keys'
/// `tcb`): `(out0, out1)` weigh `P1 - P0` and `D` in the out tangent at key 1,
/// `(in0, in1)` weigh `D` and `P3 - P2` in the in tangent at key 2.
fn multipliers(t: [f64; 4], k1: Tcb, k2: Tcb) -> ([f64; 2], [f64; 2]) {
    let a1 = 2.0 * (t[2] - t[1]) / (t[2] - t[0]);
    let out0 = 0.5 * a1 * (1.0 - k1.tension) * (1.0 + k1.continuity) * (1.0 + k1.bias);
    let out1 = 0.5 * a1 * (1.0 - k1.tension) * (1.0 - k1.continuity) * (1.0 - k1.bias);
    let a2 = 2.0 * (t[2] - t[1]) / (t[3] - t[1]);
    let in0 = 0.5 * a2 * (1.0 - k2.tension) * (1.0 - k2.continuity) * (1.0 + k2.bias);
    let in1 = 0.5 * a2 * (1.0 - k2.tension) * (1.0 + k2.continuity) * (1.0 - k2.bias);
    ([out0, out1], [in0, in1])
}

/// The segment `i` of those spanning `[start, end]` that time `t` falls in, and the
/// parameter `u` in [0, 1] along it: clamped to the first segment's start and the
/// last one's end (the original's `ComputeIAndU`).
fn locate(spans: &[(f64, f64)], t: f64) -> (usize, f64) {
    let last = spans.len() - 1;
    if t <= spans[0].0 {
        return (0, 0.0);
    }
    if t >= spans[last].1 {
        return (last, 1.0);
    }
    // The first segment ending after t; it starts at or before t, and is not empty.
    let i = spans.iter().position(|&(_, end)| t < end).unwrap_or(last);
    let (start, end) = spans[i];
    (i, (t - start) / (end - start))
}

/// A position (or scale) key.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PositionKey {
    /// Its time.
    pub time: f64,
    /// Its value.
    pub value: [f64; 3],
    /// The curve's shape through it.
    pub tcb: Tcb,
}

/// A curve through position keys: one cubic `C0 + C1 u + C2 u² + C3 u³` per segment.
#[derive(Clone, Debug, PartialEq)]
pub struct PositionSpline {
    /// `[C0, C1, C2, C3]` of each segment.
    cubics: Vec<[[f64; 3]; 4]>,
    /// The time each segment starts and ends.
    spans: Vec<(f64, f64)>,
}

impl PositionSpline {
    /// The curve through `keys`: at least 4 of them, and none at the time of the
    /// key two before it (the parser's checks).
    pub fn new(keys: &[PositionKey]) -> PositionSpline {
        debug_assert!(keys.len() >= 4);
        let mut cubics = Vec::with_capacity(keys.len() - 3);
        let mut spans = Vec::with_capacity(keys.len() - 3);
        for k in keys.windows(4) {
            let t = [k[0].time, k[1].time, k[2].time, k[3].time];
            let ([out0, out1], [in0, in1]) = multipliers(t, k[1].tcb, k[2].tcb);
            let (p0, p1, p2, p3) = (k[0].value, k[1].value, k[2].value, k[3].value);
            let mut c = [[0.0; 3]; 4];
            for a in 0..3 {
                let d = p2[a] - p1[a];
                let out = out1 * d + out0 * (p1[a] - p0[a]);
                let inn = in1 * (p3[a] - p2[a]) + in0 * d;
                c[0][a] = p1[a];
                c[1][a] = out;
                c[2][a] = 3.0 * d - 2.0 * out - inn;
                c[3][a] = -2.0 * d + out + inn;
            }
            cubics.push(c);
            spans.push((t[1], t[2]));
        }
        PositionSpline { cubics, spans }
    }

    /// The value at time `t`.
    pub fn at(&self, t: f64) -> [f64; 3] {
        let (i, u) = locate(&self.spans, t);
        let c = &self.cubics[i];
        [0, 1, 2].map(|a| c[0][a] + u * (c[1][a] + u * (c[2][a] + u * c[3][a])))
    }
}

/// A rotation key: an angle about an axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RotationKey {
    /// Its time.
    pub time: f64,
    /// The axis, as written (meant to be of unit length).
    pub axis: [f64; 3],
    /// The angle, in radians.
    pub angle: f64,
    /// The curve's shape through it.
    pub tcb: Tcb,
}

/// A curve through rotation keys: per segment the quaternions `p` and `q` of its two
/// keys and the inner points `a` and `b` that Kochanek-Bartels tangents give, taken
/// by `squad(u, p, a, b, q)`.
#[derive(Clone, Debug, PartialEq)]
pub struct RotationSpline {
    /// `[p, a, b, q]` of each segment.
    quads: Vec<[Quat; 4]>,
    /// The time each segment starts and ends.
    spans: Vec<(f64, f64)>,
}

impl RotationSpline {
    /// The curve through `keys` (the same conditions as [`PositionSpline::new`]).
    ///
    /// As in the original, the quaternion of each segment's second key is negated
    /// when it lies more than 90° (in 4D) from the first's, so that the segment takes
    /// the short way, and the negated key is written back (through its angle and
    /// axis) for the segments after it.
    pub fn new(keys: &[RotationKey]) -> RotationSpline {
        debug_assert!(keys.len() >= 4);
        let mut keys = keys.to_vec();
        let mut quads = Vec::with_capacity(keys.len() - 3);
        let mut spans = Vec::with_capacity(keys.len() - 3);
        for i in 0..keys.len() - 3 {
            let quat = |k: &RotationKey| Quat::from_angle_axis(k.angle, k.axis);
            let (q0, q1, mut q2, q3) = (
                quat(&keys[i]),
                quat(&keys[i + 1]),
                quat(&keys[i + 2]),
                quat(&keys[i + 3]),
            );
            if q1.dot(q2) < 0.0 {
                q2 = -q2;
                (keys[i + 2].angle, keys[i + 2].axis) = q2.to_angle_axis();
            }
            let t = [keys[i].time, keys[i + 1].time, keys[i + 2].time, keys[i + 3].time];
            let ([out0, out1], [in0, in1]) = multipliers(t, keys[i + 1].tcb, keys[i + 2].tcb);
            // log(q1⁻¹ q2), the segment's own turn, and the turns before and after it.
            let log_d = (q1.conjugate() * q2).log();
            let out = log_d.scale(out1) + (q0.conjugate() * q1).log().scale(out0);
            let inn = log_d.scale(in0) + (q2.conjugate() * q3).log().scale(in1);
            let a = q1 * (out - log_d).scale(0.5).exp();
            let b = q2 * (log_d - inn).scale(0.5).exp();
            quads.push([q1, a, b, q2]);
            spans.push((t[1], t[2]));
        }
        RotationSpline { quads, spans }
    }

    /// The rotation at time `t`, as an angle (radians) about a unit axis.
    pub fn at(&self, t: f64) -> (f64, [f64; 3]) {
        let (i, u) = locate(&self.spans, t);
        let [p, a, b, q] = self.quads[i];
        p.squad(u, a, b, q).to_angle_axis()
    }
}

#[cfg(test)]
mod tests;
