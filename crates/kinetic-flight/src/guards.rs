//! `guards` (Section 3.2): guards around every object, so that two objects that collide have
//! the larger containing a guard of the smaller (Lemma 7), and box events that tell which
//! boxes hold which guards.
//!
//! The guards of an object K with inner radius r are the points of a regular grid in the cube
//! C(K) of side 2 (rho + 1) r about its centre, with cells of side at most
//! 2 r / (sqrt 3 (rho + 1)) ([`GuardGrid`]): `m^3` points on `m` grid planes per axis. The
//! guards are never stored one by one: the guards of K inside a box form a sub-grid, one
//! index range of grid planes per axis.
//!
//! Two levels find the box events (a box starts or stops holding a guard):
//! - Each axis has a kinetic sorted list of the ends of every object's box (of B+, inflated
//!   by a relative 1e-9) and of its guard cube. A *watch* (K, K') exists while the box of a
//!   larger K' overlaps the cube of K on all three axes (kept by the swaps, as in the sweep).
//! - A watch knows, per axis, between which two grid planes of K each end of the box of K'
//!   lies, with one order certificate per neighbouring plane (cached roots, as in the sorted
//!   lists). When an end crosses a plane, the index moves by one: a box event. The box holds
//!   a guard when every axis has a plane strictly between its ends.
//!
//! Putting every grid plane in the global lists instead (m of them per object and axis) makes
//! planes of unrelated objects swap all the time: 6.3 M events against 26 k for the sweep on
//! 150 objects. The watches keep the planes local to the pairs that need them.
//!
//! Candidate pairs: (K, K') while K' is at least as large as K (inner radius), the box of K'
//! holds a guard of K, and no closer object in the same cone rules K' out. By Lemma 7 every
//! colliding pair is one of them.
//!
//! Cones (Lemma 9, [`ConeSet`]): a watch knows the cone, if any, that every guard of K sees
//! the centre of K' in. The cube of guards lies in a cone when its farthest corner from each
//! facet plane does (`n . d >= a |n|_1`), three polynomial certificates; the centre events
//! are their roots. Within one cone of one guarded object, a watch is *dominated* by another
//! whose centre is closer along the representative edge and whose outer ball is apart from
//! its own (two more polynomial certificates): by Lemma 9 a centre in the tetrahedron from a
//! guard to the cone's triangle through K' would lie inside K' had K' held the guard, so K'
//! holds none of K's guards and the pair is dropped. This is the paper's K*(gamma) per cone,
//! taken over all guards of K at once (one cone per watch instead of one per guard and
//! object), so it never stores a guard or a cone one by one; it leaves a pair in when the
//! guard cube straddles cone facets (objects close to K relative to its cube), where the
//! paper's per-guard cones could still drop it.
//!
//! The supporting query (the closest object in a cone that proves another away) is a scan
//! of the watches of the same guarded object in the same cone: O(k) per query for k such
//! watches, against the paper's O(log^6 n) seven-level range and segment trees; k is the
//! number of larger boxes over one guard cube in one cone, a handful in every scene we run.
//! Measured with `perf` on the nest scene at n = 1e4 (see the README), the cone work (placing
//! watches in cones, dominance, their roots) takes 2 to 4 % of the time and the scan itself
//! under 1 %; the swaps of box and cube ends in the sorted lists take most of it.
//!
//! Objects fatter than the grid's rho (or whose centre is outside them) cannot be guarded;
//! they are paired with every other object.

use crate::axes::{AxisItems, AxisLists};
use crate::cones::ConeSet;
use kinetic_core::certificates::{above_just_after, ball_ball_gap};
use kinetic_core::roots::first_sign_change;
use kinetic_core::{
    Bodies, CandidateStructure, EventQueue, OrderCertificate, PairChange, Poly, Real, ScalarKey,
    Vec3,
};
use rustc_hash::{FxHashMap, FxHashSet};

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

/// What an item of a list is: an end of an object's box or of its guard cube.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum End {
    BoxLo,
    BoxHi,
    CubeLo,
    CubeHi,
}

fn item(object: u32, end: End) -> u32 {
    4 * object + end as u32
}

fn decode(item: u32) -> (u32, End) {
    let end = match item % 4 {
        0 => End::BoxLo,
        1 => End::BoxHi,
        2 => End::CubeLo,
        _ => End::CubeHi,
    };
    (item / 4, end)
}

/// Where one end of a box lies among the grid planes of a guarded object on one axis: `j`
/// planes below it, with the certificates that plane `j - 1` stays below and plane `j` above.
#[derive(Clone, Copy, Debug)]
struct EndWatch {
    j: u32,
    lo: Option<OrderCertificate>,
    hi: Option<OrderCertificate>,
}

impl EndWatch {
    fn due(&self) -> Real {
        let t = |c: &Option<OrderCertificate>| c.map_or(Real::INFINITY, |c| c.failure_time());
        t(&self.lo).min(t(&self.hi))
    }
}

