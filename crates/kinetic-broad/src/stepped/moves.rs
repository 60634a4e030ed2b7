//! Boxes over a step: whether two boxes moving at constant speeds meet within it, and the
//! typical move of a set of boxes (the frame a stepped grid sweeps them in).

use crate::aabb::Aabb;
use kinetic_core::{Real, Vec3};

/// The typical move of the boxes is taken from at most this many of them.
const SAMPLE: usize = 32;

/// The median move of the boxes `boxes` over the step, axis by axis, from at most
/// [`SAMPLE`] of them evenly spaced by index.
pub(crate) fn typical_move(boxes: &[Option<(Aabb, Vec3)>], sample: &mut Vec<Real>) -> Vec3 {
    let every = boxes.len().div_ceil(SAMPLE).max(1);
    let moves = || boxes.iter().step_by(every).flatten().map(|b| b.1);
    if moves().next().is_none() {
        return Vec3::ZERO;
    }
    let mut axis = |k: usize| {
        sample.clear();
        sample.extend(moves().map(|d| d[k]).filter(|x| x.is_finite()));
        if sample.is_empty() {
            return 0.0;
        }
        let mid = sample.len() / 2;
        *sample.select_nth_unstable_by(mid, Real::total_cmp).1
    };
    Vec3::new(axis(0), axis(1), axis(2))
}

/// Whether box `a` moving by `da` and box `b` moving by `db`, both at constant speed over the
/// step, overlap at some moment of it (touching counts; a little more, for the rounding).
pub(crate) fn meet_within_step(
    (Aabb { min: alo, max: ahi }, da): (Aabb, Vec3),
    (Aabb { min: blo, max: bhi }, db): (Aabb, Vec3),
) -> bool {
    // Most candidates overlap as the step starts: no allowance needed.
    if alo.cmple(bhi).all() && blo.cmple(ahi).all() {
        return true;
    }
    let d = da - db;
    // a.lo + d t <= b.hi and b.lo <= a.hi + d t, on each axis.
    let tol = 1e-9 * (alo.abs() + ahi.abs() + blo.abs() + bhi.abs() + d.abs());
    let (upper, lower) = (bhi - alo + tol, blo - ahi - tol);
    // Overlapping within the allowance as the step starts: no division.
    if upper.cmpge(Vec3::ZERO).all() && lower.cmple(Vec3::ZERO).all() {
        return true;
    }
    let (mut t0, mut t1): (Real, Real) = (0.0, 1.0);
    for k in 0..3 {
        let (upper, lower) = (upper[k], lower[k]);
        if d[k] == 0.0 {
            if upper < 0.0 || lower > 0.0 {
                return false;
            }
            continue;
        }
        let (x, y) = (upper / d[k], lower / d[k]);
        let (lo, hi) = if d[k] > 0.0 { (y, x) } else { (x, y) };
        t0 = t0.max(lo);
        t1 = t1.min(hi);
    }
    t0 <= t1
}

/// Whether boxes `x` and `y` of colliders `a` and `b` (each with the move expected of it
/// over the step) make a pair of the engine's: they overlap now, or meet within the step
/// swept by the moves the engine looks ahead (`ahead(i, d)`, [`crate::Engine::ahead`],
/// asked only of boxes that do not overlap now).
pub(crate) fn meet_ahead(
    (a, x): (u32, (Aabb, Vec3)),
    (b, y): (u32, (Aabb, Vec3)),
    ahead: &impl Fn(u32, Vec3) -> Vec3,
) -> bool {
    x.0.overlaps(&y.0) || meet_within_step((x.0, ahead(a, x.1)), (y.0, ahead(b, y.1)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit(at: Vec3) -> Aabb {
        Aabb::new(at, at + Vec3::ONE)
    }

    #[test]
    fn boxes_meet_within_the_step_by_their_motion_relative_to_each_other() {
        let (a, b) = (unit(Vec3::ZERO), unit(Vec3::new(3.0, 0.0, 0.0)));
        // Apart and still, or falling side by side: no.
        assert!(!meet_within_step((a, Vec3::ZERO), (b, Vec3::ZERO)));
        let fall = Vec3::new(0.0, -5.0, 0.0);
        assert!(!meet_within_step((a, fall), (b, fall)));
        // Closing the gap of 2 within the step: yes, whichever moves; half way: no.
        let right = Vec3::new(2.0, 0.0, 0.0);
        assert!(meet_within_step((a, right), (b, Vec3::ZERO)));
        assert!(meet_within_step((a, Vec3::ZERO), (b, -right)));
        assert!(!meet_within_step((a, right / 2.0), (b, Vec3::ZERO)));
        // Crossing on x while apart on y the whole step: no; a diagonal that meets: yes.
        let c = unit(Vec3::new(3.0, 2.0, 0.0));
        assert!(!meet_within_step(
            (a, Vec3::new(4.0, 0.0, 0.0)),
            (c, Vec3::ZERO)
        ));
        assert!(meet_within_step(
            (a, Vec3::new(4.0, 2.0, 0.0)),
            (c, Vec3::ZERO)
        ));
        // Touching counts.
        assert!(meet_within_step(
            (a, Vec3::ZERO),
            (unit(Vec3::X), Vec3::ZERO)
        ));
    }
}
