//! The first pass of a prediction over a batch of neighbours: each pair's gap coefficients,
//! with no branch that depends on the pair, keeping the few pairs that may fail before the
//! bound. A sphere whose plan starts now (after a collision: most predictions) takes its
//! pairs two at a time in SSE2 lanes, each lane with the scalar pass's operations in order.

use super::{Motion, PeriodicSpheres};
use crate::math::{Real, Vec3};

impl PeriodicSpheres {
    /// The first pass over a batch of `m`'s neighbours: writes to `kept` the pairs that
    /// [`pair_due`](super::predict::pair_due) would not turn away at once (apart, and parting or failing after `bound`),
    /// and returns how many. Each pair's gap is taken around the later of the two plans'
    /// starts, as `pair_due` takes it; `STARTED_NOW` says that `m`'s plan starts now, so that
    /// every pair's gap is taken around now.
    #[inline]
    pub(super) fn sift<const STARTED_NOW: bool>(
        &self,
        m: &Motion,
        here: Vec3,
        bound: Real,
        batch: &[u32],
        kept: &mut [Kept],
    ) -> usize {
        let now = self.now;
        let motion = &self.motion[..];
        let half = self.period.half_side;
        // The starts first, in a loop of loads alone: the neighbours' motions are fetched
        // together rather than one pair at a time.
        let mut starts = [0.0; BATCH];
        for (start, &k) in starts.iter_mut().zip(batch) {
            *start = motion[k as usize].t0;
        }
        let kept = &mut kept[..batch.len()];
        let mut len = 0;
        for (&k, &t0) in batch.iter().zip(&starts) {
            let mb = &motion[k as usize];
            let mut d = here - mb.at(now);
            let near = (d.x.abs() < half.x) & (d.y.abs() < half.y) & (d.z.abs() < half.z);
            let mut shift = Vec3::ZERO;
            if !near {
                shift = self.period.nearest(d);
                d -= shift;
            }
            let reach = m.radius + mb.radius;
            let threshold2 = reach * reach;
            let v = m.velocity - mb.velocity;
            let (base, c0, c1, gap_now);
            if STARTED_NOW {
                base = now;
                c0 = d.dot(d) - threshold2;
                c1 = 2.0 * d.dot(v);
                gap_now = c0;
            } else {
                let later = if m.t0 > t0 { m.t0 } else { t0 };
                base = if later < now { later } else { now };
                let db = if base == now {
                    d
                } else {
                    (m.at(base) - mb.at(base)) - shift
                };
                c0 = db.dot(db) - threshold2;
                c1 = 2.0 * db.dot(v);
                gap_now = if base == now {
                    c0
                } else {
                    d.dot(d) - threshold2
                };
            }
            let apart = (c0 > 0.0) & (gap_now > 0.0);
            let ahead = bound - base;
            let after_bound =
                ahead.is_finite() & (c0 > -c1 * (ahead * (1.0 + 1e-9) + bound.abs() * 1e-15));
            let parting = (c0 <= 0.0) & (c1 > 0.0) & (base == now);
            let none = parting | (apart & ((c1 >= 0.0) | after_bound));
            kept[len] = Kept {
                k,
                c0,
                c1,
                base,
                clear: apart,
            };
            len += usize::from(!none);
        }
        len
    }

