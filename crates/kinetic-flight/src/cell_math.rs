//! Box and grid arithmetic shared by the sweep, the grid and the loose grid: an object's box
//! about its centre, the polynomials of its ends in local time, when an end crosses a grid
//! line or leaves a region, the box a box sweeps, and the levels of a hierarchical grid.
//!
//! One home for each: the structures import these instead of keeping copies or reaching into
//! each other.

use kinetic_core::kds::roots::quadratic_roots;
use kinetic_core::kds::{Bodies, sign};
use kinetic_core::{Real, Vec3};

/// Inflation of the boxes, relative to the outer radius.
const INFLATE: Real = 1e-9;

/// Levels the middle 98% of the first objects' sizes are spread over, at most: the ratio of
/// one level's cells to the next is the power of two that gives this.
const BULK_LEVELS: Real = 3.0;
/// The widest ratio between levels.
const MAX_RATIO: Real = 16.0;

/// A box as offsets (min, max) from the object's centre.
pub(crate) type Ends = (Vec3, Vec3);

/// Object `id`'s box about its centre: its own axis-aligned box when it does not spin and its
/// geometry gives one, the box of its outer ball otherwise ([`kinetic_core::Body::local_box`]);
/// inflated.
pub(crate) fn box_ends(bodies: &Bodies, id: u32) -> Ends {
    let body = bodies[id as usize].as_ref().expect("a live object");
    let r = body.shape.outer_radius();
    let (lo, hi) = body.local_box();
    let pad = Vec3::splat(r * INFLATE);
    (lo - pad, hi + pad)
}

/// The widest side of object `id`'s box ([`box_ends`]).
pub(crate) fn box_width(bodies: &Bodies, id: u32) -> Real {
    let (lo, hi) = box_ends(bodies, id);
    (hi - lo).max_element()
}

/// A polynomial in local time `tau = t - now`: `[c0, c1, c2]`.
pub(crate) type Local = [Real; 3];

/// The sign of `c` just after local time 0.
pub(crate) fn sign_after(c: Local) -> i8 {
    c.iter().find(|&&x| x != 0.0).map_or(0, |&x| sign(x))
}

/// The first time after `now` at which `c - g` changes sign to `to` (+1 or -1), or `now`
/// itself when it is already on that side just after `now`; +infinity for never. The roots
/// are those of `kinetic_core::kds::roots` (the same closed forms, without building a polynomial).
pub(crate) fn crossing(c: Local, g: Real, to: i8, now: Real) -> Real {
    let p = [c[0] - g, c[1], c[2]];
    let s = sign_after(p);
    if s == to {
        return now;
    }
    if s == 0 {
        return Real::INFINITY;
    }
    // Just after `now` the sign is -to: the first root where it changes is the answer.
    if p[2] == 0.0 {
        let tau = -p[0] / p[1];
        return if tau > 0.0 && tau.is_finite() {
            now + tau
        } else {
            Real::INFINITY
        };
    }
    let mut roots = [(0.0, false); 4];
    let n = quadratic_roots(p[0], p[1], p[2], &mut roots);
    roots[..n]
        .iter()
        .find(|(_, touch)| !touch)
        .map_or(Real::INFINITY, |(tau, _)| now + tau)
}

/// When the box with ends `keys` (around `now`) first leaves the region `lo..hi` after
/// `now` (`now` if it is outside already or leaving).
pub(crate) fn exit_from(keys: &[(Local, Local); 3], lo: Vec3, hi: Vec3, now: Real) -> Real {
    let mut t = Real::INFINITY;
    for (k, (l, u)) in keys.iter().enumerate() {
        t = t
            .min(crossing(*l, lo[k], -1, now))
            .min(crossing(*u, hi[k], 1, now));
    }
    t
}

/// The box that a box sweeps over local times `0..=h`, widened by `margin` on every side; its
/// ends are `keys` (per axis, the lower and the upper end as polynomials in local time).
pub(crate) fn swept_box(keys: &[(Local, Local); 3], h: Real, margin: Real) -> (Vec3, Vec3) {
    let eval = |c: Local, t: Real| c[0] + (c[1] + c[2] * t) * t;
    let (mut lo, mut hi) = (Vec3::ZERO, Vec3::ZERO);
    for (k, (l, u)) in keys.iter().enumerate() {
        // The extremes over [0, h]: at its ends, or where the axis turns.
        let turn = if l[2] != 0.0 {
            -l[1] / (2.0 * l[2])
        } else {
            0.0
        };
        let ts = [0.0, h, if turn > 0.0 && turn < h { turn } else { 0.0 }];
        let lmin = ts
            .iter()
            .map(|&t| eval(*l, t))
            .fold(Real::INFINITY, Real::min);
        let umax = ts
            .iter()
            .map(|&t| eval(*u, t))
            .fold(Real::NEG_INFINITY, Real::max);
        lo[k] = lmin - margin;
        hi[k] = umax + margin;
    }
    (lo, hi)
}

/// The finest cells and the ratio between levels for objects of widths `w`: the smallest
/// width, and the power of two that spreads the middle 98% of the widths over about
/// [`BULK_LEVELS`] levels (at most [`MAX_RATIO`]). `None` without a positive finite width.
pub(crate) fn levels_for(w: impl Iterator<Item = Real>) -> Option<(Real, Real)> {
    let mut w: Vec<Real> = w.filter(|w| *w > 0.0 && w.is_finite()).collect();
    if w.is_empty() {
        return None;
    }
    w.sort_unstable_by(Real::total_cmp);
    let pick = |q: Real| w[((w.len() - 1) as Real * q).round() as usize];
    let octaves = (pick(0.99) / pick(0.01)).log2();
    let ratio = (2.0 as Real)
        .powf((octaves / BULK_LEVELS).ceil().max(1.0))
        .min(MAX_RATIO);
    Some((w[0], ratio))
}
