//! What the grid tells about itself: the clock, the balls, the statistics and figures.

use super::ElasticCells;
use crate::bulk::{Bulk, Sums, ball_volume};
use kinetic_core::FlightPlan;
use kinetic_core::Real;
use kinetic_core::{ContactEvent, Stats};

impl ElasticCells {
    /// The current time.
    pub fn now(&self) -> Real {
        self.now
    }

    /// Number of balls.
    pub fn len(&self) -> usize {
        self.plans.len()
    }

    /// Whether there are no balls.
    pub fn is_empty(&self) -> bool {
        self.plans.is_empty()
    }

    /// Ball `id`'s current plan.
    pub fn plan(&self, id: u32) -> &FlightPlan {
        &self.plans[self.int[id as usize] as usize]
    }

    /// Ball `id`'s radius.
    pub fn radius(&self, id: u32) -> Real {
        self.radius[self.int[id as usize] as usize]
    }

    /// The statistics so far (collisions, bounces, cell events and stale entries re-checked;
    /// certificates are the balls' scheduled events).
    pub fn stats(&self) -> &Stats {
        &self.stats
    }

    /// The grid's own figures: levels, cells, block cells held, and pairs of nearby balls
    /// now.
    pub fn counters(&self) -> Vec<(&'static str, f64)> {
        let cells: usize = self.levels.iter().map(|l| l.head.len()).sum();
        let block_cells: usize = self
            .levels
            .iter()
            .map(|l| l.visitors.values().map(Vec::len).sum::<usize>())
            .sum();
        vec![
            ("levels", self.levels.len() as f64),
            ("cells", cells as f64),
            ("block_cells", block_cells as f64),
            ("nearby_pairs", self.nearby_pairs() as f64),
        ]
    }

    /// Takes the contact events so far, in time order, ties by `(a, b)`.
    pub fn drain_events(&mut self) -> Vec<ContactEvent> {
        let mut events = std::mem::take(&mut self.events);
        events.sort_by(|x, y| x.time.total_cmp(&y.time).then((x.a, x.b).cmp(&(y.a, y.b))));
        events
    }

    /// The time of the next event (+infinity for none).
    pub fn next_event_time(&self) -> Real {
        self.queue.next_time()
    }

    /// The number of pairs of nearby balls (each counted once).
    pub fn nearby_pairs(&self) -> usize {
        let mut out = Vec::new();
        let mut total = 0;
        for id in 0..self.len() as u32 {
            out.clear();
            self.neighbours(id, &mut out);
            total += out.len();
        }
        total / 2
    }

    /// Starts the bulk figures afresh from now (after the system has equilibrated).
    pub fn reset_bulk(&mut self) {
        self.sums = Sums::from(self.now);
    }

    /// Collision rate, temperature and the pressure on the walls over the run so far (masses
    /// `(2 r)^3`, as [`crate::ListedSpheres::bulk`] has them).
    pub fn bulk(&self) -> Bulk {
        let filled = self.radius.iter().map(|&r| ball_volume(r)).sum();
        let side = self.walls.max - self.walls.min;
        let n = self.len();
        self.sums
            .figures(self.now, n, self.two_kinetic, side, true, filled)
    }

    /// The kinetic energy now (masses radius cubed, as the response has them).
    pub fn kinetic_energy(&self) -> Real {
        self.plans
            .iter()
            .zip(&self.radius)
            .map(|(p, r)| 0.5 * r * r * r * p.velocity_at(self.now).length_squared())
            .sum()
    }

    /// The deepest overlap of two balls now (`r_a + r_b - |p_a - p_b|`, negative when all
    /// are apart), over the pairs of nearby balls.
    pub fn max_overlap(&self) -> Real {
        let mut out = Vec::new();
        let mut worst = Real::NEG_INFINITY;
        for id in 0..self.len() as u32 {
            out.clear();
            self.neighbours(id, &mut out);
            let p = self.plans[id as usize].position_at(self.now);
            for &o in &out {
                let q = self.plans[o as usize].position_at(self.now);
                let d = self.radius[id as usize] + self.radius[o as usize] - (p - q).length();
                worst = worst.max(d);
            }
        }
        worst
    }
}
