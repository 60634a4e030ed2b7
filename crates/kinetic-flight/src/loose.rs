//! `loose`: a loose kinetic grid. Each object holds a fixed region, a box that its own box
//! stays inside for a while on its flight plan; candidate pairs are the objects whose regions
//! overlap. The one certificate per object is that its box stays inside its region, and its
//! failure time comes from the plan; pairs have no certificates of their own.
//!
//! - Regions: the box an object's box sweeps on its plan while the object travels
//!   [`LooseGrid::with_reach`]'s `travel` box widths, widened on every side by `margin` box
//!   widths. An object at rest holds its box widened by the margin for as long as it rests.
//! - Events: an object whose box reaches the edge of its region is given a new region from
//!   where it is (re-anchored); its pairs are found again among the objects whose regions
//!   share a grid cell with its new one. It stays filed in the cells both regions cover and
//!   only leaves and enters the others.
//! - Re-plans: an object whose new plan keeps its box inside its region keeps the region and
//!   only has its exit time recomputed. A body jostled in a pile, re-planned every few steps,
//!   so costs one root computation and a queue update, not a pass over its neighbours.
//! - Cells: one uniform grid, its cells as wide as the first regions' median. A region is
//!   filed in the cells it covers; one covering more than 8 on an axis or 64 in all (a
//!   ground slab, a boulder among pebbles) is big, kept in a list that every region checks,
//!   and checks every region itself when it is placed. Once more than 32 regions, and more
//!   than one in 8, are big (cells sized by a lone first speck), the cells are sized afresh.
//! - Horizon ([`LooseGrid::with_horizon`]): a region covers at most this much time of flight,
//!   so a body drifting slowly holds a region close to its box.
//! - Least flight ([`LooseGrid::with_least_flight`]): a region covers at least this much time
//!   of flight, so a body that crosses its own width many times in that time (a shot fired
//!   at 1e8 units per second) holds one long region per that time instead of one per two
//!   widths: its re-anchors are bounded by the time it flies, not by how far it goes. A
//!   region more than 8 cells long is big and sits in the big list.
//!
//! The candidates are a superset of the sweep's (boxes inside overlapping regions), so a
//! caller that needs exact contacts certifies them itself. It suits bodies whose plans keep
//! failing (a settling pile) and crowds that fall together, where a structure of exact box
//! pairs pays for every box event and re-plan with certificates of all its neighbours.

use crate::grid::{Local, exit_from, swept_box};
use crate::sweep::{box_ends, box_width};
use kinetic_core::{Bodies, CandidateStructure, EventQueue, PairChange, Real, ScalarKey, Vec3};
use rustc_hash::FxHashMap;

/// A region stretches over the travel of this many box widths by default...
const TRAVEL: Real = 2.0;
/// ... and is wider than the swept box by this many box widths on every side.
const MARGIN: Real = 0.25;
/// A region is filed in the cells it covers when it covers at most this many on every axis
/// and this many in all; a larger one is big, and kept in a list every region checks.
const MAX_SPAN: i64 = 8;
const MAX_CELLS: i64 = 64;
/// The cells are sized afresh when more than this many regions are big, and they are more
/// than one in [`BIG_SHARE`] of all.
const MANY_BIG: usize = 32;
const BIG_SHARE: usize = 8;

/// A cell's index on each axis.
type CellKey = [i64; 3];

/// An object in the loose grid.
#[derive(Clone, Debug)]
struct Member {
    /// Its region's corners.
    lo: Vec3,
    hi: Vec3,
    /// The cells its region is filed in (their slots), none when it is big.
    slots: Vec<u32>,
    big: bool,
    /// The objects whose regions overlap its own.
    partners: Vec<u32>,
    /// When its box leaves its region on its plan.
    exit: Real,
}

/// The loose kinetic grid: candidate pairs are the objects whose regions overlap.
#[derive(Debug)]
pub struct LooseGrid {
    travel: Real,
    margin: Real,
    /// No region covers more than this much time of its object's flight...
    horizon: Real,
    /// ... nor less than this much (when it is shorter than the horizon).
    least_flight: Real,
    /// The cells' side (set by the first objects' regions, their median width).
    cell: Option<Real>,
    /// The median box width of the first objects: no margin is wider than `margin` of it (a
    /// ground slab's region is not metres taller than the slab).
    typical: Real,
    members: Vec<Option<Member>>,
    live: usize,
    /// Cells by index, each a slot in `occupants`; `free` lists the slots of emptied cells.
    cells: FxHashMap<CellKey, u32>,
    occupants: Vec<Vec<u32>>,
    free: Vec<u32>,
    /// The big regions.
    big: Vec<u32>,
    exits: EventQueue,
    /// Stamps for collecting an object's new partners without duplicates.
    mark: Vec<u64>,
    epoch: u64,
    pairs: usize,
    anchors: u64,
    /// Re-anchors whose new region covers the same cells as the old (left filed there).
    same_cells: u64,
    kept: u64,
    refiles: u64,
    scratch: Vec<u32>,
}

