//! The guards as the simulator's candidate structure.

use super::{End, Guards, Watch, decode};
use crate::axes::AxisLists;
use kinetic_core::kds::{Bodies, PairChange};
use kinetic_core::{CandidateStructure, Real, Vec3};

impl CandidateStructure for Guards {
    fn name(&self) -> &'static str {
        "guards"
    }

    fn insert(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        self.sync(now);
        self.admit(bodies, id);
        self.lists.insert(self.items(bodies, id));
        self.pair_new(id, bodies, changes);
    }

    fn insert_many(
        &mut self,
        ids: &[u32],
        bodies: &Bodies,
        now: Real,
        changes: &mut Vec<PairChange>,
    ) {
        if !self.lists.is_empty() || ids.len() < 2 {
            for &id in ids {
                self.insert(id, bodies, now, changes);
            }
            return;
        }
        self.now = now;
        let mut all = Vec::new();
        for &id in ids {
            self.admit(bodies, id);
            all.extend(self.items(bodies, id));
        }
        self.lists = AxisLists::build(now, all);
        for (g, b) in self.cube_pairs() {
            self.open_watch(bodies, g, b, changes);
        }
        let wild: Vec<u32> = ids
            .iter()
            .copied()
            .filter(|&i| self.wild[i as usize])
            .collect();
        for &w in &wild {
            for &o in ids {
                if o != w && !(self.wild[o as usize] && o < w) {
                    self.link(w, o, 1, changes);
                }
            }
        }
    }

    fn remove(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        if !self.present(id) {
            return;
        }
        self.sync(now);
        for slot in self.watches_of[id as usize].clone() {
            let w = self.watches[slot as usize].expect("a live watch");
            self.close_watch(bodies, w.guarded, w.boxer, changes);
        }
        for o in self.links[id as usize].clone() {
            self.link(id, o, -1, changes);
        }
        self.lists.remove(self.items(bodies, id));
        if self.wild[id as usize] {
            self.wild_count -= 1;
        }
        self.half[id as usize] = 0.0;
        self.inner[id as usize] = 0.0;
        self.wild[id as usize] = false;
    }

    fn replan(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        if !self.present(id) {
            return;
        }
        self.sync(now);
        let new = self.items(bodies, id);
        if !self.lists.keeps_order(&new, now) {
            // The box jumped (a teleport, a spin started or stopped): it is filed afresh,
            // its new pairs reported before its old ones go.
            let from = changes.len();
            self.remove(id, bodies, now, changes);
            self.insert(id, bodies, now, changes);
            kinetic_core::kds::additions_first(&mut changes[from..]);
            return;
        }
        self.lists.set_keys(new);
        // Its watches start afresh from the new plan.
        let slots = self.watches_of[id as usize].clone();
        for &slot in &slots {
            let old = self.watches[slot as usize].expect("a live watch");
            let fresh = self.make_watch(bodies, old.guarded, old.boxer, now);
            let w = Watch {
                ends: fresh.ends,
                ..old
            };
            self.put_watch(slot, Some(w));
            self.schedule(slot);
        }
        self.recone(bodies, &slots, changes);
    }

    fn next_event_time(&self) -> Real {
        self.lists
            .next_event_time()
            .min(self.watch_queue.next_time())
            .min(self.cone_queue.next_time())
    }

    fn process_next_event(
        &mut self,
        bodies: &Bodies,
        changes: &mut Vec<PairChange>,
    ) -> &'static str {
        let cone_time = self.cone_queue.next_time();
        if cone_time < self.lists.next_event_time() && cone_time < self.watch_queue.next_time() {
            let (slot, time) = self.cone_queue.peek().expect("a due cone event");
            self.now = self.now.max(time);
            return self.on_cone(slot, bodies, changes);
        }
        if self.watch_queue.next_time() < self.lists.next_event_time() {
            let (slot, time) = self.watch_queue.peek().expect("a due watch");
            self.now = self.now.max(time);
            self.on_watch(slot, bodies, changes);
            return "box";
        }
        let Some((_, swap)) = self.lists.next_swap() else {
            return "swap";
        };
        self.now = self.now.max(swap.time);
        let (u, v) = (decode(swap.left), decode(swap.right));
        let (guarded, boxer) = match (u.1, v.1) {
            (End::CubeLo | End::CubeHi, End::BoxLo | End::BoxHi) => (u.0, v.0),
            (End::BoxLo | End::BoxHi, End::CubeLo | End::CubeHi) => (v.0, u.0),
            _ => return "swap",
        };
        if self.guards_against(guarded, boxer) {
            if self.cube_overlap(guarded, boxer) {
                self.open_watch(bodies, guarded, boxer, changes);
            } else {
                self.close_watch(bodies, guarded, boxer, changes);
            }
        }
        "swap"
    }

    fn certificates(&self) -> usize {
        self.lists.certificates() + self.watch_certs
    }

    fn boxes(&self, bodies: &Bodies, now: Real) -> Vec<(Vec3, Vec3)> {
        self.half
            .iter()
            .enumerate()
            .filter(|&(_, &h)| h > 0.0)
            .filter_map(|(id, &h)| {
                let c = bodies.get(id)?.as_ref()?.plan.position_at(now);
                Some((c - Vec3::splat(h), c + Vec3::splat(h)))
            })
            .collect()
    }

    fn counters(&self) -> Vec<(&'static str, f64)> {
        let m = f64::from(self.grid.m);
        vec![
            ("grid_planes_per_axis", m),
            ("guards_per_object", m * m * m),
            ("watches", self.watches() as f64),
            ("guarded_pairs", self.pairs.len() as f64),
            ("unguarded_objects", self.wild_count as f64),
            ("box_events", self.box_events as f64),
            ("cones_per_guard", self.cones.len() as f64),
            (
                "coned_watches",
                self.watches
                    .iter()
                    .flatten()
                    .filter(|w| w.cone.is_some())
                    .count() as f64,
            ),
            (
                "dominated_watches",
                self.watches
                    .iter()
                    .flatten()
                    .filter(|w| w.dominator.is_some())
                    .count() as f64,
            ),
            ("centre_events", self.centre_events as f64),
            ("dominance_events", self.dominance_events as f64),
        ]
    }

    fn validate(&self, bodies: &Bodies, now: Real) -> Result<(), String> {
        self.check(bodies, now)
    }
}
