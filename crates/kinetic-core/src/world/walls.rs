//! Walls: under the elastic response a ball bounces off the sides of the box that holds the
//! scene. One certificate per ball: the earliest of its wall contacts.

use super::pairs::{Due, Walk};
use super::{Response, World};
use crate::certificates::wall_gap;
use crate::math::Real;

/// A ball's next wall contact: which axis, which side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct WallHit {
    pub time: Real,
    pub axis: usize,
    pub upper: bool,
}

impl World {
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
pub(crate) fn wall_hit(
    plan: &crate::FlightPlan,
    r: Real,
    walls: &super::Walls,
    dims: usize,
    now: Real,
) -> Option<WallHit> {
    let centre = plan.local_coefficients(now);
    let mut best: Option<WallHit> = None;
    for axis in 0..dims {
        for (upper, at) in [(false, walls.min[axis]), (true, walls.max[axis])] {
            let w = wall_gap(&centre, r, axis, at, upper);
            if w.c[2] == 0.0 && w.c[0] > 0.0 {
                // Linear motion, apart: the walk's answer directly. Moving away (or along)
                // never hits; moving in hits at the single root of the gap.
                let tau = -w.c[0] / w.c[1];
                if w.c[1] < 0.0
                    && tau > 0.0
                    && tau.is_finite()
                    && best.is_none_or(|b| now + tau < b.time)
                {
                    best = Some(WallHit {
                        time: now + tau,
                        axis,
                        upper,
                    });
                }
                continue;
            }
            let mut walk = Walk::elastic(&w, now, now, &w);
            while let Some((_, _, Due::Graze)) = walk.due {
                walk.consume(Response::Elastic);
            }
            if let Some((time, _, _)) = walk.due
                && best.is_none_or(|b| time < b.time)
            {
                best = Some(WallHit { time, axis, upper });
            }
        }
    }
    best
}

/// The plan of a ball that reaches a wall at `now`: its velocity across the wall reversed if
/// it moves into it (rounding cannot make it turn twice).
pub(crate) fn bounced(plan: &crate::FlightPlan, hit: WallHit, now: Real) -> crate::FlightPlan {
    let mut v = plan.velocity_at(now);
    if (hit.upper && v[hit.axis] > 0.0) || (!hit.upper && v[hit.axis] < 0.0) {
        v[hit.axis] = -v[hit.axis];
    }
    plan.replanned(now, v)
}
