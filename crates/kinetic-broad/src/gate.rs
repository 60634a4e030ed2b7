//! The gate: whether two proxies, on their plans, can meet within a window, and when to ask
//! again.

use kinetic_core::{Body, Real, Shape, Vec3};

/// The gate's answer for a pair: whether the proxies can meet within the window, and when
/// to ask again with the same plans: for a pair that cannot meet, a time before which it
/// cannot (asked again once a window ends past it); for one that can, a time before which
/// its proxies surely still overlap (asked again once a window starts past it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Gate {
    pub(crate) meet: bool,
    pub(crate) wake: Real,
}

/// The gate for proxies `a` and `b` over the window from `t0` to `t1` ([`Gate`]): whether
/// they can meet ([`proxies_meet`]), and when to ask again ([`proxies_overlap_until`] for
/// proxies that can, [`apart_after`] for proxies that cannot).
pub(crate) fn proxies_gate(a: &Body, b: &Body, t0: Real, t1: Real) -> Gate {
    if proxies_meet(a, b, t0, t1) {
        Gate {
            meet: true,
            wake: proxies_overlap_until(a, b, t0),
        }
    } else {
        Gate {
            meet: false,
            wake: apart_after(a, b, t0, t1),
        }
    }
}

/// The rounding allowance for proxies `a` and `b` at positions `pa` and `pb`.
fn tolerance(a: &Body, b: &Body, pa: Vec3, pb: Vec3) -> Real {
    let reach = a.shape.outer_radius() + b.shape.outer_radius();
    1e-9 * (reach + pa.abs().max_element() + pb.abs().max_element())
}

/// The least time from `t0` in which the relative motion of `a` and `b` can cover `gap`:
/// the first tau with `|dv| tau + |da| tau^2 / 2 = gap`, a hair short for rounding. `None`
/// for a gap that is not positive (or NaN).
fn time_to_cover(a: &Body, b: &Body, t0: Real, gap: Real) -> Option<Real> {
    if gap.is_nan() || gap <= 0.0 {
        return None;
    }
    let d1 = (a.plan.velocity_at(t0) - b.plan.velocity_at(t0)).length();
    let d2 = ((a.plan.acceleration - b.plan.acceleration) * 0.5).length();
    let tau = 2.0 * gap / (d1 + (d1 * d1 + 4.0 * d2 * gap).sqrt());
    (!tau.is_nan()).then_some(tau * (1.0 - 1e-9))
}

/// A time before which proxies `a` and `b`, overlapping at `t0`, surely still overlap
/// (`t0` when they do not overlap at `t0`, or only by rounding): the depth of the overlap
/// less the most the relative velocity and acceleration can open. Balls by their centres'
/// distance, other shapes by their boxes'.
fn proxies_overlap_until(a: &Body, b: &Body, t0: Real) -> Real {
    let (pa, pb) = (a.plan.position_at(t0), b.plan.position_at(t0));
    let depth = match (&a.shape, &b.shape) {
        (Shape::Ball { radius: ra }, Shape::Ball { radius: rb }) => ra + rb - (pa - pb).length(),
        _ => {
            let ((alo, ahi), (blo, bhi)) = (swept_box(a, t0, t0), swept_box(b, t0, t0));
            (ahi - blo).min(bhi - alo).min_element()
        }
    };
    let depth = depth - 2.0 * tolerance(a, b, pa, pb);
    time_to_cover(a, b, t0, depth).map_or(t0, |tau| t0 + tau)
}