impl Default for LooseGrid {
    fn default() -> LooseGrid {
        LooseGrid::new()
    }
}

impl LooseGrid {
    /// An empty loose grid with the default reach (regions over a travel of 2 box widths,
    /// with a margin of a quarter width, or of the first objects' median width if less).
    pub fn new() -> LooseGrid {
        LooseGrid::with_reach(TRAVEL, MARGIN)
    }

    /// An empty loose grid whose regions cover `travel` box widths of an object's flight and
    /// `margin` box widths more on every side (a positive margin: at least 1e-6). Longer
    /// regions: fewer re-anchors, more candidate pairs.
    pub fn with_reach(travel: Real, margin: Real) -> LooseGrid {
        LooseGrid {
            travel: travel.max(0.0),
            margin: margin.max(1e-6),
            horizon: Real::INFINITY,
            least_flight: 0.0,
            cell: None,
            typical: Real::INFINITY,
            members: Vec::new(),
            live: 0,
            cells: FxHashMap::default(),
            occupants: Vec::new(),
            free: Vec::new(),
            big: Vec::new(),
            exits: EventQueue::new(),
            mark: Vec::new(),
            epoch: 0,
            pairs: 0,
            anchors: 0,
            same_cells: 0,
            kept: 0,
            refiles: 0,
            scratch: Vec::new(),
        }
    }

    /// The same loose grid whose regions cover at most `horizon` time units of flight (a slow
    /// object's region then hugs its box instead of stretching over its whole travel).
    pub fn with_horizon(mut self, horizon: Real) -> LooseGrid {
        if horizon > 0.0 {
            self.horizon = horizon;
        }
        self
    }

    /// The same loose grid whose regions cover at least `flight` time units of flight (up to
    /// the horizon): a body fast enough to travel the default reach many times over in that
    /// time is re-anchored once per `flight` instead of once per two box widths, whatever
    /// its speed. A broad phase stepping by `dt` passes `dt`.
    pub fn with_least_flight(mut self, flight: Real) -> LooseGrid {
        if flight > 0.0 && flight.is_finite() {
            self.least_flight = flight;
        }
        self
    }

    /// Number of candidate pairs (overlapping regions).
    pub fn pairs(&self) -> usize {
        self.pairs
    }

    fn present(&self, id: u32) -> bool {
        self.members.get(id as usize).is_some_and(Option::is_some)
    }

    fn member(&self, id: u32) -> &Member {
        self.members[id as usize].as_ref().expect("a member")
    }

    /// Object `id`'s box ends on each axis as polynomials around `now`.
    fn box_keys(bodies: &Bodies, id: u32, now: Real) -> [(Local, Local); 3] {
        let (lo, hi) = box_ends(bodies, id);
        let plan = &bodies[id as usize].as_ref().expect("a live object").plan;
        std::array::from_fn(|k| {
            (
                ScalarKey::from_plan(plan, k, lo[k]).local(now),
                ScalarKey::from_plan(plan, k, hi[k]).local(now),
            )
        })
    }

    /// A fresh region for object `id` from `now`: its corners.
    fn region(&self, bodies: &Bodies, id: u32, now: Real) -> (Vec3, Vec3) {
        let w = box_width(bodies, id);
        let plan = &bodies[id as usize].as_ref().expect("a live object").plan;
        let (v, a) = (plan.velocity_at(now).length(), plan.acceleration.length());
        let d = self.travel * w;
        // The time to travel d: v h + a h^2 / 2 = d.
        let h = if a > 0.0 {
            (2.0 * d / (v + (v * v + 2.0 * a * d).sqrt())).max(0.0)
        } else if v > 0.0 {
            d / v
        } else {
            0.0
        }
        .max(self.least_flight)
        .min(self.horizon);
        let keys = Self::box_keys(bodies, id, now);
        // A margin of a few float spacings at least, so that a point object leaves after now.
        let scale = plan.position_at(now).abs().max_element() + w;
        let m = (self.margin * w.min(self.typical))
            .max(1e-9 * scale)
            .max(Real::MIN_POSITIVE);
        swept_box(&keys, h, m)
    }

