//! Walls: under the elastic response a ball bounces off the sides of the box that holds the
//! scene. One certificate per ball: the earliest of its wall contacts.

use super::pairs::{Due, Walk};
use super::{Response, Simulator};
use crate::certificates::wall_gap;
use crate::math::Real;
use crate::poly::Poly;

/// A ball's next wall contact: which axis, which side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallHit {
    /// When the ball touches the wall.
    pub time: Real,
    /// The axis the wall is across.
    pub axis: usize,
    /// The wall at the upper end of that axis (else the lower).
    pub upper: bool,
}

impl Simulator {
    /// Recomputes the wall certificate of `id` (elastic response with walls only).
    pub(crate) fn refresh_walls(&mut self, id: u32) {
        let Some(walls) = self.walls.filter(|_| self.response == Response::Elastic) else {
            return;
        };
        let Some(body) = self.bodies[id as usize].as_ref() else {
            return;
        };
        let best = wall_hit(
            &body.plan,
            body.shape.outer_radius(),
            &walls,
            self.dims(),
            self.now,
        );
        self.wall_due[id as usize] = best;
        match best {
            Some(hit) => self.wall_queue.schedule(id, hit.time, u64::from(id)),
            None => {
                self.wall_queue.remove(id);
            }
        }
    }

    /// A ball reaches a wall: its velocity across that wall is reversed.
    pub(crate) fn bounce(&mut self, id: u32) {
        let Some(hit) = self.wall_due[id as usize] else {
            return;
        };
        let plan = bounced(&self.plan_of(id), hit, self.now);
        self.stats.bounces += 1;
        self.replan(id, plan);
    }
}

/// The first wall contact of a ball of radius `r` with `plan` after `now` (grazes skipped: a
/// ball grazing a wall does not bounce), over the first `dims` axes.
pub fn wall_hit(
    plan: &crate::FlightPlan,
    r: Real,
    walls: &super::Walls,
    dims: usize,
    now: Real,
) -> Option<WallHit> {
    if plan.acceleration == crate::math::Vec3::ZERO
        && let Some(hit) = linear_wall_hit(plan, r, walls, dims, now)
    {
        return hit;
    }
    touching_wall_hit(plan, r, walls, dims, now)
}

/// [`wall_hit`] for a ball touching a wall (just bounced) or accelerating: each wall's gap
/// polynomial, by the root walk where no closed form is clear.
#[cold]
#[inline(never)]
fn touching_wall_hit(
    plan: &crate::FlightPlan,
    r: Real,
    walls: &super::Walls,
    dims: usize,
    now: Real,
) -> Option<WallHit> {
    earliest_wall(plan, r, walls, dims, now, wall_time)
}

/// [`wall_hit`] for a linear plan clear of every wall: the closed form of [`wall_time`] on
/// each axis's wall ahead (the one behind is never hit), with its arithmetic, so the answer
/// is the same bit for bit. `None` when the ball touches or crosses a wall, where the general
/// path decides.
#[inline]
fn linear_wall_hit(
    plan: &crate::FlightPlan,
    r: Real,
    walls: &super::Walls,
    dims: usize,
    now: Real,
) -> Option<Option<WallHit>> {
    let p = plan.position_at(now);
    let v = plan.velocity_at(now);
    let mut best: Option<WallHit> = None;
    for axis in 0..dims {
        let below = (p[axis] - walls.min[axis]) - r;
        let above = (walls.max[axis] - p[axis]) - r;
        if !(below > 0.0 && above > 0.0) {
            return None;
        }
        // The gap's coefficients as `wall_gap` writes them: `c1` is `v` below, `-v` above.
        let (upper, c0, c1) = if v[axis] < 0.0 {
            (false, below, v[axis])
        } else if v[axis] > 0.0 {
            (true, above, -v[axis])
        } else {
            continue; // at rest along the axis (or NaN): neither wall
        };
        let tau = -c0 / c1;
        if tau > 0.0 && tau.is_finite() {
            let time = now + tau;
            if best.is_none_or(|b| time < b.time) {
                best = Some(WallHit { time, axis, upper });
            }
        }
    }
    Some(best)
}

