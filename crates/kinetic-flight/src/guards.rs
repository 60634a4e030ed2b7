//! `guards` (Section 3.2): guards around every object, so that two objects that collide have
//! the larger containing a guard of the smaller (Lemma 7), and box events that tell which
//! boxes hold which guards.
//!
//! The guards of an object K with inner radius r are the points of a regular grid in the cube
//! C(K) of side 2 (rho + 1) r about its centre, with cells of side at most
//! 2 r / (sqrt 3 (rho + 1)) ([`GuardGrid`]): `m^3` points on `m` grid planes per axis. The
//! guards are never stored one by one. Each axis has one kinetic sorted list holding the ends
//! of every object's box (of B+, inflated by a relative 1e-9) and every object's `m` grid
//! planes, as the design notes suggest: the guards of K inside a box form a sub-grid, one
//! index range per axis, read from the list positions. A swap of a box end with a grid plane
//! of another object is a box event.
//!
//! Candidate pairs: (K, K') whenever K' is at least as large as K (inner radius) and the box
//! of K' contains a guard of K. By Lemma 7 every colliding pair is one of them. This is the
//! paper's structure without the cones of Lemma 9: the paper keeps, per cone of each guard,
//! only the closest object whose box holds the guard, which bounds the candidates even when
//! many nested boxes hold one guard (its Fig. 6). Without cones every such box is a
//! candidate; scenes where boxes of larger objects pile up on one guard cost more pairs.
//!
//! Objects fatter than the grid's rho (or whose centre is outside them) cannot be guarded;
//! they are paired with every other object.

use kinetic_core::{Bodies, CandidateStructure, KineticSortedList, PairChange, Real, ScalarKey};
use rustc_hash::FxHashSet;

/// Relative inflation of the boxes.
const INFLATE: Real = 1.0 + 1e-9;

/// The guard grid of Lemma 7 for fatness `rho`: `m` planes per axis across the cube of half
/// side `(rho + 1) r`, evenly spaced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GuardGrid {
    /// The fatness the grid guards against.
    pub rho: Real,
    /// Grid planes per axis (guards per object: `m^3`).
    pub m: u32,
}

impl GuardGrid {
    /// The grid for objects at most `rho`-fat.
    pub fn new(rho: Real) -> GuardGrid {
        let rho = rho.max(1.0);
        // Cells of side at most 2 r / (sqrt 3 (rho + 1)) across a side of 2 (rho + 1) r.
        let cells = (3f64.sqrt() * (rho + 1.0) * (rho + 1.0)).ceil();
        GuardGrid {
            rho,
            m: cells as u32 + 1,
        }
    }

    /// The offset of plane `i` from the centre, for inner radius `r`.
    pub fn offset(&self, r: Real, i: u32) -> Real {
        let half = (self.rho + 1.0) * r;
        -half + 2.0 * half * Real::from(i) / Real::from(self.m - 1)
    }

    /// The guards of an object with centre `c` and inner radius `r`.
    pub fn guards(&self, c: glam::DVec3, r: Real) -> impl Iterator<Item = glam::DVec3> + '_ {
        let m = self.m;
        (0..m * m * m).map(move |k| {
            let (i, j, l) = (k % m, (k / m) % m, k / (m * m));
            c + glam::DVec3::new(self.offset(r, i), self.offset(r, j), self.offset(r, l))
        })
    }
}

/// What an item of a list is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Item {
    Lower,
    Upper,
    Plane(u32),
}

/// The guards structure (without cones; see the module notes).
#[derive(Debug)]
pub struct Guards {
    grid: GuardGrid,
    lists: [KineticSortedList; 3],
    /// Inner radius per object (0 for ids not in the structure).
    inner: Vec<Real>,
    /// Box half side per object.
    half: Vec<Real>,
    /// Objects too fat to guard: paired with everyone.
    wild: Vec<bool>,
    wild_count: usize,
    /// Directed pairs (guarded, boxer): the boxer's box holds a guard of the guarded.
    pairs: FxHashSet<(u32, u32)>,
    /// Per object, the objects it is paired with either way (directed pairs and wild pairs).
    links: Vec<Vec<u32>>,
    box_events: u64,
    now: Real,
}

impl Guards {
    /// An empty structure whose grids guard against objects at most `rho`-fat.
    pub fn new(rho: Real) -> Guards {
        Guards {
            grid: GuardGrid::new(rho),
            lists: Default::default(),
            inner: Vec::new(),
            half: Vec::new(),
            wild: Vec::new(),
            wild_count: 0,
            pairs: FxHashSet::default(),
            links: Vec::new(),
            box_events: 0,
            now: 0.0,
        }
    }