    /// When object `id`'s box, on its plan, first leaves the region `lo..hi` after `now`
    /// (`now` if it is outside already or leaving).
    fn exit_time(bodies: &Bodies, id: u32, lo: Vec3, hi: Vec3, now: Real) -> Real {
        exit_from(&Self::box_keys(bodies, id, now), lo, hi, now)
    }

    /// The cells the region `lo..hi` covers, per axis the first and last index; `None` when
    /// it is big (or there are no cells yet).
    fn footprint(&self, lo: Vec3, hi: Vec3) -> Option<[[i64; 2]; 3]> {
        let s = self.cell?;
        let mut f = [[0i64; 2]; 3];
        let mut all = 1;
        for k in 0..3 {
            // Saturating casts: a region out at 1e300 is big, not wrapped.
            let a = (lo[k] / s).floor() as i64;
            let b = ((hi[k] / s).floor() as i64).max(a);
            let span = b.saturating_sub(a).saturating_add(1);
            if !(1..=MAX_SPAN).contains(&span) {
                return None;
            }
            all *= span;
            f[k] = [a, b];
        }
        (all <= MAX_CELLS).then_some(f)
    }

    /// The slot of cell `key`, made if the cell is new.
    fn slot_for(&mut self, key: CellKey) -> u32 {
        if let Some(&slot) = self.cells.get(&key) {
            return slot;
        }
        let slot = self.free.pop().unwrap_or_else(|| {
            self.occupants.push(Vec::new());
            (self.occupants.len() - 1) as u32
        });
        self.cells.insert(key, slot);
        slot
    }

    /// Files member `id`'s region: in the cells it covers, or in the big list. Returns the
    /// slots.
    fn file(&mut self, id: u32, lo: Vec3, hi: Vec3) -> (Vec<u32>, bool) {
        let Some(f) = self.footprint(lo, hi) else {
            self.big.push(id);
            return (Vec::new(), true);
        };
        let mut slots = Vec::with_capacity(8);
        for key in cell_keys(f) {
            let slot = self.slot_for(key);
            self.occupants[slot as usize].push(id);
            slots.push(slot);
        }
        (slots, false)
    }

    /// Moves member `id`'s filing from the cells of footprint `from` (its `slots`, in
    /// [`cell_keys`] order) to those of `to`: out of the cells only `from` covers (emptied
    /// ones forgotten), into those only `to` covers. Returns the slots of `to`, in order.
    fn shift_filing(
        &mut self,
        id: u32,
        slots: Vec<u32>,
        from: [[i64; 2]; 3],
        to: [[i64; 2]; 3],
    ) -> Vec<u32> {
        if from == to {
            self.same_cells += 1;
            return slots;
        }
        let within = |f: &[[i64; 2]; 3], key: &CellKey| {
            (0..3).all(|k| f[k][0] <= key[k] && key[k] <= f[k][1])
        };
        let mut out = Vec::with_capacity(slots.len());
        let span = |k: usize| from[k][1] - from[k][0] + 1;
        for key in cell_keys(to) {
            if within(&from, &key) {
                let at = ((key[0] - from[0][0]) * span(1) + key[1] - from[1][0]) * span(2) + key[2]
                    - from[2][0];
                out.push(slots[at as usize]);
                continue;
            }
            let slot = self.slot_for(key);
            self.occupants[slot as usize].push(id);
            out.push(slot);
        }
        for (key, &slot) in cell_keys(from).zip(&slots) {
            if within(&to, &key) {
                continue;
            }
            let list = &mut self.occupants[slot as usize];
            if let Some(i) = list.iter().position(|&x| x == id) {
                list.swap_remove(i);
            }
            if list.is_empty() {
                self.cells.remove(&key);
                self.free.push(slot);
            }
        }
        out
    }