/// For proxies `a` and `b` that cannot meet between `t0` and `t1`, a time before which they
/// cannot meet, at least `t1`: beyond the window, a lower bound from the balls about them
/// (their own, or about their boxes), the gap now less the most the relative velocity and
/// acceleration can close.
fn apart_after(a: &Body, b: &Body, t0: Real, t1: Real) -> Real {
    let (pa, pb) = (a.plan.position_at(t0), b.plan.position_at(t0));
    // Two balls meet when their centres come within the sum of the radii; other shapes when
    // their boxes meet, and a box reaches as far as its corners (a ball's, r sqrt 3).
    let reach = match (&a.shape, &b.shape) {
        (Shape::Ball { radius: ra }, Shape::Ball { radius: rb }) => ra + rb,
        _ => box_reach(a) + box_reach(b),
    };
    let gap = (pa - pb).length() - reach - 2.0 * tolerance(a, b, pa, pb);
    time_to_cover(a, b, t0, gap).map_or(t1, |tau| t1.max(t0 + tau))
}

/// How far `body`'s box ([`Body::local_box`]) reaches from its centre.
fn box_reach(body: &Body) -> Real {
    let (lo, hi) = body.local_box();
    lo.abs().max(hi.abs()).length()
}

/// The time before which proxies `a` and `b`, on their plans, cannot meet, looking from `t0`:
/// minus infinity when they can meet between `t0` and `t1`, else [`apart_after`].
#[cfg(test)]
fn proxies_apart_until(a: &Body, b: &Body, t0: Real, t1: Real) -> Real {
    if proxies_meet(a, b, t0, t1) {
        Real::NEG_INFINITY
    } else {
        apart_after(a, b, t0, t1)
    }
}

/// Whether proxies `a` and `b`, on their plans, can meet between `t0` and `t1`: for two
/// balls, whether their centres come within the sum of their radii (conservatively: the
/// relative acceleration's part is bounded by its largest value over the window, and a
/// rounding allowance is added); for other shapes, whether the boxes they sweep over the
/// window overlap.
pub(crate) fn proxies_meet(a: &Body, b: &Body, t0: Real, t1: Real) -> bool {
    let (Shape::Ball { radius: ra }, Shape::Ball { radius: rb }) = (&a.shape, &b.shape) else {
        let ((alo, ahi), (blo, bhi)) = (swept_box(a, t0, t1), swept_box(b, t0, t1));
        let tol = 1e-9 * (a.shape.outer_radius() + b.shape.outer_radius())
            + 1e-12
                * alo
                    .abs()
                    .max(ahi.abs())
                    .max(blo.abs())
                    .max(bhi.abs())
                    .max_element();
        return (alo - bhi).max_element() <= tol && (blo - ahi).max_element() <= tol;
    };
    let (pa, pb) = (a.plan.position_at(t0), b.plan.position_at(t0));
    let d0 = pa - pb;
    let d1 = a.plan.velocity_at(t0) - b.plan.velocity_at(t0);
    let d2 = (a.plan.acceleration - b.plan.acceleration) * 0.5;
    let h = (t1 - t0).max(0.0);
    // Closest approach of the linear part over [0, h].
    let v2 = d1.length_squared();
    let s = if v2 > 0.0 {
        (-d0.dot(d1) / v2).clamp(0.0, h)
    } else {
        0.0
    };
    let gap = (d0 + d1 * s).length() - d2.length() * h * h;
    let reach = ra + rb;
    let tol = 1e-9 * (reach + pa.abs().max_element() + pb.abs().max_element());
    gap <= reach + tol
}

