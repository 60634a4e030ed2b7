//! The broad phases' boxes: one axis-aligned box type in double precision, its twin rounded
//! outwards to single precision for fast overlap tests, and the tests both halves share.

use glam::Vec3A;
use kinetic_core::{Real, Vec3};

/// An axis-aligned box `(min, max)`.
pub(crate) type Aabb = (Vec3, Vec3);

/// A box rounded outwards to single precision, `[min, max]`, in 16-byte vectors that one
/// instruction compares.
pub(crate) type AabbF32 = [Vec3A; 2];

/// Box `b` rounded outwards to single precision: each end moved out by more than half a
/// single-precision step before it is rounded to the nearest.
pub(crate) fn to_f32(b: &Aabb) -> AabbF32 {
    let out = |x: Vec3| x.abs() * (f32::EPSILON as Real) + f32::MIN_POSITIVE as Real;
    let (lo, hi) = (b.0 - out(b.0), b.1 + out(b.1));
    [
        Vec3A::new(lo.x as f32, lo.y as f32, lo.z as f32),
        Vec3A::new(hi.x as f32, hi.y as f32, hi.z as f32),
    ]
}

/// Box `b`'s widest side (NaN for a box with a NaN side).
pub(crate) fn width(b: &AabbF32) -> f32 {
    let w = b[1] - b[0];
    if w.is_nan() {
        return f32::NAN;
    }
    w.max_element()
}

/// Whether two boxes overlap (touching counts).
pub(crate) fn overlap(a: &AabbF32, b: &AabbF32) -> bool {
    a[0].cmple(b[1]).all() & b[0].cmple(a[1]).all()
}

/// Whether boxes `a` and `b` overlap as the grid finds them: rounded outwards to single
/// precision, touching counting.
pub(crate) fn overlapping(a: &Aabb, b: &Aabb) -> bool {
    overlap(&to_f32(a), &to_f32(b))
}

/// A small deterministic generator for the tests (a linear congruential step): a number in
/// `[0, 1)`.
#[cfg(test)]
pub(crate) fn next(s: &mut u64) -> Real {
    *s = s
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*s >> 11) as Real / (1u64 << 53) as Real
}

/// A point of the unit cube from the same generator.
#[cfg(test)]
pub(crate) fn next_vec(s: &mut u64) -> Vec3 {
    Vec3::new(next(s), next(s), next(s))
}