    /// Takes member `id` out of its cells (or the big list); emptied cells are forgotten.
    fn unfile(&mut self, id: u32) {
        let m = self.members[id as usize].as_mut().expect("a member");
        let slots = std::mem::take(&mut m.slots);
        let (lo, hi) = (m.lo, m.hi);
        if m.big {
            if let Some(i) = self.big.iter().position(|&x| x == id) {
                self.big.swap_remove(i);
            }
            return;
        }
        let mut emptied = false;
        for &slot in &slots {
            let list = &mut self.occupants[slot as usize];
            if let Some(i) = list.iter().position(|&x| x == id) {
                list.swap_remove(i);
            }
            emptied |= list.is_empty();
        }
        if emptied {
            let Some(f) = self.footprint(lo, hi) else {
                return;
            };
            for key in cell_keys(f) {
                if let Some(&slot) = self.cells.get(&key)
                    && self.occupants[slot as usize].is_empty()
                {
                    self.cells.remove(&key);
                    self.free.push(slot);
                }
            }
        }
    }

    /// Sizes the cells afresh (the median width of the regions now) and files every region
    /// again. Partners stay: they are the overlapping regions, whatever the cells.
    fn refile(&mut self) {
        let w = median(
            self.members
                .iter()
                .flatten()
                .map(|m| (m.hi - m.lo).max_element()),
        );
        let Some(w) = w else {
            return;
        };
        self.cell = Some(w);
        self.refiles += 1;
        self.cells.clear();
        self.occupants.clear();
        self.free.clear();
        self.big.clear();
        for id in 0..self.members.len() as u32 {
            let Some(m) = self.members[id as usize].as_ref() else {
                continue;
            };
            let (lo, hi) = (m.lo, m.hi);
            let (slots, big) = self.file(id, lo, hi);
            let m = self.members[id as usize].as_mut().expect("a member");
            m.slots = slots;
            m.big = big;
        }
    }

    /// Gives member `id` a fresh region from its plan at `now`, finds its partners again and
    /// reports the pairs that change.
    fn anchor(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        self.anchors += 1;
        let (lo, hi) = self.region(bodies, id, now);
        // A region that still covers some of the same cells stays filed there: it leaves
        // only the cells it no longer covers and enters only the new ones.
        let mut kept_slots = None;
        let mut old = if self.present(id) {
            let m = self.member(id);
            let moved = match (m.big, self.footprint(m.lo, m.hi), self.footprint(lo, hi)) {
                (false, Some(from), Some(to)) => Some((from, to)),
                _ => None,
            };
            if moved.is_none() {
                self.unfile(id);
            }
            let m = self.members[id as usize].take().expect("a member");
            if let Some((from, to)) = moved {
                kept_slots = Some(self.shift_filing(id, m.slots, from, to));
            }
            m.partners
        } else {
            self.live += 1;
            Vec::new()
        };
        self.epoch += 1;
        let epoch = self.epoch;
        if self.mark.len() < self.members.len() {
            self.mark.resize(self.members.len(), 0);
        }
        self.mark[id as usize] = epoch;
        let mut found = std::mem::take(&mut self.scratch);
        found.clear();
        let (slots, big) = match kept_slots {
            Some(slots) => (slots, false),
            None => self.file(id, lo, hi),
        };
        let (members, mark) = (&self.members, &mut self.mark);
        let mut meet = |p: u32, found: &mut Vec<u32>| {
            if mark[p as usize] != epoch {
                mark[p as usize] = epoch;
                let q = members[p as usize].as_ref().expect("a member");
                if q.lo.cmple(hi).all() && lo.cmple(q.hi).all() {
                    found.push(p);
                }
            }
        };
        if big {
            // A big region meets any other: it looks at them all.
            for (p, q) in self.members.iter().enumerate() {
                if q.is_some() {
                    meet(p as u32, &mut found);
                }
            }
        } else {
            for &slot in &slots {
                for &p in &self.occupants[slot as usize] {
                    meet(p, &mut found);
                }
            }
            for &p in &self.big {
                meet(p, &mut found);
            }
        }
        found.sort_unstable();
        old.sort_unstable();
        // Pairs that end, then pairs that begin.
        for &p in &old {
            if found.binary_search(&p).is_err() {
                self.part(id, p, changes);
            }
        }
        for &p in &found {
            if old.binary_search(&p).is_err() {
                let q = self.members[p as usize].as_mut().expect("a member");
                q.partners.push(id);
                self.pairs += 1;
                changes.push(pair_change(id, p, 1));
            }
        }
        let exit = Self::exit_time(bodies, id, lo, hi, now);
        self.members[id as usize] = Some(Member {
            lo,
            hi,
            slots,
            big,
            partners: found,
            exit,
        });
        self.scratch = old;
        self.schedule(id, exit);
        if self.big.len() > MANY_BIG && self.big.len() * BIG_SHARE > self.live {
            self.refile();
        }
    }

