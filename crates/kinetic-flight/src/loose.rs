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
//!   share a grid cell with its new one.
//! - Re-plans: an object whose new plan keeps its box inside its region keeps the region and
//!   only has its exit time recomputed. A body jostled in a pile, re-planned every few steps,
//!   so costs one root computation and a queue update, not a pass over its neighbours.
//! - Cells: levels as in [`crate::Grid`], a power of two apart, sized by the regions. A
//!   region lives at the lowest level whose cells are at least as wide as it, and visits every
//!   occupied level above; it pairs with the owners of the cells it shares and, at its own
//!   level, with the visitors too.
//!
//! The candidates are a superset of the sweep's (boxes inside overlapping regions), so a
//! caller that needs exact contacts certifies them itself. It suits bodies whose plans keep
//! failing (a settling pile) and crowds that fall together, where a structure of exact box
//! pairs pays for every box event and re-plan with certificates of all its neighbours.

use crate::grid::{Cell, CellKey, Local, cell_listings, crossing, levels_for};
use crate::sweep::box_ends;
use kinetic_core::{Bodies, CandidateStructure, EventQueue, PairChange, Real, ScalarKey, Vec3};
use rustc_hash::FxHashMap;
use std::collections::BTreeSet;

/// A region stretches over the travel of this many box widths by default...
const TRAVEL: Real = 2.0;
/// ... and is wider than the swept box by this many box widths on every side.
const MARGIN: Real = 0.25;

/// The cells a region covers at one level: per axis, the first and last index.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Footprint {
    level: i32,
    cells: [[i64; 2]; 3],
}

impl Footprint {
    fn keys(&self) -> impl Iterator<Item = CellKey> + '_ {
        let [x, y, z] = self.cells;
        (x[0]..=x[1]).flat_map(move |i| {
            (y[0]..=y[1]).flat_map(move |j| (z[0]..=z[1]).map(move |k| (self.level, i, j, k)))
        })
    }
}

