//! The engine's call: the user's changes and the bodies moved, then the structure's events
//! over the coming step and the pairs handed over.

use super::pairs::PairOut;
use super::{BroadPhaseCore, StepStats};
use crate::{Bound, ColliderStatus, Engine, EngineStep, Key, PairEvent};
use kinetic_core::{FlightPlan, Real, Vec3};

impl BroadPhaseCore {
    /// One call of the engine: at the start of a step (the user's changes, positions
    /// unchanged) or after a position update of `step.dt` (the updates of one step together
    /// one step long). `modified`: the colliders added, changed or moved since the last call;
    /// `removed`: those removed (their pairs go without events). The pairs to add and delete
    /// are pushed onto `events`, sorted: the engine's own pairs, those whose boxes as the
    /// engine grows them meet within the step (see `handed.rs`).
    pub fn update(
        &mut self,
        step: EngineStep,
        engine: &impl Engine,
        modified_colliders: &[Key],
        removed_colliders: &[Key],
        events: &mut Vec<PairEvent>,
    ) {
        let mut held = std::mem::take(&mut self.held_events);
        held.clear();
        let starts = !self.clock.in_step;
        self.update_held(
            step,
            engine,
            modified_colliders,
            removed_colliders,
            &mut held,
        );
        let changed = (modified_colliders, removed_colliders);
        self.hand_over(engine, &held, changed, starts, events);
        self.held_events = held;
    }

