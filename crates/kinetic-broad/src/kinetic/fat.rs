//! Fat boxes: a body at rest is held by boxes about its colliders, not by balls on its plan.
//!
//! A body planned at rest (asleep, or one that would stay within half its slack for a while:
//! resting on a floor or in a pile) has each of its colliders held by a fat box: the
//! collider's own box now and where its velocity takes it by the end of the step, grown by
//! [`FAT_MARGIN`] of its half-width (at least the body's slack). A box at rest is what the
//! structure holds best: no events, and a box about a box is far tighter than the ball about
//! it, whose pairs with its neighbours the narrow phase would test every step (unit boxes
//! resting 1.5 apart: three times the pairs). The boxes stay while each collider's box,
//! swept over the coming step, stays inside its fat box, as the enlarged boxes of Box2D's
//! and rapier's trees do; a body that leaves them is planned again ([`BroadPhaseCore::hold`]).
//! An engine that gives no boxes ([`Engine::bounds`]) keeps every body on its plan.

use super::{BroadPhaseCore, Motion};
use crate::Aabb;
use crate::{Bound, Engine, Key};
use kinetic_core::{Real, Vec3};

/// A fat box is grown by this share of its collider's box half-width on every side.
const FAT_MARGIN: Real = 0.1;

impl Motion {
    /// Whether its plan is at rest.
    pub(super) fn at_rest(&self) -> bool {
        self.plan.velocity == Vec3::ZERO && self.plan.acceleration == Vec3::ZERO
    }
}

impl BroadPhaseCore {
    /// The fat box for collider `c` of a body moving at `v` over a step `dt`, with base slack
    /// `slack`; `None` if the engine gives no box.
    fn fat_box_for(engine: &impl Engine, c: Key, v: Vec3, dt: Real, slack: Real) -> Option<Aabb> {
        let b = engine.bounds(c)?.swept(v * dt);
        let m = (FAT_MARGIN * b.widest() / 2.0).max(slack);
        Some(b.grown(Vec3::splat(m)))
    }

    /// Whether every collider of fat body `b`, moving at `v`, stays inside its fat box over
    /// the coming step `dt`.
    pub(super) fn keeps_boxes(&self, engine: &impl Engine, b: Key, v: Vec3, dt: Real) -> bool {
        self.motions[b].colliders.iter().all(|&i| {
            let Some(p) = self.proxies[i as usize] else {
                return true;
            };
            let (Some(fat), Some(b)) = (p.fat, engine.bounds(p.key)) else {
                return false;
            };
            b.swept(v * dt).inside(&fat)
        })
    }

    /// Holds body `b` (moving at `velocity`) as its plan, just fitted, calls for: by fresh
    /// fat boxes when the plan is at rest and the engine gives boxes, else by the balls of its
    /// holds on the plan (`resized`: with a new slack).
    pub(super) fn hold(&mut self, engine: &impl Engine, b: Key, velocity: Vec3, resized: bool) {
        if self.is_stepped() {
            // A stepped world keeps the plans only to price a kinetic step: no proxy to move.
            self.stats.replans += 1;
            self.step.replans += 1;
            return;
        }
        if self.motions[b].at_rest()
            && let Some(boxes) = self.fat_boxes(engine, b, velocity)
        {
            self.motions.get_mut(b).expect("a motion").fat = true;
            self.stats.boxed += 1;
            self.stats.replans += 1;
            self.step.replans += 1;
            // A box covers its collider's whole step; only the others' lag grows it.
            let grow = self.lag_growth();
            for (i, hold, fat) in boxes {
                self.take_out(i);
                self.proxies[i as usize].as_mut().expect("held").fat = Some(fat);
                self.put_in(i, hold, grow);
                self.book.apply(&mut self.changes, self.clock.kds);
            }
            return;
        }
        let m = self.motions.get_mut(b).expect("a motion");
        let unboxed = std::mem::take(&mut m.fat);
        if unboxed {
            for &i in &m.colliders {
                if let Some(p) = self.proxies[i as usize].as_mut() {
                    p.fat = None;
                }
            }
        }
        self.replan(b, resized || unboxed);
    }

    /// Fresh fat boxes for each collider of body `b`, moving at `v`, with their holds; `None`
    /// if the engine gives no boxes.
    fn fat_boxes(&self, engine: &impl Engine, b: Key, v: Vec3) -> Option<Vec<(u32, Bound, Aabb)>> {
        let m = &self.motions[b];
        let (slack, dt) = (m.slack, self.clock.dt);
        m.colliders
            .iter()
            .filter_map(|&i| self.proxies[i as usize].map(|p| (i, p)))
            .map(|(i, p)| Self::fat_box_for(engine, p.key, v, dt, slack).map(|f| (i, p.hold, f)))
            .collect()
    }

    /// Gives body `b`, at rest, fat boxes where the engine gives them, with no structure to
    /// tell (a stepped world going back to kinetic builds its structure next).
    pub(super) fn box_in(&mut self, engine: &impl Engine, b: Key) {
        let Some(rb) = engine.body(b) else { return };
        let Some(boxes) = self.fat_boxes(engine, b, rb.velocity) else {
            return;
        };
        self.motions.get_mut(b).expect("a motion").fat = true;
        for (i, _, fat) in boxes {
            self.proxies[i as usize].as_mut().expect("held").fat = Some(fat);
        }
    }

    /// The fat box of collider `i`, held by `hold`, when it joins a body held by fat boxes
    /// (`None` for any other).
    pub(super) fn joining_box(&self, engine: &impl Engine, i: Key, hold: &Bound) -> Option<Aabb> {
        let Bound::Moving { body, .. } = *hold else {
            return None;
        };
        let m = self.motions.get(body).filter(|m| m.fat)?;
        let rb = engine.body(body)?;
        Self::fat_box_for(engine, i, rb.velocity, self.clock.dt, m.slack)
    }

    /// Checks that every collider of fat body `b` is inside its fat box now.
    pub(super) fn check_boxes(
        &self,
        engine: &impl Engine,
        b: Key,
        m: &Motion,
    ) -> Result<(), String> {
        for &i in &m.colliders {
            let Some(p) = self.proxies[i as usize] else {
                continue;
            };
            let Some(fat) = p.fat else {
                return Err(format!(
                    "collider {i} of body {b:?}, held by boxes, has none"
                ));
            };
            if let Some(own) = engine.bounds(p.key)
                && !own.inside(&fat)
            {
                return Err(format!(
                    "collider {i} of body {b:?}: box {}..{} outside its fat box {}..{}",
                    own.min, own.max, fat.min, fat.max
                ));
            }
        }
        Ok(())
    }
}