    /// The guard grid.
    pub fn grid(&self) -> GuardGrid {
        self.grid
    }

    fn stride(&self) -> u32 {
        self.grid.m + 2
    }

    fn item(&self, object: u32, what: Item) -> u32 {
        object * self.stride()
            + match what {
                Item::Lower => 0,
                Item::Upper => 1,
                Item::Plane(i) => 2 + i,
            }
    }

    fn decode(&self, item: u32) -> (u32, Item) {
        let (o, j) = (item / self.stride(), item % self.stride());
        let what = match j {
            0 => Item::Lower,
            1 => Item::Upper,
            j => Item::Plane(j - 2),
        };
        (o, what)
    }

    fn present(&self, id: u32) -> bool {
        self.half.get(id as usize).is_some_and(|&h| h > 0.0)
    }

    /// The items of object `id` on each axis with their keys.
    fn keys(&self, bodies: &Bodies, id: u32) -> Vec<[(u32, ScalarKey); 3]> {
        let plan = &bodies[id as usize].as_ref().expect("a live object").plan;
        let (half, r) = (self.half[id as usize], self.inner[id as usize]);
        let mut out = Vec::new();
        let key = |axis, off| ScalarKey::from_plan(plan, axis, off);
        out.push(std::array::from_fn(|k| {
            (self.item(id, Item::Lower), key(k, -half))
        }));
        out.push(std::array::from_fn(|k| {
            (self.item(id, Item::Upper), key(k, half))
        }));
        if !self.wild[id as usize] {
            for i in 0..self.grid.m {
                let off = self.grid.offset(r, i);
                out.push(std::array::from_fn(|k| {
                    (self.item(id, Item::Plane(i)), key(k, off))
                }));
            }
        }
        out
    }

    /// Whether the box of `boxer` holds a guard of `guarded`, read from the three orders.
    fn holds_guard(&self, guarded: u32, boxer: u32) -> bool {
        (0..3).all(|axis| {
            let l = &self.lists[axis];
            let p = |item| l.position(item).expect("an item of the list");
            let (lo, hi) = (
                p(self.item(boxer, Item::Lower)),
                p(self.item(boxer, Item::Upper)),
            );
            (0..self.grid.m).any(|i| {
                let q = p(self.item(guarded, Item::Plane(i)));
                lo < q && q < hi
            })
        })
    }

    /// Whether `boxer` guards against `guarded`: both guarded and `boxer` at least as large.
    fn guards_against(&self, guarded: u32, boxer: u32) -> bool {
        guarded != boxer
            && !self.wild[guarded as usize]
            && !self.wild[boxer as usize]
            && self.inner[boxer as usize] >= self.inner[guarded as usize]
    }

    fn link(&mut self, a: u32, b: u32, delta: i32, changes: &mut Vec<PairChange>) {
        if delta > 0 {
            self.links[a as usize].push(b);
            self.links[b as usize].push(a);
        } else {
            for (x, y) in [(a, b), (b, a)] {
                let list = &mut self.links[x as usize];
                let i = list.iter().position(|&p| p == y).expect("a linked pair");
                list.swap_remove(i);
            }
        }
        changes.push(PairChange { a, b, delta });
    }

    /// Sets the directed pair (guarded, boxer) to `on`.
    fn set_pair(&mut self, guarded: u32, boxer: u32, on: bool, changes: &mut Vec<PairChange>) {
        let had = self.pairs.contains(&(guarded, boxer));
        if on && !had {
            self.pairs.insert((guarded, boxer));
            self.link(guarded, boxer, 1, changes);
        } else if !on && had {
            self.pairs.remove(&(guarded, boxer));
            self.link(guarded, boxer, -1, changes);
        }
    }

    fn sync(&mut self, now: Real) {
        self.now = now;
        for l in &mut self.lists {
            l.advance_clock(now)
                .expect("every swap before now was processed");
        }
    }

    fn grow(&mut self, id: u32) {
        let need = id as usize + 1;
        if self.half.len() < need {
            self.half.resize(need, 0.0);
            self.inner.resize(need, 0.0);
            self.wild.resize(need, false);
            self.links.resize(need, Vec::new());
        }
    }

