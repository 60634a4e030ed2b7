//! Choosing by measuring: a run on the default structure races the shortlisted structures on
//! slices of its own simulated time, keeps the fastest, and checks again at growing intervals.
//!
//! Every structure gives the same log (the world hands its objects from one to another
//! without an event, [`crate::World::switch_structure`]), so a trial is never wasted: each
//! slice a structure runs is part of the run. What a trial costs is the difference: its
//! build, the rebuild of the structure it is measured against when it loses, and its time
//! beyond what the leader would have taken on the same slice. Those are kept within
//! [`SHARE`] of the run's projected time, and a trial running past [`ABORT`] times the
//! leader's pace is cut short (it has lost).
//!
//! The rates compared are wall seconds per unit of simulated time, measured on adjacent
//! slices; a scene whose work moves along its horizon is measured again at each check.

use super::Structure;
use crate::scene::Scene;
use kinetic_core::WorldKind;

/// The share of the run's projected wall time the trials may cost (builds, rebuilds and
/// time beyond the leader's pace).
pub(crate) const SHARE: f64 = 0.05;

/// A trial running slower than this many times the leader's pace stops there: it has lost.
pub(crate) const ABORT: f64 = 2.0;

/// A structure replaces the leader only when it is faster by more than this share (the
/// margin keeps timing noise from switching back and forth).
const MARGIN: f64 = 0.05;

/// The least wall time a measurement takes, in seconds: shorter ones are mostly noise.
const LEAST_WALL: f64 = 0.005;

/// The share of the horizon the first slice covers; slices double until one takes
/// [`LEAST_WALL`].
const FIRST_SLICE: f64 = 1.0 / 4096.0;

/// The brute force is raced only up to this many objects (its pairs grow as the square).
const BRUTE_FORCE_MAX: usize = 1500;

/// One slice of a run and the structure that ran it.
#[derive(Clone, Debug, PartialEq)]
pub struct Slice {
    /// The structure.
    pub structure: Structure,
    /// The simulated times it ran from and to.
    pub from: f64,
    /// See `from`.
    pub to: f64,
    /// Wall seconds of the slice, the structure's build (when the slice began with one)
    /// included.
    pub wall_seconds: f64,
    /// Wall seconds of the build that began the slice (0 for none).
    pub build_seconds: f64,
}

/// What the race is doing.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Phase {
    /// Measuring the leader's pace.
    Pace,
    /// Trying a structure against the leader.
    Trial,
    /// Running on the leader until the next check.
    Settled,
}

/// The race of one run.
#[derive(Debug)]
pub(crate) struct Race {
    horizon: f64,
    phase: Phase,
    /// The structure running now, and the fastest measured.
    current: Structure,
    leader: Structure,
    /// Wall seconds per unit of simulated time of the leader, as last measured.
    pace: f64,
    /// The structures still to try, in order, and the runner-up's pace when known.
    to_try: Vec<Structure>,
    paces: Vec<(Structure, f64)>,
    /// The simulated time and wall seconds measured so far in this phase.
    measured_from: f64,
    measured_wall: f64,
    /// The slice length in simulated time.
    slice: f64,
    /// The trials' cost so far, and what they may cost.
    spent: f64,
    budget: f64,
    /// The simulated time of the next check once settled.
    next_check: f64,
    /// The build that began the current slice, to note on it.
    build: f64,
    slices: Vec<Slice>,
}

impl Race {
    /// A race for `scene` starting on `pick`, which took `build_seconds` to build: the
    /// structures that may beat it are the other box structures that run in its world, and
    /// the brute force for up to [`BRUTE_FORCE_MAX`] objects. An empty shortlist makes a run
    /// on `pick` alone.
    pub(crate) fn new(scene: &Scene, pick: Structure, build_seconds: f64) -> Race {
        let mut shortlist = vec![Structure::LooseGrid, Structure::Grid, Structure::Sweep];
        if scene.objects.len() <= BRUTE_FORCE_MAX {
            shortlist.push(Structure::BruteForce);
        }
        let to_try = if pick.runs_in_a_world() && scene.periodic.is_none() {
            shortlist
                .into_iter()
                .filter(|&s| s != pick && s.applies_to(scene))
                .filter(|&s| scene.world == WorldKind::Free || s != Structure::Guards)
                .collect()
        } else {
            Vec::new()
        };
        let horizon = scene.horizon;
        Race {
            horizon,
            phase: if to_try.is_empty() {
                Phase::Settled
            } else {
                Phase::Pace
            },
            current: pick,
            leader: pick,
            pace: f64::NAN,
            to_try,
            paces: Vec::new(),
            measured_from: 0.0,
            measured_wall: 0.0,
            slice: horizon * FIRST_SLICE,
            spent: 0.0,
            budget: 0.0,
            next_check: f64::INFINITY,
            build: build_seconds,
            slices: Vec::new(),
        }
    }

