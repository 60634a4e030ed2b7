//! The audit: every invariant of the guards recomputed from scratch.

use super::{Guards, Watch};
use kinetic_core::Real;
use kinetic_core::kds::Bodies;
use rustc_hash::FxHashSet;

impl Guards {
    /// Checks the cone and dominance of watch `slot` against the plans at `now`.
    fn validate_cone(
        &self,
        bodies: &Bodies,
        slot: u32,
        w: &Watch,
        now: Real,
    ) -> Result<(), String> {
        let (g, b) = (w.guarded, w.boxer);
        let due = w.cone_event_time();
        if self.cone_queue.time_of(slot).unwrap_or(Real::INFINITY) != due {
            return Err(format!(
                "watch ({g}, {b}): cone event not scheduled at {due}"
            ));
        }
        let d = Self::plan(bodies, b).position_at(now) - Self::plan(bodies, g).position_at(now);
        let eps = 1e-9 * (1.0 + d.length() + Self::plan(bodies, g).position_at(now).length());
        let soon = now + 1e-9 * now.abs().max(1.0);
        if let Some(c) = w.cone {
            if !self.by_cone.get(&(g, c)).is_some_and(|l| l.contains(&slot)) {
                return Err(format!("watch ({g}, {b}) missing from its cone {c}"));
            }
            if w.cone_due > soon {
                let half = self.cube_half(g);
                for n in self.cones.cone(c).normals {
                    let margin = n.dot(d) - half * n.abs().element_sum();
                    if margin < -eps {
                        return Err(format!(
                            "watch ({g}, {b}): guard cube leaves cone {c} by {margin}"
                        ));
                    }
                }
            }
        }
        if let Some(o) = w.dominator {
            let x = self.watches[o as usize].ok_or("a dead dominator")?;
            if !self.dominatees[o as usize].contains(&slot) {
                return Err(format!("watch ({g}, {b}): not listed by its dominator"));
            }
            if x.guarded != g || x.cone.is_none() || x.cone != w.cone {
                return Err(format!("watch ({g}, {b}): dominator not in the same cone"));
            }
            if w.dominator_due > soon {
                let c = w.cone.expect("a cone");
                let other = Self::plan(bodies, x.boxer).position_at(now);
                let me = Self::plan(bodies, b).position_at(now);
                let closer = self.cones.cone(c).edge().dot(me - other);
                let gap =
                    (me - other).length() - (self.half[b as usize] + self.half[x.boxer as usize]);
                if closer < -eps || gap < -eps {
                    return Err(format!(
                        "watch ({g}, {b}) dominated by {}: closer by {closer}, apart by {gap}",
                        x.boxer
                    ));
                }
            }
        }
        for &d in &self.dominatees[slot as usize] {
            if self.watches[d as usize].and_then(|x| x.dominator) != Some(slot) {
                return Err(format!(
                    "watch ({g}, {b}) lists a dominatee it does not dominate"
                ));
            }
        }
        Ok(())
    }

    /// Recomputes the invariants from scratch
    /// ([`kinetic_core::CandidateStructure::validate`]).
    pub(super) fn check(&self, bodies: &Bodies, now: Real) -> Result<(), String> {
        self.watch_queue.validate()?;
        self.lists.validate(
            "guards",
            bodies,
            now,
            |id| self.present(id),
            |id| self.items(bodies, id),
        )?;
        let certs: usize = self.watches.iter().flatten().map(Watch::certificates).sum();
        if certs != self.watch_certs {
            return Err(format!(
                "watches hold {certs} certificates, counted {}",
                self.watch_certs
            ));
        }
        let want: FxHashSet<(u32, u32)> = self.cube_pairs().into_iter().collect();
        let have: FxHashSet<(u32, u32)> = self.watch_index.keys().copied().collect();
        if want != have {
            return Err(format!(
                "watches: {} kept, {} boxes overlap a guard cube (missing {:?}, extra {:?})",
                have.len(),
                want.len(),
                want.difference(&have).next(),
                have.difference(&want).next()
            ));
        }
        let mut holding = FxHashSet::default();
        for (&(g, b), &slot) in &self.watch_index {
            let w = self.watches[slot as usize].ok_or("a dead watch slot")?;
            let due = w.due();
            if self.watch_queue.time_of(slot).unwrap_or(Real::INFINITY) != due {
                return Err(format!("watch ({g}, {b}) not scheduled at {due}"));
            }
            if w.wanted() {
                holding.insert((g, b));
            }
            self.validate_cone(bodies, slot, &w, now)?;
            if due <= now + 1e-9 * now.abs().max(1.0) {
                // A plane crossing due now (or within rounding of now), not processed yet.
                continue;
            }
            // Each end lies above the planes it is kept above, up to rounding at the moment
            // it crossed one.
            for axis in 0..3 {
                for (e, sign) in [(0, -1.0), (1, 1.0)] {
                    let end =
                        Self::plan(bodies, b).position_at(now)[axis] + sign * self.half[b as usize];
                    let eps = 1e-9 * (1.0 + end.abs());
                    let plane = |i| self.plane(bodies, g, axis, i).value_at(now);
                    let below = |x: Real| (0..self.grid.m).filter(|&i| plane(i) < x).count();
                    let kept = w.ends[axis][e].j as usize;
                    if !(below(end - eps) <= kept && kept <= below(end + eps)) {
                        return Err(format!(
                            "watch ({g}, {b}): axis {axis} end {e} kept above {kept} planes, \
                             is above {}",
                            below(end)
                        ));
                    }
                }
            }
        }
        let coned: usize = self.by_cone.values().map(Vec::len).sum();
        let want_coned = self
            .watches
            .iter()
            .flatten()
            .filter(|w| w.cone.is_some())
            .count();
        if coned != want_coned {
            return Err(format!(
                "cones list {coned} watches, {want_coned} watches are in a cone"
            ));
        }
        if holding != self.pairs {
            return Err(format!(
                "guarded pairs: {} kept, {} watches hold a guard undominated",
                self.pairs.len(),
                holding.len()
            ));
        }
        let links: usize = self.links.iter().map(Vec::len).sum();
        let live = (0..self.half.len() as u32)
            .filter(|&i| self.present(i))
            .count();
        let w = self.wild_count;
        let wild_ends = 2 * w * live.saturating_sub(1) - w * w.saturating_sub(1);
        if links != 2 * self.pairs.len() + wild_ends {
            return Err(format!(
                "guards: {links} link ends for {} guarded pairs and {w} unguarded objects",
                self.pairs.len()
            ));
        }
        Ok(())
    }
}