/// The box of `boxer` overlapping the guard cube of `guarded`.
#[derive(Clone, Copy, Debug)]
struct Watch {
    guarded: u32,
    boxer: u32,
    /// Per axis, the lower and upper end of the box.
    ends: [[EndWatch; 2]; 3],
    /// The cone (of every guard of `guarded` alike) holding the centre of `boxer`, while the
    /// whole guard cube sees the centre in one cone; until `cone_due`.
    cone: Option<u32>,
    cone_due: Real,
    /// A closer object of the same cone, apart from `boxer`: then `boxer` holds no guard of
    /// `guarded` (Lemma 9), until `dominator_due`.
    dominator: Option<u32>,
    dominator_due: Real,
}

impl Watch {
    fn due(&self) -> Real {
        self.ends
            .iter()
            .flatten()
            .map(EndWatch::due)
            .fold(Real::INFINITY, Real::min)
    }

    /// Its order certificates.
    fn certificates(&self) -> usize {
        self.ends
            .iter()
            .flatten()
            .map(|e| usize::from(e.lo.is_some()) + usize::from(e.hi.is_some()))
            .sum()
    }

    /// Whether the box holds a guard: a grid plane strictly between its ends on every axis.
    fn holds(&self) -> bool {
        self.ends.iter().all(|[lo, hi]| hi.j > lo.j)
    }

    /// Whether the pair is a candidate: the box holds a guard and no closer object in the
    /// same cone proves the guard is not inside `boxer`.
    fn wanted(&self) -> bool {
        self.holds() && self.dominator.is_none()
    }

    fn cone_event_time(&self) -> Real {
        self.cone_due.min(self.dominator_due)
    }
}

/// The first time after `now` at which `p` (in local time) changes sign, never `now` itself.
fn due(p: &Poly, now: Real) -> Real {
    first_sign_change(p).map_or(Real::INFINITY, |tau| {
        let t = now + tau;
        if t > now { t } else { now.next_up() }
    })
}

/// Puts watch `slot` in `queue` at `due`, or out of it when it is never due.
fn reschedule(queue: &mut EventQueue, slot: u32, due: Real) {
    if due.is_finite() {
        queue.schedule(slot, due, u64::from(slot));
    } else {
        queue.remove(slot);
    }
}

/// `n . d(tau) - shift` for a relative centre `d` given as local coefficients.
fn along(n: Vec3, d: &[Vec3; 3], shift: Real) -> Poly {
    Poly::new(&[n.dot(d[0]) - shift, n.dot(d[1]), n.dot(d[2])])
}

/// The guards structure with cones (see the module notes).
#[derive(Debug)]
pub struct Guards {
    grid: GuardGrid,
    lists: AxisLists,
    /// Inner radius per object (0 for ids not in the structure or unguarded).
    inner: Vec<Real>,
    /// Box half side per object (0 for ids not in the structure).
    half: Vec<Real>,
    /// Objects too fat to guard: paired with everyone.
    wild: Vec<bool>,
    wild_count: usize,
    watches: Vec<Option<Watch>>,
    /// Order certificates over all watches.
    watch_certs: usize,
    free: Vec<u32>,
    watch_index: FxHashMap<(u32, u32), u32>,
    watches_of: Vec<Vec<u32>>,
    watch_queue: EventQueue,
    cones: ConeSet,
    /// Per watch slot, the watches it dominates.
    dominatees: Vec<Vec<u32>>,
    /// The watches per (guarded, cone) whose centres the whole guard cube sees in the cone.
    by_cone: FxHashMap<(u32, u32), Vec<u32>>,
    /// Centre events (a centre crossing a facet of a cone) and dominance ends.
    cone_queue: EventQueue,
    centre_events: u64,
    dominance_events: u64,
    /// Directed pairs (guarded, boxer) whose box holds a guard.
    pairs: FxHashSet<(u32, u32)>,
    /// Per object, the objects it is paired with either way (guarded pairs and wild pairs).
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
            watches: Vec::new(),
            watch_certs: 0,
            free: Vec::new(),
            watch_index: FxHashMap::default(),
            watches_of: Vec::new(),
            watch_queue: EventQueue::new(),
            cones: ConeSet::new(rho),
            dominatees: Vec::new(),
            by_cone: FxHashMap::default(),
            cone_queue: EventQueue::new(),
            centre_events: 0,
            dominance_events: 0,
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

    /// Number of watches (boxes overlapping a smaller object's guard cube).
    pub fn watches(&self) -> usize {
        self.watch_index.len()
    }

    fn present(&self, id: u32) -> bool {
        self.half.get(id as usize).is_some_and(|&h| h > 0.0)
    }

    fn plan(bodies: &Bodies, id: u32) -> &kinetic_core::FlightPlan {
        &bodies[id as usize].as_ref().expect("a live object").plan
    }

