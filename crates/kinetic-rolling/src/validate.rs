//! The audit: every invariant recomputed from scratch.

use crate::tree::{Kind, ListLayout, NONE, RollingTree, Side, balanced, half_side, key, plan};
use kinetic_core::Real;
use kinetic_core::kds::Bodies;

impl RollingTree {
    /// Checks the tree's shape and balance, the lists (sorted, scheduled, with the items and
    /// keys of the current plans) and the containment counts. That no contact is missed
    /// follows (the lists are sorted, and every contact lies inside a box); the simulator's
    /// own audit checks it directly.
    pub(crate) fn check(&self, bodies: &Bodies, _now: Real) -> Result<(), String> {
        let live: Vec<u32> = (0..bodies.len() as u32)
            .filter(|&b| bodies[b as usize].is_some())
            .collect();
        let mut in_tree = self.balls_of(self.root);
        in_tree.sort_unstable();
        if in_tree != live {
            return Err(format!(
                "the tree holds {} balls, the world {}",
                in_tree.len(),
                live.len()
            ));
        }
        let mut boxes = 0;
        let mut certs = 0;
        for k in self.nodes_of(self.root) {
            let n = self.nodes[k as usize];
            if n.parent != NONE && self.nodes[n.parent as usize].depth + 1 != n.depth {
                return Err(format!("node {k} has depth {}", n.depth));
            }
            if n.is_leaf() {
                if self.leaf[n.ball as usize] != k || n.size != 1 {
                    return Err(format!("leaf {k} of ball {} is not indexed", n.ball));
                }
                if self.paths[n.ball as usize].len() != n.depth as usize {
                    return Err(format!("ball {} has a path of the wrong length", n.ball));
                }
                continue;
            }
            let halves = n.child.map(|c| self.balls_of(c));
            let [s, l] = n.child.map(|c| self.nodes[c as usize].size);
            if !balanced(s, l)
                || s + l != n.size
                || halves[0].len() + halves[1].len() != n.size as usize
            {
                return Err(format!("node {k} has halves {s} and {l} of {}", n.size));
            }
            for (half, side) in halves.iter().zip([Side::Small, Side::Large]) {
                for &b in half {
                    let r = self.radius[b as usize];
                    if (side == Side::Small && r > n.rho) || (side == Side::Large && r < n.rho) {
                        return Err(format!(
                            "ball {b} (r = {r}) on the wrong side of rho = {}",
                            n.rho
                        ));
                    }
                    match self.step_at(b, k) {
                        Some(st) if st.side == side => {}
                        _ => return Err(format!("ball {b} has no step for node {k}")),
                    }
                }
            }
            self.check_node_keys(k, &halves, bodies)?;
            let d = n.depth as usize;
            let mut points: Vec<u32> = self.node_pairs(k).into_iter().map(|(j, _)| j).collect();
            points.sort_unstable();
            for &j in &halves[0] {
                let inside =
                    points.partition_point(|&x| x <= j) - points.partition_point(|&x| x < j);
                if self.paths[j as usize][d].inside as usize != inside {
                    return Err(format!(
                        "at node {k}, ball {j} counts {} boxes, the lists say {inside}",
                        self.paths[j as usize][d].inside
                    ));
                }
            }
            match self.layout {
                ListLayout::PerNode => {
                    let per = halves[0].len() + 2 * halves[1].len();
                    let lens = self.space(k as usize).lists.each_ref().map(|l| l.len());
                    if lens != [per; 2] {
                        return Err(format!("node {k} lists have {lens:?} items, not {per}"));
                    }
                    certs += self.check_lists(k as usize)?;
                }
                ListLayout::Global => boxes += halves[1].len(),
            }
        }
        if self.layout == ListLayout::Global && !self.spaces.is_empty() {
            let want = 2 * boxes + live.len();
            let lens = self.space(0).lists.each_ref().map(|l| l.len());
            if lens != [want; 2] {
                return Err(format!("global lists have {lens:?} items, not {want}"));
            }
            certs += self.check_lists(0)?;
        }
        if certs != self.certs {
            return Err(format!("{} certificates counted, {certs} held", self.certs));
        }
        Ok(())
    }

    /// Each list is valid and scheduled in the global queue at its next swap.
    fn check_lists(&self, sp: usize) -> Result<usize, String> {
        let mut certs = 0;
        for (a, list) in self.space(sp).lists.iter().enumerate() {
            list.validate()?;
            let queued = self.queue.time_of((2 * sp + a) as u32);
            if queued.unwrap_or(Real::INFINITY) != list.next_event_time() {
                return Err(format!("list {a} of space {sp} is queued at {queued:?}"));
            }
            certs += list.certificates();
        }
        Ok(certs)
    }

    /// The keys of node `k`'s items are those of the balls' current plans.
    fn check_node_keys(
        &self,
        k: u32,
        halves: &[Vec<u32>; 2],
        bodies: &Bodies,
    ) -> Result<(), String> {
        let n = self.nodes[k as usize];
        let d = n.depth as usize;
        let sp = self.space(self.space_of(k));
        let mut expect = Vec::new();
        for &j in &halves[0] {
            expect.push((self.point_of(j, k), j, Kind::Point, 0.0));
        }
        for &i in &halves[1] {
            let s = self.paths[i as usize][d];
            let h = half_side(self.radius[i as usize], n.rho);
            expect.push((s.item, i, Kind::Min, -h));
            expect.push((s.item2, i, Kind::Max, h));
        }
        for (id, b, kind, offset) in expect {
            let item = sp.items[id as usize];
            if item.ball != b || item.kind != kind {
                return Err(format!("item {id} at node {k} is not ball {b}'s {kind:?}"));
            }
            let p = plan(bodies, b);
            for a in 0..2 {
                if sp.lists[a].key(id) != Some(&key(&p, a, offset)) {
                    return Err(format!("ball {b}'s {kind:?} at node {k} has a stale key"));
                }
            }
        }
        Ok(())
    }
}