    /// Registers object `id`'s sizes; returns whether it is wild.
    fn admit(&mut self, bodies: &Bodies, id: u32) -> bool {
        self.grow(id);
        let shape = &bodies[id as usize].as_ref().expect("a live object").shape;
        let (inner, outer) = (shape.inner_radius(), shape.outer_radius());
        let wild = !(inner > 0.0 && outer <= self.grid.rho * inner * (1.0 + 1e-12));
        self.half[id as usize] = outer * INFLATE;
        self.inner[id as usize] = if wild { 0.0 } else { inner };
        self.wild[id as usize] = wild;
        if wild {
            self.wild_count += 1;
        }
        wild
    }

    /// Every directed pair (guarded, boxer) whose box holds a guard, by a sweep along x over
    /// the boxes and the guard cubes.
    fn guarded_pairs(&self) -> Vec<(u32, u32)> {
        let mut out = Vec::new();
        let (mut boxes, mut cubes): (Vec<u32>, Vec<u32>) = (Vec::new(), Vec::new());
        let last = self.grid.m - 1;
        for &item in self.lists[0].order() {
            let (o, what) = self.decode(item);
            match what {
                Item::Lower => {
                    for &g in &cubes {
                        if self.guards_against(g, o) && self.holds_guard(g, o) {
                            out.push((g, o));
                        }
                    }
                    boxes.push(o);
                }
                Item::Plane(0) => {
                    for &b in &boxes {
                        if self.guards_against(o, b) && self.holds_guard(o, b) {
                            out.push((o, b));
                        }
                    }
                    cubes.push(o);
                }
                Item::Upper => boxes.retain(|&b| b != o),
                Item::Plane(i) if i == last => cubes.retain(|&c| c != o),
                Item::Plane(_) => {}
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Pairs object `id` (just added) with the others.
    fn pair_new(&mut self, id: u32, bodies: &Bodies, changes: &mut Vec<PairChange>) {
        for other in 0..bodies.len() as u32 {
            if other == id || !self.present(other) {
                continue;
            }
            if self.wild[id as usize] || self.wild[other as usize] {
                self.link(id, other, 1, changes);
                continue;
            }
            for (g, b) in [(id, other), (other, id)] {
                if self.guards_against(g, b) && self.holds_guard(g, b) {
                    self.set_pair(g, b, true, changes);
                }
            }
        }
    }
}

impl CandidateStructure for Guards {
    fn name(&self) -> &'static str {
        "guards"
    }

    fn insert(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        self.sync(now);
        self.admit(bodies, id);
        for axis_items in self.keys(bodies, id) {
            for (axis, (item, key)) in axis_items.into_iter().enumerate() {
                self.lists[axis].insert(item, key).expect("a new item");
            }
        }
        self.pair_new(id, bodies, changes);
    }

    fn insert_many(
        &mut self,
        ids: &[u32],
        bodies: &Bodies,
        now: Real,
        changes: &mut Vec<PairChange>,
    ) {
        if !self.lists[0].is_empty() || ids.len() < 2 {
            for &id in ids {
                self.insert(id, bodies, now, changes);
            }
            return;
        }
        self.now = now;
        let mut items: [Vec<(u32, ScalarKey)>; 3] = Default::default();
        for &id in ids {
            self.admit(bodies, id);
            for axis_items in self.keys(bodies, id) {
                for (axis, it) in axis_items.into_iter().enumerate() {
                    items[axis].push(it);
                }
            }
        }
        for (axis, items) in items.into_iter().enumerate() {
            self.lists[axis] = KineticSortedList::from_items(now, items).expect("valid keys");
        }
        for (g, b) in self.guarded_pairs() {
            self.set_pair(g, b, true, changes);
        }
        let wild: Vec<u32> = ids
            .iter()
            .copied()
            .filter(|&i| self.wild[i as usize])
            .collect();
        for &w in &wild {
            for &o in ids {
                if o != w && !(self.wild[o as usize] && o < w) {
                    self.link(w, o, 1, changes);
                }
            }
        }
    }

    fn remove(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        if !self.present(id) {
            return;
        }
        self.sync(now);
        for o in self.links[id as usize].clone() {
            self.link(id, o, -1, changes);
        }
        self.pairs.retain(|&(g, b)| g != id && b != id);
        for axis_items in self.keys(bodies, id) {
            for (axis, (item, _)) in axis_items.into_iter().enumerate() {
                self.lists[axis].remove(item).expect("an item");
            }
        }
        if self.wild[id as usize] {
            self.wild_count -= 1;
        }
        self.half[id as usize] = 0.0;
        self.inner[id as usize] = 0.0;
        self.wild[id as usize] = false;
    }

    fn replan(&mut self, id: u32, bodies: &Bodies, now: Real, _: &mut Vec<PairChange>) {
        if !self.present(id) {
            return;
        }
        self.sync(now);
        for axis_items in self.keys(bodies, id) {
            for (axis, (item, key)) in axis_items.into_iter().enumerate() {
                self.lists[axis].set_key(item, key).expect("an item");
            }
        }
    }

    fn next_event_time(&self) -> Real {
        self.lists
            .iter()
            .map(|l| l.next_event_time())
            .fold(Real::INFINITY, Real::min)
    }

    fn process_next_event(&mut self, _: &Bodies, changes: &mut Vec<PairChange>) -> &'static str {
        let (axis, t) = (0..3).map(|k| (k, self.lists[k].next_event_time())).fold(
            (0, Real::INFINITY),
            |best, x| if x.1 < best.1 { x } else { best },
        );
        let Some(swap) = self.lists[axis].process_next_event(t) else {
            return "swap";
        };
        self.now = self.now.max(swap.time);
        let (u, v) = (self.decode(swap.left), self.decode(swap.right));
        let (guarded, boxer) = match (u.1, v.1) {
            (Item::Plane(_), Item::Lower | Item::Upper) => (u.0, v.0),
            (Item::Lower | Item::Upper, Item::Plane(_)) => (v.0, u.0),
            _ => return "swap",
        };
        if !self.guards_against(guarded, boxer) {
            return "swap";
        }
        self.box_events += 1;
        let on = self.holds_guard(guarded, boxer);
        self.set_pair(guarded, boxer, on, changes);
        "box"
    }

    fn certificates(&self) -> usize {
        self.lists.iter().map(|l| l.certificates()).sum()
    }

    fn counters(&self) -> Vec<(&'static str, f64)> {
        let m = f64::from(self.grid.m);
        vec![
            ("grid_planes_per_axis", m),
            ("guards_per_object", m * m * m),
            ("guarded_pairs", self.pairs.len() as f64),
            ("unguarded_objects", self.wild_count as f64),
            ("box_events", self.box_events as f64),
        ]
    }

    fn validate(&self, bodies: &Bodies, now: Real) -> Result<(), String> {
        for (axis, l) in self.lists.iter().enumerate() {
            l.validate()
                .map_err(|e| format!("guards list {axis}: {e}"))?;
        }
        for (id, body) in bodies.iter().enumerate() {
            let id = id as u32;
            match body {
                Some(_) if self.present(id) => {
                    for axis_items in self.keys(bodies, id) {
                        for (axis, (item, want)) in axis_items.into_iter().enumerate() {
                            let have = self.lists[axis]
                                .key(item)
                                .ok_or(format!("object {id}: item {item} missing"))?;
                            let (x, y) = (have.value_at(now), want.value_at(now));
                            if (x - y).abs() > 1e-9 * (1.0 + x.abs()) {
                                return Err(format!(
                                    "object {id}: item {item} on axis {axis} at {x}, plan says {y}"
                                ));
                            }
                        }
                    }
                }
                Some(_) => return Err(format!("object {id} is live but not in the guards")),
                None if self.present(id) => {
                    return Err(format!("object {id} is gone but still in the guards"));
                }
                None => {}
            }
        }
        let want: FxHashSet<(u32, u32)> = self.guarded_pairs().into_iter().collect();
        if want != self.pairs {
            let missing = want.difference(&self.pairs).next();
            let extra = self.pairs.difference(&want).next();
            return Err(format!(
                "guarded pairs: {} kept, {} hold a guard (missing {missing:?}, extra {extra:?})",
                self.pairs.len(),
                want.len()
            ));
        }
        let links: usize = self.links.iter().map(Vec::len).sum();
        let live = (0..self.half.len() as u32)
            .filter(|&i| self.present(i))
            .count();
        let wild_links: usize = (0..self.half.len() as u32)
            .filter(|&i| self.present(i) && self.wild[i as usize])
            .map(|_| live - 1)
            .sum::<usize>()
            * 2
            - self.wild_count * self.wild_count.saturating_sub(1);
        if links != 2 * self.pairs.len() + wild_links {
            return Err(format!(
                "guards: {links} link ends for {} guarded pairs and {} unguarded objects",
                self.pairs.len(),
                self.wild_count
            ));
        }
        Ok(())
    }
}
