//! 3 x 3 matrices in f64, as rows: what affine transforms (AFF's nodes, instances'
//! placements) need of their linear parts.

/// The cofactor matrix of `m`: its determinant times its inverse transpose (defined
/// for a singular `m` too).
pub fn cofactors(m: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let cof = |r0: usize, r1: usize, c0: usize, c1: usize| m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0];
    [
        [cof(1, 2, 1, 2), -cof(1, 2, 0, 2), cof(1, 2, 0, 1)],
        [-cof(0, 2, 1, 2), cof(0, 2, 0, 2), -cof(0, 2, 0, 1)],
        [cof(0, 1, 1, 2), -cof(0, 1, 0, 2), cof(0, 1, 0, 1)],
    ]
}

/// The determinant of `m`, given its cofactor matrix `cof`.
pub fn determinant(m: [[f64; 3]; 3], cof: [[f64; 3]; 3]) -> f64 {
    m[0][0] * cof[0][0] + m[0][1] * cof[0][1] + m[0][2] * cof[0][2]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A matrix times its cofactors' transpose is its determinant times the
    /// identity; the determinant of this one, expanded by hand along its first row,
    /// is 2 * 12 - 1 * 3.5 = 20.5.
    #[test]
    fn cofactors_transposed_invert_times_the_determinant() {
        let m = [[2.0, 1.0, 0.0], [1.0, 3.0, 1.0], [0.5, 0.0, 4.0]];
        let c = cofactors(m);
        let det = determinant(m, c);
        assert_eq!(det, 2.0 * 12.0 - 1.0 * 3.5 + 0.0);
        for (i, row) in m.iter().enumerate() {
            for (j, col) in c.iter().enumerate() {
                let p: f64 = row.iter().zip(col).map(|(a, b)| a * b).sum();
                assert!((p - if i == j { det } else { 0.0 }).abs() < 1e-12, "{i} {j}");
            }
        }
    }
}