/// The earliest wall contact, each wall's gap polynomial timed by `time_of`.
fn earliest_wall(
    plan: &crate::FlightPlan,
    r: Real,
    walls: &super::Walls,
    dims: usize,
    now: Real,
    time_of: fn(&Poly, Real) -> Option<Real>,
) -> Option<WallHit> {
    let centre = plan.local_coefficients(now);
    let mut best: Option<WallHit> = None;
    for axis in 0..dims {
        for (upper, at) in [(false, walls.min[axis]), (true, walls.max[axis])] {
            let w = wall_gap(&centre, r, axis, at, upper);
            if let Some(time) = time_of(&w, now)
                && best.is_none_or(|b| time < b.time)
            {
                best = Some(WallHit { time, axis, upper });
            }
        }
    }
    best
}

/// When the wall gap `w` (in time after `now`) first closes: for a linear plan that is apart,
/// the walk's answer in closed form (moving away or along never hits; moving in hits at the
/// single root), otherwise the walk's.
fn wall_time(w: &Poly, now: Real) -> Option<Real> {
    if w.c[2] == 0.0 && w.c[0] > 0.0 {
        let tau = -w.c[0] / w.c[1];
        return (w.c[1] < 0.0 && tau > 0.0 && tau.is_finite()).then_some(now + tau);
    }
    walked_wall_time(w, now)
}

/// When the wall gap `w` first closes, by the root walk (grazes skipped).
fn walked_wall_time(w: &Poly, now: Real) -> Option<Real> {
    let mut walk = Walk::elastic(w, now, now, w);
    while let Some((_, _, Due::Graze)) = walk.due {
        walk.consume(Response::Elastic);
    }
    walk.due.map(|(time, _, _)| time)
}

/// The plan of a ball that reaches a wall at `now`: its velocity across the wall reversed if
/// it moves into it (rounding cannot make it turn twice).
pub fn bounced(plan: &crate::FlightPlan, hit: WallHit, now: Real) -> crate::FlightPlan {
    let mut v = plan.velocity_at(now);
    if (hit.upper && v[hit.axis] > 0.0) || (!hit.upper && v[hit.axis] < 0.0) {
        v[hit.axis] = -v[hit.axis];
    }
    plan.replanned(now, v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::FlightPlan;
    use crate::math::Vec3;
    use rand::{Rng, SeedableRng};

    #[test]
    fn linear_wall_contacts_are_the_walks_bit_for_bit() {
        let walls = super::super::Walls {
            min: Vec3::new(-3.0, 0.0, 1e6),
            max: Vec3::new(5.0, 0.5, 1e6 + 40.0),
        };
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut hits = 0;
        for k in 0..20000 {
            let r = rng.random_range(0.001..0.2);
            let p = Vec3::new(
                rng.random_range(walls.min.x + r..walls.max.x - r),
                rng.random_range(walls.min.y + r..walls.max.y - r),
                rng.random_range(walls.min.z + r..walls.max.z - r),
            );
            // Some axes at rest, some speeds tiny, some huge; a few balls touching a wall.
            let mut v = Vec3::new(
                rng.random_range(-2.0..2.0),
                rng.random_range(-2.0..2.0),
                rng.random_range(-2.0..2.0),
            );
            match k % 5 {
                0 => v.x = 0.0,
                1 => v *= 1e-12,
                2 => v *= 1e9,
                _ => {}
            }
            let p = if k % 7 == 0 {
                Vec3::new(walls.min.x + r, p.y, p.z)
            } else {
                p
            };
            let t0 = rng.random_range(0.0..10.0);
            let plan = FlightPlan::linear(p, v).starting_at(t0);
            let now = t0 + rng.random_range(0.0..0.01);
            let got = wall_hit(&plan, r, &walls, 3, now);
            let walked = earliest_wall(&plan, r, &walls, 3, now, walked_wall_time);
            assert_eq!(got, walked, "ball {k}");
            hits += usize::from(got.is_some());
        }
        assert!(hits > 15000, "{hits} of 20000 balls reach a wall");
    }
}
