//! Numbers as nffrt writes them for people and in JSON: a count with its noun in
//! the right number (`1 tile`, `2 tiles`), and an `f32` as the shortest decimal that
//! reads back as the same `f32` (`1.2`, not the `1.2000000476837158` of its `f64`).

use std::fmt::Display;

/// `n` and its noun: `singular` for exactly one, `plural` otherwise (`0 tiles`,
/// `1 tile`, `1.5 pixels`).
pub fn count<N: Display + PartialEq + From<u8>>(n: N, singular: &str, plural: &str) -> String {
    let noun = if n == N::from(1) { singular } else { plural };
    format!("{n} {noun}")
}

/// The `f64` nearest the shortest decimal of `x` (what `{x}` prints): the value a
/// reader of the text would type, for JSON and Python, which hold `f64`. Converting
/// `x as f64` keeps the `f32`'s binary value, whose decimal is long (`1.2f32` is
/// 1.2000000476837158). Not finite values are returned as they are.
pub fn shortest_f64(x: f32) -> f64 {
    format!("{x}").parse().unwrap_or(x as f64)
}

/// [`shortest_f64`] of each coordinate.
pub fn shortest_f64s<const N: usize>(v: [f32; N]) -> [f64; N] {
    v.map(shortest_f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_take_the_noun_in_the_right_number() {
        assert_eq!(count(0u32, "tile", "tiles"), "0 tiles");
        assert_eq!(count(1usize, "mesh", "meshes"), "1 mesh");
        assert_eq!(count(2u64, "vertex", "vertices"), "2 vertices");
        assert_eq!(count(1.0f32, "pixel", "pixels"), "1 pixel");
        assert_eq!(count(1.5f32, "pixel", "pixels"), "1.5 pixels");
    }

    #[test]
    fn f32_values_read_as_their_shortest_decimal() {
        // The decimals typed in a scene file, which f32 cannot hold exactly.
        assert_eq!(1.2f32 as f64, 1.2000000476837158);
        assert_eq!(shortest_f64(1.2), 1.2);
        assert_eq!(shortest_f64(-1.6), -1.6);
        assert_eq!(shortest_f64(0.1), 0.1);
        // Exact values stay exact; the f32 just below 3.95 needs eight digits.
        assert_eq!(shortest_f64(40.0), 40.0);
        assert_eq!(shortest_f64(f32::from_bits(3.95f32.to_bits() - 1)), 3.9499998);
        assert_eq!(shortest_f64(f32::MAX), 3.4028235e38);
        assert!(shortest_f64(f32::NAN).is_nan());
        assert_eq!(shortest_f64(f32::INFINITY), f64::INFINITY);
        assert_eq!(shortest_f64s([0.3, 2.0]), [0.3, 2.0]);
    }
}
