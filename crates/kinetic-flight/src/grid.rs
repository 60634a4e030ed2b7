//! `grid`: a hierarchical kinetic grid over the sweep's boxes. Candidate pairs are the same as
//! the sweep's (the objects whose boxes overlap), but a pair is only ever looked at while the
//! two boxes share a grid cell, so the work follows the objects' neighbourhoods instead of
//! three global orders: a body falling past a pile a kilometre away costs nothing.
//!
//! - Levels: level `L` has cubic cells of side `base r^L`. An object lives at the lowest level
//!   whose nominal cells are at least as wide as its box. It is also a visitor at every
//!   occupied level above its own. The ratio `r` is a power of two set by the first objects:
//!   2 when their sizes are alike, wider when the middle 98% of them spread over more than
//!   three octaves (8 for sizes over three orders of magnitude), so that an object visits a
//!   few levels instead of one per octave.
//! - Footprints: at each of its levels an object holds the range of cells its box overlaps.
//!   Four certificates per axis keep it at its own level: each end of the box stays within the
//!   cell range. An end that leaves the range extends it at once; an end that moved a whole
//!   cell inward shrinks it once it is a hysteresis (`1e-6` of the cell) past the line, so an
//!   end that sits on a grid line never makes events back and forth.
//! - Derived footprints: cell sides are the base times powers of two, so where a visited
//!   level's cells are the own level's times `2^s`, each of its cells holds whole own cells
//!   and the range there is the own range shifted right by `s` bits. It has no certificates:
//!   it changes when the own range does (at most one end, one cell, the same way). Only a
//!   visited level whose cells are narrower than the own level's (own cells widened for
//!   sparse objects) keeps certificates of its own. On the rapier debris field at 1e4 this
//!   took the cell crossings from 34,171 to 19,271 over 120 steps, with the same pairs.
//! - Pairs: two objects are a grid pair while they share a cell at the higher of their two
//!   levels (a visitor pairs with the cell's owners, an owner with everyone there), counted
//!   over the cells they share. Boxes that overlap share every cell of their overlap, so no
//!   pair with overlapping boxes is outside the grid pairs.
//! - Box pairs: a grid pair is a candidate while its two boxes overlap on all three axes.
//!   A candidate has a certificate per axis (each stays overlapping); a pair that is not has
//!   one, on a witness axis where the boxes are apart (the one that stays apart longest),
//!   since the boxes cannot overlap before it closes whatever the other two axes do. When
//!   it closes, the other two are looked at afresh: the pair becomes a candidate or takes
//!   another witness. Boxes meet exactly when they meet and part a hysteresis (`1e-6` of
//!   the smaller box) after they part. On the rapier debris field at 1e4 the witness took
//!   the box events from 12,459 to 752 over 120 steps, with the same candidates.
//!
//! - Cell sizes: a level's cells are first narrowed (by powers of two) to the widest of the
//!   objects that first fill it, so that a level whose objects are smaller than its nominal
//!   size does not draw every small object around into its cells. A level first filled by at
//!   least 32 objects at once then gets cells widened by a power of two (at most 64x) to
//!   about one of its objects per cell: fewer crossings.
//!
//! Cost: a footprint (12 certificates) per object at its own level and at each occupied level
//! above it whose cells are narrower, one certificate per grid pair (three for a candidate),
//! in one queue entry; an event costs O(1)
//! hash-map work and a queue update.
//! The sweep's events are the swaps of three global orders, O(n^2) for a crowd that passes
//! another; the grid's are the cell crossings and the box events of neighbours.

use crate::sweep::{Ends, box_ends, box_width};
use kinetic_core::roots::quadratic_roots;
use kinetic_core::{
    Bodies, CandidateStructure, EventQueue, PairChange, Real, ScalarKey, Vec3, sign,
};
use rustc_hash::{FxHashMap, FxHashSet};
use std::collections::BTreeSet;

/// Hysteresis of a release (a footprint shrinking, two boxes parting), relative to the cell
/// or the smaller box.
const HYSTERESIS: Real = 1e-6;
/// The same, relative to the coordinates: several float spacings, so that a release is never
/// undone by rounding at large coordinates.
const HYSTERESIS_ABS: Real = 1e-12;

/// Levels the middle 98% of the first objects' sizes are spread over, at most: the ratio of
/// one level's cells to the next is the power of two that gives this.
const BULK_LEVELS: Real = 3.0;
/// The widest ratio between levels.
const MAX_RATIO: Real = 16.0;

/// The most a level's cells are widened for sparse objects.
const MAX_WIDEN: Real = 64.0;
/// The fewest objects of a level whose spread widens its cells.
const WIDEN_MIN_OBJECTS: usize = 32;

/// With a least flight ([`Grid::with_least_flight`]), an object whose box would travel more
/// than this many of its own level's cells on an axis within that flight is fast...
const FAST_SPAN: Real = 8.0;
/// ... and a fast one stays fast until that travel is under this many.
const SLOW_SPAN: Real = 4.0;
/// A fast object's region is wider than the box it sweeps by this many box widths on every
/// side.
const FAST_MARGIN: Real = 0.25;

/// A cell: its level and integer coordinates.
type CellKey = (i32, i64, i64, i64);

/// A polynomial in local time `tau = t - now`: `[c0, c1, c2]`.
pub(crate) type Local = [Real; 3];

/// The first time after `now` at which `c - g` changes sign to `to` (+1 or -1), or `now`
/// itself when it is already on that side just after `now`; +infinity for never. The roots
/// are those of `kinetic_core::roots` (the same closed forms, without building a polynomial).
pub(crate) fn crossing(c: Local, g: Real, to: i8, now: Real) -> Real {
    let p = [c[0] - g, c[1], c[2]];
    let s = sign_after(p);
    if s == to {
        return now;
    }
    if s == 0 {
        return Real::INFINITY;
    }
    // Just after `now` the sign is -to: the first root where it changes is the answer.
    if p[2] == 0.0 {
        let tau = -p[0] / p[1];
        return if tau > 0.0 && tau.is_finite() {
            now + tau
        } else {
            Real::INFINITY
        };
    }
    let mut roots = [(0.0, false); 4];
    let n = quadratic_roots(p[0], p[1], p[2], &mut roots);
    roots[..n]
        .iter()
        .find(|(_, touch)| !touch)
        .map_or(Real::INFINITY, |(tau, _)| now + tau)
}

/// The box that a box sweeps over local times `0..=h`, widened by `margin` on every side; its
/// ends are `keys` (per axis, the lower and the upper end as polynomials in local time).
pub(crate) fn swept_box(keys: &[(Local, Local); 3], h: Real, margin: Real) -> (Vec3, Vec3) {
    let eval = |c: Local, t: Real| c[0] + (c[1] + c[2] * t) * t;
    let (mut lo, mut hi) = (Vec3::ZERO, Vec3::ZERO);
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
        lo[k] = lmin - margin;
        hi[k] = umax + margin;
    }
    (lo, hi)
}

/// When the box with ends `keys` (around `now`) first leaves the region `lo..hi` after
/// `now` (`now` if it is outside already or leaving).
pub(crate) fn exit_from(keys: &[(Local, Local); 3], lo: Vec3, hi: Vec3, now: Real) -> Real {
    let mut t = Real::INFINITY;
    for (k, (l, u)) in keys.iter().enumerate() {
        t = t
            .min(crossing(*l, lo[k], -1, now))
            .min(crossing(*u, hi[k], 1, now));
    }
    t
}