/// An object in the loose grid.
#[derive(Clone, Debug)]
struct Member {
    level: i32,
    /// Its region's corners.
    lo: Vec3,
    hi: Vec3,
    /// Its own level first, then the occupied levels above it.
    footprints: Vec<Footprint>,
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
    base: Option<Real>,
    ratio: Real,
    /// The median box width of the first objects: no margin is wider than `margin` of it (a
    /// ground slab's region is not metres taller than the slab).
    typical: Real,
    occupied: BTreeSet<i32>,
    members: Vec<Option<Member>>,
    cells: FxHashMap<CellKey, Cell>,
    exits: EventQueue,
    /// Stamps for collecting an object's new partners without duplicates.
    mark: Vec<u64>,
    epoch: u64,
    pairs: usize,
    anchors: u64,
    kept: u64,
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
            base: None,
            ratio: 2.0,
            typical: Real::INFINITY,
            occupied: BTreeSet::new(),
            members: Vec::new(),
            cells: FxHashMap::default(),
            exits: EventQueue::new(),
            mark: Vec::new(),
            epoch: 0,
            pairs: 0,
            anchors: 0,
            kept: 0,
            scratch: Vec::new(),
        }
    }

    /// Number of candidate pairs (overlapping regions).
    pub fn pairs(&self) -> usize {
        self.pairs
    }

    fn cell_size(&self, level: i32) -> Real {
        self.base.unwrap_or(1.0) * self.ratio.powi(level)
    }

    fn level_for(&self, width: Real) -> i32 {
        let base = self.base.unwrap_or(1.0);
        if width > 0.0 && width.is_finite() {
            (((width / base).log2() / self.ratio.log2()).ceil() as i32).clamp(-200, 200)
        } else {
            0
        }
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
        let (lo, hi) = box_ends(bodies, id);
        let w = (hi - lo).max_element();
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
        };
        let keys = Self::box_keys(bodies, id, now);
        // A margin of a few float spacings at least, so that a point object leaves after now.
        let scale = plan.position_at(now).abs().max_element() + w;
        let m = (self.margin * w.min(self.typical))
            .max(1e-9 * scale)
            .max(Real::MIN_POSITIVE);
        let eval = |c: Local, t: Real| c[0] + (c[1] + c[2] * t) * t;
        let (mut rlo, mut rhi) = (Vec3::ZERO, Vec3::ZERO);
        for (k, (l, u)) in keys.iter().enumerate() {
            // The extremes over [0, h]: at its ends, or where the axis turns.
            let turn = if l[2] != 0.0 {
                -l[1] / (2.0 * l[2])
            } else {
                0.0
            };
            let ts = [0.0, h, if turn > 0.0 && turn < h { turn } else { 0.0 }];
            let lmin = ts
                .iter()
                .map(|&t| eval(*l, t))
                .fold(Real::INFINITY, Real::min);
            let umax = ts
                .iter()
                .map(|&t| eval(*u, t))
                .fold(Real::NEG_INFINITY, Real::max);
            rlo[k] = lmin - m;
            rhi[k] = umax + m;
        }
        (rlo, rhi)
    }

    /// When object `id`'s box, on its plan, first leaves the region `lo..hi` after `now`
    /// (`now` if it is outside already or leaving).
    fn exit_time(bodies: &Bodies, id: u32, lo: Vec3, hi: Vec3, now: Real) -> Real {
        let keys = Self::box_keys(bodies, id, now);
        let mut t = Real::INFINITY;
        for (k, (l, u)) in keys.iter().enumerate() {
            t = t
                .min(crossing(*l, lo[k], -1, now))
                .min(crossing(*u, hi[k], 1, now));
        }
        t
    }

    /// The footprint of the region `lo..hi` at `level`.
    fn footprint(&self, lo: Vec3, hi: Vec3, level: i32) -> Footprint {
        let s = self.cell_size(level);
        Footprint {
            level,
            cells: std::array::from_fn(|k| {
                let a = (lo[k] / s).floor() as i64;
                [a, ((hi[k] / s).floor() as i64).max(a)]
            }),
        }
    }

    /// Makes `level` occupied: every member below it becomes a visitor there (no owners yet,
    /// so no new pairs).
    fn occupy(&mut self, level: i32) {
        if !self.occupied.insert(level) {
            return;
        }
        for id in 0..self.members.len() as u32 {
            let Some(m) = self.members[id as usize].as_ref() else {
                continue;
            };
            if m.level >= level || m.footprints.is_empty() {
                continue;
            }
            let f = self.footprint(m.lo, m.hi, level);
            for key in f.keys() {
                self.cells.entry(key).or_default().visitors.insert(id);
            }
            let m = self.members[id as usize].as_mut().expect("a member");
            let at = m.footprints.partition_point(|g| g.level < level);
            m.footprints.insert(at, f);
        }
    }

    /// Takes member `id` out of the cells of its footprints.
    fn leave_cells(&mut self, id: u32) {
        let m = self.members[id as usize].as_mut().expect("a member");
        let (level, footprints) = (m.level, std::mem::take(&mut m.footprints));
        for f in &footprints {
            for key in f.keys() {
                let Some(cell) = self.cells.get_mut(&key) else {
                    continue;
                };
                if f.level == level {
                    if let Some(i) = cell.owners.iter().position(|&x| x == id) {
                        cell.owners.swap_remove(i);
                    }
                } else {
                    cell.visitors.remove(&id);
                }
                if cell.owners.is_empty() && cell.visitors.is_empty() {
                    self.cells.remove(&key);
                }
            }
        }
    }

    /// Gives member `id` a fresh region from its plan at `now`, finds its partners again and
    /// reports the pairs that change.
    fn anchor(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        self.anchors += 1;
        let (lo, hi) = self.region(bodies, id, now);
        let level = self.level_for((hi - lo).max_element());
        if self.present(id) {
            self.leave_cells(id);
        }
        // Out of the members while its level fills, or it would visit there itself.
        let old = self.members[id as usize]
            .take()
            .map_or(Vec::new(), |m| m.partners);
        self.occupy(level);
        let levels: Vec<i32> = self.occupied.range(level..).copied().collect();
        let footprints: Vec<Footprint> =
            levels.iter().map(|&l| self.footprint(lo, hi, l)).collect();
        // Enter the cells, collecting the regions met there.
        self.epoch += 1;
        let epoch = self.epoch;
        if self.mark.len() < self.members.len() {
            self.mark.resize(self.members.len(), 0);
        }
        let mut found = std::mem::take(&mut self.scratch);
        found.clear();
        for f in &footprints {
            let owner = f.level == level;
            for key in f.keys() {
                let cell = self.cells.entry(key).or_default();
                let visitors = owner.then_some(&cell.visitors);
                for &p in cell.owners.iter().chain(visitors.into_iter().flatten()) {
                    if self.mark[p as usize] != epoch {
                        self.mark[p as usize] = epoch;
                        let q = self.members[p as usize].as_ref().expect("a member");
                        if q.lo.cmple(hi).all() && lo.cmple(q.hi).all() {
                            found.push(p);
                        }
                    }
                }
                if owner {
                    cell.owners.push(id);
                } else {
                    cell.visitors.insert(id);
                }
            }
        }
        found.sort_unstable();
        let mut old = old;
        old.sort_unstable();
        // Pairs that end, then pairs that begin.
        for &p in &old {
            if found.binary_search(&p).is_err() {
                let q = self.members[p as usize].as_mut().expect("a member");
                if let Some(i) = q.partners.iter().position(|&x| x == id) {
                    q.partners.swap_remove(i);
                }
                self.pairs -= 1;
                changes.push(pair_change(id, p, -1));
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
            level,
            lo,
            hi,
            footprints,
            partners: found.clone(),
            exit,
        });
        self.scratch = found;
        self.schedule(id, exit);
    }

    fn schedule(&mut self, id: u32, exit: Real) {
        if exit.is_finite() {
            self.exits.schedule(id, exit, 0);
        } else {
            self.exits.remove(id);
        }
    }
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
        if self.base.is_none() {
            let mut w: Vec<Real> = ids
                .iter()
                .map(|&id| {
                    let (lo, hi) = box_ends(bodies, id);
                    (hi - lo).max_element()
                })
                .filter(|w| w.is_finite())
                .collect();
            if !w.is_empty() {
                let mid = w.len() / 2;
                self.typical = *w.select_nth_unstable_by(mid, Real::total_cmp).1;
            }
            // Levels from the first regions' widths, as the grid's from its boxes'.
            let w = ids.iter().map(|&id| {
                let (lo, hi) = self.region(bodies, id, now);
                (hi - lo).max_element()
            });
            if let Some((base, ratio)) = levels_for(w) {
                self.base = Some(base);
                self.ratio = ratio;
            }
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
        self.leave_cells(id);
        let m = self.members[id as usize].take().expect("a member");
        for p in m.partners {
            let q = self.members[p as usize].as_mut().expect("a member");
            if let Some(i) = q.partners.iter().position(|&x| x == id) {
                q.partners.swap_remove(i);
            }
            self.pairs -= 1;
            changes.push(pair_change(id, p, -1));
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
            ("levels", self.occupied.len() as f64),
            ("level_ratio", self.ratio),
            ("anchors", self.anchors as f64),
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
        let listed = cell_listings(&self.cells, "loose")?;
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
            if m.level != self.level_for((m.hi - m.lo).max_element()) {
                return Err(format!("loose: object {id} at the wrong level {}", m.level));
            }
            let levels: Vec<i32> = self.occupied.range(m.level..).copied().collect();
            let have: Vec<i32> = m.footprints.iter().map(|f| f.level).collect();
            if levels != have {
                return Err(format!(
                    "loose: object {id} visits levels {have:?}, not {levels:?}"
                ));
            }
            for f in &m.footprints {
                if *f != self.footprint(m.lo, m.hi, f.level) {
                    return Err(format!("loose: object {id} has a stale footprint {f:?}"));
                }
                for key in f.keys() {
                    if listed.get(&(key, id)) != Some(&(f.level == m.level)) {
                        return Err(format!("loose: object {id} not listed right in {key:?}"));
                    }
                    covered += 1;
                }
            }
        }
        if covered != listed.len() {
            return Err(format!(
                "loose: {} listings for {covered} footprint cells",
                listed.len()
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