    /// The list items of object `id` with their keys, per axis.
    fn items(&self, bodies: &Bodies, id: u32) -> AxisItems {
        let plan = Self::plan(bodies, id);
        let (half, r) = (self.half[id as usize], self.inner[id as usize]);
        let key = |axis, off| ScalarKey::from_plan(plan, axis, off);
        let mut out = vec![
            std::array::from_fn(|k| (item(id, End::BoxLo), key(k, -half))),
            std::array::from_fn(|k| (item(id, End::BoxHi), key(k, half))),
        ];
        if !self.wild[id as usize] {
            let (lo, hi) = (self.grid.offset(r, 0), self.grid.offset(r, self.grid.m - 1));
            out.push(std::array::from_fn(|k| (item(id, End::CubeLo), key(k, lo))));
            out.push(std::array::from_fn(|k| (item(id, End::CubeHi), key(k, hi))));
        }
        out
    }

    /// Whether `boxer` guards against `guarded`: both guarded and `boxer` at least as large.
    fn guards_against(&self, guarded: u32, boxer: u32) -> bool {
        guarded != boxer
            && !self.wild[guarded as usize]
            && !self.wild[boxer as usize]
            && self.inner[boxer as usize] >= self.inner[guarded as usize]
    }

    /// Whether the box of `boxer` overlaps the guard cube of `guarded`, from the list orders.
    fn cube_overlap(&self, guarded: u32, boxer: u32) -> bool {
        (0..3).all(|axis| {
            let p = |it| self.lists.position(axis, it);
            p(item(guarded, End::CubeLo)) < p(item(boxer, End::BoxHi))
                && p(item(boxer, End::BoxLo)) < p(item(guarded, End::CubeHi))
        })
    }

    /// Where end `upper` of the box of `boxer` lies among the grid planes of `guarded` on
    /// `axis`, now.
    fn end_watch(
        &self,
        bodies: &Bodies,
        guarded: u32,
        boxer: u32,
        axis: usize,
        upper: bool,
        now: Real,
    ) -> EndWatch {
        let half = self.half[boxer as usize];
        let end = ScalarKey::from_plan(
            Self::plan(bodies, boxer),
            axis,
            if upper { half } else { -half },
        )
        .local(now);
        let plane = |i| self.plane(bodies, guarded, axis, i).local(now);
        let m = self.grid.m;
        let j = (0..m)
            .take_while(|&i| above_just_after(&end, &plane(i)))
            .count() as u32;
        EndWatch {
            j,
            lo: (j > 0).then(|| OrderCertificate::new(&plane(j - 1), &end, now)),
            hi: (j < m).then(|| OrderCertificate::new(&end, &plane(j), now)),
        }
    }

    fn plane(&self, bodies: &Bodies, guarded: u32, axis: usize, i: u32) -> ScalarKey {
        let off = self.grid.offset(self.inner[guarded as usize], i);
        ScalarKey::from_plan(Self::plan(bodies, guarded), axis, off)
    }

    fn make_watch(&self, bodies: &Bodies, guarded: u32, boxer: u32, now: Real) -> Watch {
        Watch {
            guarded,
            boxer,
            ends: std::array::from_fn(|axis| {
                [false, true].map(|upper| self.end_watch(bodies, guarded, boxer, axis, upper, now))
            }),
            cone: None,
            cone_due: Real::INFINITY,
            dominator: None,
            dominator_due: Real::INFINITY,
        }
    }

    /// The centre of `boxer` relative to that of `guarded`, in local time from `now`.
    fn relative(bodies: &Bodies, guarded: u32, boxer: u32, now: Real) -> [Vec3; 3] {
        let (a, b) = (
            Self::plan(bodies, boxer).local_coefficients(now),
            Self::plan(bodies, guarded).local_coefficients(now),
        );
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }

    /// Half the side of the guard cube of `guarded`, a relative 1e-9 wider.
    fn cube_half(&self, guarded: u32) -> Real {
        self.grid
            .offset(self.inner[guarded as usize], self.grid.m - 1)
            * (1.0 + 1e-9)
    }

