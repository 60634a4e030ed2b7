//! `ball_ball_disjoint`: two balls do not overlap.

use crate::math::{Real, Vec3};
use crate::poly::Poly;

/// `|c_a(tau) - c_b(tau)|^2 - threshold2`, positive while the balls are apart, zero when they
/// touch. `a` and `b` are the centres as local polynomials `[p, v, a / 2]` (see
/// [`crate::FlightPlan::local_coefficients`]); `threshold2` is `(r_a + r_b)^2` in free space
/// and `4 r_a r_b` for balls rolling on a plane (centres replaced by tangency points).
/// Degree 2 for coasting balls, 4 when their accelerations differ.
///
/// ```
/// # use kinetic_core::{kds::certificates::ball_ball_gap, Vec3, kds::roots::first_sign_change};
/// let a = [Vec3::ZERO, Vec3::X, Vec3::ZERO];
/// let b = [Vec3::new(10.0, 0.0, 0.0), Vec3::ZERO, Vec3::ZERO];
/// let gap = ball_ball_gap(&a, &b, 4.0); // radii summing to 2
/// assert_eq!(first_sign_change(&gap), Some(8.0));
/// ```
#[inline]
pub fn ball_ball_gap(a: &[Vec3; 3], b: &[Vec3; 3], threshold2: Real) -> Poly {
    let d0 = a[0] - b[0];
    let d1 = a[1] - b[1];
    let d2 = a[2] - b[2];
    Poly {
        c: [
            d0.dot(d0) - threshold2,
            2.0 * d0.dot(d1),
            d1.dot(d1) + 2.0 * d0.dot(d2),
            2.0 * d1.dot(d2),
            d2.dot(d2),
        ],
    }
}