/// The finest cells and the ratio between levels for objects of widths `w`: the smallest
/// width, and the power of two that spreads the middle 98% of the widths over about
/// [`BULK_LEVELS`] levels (at most [`MAX_RATIO`]). `None` without a positive finite width.
pub(crate) fn levels_for(w: impl Iterator<Item = Real>) -> Option<(Real, Real)> {
    let mut w: Vec<Real> = w.filter(|w| *w > 0.0 && w.is_finite()).collect();
    if w.is_empty() {
        return None;
    }
    w.sort_unstable_by(Real::total_cmp);
    let pick = |q: Real| w[((w.len() - 1) as Real * q).round() as usize];
    let octaves = (pick(0.99) / pick(0.01)).log2();
    let ratio = (2.0 as Real)
        .powf((octaves / BULK_LEVELS).ceil().max(1.0))
        .min(MAX_RATIO);
    Some((w[0], ratio))
}

/// Whether two zones (closed boxes, lower and upper corners) meet, give or take rounding.
fn zones_meet(a: (Vec3, Vec3), b: (Vec3, Vec3)) -> bool {
    (0..3).all(|k| {
        let tol = (1e-9 * ((a.1[k] - a.0[k]) + (b.1[k] - b.0[k]))
            + 1e-12 * (a.0[k].abs() + b.0[k].abs()))
        .max(0.0);
        a.0[k] <= b.1[k] + tol && b.0[k] <= a.1[k] + tol
    })
}

/// The sign of `c` just after local time 0.
fn sign_after(c: Local) -> i8 {
    c.iter().find(|&&x| x != 0.0).map_or(0, |&x| sign(x))
}

