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
use super::cost::LOOSE_SPREAD;
use crate::scene::Scene;
use kinetic_core::Response;
use std::time::Instant;

/// The share of the run's projected wall time the trials may cost (builds, rebuilds and
/// time beyond the leader's pace).
pub(crate) const SHARE: f64 = 0.1;

/// A trial running slower than this many times the leader's pace stops there: it has lost.
pub(crate) const ABORT: f64 = 2.0;

/// A structure replaces the leader only when it is faster by more than this share (the
/// margin keeps timing noise from switching back and forth).
const MARGIN: f64 = 0.05;

/// At a check, the runner-up is tried again only if it ran within this many times the
/// leader's pace now (chosen, not fitted: the pace at which a trial is cut short, so one
/// that would be cut short again is not tried).
const RETRY_WITHIN: f64 = ABORT;

/// A trial's estimated build counts this many times against the budget: estimates scaled
/// by the start's ([`Race::sample_scale`]) came within 1.3x of the builds then measured (the
/// grid and the loose grid on 53,990 and 67,608 balls).
const BUILD_SPREAD: f64 = 1.5;

/// The least wall time a measurement takes, in seconds: shorter ones are mostly noise.
const LEAST_WALL: f64 = 0.001;

/// Two slices' paces within this share of each other are the structure's steady pace.
const STEADY: f64 = 0.25;

/// The share of the horizon the first slice covers; slices double until the leader's pace is
/// measured.
const FIRST_SLICE: f64 = 1.0 / 4096.0;

/// The brute force is never tried above this many objects: its pairs (4.5 million here)
/// would take gigabytes before any measurement could stop them.
pub(crate) const BRUTE_FORCE_TRIAL_MAX: usize = 3000;

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

/// A trial's pace over its last two slices: steady where they agree, else the last one's.
#[derive(Clone, Copy, Debug)]
enum Trend {
    Steady(f64),
    Moving(f64),
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

/// The structures that may beat `pick` in a world of `objects` objects whose outer radii
/// spread by `spread`: the other box structures and the brute force (up to
/// [`BRUTE_FORCE_TRIAL_MAX`] objects), the grid first (it holds any spread of sizes at a
/// small cost per object), the loose grid only for sizes within [`LOOSE_SPREAD`] (beyond, a
/// few large objects hold regions that every other region checks, and its build grows with
/// their number times all the objects, which a sample does not show: 49,367 balls of sizes
/// 1:945 on a plane, estimated at 0.08 s, took 4.8 s to build, half the grid's whole run).
/// None for a hard-sphere simulator, which runs alone.
fn shortlist(pick: Structure, objects: usize, spread: f64) -> Vec<Structure> {
    if !pick.runs_in_a_world() {
        return Vec::new();
    }
    [
        Structure::Grid,
        Structure::LooseGrid,
        Structure::Sweep,
        Structure::BruteForce,
    ]
    .into_iter()
    .filter(|&s| s != pick)
    .filter(|&s| s != Structure::BruteForce || objects <= BRUTE_FORCE_TRIAL_MAX)
    .filter(|&s| s != Structure::LooseGrid || spread <= LOOSE_SPREAD)
    .collect()
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
    /// The structures passed over for the budget: tried at a later check, when the run
    /// has grown.
    untried: Vec<Structure>,
    paces: Vec<(Structure, f64)>,
    /// The pace of the last slice measured for the leader's pace (NaN for none).
    last_pace: f64,
    /// The simulated time and wall seconds measured so far in this phase.
    measured_from: f64,
    measured_wall: f64,
    /// The slice length in simulated time.
    slice: f64,
    /// The trials' cost so far.
    spent: f64,
    /// The simulated time of the next check once settled.
    next_check: f64,
    /// The build that began the current slice, to note on it.
    build: f64,
    /// What each structure's build costs: measured where it was built, else estimated on a
    /// sample ([`super::build_cost`]) when first needed.
    builds: Vec<(Structure, f64)>,
    /// Balls moving linearly pass through each other (no response): each pair is one exact
    /// certificate, so the brute force's events are the contacts alone, which every
    /// structure processes too. (Cuboids, hulls and accelerations re-certify their pairs as
    /// they close in: 170 cuboids ran 2x slower on the brute force than on the grid.)
    passing: bool,
    /// The share of pair events among the run's events so far.
    contact_share: f64,
    slices: Vec<Slice>,
    /// The structure the run started on and its build, measured.
    start: (Structure, f64),
    /// A whole build's cost over its sample's ([`Race::sample_scale`]), once known.
    sample_scale: Option<f64>,
    /// The slice the current trial was set, restored after it.
    base_slice: Option<f64>,
}

impl Race {
    /// A race for `scene` starting on `pick`, which took `build_seconds` to build: the
    /// structures that may beat it are the other box structures that run in its world and
    /// the brute force. An empty shortlist makes a run on `pick` alone.
    pub(crate) fn new(scene: &Scene, pick: Structure, build_seconds: f64) -> Race {
        let to_try = if pick.runs_in_a_world() && scene.periodic.is_none() {
            // The model shortlists: not the sweep where it would do far more than the grid.
            let share = Structure::sweep_share(scene, super::scene_measures::crossings(scene));
            shortlist(pick, scene.objects.len(), scene.size_ratio())
                .into_iter()
                .filter(|&s| s.applies_to(scene))
                .filter(|&s| s != Structure::Sweep || super::cost::sweep_worth_trying(share))
                .collect()
        } else {
            Vec::new()
        };
        let horizon = scene.horizon;
        let passing =
            scene.response == Response::None && !super::scene_measures::heavy_pairs(scene);
        Race::with(
            to_try,
            horizon,
            horizon * FIRST_SLICE,
            passing,
            pick,
            build_seconds,
        )
    }

