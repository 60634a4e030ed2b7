//! The stepped grid's pairs kept from step to step: each box is given a fat box that covers
//! where it is going over the next few steps, the pairs of fat boxes that overlap are found
//! with the [`SteppedGrid`] now and then, and each step tests only those candidates.
//!
//! The pairs are exactly the grid's own: two boxes inside fat boxes that do not overlap do
//! not overlap, and each candidate is tested as the grid tests a pair (single precision,
//! rounded outwards). A box that leaves its fat box, or one that comes or goes, gets a new
//! fat box whose candidates are looked up in the grid the fat boxes were filed in (passing
//! over the boxes it holds stale) and among the other boxes re-fattened since. Once the
//! re-fattening since the last filing has taken as long as that filing (rent or buy), or
//! half the boxes have been re-fattened, all are filed afresh. A box's fat
//! box is its box swept over some steps of its own move, grown by [`MARGIN`] of its width: a
//! body in steady flight keeps it for those steps, a body at rest for as long as it rests.
//! The steps: a filing costs about [`FILING_TESTS`] candidate tests a box, and each
//! candidate is tested every call, so over `s` steps a call costs about `FILING_TESTS boxes /
//! s + c s` tests for `c` candidates a step covered, least at `s = sqrt(FILING_TESTS boxes /
//! c)`; `c` is taken from the last filing, and `s` kept within [`AHEAD`] and [`MOST_AHEAD`]
//! (the rapier bench's debris: 40 to 64 steps; its kinematic bodies and bursts, with more
//! candidates, 16 to 18).
//!
//! Where the boxes move more steadily in the frame of the typical box than in the world's
//! (a rain, a heap in free fall: every body's move grows each step by the same amount), the
//! fat boxes ride with that frame: each is kept where its box lies in it and swept over its
//! move there, so bodies falling side by side keep theirs until they land. Two boxes shifted
//! alike overlap as before, so no pair is lost.
//!
//! Fat boxes pay where they last: debris, a burst flying apart, kinematic bodies on their
//! paths, a small pile once it has settled, bodies falling together. In a settling pile or a
//! gas bodies are pushed out of their fat boxes at once: there each step finds the pairs from
//! scratch. Fat boxes are tried only once the boxes move steadily, in either frame, or once
//! they are seen to stay in place: while the pairs are found from scratch each box keeps a
//! trial fat box of its own (no grid, no pairs, looked at one call in [`TRIAL_EVERY`]), and
//! where few boxes leave theirs a call (a stack whose bodies tremble in their contacts, with
//! a few bullets through it) fat boxes would last whatever the moves say. What a call with
//! fat boxes takes is timed against what finding its pairs from scratch took when last timed
//! (either way gives the same pairs, so the clock changes no result); fat boxes filed afresh
//! fewer than [`MIN_LIFE`] calls after the last time, or costing more, are tried again only
//! after [`FIRST_WAIT`] calls, then twice as many each time they fail, up to [`LAST_WAIT`].

use super::enlarged::SCAN_MOST;
use super::{SteppedGrid, typical_move};
use crate::aabb::{Aabb, AabbF32, overlap, overlapping, to_f32};
use kinetic_core::{Real, Vec3};
use std::time::Instant;

/// A fat box covers at least this many steps of its box's move...
const AHEAD: Real = 16.0;
/// ... and at most this many...
const MOST_AHEAD: Real = 64.0;
/// ... and this share of its width on every side.
const MARGIN: Real = 0.1;
/// Filing the fat boxes afresh costs about this many candidate tests a box (debris of 1e3
/// bodies in rapier: 125 us a filing, 20 ns a candidate tested).
const FILING_TESTS: Real = 6.0;
/// The boxes move steadily where at most one in this many changed its move by enough to leave
/// its fat box within [`AHEAD`] steps.
const MOVED_SHARE: usize = 16;
/// The work of a call, in boxes filed in the grid: a box checked against its fat box...
const CHECK_WORK: Real = 0.25;
/// ... a pair of boxes tested...
const TEST_WORK: Real = 0.5;
/// ... a box re-fattened and its candidates looked up.
const QUERY_WORK: Real = 4.0;
/// Works are averaged over about this many calls.
const SMOOTHING: Real = 8.0;
/// Fat boxes filed afresh fewer than this many calls after the last time, or whose calls
/// took more work than finding the pairs from scratch, did not pay...
const MIN_LIFE: u64 = 4;
/// ... and the pairs are found from scratch for this many calls...
const FIRST_WAIT: u64 = 32;
/// ... doubled at each failure up to this many.
const LAST_WAIT: u64 = 1024;
/// Fat boxes are tried where at most one box in this many leaves its trial fat box a call
/// (chosen, not fitted: what they then cost is timed, and decides).
const STAY_SHARE: usize = 16;
/// A timed call counts for at most this many times what it was expected to take (chosen,
/// not fitted: a filing of the fat boxes takes about twice a call from scratch).
const OUTLIER: Real = 4.0;
/// Trial fat boxes are looked at on one call in this many (a look at every box each call
/// cost a gas of 1e3 bodies a sixth of its broad phase)...
const TRIAL_EVERY: u64 = 4;
/// ... and the boxes leaving them averaged over about this many looks, after which they are
/// taken at the earliest (chosen, not fitted: four looks cover the 16 steps a fat box
/// covers at the least, [`AHEAD`]).
const TRIAL_LOOKS: Real = 4.0;