fn minus(a: Local, b: Local) -> Local {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The cells an object covers at one level, and the footprint certificates' failure times.
#[derive(Clone, Debug)]
struct Track {
    level: i32,
    /// Per axis, the first and last cell index.
    cells: [[i64; 2]; 3],
    /// Per axis: lower end leaves (extend down), lower end a cell in (shrink), upper end
    /// leaves (extend up), upper end a cell in (shrink). All infinite on a derived track.
    due: [[Real; 4]; 3],
    /// `Some(s)` on a derived track: a visited level whose cells are the object's own level's
    /// times `2^s`, whose range is the own range shifted right by `s` bits. It has no
    /// certificates of its own and changes with the own track.
    shift: Option<u32>,
}

impl Track {
    /// The track at `level`, whose cells are `own`'s times `2^shift`, derived from `own`.
    fn derived(own: &Track, level: i32, shift: u32) -> Track {
        Track {
            level,
            cells: own.cells.map(|[a, b]| [a >> shift, b >> shift]),
            due: [[Real::INFINITY; 4]; 3],
            shift: Some(shift),
        }
    }
}

/// An object in the grid.
#[derive(Clone, Debug)]
struct Member {
    level: i32,
    /// Its box's size (the widest side).
    width: Real,
    /// The lower and upper ends of its box, per axis.
    lo: [ScalarKey; 3],
    hi: [ScalarKey; 3],
    /// Its own level first, then the occupied levels above it.
    tracks: Vec<Track>,
    /// Its grid pairs' slots.
    pairs: Vec<u32>,
    /// A fast object's region (it then has no tracks and is in no cell): the box its box
    /// sweeps over the least flight, widened by [`FAST_MARGIN`] of its width.
    region: Option<(Vec3, Vec3)>,
}

/// A cell's objects: those living at its level, and visitors from below.
#[derive(Clone, Debug, Default)]
struct Cell {
    owners: Vec<u32>,
    visitors: Visitors,
}

/// A cell's visitors: a short list while there are few (most cells), a set once there are
/// many (a coarse cell may hold thousands of small visitors).
#[derive(Clone, Debug)]
enum Visitors {
    Few(Vec<u32>),
    Many(FxHashSet<u32>),
}

/// The most visitors a cell keeps in a list.
const FEW_VISITORS: usize = 16;

impl Default for Visitors {
    fn default() -> Self {
        Visitors::Few(Vec::new())
    }
}

impl Visitors {
    fn insert(&mut self, id: u32) {
        match self {
            Visitors::Few(v) if v.len() < FEW_VISITORS => v.push(id),
            Visitors::Few(v) => {
                let mut set: FxHashSet<u32> = v.drain(..).collect();
                set.insert(id);
                *self = Visitors::Many(set);
            }
            Visitors::Many(set) => {
                set.insert(id);
            }
        }
    }

    fn remove(&mut self, id: u32) {
        match self {
            Visitors::Few(v) => {
                if let Some(i) = v.iter().position(|&x| x == id) {
                    v.swap_remove(i);
                }
            }
            Visitors::Many(set) => {
                set.remove(&id);
            }
        }
    }

    fn is_empty(&self) -> bool {
        match self {
            Visitors::Few(v) => v.is_empty(),
            Visitors::Many(set) => set.is_empty(),
        }
    }

    fn iter(&self) -> impl Iterator<Item = &u32> {
        let (few, many) = match self {
            Visitors::Few(v) => (Some(v.iter()), None),
            Visitors::Many(set) => (None, Some(set.iter())),
        };
        few.into_iter().flatten().chain(many.into_iter().flatten())
    }
}

/// Every listing of the cells `cells` as `(cell, object) -> whether an owner`; an error
/// (prefixed `name`) for an empty cell kept or an object listed twice in one cell.
fn cell_listings(
    cells: &FxHashMap<CellKey, Cell>,
    name: &str,
) -> Result<FxHashMap<(CellKey, u32), bool>, String> {
    let mut listed = FxHashMap::default();
    for (key, cell) in cells {
        if cell.owners.is_empty() && cell.visitors.is_empty() {
            return Err(format!("{name}: empty cell {key:?} kept"));
        }
        let owners = cell.owners.iter().map(|&id| (id, true));
        for (id, owner) in owners.chain(cell.visitors.iter().map(|&id| (id, false))) {
            if listed.insert((*key, id), owner).is_some() {
                return Err(format!("{name}: object {id} twice in cell {key:?}"));
            }
        }
    }
    Ok(listed)
}

/// A grid pair: objects `a < b` sharing `count` cells.
#[derive(Clone, Debug)]
struct Slot {
    a: u32,
    b: u32,
    count: u32,
    /// Per axis, whether the boxes overlap there (with the parting hysteresis), as last
    /// looked at: kept up to date on all three axes while the pair is a candidate, on the
    /// witness axis alone while it is not.
    inside: [bool; 3],
    due: [Real; 3],
    /// For a pair that is not a candidate, an axis on which the boxes are apart (the one
    /// that stays apart longest): the only one watched until it closes. [`NO_WITNESS`] for a
    /// candidate.
    witness: u8,
    /// Whether the pair is a candidate (all three axes inside).
    reported: bool,
}

/// [`Slot::witness`] of a candidate pair.
const NO_WITNESS: u8 = 3;

/// The hierarchical kinetic grid: candidate pairs are the objects whose boxes overlap (the
/// sweep's), found among the objects that share grid cells.
#[derive(Debug, Default)]
pub struct Grid {
    base: Option<Real>,
    /// The ratio of a level's cells to the level below's (a power of two), set with the base.
    ratio: Real,
    /// Levels whose cells are wider than the level's size, by this power of two.
    widen: FxHashMap<i32, Real>,
    occupied: BTreeSet<i32>,
    members: Vec<Option<Member>>,
    cells: FxHashMap<CellKey, Cell>,
    pair_of: FxHashMap<(u32, u32), u32>,
    slots: Vec<Option<Slot>>,
    free: Vec<u32>,
    crossings_queue: EventQueue,
    pairs_queue: EventQueue,
    box_pairs: usize,
    crossings: u64,
    pair_events: u64,
    scratch: Vec<u32>,
    /// The least flight: 0 for none (no object is ever fast).
    least_flight: Real,
    /// The fast objects.
    fast: Vec<u32>,
    /// Per level, bounds of the cells its owners have entered (they only grow): a fast
    /// object's region looks for owners within them only.
    owned: Vec<(i32, [[i64; 2]; 3])>,
    fast_anchors: u64,
}

impl Grid {
    /// An empty grid; its finest cells are sized by the first objects.
    pub fn new() -> Grid {
        Grid::default()
    }

    /// The same grid with fast objects kept out of its cells. An object whose box would cross
    /// more than 8 of its level's cells on an axis within `flight` time units holds a region
    /// instead: the box its box sweeps over `flight`, widened by a quarter of its width. Its
    /// grid pairs are the objects whose regions or own-level cells meet that region, found
    /// again when its box reaches the region's edge. So a shot fired at any speed costs about
    /// one event per `flight` and the box events of what it passes, where in the cells it
    /// would cost one event per cell crossed. It turns back into a cell dweller once it
    /// would cross fewer than 4 cells. A broad phase stepping by `dt` passes `dt`.
    pub fn with_least_flight(mut self, flight: Real) -> Grid {
        if flight > 0.0 && flight.is_finite() {
            self.least_flight = flight;
        }
        self
    }

    /// Number of overlapping box pairs (the candidates).
    pub fn box_pairs(&self) -> usize {
        self.box_pairs
    }

    /// Number of grid pairs (objects sharing a cell), candidates included.
    pub fn grid_pairs(&self) -> usize {
        self.pair_of.len()
    }

    /// The side of level `level`'s cells: the level's nominal size, narrowed to the widest of
    /// the objects that first filled it and widened where they were sparse.
    fn cell_size(&self, level: i32) -> Real {
        let own = self.base.unwrap_or(1.0) * self.ratio().powi(level);
        own * self.widen.get(&level).copied().unwrap_or(1.0)
    }

    /// Sizes the cells of the levels that `ids` are the first to occupy: first narrowed (by
    /// powers of two, down to the level below's) to the widest of those objects, so that a
    /// level holding only smaller objects than its nominal size does not draw every small
    /// object around into its cells; then, where the level's objects are sparse, widened to
    /// about one of them per cell (at most [`MAX_WIDEN`] times): fewer crossings, and still
    /// O(1) objects per cell.
    fn widen_for(&mut self, ids: &[u32], bodies: &Bodies, now: Real) {
        let mut spread: FxHashMap<i32, (usize, Vec3, Vec3, Real)> = FxHashMap::default();
        for &id in ids {
            let m = self.make_member(bodies, id);
            if self.occupied.contains(&m.level) || self.widen.contains_key(&m.level) {
                continue;
            }
            let c = bodies[id as usize]
                .as_ref()
                .expect("a live object")
                .plan
                .position_at(now);
            let e = spread.entry(m.level).or_insert((0, c, c, 0.0));
            *e = (e.0 + 1, e.1.min(c), e.2.max(c), e.3.max(m.width));
        }
        let min_f = 1.0 / self.ratio();
        for (level, (n, lo, hi, widest)) in spread {
            let nominal = self.cell_size(level);
            let mut f = 1.0;
            while f > min_f && nominal * f / 2.0 >= widest {
                f /= 2.0;
            }
            if n >= WIDEN_MIN_OBJECTS {
                let own = nominal * f;
                let volume = (hi - lo).max(Vec3::splat(own)).element_product();
                let side = (volume / n as Real).cbrt();
                let mut g = 1.0;
                while g < MAX_WIDEN && 2.0 * g * own <= side {
                    g *= 2.0;
                }
                f *= g;
            }
            self.widen.insert(level, f);
        }
    }

    fn ratio(&self) -> Real {
        if self.ratio >= 2.0 { self.ratio } else { 2.0 }
    }

    fn level_for(&self, width: Real) -> i32 {
        let base = self.base.unwrap_or(1.0);
        if width > 0.0 && width.is_finite() {
            (((width / base).log2() / self.ratio().log2()).ceil() as i32).clamp(-200, 200)
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

    /// The member for object `id`'s current plan and box (no tracks yet).
    fn make_member(&self, bodies: &Bodies, id: u32) -> Member {
        let (lo, hi): Ends = box_ends(bodies, id);
        let plan = &bodies[id as usize].as_ref().expect("a live object").plan;
        let width = (hi - lo).max_element();
        Member {
            level: self.level_for(width),
            width,
            lo: std::array::from_fn(|k| ScalarKey::from_plan(plan, k, lo[k])),
            hi: std::array::from_fn(|k| ScalarKey::from_plan(plan, k, hi[k])),
            tracks: Vec::new(),
            pairs: Vec::new(),
            region: None,
        }
    }

    /// The ends of the box of `m` around `now`, per axis.
    fn keys_of(m: &Member, now: Real) -> [(Local, Local); 3] {
        std::array::from_fn(|k| (m.lo[k].local(now), m.hi[k].local(now)))
    }

    /// Whether `m` at `now` travels more than `span` of its own level's cells on an axis
    /// within the least flight (never without one).
    fn is_fast(&self, m: &Member, now: Real, span: Real) -> bool {
        if self.least_flight <= 0.0 {
            return false;
        }
        let h = self.least_flight;
        let travel = (0..3)
            .map(|k| {
                let c = m.lo[k].local(now);
                c[1].abs() * h + c[2].abs() * h * h
            })
            .fold(0.0, Real::max);
        travel > span * self.cell_size(m.level)
    }

    /// Where member `id` may be: a fast one's region, else the cells of its own track.
    fn zone(&self, id: u32) -> (Vec3, Vec3) {
        let m = self.member(id);
        if let Some(region) = m.region {
            return region;
        }
        let t = &m.tracks[0];
        let s = self.cell_size(t.level);
        let lo = Vec3::from_array(std::array::from_fn(|k| s * t.cells[k][0] as Real));
        let hi = Vec3::from_array(std::array::from_fn(|k| s * (t.cells[k][1] + 1) as Real));
        (lo, hi)
    }

    /// Whether fast member `f` and member `x` are a grid pair: their zones meet.
    fn fast_pair(&self, f: u32, x: u32) -> bool {
        zones_meet(self.zone(f), self.zone(x))
    }

    /// Gives fast member `id` (no tracks, in no cell) a fresh region from `now`, makes its
    /// grid pairs those whose zones meet it (reporting the changes) and schedules its exit.
    fn anchor_fast(&mut self, id: u32, now: Real, changes: &mut Vec<PairChange>) {
        self.fast_anchors += 1;
        let m = self.member(id);
        let keys = Self::keys_of(m, now);
        let scale = keys
            .iter()
            .map(|(l, u)| l[0].abs().max(u[0].abs()))
            .fold(0.0, Real::max)
            + m.width;
        let margin = (FAST_MARGIN * m.width)
            .max(1e-9 * scale)
            .max(Real::MIN_POSITIVE);
        let (lo, hi) = swept_box(&keys, self.least_flight, margin);
        let exit = exit_from(&keys, lo, hi, now);
        self.members[id as usize].as_mut().expect("a member").region = Some((lo, hi));
        let want = self.fast_partners(id, lo, hi);
        let m = self.member(id);
        let mut have: Vec<u32> = m
            .pairs
            .iter()
            .map(|&i| {
                let slot = self.slots[i as usize].as_ref().expect("a slot");
                if slot.a == id { slot.b } else { slot.a }
            })
            .collect();
        have.sort_unstable();
        for &p in &have {
            if want.binary_search(&p).is_err() {
                self.pair_down(id, p, changes);
            }
        }
        for &p in &want {
            if have.binary_search(&p).is_err() {
                self.pair_up(id, p, now, changes);
            }
        }
        if exit.is_finite() {
            self.crossings_queue.schedule(id, exit, 0);
        } else {
            self.crossings_queue.remove(id);
        }
    }

    /// The members whose zones meet the region `lo..hi` of fast member `id`, sorted: the
    /// other fast ones, and the owners of the cells around it at every occupied level.
    fn fast_partners(&self, id: u32, lo: Vec3, hi: Vec3) -> Vec<u32> {
        let mut out: Vec<u32> = self
            .fast
            .iter()
            .copied()
            .filter(|&f| f != id && zones_meet(self.zone(f), (lo, hi)))
            .collect();
        let mut owners = Vec::new();
        // Levels whose cells around the region outnumber the cells kept are read from the
        // whole table instead, once.
        let mut whole = Vec::new();
        for &(level, bounds) in &self.owned {
            let s = self.cell_size(level);
            // One cell more on every side, so that a cell whose edge the region touches is
            // read however the division rounds; no farther than any owner has been.
            let range: [[i64; 2]; 3] = std::array::from_fn(|k| {
                [
                    ((lo[k] / s).floor() as i64)
                        .saturating_sub(1)
                        .max(bounds[k][0]),
                    ((hi[k] / s).floor() as i64)
                        .saturating_add(1)
                        .min(bounds[k][1]),
                ]
            });
            if range.iter().any(|[a, b]| a > b) {
                continue;
            }
            let count: Real = range
                .iter()
                .map(|[a, b]| *b as Real - *a as Real + 1.0)
                .product();
            if count > self.cells.len() as Real {
                whole.push((level, range));
                continue;
            }
            for x in range[0][0]..=range[0][1] {
                for y in range[1][0]..=range[1][1] {
                    for z in range[2][0]..=range[2][1] {
                        if let Some(cell) = self.cells.get(&(level, x, y, z)) {
                            owners.extend_from_slice(&cell.owners);
                        }
                    }
                }
            }
        }
        if !whole.is_empty() {
            for (key, cell) in &self.cells {
                let within = whole.iter().any(|(level, r)| {
                    *level == key.0
                        && [key.1, key.2, key.3]
                            .iter()
                            .zip(r)
                            .all(|(c, [a, b])| a <= c && c <= b)
                });
                if within {
                    owners.extend_from_slice(&cell.owners);
                }
            }
        }
        owners.sort_unstable();
        owners.dedup();
        out.extend(
            owners
                .into_iter()
                .filter(|&x| x != id && zones_meet(self.zone(x), (lo, hi))),
        );
        out.sort_unstable();
        out
    }

    /// Makes the grid pairs of member `id`, which lives in cells, with the fast members those
    /// whose regions meet its own-level cells (after its own track changed).
    fn fast_links(&mut self, id: u32, now: Real, changes: &mut Vec<PairChange>) {
        for i in 0..self.fast.len() {
            let f = self.fast[i];
            let want = self.fast_pair(f, id);
            let have = self.pair_of.contains_key(&(f.min(id), f.max(id)));
            if want && !have {
                self.pair_up(f, id, now, changes);
            } else if have && !want {
                self.pair_down(f, id, changes);
            }
        }
    }

    /// Puts member `id` (in `members`, with no tracks, region or pairs) into the grid: fast,
    /// with a region, or into the cells of its levels.
    fn settle(&mut self, id: u32, now: Real, changes: &mut Vec<PairChange>) {
        let m = self.member(id);
        if self.is_fast(m, now, FAST_SPAN) {
            self.fast.push(id);
            self.anchor_fast(id, now, changes);
        } else {
            // Out of the members while its level fills, or it would visit there itself.
            let m = self.members[id as usize].take().expect("a member");
            self.occupy(m.level, now, changes);
            self.members[id as usize] = Some(m);
            self.place(id, now, changes);
        }
    }

    /// The footprint of `m` at `level` at time `now`, certificates not yet computed.
    fn footprint(&self, m: &Member, level: i32, now: Real) -> Track {
        let s = self.cell_size(level);
        let mut cells = [[0i64; 2]; 3];
        for (k, c) in cells.iter_mut().enumerate() {
            let (lo, hi) = (m.lo[k].local(now), m.hi[k].local(now));
            let mut a = (lo[0] / s).floor() as i64;
            while sign_after([lo[0] - s * a as Real, lo[1], lo[2]]) < 0 {
                a -= 1;
            }
            let mut b = ((hi[0] / s).floor() as i64).max(a);
            while sign_after([s * (b + 1) as Real - hi[0], -hi[1], -hi[2]]) < 0 {
                b += 1;
            }
            *c = [a, b];
        }
        let mut track = Track {
            level,
            cells,
            due: [[Real::INFINITY; 4]; 3],
            shift: None,
        };
        for k in 0..3 {
            self.certify_axis(m, &mut track, k, now);
        }
        track
    }

    /// `Some(s)` when the cells of `level`, a level above `own`, are `own`'s times `2^s`: an
    /// object living at `own` then covers, at `level`, the cells that hold its own cells (its
    /// box's ends cross a line of `level` only where they cross one of `own`), so its track
    /// there is derived from its own track instead of certified.
    fn shift_to(&self, own: i32, level: i32) -> Option<u32> {
        if level == own {
            return None;
        }
        let r = self.cell_size(level) / self.cell_size(own);
        let s = r.log2().round();
        (r >= 1.0 && s <= 62.0 && (2.0 as Real).powi(s as i32) == r).then_some(s as u32)
    }

    /// The track of `m` at `level` above its own, at time `now`, given its own track `own`:
    /// derived from it where the cells allow, else certified.
    fn track_at(&self, m: &Member, own: &Track, level: i32, now: Real) -> Track {
        match self.shift_to(m.level, level) {
            Some(s) => Track::derived(own, level, s),
            None => self.footprint(m, level, now),
        }
    }

    /// The four footprint certificates of `track` on `axis`.
    fn certify_axis(&self, m: &Member, track: &mut Track, k: usize, now: Real) {
        let s = self.cell_size(track.level);
        let [a, b] = track.cells[k];
        let (lo, hi) = (m.lo[k].local(now), m.hi[k].local(now));
        let slack = |g: Real| HYSTERESIS * s + HYSTERESIS_ABS * g.abs();
        let (ga, gb) = (s * a as Real, s * (b + 1) as Real);
        let inner_a = s * (a + 1) as Real;
        let inner_b = s * b as Real;
        track.due[k] = [
            crossing(lo, ga, -1, now),
            if a < b {
                crossing(lo, inner_a + slack(inner_a), 1, now)
            } else {
                Real::INFINITY
            },
            crossing(hi, gb, 1, now),
            if a < b {
                crossing(hi, inner_b - slack(inner_b), -1, now)
            } else {
                Real::INFINITY
            },
        ];
    }

    fn next_crossing(m: &Member) -> Real {
        m.tracks
            .iter()
            .filter(|t| t.shift.is_none())
            .flat_map(|t| t.due.iter().flatten())
            .fold(Real::INFINITY, |x, &y| x.min(y))
    }

    fn schedule_member(&mut self, id: u32) {
        let t = Self::next_crossing(self.member(id));
        if t.is_finite() {
            self.crossings_queue.schedule(id, t, 0);
        } else {
            self.crossings_queue.remove(id);
        }
    }

    /// Cells of `track` whose index on axis `k` is `i` (a slab), or all when `k` is 3.
    fn cells_of(track: &Track, slab: Option<(usize, i64)>, out: &mut Vec<CellKey>) {
        out.clear();
        let range = |k: usize| match slab {
            Some((axis, i)) if axis == k => i..=i,
            _ => track.cells[k][0]..=track.cells[k][1],
        };
        for x in range(0) {
            for y in range(1) {
                for z in range(2) {
                    out.push((track.level, x, y, z));
                }
            }
        }
    }

    fn enter(
        &mut self,
        id: u32,
        key: CellKey,
        owner: bool,
        now: Real,
        changes: &mut Vec<PairChange>,
    ) {
        if owner {
            let (level, cell) = (key.0, [key.1, key.2, key.3]);
            match self.owned.iter_mut().find(|(l, _)| *l == level) {
                Some((_, b)) => {
                    for k in 0..3 {
                        b[k] = [b[k][0].min(cell[k]), b[k][1].max(cell[k])];
                    }
                }
                None => self.owned.push((level, cell.map(|c| [c, c]))),
            }
        }
        let cell = self.cells.entry(key).or_default();
        let mut partners = std::mem::take(&mut self.scratch);
        partners.clear();
        partners.extend_from_slice(&cell.owners);
        if owner {
            partners.extend(cell.visitors.iter().copied());
            cell.owners.push(id);
        } else {
            cell.visitors.insert(id);
        }
        for &p in &partners {
            self.pair_up(id, p, now, changes);
        }
        self.scratch = partners;
    }

    fn leave(&mut self, id: u32, key: CellKey, owner: bool, changes: &mut Vec<PairChange>) {
        let Some(cell) = self.cells.get_mut(&key) else {
            return;
        };
        if owner {
            if let Some(i) = cell.owners.iter().position(|&x| x == id) {
                cell.owners.swap_remove(i);
            }
        } else {
            cell.visitors.remove(id);
        }
        let mut partners = std::mem::take(&mut self.scratch);
        partners.clear();
        partners.extend_from_slice(&cell.owners);
        if owner {
            partners.extend(cell.visitors.iter().copied());
        }
        if cell.owners.is_empty() && cell.visitors.is_empty() {
            self.cells.remove(&key);
        }
        for &p in &partners {
            self.pair_down(id, p, changes);
        }
        self.scratch = partners;
    }

    /// The per-axis states of the boxes of `a` and `b` just after `now` (looked at afresh on
    /// the axes `fresh`, kept on the others), and their certificates: for a candidate, when
    /// each axis parts; for a pair that is not, when its witness closes (the apart axis that
    /// closes last), with no certificate on the other two, since the boxes cannot overlap
    /// before then whatever those do.
    fn certify_pair(&self, slot: &mut Slot, now: Real, fresh: [bool; 3]) {
        let (ma, mb) = (self.member(slot.a), self.member(slot.b));
        let slack_rel = HYSTERESIS * ma.width.min(mb.width);
        let mut ends = [[[0.0; 3]; 2]; 3];
        for k in 0..3 {
            // p1: b's upper end above a's lower end; p2: a's upper end above b's lower end.
            let p1 = minus(mb.hi[k].local(now), ma.lo[k].local(now));
            let p2 = minus(ma.hi[k].local(now), mb.lo[k].local(now));
            if fresh[k] {
                slot.inside[k] = sign_after(p1) >= 0 && sign_after(p2) >= 0;
            }
            ends[k] = [p1, p2];
        }
        slot.due = [Real::INFINITY; 3];
        if slot.inside.iter().all(|&x| x) {
            slot.witness = NO_WITNESS;
            for (k, [p1, p2]) in ends.into_iter().enumerate() {
                let e = slack_rel + HYSTERESIS_ABS * (ma.lo[k].k0.abs() + mb.lo[k].k0.abs());
                slot.due[k] = crossing(p1, -e, -1, now).min(crossing(p2, -e, -1, now));
            }
            return;
        }
        let mut witness: Option<(usize, Real)> = None;
        for (k, [p1, p2]) in ends.into_iter().enumerate() {
            if slot.inside[k] {
                continue;
            }
            // Apart on this axis: the one of p1, p2 that is below zero (their sum, the two
            // widths, is positive) comes back up.
            let low = if p1[0] <= p2[0] { p1 } else { p2 };
            let close = crossing(low, 0.0, 1, now);
            if witness.is_none_or(|(_, t)| close > t) {
                witness = Some((k, close));
            }
        }
        let (k, close) = witness.expect("an axis apart");
        slot.witness = k as u8;
        slot.due[k] = close;
    }

    fn schedule_slot(&mut self, i: u32) {
        let slot = self.slots[i as usize].as_ref().expect("a slot");
        let t = slot.due.iter().fold(Real::INFINITY, |x, &y| x.min(y));
        if t.is_finite() {
            self.pairs_queue.schedule(i, t, 0);
        } else {
            self.pairs_queue.remove(i);
        }
    }

    /// Reports a change of slot `i`'s candidacy.
    fn report(&mut self, i: u32, changes: &mut Vec<PairChange>) {
        let slot = self.slots[i as usize].as_mut().expect("a slot");
        let now_in = slot.inside.iter().all(|&x| x);
        if now_in != slot.reported {
            slot.reported = now_in;
            let delta = if now_in { 1 } else { -1 };
            changes.push(PairChange {
                a: slot.a,
                b: slot.b,
                delta,
            });
            if now_in {
                self.box_pairs += 1;
            } else {
                self.box_pairs -= 1;
            }
        }
    }

    fn pair_up(&mut self, x: u32, y: u32, now: Real, changes: &mut Vec<PairChange>) {
        let key = (x.min(y), x.max(y));
        if let Some(&i) = self.pair_of.get(&key) {
            self.slots[i as usize].as_mut().expect("a slot").count += 1;
            return;
        }
        let mut slot = Slot {
            a: key.0,
            b: key.1,
            count: 1,
            inside: [false; 3],
            due: [Real::INFINITY; 3],
            witness: NO_WITNESS,
            reported: false,
        };
        self.certify_pair(&mut slot, now, [true; 3]);
        let i = match self.free.pop() {
            Some(i) => {
                self.slots[i as usize] = Some(slot);
                i
            }
            None => {
                self.slots.push(Some(slot));
                (self.slots.len() - 1) as u32
            }
        };
        self.pair_of.insert(key, i);
        for m in [key.0, key.1] {
            self.members[m as usize]
                .as_mut()
                .expect("a member")
                .pairs
                .push(i);
        }
        self.schedule_slot(i);
        self.report(i, changes);
    }

    fn pair_down(&mut self, x: u32, y: u32, changes: &mut Vec<PairChange>) {
        let key = (x.min(y), x.max(y));
        let Some(&i) = self.pair_of.get(&key) else {
            return;
        };
        let slot = self.slots[i as usize].as_mut().expect("a slot");
        slot.count -= 1;
        if slot.count > 0 {
            return;
        }
        if slot.reported {
            slot.inside = [false; 3];
            self.report(i, changes);
        }
        self.slots[i as usize] = None;
        self.free.push(i);
        self.pair_of.remove(&key);
        self.pairs_queue.remove(i);
        for m in [key.0, key.1] {
            let pairs = &mut self.members[m as usize].as_mut().expect("a member").pairs;
            if let Some(j) = pairs.iter().position(|&p| p == i) {
                pairs.swap_remove(j);
            }
        }
    }

    /// Makes `level` occupied: every member below it becomes a visitor there.
    fn occupy(&mut self, level: i32, now: Real, changes: &mut Vec<PairChange>) {
        if !self.occupied.insert(level) {
            return;
        }
        let below: Vec<u32> = (0..self.members.len() as u32)
            .filter(|&id| {
                self.members[id as usize]
                    .as_ref()
                    .is_some_and(|m| m.level < level && !m.tracks.is_empty())
            })
            .collect();
        let mut keys = Vec::new();
        for id in below {
            let m = self.member(id);
            let track = self.track_at(m, &m.tracks[0], level, now);
            Self::cells_of(&track, None, &mut keys);
            let m = self.members[id as usize].as_mut().expect("a member");
            let at = m.tracks.partition_point(|t| t.level < level);
            m.tracks.insert(at, track);
            for &key in &keys {
                self.enter(id, key, false, now, changes);
            }
            self.schedule_member(id);
        }
    }

    /// Puts member `id` (already in `members`, no tracks) into the cells of its levels.
    fn place(&mut self, id: u32, now: Real, changes: &mut Vec<PairChange>) {
        let level = self.member(id).level;
        let levels: Vec<i32> = self.occupied.range(level..).copied().collect();
        self.members[id as usize]
            .as_mut()
            .expect("a member")
            .tracks
            .reserve_exact(levels.len());
        let mut keys = Vec::new();
        for l in levels {
            let m = self.member(id);
            let track = match m.tracks.first() {
                Some(own) => self.track_at(m, own, l, now),
                None => self.footprint(m, l, now),
            };
            Self::cells_of(&track, None, &mut keys);
            self.members[id as usize]
                .as_mut()
                .expect("a member")
                .tracks
                .push(track);
            for &key in &keys {
                self.enter(id, key, l == level, now, changes);
            }
        }
        self.schedule_member(id);
        self.fast_links(id, now, changes);
    }

    /// Takes member `id` out of every cell or out of the fast ones (all its pairs go) and
    /// out of the queue: it is left with no tracks and no region.
    fn unplace(&mut self, id: u32, changes: &mut Vec<PairChange>) {
        let m = self.members[id as usize].as_mut().expect("a member");
        let (level, tracks) = (m.level, std::mem::take(&mut m.tracks));
        if m.region.take().is_some()
            && let Some(i) = self.fast.iter().position(|&x| x == id)
        {
            self.fast.swap_remove(i);
        }
        let mut keys = Vec::new();
        for track in &tracks {
            Self::cells_of(track, None, &mut keys);
            for &key in &keys {
                self.leave(id, key, track.level == level, changes);
            }
        }
        // What is left are pairs with fast members, or a fast member's own.
        for i in self.member(id).pairs.clone() {
            let slot = self.slots[i as usize].as_ref().expect("a slot");
            let other = if slot.a == id { slot.b } else { slot.a };
            self.pair_down(id, other, changes);
        }
        self.crossings_queue.remove(id);
    }

    fn process_crossing(&mut self, id: u32, now: Real, changes: &mut Vec<PairChange>) {
        let m = self.member(id);
        if m.region.is_some() {
            // A fast member's box reached its region's edge: a new region, or back into the
            // cells once it is slow.
            if self.is_fast(m, now, SLOW_SPAN) {
                self.anchor_fast(id, now, changes);
            } else {
                self.unplace(id, changes);
                self.settle(id, now, changes);
            }
            return;
        }
        if self.is_fast(m, now, FAST_SPAN) {
            // Sped up (an accelerated plan): out of the cells.
            self.unplace(id, changes);
            self.settle(id, now, changes);
            return;
        }
        self.crossings += 1;
        let m = self.member(id);
        // The due certificate: its track, axis and kind.
        let (mut ti, mut k, mut kind, mut best) = (0, 0, 0, Real::INFINITY);
        // Derived tracks have no certificates of their own.
        for (i, t) in m
            .tracks
            .iter()
            .enumerate()
            .filter(|(_, t)| t.shift.is_none())
        {
            for (axis, due) in t.due.iter().enumerate() {
                for (c, &d) in due.iter().enumerate() {
                    if d < best {
                        (ti, k, kind, best) = (i, axis, c, d);
                    }
                }
            }
        }
        let owner = m.tracks[ti].level == m.level;
        let mut track = m.tracks[ti].clone();
        let [a, b] = track.cells[k];
        let mut keys = Vec::new();
        // Which end of the range moves, the slab of cells entered or left, the new end.
        let (end, slab, moved, entering) = match kind {
            0 => (0, a - 1, a - 1, true),
            1 => (0, a, a + 1, false),
            2 => (1, b + 1, b + 1, true),
            _ => (1, b, b - 1, false),
        };
        track.cells[k][end] = moved;
        // The slab spans the other axes' ranges, which this event leaves as they are.
        Self::cells_of(&track, Some((k, slab)), &mut keys);
        for &key in &keys {
            if entering {
                self.enter(id, key, owner, now, changes);
            } else {
                self.leave(id, key, owner, changes);
            }
        }
        self.certify_axis(self.member(id), &mut track, k, now);
        let m = self.members[id as usize].as_mut().expect("a member");
        m.tracks[ti] = track;
        if owner {
            // The derived tracks follow the own range on this axis: at most one end of each
            // moves, by one cell, the same way.
            for tj in 1..m.tracks.len() {
                let m = self.member(id);
                let (own, t) = (&m.tracks[0], &m.tracks[tj]);
                let Some(shift) = t.shift else { continue };
                let want = own.cells[k].map(|c| c >> shift);
                let have = t.cells[k];
                if want == have {
                    continue;
                }
                let mut t = t.clone();
                t.cells[k] = want;
                // The slab entered (from the new range) or left (from the old).
                let (slab, from) = if want[0] < have[0] {
                    (want[0], &t)
                } else if want[0] > have[0] {
                    (have[0], &m.tracks[tj])
                } else if want[1] > have[1] {
                    (want[1], &t)
                } else {
                    (have[1], &m.tracks[tj])
                };
                Self::cells_of(from, Some((k, slab)), &mut keys);
                for &key in &keys {
                    if entering {
                        self.enter(id, key, false, now, changes);
                    } else {
                        self.leave(id, key, false, changes);
                    }
                }
                self.members[id as usize].as_mut().expect("a member").tracks[tj] = t;
            }
            self.fast_links(id, now, changes);
        }
        self.schedule_member(id);
    }

    /// Certifies every grid pair of member `id` afresh (after its plan changed).
    fn recertify_pairs(&mut self, id: u32, now: Real, changes: &mut Vec<PairChange>) {
        for i in self.member(id).pairs.clone() {
            let mut slot = self.slots[i as usize].take().expect("a slot");
            self.certify_pair(&mut slot, now, [true; 3]);
            self.slots[i as usize] = Some(slot);
            self.schedule_slot(i);
            self.report(i, changes);
        }
    }

    fn process_pair(&mut self, i: u32, now: Real, changes: &mut Vec<PairChange>) {
        self.pair_events += 1;
        let mut slot = self.slots[i as usize].take().expect("a slot");
        let k = (0..3)
            .min_by(|&x, &y| slot.due[x].total_cmp(&slot.due[y]))
            .expect("three axes");
        slot.inside[k] = !slot.inside[k];
        // A candidate's axes are all watched. A pair apart watched its witness alone, which
        // has just closed: the other two are looked at afresh.
        let fresh = if slot.reported {
            [false; 3]
        } else {
            std::array::from_fn(|j| j != k)
        };
        self.certify_pair(&mut slot, now, fresh);
        self.slots[i as usize] = Some(slot);
        self.schedule_slot(i);
        self.report(i, changes);
    }
}

impl CandidateStructure for Grid {
    fn name(&self) -> &'static str {
        "grid"
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
            // The finest cells fit the smallest box. Levels are a power of two apart, so that
            // the middle 98% of sizes span about BULK_LEVELS levels: 2 for similar sizes, wider
            // for a spread (fewer levels for each object to visit).
            let w = ids.iter().map(|&id| box_width(bodies, id));
            if let Some((base, ratio)) = levels_for(w) {
                self.base = Some(base);
                self.ratio = ratio;
            }
        }
        self.widen_for(ids, bodies, now);
        let mut fresh = Vec::with_capacity(ids.len());
        let mut fast = Vec::new();
        // The members' table grown once for the bulk, not copied over as it doubles.
        if let Some(&top) = ids.iter().max()
            && self.members.len() <= top as usize
        {
            self.members.resize(top as usize + 1, None);
        }
        for &id in ids {
            if self.present(id) {
                continue;
            }
            let m = self.make_member(bodies, id);
            if self.is_fast(&m, now, FAST_SPAN) {
                self.members[id as usize] = Some(m);
                fast.push(id);
                continue;
            }
            // Levels first, so that the visitors are in place when the owners come.
            self.occupy(m.level, now, changes);
            self.members[id as usize] = Some(m);
            fresh.push(id);
        }
        // Room for what a bulk of objects fills at once (cells, grid pairs), so that the
        // tables are not grown and copied over and over while it is placed.
        if fresh.len() > 1 {
            let n = fresh.len();
            self.cells.reserve(n);
            self.pair_of.reserve(2 * n);
            self.slots.reserve(2 * n);
        }
        for id in fresh {
            self.place(id, now, changes);
        }
        for id in fast {
            self.fast.push(id);
            self.anchor_fast(id, now, changes);
        }
    }

    fn remove(&mut self, id: u32, _: &Bodies, _: Real, changes: &mut Vec<PairChange>) {
        if !self.present(id) {
            return;
        }
        self.unplace(id, changes);
        self.members[id as usize] = None;
    }

    fn replan(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        if !self.present(id) {
            return;
        }
        let new = self.make_member(bodies, id);
        let was_fast = self.member(id).region.is_some();
        let fast = self.is_fast(&new, now, if was_fast { SLOW_SPAN } else { FAST_SPAN });
        if was_fast && fast {
            // Still fast: a new region, and its pairs certified on the new plan.
            let m = self.members[id as usize].as_mut().expect("a member");
            (m.lo, m.hi, m.width, m.level) = (new.lo, new.hi, new.width, new.level);
            self.anchor_fast(id, now, changes);
            self.recertify_pairs(id, now, changes);
            return;
        }
        if was_fast || fast || new.level != self.member(id).level {
            // A new box size, or into or out of the cells: placed afresh.
            self.unplace(id, changes);
            let pairs = self.members[id as usize]
                .replace(new)
                .expect("a member")
                .pairs;
            debug_assert!(pairs.is_empty(), "unplaced with pairs left");
            self.settle(id, now, changes);
            return;
        }
        let m = self.members[id as usize].as_mut().expect("a member");
        (m.lo, m.hi, m.width) = (new.lo, new.hi, new.width);
        // Enter the new cells before leaving the old, so that shared cells keep their pairs.
        let old = m.tracks.clone();
        let level = m.level;
        let (mut before, mut after) = (Vec::new(), Vec::new());
        for (ti, old_track) in old.iter().enumerate() {
            let m = self.member(id);
            let track = if ti == 0 {
                self.footprint(m, old_track.level, now)
            } else {
                self.track_at(m, &m.tracks[0], old_track.level, now)
            };
            Self::cells_of(old_track, None, &mut before);
            Self::cells_of(&track, None, &mut after);
            let owner = old_track.level == level;
            for &key in &after {
                if !before.contains(&key) {
                    self.enter(id, key, owner, now, changes);
                }
            }
            for &key in &before {
                if !after.contains(&key) {
                    self.leave(id, key, owner, changes);
                }
            }
            self.members[id as usize].as_mut().expect("a member").tracks[ti] = track;
        }
        self.schedule_member(id);
        self.fast_links(id, now, changes);
        self.recertify_pairs(id, now, changes);
    }

    fn next_event_time(&self) -> Real {
        self.crossings_queue
            .next_time()
            .min(self.pairs_queue.next_time())
    }

    fn process_next_event(&mut self, _: &Bodies, changes: &mut Vec<PairChange>) -> &'static str {
        let (c, p) = (self.crossings_queue.peek(), self.pairs_queue.peek());
        match (c, p) {
            (Some((id, t)), p) if p.is_none_or(|(_, tp)| t <= tp) => {
                self.process_crossing(id, t, changes);
                "crossing"
            }
            (_, Some((i, t))) => {
                self.process_pair(i, t, changes);
                "box"
            }
            _ => "crossing",
        }
    }

    fn certificates(&self) -> usize {
        let tracks: usize = self
            .members
            .iter()
            .flatten()
            .map(|m| m.tracks.iter().filter(|t| t.shift.is_none()).count())
            .sum();
        // A fast member's certificate is its box inside its region: a face each.
        4 * 3 * tracks + 6 * self.fast.len() + 3 * self.pair_of.len()
    }

    fn counters(&self) -> Vec<(&'static str, f64)> {
        let tracks = self
            .members
            .iter()
            .flatten()
            .flat_map(|m| &m.tracks)
            .fold((0, 0), |(n, d), t| (n + 1, d + t.shift.is_some() as usize));
        vec![
            ("box_pairs", self.box_pairs as f64),
            ("grid_pairs", self.pair_of.len() as f64),
            ("cells", self.cells.len() as f64),
            ("levels", self.occupied.len() as f64),
            ("tracks", tracks.0 as f64),
            ("derived_tracks", tracks.1 as f64),
            ("level_ratio", self.ratio()),
            ("crossings", self.crossings as f64),
            ("box_events", self.pair_events as f64),
            ("fast", self.fast.len() as f64),
            ("fast_anchors", self.fast_anchors as f64),
        ]
    }

    fn boxes(&self, _: &Bodies, now: Real) -> Vec<(Vec3, Vec3)> {
        self.members
            .iter()
            .flatten()
            .map(|m| {
                let lo = Vec3::from_array(std::array::from_fn(|k| m.lo[k].value_at(now)));
                let hi = Vec3::from_array(std::array::from_fn(|k| m.hi[k].value_at(now)));
                (lo, hi)
            })
            .collect()
    }

    fn validate(&self, bodies: &Bodies, now: Real) -> Result<(), String> {
        self.crossings_queue.validate()?;
        self.pairs_queue.validate()?;
        let at = |key: &ScalarKey| key.value_at(now);
        let listed = cell_listings(&self.cells, "grid")?;
        let mut covered = 0usize;
        let mut keys = Vec::new();
        for (id, m) in self.members.iter().enumerate() {
            let Some(m) = m else { continue };
            let id = id as u32;
            if bodies.get(id as usize).is_none_or(Option::is_none) {
                return Err(format!("grid: object {id} held but not live"));
            }
            let want = self.make_member(bodies, id);
            if want.level != m.level {
                return Err(format!(
                    "grid: object {id} at level {}, box says {}",
                    m.level, want.level
                ));
            }
            let listed_fast = self.fast.iter().filter(|&&f| f == id).count();
            if let Some((rlo, rhi)) = m.region {
                if listed_fast != 1 || !m.tracks.is_empty() {
                    return Err(format!(
                        "grid: fast object {id} listed {listed_fast} times, with {} tracks",
                        m.tracks.len()
                    ));
                }
                for k in 0..3 {
                    let (lo, hi) = (at(&m.lo[k]), at(&m.hi[k]));
                    let tol = 1e-9 * (m.width + lo.abs() + hi.abs());
                    if lo < rlo[k] - tol || hi > rhi[k] + tol {
                        return Err(format!(
                            "grid: fast object {id} axis {k}: box [{lo}, {hi}] out of its region [{}, {}]",
                            rlo[k], rhi[k]
                        ));
                    }
                }
                continue;
            }
            if listed_fast != 0 {
                return Err(format!("grid: object {id} in cells but listed fast"));
            }
            let levels: Vec<i32> = self.occupied.range(m.level..).copied().collect();
            let have: Vec<i32> = m.tracks.iter().map(|t| t.level).collect();
            if levels != have {
                return Err(format!(
                    "grid: object {id} tracks levels {have:?}, not {levels:?}"
                ));
            }
            for t in &m.tracks {
                let shift = self.shift_to(m.level, t.level);
                if t.shift != shift
                    || shift.is_some_and(|s| t.cells != Track::derived(&m.tracks[0], 0, s).cells)
                {
                    return Err(format!(
                        "grid: object {id} at level {}: derived {:?}, should be {shift:?} from its own cells",
                        t.level, t.shift
                    ));
                }
                let s = self.cell_size(t.level);
                for k in 0..3 {
                    let [a, b] = t.cells[k];
                    let (lo, hi) = (at(&m.lo[k]), at(&m.hi[k]));
                    let tol = 1e-9 * (s + lo.abs() + hi.abs());
                    let slack = HYSTERESIS * s + HYSTERESIS_ABS * (lo.abs() + hi.abs()) + tol;
                    if a > b
                        || lo < s * a as Real - tol
                        || hi > s * (b + 1) as Real + tol
                        || (a < b && lo > s * (a + 1) as Real + slack)
                        || (a < b && hi < s * b as Real - slack)
                    {
                        return Err(format!(
                            "grid: object {id} at level {} axis {k}: cells {a}..={b} of side {s} for box [{lo}, {hi}]",
                            t.level
                        ));
                    }
                    if t.due[k].iter().any(|&d| d < now) {
                        return Err(format!(
                            "grid: object {id} has a footprint certificate due before {now}"
                        ));
                    }
                }
                Self::cells_of(t, None, &mut keys);
                let bounds = self.owned.iter().find(|(l, _)| *l == m.level).map(|x| x.1);
                for key in &keys {
                    let inside = |b: [[i64; 2]; 3]| {
                        [key.1, key.2, key.3]
                            .iter()
                            .zip(b)
                            .all(|(c, [a, z])| a <= *c && *c <= z)
                    };
                    if t.level == m.level && !bounds.is_some_and(inside) {
                        return Err(format!(
                            "grid: object {id} owns cell {key:?} outside its level's bounds {bounds:?}"
                        ));
                    }
                    if listed.get(&(*key, id)) != Some(&(t.level == m.level)) {
                        return Err(format!(
                            "grid: object {id} not listed right in cell {key:?}"
                        ));
                    }
                }
                covered += keys.len();
            }
        }
        if covered != listed.len() {
            return Err(format!(
                "grid: {} listings for {covered} footprint cells",
                listed.len()
            ));
        }
        // Grid pairs: counted over the shared cells, owners with everyone.
        let mut want: FxHashMap<(u32, u32), u32> = FxHashMap::default();
        for cell in self.cells.values() {
            for (i, &x) in cell.owners.iter().enumerate() {
                for &y in cell.owners[i + 1..].iter().chain(cell.visitors.iter()) {
                    *want.entry((x.min(y), x.max(y))).or_default() += 1;
                }
            }
        }
        // A fast member pairs with every member whose zone meets its region, once.
        for &f in &self.fast {
            for (x, m) in self.members.iter().enumerate() {
                let x = x as u32;
                if m.is_none()
                    || x == f
                    || (m.as_ref().is_some_and(|m| m.region.is_some()) && x < f)
                {
                    continue;
                }
                if self.fast_pair(f, x) {
                    *want.entry((x.min(f), x.max(f))).or_default() += 1;
                }
            }
        }
        if want.len() != self.pair_of.len() {
            return Err(format!(
                "grid: {} grid pairs kept, {} share cells",
                self.pair_of.len(),
                want.len()
            ));
        }
        let mut reported = 0;
        for (key, count) in want {
            let Some(&i) = self.pair_of.get(&key) else {
                return Err(format!(
                    "grid: pair {key:?} shares {count} cells but is not kept"
                ));
            };
            let slot = self.slots[i as usize]
                .as_ref()
                .ok_or("grid: a kept pair without a slot")?;
            if slot.count != count || (slot.a, slot.b) != key {
                return Err(format!(
                    "grid: pair {key:?} counted {} of {count}",
                    slot.count
                ));
            }
            if slot.reported != slot.inside.iter().all(|&x| x) {
                return Err(format!(
                    "grid: pair {key:?} reported {} against its axes",
                    slot.reported
                ));
            }
            reported += slot.reported as usize;
            let witness = slot.witness as usize;
            if !slot.reported && (witness >= 3 || slot.inside[witness]) {
                return Err(format!(
                    "grid: pair {key:?} is not a candidate but has no axis apart to watch"
                ));
            }
            let (ma, mb) = (self.member(key.0), self.member(key.1));
            // A candidate's three axes are watched; a pair apart watches its witness alone.
            for k in (0..3).filter(|&k| slot.reported || k == witness) {
                let p1 = at(&mb.hi[k]) - at(&ma.lo[k]);
                let p2 = at(&ma.hi[k]) - at(&mb.lo[k]);
                let tol = 1e-9 * (ma.width + mb.width)
                    + 1e-12 * (at(&ma.lo[k]).abs() + at(&mb.lo[k]).abs());
                let e = HYSTERESIS * ma.width.min(mb.width)
                    + tol
                    + HYSTERESIS_ABS * (at(&ma.lo[k]).abs() + at(&mb.lo[k]).abs());
                let ok = if slot.inside[k] {
                    p1 >= -e && p2 >= -e
                } else {
                    p1 <= tol || p2 <= tol
                };
                if !ok {
                    return Err(format!(
                        "grid: pair {key:?} axis {k} inside = {} but the ends are {p1}, {p2} apart",
                        slot.inside[k]
                    ));
                }
                if slot.due[k] < now {
                    return Err(format!(
                        "grid: pair {key:?} has a certificate due before {now}"
                    ));
                }
            }
        }
        if reported != self.box_pairs {
            return Err(format!(
                "grid: {} box pairs counted, {reported} reported",
                self.box_pairs
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn listed(v: &Visitors) -> Vec<u32> {
        let mut ids: Vec<u32> = v.iter().copied().collect();
        ids.sort_unstable();
        ids
    }

    #[test]
    fn visitors_turn_from_a_list_into_a_set_and_keep_every_id_once() {
        let mut v = Visitors::default();
        assert!(v.is_empty());
        for id in 0..FEW_VISITORS as u32 {
            v.insert(id);
        }
        assert!(matches!(v, Visitors::Few(_)));
        v.remove(3);
        v.remove(99);
        assert_eq!(listed(&v).len(), FEW_VISITORS - 1);
        for id in 100..110 {
            v.insert(id);
        }
        assert!(matches!(v, Visitors::Many(_)));
        let mut want: Vec<u32> = (0..FEW_VISITORS as u32).filter(|&i| i != 3).collect();
        want.extend(100..110);
        assert_eq!(listed(&v), want);
        for id in want {
            v.remove(id);
        }
        assert!(v.is_empty());
        assert!(listed(&v).is_empty());
    }
}
