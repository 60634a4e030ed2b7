//! The audit: the invariants recomputed from scratch.

use super::{BroadPhaseCore, Clock, Proxy};
use crate::pairs::proxies_meet;
use crate::{Bound, ColliderStatus, Engine, Key};
use kinetic_core::{Body, Vec3};

impl BroadPhaseCore {
    /// Recomputes the invariants from scratch, between calls: the structure's own and the
    /// pair book's (kinetic), or every pair of colliders whose boxes overlap handed over
    /// (stepped); every enabled collider of `colliders` (all the engine has) held, and
    /// (kinetic) every moving body within its slack of its plan.
    pub fn validate(
        &self,
        engine: &impl Engine,
        colliders: impl IntoIterator<Item = Key>,
    ) -> Result<(), String> {
        if let Some(st) = &self.stepped {
            self.check_stepped(engine, &st.reported)?;
        } else {
            if let Some(s) = &self.structure {
                s.validate(&self.bodies, self.clock.kds)?;
            }
            self.book
                .audit(true, meet(&self.bodies, self.clock))
                .map_err(|e| format!("{e}; window {} to {}", self.clock.pos, self.clock.kds))?;
        }
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
    /// colliders whose boxes now overlap (the engine's boxes, or a fixed collider's own) are
    /// among them.
    fn check_stepped(&self, engine: &impl Engine, reported: &[(u32, u32)]) -> Result<(), String> {
        if !reported.windows(2).all(|w| w[0] < w[1]) {
            return Err("the stepped pairs are not sorted and distinct".into());
        }
        let boxes: Vec<(u32, (Vec3, Vec3))> = self
            .proxies
            .iter()
            .enumerate()
            .filter_map(|(i, p)| {
                let p = p.as_ref()?;
                let b = match p.hold {
                    Bound::Fixed { min, max } => (min, max),
                    Bound::Moving { .. } => engine.bounds(p.key)?,
                };
                Some((i as u32, b))
            })
            .collect();
        for (k, (a, x)) in boxes.iter().enumerate() {
            for (b, y) in &boxes[k + 1..] {
                let meet = x.0.cmple(y.1).all() && y.0.cmple(x.1).all();
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

/// Whether the proxies of colliders `a` and `b` can meet within the window from the positions'
/// time to the structure's (a missing proxy: yes).
fn meet(bodies: &[Option<Body>], clock: Clock) -> impl Fn(u32, u32) -> bool + '_ {
    move |a, b| match (&bodies[a as usize], &bodies[b as usize]) {
        (Some(x), Some(y)) => proxies_meet(x, y, clock.pos, clock.kds),
        _ => true,
    }
}