    /// [`Self::sift`] for a sphere whose plan starts now, two pairs at a time in the two
    /// lanes of SSE2 registers: each lane takes the scalar pass's operations in its order, so
    /// the coefficients are the same to the bit.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "sse2")]
    pub(super) fn sift_now(
        &self,
        m: &Motion,
        here: Vec3,
        bound: Real,
        batch: &[u32],
        kept: &mut [Kept],
    ) -> usize {
        use std::arch::x86_64::*;
        let now = self.now;
        let motion = &self.motion[..];
        let p = &self.period;
        let splat = _mm_set1_pd;
        let sign = splat(-0.0);
        let abs = |x: __m128d| _mm_andnot_pd(sign, x);
        let (zero, two, now2) = (splat(0.0), splat(2.0), splat(now));
        let here = [splat(here.x), splat(here.y), splat(here.z)];
        let half = [
            splat(p.half_side.x),
            splat(p.half_side.y),
            splat(p.half_side.z),
        ];
        let side = [splat(p.side.x), splat(p.side.y), splat(p.side.z)];
        let inv = [
            splat(p.inv_side.x),
            splat(p.inv_side.y),
            splat(p.inv_side.z),
        ];
        let mv = [
            splat(m.velocity.x),
            splat(m.velocity.y),
            splat(m.velocity.z),
        ];
        let radius = splat(m.radius);
        let magic = splat(6_755_399_441_055_744.0); // 1.5 * 2^52: rounds to integers
        // As the scalar pass: a pair failing after the bound is turned away.
        let ahead = bound - now;
        let finite = ahead.is_finite();
        let reach_bound = splat(ahead * (1.0 + 1e-9) + bound.abs() * 1e-15);
        let mut len = 0;
        for pair in batch.chunks(2) {
            let (k0, k1) = (pair[0], *pair.last().unwrap_or(&pair[0]));
            let (a, b) = (&motion[k0 as usize], &motion[k1 as usize]);
            let lane = |x: Real, y: Real| _mm_set_pd(y, x);
            let dt = _mm_sub_pd(now2, lane(a.t0, b.t0));
            let pos = [
                lane(a.position.x, b.position.x),
                lane(a.position.y, b.position.y),
                lane(a.position.z, b.position.z),
            ];
            let vel = [
                lane(a.velocity.x, b.velocity.x),
                lane(a.velocity.y, b.velocity.y),
                lane(a.velocity.z, b.velocity.z),
            ];
            let mut d = [zero; 3];
            let mut near = _mm_castsi128_pd(_mm_set1_epi64x(-1));
            for x in 0..3 {
                d[x] = _mm_sub_pd(here[x], _mm_add_pd(pos[x], _mm_mul_pd(vel[x], dt)));
                near = _mm_and_pd(near, _mm_cmplt_pd(abs(d[x]), half[x]));
            }
            if _mm_movemask_pd(near) != 3 {
                for x in 0..3 {
                    let whole = _mm_sub_pd(_mm_add_pd(_mm_mul_pd(d[x], inv[x]), magic), magic);
                    let shifted = _mm_sub_pd(d[x], _mm_mul_pd(whole, side[x]));
                    d[x] = _mm_or_pd(_mm_and_pd(near, d[x]), _mm_andnot_pd(near, shifted));
                }
            }
            let reach = _mm_add_pd(radius, lane(a.radius, b.radius));
            let threshold2 = _mm_mul_pd(reach, reach);
            let dot = |u: &[__m128d; 3], v: &[__m128d; 3]| {
                _mm_add_pd(
                    _mm_add_pd(_mm_mul_pd(u[0], v[0]), _mm_mul_pd(u[1], v[1])),
                    _mm_mul_pd(u[2], v[2]),
                )
            };
            let w = [
                _mm_sub_pd(mv[0], vel[0]),
                _mm_sub_pd(mv[1], vel[1]),
                _mm_sub_pd(mv[2], vel[2]),
            ];
            let c0 = _mm_sub_pd(dot(&d, &d), threshold2);
            let c1 = _mm_mul_pd(two, dot(&d, &w));
            let apart = _mm_cmpgt_pd(c0, zero);
            let late = _mm_cmpgt_pd(c0, _mm_mul_pd(_mm_xor_pd(c1, sign), reach_bound));
            let after_bound = if finite { late } else { zero };
            let parting = _mm_and_pd(_mm_cmple_pd(c0, zero), _mm_cmpgt_pd(c1, zero));
            let none = _mm_or_pd(
                parting,
                _mm_and_pd(apart, _mm_or_pd(_mm_cmpge_pd(c1, zero), after_bound)),
            );
            let keep = !_mm_movemask_pd(none) & if pair.len() == 2 { 3 } else { 1 };
            let apart = _mm_movemask_pd(apart);
            let lanes = |x: __m128d| [_mm_cvtsd_f64(x), _mm_cvtsd_f64(_mm_unpackhi_pd(x, x))];
            let (c0s, c1s) = (lanes(c0), lanes(c1));
            for (j, &k) in pair.iter().enumerate() {
                kept[len] = Kept {
                    k,
                    c0: c0s[j],
                    c1: c1s[j],
                    base: now,
                    clear: apart >> j & 1 != 0,
                };
                len += (keep >> j & 1) as usize;
            }
        }
        len
    }

    #[cfg(not(target_arch = "x86_64"))]
    #[inline]
    pub(super) fn sift_now(
        &self,
        m: &Motion,
        here: Vec3,
        bound: Real,
        batch: &[u32],
        kept: &mut [Kept],
    ) -> usize {
        self.sift::<true>(m, here, bound, batch, kept)
    }
}

/// Neighbours sifted in one batch.
pub(super) const BATCH: usize = 32;

/// A pair kept by the first pass: the neighbour, the first two coefficients of its gap
/// `c0 + c1 tau + c2 tau^2` around `base`, and whether the two are clear of each other at
/// `base` and now.
#[derive(Clone, Copy, Debug)]
pub(super) struct Kept {
    pub(super) k: u32,
    pub(super) c0: Real,
    pub(super) c1: Real,
    pub(super) base: Real,
    pub(super) clear: bool,
}

impl Kept {
    pub(super) const NONE: Kept = Kept {
        k: 0,
        c0: 0.0,
        c1: 0.0,
        base: 0.0,
        clear: false,
    };
}
