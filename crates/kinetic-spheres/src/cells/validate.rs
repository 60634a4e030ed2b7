//! The audit: every invariant of the grid recomputed from scratch.

use super::{ElasticCells, Event, NIL, WIDEN};
use kinetic_core::Real;

impl ElasticCells {
    /// Recomputes the invariants from scratch: home cells and lists, blocks and visitors,
    /// the queue; and, over every pair of balls, that no certificate fails before the
    /// earlier of its two balls' scheduled events (the grid misses no pair). Quadratic in the
    /// number of balls: for tests.
    pub fn validate(&self) -> Result<(), String> {
        self.queue.validate()?;
        let count = self.len();
        let mut listed = 0;
        for (li, l) in self.levels.iter().enumerate() {
            for (cell, &first) in l.head.iter().enumerate() {
                let mut o = first;
                let mut prev = NIL;
                while o != NIL {
                    listed += 1;
                    if self.level[o as usize] as usize != li
                        || l.index(self.home[o as usize]) as usize != cell
                        || self.link[o as usize][1] != prev
                    {
                        return Err(format!("cells: ball {o} listed in the wrong cell {cell}"));
                    }
                    (prev, o) = (o, self.link[o as usize][0]);
                }
            }
        }
        if listed != count {
            return Err(format!("cells: {listed} balls listed, {count} held"));
        }
        for id in 0..count as u32 {
            let i = id as usize;
            let p = self.plans[i].position_at(self.now);
            let l = &self.levels[self.level[i] as usize];
            for k in 0..3 {
                let tol = WIDEN * l.cell[k];
                let lo = self.walls.min[k] + self.home[i][k] as Real * l.cell[k];
                if p[k] < lo - tol && self.home[i][k] > 0
                    || p[k] > lo + l.cell[k] + tol && self.home[i][k] + 1 < l.n[k]
                {
                    return Err(format!(
                        "cells: ball {id} at {p} is outside its home cell {:?}",
                        self.home[i]
                    ));
                }
                let r = self.radius[i];
                if p[k] - r < self.walls.min[k] - tol || p[k] + r > self.walls.max[k] + tol {
                    return Err(format!("cells: ball {id} at {p} is outside the walls"));
                }
            }
            if self.blocks[i].len() != self.level[i] as usize {
                return Err(format!(
                    "cells: ball {id} has {} blocks",
                    self.blocks[i].len()
                ));
            }
            for b in &self.blocks[i] {
                let exact = (self.radius[i] + self.levels[b.level as usize].r_max) * (1.0 - WIDEN);
                for k in 0..3 {
                    let need_lo = self.cell_along(b.level, k, p[k] - exact);
                    let need_hi = self.cell_along(b.level, k, p[k] + exact);
                    if b.lo[k] > need_lo || b.hi[k] < need_hi {
                        return Err(format!(
                            "cells: ball {id}'s block {:?}..{:?} at level {} misses cells \
                             {need_lo}..{need_hi} along axis {k}",
                            b.lo, b.hi, b.level
                        ));
                    }
                }
                let fine = &self.levels[b.level as usize];
                for z in b.lo[2]..=b.hi[2] {
                    for y in b.lo[1]..=b.hi[1] {
                        for x in b.lo[0]..=b.hi[0] {
                            let cell = fine.index([x, y, z]);
                            let n = fine
                                .visitors
                                .get(&cell)
                                .map_or(0, |v| v.iter().filter(|&&o| o == id).count());
                            if n != 1 {
                                return Err(format!(
                                    "cells: ball {id} visits cell {cell} of level {} {n} times",
                                    b.level
                                ));
                            }
                        }
                    }
                }
            }
            let next = self.next[i];
            let queued = self.queue.time_of(id).unwrap_or(Real::INFINITY);
            if queued != next.time {
                return Err(format!(
                    "cells: ball {id} next at {} but queued at {queued}",
                    next.time
                ));
            }
            let [first, second] = self.pair_next[i];
            if first.before(&next) || second.before(&first) {
                return Err(format!(
                    "cells: ball {id}'s pair events at {} and {} are out of order with its \
                     next event at {}",
                    first.time, second.time, next.time
                ));
            }
            if first.time.is_infinite() && matches!(second.event, Event::Pair { .. }) {
                return Err(format!(
                    "cells: ball {id} has a second pair event and no first"
                ));
            }
            if next.time < self.now {
                return Err(format!(
                    "cells: ball {id} was due at {}, now is {}",
                    next.time, self.now
                ));
            }
            if self.wall_from_plan(id) != self.wall[i] {
                return Err(format!("cells: ball {id}'s wall contact is not its plan's"));
            }
            if let Some(hit) = self.wall_next(id)
                && hit.time < next.time
            {
                return Err(format!(
                    "cells: ball {id} reaches a wall at {} unscheduled",
                    hit.time
                ));
            }
            let cell = self.cell_event(id);
            if cell.time < next.time {
                return Err(format!(
                    "cells: ball {id}'s cell event at {} unscheduled",
                    cell.time
                ));
            }
        }
        let visits: usize = self
            .blocks
            .iter()
            .flatten()
            .map(|b| {
                (0..3)
                    .map(|k| (b.hi[k] - b.lo[k] + 1) as usize)
                    .product::<usize>()
            })
            .sum();
        let held: usize = self
            .levels
            .iter()
            .map(|l| l.visitors.values().map(Vec::len).sum::<usize>())
            .sum();
        if visits != held {
            return Err(format!(
                "cells: blocks cover {visits} cells, visitors hold {held}"
            ));
        }
        for a in 0..count as u32 {
            for b in a + 1..count as u32 {
                let Some((t, _)) = self.pair_due(a, b) else {
                    continue;
                };
                let due = self.next[a as usize].time.min(self.next[b as usize].time);
                if t < due {
                    return Err(format!(
                        "cells: pair ({a}, {b}) fails at {t}, but its balls are next due at {due}"
                    ));
                }
            }
        }
        Ok(())
    }
}
