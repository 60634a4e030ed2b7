//! The numeric types: kinetic math is `f64` throughout (contact times to 1e-7 relative), and
//! the roundings to whole numbers that grids take without a call into the C library.

/// The scalar type.
pub type Real = f64;
/// A rotation.
pub use glam::DQuat as Quat;
/// A point or vector in 3-space.
pub use glam::DVec3 as Vec3;

/// Added to and taken off a number below 2^51 in magnitude, rounds it to the nearest integer
/// (ties to even): 1.5 * 2^52.
pub const ROUNDING: Real = 6_755_399_441_055_744.0;

/// `x` rounded to the nearest integer (ties to even), for magnitudes below 2^51.
#[inline]
pub fn round_near(x: Real) -> Real {
    (x + ROUNDING) - ROUNDING
}

/// The floor of `x`, for magnitudes below 2^51.
#[inline]
fn floor_small(x: Real) -> Real {
    let near = round_near(x);
    near - if near > x { 1.0 } else { 0.0 }
}

/// `floor(x)` as an integer, saturating (NaN gives 0), as `x.floor() as i64` gives it: the
/// floor taken in floating point and converted once (converting back to compare, the plain
/// way, waits on the previous conversion's register).
#[inline]
pub fn floor_int(x: Real) -> i64 {
    if x.abs() < ROUNDING / 3.0 {
        floor_small(x) as i64
    } else {
        x.floor() as i64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn floor_int_is_the_floor_as_an_integer() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let mut xs = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.5,
            -1.5,
            2.5,
            -2.5,
            1.0 - Real::EPSILON,
            -1.0 + Real::EPSILON / 2.0,
            ROUNDING / 3.0,
            -ROUNDING / 3.0,
            ROUNDING / 3.0 - 0.5,
            -ROUNDING / 3.0 + 0.5,
            1e300,
            -1e300,
            Real::INFINITY,
            Real::NEG_INFINITY,
            Real::NAN,
            Real::MIN_POSITIVE,
            -Real::MIN_POSITIVE,
        ];
        for k in 0..10_000 {
            let scale = 10f64.powi(k % 20 - 4);
            xs.push(rng.random_range(-0.5..0.5) * scale);
        }
        for x in xs {
            assert_eq!(floor_int(x), x.floor() as i64, "{x}");
        }
        assert_eq!(round_near(2.5), 2.0);
        assert_eq!(round_near(-3.5), -4.0);
    }
}