/// Pairs of overlapping boxes, kept between calls while the boxes keep within fat boxes.
#[derive(Clone, Debug, Default)]
pub(crate) struct FatPairs {
    /// The grid the pairs are found in from scratch while fat boxes do not hold, and the fat
    /// boxes are filed in while they do (one grid for both: its buffers, grown at the first
    /// call, serve the first filing too).
    grid: SteppedGrid,
    /// Per index, the fat box (`None`: no box).
    fat: Vec<Option<Aabb>>,
    /// Per index, the call at which it last left its fat box: after `built`, it was
    /// re-fattened since the fat boxes were filed (its entry in the grid is stale).
    left: Vec<u64>,
    /// The indices re-fattened since the fat boxes were filed.
    refat: Vec<u32>,
    /// The pairs of overlapping fat boxes, sorted.
    candidates: Vec<(u32, u32)>,
    /// Whether the fat boxes are in use, and the call at which they were last filed.
    ready: bool,
    built: u64,
    /// Calls before which the pairs are found from scratch, and how long the last wait was.
    plain_until: u64,
    wait: u64,
    /// Per index, the box's move at the last call.
    last_moves: Vec<Option<Vec3>>,
    /// The work of a call with fat boxes, averaged over about [`SMOOTHING`] calls (in boxes
    /// filed: the same on every run, for [`FatPairs::work`]).
    work: Real,
    /// What a call with fat boxes took, and what finding its pairs from scratch would have
    /// (its boxes and pairs at the pace measured when they were last found so), averaged
    /// over about [`SMOOTHING`] calls, in nanoseconds: whether fat boxes pay is measured
    /// (either way gives the same pairs). The pace: nanoseconds a box filed, a pair found
    /// counting [`TEST_WORK`] of one.
    took: Real,
    plain_took: Real,
    plain_pace: Option<Real>,
    /// The steps of its move a fat box covers, and the candidates a step covered at the
    /// last filing.
    ahead: Real,
    candidates_a_step: Option<Real>,
    /// The frame the boxes are swept in while fat boxes hold: the one they were filed in
    /// (boxes meet as they move in any frame that moves steadily).
    frame: Vec3,
    /// Whether the fat boxes ride with the typical box, in whose frame the boxes of a world
    /// falling together hardly move; how far that frame has moved since they were filed
    /// (the fat boxes lie that far behind the boxes), and how far it moves over the step
    /// under way (zero when not riding).
    ride: bool,
    drift: Vec3,
    carry: Vec3,
    /// The typical move at the last call, whether the boxes moved more steadily in its
    /// frame than in the world's at the last count, and scratch.
    last_typical: Option<Vec3>,
    steadier_riding: bool,
    sample: Vec<Real>,
    /// While the pairs are found from scratch: per index, a trial fat box (swept in the
    /// frame passed), the boxes that left theirs a call, averaged, the looks taken, and
    /// whether the last said the boxes stay in place.
    trial: Vec<Option<Aabb>>,
    trial_leaving: Real,
    trial_looks: u64,
    trial_stays: bool,
    /// Scratch: the indices leaving their fat boxes this call, and the pairs they gain.
    leaving: Vec<u32>,
    gained: Vec<(u32, u32)>,
    found: Vec<u32>,
    merged: Vec<(u32, u32)>,
    /// Scratch: each box swept and rounded as the grid tests a pair.
    rounded: Vec<Option<AabbF32>>,
    /// What the last filing of the fat boxes took, and the re-fattening since, in
    /// nanoseconds; the grid of the boxes re-fattened since, for a call's look-ups.
    filing_took: Real,
    refat_took: Real,
    refat_grid: SteppedGrid,
    /// How many times the fat boxes were filed afresh, boxes re-fattened on their own, and
    /// calls.
    pub(crate) rebuilds: u64,
    /// Calls whose re-fattened boxes were filed in a grid of their own.
    pub(crate) refat_filings: u64,
    pub(crate) refattened: u64,
    pub(crate) calls: u64,
}

