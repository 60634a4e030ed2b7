//! `wall`: a ball stays on the inner side of an axis-aligned wall.

use crate::math::{Real, Vec3};
use crate::poly::Poly;

/// The gap between a ball of radius `radius` (centre as local polynomial `[p, v, a / 2]`) and
/// the wall at `wall` across axis `axis`; `upper` for a wall bounding from above. Positive
/// while the ball is inside.
pub fn wall_gap(centre: &[Vec3; 3], radius: Real, axis: usize, wall: Real, upper: bool) -> Poly {
    let (p, v, h) = (centre[0][axis], centre[1][axis], centre[2][axis]);
    if upper {
        Poly::new(&[(wall - p) - radius, -v, -h])
    } else {
        Poly::new(&[(p - wall) - radius, v, h])
    }
}