    /// Ends the pair of `id` and its partner `p`: off `p`'s partners, and reported.
    fn part(&mut self, id: u32, p: u32, changes: &mut Vec<PairChange>) {
        let q = self.members[p as usize].as_mut().expect("a member");
        if let Some(i) = q.partners.iter().position(|&x| x == id) {
            q.partners.swap_remove(i);
        }
        self.pairs -= 1;
        changes.push(pair_change(id, p, -1));
    }

    fn schedule(&mut self, id: u32, exit: Real) {
        if exit.is_finite() {
            self.exits.schedule(id, exit, 0);
        } else {
            self.exits.remove(id);
        }
    }
}

/// The median of the positive finite widths `w`, if any.
fn median(w: impl Iterator<Item = Real>) -> Option<Real> {
    let mut w: Vec<Real> = w.filter(|w| *w > 0.0 && w.is_finite()).collect();
    let mid = w.len() / 2;
    (!w.is_empty()).then(|| *w.select_nth_unstable_by(mid, Real::total_cmp).1)
}

/// The cells of footprint `f`, in order.
fn cell_keys(f: [[i64; 2]; 3]) -> impl Iterator<Item = CellKey> {
    (f[0][0]..=f[0][1]).flat_map(move |i| {
        (f[1][0]..=f[1][1]).flat_map(move |j| (f[2][0]..=f[2][1]).map(move |k| [i, j, k]))
    })
}

fn pair_change(x: u32, y: u32, delta: i32) -> PairChange {
    PairChange {
        a: x.min(y),
        b: x.max(y),
        delta,
    }
}

