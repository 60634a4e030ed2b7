//! The key of a pair of objects: its two ids in order, the lower first, so that `(a, b)` and
//! `(b, a)` are one pair. Every structure and table that files pairs by their ids uses these.

/// The pair of `a` and `b` in order: the lower id first.
#[inline]
pub fn ordered_pair(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// The pair of `a` and `b` in one word: the lower id in the high 32 bits, the higher in the
/// low 32, so that keys sort as the ordered pairs do.
#[inline]
pub fn pair_key(a: u32, b: u32) -> u64 {
    (u64::from(a.min(b)) << 32) | u64::from(a.max(b))
}
