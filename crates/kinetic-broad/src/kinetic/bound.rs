//! What the structures see of an engine's collider: a proxy that holds it, and a flight plan.
//!
//! - A collider on a moving (dynamic or kinematic) body is a ball about the body's centre of
//!   mass that holds the collider at every orientation, grown by the engine's contact margins
//!   and a slack. Spin never moves it, so the plan is the centre of mass alone: a polynomial
//!   of degree at most 2 (rest, coasting, constant acceleration).
//! - A collider on a fixed body (or on none) is its own axis-aligned box, grown the same way,
//!   at rest. In the guards structure it is the ball about that box.

use crate::Key;
use kinetic_core::{FlightPlan, Real, Vec3};

/// How a collider is held.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bound {
    /// On a fixed body or none: a box `(min, max)`, at rest.
    Fixed {
        /// The box's least corner, margins included.
        min: Vec3,
        /// The box's greatest corner, margins included.
        max: Vec3,
    },
    /// On a moving body: a ball of `radius` about the body's centre of mass, which the body
    /// must keep within `slack` of its plan.
    Moving {
        /// The body's key.
        body: Key,
        /// The ball's radius: the collider's reach from the centre of mass, the margins and
        /// the slack.
        radius: Real,
        /// How far the body may stray from its plan.
        slack: Real,
    },
}

/// How much a moving body may stray from its plan before it is re-planned: `fraction` of its
/// collider's reach, at least `min` length units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slack {
    /// The share of the collider's reach.
    pub fraction: Real,
    /// The least slack, in length units.
    pub min: Real,
}

impl Slack {
    /// No slack: a hold read only for which body it rides ([`crate::Engine::collider_on_boxes`]).
    pub const NONE: Slack = Slack {
        fraction: 0.0,
        min: 0.0,
    };
}

impl Bound {
    /// The hold for a collider on a moving body `body`: the collider reaches `reach` from the
    /// body's centre of mass, and the engine's contact margins add `margin`.
    pub fn moving(body: Key, reach: Real, margin: Real, slack: Slack) -> Bound {
        let slack = (slack.fraction * reach).max(slack.min);
        Bound::Moving {
            body,
            radius: reach + margin + slack,
            slack,
        }
    }

    /// The hold for a collider on no body or a fixed one: its box grown by `margin`.
    pub fn fixed(min: Vec3, max: Vec3, margin: Real) -> Bound {
        Bound::Fixed {
            min: min - Vec3::splat(margin),
            max: max + Vec3::splat(margin),
        }
    }

    /// Whether two holds are the same up to rounding of the collider's pose (a pose that
    /// moved with its body gives the same ball).
    pub fn same(&self, other: &Bound) -> bool {
        let close = |a: Real, b: Real| (a - b).abs() <= 1e-5 * a.abs().max(b.abs()).max(1e-3);
        match (*self, *other) {
            (Bound::Fixed { min: a, max: b }, Bound::Fixed { min: c, max: d }) => a == c && b == d,
            (
                Bound::Moving {
                    body: b1,
                    radius: r1,
                    ..
                },
                Bound::Moving {
                    body: b2,
                    radius: r2,
                    ..
                },
            ) => b1 == b2 && close(r1, r2),
            _ => false,
        }
    }
}

/// The plan through the body's state now: centre `x`, velocity `v`, acceleration `a`, at
/// time `t`. Engines with a semi-implicit Euler integrator (rapier, avian) integrate positions
/// in `substeps` steps of `dt / substeps`, each after adding its share of `a dt` to the
/// velocity; over whole steps the centre then lies on the parabola whose velocity now is
/// `v + a dt / (2 substeps)`.
pub fn fit_plan(x: Vec3, v: Vec3, a: Vec3, t: Real, dt: Real, substeps: Real) -> FlightPlan {
    FlightPlan::accelerated(x, v + a * (dt / (2.0 * substeps)), a).starting_at(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A semi-implicit Euler position update for a free body under constant acceleration.
    fn substepped(x: Vec3, v: Vec3, a: Vec3, dt: Real, substeps: usize, steps: usize) -> Vec3 {
        let (mut x, mut v) = (x, v);
        let h = dt / substeps as Real;
        for _ in 0..steps * substeps {
            v += a * h;
            x += v * h;
        }
        x
    }

    #[test]
    fn the_fitted_parabola_passes_through_every_step_of_the_substepped_integrator() {
        let (x, v, a) = (
            Vec3::new(1.0, 20.0, -3.0),
            Vec3::new(2.0, 0.5, 1.0),
            Vec3::new(0.0, -9.81, 0.3),
        );
        for substeps in [1, 4] {
            let plan = fit_plan(x, v, a, 0.0, 1.0 / 60.0, substeps as Real);
            for n in [1, 10, 100] {
                let want = substepped(x, v, a, 1.0 / 60.0, substeps, n);
                let got = plan.position_at(n as Real / 60.0);
                assert!((want - got).length() < 1e-9, "{substeps} {n}: {want} {got}");
            }
        }
    }

    #[test]
    fn a_holds_slack_is_a_share_of_its_reach_and_at_least_the_least() {
        let body = Key::new(3, 1);
        let slack = Slack {
            fraction: 0.05,
            min: 0.01,
        };
        let Bound::Moving {
            radius, slack: s, ..
        } = Bound::moving(body, 2.0, 0.1, slack)
        else {
            panic!("a moving hold");
        };
        assert_eq!(s, 0.1);
        assert!((radius - 2.2).abs() < 1e-12);
        let Bound::Moving { slack: s, .. } = Bound::moving(body, 0.1, 0.1, slack) else {
            panic!("a moving hold");
        };
        assert_eq!(s, 0.01);
        assert!(Bound::moving(body, 2.0, 0.1, slack).same(&Bound::moving(body, 2.0, 0.1, slack)));
        assert!(!Bound::moving(body, 2.0, 0.1, slack).same(&Bound::fixed(
            Vec3::ZERO,
            Vec3::ONE,
            0.0
        )));
    }
}
