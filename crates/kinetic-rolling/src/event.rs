//! Swap events: a tangency point entering or leaving a threshold box.

use crate::tree::{Kind, RollingTree, Side};
use kinetic_core::kds::{PairChange, Swap};

impl RollingTree {
    /// Processes the earliest swap of all the lists.
    pub(crate) fn next_swap(&mut self, changes: &mut Vec<PairChange>) {
        let Some((id, t)) = self.queue.peek() else {
            return;
        };
        let (sp, axis) = (id as usize / 2, id as usize % 2);
        self.now = self.now.max(t);
        let list = &mut self.space_mut(sp).lists[axis];
        let swap = list.process_next_event(t);
        let due = list.next_event_time();
        self.reschedule(sp, axis, due);
        if let Some(swap) = swap {
            self.on_swap(sp, axis, swap, changes);
        }
    }

    /// A point and a side of a box exchanged places on `axis`: the point entered or left the
    /// box on that side; if all other sides agree, the pair becomes or stops being a candidate.
    fn on_swap(&mut self, sp: usize, axis: usize, swap: Swap, changes: &mut Vec<PairChange>) {
        let items = &self.space(sp).items;
        let (l, r) = (items[swap.left as usize], items[swap.right as usize]);
        // (point, box, box side, entering)
        let (pt, bx, entering) = match (l.kind, r.kind) {
            (Kind::Min, Kind::Point) => (r, l, false),
            (Kind::Point, Kind::Min) => (l, r, true),
            (Kind::Point, Kind::Max) => (l, r, false),
            (Kind::Max, Kind::Point) => (r, l, true),
            _ => {
                self.unrelated_swaps += 1;
                return;
            }
        };
        let (k, j, i) = (bx.node, pt.ball, bx.ball);
        // In the global lists, a point meets the boxes of nodes it is not small at.
        if self.step_at(j, k).is_none_or(|s| s.side != Side::Small) {
            self.unrelated_swaps += 1;
            return;
        }
        let sides = self.sides(k, j, i);
        let this = (axis, usize::from(bx.kind == Kind::Max));
        let others = (0..2)
            .flat_map(|a| (0..2).map(move |s| (a, s)))
            .filter(|&c| c != this)
            .all(|(a, s)| sides[a][s]);
        if !others {
            return;
        }
        let d = self.nodes[k as usize].depth as usize;
        let step = &mut self.paths[j as usize][d];
        if entering {
            step.inside += 1;
            self.max_inside = self.max_inside.max(step.inside);
        } else {
            step.inside -= 1;
        }
        let delta = if entering { 1 } else { -1 };
        changes.push(PairChange { a: j, b: i, delta });
    }
}