    /// The cone that every guard of `guarded` sees the centre of `boxer` in, with the time to
    /// look again: when the centre leaves it (a centre event) or, with no such cone, when
    /// the cube might come to lie inside one.
    ///
    /// With hysteresis, so that rounding at a crossing cannot bring the same crossing back
    /// an instant later: the cube enters a cone only with every margin at least `slack` (a
    /// relative 1e-9 of the distance), and leaves it when a margin reaches 0; outside, it
    /// looks again when a margin below `slack` reaches `2 slack`, or when the centre is
    /// `slack` past a facet of its cone.
    fn cone_state(&self, bodies: &Bodies, guarded: u32, boxer: u32) -> (Option<u32>, Real) {
        let now = self.now;
        let d = Self::relative(bodies, guarded, boxer, now);
        let i = self.cones.locate(d[0]);
        let cone = self.cones.cone(i);
        // The cube lies in the cone when its farthest corner from each facet plane does:
        // n . d >= a |n|_1 for the cube's half side a.
        let half = self.cube_half(guarded);
        let slack = 1e-9 * (d[0].length() + half);
        let margins = cone
            .normals
            .map(|n| along(n, &d, half * n.abs().element_sum()));
        let first = |ps: &mut dyn Iterator<Item = Poly>| {
            ps.map(|p| due(&p, now)).fold(Real::INFINITY, Real::min)
        };
        if margins
            .iter()
            .all(|p| p.c[0] >= slack && p.sign_just_after_zero() > 0)
        {
            (Some(i), first(&mut margins.into_iter()))
        } else {
            let rising = margins.into_iter().filter(|p| p.c[0] < slack).map(|p| {
                let mut p = p;
                p.c[0] -= 2.0 * slack;
                p
            });
            let leaving = cone.normals.map(|n| along(n, &d, -slack));
            (None, first(&mut rising.chain(leaving)))
        }
    }

    /// The watch of the same guarded object and cone that proves `slot`'s boxer holds no
    /// guard, with the time the proof lasts: its centre is closer along the representative
    /// edge, and the outer balls are apart (Lemma 9: a centre between a guard and the
    /// triangle of the cone through the other centre lies inside that other object, had it
    /// held the guard). Of several, the one whose proof lasts longest.
    fn find_dominator(&self, bodies: &Bodies, slot: u32) -> (Option<u32>, Real) {
        let w = self.watches[slot as usize].expect("a live watch");
        let Some(cone) = w.cone else {
            return (None, Real::INFINITY);
        };
        let Some(list) = self.by_cone.get(&(w.guarded, cone)) else {
            return (None, Real::INFINITY);
        };
        let now = self.now;
        let edge = self.cones.cone(cone).edge();
        let me = Self::plan(bodies, w.boxer).local_coefficients(now);
        let mut best: (Option<u32>, Real) = (None, Real::NEG_INFINITY);
        for &o in list {
            if o == slot {
                continue;
            }
            let other = self.watches[o as usize].expect("a live watch").boxer;
            let them = Self::plan(bodies, other).local_coefficients(now);
            let farther = Poly::new(&[
                edge.dot(me[0] - them[0]),
                edge.dot(me[1] - them[1]),
                edge.dot(me[2] - them[2]),
            ]);
            // Hysteresis as for the cones: a dominance starts only with a relative 1e-9 to
            // spare, so rounding where one ends cannot restart it an instant later.
            let reach = self.half[w.boxer as usize] + self.half[other as usize];
            let slack = 1e-9 * ((me[0] - them[0]).length() + reach);
            if farther.c[0] < slack || farther.sign_just_after_zero() <= 0 {
                continue;
            }
            let apart = ball_ball_gap(&me, &them, reach * reach);
            if apart.c[0] < slack * reach || apart.sign_just_after_zero() <= 0 {
                continue;
            }
            let until = due(&farther, now).min(due(&apart, now));
            if until > best.1 {
                best = (Some(o), until);
            }
        }
        match best.0 {
            Some(_) => best,
            None => (None, Real::INFINITY),
        }
    }

    fn schedule_cone(&mut self, slot: u32) {
        let w = self.watches[slot as usize].as_ref().expect("a live watch");
        reschedule(&mut self.cone_queue, slot, w.cone_event_time());
    }

    /// Takes `slot` out of its cone's list and drops its dominance links; the watches it
    /// dominated are pushed to `redo`.
    fn detach(&mut self, slot: u32, redo: &mut Vec<u32>) {
        let mut w = self.watches[slot as usize].expect("a live watch");
        if let Some(c) = w.cone.take() {
            let key = (w.guarded, c);
            let list = self.by_cone.get_mut(&key).expect("a listed cone");
            let i = list
                .iter()
                .position(|&s| s == slot)
                .expect("a listed watch");
            list.swap_remove(i);
            if list.is_empty() {
                self.by_cone.remove(&key);
            }
        }
        if let Some(d) = w.dominator.take() {
            let list = &mut self.dominatees[d as usize];
            let i = list.iter().position(|&s| s == slot).expect("a dominatee");
            list.swap_remove(i);
        }
        w.cone_due = Real::INFINITY;
        w.dominator_due = Real::INFINITY;
        self.put_watch(slot, Some(w));
        for d in std::mem::take(&mut self.dominatees[slot as usize]) {
            let mut x = self.watches[d as usize].expect("a live watch");
            x.dominator = None;
            x.dominator_due = Real::INFINITY;
            self.put_watch(d, Some(x));
            redo.push(d);
        }
    }