impl FatPairs {
    /// Puts the pairs `(a, b)`, `a < b`, of the boxes `boxes` (per index: the box and how far
    /// it moves a step, `None` for none), swept over the step in the frame that moves
    /// `frame` a step, that overlap and that `keep(a, b)` keeps into `out`, sorted; what
    /// `out` held is cleared.
    pub(crate) fn pairs(
        &mut self,
        boxes: &[Option<(Aabb, Vec3)>],
        frame: Vec3,
        keep: &dyn Fn(u32, u32) -> bool,
        out: &mut Vec<(u32, u32)>,
    ) {
        // The typical move, each call: riding fat boxes follow it, and the boxes are swept
        // in its frame.
        let typical = typical_move(boxes, &mut self.sample);
        let last_typical = self.last_typical.replace(typical);
        if self.ready && self.ride {
            self.drift += self.carry;
            self.carry = typical;
        }
        let frame = match (self.ready, self.ride) {
            (true, true) => typical,
            (true, false) => self.frame,
            (false, _) => frame,
        };
        let boxes = &Swept { boxes, frame };
        self.calls += 1;
        let start = Instant::now();
        // The moves are compared from call to call only while fat boxes do not hold.
        let steady = self.ready || self.steady(boxes, typical, last_typical);
        if self.calls < self.plain_until || !steady {
            self.plain(boxes, keep, out, start);
            return;
        }
        let refattened = self.refattened;
        let kept = self.ready && self.update(boxes);
        let mut work =
            boxes.len() as Real * CHECK_WORK + (self.refattened - refattened) as Real * QUERY_WORK;
        if !kept {
            let pays = self.took <= self.plain_took;
            if self.ready && (self.calls - self.built < MIN_LIFE || !pays) {
                // They did not last: from scratch for a while.
                self.wait = (2 * self.wait).clamp(FIRST_WAIT, LAST_WAIT);
                self.plain_until = self.calls + self.wait;
                self.plain(boxes, keep, out, start);
                return;
            }
            if self.ready {
                self.wait = 0;
            }
            self.file(boxes, typical);
            work += boxes.len() as Real + self.candidates.len() as Real * TEST_WORK;
        }
        out.clear();
        if self.candidates.len() * 4 >= boxes.len() {
            // Candidates at least a quarter as many as the boxes (a pile, a burst): each box
            // rounded once, not once a candidate (from half as many, a burst of 1e3 bodies
            // cost 7% more). Two loops rather than one choosing per candidate: that one cost
            // kinematic bodies at 1e3 a tenth more.
            self.rounded.clear();
            self.rounded
                .extend(boxes.iter().map(|b| b.map(|b| to_f32(&b.0))));
            for &(a, b) in &self.candidates {
                if let (Some(x), Some(y)) = (&self.rounded[a as usize], &self.rounded[b as usize])
                    && overlap(x, y)
                    && keep(a, b)
                {
                    out.push((a, b));
                }
            }
        } else {
            for &(a, b) in &self.candidates {
                if let (Some(x), Some(y)) = (boxes.get(a), boxes.get(b))
                    && overlapping(&x.0, &y.0)
                    && keep(a, b)
                {
                    out.push((a, b));
                }
            }
        }
        // What the call took, against what finding its pairs from scratch would have.
        work += self.candidates.len() as Real * TEST_WORK;
        let plain = boxes.len() as Real + out.len() as Real * TEST_WORK;
        self.work += (work - self.work) / SMOOTHING;
        // A call's time counts for at most OUTLIER times its estimate from scratch, and a
        // pace for at most OUTLIER times the last: a call preempted on a shared machine
        // says nothing of either way.
        let took = start.elapsed().as_nanos() as Real;
        let plain_took = plain * self.plain_pace.unwrap_or(took / plain);
        self.took += (took.min(OUTLIER * plain_took) - self.took) / SMOOTHING;
        self.plain_took += (plain_took - self.plain_took) / SMOOTHING;
    }