/// The box that `body` sweeps between `t0` and `t1`: its own box (when it does not spin and
/// its geometry gives one) or its outer ball's ([`Body::local_box`]), about each position on
/// the way.
fn swept_box(body: &Body, t0: Real, t1: Real) -> (Vec3, Vec3) {
    let plan = &body.plan;
    let (lo, hi) = body.local_box();
    let h = (t1 - t0).max(0.0);
    let (p0, v) = (plan.position_at(t0), plan.velocity_at(t0));
    let (mut plo, mut phi) = (p0, p0);
    for k in 0..3 {
        let (a, vk) = (plan.acceleration[k], v[k]);
        let at = |t: Real| p0[k] + (vk + 0.5 * a * t) * t;
        let turn = if a != 0.0 { -vk / a } else { 0.0 };
        for t in [h, if turn > 0.0 && turn < h { turn } else { 0.0 }] {
            plo[k] = plo[k].min(at(t));
            phi[k] = phi[k].max(at(t));
        }
    }
    (plo + lo, phi + hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use kinetic_core::FlightPlan;

    #[test]
    fn a_ball_and_a_box_meet_when_their_swept_boxes_overlap() {
        let slab = slab();
        // A ball of radius 0.5 falling from 3 at speed 2: its box reaches the slab's top at
        // t = 1.25.
        let ball = ball(
            0.5,
            FlightPlan::linear(Vec3::new(0.0, 3.0, 0.0), Vec3::new(0.0, -2.0, 0.0)),
        );
        assert!(!proxies_meet(&ball, &slab, 0.0, 1.2));
        assert!(proxies_meet(&ball, &slab, 0.0, 1.3));
        assert!(proxies_meet(&slab, &ball, 1.2, 1.3));
        // Apart over [0, 1.2], and no earlier than the outer balls allow after.
        let until = proxies_apart_until(&ball, &slab, 0.0, 1.2);
        assert!((1.2..1.25).contains(&until), "{until}");
        // Two balls closing at 1 from a gap of 3: apart until 3 (to rounding).
        let (a, b) = (ball_at(1.0, 0.0, 0.0), ball_at(1.0, 5.0, -1.0));
        let until = proxies_apart_until(&a, &b, 0.0, 1.0);
        assert!((until - 3.0).abs() < 1e-6, "{until}");
        assert_eq!(proxies_apart_until(&a, &b, 0.0, 3.5), Real::NEG_INFINITY);
    }

    #[test]
    fn a_ball_coming_at_a_boxs_corner_is_not_woken_too_late() {
        // A cube of half-width 0.5 at the origin and a ball of radius 1 coming along the
        // diagonal: their boxes meet corner to corner when the ball's centre is at
        // (1.5, 1.5, 1.5), at t = 3.5, before the two outer balls could touch.
        let cube = Body {
            shape: kinetic_flight::ConvexShape::cuboid(Vec3::splat(0.5))
                .unwrap()
                .into_shape(),
            plan: FlightPlan::at_rest(Vec3::ZERO),
        };
        let ball = ball(1.0, FlightPlan::linear(Vec3::splat(5.0), Vec3::splat(-1.0)));
        assert!(proxies_meet(&ball, &cube, 3.4, 3.6));
        for (a, b) in [(&ball, &cube), (&cube, &ball)] {
            let until = proxies_apart_until(a, b, 0.0, 1.0);
            assert!((1.0..=3.5).contains(&until), "{until}");
            assert!(!proxies_meet(a, b, 0.0, until));
        }
    }

    #[test]
    fn overlapping_proxies_surely_overlap_until_their_depth_can_open() {
        // Balls of radius 1, 1.5 apart (depth 0.5), parting at 1: still overlapping until
        // 0.5, and not for sure any later.
        let (a, b) = (ball_at(1.0, 0.0, 0.0), ball_at(1.0, 1.5, 1.0));
        let until = proxies_overlap_until(&a, &b, 0.0);
        assert!((until - 0.5).abs() < 1e-6, "{until}");
        assert_eq!(
            proxies_gate(&a, &b, 0.0, 0.1),
            Gate {
                meet: true,
                wake: until
            }
        );
        // Not overlapping now (only meeting later in the window): asked again next call.
        let c = ball_at(1.0, 2.5, -1.0);
        assert_eq!(proxies_overlap_until(&a, &c, 0.0), 0.0);
        assert!(proxies_gate(&a, &c, 0.0, 1.0).meet);
        // At rest together: overlapping for ever.
        let d = ball_at(1.0, 1.5, 0.0);
        assert_eq!(proxies_overlap_until(&a, &d, 0.0), Real::INFINITY);
        // A ball resting 0.2 deep in a slab, falling at 2 from rest: the boxes' depth 0.2
        // opens no sooner than sqrt(0.2) (acceleration 2 is 1 t^2).
        let slab = slab();
        let rising = ball(
            0.5,
            FlightPlan::accelerated(
                Vec3::new(0.0, 0.3, 0.0),
                Vec3::ZERO,
                Vec3::new(0.0, 2.0, 0.0),
            ),
        );
        let until = proxies_overlap_until(&rising, &slab, 0.0);
        assert!((until - 0.2f64.sqrt()).abs() < 1e-6, "{until}");
    }

    /// A resting slab 20 wide and 1 thick, its top at 0 (a ground).
    fn slab() -> Body {
        Body {
            shape: kinetic_flight::ConvexShape::cuboid(Vec3::new(10.0, 0.5, 10.0))
                .unwrap()
                .into_shape(),
            plan: FlightPlan::at_rest(Vec3::new(0.0, -0.5, 0.0)),
        }
    }

    fn ball_at(radius: Real, x: Real, v: Real) -> Body {
        ball(
            radius,
            FlightPlan::linear(Vec3::new(x, 0.0, 0.0), Vec3::new(v, 0.0, 0.0)),
        )
    }

    fn ball(radius: Real, plan: FlightPlan) -> Body {
        Body {
            shape: Shape::Ball { radius },
            plan,
        }
    }

    #[test]
    fn balls_meet_when_their_paths_come_within_the_sum_of_the_radii() {
        let at = |x: Real| FlightPlan::at_rest(Vec3::new(x, 0.0, 0.0));
        let moving =
            |x: Real, v: Real| FlightPlan::linear(Vec3::new(x, 0.0, 0.0), Vec3::new(v, 0.0, 0.0));
        // At rest 2 apart: radii 1 + 0.99 miss, 1 + 1 touch.
        assert!(!proxies_meet(
            &ball(1.0, at(0.0)),
            &ball(0.99, at(2.0)),
            0.0,
            1.0
        ));
        assert!(proxies_meet(
            &ball(1.0, at(0.0)),
            &ball(1.0, at(2.0)),
            0.0,
            1.0
        ));
        // Closing at 1 per unit time from 3 apart: they touch at t = 1.
        let (a, b) = (ball(1.0, at(0.0)), ball(1.0, moving(3.0, -1.0)));
        assert!(!proxies_meet(&a, &b, 0.0, 0.99));
        assert!(proxies_meet(&a, &b, 0.0, 1.01));
        // Passing through each other within the window, apart at both ends.
        let b = ball(0.1, moving(-5.0, 10.0));
        assert!(proxies_meet(&ball(0.1, at(0.0)), &b, 0.0, 1.0));
        assert!(!proxies_meet(&ball(0.1, at(0.0)), &b, 0.0, 0.4));
        // Falling onto a resting ball: the relative acceleration is bounded over the window.
        let fall = |t: Real| {
            FlightPlan::accelerated(
                Vec3::new(0.0, 3.0, 0.0),
                Vec3::ZERO,
                Vec3::new(0.0, -2.0, 0.0),
            )
            .starting_at(t)
        };
        let rest = ball(1.0, at(0.0));
        assert!(proxies_meet(&rest, &ball(1.0, fall(0.0)), 0.0, 1.0));
        assert!(!proxies_meet(&rest, &ball(1.0, fall(0.0)), 0.0, 0.5));
        // Other shapes: always (their boxes overlap).
        let cube = Body {
            shape: Shape::Ball { radius: 1.0 },
            plan: at(100.0),
        };
        let mut other = cube.clone();
        other.shape = kinetic_flight::ConvexShape::cuboid(Vec3::ONE)
            .unwrap()
            .into_shape();
        assert!(proxies_meet(&cube, &other, 0.0, 1.0));
    }
}
