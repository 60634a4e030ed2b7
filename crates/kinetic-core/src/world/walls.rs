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
        let centre = body.plan.local_coefficients(self.now);
        let r = body.shape.outer_radius();
        let mut best: Option<WallHit> = None;
        for axis in 0..self.dims() {
            for (upper, at) in [(false, walls.min[axis]), (true, walls.max[axis])] {
                let w = wall_gap(&centre, r, axis, at, upper);
                // Only collisions count: a ball grazing a wall does not bounce.
                let mut walk = Walk::elastic(&w, self.now, self.now, &w);
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
        let plan = self.plan_of(id);
        let mut v = plan.velocity_at(self.now);
        // Only a ball moving into the wall turns; rounding cannot make it turn twice.
        if (hit.upper && v[hit.axis] > 0.0) || (!hit.upper && v[hit.axis] < 0.0) {
            v[hit.axis] = -v[hit.axis];
        }
        self.stats.bounces += 1;
        self.replan(id, plan.replanned(self.now, v));
    }
}
