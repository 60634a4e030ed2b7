//! The collision tree as the simulator's candidate structure.

use crate::tree::{ListLayout, NONE, RollingTree, Side, half_side};
use kinetic_core::kds::{Bodies, PairChange};
use kinetic_core::{CandidateStructure, Real, Vec3};

impl CandidateStructure for RollingTree {
    fn name(&self) -> &'static str {
        match self.layout {
            ListLayout::PerNode => "rolling-tree",
            ListLayout::Global => "rolling-global-lists",
        }
    }

    fn insert(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        self.insert_ball(id, bodies, now, changes);
    }

    fn insert_many(
        &mut self,
        ids: &[u32],
        bodies: &Bodies,
        now: Real,
        changes: &mut Vec<PairChange>,
    ) {
        if self.root == NONE && ids.len() > 1 {
            self.bulk_build(ids, bodies, now, changes);
        } else {
            for &id in ids {
                self.insert_ball(id, bodies, now, changes);
            }
        }
    }

    fn remove(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        self.remove_ball(id, bodies, now, changes);
    }

    fn replan(&mut self, id: u32, bodies: &Bodies, now: Real, _: &mut Vec<PairChange>) {
        self.replan_ball(id, bodies, now);
    }

    fn next_event_time(&self) -> Real {
        self.queue.next_time()
    }

    fn process_next_event(&mut self, _: &Bodies, changes: &mut Vec<PairChange>) -> &'static str {
        self.next_swap(changes);
        "swap"
    }

    fn certificates(&self) -> usize {
        self.certs
    }

    /// The threshold boxes of every node, flat in the plane (z = 0).
    fn boxes(&self, bodies: &Bodies, now: Real) -> Vec<(Vec3, Vec3)> {
        let mut out = Vec::new();
        for (b, path) in self.paths.iter().enumerate() {
            let Some(Some(body)) = bodies.get(b) else {
                continue;
            };
            let p = body.plan.position_at(now);
            for step in path.iter().filter(|s| s.side == Side::Large) {
                let h = half_side(self.radius[b], self.nodes[step.node as usize].rho);
                out.push((
                    Vec3::new(p.x - h, p.y - h, 0.0),
                    Vec3::new(p.x + h, p.y + h, 0.0),
                ));
            }
        }
        out
    }

    fn counters(&self) -> Vec<(&'static str, f64)> {
        vec![
            ("max_boxes_per_point", f64::from(self.max_inside)),
            ("tree_depth", f64::from(self.depth())),
            ("internal_nodes", self.internal_nodes() as f64),
            ("subtree_rebuilds", self.rebuilds as f64),
            ("unrelated_swaps", self.unrelated_swaps as f64),
        ]
    }

    fn validate(&self, bodies: &Bodies, now: Real) -> Result<(), String> {
        self.check(bodies, now)
    }
}
