//! `order`: item `x` stays at or below item `y` in a 1-D sorted list.

use crate::math::Real;
use crate::poly::Poly;
use crate::roots::roots_after_zero;

/// A scalar key that moves as a polynomial of degree at most 2:
/// `k(t) = k0 + k1 (t - t0) + k2 (t - t0)^2`, for instance one coordinate of a flight plan
/// plus an offset (a box endpoint).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct ScalarKey {
    /// Reference time.
    pub t0: Real,
    /// Value at `t0`.
    pub k0: Real,
    /// Rate at `t0`.
    pub k1: Real,
    /// Half the (constant) second derivative.
    pub k2: Real,
}

impl ScalarKey {
    /// A key moving as `value + rate (t - t0) + half_accel (t - t0)^2`.
    pub fn new(t0: Real, value: Real, rate: Real, half_accel: Real) -> ScalarKey {
        ScalarKey {
            t0,
            k0: value,
            k1: rate,
            k2: half_accel,
        }
    }

    /// A linear key `value + rate t`.
    pub fn linear(value: Real, rate: Real) -> ScalarKey {
        ScalarKey::new(0.0, value, rate, 0.0)
    }

    /// Coordinate `axis` of a flight plan's centre, plus `offset`.
    pub fn from_plan(plan: &crate::FlightPlan, axis: usize, offset: Real) -> ScalarKey {
        ScalarKey::new(
            plan.t0,
            plan.position[axis] + offset,
            plan.velocity[axis],
            0.5 * plan.acceleration[axis],
        )
    }

    /// The value at time `t`.
    #[inline]
    pub fn value_at(&self, t: Real) -> Real {
        let d = t - self.t0;
        self.k0 + (self.k1 + self.k2 * d) * d
    }

    /// The key as `[value, rate, half accel]` around time `now`. Comparing these
    /// lexicographically orders keys "just after `now`", exactly and transitively.
    #[inline]
    pub fn local(&self, now: Real) -> [Real; 3] {
        let d = now - self.t0;
        [
            self.k0 + (self.k1 + self.k2 * d) * d,
            self.k1 + 2.0 * self.k2 * d,
            self.k2,
        ]
    }
}

/// Whether key `a` lies strictly above key `b` just after the moment both are expressed at.
#[inline]
pub fn above_just_after(a: &[Real; 3], b: &[Real; 3]) -> bool {
    for i in 0..3 {
        if a[i] != b[i] {
            return a[i] > b[i];
        }
    }
    false
}

/// The certificate `k_y - k_x >= 0` for two neighbours of a sorted list, with its failure
/// times cached (CGAL style): when the two swap, the reversed certificate fails at the
/// polynomial's next sign change, so a swap never re-fires at the same root.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrderCertificate {
    /// Absolute times at which `k_y - k_x` changes sign, ascending.
    changes: [Real; 2],
    /// How many of `changes` there are.
    n: u8,
    /// Index into `changes` of the next failure; `IMMEDIATE` when it fails at `made`.
    next: u8,
    /// When the certificate was made.
    made: Real,
}

const IMMEDIATE: u8 = u8::MAX;

impl OrderCertificate {
    /// The certificate for `x` below `y`, made at `now` from their local keys.
    #[inline]
    pub fn new(x: &[Real; 3], y: &[Real; 3], now: Real) -> OrderCertificate {
        let p = Poly::new(&[y[0] - x[0], y[1] - x[1], y[2] - x[2]]);
        let mut cert = OrderCertificate {
            changes: [Real::INFINITY; 2],
            n: 0,
            next: 0,
            made: now,
        };
        for r in roots_after_zero(&p).iter().filter(|r| r.is_sign_change()) {
            if (cert.n as usize) < 2 {
                cert.changes[cert.n as usize] = now + r.tau;
                cert.n += 1;
            }
        }
        if p.sign_just_after_zero() < 0 {
            cert.next = IMMEDIATE;
        }
        cert
    }

    /// When it fails next (+infinity for never).
    #[inline]
    pub fn failure_time(&self) -> Real {
        match self.next {
            IMMEDIATE => self.made,
            i if i < self.n => self.changes[i as usize],
            _ => Real::INFINITY,
        }
    }

    /// The certificate of the same two items after they swapped at the failure time.
    #[inline]
    pub fn swapped(&self) -> OrderCertificate {
        let next = match self.next {
            IMMEDIATE => 0,
            i => i.saturating_add(1),
        };
        OrderCertificate { next, ..*self }
    }
}
