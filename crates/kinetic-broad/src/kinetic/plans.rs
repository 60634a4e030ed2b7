//! Bodies' flight plans: fitted to the engine's integrator, kept while a body stays within its
//! slack, and the slack grown for a body that keeps re-planning.

use super::{BroadPhaseCore, Motion};
use super::{CALM_UPDATES, MAX_GROWTH, REST_STEPS, RESTLESS_RUN, RESTLESS_UPDATES};
use crate::{BodyState, Bound, Engine, EngineStep, Key, fit_plan};
use kinetic_core::{FlightPlan, Real, Vec3};
use smallvec::SmallVec;

impl Motion {
    /// How much its base slack is grown: `2^growth`.
    pub(super) fn scale(&self) -> Real {
        (1u32 << self.growth) as Real
    }

    /// Its slack now.
    pub(super) fn slack_now(&self) -> Real {
        self.slack * self.scale()
    }

    /// Whether the body, at `x` with velocity `v` at time `t`, keeps its plan: within its
    /// slack of it now, and by the end of the step (`dt`) on the path the engine gives it if
    /// nothing touches it ([`fit_plan`], evaluated without building the plan).
    pub(super) fn keeps_plan(&self, x: Vec3, v: Vec3, t: Real, dt: Real, substeps: Real) -> bool {
        let slack = self.slack_now();
        let slack2 = slack * slack;
        if (x - self.plan.position_at(t)).length_squared() > slack2 {
            return false;
        }
        let (a, end) = (self.steady_a, t + dt);
        let d = end - t;
        let ballistic = x + (v + a * (dt / (2.0 * substeps)) + a * (0.5 * d)) * d;
        (ballistic - self.plan.position_at(end)).length_squared() <= slack2
    }
}

impl BroadPhaseCore {
    /// Starts a motion record for a body seen for the first time, resting where it is.
    pub(super) fn motion_for(&mut self, h: Key, rb: &BodyState, slack: Real) -> &mut Motion {
        let t = self.clock.pos;
        let m = self.motions.get_or_insert_with(h, || Motion {
            plan: FlightPlan::at_rest(rb.centre).starting_at(t),
            slack,
            growth: 0,
            replanned: 0,
            restless: 0,
            colliders: SmallVec::new(),
            last_v: rb.velocity,
            seen: u64::MAX,
            last_a: None,
            steady_a: Vec3::ZERO,
            listed: false,
            fat: false,
        });
        m.slack = m.slack.min(slack);
        m
    }

    /// How far any moving body can go between the positions' time and the structure's clock:
    /// a change made at the positions' time grows its proxy by this (and its own reach) until
    /// the positions catch up. Zero when they are level. Worked out once per call, from the
    /// plans the call started with: a body re-planned during the call is grown by its own
    /// reach, so the pairs between two grown proxies are covered too.
    pub(super) fn lag_growth(&mut self) -> Real {
        let lag = self.clock.kds - self.clock.pos;
        if lag <= 0.0 {
            return 0.0;
        }
        if let Some(g) = self.lag_reach {
            return g;
        }
        let g = self
            .moving
            .iter()
            .map(|b| reach_over(&self.motions[*b].plan, self.clock.pos, lag))
            .fold(0.0, Real::max);
        self.lag_reach = Some(g);
        g
    }

    pub(super) fn own_reach(&self, hold: &Bound) -> Real {
        let lag = self.clock.kds - self.clock.pos;
        match *hold {
            Bound::Moving { body, .. } if lag > 0.0 => {
                reach_over(&self.motions[body].plan, self.clock.pos, lag)
            }
            _ => 0.0,
        }
    }

    /// Fits body `h` a new plan at the positions' time: called for a body that left its
    /// slack ([`Motion::keeps_plan`], checked by the caller) or, `first`, one seen for the
    /// first time (which does not count as a re-plan towards its slack growing). Returns
    /// whether the slack changed with it (and so the size of the body's proxies); `None`
    /// for a body the engine no longer has.
    pub(super) fn refit(
        &mut self,
        h: Key,
        engine: &impl Engine,
        step: EngineStep,
        first: bool,
    ) -> Option<bool> {
        let rb = engine.body(h)?;
        Some(self.refit_to(h, &rb, step, first))
    }

