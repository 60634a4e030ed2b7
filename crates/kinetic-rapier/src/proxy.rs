//! What the structures see of a rapier collider: a proxy that holds it, and a flight plan.
//!
//! - A collider on a moving (dynamic or kinematic) body is a ball about the body's centre of
//!   mass that holds the collider at every orientation, grown by the prediction distance, the
//!   contact skin and a slack. Spin never moves it, so the plan is the centre of mass alone:
//!   a polynomial of degree at most 2 (rest, coasting, constant acceleration).
//! - A collider on a fixed body (or on none) is its own axis-aligned box, grown the same way,
//!   at rest. In the guards structure it is the ball about that box.

use kinetic_core::{FlightPlan, Real, Vec3};
use rapier3d::prelude::*;

/// Converts a rapier vector.
pub(crate) fn dvec(v: &Vector<f32>) -> Vec3 {
    Vec3::new(v.x as Real, v.y as Real, v.z as Real)
}

/// Converts a rapier point.
pub(crate) fn dpoint(p: &Point<f32>) -> Vec3 {
    Vec3::new(p.x as Real, p.y as Real, p.z as Real)
}

/// A rigid body's centre of mass in world space, from its current pose (rapier refreshes its
/// own world centre of mass only at the end of a step, after the broad phase has run).
pub(crate) fn centre_of_mass(rb: &RigidBody) -> Vec3 {
    dpoint(&(rb.position() * rb.local_center_of_mass()))
}

/// How a collider is held.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Hold {
    /// On a fixed body or none: a box `(min, max)`, at rest.
    Fixed { min: Vec3, max: Vec3 },
    /// On a moving body: a ball of `radius` about the body's centre of mass, which the body
    /// must keep within `slack` of its plan.
    Moving {
        body: RigidBodyHandle,
        radius: Real,
        slack: Real,
    },
}

impl Hold {
    /// The hold for `co` under `params`, with slack `fraction` of its size (at least
    /// `min_slack` length units).
    pub(crate) fn of(
        co: &Collider,
        bodies: &RigidBodySet,
        params: &IntegrationParameters,
        fraction: Real,
        min_slack: Real,
    ) -> Hold {
        let margin = params.prediction_distance() as Real / 2.0 + co.contact_skin() as Real;
        let moving = co
            .parent()
            .and_then(|h| bodies.get(h).map(|rb| (h, rb)))
            .filter(|(_, rb)| !rb.is_fixed());
        match moving {
            None => {
                let aabb = co.compute_aabb();
                Hold::Fixed {
                    min: dpoint(&aabb.mins) - Vec3::splat(margin),
                    max: dpoint(&aabb.maxs) + Vec3::splat(margin),
                }
            }
            Some((h, rb)) => {
                let sphere = co.shape().compute_bounding_sphere(co.position());
                let reach = (dpoint(sphere.center()) - centre_of_mass(rb)).length()
                    + sphere.radius() as Real;
                let slack = (fraction * reach).max(min_slack * params.length_unit as Real);
                Hold::Moving {
                    body: h,
                    radius: reach + margin + slack,
                    slack,
                }
            }
        }
    }

    /// Whether two holds are the same up to rounding of the collider's pose (a pose that
    /// moved with its body gives the same ball).
    pub(crate) fn same(&self, other: &Hold) -> bool {
        let close = |a: Real, b: Real| (a - b).abs() <= 1e-5 * a.abs().max(b.abs()).max(1e-3);
        match (*self, *other) {
            (Hold::Fixed { min: a, max: b }, Hold::Fixed { min: c, max: d }) => a == c && b == d,
            (
                Hold::Moving {
                    body: b1,
                    radius: r1,
                    ..
                },
                Hold::Moving {
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
/// time `t`. rapier integrates positions in `substeps` steps of `dt / substeps`, each after
/// adding its share of `a dt` to the velocity; over whole steps the centre then lies on the
/// parabola whose velocity now is `v + a dt / (2 substeps)`.
pub(crate) fn fit(x: Vec3, v: Vec3, a: Vec3, t: Real, dt: Real, substeps: Real) -> FlightPlan {
    FlightPlan::accelerated(x, v + a * (dt / (2.0 * substeps)), a).starting_at(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// rapier's position update for a free body under constant acceleration, done by hand.
    fn rapier_like(x: Vec3, v: Vec3, a: Vec3, dt: Real, substeps: usize, steps: usize) -> Vec3 {
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
            let plan = fit(x, v, a, 0.0, 1.0 / 60.0, substeps as Real);
            for n in [1, 10, 100] {
                let want = rapier_like(x, v, a, 1.0 / 60.0, substeps, n);
                let got = plan.position_at(n as Real / 60.0);
                assert!((want - got).length() < 1e-9, "{substeps} {n}: {want} {got}");
            }
        }
    }
}
