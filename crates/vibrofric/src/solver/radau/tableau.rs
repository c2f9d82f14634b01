//! The coefficients of the 3-stage Radau IIA method of order 5 (Hairer & Wanner, *Solving
//! ODEs II*, §IV.5 and §IV.8): nodes `C`, weights `B`, the Butcher matrix `A`, the dense-output
//! and error-estimate constants, and the eigen-decomposition `T·Λ·T⁻¹` of `A⁻¹` that splits the
//! Newton system into one real and one complex system. Constants only, no logic.

pub(crate) const SQ6: f64 = 2.449_489_742_783_178;
/// Collocation nodes.
pub const C: [f64; 3] = [(4.0 - SQ6) / 10.0, (4.0 + SQ6) / 10.0, 1.0];
/// Quadrature weights (= last row of the Butcher matrix: the method is stiffly accurate).
pub const B: [f64; 3] = [(16.0 - SQ6) / 36.0, (16.0 + SQ6) / 36.0, 1.0 / 9.0];
/// Butcher matrix.
pub(crate) const A: [[f64; 3]; 3] = [
    [
        (88.0 - 7.0 * SQ6) / 360.0,
        (296.0 - 169.0 * SQ6) / 1800.0,
        (-2.0 + 3.0 * SQ6) / 225.0,
    ],
    [
        (296.0 + 169.0 * SQ6) / 1800.0,
        (88.0 + 7.0 * SQ6) / 360.0,
        (-2.0 - 3.0 * SQ6) / 225.0,
    ],
    [B[0], B[1], B[2]],
];

pub(crate) const C1M1: f64 = C[0] - 1.0;
pub(crate) const C2M1: f64 = C[1] - 1.0;
pub(crate) const C1MC2: f64 = C[0] - C[1];
/// Coefficients of the embedded error estimate.
pub(crate) const DD1: f64 = -(13.0 + 7.0 * SQ6) / 3.0;
pub(crate) const DD2: f64 = (-13.0 + 7.0 * SQ6) / 3.0;
pub(crate) const DD3: f64 = -1.0 / 3.0;
/// Real eigenvalue of the inverse Butcher matrix: 30/(6 + 81^(1/3) − 9^(1/3)).
pub(crate) const U1: f64 = 3.637_834_252_744_496;

/// Complex eigenvalue `ALPH ± i·BETA` of the inverse Butcher matrix.
pub(crate) const ALPH: f64 = 2.681_082_873_627_752;
pub(crate) const BETA: f64 = 3.050_430_199_247_411;
/// Eigenvectors `T` of the inverse Butcher matrix (`A⁻¹·T = T·diag(U1, [[ALPH, −BETA],
/// [BETA, ALPH]])`, RADAU5's normalisation) and `TI = T⁻¹`: they split the Newton system
/// into one real and one complex `N×N` system.
pub(crate) const T: [[f64; 3]; 3] = [
    [
        9.123_239_487_089_294e-2,
        -0.141_255_295_020_954_2,
        -3.002_919_410_514_742_4e-2,
    ],
    [
        0.241_717_932_707_107,
        0.204_129_352_293_799_9,
        0.382_942_112_757_261_9,
    ],
    [0.966_048_182_615_093, 1.0, 0.0],
];
pub(crate) const TI: [[f64; 3]; 3] = [
    [
        4.325_579_890_063_155,
        0.339_199_251_815_809_9,
        0.541_770_539_935_874_9,
    ],
    [
        -4.178_718_591_551_905,
        -0.327_682_820_761_062_4,
        0.476_623_554_500_550_5,
    ],
    [
        -0.502_872_634_945_786_9,
        2.571_926_949_855_605,
        -0.596_039_204_828_224_9,
    ],
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transformation_constants_diagonalise_the_inverse_butcher_matrix() {
        let a = nalgebra::Matrix3::from_fn(|i, j| A[i][j]);
        let ainv = a.try_inverse().unwrap();
        let t = nalgebra::Matrix3::from_fn(|i, j| T[i][j]);
        let ti = nalgebra::Matrix3::from_fn(|i, j| TI[i][j]);
        let lambda = nalgebra::Matrix3::new(U1, 0.0, 0.0, 0.0, ALPH, -BETA, 0.0, BETA, ALPH);
        assert!((ti * t - nalgebra::Matrix3::identity()).amax() < 1e-14);
        assert!(
            (ainv * t - t * lambda).amax() < 1e-13,
            "{}",
            ainv * t - t * lambda
        );
    }
}