impl CandidateStructure for LooseGrid {
    fn name(&self) -> &'static str {
        "loose"
    }

    fn insert(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        self.insert_many(&[id], bodies, now, changes);
    }

    fn insert_many(
        &mut self,
        ids: &[u32],
        bodies: &Bodies,
        now: Real,
        changes: &mut Vec<PairChange>,
    ) {
        if self.cell.is_none() {
            if let Some(w) = median(ids.iter().map(|&id| box_width(bodies, id))) {
                self.typical = w;
            }
            // Cells as wide as the first regions' median.
            self.cell = median(ids.iter().map(|&id| {
                let (lo, hi) = self.region(bodies, id, now);
                (hi - lo).max_element()
            }));
        }
        if let Some(&top) = ids.iter().max()
            && self.members.len() <= top as usize
        {
            self.members.resize(top as usize + 1, None);
        }
        for &id in ids {
            if !self.present(id) {
                self.anchor(id, bodies, now, changes);
            }
        }
    }

    fn remove(&mut self, id: u32, _: &Bodies, _: Real, changes: &mut Vec<PairChange>) {
        if !self.present(id) {
            return;
        }
        self.unfile(id);
        self.live -= 1;
        let m = self.members[id as usize].take().expect("a member");
        for p in m.partners {
            self.part(id, p, changes);
        }
        self.exits.remove(id);
    }

    fn replan(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        if !self.present(id) {
            return;
        }
        let m = self.member(id);
        let exit = Self::exit_time(bodies, id, m.lo, m.hi, now);
        if exit > now {
            // Still inside its region on the new plan: it keeps the region.
            self.kept += 1;
            self.members[id as usize].as_mut().expect("a member").exit = exit;
            self.schedule(id, exit);
        } else {
            self.anchor(id, bodies, now, changes);
        }
    }

    fn next_event_time(&self) -> Real {
        self.exits.next_time()
    }

    fn process_next_event(
        &mut self,
        bodies: &Bodies,
        changes: &mut Vec<PairChange>,
    ) -> &'static str {
        if let Some((id, t)) = self.exits.peek() {
            self.anchor(id, bodies, t, changes);
        }
        "anchor"
    }

    fn certificates(&self) -> usize {
        self.exits.len()
    }

    fn counters(&self) -> Vec<(&'static str, f64)> {
        vec![
            ("region_pairs", self.pairs as f64),
            ("cells", self.cells.len() as f64),
            ("big", self.big.len() as f64),
            ("cell_size", self.cell.unwrap_or(0.0)),
            ("refiles", self.refiles as f64),
            ("anchors", self.anchors as f64),
            ("anchors_same_cells", self.same_cells as f64),
            ("regions_kept", self.kept as f64),
        ]
    }

    fn boxes(&self, _: &Bodies, _: Real) -> Vec<(Vec3, Vec3)> {
        self.members
            .iter()
            .flatten()
            .map(|m| (m.lo, m.hi))
            .collect()
    }

    fn validate(&self, bodies: &Bodies, now: Real) -> Result<(), String> {
        self.exits.validate()?;
        let mut covered = 0;
        let mut live = Vec::new();
        for (id, m) in self.members.iter().enumerate() {
            let Some(m) = m else { continue };
            let id = id as u32;
            if bodies.get(id as usize).is_none_or(Option::is_none) {
                return Err(format!("loose: object {id} held but not live"));
            }
            live.push(id);
            // Its box now is inside its region, and stays so until its exit.
            let keys = Self::box_keys(bodies, id, now);
            let tol = 1e-9 * (m.hi - m.lo).max_element()
                + 1e-12 * m.lo.abs().max(m.hi.abs()).max_element();
            for (k, (l, u)) in keys.iter().enumerate() {
                if l[0] < m.lo[k] - tol || u[0] > m.hi[k] + tol {
                    return Err(format!(
                        "loose: object {id} axis {k}: box [{}, {}] outside its region [{}, {}]",
                        l[0], u[0], m.lo[k], m.hi[k]
                    ));
                }
            }
            if m.exit < now {
                return Err(format!("loose: object {id} left its region at {}", m.exit));
            }
            let queued = self.exits.time_of(id);
            if queued != m.exit.is_finite().then_some(m.exit) {
                return Err(format!(
                    "loose: object {id} exits at {}, queued at {queued:?}",
                    m.exit
                ));
            }
            match self.footprint(m.lo, m.hi) {
                None => {
                    if !m.big || !m.slots.is_empty() {
                        return Err(format!("loose: object {id} is big but filed in cells"));
                    }
                    if self.big.iter().filter(|&&x| x == id).count() != 1 {
                        return Err(format!("loose: big object {id} not listed once"));
                    }
                }
                Some(f) => {
                    let mut want = Vec::new();
                    for key in cell_keys(f) {
                        let Some(&slot) = self.cells.get(&key) else {
                            return Err(format!("loose: object {id}: cell {key:?} missing"));
                        };
                        want.push(slot);
                    }
                    if m.big || m.slots != want {
                        return Err(format!("loose: object {id} filed in the wrong cells"));
                    }
                    for &slot in &m.slots {
                        let n = self.occupants[slot as usize]
                            .iter()
                            .filter(|&&x| x == id)
                            .count();
                        if n != 1 {
                            return Err(format!("loose: object {id} listed {n} times in a cell"));
                        }
                    }
                    covered += m.slots.len();
                }
            }
        }
        if self.big.len() != self.members.iter().flatten().filter(|m| m.big).count() {
            return Err(format!("loose: {} big objects listed", self.big.len()));
        }
        if live.len() != self.live {
            return Err(format!(
                "loose: {} objects counted, {} live",
                self.live,
                live.len()
            ));
        }
        // Every listing is a member's, and every cell kept holds some.
        let listed: usize = self.occupants.iter().map(Vec::len).sum();
        let mut slots: Vec<u32> = self.cells.values().copied().collect();
        slots.sort_unstable();
        slots.dedup();
        if slots.len() != self.cells.len()
            || slots.iter().any(|&s| self.occupants[s as usize].is_empty())
            || self
                .free
                .iter()
                .any(|&s| !self.occupants[s as usize].is_empty())
        {
            return Err("loose: a cell is shared, empty but kept, or freed but not empty".into());
        }
        if covered != listed {
            return Err(format!(
                "loose: {listed} listings for {covered} filed cells"
            ));
        }
        // Partners: exactly the overlapping regions, both ways.
        let mut pairs = 0;
        for (i, &a) in live.iter().enumerate() {
            let ma = self.member(a);
            let mut want: Vec<u32> = live[..i]
                .iter()
                .chain(&live[i + 1..])
                .copied()
                .filter(|&b| {
                    let mb = self.member(b);
                    ma.lo.cmple(mb.hi).all() && mb.lo.cmple(ma.hi).all()
                })
                .collect();
            let mut have = ma.partners.clone();
            want.sort_unstable();
            have.sort_unstable();
            if want != have {
                return Err(format!(
                    "loose: object {a} has partners {have:?}, regions say {want:?}"
                ));
            }
            pairs += have.len();
        }
        if pairs != 2 * self.pairs {
            return Err(format!(
                "loose: {} pairs counted, {} held",
                self.pairs,
                pairs / 2
            ));
        }
        Ok(())
    }
}
