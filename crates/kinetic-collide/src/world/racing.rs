//! A world on its default structure chooses by measuring, as a run of the tool does: its
//! [`World::advance_to`] races the structures the model shortlists on slices of the world's
//! own simulated time ([`Race::open`]), keeps the fastest, and checks again at growing
//! intervals.
//!
//! The world starts on the adaptive structure ([`Auto`]), which the race names by what it
//! holds (the brute force, the loose grid, the grid or the sweep). A trial hands the objects
//! to another structure and back when it loses; every structure gives the same events, so
//! the log does not change. What the trials cost (builds, rebuilds, time beyond the leader's
//! pace) stays within a share of the time `advance_to` has taken so far, so within that
//! share of the whole run however long the world is used. Events processed by
//! [`World::step`] are timed too, but the race moves on only in `advance_to`.

use super::World;
use crate::structures::{Auto, BRUTE_FORCE_TRIAL_MAX, Race, Slice, Structure, build_cost};
use kinetic_core::{Real, Response, Shape, WorldError};
use std::time::{Duration, Instant};

/// The race of a world on its default structure.
#[derive(Debug)]
pub(super) struct Racing {
    /// Made at the first advance that moves the clock.
    race: Option<Race>,
    /// What the adaptive structure held when the race began: a switch to it builds the
    /// adaptive structure again.
    pick: Structure,
    /// The slice in progress: where it began, and the wall seconds run on it so far.
    from: Real,
    wall: f64,
}

impl Racing {
    /// A race not yet begun, for a world on the adaptive structure.
    pub(super) fn new() -> Racing {
        Racing {
            race: None,
            pick: Structure::BruteForce,
            from: 0.0,
            wall: 0.0,
        }
    }

    /// Counts `wall` seconds of events processed by [`World::step`] in the slice.
    pub(super) fn stepped(&mut self, wall: f64) {
        self.wall += wall;
    }

    /// The slices run so far, the one in progress (up to `now`, on `current`) last.
    pub(super) fn slices(&self, current: Structure, now: Real) -> Vec<Slice> {
        let Some(race) = &self.race else {
            return Vec::new();
        };
        let mut slices = race.slices().to_vec();
        if now > self.from {
            slices.push(Slice {
                structure: current,
                from: self.from,
                to: now,
                wall_seconds: self.wall,
                build_seconds: 0.0,
            });
        }
        slices
    }
}

impl World {
    /// [`World::advance_to`] in the race's slices: each slice timed (a slice may span several
    /// calls), and the objects handed to the structure the race names after it.
    pub(super) fn advance_racing(
        &mut self,
        racing: &mut Racing,
        t: Real,
    ) -> Result<(), WorldError> {
        let now = self.inner.now();
        if t.is_nan() || t <= now {
            return self.inner.advance_to(t);
        }
        let race =
            match &mut racing.race {
                Some(race) => race,
                None => {
                    let name = self.inner.structure_name();
                    racing.pick = Structure::from_name(name).unwrap_or(Structure::BruteForce);
                    racing.from = now;
                    racing.wall = 0.0;
                    // Balls moving linearly through each other: one exact certificate a pair.
                    let passing =
                        self.inner.response() == Response::None
                            && self.inner.bodies().iter().flatten().all(|b| {
                                matches!(b.shape, Shape::Ball { .. }) && b.plan.degree() <= 1
                            });
                    let spread = crate::scene::radius_spread(
                        self.inner
                            .bodies()
                            .iter()
                            .flatten()
                            .map(|b| b.shape.outer_radius()),
                    );
                    let race = Race::open(racing.pick, self.inner.len(), spread, passing, t - now);
                    racing.race.insert(race)
                }
            };
        loop {
            let planned = race.slice_end(racing.from);
            let now = self.inner.now();
            // Events processed by `step` may have passed the slice's end: it ends now.
            if planned > now {
                let end = planned.min(t);
                let deadline = race.wall_limit(planned).map(|limit| {
                    Instant::now() + Duration::from_secs_f64((limit - racing.wall).max(0.0))
                });
                let start = Instant::now();
                let reached = self.advance_within(end, deadline)?;
                racing.wall += start.elapsed().as_secs_f64();
                if reached && end < planned {
                    // The slice goes on at the next call.
                    return Ok(());
                }
            } else if now <= racing.from {
                // No slice ahead (it cannot happen: a slice has a length): no more racing.
                return self.inner.advance_to(t);
            }
            // The slice ends: where planned, or where a trial passed its wall-clock limit.
            let to = self.inner.now();
            let stats = self.inner.stats();
            let pairs = stats.events_by_kind.get("collision").copied().unwrap_or(0);
            race.contact_share(pairs as f64 / stats.events_total().max(1) as f64);
            let world: &World = self;
            let next = race.slice_done(racing.from, to, racing.wall, &mut |s, worth| {
                if s == Structure::BruteForce && world.len() > BRUTE_FORCE_TRIAL_MAX {
                    // Its pairs would take gigabytes before a measurement could stop them.
                    f64::INFINITY
                } else {
                    build_cost(world, s, 0.0, worth)
                }
            });
            racing.from = to;
            racing.wall = 0.0;
            if let Some(next) = next {
                let build = Instant::now();
                if next == racing.pick {
                    let auto = Auto::new();
                    self.inner.replace_structure(Box::new(auto));
                } else {
                    self.hand_to(next, 0.0)?;
                }
                race.switched(build.elapsed().as_secs_f64());
            }
            if to >= t {
                return self.inner.advance_to(t);
            }
        }
    }

    /// Processes every event up to `t` and moves the clock there, or stops between two
    /// instants (the clock at the last event) once the wall clock passes `deadline`, looked
    /// at every 64 instants: whether it reached `t`.
    fn advance_within(&mut self, t: Real, deadline: Option<Instant>) -> Result<bool, WorldError> {
        let Some(deadline) = deadline else {
            self.inner.advance_to(t)?;
            return Ok(true);
        };
        let mut looked = 0u32;
        while self.inner.step(t)?.is_some() {
            // A slice ends only between instants, so ties keep their order.
            if self.inner.next_event_time() <= self.inner.now() {
                continue;
            }
            looked += 1;
            if looked >= 64 {
                looked = 0;
                if Instant::now() >= deadline {
                    return Ok(false);
                }
            }
        }
        self.inner.advance_to(t)?;
        Ok(true)
    }
}
