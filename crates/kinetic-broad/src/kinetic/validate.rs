//! The audit: the invariants recomputed from scratch.

use super::{BroadPhaseCore, Proxy};
use crate::Aabb;
use crate::{Bound, ColliderStatus, Engine, Key};

impl BroadPhaseCore {
    /// Recomputes the invariants from scratch, between calls: the structure's own and the
    /// pair book's (kinetic), or every pair of colliders whose boxes overlap handed over
    /// (stepped); the engine's pairs: every held pair whose engine boxes overlap handed
    /// over, and none that is not held; every enabled collider of `colliders` (all the engine
    /// has) held, and (kinetic) every moving body within its slack of its plan.
    pub fn validate(
        &self,
        engine: &impl Engine,
        colliders: impl IntoIterator<Item = Key>,
    ) -> Result<(), String> {
        if let Some(st) = &self.stepped {
            self.check_stepped(engine, &st.pairs())?;
            // Each moving collider's box, as the engine gives it now, lies inside the one
            // the stepped world keeps for it (outside the engine's enlarged boxes).
            for p in self.proxies.iter().flatten() {
                let Bound::Moving { .. } = p.hold else {
                    continue;
                };
                let (Some(kept), Some(b)) = (st.kept_box(p.key.index), engine.bounds(p.key)) else {
                    continue;
                };
                if !b.inside(&kept) {
                    return Err(format!(
                        "collider {:?}: box {b:?} outside the box it is kept in, {kept:?}",
                        p.key
                    ));
                }
            }
        } else {
            if let Some(s) = &self.structure {
                s.validate(&self.bodies, self.clock.kds)?;
            }
            self.book
                .audit(true)
                .map_err(|e| format!("{e}; window {} to {}", self.clock.pos, self.clock.kds))?;
        }
        let held = match &self.stepped {
            Some(st) => st.pairs().into_owned(),
            None => self.book.reported_pairs(),
        };
        self.check_handed(engine, &held)?;
        for h in colliders {
            if matches!(engine.collider(h, self.slack), ColliderStatus::Held(_)) && !self.knows(h) {
                return Err(format!("collider {h:?} is not held"));
            }
        }
        let held = self.proxies.iter().flatten().count();
        if held != self.held {
            return Err(format!("{held} colliders held, counted {}", self.held));
        }
        for (i, p) in self.proxies.iter().enumerate() {
            let want = p.as_ref().map(Proxy::mover);
            if self.movers.get(i).copied().flatten() != want {
                return Err(format!(
                    "collider {i}: mover entry {:?}, held as {want:?}",
                    self.movers.get(i)
                ));
            }
        }
        // A stepped world keeps its plans only now and then, to price a kinetic step.
        let plans = if self.stepped.is_some() {
            Default::default()
        } else {
            self.motions.iter().collect::<Vec<_>>()
        };
        for (h, m) in plans {
            if m.fat {
                self.check_boxes(engine, h, m)?;
                continue;
            }
            let Some(rb) = engine.body(h) else { continue };
            let off = (rb.centre - m.plan.position_at(self.clock.pos)).length();
            if off > m.slack_now() * (1.0 + 1e-6) {
                return Err(format!(
                    "body {h:?} is {off} from its plan, slack {}",
                    m.slack_now()
                ));
            }
        }
        Ok(())
    }
}

impl BroadPhaseCore {
    /// In a stepped world: the pairs handed over are sorted and distinct, and every two held
    /// colliders whose boxes now overlap (the engine's enlarged boxes, else its boxes, or a
    /// fixed collider's own) are among them.
    fn check_stepped(&self, engine: &impl Engine, reported: &[(u32, u32)]) -> Result<(), String> {
        if !reported.windows(2).all(|w| w[0] < w[1]) {
            return Err("the stepped pairs are not sorted and distinct".into());
        }
        let boxes: Vec<(u32, Aabb)> = self
            .proxies
            .iter()
            .enumerate()
            .filter_map(|(i, p)| {
                let p = p.as_ref()?;
                let b = match p.hold {
                    Bound::Fixed { min, max } => Aabb::new(min, max),
                    // The engine's enlarged box where it keeps one: the stepped world's own.
                    Bound::Moving { .. } => {
                        engine.enlarged(p.key).or_else(|| engine.bounds(p.key))?
                    }
                };
                Some((i as u32, b))
            })
            .collect();
        for (k, (a, x)) in boxes.iter().enumerate() {
            for (b, y) in &boxes[k + 1..] {
                let meet = x.overlaps(y);
                if meet && reported.binary_search(&(*a.min(b), *a.max(b))).is_err() {
                    return Err(format!(
                        "colliders {a} and {b}: boxes overlap, the pair is not handed over"
                    ));
                }
            }
        }
        Ok(())
    }
}

impl BroadPhaseCore {
    /// The engine's pairs are the held pairs (`held`, sorted) whose engine boxes meet: every
    /// held pair whose boxes overlap now is handed over, and every handed pair is held.
    fn check_handed(&self, engine: &impl Engine, held: &[(u32, u32)]) -> Result<(), String> {
        self.validate_handed()?;
        let key = |i: u32| self.proxies[i as usize].map(|p| p.key);
        let mut handed = 0;
        for &(a, b) in held {
            let (Some(ka), Some(kb)) = (key(a), key(b)) else {
                continue;
            };
            let has = self.has_pair(ka, kb);
            handed += usize::from(has);
            if let (Some(x), Some(y)) = (engine.bounds(ka), engine.bounds(kb))
                && x.overlaps(&y)
                && !has
            {
                return Err(format!(
                    "colliders {a} and {b}: held, their boxes overlap, not handed to the engine"
                ));
            }
        }
        if handed != self.handed_count() {
            return Err(format!(
                "{} pairs handed to the engine, {handed} of them held",
                self.handed_count()
            ));
        }
        // Each collider's partners are its handed pairs, each once.
        let mut ends = 0;
        for ka in (0..self.proxies.len() as u32).filter_map(key) {
            let mut others: Vec<Key> = self.partners(ka).collect();
            ends += others.len();
            if let Some(kb) = others.iter().find(|&&kb| !self.has_pair(ka, kb)) {
                return Err(format!("{kb:?} listed as a partner of {ka:?}, not handed"));
            }
            others.sort_unstable();
            if others.windows(2).any(|w| w[0] == w[1]) {
                return Err(format!("{ka:?} has a partner listed twice"));
            }
        }
        if ends != 2 * handed {
            return Err(format!(
                "{ends} partner ends listed for {handed} handed pairs"
            ));
        }
        Ok(())
    }
}