    /// The structure running now.
    pub(crate) fn current(&self) -> Structure {
        self.current
    }

    /// Where the slice starting at `now` ends (the horizon once settled for good).
    pub(crate) fn slice_end(&self, now: f64) -> f64 {
        let end = match self.phase {
            Phase::Settled => self.next_check,
            Phase::Pace => now + self.slice,
            // In quarters, so that a slow trial is cut short.
            Phase::Trial => (now + self.slice / 4.0).min(self.measured_from + self.slice),
        };
        end.min(self.horizon)
    }

    /// The slice from `from` to `to` took `wall` seconds on the current structure (its build
    /// excluded). Returns the structure to switch to, if any.
    pub(crate) fn slice_done(&mut self, from: f64, to: f64, wall: f64) -> Option<Structure> {
        self.slices.push(Slice {
            structure: self.current,
            from,
            to,
            wall_seconds: wall + self.build,
            build_seconds: self.build,
        });
        self.build = 0.0;
        self.measured_wall += wall;
        let span = to - self.measured_from;
        if to >= self.horizon || span <= 0.0 {
            return None;
        }
        match self.phase {
            Phase::Pace => {
                if self.measured_wall < LEAST_WALL {
                    self.slice *= 2.0;
                    return None;
                }
                self.pace = self.measured_wall / span;
                // The trials may cost a share of what the rest of the run will take.
                self.budget = SHARE * self.pace * self.horizon;
                // A trial slice is as long as the leader took LEAST_WALL to run, or longer
                // when the budget allows: four times as long as measured, a share of each
                // trial's budget.
                let per_trial = self.budget / self.to_try.len() as f64;
                self.slice = (span).max((per_trial / (ABORT * self.pace)).min(4.0 * span));
                self.next_trial()
            }
            Phase::Trial => {
                let pace = self.measured_wall / span;
                let done = span >= self.slice * (1.0 - 1e-9);
                if !done && pace <= ABORT * self.pace {
                    return None;
                }
                // Over the leader's pace on the same slice: what the trial cost.
                self.spent += (self.measured_wall - self.pace * span).max(0.0);
                self.paces.retain(|&(s, _)| s != self.current);
                self.paces.push((self.current, pace));
                let trial = self.current;
                if pace < self.pace * (1.0 - MARGIN) {
                    self.leader = trial;
                    self.pace = pace;
                    self.next_trial()
                } else {
                    match self.next_trial() {
                        Some(next) => Some(next),
                        None => {
                            // Back to the leader: a rebuild.
                            self.current = self.leader;
                            Some(self.leader)
                        }
                    }
                }
            }
            Phase::Settled => {
                // A check: the leader's pace since the last one, then a trial of the
                // runner-up if the budget allows.
                self.pace = self.measured_wall / span;
                self.budget = self.budget.max(SHARE * self.pace * self.horizon);
                self.next_check =
                    (to + 3.0 * (to - self.measured_from).max(self.slice)).min(self.horizon);
                self.paces.sort_by(|a, b| a.1.total_cmp(&b.1));
                if let Some(&(runner_up, _)) = self.paces.iter().find(|p| p.0 != self.leader) {
                    self.to_try = vec![runner_up];
                }
                self.next_trial()
            }
        }
    }

    /// The next structure to try, when the budget allows; otherwise settles on the leader.
    fn next_trial(&mut self) -> Option<Structure> {
        self.measured_wall = 0.0;
        let now = self.slices.last().map_or(0.0, |s| s.to);
        self.measured_from = now;
        // A trial costs at most its build, the rebuild of the leader and ABORT - 1 times the
        // leader's time on its slice; builds are guessed from the one slice's cost.
        let worst = (ABORT - 1.0) * self.pace * self.slice + 2.0 * self.last_build();
        if !self.to_try.is_empty() && self.spent + worst <= self.budget {
            let next = self.to_try.remove(0);
            self.phase = Phase::Trial;
            self.current = next;
            return Some(next);
        }
        self.to_try.clear();
        self.phase = Phase::Settled;
        if !self.next_check.is_finite() || self.next_check <= now {
            self.next_check = (now + 3.0 * now.max(self.slice)).min(self.horizon);
        }
        None
    }

    /// The longest build measured so far (0 before any).
    fn last_build(&self) -> f64 {
        self.slices
            .iter()
            .map(|s| s.build_seconds)
            .fold(0.0, f64::max)
    }

    /// The switch the race asked for took `build` wall seconds.
    pub(crate) fn switched(&mut self, build: f64) {
        self.spent += build;
        self.build = build;
    }

    /// The slices run, in order.
    pub(crate) fn into_slices(self) -> Vec<Slice> {
        self.slices
    }
}
