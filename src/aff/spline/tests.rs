//! The splines against values worked out by hand from the Kochanek-Bartels formulas
//! in the module's documentation (each test writes its working out).

use std::f64::consts::PI;

use super::*;

fn key(time: f64, x: f64, tcb: Tcb) -> PositionKey {
    PositionKey {
        time,
        value: [x, 2.0 * x, -x],
        tcb,
    }
}

fn rot(time: f64, degrees: f64) -> RotationKey {
    RotationKey {
        time,
        axis: [0.0, 0.0, 1.0],
        angle: degrees.to_radians(),
        tcb: Tcb::default(),
    }
}

fn assert_close(got: f64, want: f64) {
    assert!((got - want).abs() < 1e-12, "got {got}, want {want}");
}

/// The value's x, with y = 2x and z = -x checked alongside (each axis is its own curve).
fn x_at(s: &PositionSpline, t: f64) -> f64 {
    let [x, y, z] = s.at(t);
    assert_close(y, 2.0 * x);
    assert_close(z, -x);
    x
}

#[test]
fn catmull_rom_keys_and_between() {
    // Keys (t, x): (0, 0), (1, 0), (2, 1), (3, 3), all T = C = B = 0; the curve runs
    // from key 1 to key 2. D = 1.
    // Out at key 1: a1 = 2 (2 - 1) / (2 - 0) = 1, both weights 1/2:
    //   T1 = D/2 + (0 - 0)/2 = 1/2.
    // In at key 2: a2 = 2 (2 - 1) / (3 - 1) = 1: T2 = (3 - 1)/2 + D/2 = 3/2.
    // P(u) = 0 + u/2 + (3 - 1 - 3/2) u² + (1/2 + 3/2 - 2) u³ = u/2 + u²/2.
    let s = PositionSpline::new(
        &[0.0, 0.0, 1.0, 3.0]
            .iter()
            .enumerate()
            .map(|(i, &x)| key(i as f64, x, Tcb::default()))
            .collect::<Vec<_>>(),
    );
    assert_close(x_at(&s, 1.0), 0.0);
    assert_close(x_at(&s, 2.0), 1.0);
    assert_close(x_at(&s, 1.5), 0.25 + 0.125);
    assert_close(x_at(&s, 1.25), 0.125 + 0.03125);
    // Clamped outside keys 1 and 2.
    assert_close(x_at(&s, -4.0), 0.0);
    assert_close(x_at(&s, 2.5), 1.0);
}

#[test]
fn tension_continuity_bias_and_uneven_times() {
    // Keys (t, x): (0, 1), (2, 2), (3, 4), (5, 4); key 1 has T = 1/2, key 2 has
    // C = 1/2 and B = -1/2. The curve runs from key 1 (t = 2) to key 2 (t = 3); D = 2.
    // Out at key 1: a1 = 2 (3 - 2) / (3 - 0) = 2/3;
    //   out0 = out1 = 1/2 · 2/3 · (1 - 1/2) = 1/6; T1 = D/6 + (2 - 1)/6 = 1/2.
    // In at key 2: a2 = 2 (3 - 2) / (5 - 2) = 2/3;
    //   in0 = 1/2 · 2/3 · (1 - C)(1 + B) = 1/3 · 1/2 · 1/2 = 1/12,
    //   in1 = 1/2 · 2/3 · (1 + C)(1 - B) = 1/3 · 3/2 · 3/2 = 3/4;
    //   T2 = 3/4 (4 - 4) + D/12 = 1/6.
    // P(u) = 2 + u/2 + (6 - 1 - 1/6) u² + (1/2 + 1/6 - 4) u³ = 2 + u/2 + 29/6 u² - 10/3 u³.
    let plain = Tcb::default();
    let keys = [
        key(0.0, 1.0, plain),
        key(
            2.0,
            2.0,
            Tcb {
                tension: 0.5,
                ..plain
            },
        ),
        key(
            3.0,
            4.0,
            Tcb {
                continuity: 0.5,
                bias: -0.5,
                ..plain
            },
        ),
        key(5.0, 4.0, plain),
    ];
    let s = PositionSpline::new(&keys);
    let p = |u: f64| 2.0 + u / 2.0 + 29.0 / 6.0 * u * u - 10.0 / 3.0 * u * u * u;
    assert_close(x_at(&s, 2.0), 2.0);
    assert_close(x_at(&s, 3.0), 4.0);
    assert_close(p(1.0), 4.0);
    for u in [0.1, 0.5, 0.8] {
        assert_close(x_at(&s, 2.0 + u), p(u));
    }
    // At u = 1/2: 2 + 1/4 + 29/24 - 10/24 = 73/24.
    assert_close(x_at(&s, 2.5), 73.0 / 24.0);
}