    /// Whether fat boxes hold the pairs now.
    pub(crate) fn holds(&self) -> bool {
        self.ready
    }

    /// The frame the boxes are swept in while fat boxes hold the pairs (the frame passed
    /// to [`FatPairs::pairs`] is not looked at then).
    pub(crate) fn frame(&self) -> Option<Vec3> {
        self.ready.then_some(self.frame)
    }

    /// The work of a call while fat boxes hold the pairs, averaged (in boxes filed).
    pub(crate) fn work(&self) -> Option<Real> {
        self.ready.then_some(self.work)
    }

    /// Whether the boxes move steadily enough for fat boxes: no more than one in
    /// [`MOVED_SHARE`] changed its move since the last call by enough to leave its fat box
    /// within [`AHEAD`] steps at that rate (a pile settling does), in the world's frame or in
    /// the typical box's, whichever they are steadier in (bodies falling together are
    /// steady in the frame that falls with them); the typical move was `typical` at this
    /// call and `last` at the one before. Keeps each box's move for the next call, in the
    /// same pass.
    fn steady(&mut self, boxes: &Swept, typical: Vec3, last: Option<Vec3>) -> bool {
        let compared = self.last_moves.len() == boxes.len();
        if !compared {
            self.last_moves.clear();
            self.last_moves.resize(boxes.len(), None);
        }
        let reach = AHEAD * AHEAD / 2.0;
        // How the typical box's move changed: the frame riding with it turned by that much.
        let turn = last.map_or(Vec3::ZERO, |u| typical - u);
        let (mut unsteady, mut unsteady_riding) = (0, 0);
        for (b, last) in boxes.boxes.iter().zip(&mut self.last_moves) {
            if let (Some((b, d)), Some(d0)) = (b, *last) {
                // The swept box's width.
                let width = (b.max - b.min + (*d - boxes.frame).abs()).max_element();
                let change = *d - d0;
                unsteady += usize::from(change.length() * reach > MARGIN * width);
                unsteady_riding += usize::from((change - turn).length() * reach > MARGIN * width);
            }
            *last = b.map(|b| b.1);
        }
        self.steadier_riding = unsteady_riding < unsteady;
        let steady = unsteady.min(unsteady_riding) * MOVED_SHARE <= boxes.len();
        compared && (steady || self.stay_in_place(boxes))
    }

    /// Whether the boxes stay in place, by their trial fat boxes: at most one box in
    /// [`STAY_SHARE`] leaves its own a call. The trial fat boxes are looked at on one call
    /// in [`TRIAL_EVERY`], and the boxes leaving them a call averaged over about
    /// [`TRIAL_LOOKS`] looks, which they are taken at the earliest.
    fn stay_in_place(&mut self, boxes: &Swept) -> bool {
        if !self.calls.is_multiple_of(TRIAL_EVERY) {
            return self.trial_stays;
        }
        self.trial.resize(boxes.len(), None);
        let mut leaving = 0;
        for (b, trial) in boxes.iter().zip(&mut self.trial) {
            let stays = match (b, *trial) {
                (Some((b, _)), Some(fat)) => b.inside(&fat),
                (None, None) => true,
                _ => false,
            };
            if !stays {
                leaving += usize::from(trial.is_some());
                *trial = b.map(|b| fatten(b, Vec3::ZERO, Vec3::ZERO, AHEAD));
            }
        }
        // The first look gives every box its trial fat box.
        if self.trial_looks > 0 {
            let a_call = leaving as Real / TRIAL_EVERY as Real;
            self.trial_leaving += (a_call - self.trial_leaving) / TRIAL_LOOKS;
        }
        self.trial_looks += 1;
        self.trial_stays = self.trial_looks > TRIAL_LOOKS as u64
            && self.trial_leaving * STAY_SHARE as Real <= boxes.len() as Real;
        self.trial_stays
    }