    /// Looks again for a dominator of `slot` and updates its pair.
    fn redominate(&mut self, bodies: &Bodies, slot: u32, changes: &mut Vec<PairChange>) {
        let Some(mut w) = self.watches[slot as usize] else {
            return;
        };
        if let Some(d) = w.dominator.take() {
            let list = &mut self.dominatees[d as usize];
            let i = list.iter().position(|&s| s == slot).expect("a dominatee");
            list.swap_remove(i);
        }
        // The search reads only the watch's cone and boxer, which stay as stored.
        let (dominator, until) = self.find_dominator(bodies, slot);
        w.dominator = dominator;
        w.dominator_due = until;
        if let Some(d) = dominator {
            self.dominatees[d as usize].push(slot);
        }
        self.put_watch(slot, Some(w));
        self.schedule_cone(slot);
        self.set_pair(w.guarded, w.boxer, w.wanted(), changes);
    }

    /// Places the watches `slots` in their cones afresh (they are new, or their plans
    /// changed, or a centre crossed a facet) and settles every dominance that this touches.
    fn recone(&mut self, bodies: &Bodies, slots: &[u32], changes: &mut Vec<PairChange>) {
        let mut redo = Vec::new();
        for &s in slots {
            self.detach(s, &mut redo);
        }
        for &s in slots {
            let mut w = self.watches[s as usize].expect("a live watch");
            let (cone, until) = self.cone_state(bodies, w.guarded, w.boxer);
            w.cone = cone;
            w.cone_due = until;
            self.put_watch(s, Some(w));
            redo.push(s);
            if let Some(c) = cone {
                let list = self.by_cone.entry((w.guarded, c)).or_default();
                // Undominated watches of this cone may now be dominated by this one.
                redo.extend(
                    list.iter().copied().filter(|&o| {
                        self.watches[o as usize].is_some_and(|x| x.dominator.is_none())
                    }),
                );
                list.push(s);
            }
        }
        redo.sort_unstable();
        redo.dedup();
        for s in redo {
            self.redominate(bodies, s, changes);
        }
    }

    /// A cone event of watch `slot`: its centre crossed a facet ("centre"), or its dominance
    /// ended ("dominance"). Returns the kind.
    fn on_cone(
        &mut self,
        slot: u32,
        bodies: &Bodies,
        changes: &mut Vec<PairChange>,
    ) -> &'static str {
        let w = self.watches[slot as usize].expect("a live watch");
        if w.cone_due <= w.dominator_due {
            self.centre_events += 1;
            self.recone(bodies, &[slot], changes);
            "centre"
        } else {
            self.dominance_events += 1;
            self.redominate(bodies, slot, changes);
            "dominance"
        }
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

    /// Stores a watch (or clears its slot), keeping the count of watch certificates.
    fn put_watch(&mut self, slot: u32, w: Option<Watch>) {
        let certs = |w: &Option<Watch>| w.as_ref().map_or(0, Watch::certificates);
        self.watch_certs -= certs(&self.watches[slot as usize]);
        self.watch_certs += certs(&w);
        self.watches[slot as usize] = w;
    }

    fn schedule(&mut self, slot: u32) {
        let w = self.watches[slot as usize].as_ref().expect("a live watch");
        reschedule(&mut self.watch_queue, slot, w.due());
    }

    /// Starts watching (guarded, boxer) now.
    fn open_watch(
        &mut self,
        bodies: &Bodies,
        guarded: u32,
        boxer: u32,
        changes: &mut Vec<PairChange>,
    ) {
        if self.watch_index.contains_key(&(guarded, boxer)) {
            return;
        }
        let w = self.make_watch(bodies, guarded, boxer, self.now);
        let slot = match self.free.pop() {
            Some(s) => s,
            None => {
                self.watches.push(None);
                (self.watches.len() - 1) as u32
            }
        };
        self.put_watch(slot, Some(w));
        self.watch_index.insert((guarded, boxer), slot);
        self.watches_of[guarded as usize].push(slot);
        self.watches_of[boxer as usize].push(slot);
        if self.dominatees.len() <= slot as usize {
            self.dominatees.resize(slot as usize + 1, Vec::new());
        }
        self.schedule(slot);
        self.recone(bodies, &[slot], changes);
    }

    /// Stops watching (guarded, boxer).
    fn close_watch(
        &mut self,
        bodies: &Bodies,
        guarded: u32,
        boxer: u32,
        changes: &mut Vec<PairChange>,
    ) {
        let Some(slot) = self.watch_index.remove(&(guarded, boxer)) else {
            return;
        };
        let mut redo = Vec::new();
        self.detach(slot, &mut redo);
        self.put_watch(slot, None);
        self.watch_queue.remove(slot);
        self.cone_queue.remove(slot);
        for o in [guarded, boxer] {
            let list = &mut self.watches_of[o as usize];
            let i = list
                .iter()
                .position(|&s| s == slot)
                .expect("a listed watch");
            list.swap_remove(i);
        }
        self.free.push(slot);
        self.set_pair(guarded, boxer, false, changes);
        for d in redo {
            self.redominate(bodies, d, changes);
        }
    }