    /// [`BroadPhaseCore::refit`] for body `h` in state `rb`, as the engine gives it now.
    pub(super) fn refit_to(
        &mut self,
        h: Key,
        rb: &BodyState,
        step: EngineStep,
        first: bool,
    ) -> bool {
        let t = self.clock.pos;
        let dt = self.clock.dt.max(step.dt);
        let m = self.motions.get_mut(h).expect("a motion");
        let (x, v) = (rb.centre, rb.velocity);
        let substeps = step.substeps;
        // Where the engine will put it by the end of the step if nothing touches it.
        let ballistic = fit_plan(x, v, m.steady_a, t, dt, substeps);
        // A body that sleeps, or would stay within half its slack for the next
        // REST_STEPS steps (one resting in a pile), is planned at rest: its box ends then
        // stay put instead of swapping back and forth with its neighbours' as it jitters.
        let horizon = REST_STEPS * dt;
        let drift = ballistic.velocity.length() * horizon
            + ballistic.acceleration.length() * horizon * horizon / 2.0;
        // A body re-planned again soon after the last is given more slack; one that kept its
        // plan a long while, less.
        let update = self.clock.updates;
        let since = update.saturating_sub(m.replanned);
        let mut growth = m.growth;
        if !first {
            m.restless = if since <= RESTLESS_UPDATES {
                m.restless + 1
            } else {
                0
            };
            if m.restless >= RESTLESS_RUN {
                growth = (growth + 1).min(MAX_GROWTH);
                m.restless = 0;
            } else if since >= CALM_UPDATES {
                growth = growth.saturating_sub(1);
            }
        }
        let resized = growth != m.growth;
        if growth > m.growth {
            self.stats.slack_growths += 1;
        } else if growth < m.growth {
            self.stats.slack_shrinks += 1;
        }
        m.growth = growth;
        m.replanned = update;
        let plan = if rb.sleeping || drift <= m.slack_now() / 2.0 {
            FlightPlan::at_rest(x).starting_at(t)
        } else {
            ballistic
        };
        m.plan = plan;
        if !m.at_rest() && !m.listed {
            m.listed = true;
            self.moving.push(h);
        }
        resized
    }

    /// Gives the structure body `h`'s new plan for each of its colliders; `resized`: with
    /// proxies of a new size (its slack changed).
    pub(super) fn replan(&mut self, h: Key, resized: bool) {
        self.stats.replans += 1;
        self.step.replans += 1;
        let level = self.clock.kds == self.clock.pos;
        let grow = if level { 0.0 } else { self.lag_growth() };
        let plan = self.motions[h].plan;
        for i in self.motions[h].colliders.clone() {
            // A collider held by a fat box keeps it whatever the plan.
            let Some(proxy) = self.proxies[i as usize].filter(|p| p.fat.is_none()) else {
                continue;
            };
            if level && proxy.grown_until.is_none() && !resized {
                let body = self.bodies[i as usize].as_mut().expect("held");
                body.plan = plan;
                self.plans[i as usize] = self.plans[i as usize].wrapping_add(1);
                if let Some(s) = self.structure.as_mut() {
                    s.replan(i, &self.bodies, self.clock.kds, &mut self.changes);
                }
            } else {
                self.take_out(i);
                let own = self.own_reach(&proxy.hold);
                let g = if level { 0.0 } else { grow + own };
                self.put_in(i, proxy.hold, g);
            }
            self.book.apply(&mut self.changes, self.clock.kds);
        }
    }
}

/// How far a body on `plan` can get from where it is at `t` within `lag`.
fn reach_over(plan: &FlightPlan, t: Real, lag: Real) -> Real {
    plan.velocity_at(t).length() * lag + plan.acceleration.length() * lag * lag / 2.0
}