    /// The pairs found from scratch (fat boxes do not hold), in a call that started at
    /// `start`: its pace is measured.
    fn plain(
        &mut self,
        boxes: &Swept,
        keep: &dyn Fn(u32, u32) -> bool,
        out: &mut Vec<(u32, u32)>,
        start: Instant,
    ) {
        if self.ready {
            self.ready = false;
            self.grid.remeasure();
        }
        let items = boxes.iter().enumerate();
        let items = items.filter_map(|(i, b)| Some((i as u32, b?.0)));
        self.grid.pairs(items, keep, out);
        let units = boxes.len() as Real + out.len() as Real * TEST_WORK;
        let pace = start.elapsed().as_nanos() as Real / units.max(1.0);
        let last = self.plain_pace.unwrap_or(pace);
        self.plain_pace = Some(last + (pace.min(OUTLIER * last) - last) / SMOOTHING);
    }

    /// Every box given a fat box, filed afresh, and the pairs of fat boxes found; the
    /// typical move is `typical` at this call.
    fn file(&mut self, boxes: &Swept, typical: Vec3) {
        let start = Instant::now();
        if !self.ready {
            // Fresh from scratch: fat boxes are given the benefit of the doubt, in the frame
            // the boxes were steadier in.
            self.work = 0.0;
            self.took = 0.0;
            self.plain_took = 0.0;
            self.ride = self.steadier_riding;
            // Trial fat boxes count afresh once these no longer hold.
            self.trial.clear();
            self.trial_leaving = 0.0;
            self.trial_looks = 0;
            self.trial_stays = false;
        }
        self.drift = Vec3::ZERO;
        self.carry = if self.ride { typical } else { Vec3::ZERO };
        self.rebuilds += 1;
        self.built = self.calls;
        self.frame = boxes.frame;
        let n = boxes.len() as Real;
        let ahead = match self.candidates_a_step {
            Some(c) => (FILING_TESTS * n / c.max(1.0 / MOST_AHEAD))
                .sqrt()
                .clamp(AHEAD, MOST_AHEAD),
            None => AHEAD,
        };
        if !self.ready || ahead != self.ahead {
            // Fat boxes after plain ones, or of another length: the grid's cells follow them.
            self.grid.remeasure();
            self.ahead = ahead;
        }
        self.ready = true;
        self.fat.clear();
        let (carry, drift) = (self.carry, self.drift);
        self.fat.extend(
            boxes
                .iter()
                .map(|b| b.map(|b| fatten(b, carry, drift, ahead))),
        );
        self.left.clear();
        self.left.resize(boxes.len(), 0);
        self.refat.clear();
        let fat = self.fat.iter().enumerate();
        let items = fat.filter_map(|(i, f)| Some((i as u32, (*f)?)));
        self.grid.pairs(items, &|_, _| true, &mut self.candidates);
        self.candidates_a_step = Some(self.candidates.len() as Real / self.ahead);
        self.filing_took = start.elapsed().as_nanos() as Real;
        self.refat_took = 0.0;
    }

    /// Whether box `i` was re-fattened since the fat boxes were filed.
    fn moved(&self, i: u32) -> bool {
        self.left[i as usize] > self.built
    }