    fn sync(&mut self, now: Real) {
        self.now = now;
        self.lists.sync(now);
    }

    fn grow(&mut self, id: u32) {
        let need = id as usize + 1;
        if self.half.len() < need {
            self.half.resize(need, 0.0);
            self.inner.resize(need, 0.0);
            self.wild.resize(need, false);
            self.links.resize(need, Vec::new());
            self.watches_of.resize(need, Vec::new());
        }
    }

    /// Registers object `id`'s sizes.
    fn admit(&mut self, bodies: &Bodies, id: u32) {
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
    }

    /// Every (guarded, boxer) whose box overlaps the guard cube, by a sweep along x.
    fn cube_pairs(&self) -> Vec<(u32, u32)> {
        let mut out = Vec::new();
        let (mut boxes, mut cubes): (Vec<u32>, Vec<u32>) = (Vec::new(), Vec::new());
        for &it in self.lists.list(0).order() {
            let (o, end) = decode(it);
            match end {
                End::BoxLo => {
                    for &g in &cubes {
                        if self.guards_against(g, o) && self.cube_overlap(g, o) {
                            out.push((g, o));
                        }
                    }
                    boxes.push(o);
                }
                End::CubeLo => {
                    for &b in &boxes {
                        if self.guards_against(o, b) && self.cube_overlap(o, b) {
                            out.push((o, b));
                        }
                    }
                    cubes.push(o);
                }
                End::BoxHi => boxes.retain(|&b| b != o),
                End::CubeHi => cubes.retain(|&c| c != o),
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }

    /// A watch's certificate failed: an end of the box crossed a grid plane.
    fn on_watch(&mut self, slot: u32, bodies: &Bodies, changes: &mut Vec<PairChange>) {
        let mut w = self.watches[slot as usize].expect("a live watch");
        let due = w.due();
        let now = self.now;
        let (axis, e) = (0..6)
            .map(|k| (k / 2, k % 2))
            .find(|&(a, e)| w.ends[a][e].due() <= due)
            .expect("the due end");
        let ew = &mut w.ends[axis][e];
        let lo_due = ew.lo.map_or(Real::INFINITY, |c| c.failure_time());
        let end = ScalarKey::from_plan(
            Self::plan(bodies, w.boxer),
            axis,
            if e == 1 {
                self.half[w.boxer as usize]
            } else {
                -self.half[w.boxer as usize]
            },
        )
        .local(now);
        let m = self.grid.m;
        if lo_due <= due {
            // The end went below plane j - 1.
            ew.hi = ew.lo.map(|c| c.swapped());
            ew.j -= 1;
            ew.lo = (ew.j > 0).then(|| {
                let p = self.plane(bodies, w.guarded, axis, ew.j - 1).local(now);
                OrderCertificate::new(&p, &end, now)
            });
        } else {
            // The end went above plane j.
            ew.lo = ew.hi.map(|c| c.swapped());
            ew.j += 1;
            ew.hi = (ew.j < m).then(|| {
                let p = self.plane(bodies, w.guarded, axis, ew.j).local(now);
                OrderCertificate::new(&end, &p, now)
            });
        }
        self.put_watch(slot, Some(w));
        self.schedule(slot);
        self.box_events += 1;
        self.set_pair(w.guarded, w.boxer, w.wanted(), changes);
    }

    /// Checks the cone and dominance of watch `slot` against the plans at `now`.
    fn validate_cone(
        &self,
        bodies: &Bodies,
        slot: u32,
        w: &Watch,
        now: Real,
    ) -> Result<(), String> {
        let (g, b) = (w.guarded, w.boxer);
        let due = w.cone_event_time();
        if self.cone_queue.time_of(slot).unwrap_or(Real::INFINITY) != due {
            return Err(format!(
                "watch ({g}, {b}): cone event not scheduled at {due}"
            ));
        }
        let d = Self::plan(bodies, b).position_at(now) - Self::plan(bodies, g).position_at(now);
        let eps = 1e-9 * (1.0 + d.length() + Self::plan(bodies, g).position_at(now).length());
        let soon = now + 1e-9 * now.abs().max(1.0);
        if let Some(c) = w.cone {
            if !self.by_cone.get(&(g, c)).is_some_and(|l| l.contains(&slot)) {
                return Err(format!("watch ({g}, {b}) missing from its cone {c}"));
            }
            if w.cone_due > soon {
                let half = self.cube_half(g);
                for n in self.cones.cone(c).normals {
                    let margin = n.dot(d) - half * n.abs().element_sum();
                    if margin < -eps {
                        return Err(format!(
                            "watch ({g}, {b}): guard cube leaves cone {c} by {margin}"
                        ));
                    }
                }
            }
        }
        if let Some(o) = w.dominator {
            let x = self.watches[o as usize].ok_or("a dead dominator")?;
            if !self.dominatees[o as usize].contains(&slot) {
                return Err(format!("watch ({g}, {b}): not listed by its dominator"));
            }
            if x.guarded != g || x.cone.is_none() || x.cone != w.cone {
                return Err(format!("watch ({g}, {b}): dominator not in the same cone"));
            }
            if w.dominator_due > soon {
                let c = w.cone.expect("a cone");
                let other = Self::plan(bodies, x.boxer).position_at(now);
                let me = Self::plan(bodies, b).position_at(now);
                let closer = self.cones.cone(c).edge().dot(me - other);
                let gap =
                    (me - other).length() - (self.half[b as usize] + self.half[x.boxer as usize]);
                if closer < -eps || gap < -eps {
                    return Err(format!(
                        "watch ({g}, {b}) dominated by {}: closer by {closer}, apart by {gap}",
                        x.boxer
                    ));
                }
            }
        }
        for &d in &self.dominatees[slot as usize] {
            if self.watches[d as usize].and_then(|x| x.dominator) != Some(slot) {
                return Err(format!(
                    "watch ({g}, {b}) lists a dominatee it does not dominate"
                ));
            }
        }
        Ok(())
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
                if self.guards_against(g, b) && self.cube_overlap(g, b) {
                    self.open_watch(bodies, g, b, changes);
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
        self.lists.insert(self.items(bodies, id));
        self.pair_new(id, bodies, changes);
    }

    fn insert_many(
        &mut self,
        ids: &[u32],
        bodies: &Bodies,
        now: Real,
        changes: &mut Vec<PairChange>,
    ) {
        if !self.lists.is_empty() || ids.len() < 2 {
            for &id in ids {
                self.insert(id, bodies, now, changes);
            }
            return;
        }
        self.now = now;
        let mut all = Vec::new();
        for &id in ids {
            self.admit(bodies, id);
            all.extend(self.items(bodies, id));
        }
        self.lists = AxisLists::build(now, all);
        for (g, b) in self.cube_pairs() {
            self.open_watch(bodies, g, b, changes);
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
        for slot in self.watches_of[id as usize].clone() {
            let w = self.watches[slot as usize].expect("a live watch");
            self.close_watch(bodies, w.guarded, w.boxer, changes);
        }
        for o in self.links[id as usize].clone() {
            self.link(id, o, -1, changes);
        }
        self.lists.remove(self.items(bodies, id));
        if self.wild[id as usize] {
            self.wild_count -= 1;
        }
        self.half[id as usize] = 0.0;
        self.inner[id as usize] = 0.0;
        self.wild[id as usize] = false;
    }

    fn replan(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        if !self.present(id) {
            return;
        }
        self.sync(now);
        self.lists.set_keys(self.items(bodies, id));
        // Its watches start afresh from the new plan (a teleport moves the ends at once).
        let slots = self.watches_of[id as usize].clone();
        for &slot in &slots {
            let old = self.watches[slot as usize].expect("a live watch");
            let fresh = self.make_watch(bodies, old.guarded, old.boxer, now);
            let w = Watch {
                ends: fresh.ends,
                ..old
            };
            self.put_watch(slot, Some(w));
            self.schedule(slot);
        }
        self.recone(bodies, &slots, changes);
    }

    fn next_event_time(&self) -> Real {
        self.lists
            .next_event_time()
            .min(self.watch_queue.next_time())
            .min(self.cone_queue.next_time())
    }

    fn process_next_event(
        &mut self,
        bodies: &Bodies,
        changes: &mut Vec<PairChange>,
    ) -> &'static str {
        let cone_time = self.cone_queue.next_time();
        if cone_time < self.lists.next_event_time() && cone_time < self.watch_queue.next_time() {
            let (slot, time) = self.cone_queue.peek().expect("a due cone event");
            self.now = self.now.max(time);
            return self.on_cone(slot, bodies, changes);
        }
        if self.watch_queue.next_time() < self.lists.next_event_time() {
            let (slot, time) = self.watch_queue.peek().expect("a due watch");
            self.now = self.now.max(time);
            self.on_watch(slot, bodies, changes);
            return "box";
        }
        let Some((_, swap)) = self.lists.next_swap() else {
            return "swap";
        };
        self.now = self.now.max(swap.time);
        let (u, v) = (decode(swap.left), decode(swap.right));
        let (guarded, boxer) = match (u.1, v.1) {
            (End::CubeLo | End::CubeHi, End::BoxLo | End::BoxHi) => (u.0, v.0),
            (End::BoxLo | End::BoxHi, End::CubeLo | End::CubeHi) => (v.0, u.0),
            _ => return "swap",
        };
        if self.guards_against(guarded, boxer) {
            if self.cube_overlap(guarded, boxer) {
                self.open_watch(bodies, guarded, boxer, changes);
            } else {
                self.close_watch(bodies, guarded, boxer, changes);
            }
        }
        "swap"
    }

    fn certificates(&self) -> usize {
        self.lists.certificates() + self.watch_certs
    }

    fn boxes(&self, bodies: &Bodies, now: Real) -> Vec<(Vec3, Vec3)> {
        self.half
            .iter()
            .enumerate()
            .filter(|&(_, &h)| h > 0.0)
            .filter_map(|(id, &h)| {
                let c = bodies.get(id)?.as_ref()?.plan.position_at(now);
                Some((c - Vec3::splat(h), c + Vec3::splat(h)))
            })
            .collect()
    }

    fn counters(&self) -> Vec<(&'static str, f64)> {
        let m = f64::from(self.grid.m);
        vec![
            ("grid_planes_per_axis", m),
            ("guards_per_object", m * m * m),
            ("watches", self.watches() as f64),
            ("guarded_pairs", self.pairs.len() as f64),
            ("unguarded_objects", self.wild_count as f64),
            ("box_events", self.box_events as f64),
            ("cones_per_guard", self.cones.len() as f64),
            (
                "coned_watches",
                self.watches
                    .iter()
                    .flatten()
                    .filter(|w| w.cone.is_some())
                    .count() as f64,
            ),
            (
                "dominated_watches",
                self.watches
                    .iter()
                    .flatten()
                    .filter(|w| w.dominator.is_some())
                    .count() as f64,
            ),
            ("centre_events", self.centre_events as f64),
            ("dominance_events", self.dominance_events as f64),
        ]
    }

    fn validate(&self, bodies: &Bodies, now: Real) -> Result<(), String> {
        self.watch_queue.validate()?;
        self.lists.validate(
            "guards",
            bodies,
            now,
            |id| self.present(id),
            |id| self.items(bodies, id),
        )?;
        let certs: usize = self.watches.iter().flatten().map(Watch::certificates).sum();
        if certs != self.watch_certs {
            return Err(format!(
                "watches hold {certs} certificates, counted {}",
                self.watch_certs
            ));
        }
        let want: FxHashSet<(u32, u32)> = self.cube_pairs().into_iter().collect();
        let have: FxHashSet<(u32, u32)> = self.watch_index.keys().copied().collect();
        if want != have {
            return Err(format!(
                "watches: {} kept, {} boxes overlap a guard cube (missing {:?}, extra {:?})",
                have.len(),
                want.len(),
                want.difference(&have).next(),
                have.difference(&want).next()
            ));
        }
        let mut holding = FxHashSet::default();
        for (&(g, b), &slot) in &self.watch_index {
            let w = self.watches[slot as usize].ok_or("a dead watch slot")?;
            let due = w.due();
            if self.watch_queue.time_of(slot).unwrap_or(Real::INFINITY) != due {
                return Err(format!("watch ({g}, {b}) not scheduled at {due}"));
            }
            if w.wanted() {
                holding.insert((g, b));
            }
            self.validate_cone(bodies, slot, &w, now)?;
            if due <= now + 1e-9 * now.abs().max(1.0) {
                // A plane crossing due now (or within rounding of now), not processed yet.
                continue;
            }
            // Each end lies above the planes it is kept above, up to rounding at the moment
            // it crossed one.
            for axis in 0..3 {
                for (e, sign) in [(0, -1.0), (1, 1.0)] {
                    let end =
                        Self::plan(bodies, b).position_at(now)[axis] + sign * self.half[b as usize];
                    let eps = 1e-9 * (1.0 + end.abs());
                    let plane = |i| self.plane(bodies, g, axis, i).value_at(now);
                    let below = |x: Real| (0..self.grid.m).filter(|&i| plane(i) < x).count();
                    let kept = w.ends[axis][e].j as usize;
                    if !(below(end - eps) <= kept && kept <= below(end + eps)) {
                        return Err(format!(
                            "watch ({g}, {b}): axis {axis} end {e} kept above {kept} planes, \
                             is above {}",
                            below(end)
                        ));
                    }
                }
            }
        }
        let coned: usize = self.by_cone.values().map(Vec::len).sum();
        let want_coned = self
            .watches
            .iter()
            .flatten()
            .filter(|w| w.cone.is_some())
            .count();
        if coned != want_coned {
            return Err(format!(
                "cones list {coned} watches, {want_coned} watches are in a cone"
            ));
        }
        if holding != self.pairs {
            return Err(format!(
                "guarded pairs: {} kept, {} watches hold a guard undominated",
                self.pairs.len(),
                holding.len()
            ));
        }
        let links: usize = self.links.iter().map(Vec::len).sum();
        let live = (0..self.half.len() as u32)
            .filter(|&i| self.present(i))
            .count();
        let w = self.wild_count;
        let wild_ends = 2 * w * live.saturating_sub(1) - w * w.saturating_sub(1);
        if links != 2 * self.pairs.len() + wild_ends {
            return Err(format!(
                "guards: {links} link ends for {} guarded pairs and {w} unguarded objects",
                self.pairs.len()
            ));
        }
        Ok(())
    }
}