#[test]
fn a_time_reached_again_keeps_its_first_segment() {
    // Keys at 0, 1, 2, 3, 1.5, 2.5, 3.5, 4 (a run that goes back, as in the robot
    // scene): at 2.5 the segment from t = 2 to 3 is the first to end after it.
    let times = [0.0, 1.0, 2.0, 3.0, 1.5, 2.5, 3.5, 4.0];
    let xs = [0.0, 1.0, 2.0, 3.0, 10.0, 11.0, 12.0, 13.0];
    let keys: Vec<PositionKey> = times
        .iter()
        .zip(xs)
        .map(|(&t, x)| key(t, x, Tcb::default()))
        .collect();
    let s = PositionSpline::new(&keys);
    let first = PositionSpline::new(&keys[..5]);
    assert_close(x_at(&s, 2.5), x_at(&first, 2.5));
    // Past 3, the first segment ending later is the one from 2.5 to 3.5.
    assert_close(x_at(&s, 3.5), 12.0);
}

#[test]
fn rotation_eases_out_of_a_key_whose_neighbour_repeats_it() {
    // Keys about z at t = -1, 0, 1, 2: 0°, 0°, 90°, 90°, all T = C = B = 0. In
    // quaternions (half-angles about z): q0 = q1 = 0, q2 = q3 = π/4.
    // log(q1⁻¹ q2) = π/4 z. Out at q1: a1 = 1, Tout = (π/4)/2 + log(q0⁻¹ q1)/2 = π/8 z.
    // In at q2: a2 = 1, Tin = (π/4)/2 + log(q2⁻¹ q3)/2 = π/8 z.
    // a = q1 exp((Tout - π/4)/2) = half-angle -π/16; b = q2 exp((π/4 - Tin)/2) = π/4 + π/16.
    // All about z, so each slerp moves the half-angle linearly:
    //   slerp(u, q1, q2) = u π/4, slerp(u, a, b) = -π/16 + u 6π/16, and squad blends
    //   them at 2u(1 - u).
    // u = 1/2: both π/8, angle 45°. u = 1/4: π/16 and π/32, blended at 3/8:
    //   π/16 - 3/8 · π/32 = 1.625 π/32, angle 3.25 π/32 = 18.28125°.
    let s = RotationSpline::new(&[rot(-1.0, 0.0), rot(0.0, 0.0), rot(1.0, 90.0), rot(2.0, 90.0)]);
    let degrees = |t: f64| {
        let (angle, axis) = s.at(t);
        if angle != 0.0 {
            assert_close(axis[2], 1.0);
        }
        angle.to_degrees()
    };
    assert_close(degrees(0.0), 0.0);
    assert!((degrees(1.0) - 90.0).abs() < 1e-9);
    assert!((degrees(0.5) - 45.0).abs() < 1e-9);
    assert!((degrees(0.25) - 18.28125).abs() < 1e-9, "{}", degrees(0.25));
    // Clamped outside.
    assert_close(degrees(-0.5), 0.0);
    assert!((degrees(1.5) - 90.0).abs() < 1e-9);
    assert_close(s.at(0.25).0, 3.25 * PI / 32.0);
}

#[test]
fn rotation_takes_the_short_way() {
    // 0° to 270° about z: q2 = (cos 135°, sin 135° z) has a negative dot product with
    // q1 = 1, so it is negated to -90° about z and the curve turns the short way. With
    // the key after it at 270° again (q2⁻¹ q3 a full turn, whose log is 0), the
    // segment is symmetric: halfway, 45° about -z.
    let s = RotationSpline::new(&[rot(-1.0, 0.0), rot(0.0, 0.0), rot(1.0, 270.0), rot(2.0, 270.0)]);
    let (angle, axis) = s.at(0.5);
    assert!((angle.to_degrees() - 45.0).abs() < 1e-9, "{}", angle.to_degrees());
    assert_close(axis[2], -1.0);
}
