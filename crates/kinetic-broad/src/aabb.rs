//! The broad phase's boxes: one axis-aligned box type in double precision, shared by both
//! halves and the engines ([`crate::Engine::bounds`]), its twin rounded outwards to single
//! precision for the stepped grid's fast overlap tests, and the tests both halves share.

use glam::Vec3A;
use kinetic_core::{Real, Vec3};

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Its least corner.
    pub min: Vec3,
    /// Its greatest corner.
    pub max: Vec3,
}

impl Aabb {
    /// The box from `min` to `max`.
    #[inline]
    pub const fn new(min: Vec3, max: Vec3) -> Aabb {
        Aabb { min, max }
    }

    /// The box that holds everything.
    pub const EVERYWHERE: Aabb = Aabb::new(Vec3::NEG_INFINITY, Vec3::INFINITY);

    /// The box of half-widths `half` about `centre`.
    #[inline]
    pub fn about(centre: Vec3, half: Vec3) -> Aabb {
        Aabb::new(centre - half, centre + half)
    }

    /// Its centre.
    #[inline]
    pub fn centre(&self) -> Vec3 {
        (self.min + self.max) / 2.0
    }

    /// Its widest side.
    #[inline]
    pub fn widest(&self) -> Real {
        (self.max - self.min).max_element()
    }

    /// The box it sweeps moving by `d`.
    #[inline]
    pub fn swept(&self, d: Vec3) -> Aabb {
        Aabb::new(self.min + d.min(Vec3::ZERO), self.max + d.max(Vec3::ZERO))
    }

    /// The box grown by `by` on every side.
    #[inline]
    pub fn grown(&self, by: Vec3) -> Aabb {
        Aabb::new(self.min - by, self.max + by)
    }

    /// Whether it overlaps box `other` (touching counts).
    #[inline]
    pub fn overlaps(&self, other: &Aabb) -> bool {
        self.min.cmple(other.max).all() && other.min.cmple(self.max).all()
    }

    /// Whether it lies inside box `outer`.
    #[inline]
    pub fn inside(&self, outer: &Aabb) -> bool {
        outer.min.cmple(self.min).all() && self.max.cmple(outer.max).all()
    }
}

/// A box rounded outwards to single precision, `[min, max]`, in 16-byte vectors that one
/// instruction compares.
pub(crate) type AabbF32 = [Vec3A; 2];

/// Box `b` rounded outwards to single precision: each end moved out by more than half a
/// single-precision step before it is rounded to the nearest.
pub(crate) fn to_f32(b: &Aabb) -> AabbF32 {
    let out = |x: Vec3| x.abs() * (f32::EPSILON as Real) + f32::MIN_POSITIVE as Real;
    let (lo, hi) = (b.min - out(b.min), b.max + out(b.max));
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