    /// A race with no horizon, for a world advanced call by call: it starts on `pick` (the
    /// world's adaptive structure, named by what it holds now) with a first slice of
    /// `first_slice` units of simulated time, and weighs the other box structures and the
    /// brute force as [`Race::new`] does (`spread`: the objects' outer radii, largest over
    /// smallest). Its budget is [`SHARE`] of twice the run so far (at
    /// the leader's pace: the world is taken to run at least as long again) where a run's is
    /// a share of its horizon. The checks come at growing intervals, so what the trials cost
    /// stays within twice that share of the whole run, however long.
    pub(crate) fn open(
        pick: Structure,
        objects: usize,
        spread: f64,
        passing: bool,
        first_slice: f64,
    ) -> Race {
        let to_try = shortlist(pick, objects, spread);
        Race::with(to_try, f64::INFINITY, first_slice, passing, pick, 0.0)
    }

    fn with(
        to_try: Vec<Structure>,
        horizon: f64,
        slice: f64,
        passing: bool,
        pick: Structure,
        build_seconds: f64,
    ) -> Race {
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
            untried: Vec::new(),
            paces: Vec::new(),
            last_pace: f64::NAN,
            measured_from: 0.0,
            measured_wall: 0.0,
            slice,
            spent: 0.0,
            next_check: f64::INFINITY,
            build: build_seconds,
            builds: vec![(pick, build_seconds)],
            passing,
            contact_share: 1.0,
            slices: Vec::new(),
            start: (pick, build_seconds),
            sample_scale: None,
            base_slice: None,
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

    /// The wall seconds the slice starting now and planned to end at `to` may take, or
    /// `None` for no limit: a trial is stopped where it passes [`ABORT`] times the leader's
    /// pace over what it has run (it has lost), however slow it is (a grid 100 times slower
    /// than the loose grid on 54,000 balls on a plane would otherwise run its whole slice).
    /// The leader's pace is measured until it has run as long as its build took (at least
    /// [`LEAST_WALL`]), and a slice stops there: the first slices are shares of the horizon,
    /// and on a structure far slower than the others one can take many times its build (a
    /// sweep on 67,609 balls with bullets among them: 4.2 s on its first slice after a build
    /// of 0.39 s, where the loose grid ran the whole run in 17 s).
    pub(crate) fn wall_limit(&self, to: f64) -> Option<f64> {
        match self.phase {
            Phase::Trial if self.pace.is_finite() => {
                let allowed = ABORT * self.pace * (to - self.measured_from) - self.measured_wall;
                Some(allowed.max(LEAST_WALL))
            }
            Phase::Pace => {
                let built = self.known_build(self.leader).unwrap_or(0.0).max(LEAST_WALL);
                Some((built - self.measured_wall).max(LEAST_WALL))
            }
            _ => None,
        }
    }

    /// The slice from `from` to `to` took `wall` seconds on the current structure (its build
    /// excluded). Returns the structure to switch to, if any. `build_cost` estimates what a
    /// structure's build would cost (see [`super::build_cost`]), called once a structure,
    /// when it is weighed, with the most that build may cost and be tried.
    pub(crate) fn slice_done(
        &mut self,
        from: f64,
        to: f64,
        wall: f64,
        build_cost: &mut dyn FnMut(Structure, f64) -> f64,
    ) -> Option<Structure> {
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
                // The leader's pace is measured on doubling slices, over LEAST_WALL at least,
                // until two in a row agree (its first milliseconds, cold caches and a queue
                // still growing, can run at half its pace), or it has run as long as its
                // build took (a structure whose work comes in bursts).
                let pace = wall / (to - from).max(f64::MIN_POSITIVE);
                let last = std::mem::replace(&mut self.last_pace, pace);
                let steady = (pace - last).abs() <= STEADY * last;
                let built = self.known_build(self.leader).unwrap_or(0.0);
                if self.measured_wall < LEAST_WALL || !(steady || self.measured_wall >= built) {
                    self.slice *= 2.0;
                    return None;
                }
                // Steady, the latest slice's pace (warm); else the pace over all of them.
                self.pace = if steady {
                    pace
                } else {
                    self.measured_wall / span
                };
                // A trial slice is as long as the leader took LEAST_WALL to run, or longer
                // when the budget allows: four times as long as measured, a share of each
                // trial's budget.
                let per_trial = self.budget() / self.to_try.len() as f64;
                self.slice = (span).max((per_trial / (ABORT * self.pace)).min(4.0 * span));
                self.next_trial(build_cost)
            }
            Phase::Trial => {
                let pace = self.measured_wall / span;
                // A trial is measured over LEAST_WALL at least: a structure whose work comes
                // in bursts (the grids re-file each object after its least flight) may do
                // nothing on a short slice after its build.
                let done = span >= self.slice * (1.0 - 1e-9);
                if done && self.measured_wall < LEAST_WALL {
                    self.slice *= 2.0;
                    return None;
                }
                if !done && pace <= ABORT * self.pace {
                    return None;
                }
                // A trial that ran its slice is judged by its steady pace: a structure built
                // afresh has its certificates fresh, and one whose certificates last a while
                // (a loose grid's regions, a grid's cells for a least flight) does almost
                // nothing until the first of them fail (a loose grid on 53,990 balls ran its
                // first three quarters at a fortieth of its pace, its fourth at a third).
                let (pace, trusted) = if done {
                    match self.trial_pace() {
                        Trend::Steady(steady) => (steady, true),
                        Trend::Moving(_) if self.may_extend(span) => {
                            self.slice *= 2.0;
                            return None;
                        }
                        // Not steady within the budget: no ground to leave the leader.
                        Trend::Moving(last) => (last.max(pace), false),
                    }
                } else {
                    (pace, true)
                };
                // The next trial's slice is this one's as it was set, not as it was cut to
                // fit or doubled while the trial was not steady.
                if let Some(base) = self.base_slice.take() {
                    self.slice = base;
                }
                // Over the leader's pace on the same slice: what the trial cost.
                self.spent += (self.measured_wall - self.pace * span).max(0.0);
                self.paces.retain(|&(s, _)| s != self.current);
                self.paces.push((self.current, pace));
                let trial = self.current;
                if trusted && pace < self.pace * (1.0 - MARGIN) {
                    // The leader it beat stays a runner-up, at the pace it last ran: a trial
                    // measured on a later slice than the leader may have met lighter work,
                    // and the checks try the runner-up again.
                    let beaten = (self.leader, self.pace);
                    self.paces.retain(|&(s, _)| s != beaten.0);
                    self.paces.push(beaten);
                    self.leader = trial;
                    self.pace = pace;
                    self.next_trial(build_cost)
                } else {
                    match self.next_trial(build_cost) {
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
                // runner-up if the budget allows. Timed over LEAST_WALL at least: a check
                // that falls just after a trial ended (a slice a rounding long, its wall
                // the timer's own cost) would otherwise take a pace millions of times the
                // leader's, and any structure would beat it.
                if self.measured_wall < LEAST_WALL {
                    self.next_check = (to + self.slice).min(self.horizon);
                    return None;
                }
                self.pace = self.measured_wall / span;
                self.next_check =
                    (to + 3.0 * (to - self.measured_from).max(self.slice)).min(self.horizon);
                self.paces.sort_by(|a, b| a.1.total_cmp(&b.1));
                self.to_try = std::mem::take(&mut self.untried);
                // The runner-up, unless it ran far slower than the leader runs now: paces
                // move along a run by tens of percent, not by orders (a grid at 300 times the
                // loose grid's pace would cost its build and the leader's rebuild again).
                let runner_up = self.paces.iter().find(|p| p.0 != self.leader);
                if let Some(&(runner_up, pace)) = runner_up
                    && pace <= RETRY_WITHIN * self.pace
                {
                    self.to_try.push(runner_up);
                }
                if !self.horizon.is_finite() && self.pace > 0.0 && !self.to_try.is_empty() {
                    // With no horizon the budget grows with the run: each trial's slice is
                    // what half its share of the budget left runs at the abort pace (the
                    // other half for builds), and at least a measurement's worth.
                    let share = (self.budget() - self.spent).max(0.0) / self.to_try.len() as f64;
                    self.slice = (share / (2.0 * ABORT * self.pace)).max(LEAST_WALL / self.pace);
                }
                self.next_trial(build_cost)
            }
        }
    }

    /// The trial's pace over its last two slices, and whether they agree (within
    /// [`STEADY`]); a trial of one slice is steady at its pace.
    fn trial_pace(&self) -> Trend {
        let own = |s: &&Slice| s.structure == self.current && s.from >= self.measured_from;
        let mut last = self.slices.iter().rev().take_while(own);
        let pace = |s: &Slice| (s.wall_seconds - s.build_seconds, s.to - s.from);
        let Some((w4, s4)) = last.next().map(pace) else {
            return Trend::Steady(self.measured_wall / self.slice);
        };
        let Some((w3, s3)) = last.next().map(pace) else {
            return Trend::Steady(w4 / s4);
        };
        let (p3, p4) = (w3 / s3, w4 / s4);
        if (p4 - p3).abs() <= STEADY * p3 {
            Trend::Steady((w3 + w4) / (s3 + s4))
        } else {
            Trend::Moving(p4)
        }
    }

    /// Whether a trial that has run `span` may run as long again: its time beyond the
    /// leader's pace so far and on the doubled slice, and the leader's rebuild, fit what is
    /// left of the budget.
    fn may_extend(&self, span: f64) -> bool {
        let beyond = (self.measured_wall - self.pace * span).max(0.0);
        let more = (ABORT - 1.0) * self.pace * self.slice;
        let leader = self.known_build(self.leader).unwrap_or(0.0);
        self.spent + beyond + more + leader <= self.budget()
    }

    /// The next structure to try, when the budget allows; otherwise settles on the leader.
    fn next_trial(
        &mut self,
        build_cost: &mut dyn FnMut(Structure, f64) -> f64,
    ) -> Option<Structure> {
        self.measured_wall = 0.0;
        let now = self.slices.last().map_or(0.0, |s| s.to);
        self.measured_from = now;
        // A trial costs at most its build, the rebuild of the leader and ABORT - 1 times the
        // leader's time on its slice.
        let run = (ABORT - 1.0) * self.pace * self.slice;
        // The least a trial's run may cost: a slice the leader runs in LEAST_WALL a quarter.
        let least = ((ABORT - 1.0) * 4.0 * LEAST_WALL).min(run);
        while !self.to_try.is_empty() {
            let next = self.to_try.remove(0);
            // A trial costs at least its run and the leader's rebuild: where those do not fit
            // what is left of the budget, its build is not even estimated (an estimate costs
            // a sample's build), unless it may pay back its build outside the budget.
            let leader = self.known_build(self.leader).unwrap_or(0.0);
            let paid_back = match self.known_build(next) {
                Some(build) => self.pays_back(next, build, now),
                None => next == Structure::BruteForce && self.passing,
            };
            if !paid_back && self.spent + least + leader > self.budget() {
                self.untried.push(next);
                continue;
            }
            // The most its build may cost and be tried, paid back or within the budget: an
            // estimate may stop short once it passes that.
            let worth = self
                .payback_allowance(next, now)
                .max((self.budget() - self.spent - least - leader) / 2.0);
            let estimating = Instant::now();
            let build = self.build_of(next, worth, build_cost);
            self.spent += estimating.elapsed().as_secs_f64();
            if self.pays_back(next, build, now) {
                self.base_slice = Some(self.slice);
                self.phase = Phase::Trial;
                self.current = next;
                return Some(next);
            }
            // The trial's build counts BUILD_SPREAD times, and the leader's build once more
            // if it loses. Where its whole slice does not fit what is left, the slice is cut
            // to what does, down to the least that measures it (20,000 drifting balls: the
            // grid's trial, a fourth of the budget, was not tried for a slice of half of it,
            // and the loose grid ran 2.8x the grid's time).
            let room = self.budget() - self.spent - BUILD_SPREAD * build - leader;
            if room >= least {
                self.base_slice = Some(self.slice);
                if room < run {
                    self.slice *= room / run;
                }
                self.phase = Phase::Trial;
                self.current = next;
                return Some(next);
            }
            self.untried.push(next);
        }
        self.to_try.clear();
        self.phase = Phase::Settled;
        // (A check due within a slice's millionth is due now.)
        if !self.next_check.is_finite() || self.next_check <= now + 1e-6 * self.slice {
            self.next_check = (now + 3.0 * now.max(self.slice)).min(self.horizon);
        }
        None
    }

    /// Whether a trial of `next`, whose build costs `build`, pays for itself by the paces
    /// measured, and is tried outside the budget:
    /// - where objects pass through each other the brute force processes only the contacts,
    ///   which every structure processes too: it costs its build and the contacts' share of
    ///   the leader's work (measured: the share of pair events among the run's events). When
    ///   that is under the rest of the run at the leader's pace, less the margin, it pays back
    ///   its build. The estimate counts twice: the probe's pairs stay in cache and a whole
    ///   build's do not (a build of 680,000 pairs took twice the probe's estimate);
    /// - a structure that ran faster than the leader runs now (the leader's pace has moved
    ///   since they were compared: 1,167 balls whose loose grid ran at 1.6e-4 s a unit on the
    ///   first slice and at 3.0e-4 over the rest, against the grid's 2.4e-4) pays back where
    ///   the difference over the rest of the run is more than its build, counted twice, and
    ///   the leader's.
    fn pays_back(&self, next: Structure, build: f64, now: f64) -> bool {
        build < self.payback_allowance(next, now)
    }

    /// The most `next`'s build may cost and pay for itself (see [`Race::pays_back`]):
    /// negative where it cannot.
    fn payback_allowance(&self, next: Structure, now: f64) -> f64 {
        let rest = self.ahead(now);
        if next == Structure::BruteForce && self.passing {
            return (1.0 - MARGIN - self.contact_share) * self.pace * rest / 2.0;
        }
        let leader = self.known_build(self.leader).unwrap_or(0.0);
        self.paces
            .iter()
            .find(|p| p.0 == next)
            .map_or(f64::NEG_INFINITY, |&(_, pace)| {
                (((1.0 - MARGIN) * self.pace - pace) * rest - leader) / 2.0
            })
    }

    /// What the trials may cost: a share of the run's time at the leader's pace.
    fn budget(&self) -> f64 {
        SHARE * self.pace * self.projected()
    }

    /// The simulated time the run is projected to cover: its horizon, or with none twice
    /// the run so far (a world is taken to run at least as long again as it has).
    fn projected(&self) -> f64 {
        if self.horizon.is_finite() {
            self.horizon
        } else {
            match (self.slices.first(), self.slices.last()) {
                (Some(first), Some(last)) => 2.0 * (last.to - first.from),
                _ => 0.0,
            }
        }
    }

    /// The simulated time the run is projected to go on after `now`.
    fn ahead(&self, now: f64) -> f64 {
        if self.horizon.is_finite() {
            self.horizon - now
        } else {
            self.projected() / 2.0
        }
    }

    /// What `structure`'s build costs, as measured or estimated so far.
    fn known_build(&self, structure: Structure) -> Option<f64> {
        self.builds.iter().find(|b| b.0 == structure).map(|b| b.1)
    }

    /// What `structure`'s build costs: as measured where it was built, else as estimated.
    /// `worth` is the most it may cost and be tried (an estimate may stop short past it).
    fn build_of(
        &mut self,
        structure: Structure,
        worth: f64,
        build_cost: &mut dyn FnMut(Structure, f64) -> f64,
    ) -> f64 {
        if let Some(b) = self.known_build(structure) {
            return b;
        }
        let mut b = build_cost(structure, worth);
        if structure != Structure::BruteForce {
            b *= self.sample_scale(build_cost);
        }
        self.builds.push((structure, b));
        b
    }

    /// What a box structure's whole build costs over its estimate from a sample in this world:
    /// the structure the run started on, its build measured, estimated as others are. A
    /// sample's build stays in cache, and the whole one grows its tables as it goes: on
    /// 53,990 and 67,608 balls the grid's and the loose grid's estimates were 2.6 to 4.1
    /// times short of their builds, and a trial's loss, its build and the leader's rebuild,
    /// took the race's whole budget. On a few thousand objects a sample's fixed costs,
    /// scaled up, make it over: 3,435 balls on a plane, whose loose grid builds in 6 ms,
    /// estimated it at 10 ms, and no trial fitted.
    fn sample_scale(&mut self, build_cost: &mut dyn FnMut(Structure, f64) -> f64) -> f64 {
        if let Some(scale) = self.sample_scale {
            return scale;
        }
        let (pick, built) = self.start;
        let scale = if pick == Structure::BruteForce || built <= 0.0 {
            1.0
        } else {
            let sampled = build_cost(pick, f64::INFINITY);
            if sampled > 0.0 { built / sampled } else { 1.0 }
        };
        self.sample_scale = Some(scale);
        scale
    }

    /// The share of pair events (contacts) among the run's events so far.
    pub(crate) fn contact_share(&mut self, share: f64) {
        self.contact_share = share.clamp(0.0, 1.0);
    }

    /// The switch the race asked for took `build` wall seconds.
    pub(crate) fn switched(&mut self, build: f64) {
        self.spent += build;
        self.build = build;
        self.builds.retain(|b| b.0 != self.current);
        self.builds.push((self.current, build));
    }

    /// The slices run so far, in order.
    pub(crate) fn slices(&self) -> &[Slice] {
        &self.slices
    }

    /// The slices run, in order.
    pub(crate) fn into_slices(self) -> Vec<Slice> {
        self.slices
    }
}

#[cfg(test)]
#[path = "race_tests.rs"]
mod tests;