    /// Gives the boxes that left their fat boxes (or came or went) new ones, and the
    /// candidates with them; `false` when too many have been re-fattened since the fat
    /// boxes were filed (or the boxes are not the same many), which files them afresh.
    fn update(&mut self, boxes: &Swept) -> bool {
        if self.fat.len() != boxes.len() {
            return false;
        }
        self.leaving.clear();
        for (i, (b, f)) in boxes.iter().zip(&self.fat).enumerate() {
            let inside = match (b, f) {
                (None, None) => true,
                (Some((b, _)), Some(fat)) => behind(&b, self.drift).inside(fat),
                _ => false,
            };
            if !inside {
                self.leaving.push(i as u32);
            }
        }
        if self.leaving.is_empty() {
            return true;
        }
        // Rent or buy: filed afresh once the re-fattening since the last filing took as
        // long as that filing (or half the boxes were re-fattened).
        let fresh = self.leaving.iter().filter(|&&i| !self.moved(i));
        if (self.refat.len() + fresh.count()) * 2 > boxes.len()
            || self.refat_took > self.filing_took
        {
            return false;
        }
        let start = Instant::now();
        self.refattened += self.leaving.len() as u64;
        // New fat boxes first, so that two leaving boxes see each other's.
        for &i in &self.leaving {
            let (carry, drift, ahead) = (self.carry, self.drift, self.ahead);
            self.fat[i as usize] = boxes.get(i).map(|b| fatten(b, carry, drift, ahead));
            if !self.moved(i) {
                self.refat.push(i);
            }
            self.left[i as usize] = self.calls;
        }
        // Their candidates: in the grid (passing over stale entries), and among the boxes
        // re-fattened since it was filed (scanned, or filed in a grid of their own when a
        // scan would test more than SCAN_MOST pairs a box, as the loose boxes of enlarged
        // boxes are).
        self.gained.clear();
        let scan = self.leaving.len() * self.refat.len()
            <= SCAN_MOST * (self.leaving.len() + self.refat.len());
        if !scan {
            self.refat_filings += 1;
            let fat = &self.fat;
            let refat = self
                .refat
                .iter()
                .filter_map(|&j| Some((j, fat[j as usize]?)));
            self.refat_grid.file_for_lookups(refat);
        }
        for &i in &self.leaving {
            let Some(f) = self.fat[i as usize] else {
                continue;
            };
            self.found.clear();
            self.grid.overlapping_with(&f, &mut self.found);
            let (left, built) = (&self.left, self.built);
            self.found.retain(|&j| left[j as usize] <= built);
            if scan {
                for &j in &self.refat {
                    if let Some(g) = self.fat[j as usize]
                        && overlapping(&f, &g)
                    {
                        self.found.push(j);
                    }
                }
            } else {
                let at = self.found.len();
                self.refat_grid.overlapping_with(&f, &mut self.found);
                let fat = &self.fat;
                let mut k = at;
                while k < self.found.len() {
                    let j = self.found[k];
                    if fat[j as usize].is_some_and(|g| overlapping(&f, &g)) {
                        k += 1;
                    } else {
                        self.found.swap_remove(k);
                    }
                }
            }
            for &j in &self.found {
                if j != i {
                    self.gained.push((i.min(j), i.max(j)));
                }
            }
        }
        self.gained.sort_unstable();
        self.gained.dedup();
        // The leaving boxes' old pairs go; the gained ones merge in.
        let (left, call) = (&self.left, self.calls);
        let leaving = |i: u32| left[i as usize] == call;
        let (old, gained) = (&self.candidates, &self.gained);
        self.merged.clear();
        let mut g = gained.iter().peekable();
        for &p in old.iter().filter(|&&(a, b)| !(leaving(a) || leaving(b))) {
            while let Some(&&q) = g.peek()
                && q < p
            {
                self.merged.push(q);
                g.next();
            }
            self.merged.push(p);
        }
        self.merged.extend(g);
        std::mem::swap(&mut self.candidates, &mut self.merged);
        self.refat_took += start.elapsed().as_nanos() as Real;
        true
    }
}

/// Boxes swept over the step in a frame that moves steadily: two boxes meet as they move
/// in any such frame, and in the frame of the typical box (a falling heap's) they hardly
/// sweep at all.
pub(crate) struct Swept<'a> {
    /// Per index, the box and how far it moves a step (`None`: no box).
    boxes: &'a [Option<(Aabb, Vec3)>],
    /// How far the frame moves a step.
    frame: Vec3,
}

impl Swept<'_> {
    fn len(&self) -> usize {
        self.boxes.len()
    }

    /// Box `i` swept, and how far it moves a step.
    fn get(&self, i: u32) -> Option<(Aabb, Vec3)> {
        self.sweep(self.boxes[i as usize])
    }

    fn iter(&self) -> impl Iterator<Item = Option<(Aabb, Vec3)>> + '_ {
        self.boxes.iter().map(|&b| self.sweep(b))
    }

    fn sweep(&self, b: Option<(Aabb, Vec3)>) -> Option<(Aabb, Vec3)> {
        let (b, d) = b?;
        Some((b.swept(d - self.frame), d))
    }
}

/// The fat box of box `b` moving `d` a step, in a frame that has moved `drift` and moves
/// `carry` a step: the box where it lies in that frame, swept over `steps` steps of its move
/// there, grown by [`MARGIN`] of its width on every side. A NaN box stays NaN (and never
/// holds).
fn fatten((b, d): (Aabb, Vec3), carry: Vec3, drift: Vec3, steps: Real) -> Aabb {
    let grow = Vec3::splat(MARGIN * b.widest());
    behind(&b, drift).swept((d - carry) * steps).grown(grow)
}

/// Box `b` where it lies in a frame that has moved `drift` (the same shift for every box,
/// so two boxes that overlap still do).
fn behind(b: &Aabb, drift: Vec3) -> Aabb {
    Aabb::new(b.min - drift, b.max - drift)
}

#[cfg(test)]
#[path = "fat_pairs_tests.rs"]
mod tests;