    /// [`BroadPhaseCore::update`] up to the pairs the broad phase holds: their adds and
    /// deletes go to `events`.
    fn update_held(
        &mut self,
        step: EngineStep,
        engine: &impl Engine,
        modified_colliders: &[Key],
        removed_colliders: &[Key],
        events: &mut Vec<PairEvent>,
    ) {
        let dt = step.dt;
        let starts_step = !self.clock.in_step;
        if starts_step {
            self.clock.dt = dt;
            self.clock.left = dt;
            self.clock.in_step = true;
            self.stats.steps += 1;
            self.step = StepStats::default();
        } else {
            self.clock.pos += dt;
            self.clock.left -= dt;
            self.clock.updates += 1;
            if self.clock.left <= 1e-4 * self.clock.dt {
                self.clock.in_step = false;
            }
        }
        let update = self.clock.updates;
        self.lag_reach = None;
        if !starts_step {
            self.switch_if_due(engine);
        }

        for &h in removed_colliders {
            self.remove_collider(h);
        }

        if self.loose_grid.is_none() {
            // The first colliders tell whether the engine keeps enlarged boxes.
            self.engine_boxes = modified_colliders
                .iter()
                .any(|&h| engine.enlarged(h).is_some());
        }
        let mut new = Vec::new();
        let mut moved: Vec<Key> = Vec::new();
        if self.held == 0 {
            // The first colliders: every one is new, grown for at once.
            new.reserve(modified_colliders.len());
        }
        // A stepped world passes over its bodies only now and then: between, a position
        // update costs one box a moved collider.
        let full = starts_step || self.stepped.as_ref().is_none_or(|st| st.full());
        for &h in modified_colliders {
            if !starts_step {
                // After a position update a held collider has only moved with its body (only
                // the user changes shapes, parents and body types, at the start of a step).
                if let Some(&Some((g, body))) = self.movers.get(h.index as usize)
                    && g == h.generation
                {
                    if body != u32::MAX
                        && let Some(st) = self.stepped.as_mut()
                    {
                        st.mark(h.index);
                        if !full {
                            continue;
                        }
                    }
                    if body != u32::MAX {
                        let (word, bit) = (body as usize / 64, body % 64);
                        if self.moved_bits.len() <= word {
                            self.moved_bits.resize(word + 1, 0);
                        }
                        self.moved_bits[word] |= 1 << bit;
                    }
                    continue;
                }
            }
            let status = if self.engine_boxes {
                engine.collider_on_boxes(h)
            } else {
                engine.collider(h, self.slack)
            };
            let hold = match status {
                ColliderStatus::Missing => continue,
                ColliderStatus::Disabled => {
                    self.remove_collider(h);
                    continue;
                }
                ColliderStatus::Held(hold) => hold,
            };
            if !self.knows(h) {
                new.push((h, hold));
                continue;
            }
            let i = h.index as usize;
            let held = self.proxies[i].expect("known").hold;
            if !held.same(&hold) {
                // A new shape, body or body type: held afresh.
                self.detach(i as u32, false);
                new.push((h, hold));
            } else if let Bound::Moving { body, .. } = hold {
                moved.push(body);
            }
        }

        if let Some(st) = self.stepped.as_mut() {
            st.track_marked(engine, &self.movers);
        }
        // Bodies that moved: what they showed of their acceleration, then their plans.
        let mut seen_moving = 0;
        let step_dt = self.clock.dt.max(dt);
        let substeps = step.substeps;
        for word in 0..self.moved_bits.len() {
            while self.moved_bits[word] != 0 {
                let bits = self.moved_bits[word];
                self.moved_bits[word] = bits & (bits - 1);
                let index = word * 64 + bits.trailing_zeros() as usize;
                let Some(b) = self.motions.key_at(index) else {
                    continue;
                };
                moved.push(b);
            }
        }
        // The engine's states first, in one pass: reads of bodies scattered through the
        // engine's memory overlap when nothing else sits between them.
        let mut states = std::mem::take(&mut self.states);
        states.clear();
        states.reserve(moved.len());
        engine.motions(&moved, &mut states);
        for (k, (&b, &state)) in moved.iter().zip(&states).enumerate() {
            if let Some(&next) = moved.get(k + 4) {
                self.motions.prefetch(next);
            }
            let Some(m) = self.motions.get_mut(b) else {
                continue;
            };
            if m.seen == update && !starts_step {
                continue;
            }
            let Some((centre, v)) = state else { continue };
            if !starts_step {
                if m.seen.wrapping_add(1) == update {
                    let a = (v - m.last_v) / dt;
                    if let Some(prev) = m.last_a {
                        // Equal most often (a body in free flight, unpushed): no roots.
                        let agree = |x: Vec3, y: Vec3| {
                            x == y || (x - y).length() <= 1e-3 * x.length().max(y.length()) + 1e-3
                        };
                        if agree(a, prev) {
                            m.steady_a = a;
                        } else if !agree(a, m.steady_a) && !agree(prev, m.steady_a) {
                            // Two updates running off the steady acceleration: contact forces
                            // (a body resting on others, a pile settling). Plan it coasting,
                            // which a supported body keeps far longer than free fall.
                            m.steady_a = Vec3::ZERO;
                        }
                    }
                    m.last_a = Some(a);
                } else {
                    m.last_a = None;
                }
                m.last_v = v;
                m.seen = update;
            }
            // Most bodies keep their plans or their fat boxes: checked here, with no second
            // look-up of the plan.
            let kept = if m.fat {
                self.keeps_boxes(engine, b, v, step_dt)
            } else {
                m.keeps_plan(centre, v, self.clock.pos, step_dt, substeps)
            };
            if kept {
                let m = &self.motions[b];
                seen_moving += usize::from(m.listed && m.seen == update);
                continue;
            }
            if let Some(resized) = self.refit(b, engine, step, false) {
                self.hold(engine, b, v, resized);
            }
            if self
                .motions
                .get(b)
                .is_some_and(|m| m.listed && m.seen == update)
            {
                seen_moving += 1;
            }
        }
        self.states = states;
        let changed = !new.is_empty() || !removed_colliders.is_empty();
        self.install(&new, engine, step, update);

        // Unless every moving body moved in this update, some went to sleep or stopped.
        if !starts_step && full && seen_moving < self.moving.len() {
            // Bodies that did not move in this update went to sleep or stopped: at rest.
            let mut k = 0;
            while k < self.moving.len() {
                let b = self.moving[k];
                let seen = self.motions.get(b).is_some_and(|m| m.seen == update);
                let state = if seen { None } else { engine.body(b) };
                if let Some(state) = state {
                    let t = self.clock.pos;
                    let m = self.motions.get_mut(b).expect("listed");
                    let x = state.centre;
                    m.plan = FlightPlan::at_rest(x).starting_at(t);
                    m.listed = false;
                    m.last_a = None;
                    self.moving.swap_remove(k);
                    self.hold(engine, b, state.velocity, false);
                } else {
                    k += 1;
                }
            }
            // Proxies grown over a lag the positions have now caught up with.
            let pos = self.clock.pos;
            let proxies = &self.proxies;
            let mut grown = std::mem::take(&mut self.grown);
            grown.sort_unstable();
            grown.dedup();
            let (due, waiting): (Vec<u32>, Vec<u32>) = grown
                .into_iter()
                .filter(|&i| proxies[i as usize].is_some_and(|p| p.grown_until.is_some()))
                .partition(|&i| proxies[i as usize].is_some_and(|p| p.grown_until <= Some(pos)));
            self.grown = waiting;
            for i in due {
                let proxy = self.proxies[i as usize].expect("held");
                self.take_out(i);
                let lag = self.clock.kds > self.clock.pos;
                let grow = if lag {
                    self.lag_growth() + self.own_reach(&proxy.hold)
                } else {
                    0.0
                };
                self.put_in(i, proxy.hold, grow);
                self.book.apply(&mut self.changes, self.clock.kds);
            }
        }

        if self.is_stepped() {
            if !starts_step || changed {
                self.step_pairs(engine, events);
            }
            self.clock.kds = self.clock.pos;
            if !starts_step && !self.clock.in_step {
                self.weigh();
            }
            return;
        }

        // Look ahead over the coming step.
        self.advance(self.clock.pos + self.clock.dt);
        self.adopt(events);

        // The pairs the structure changed since the last call (none: nothing to look at).
        self.book.emit(self.clock.pos, &mut self.out);
        let out = std::mem::take(&mut self.out);
        for &o in &out {
            match o {
                PairOut::Add(a, b) => self.out_event(a, b, true, events),
                PairOut::Delete(a, b) => self.out_event(a, b, false, events),
            }
        }
        self.out = out;
        self.out.clear();
        if !starts_step && !self.clock.in_step {
            self.weigh();
        }
    }

    /// Runs the structure's events up to `t`.
    fn advance(&mut self, t: Real) {
        let Some(s) = self.structure.as_mut() else {
            self.clock.kds = self.clock.kds.max(t);
            return;
        };
        loop {
            let next = s.next_event_time();
            // A NaN time never comes due.
            if next.is_nan() || next > t {
                break;
            }
            s.process_next_event(&self.bodies, &mut self.changes);
            self.book.apply(&mut self.changes, next);
            self.stats.events += 1;
            self.step.events += 1;
            if self.audit && self.audit_error.is_none() {
                let r = s
                    .validate(&self.bodies, next)
                    .and_then(|_| self.book.audit(false));
                if let Err(e) = r {
                    self.audit_error = Some(format!("after the event at {next}: {e}"));
                }
            }
        }
        self.clock.kds = self.clock.kds.max(t);
    }
}
