//! `cells`: elastic balls inside walls (the hard-sphere systems of event-driven molecular
//! dynamics) on a hierarchical grid of cells, with one scheduled event per ball.
//!
//! The certificates are those of the world: a disjointness certificate per pair of nearby
//! balls (the same gap polynomials and root walks, so the event log is the world's, bit for
//! bit), a wall certificate per ball, and the cell certificates that say which pairs are
//! nearby. What differs is how they are kept: instead of one queue entry per pair, each ball
//! has one queue entry, its earliest event, and remembers its two earliest pair events, as
//! DynamO keeps a few events per particle. A ball whose plan changes re-predicts its pairs
//! and offers each new failure time to the partner, which keeps it if it is among its two
//! earliest; an entry whose partner changed plan since is stale. A stale first event that
//! comes due gives way to the second; past the second, the ball re-predicts. A stale entry is
//! never later than its ball's true next event, so no event is missed. Most pairs are decided
//! in closed form (apart and parting, clearly missing, a clear first contact) with the walk's
//! own coefficients and root formula, so the results are the walk's bit for bit.
//!
//! - Levels: distinct diameters are grouped by factors of two; level `L` has cells at least
//!   as wide as its largest diameter, and each ball's centre has a home cell at its level.
//!   Two balls of one level that touch have home cells that are neighbours (27 cells).
//! - A ball also holds a block at each finer level: the cells within its radius plus that
//!   level's largest radius of its centre. A finer ball that touches it has its home cell in
//!   the block, so a ball's pairs are: the home members of its 27 neighbour cells, the
//!   coarser balls whose blocks hold its home cell, and the home members of its blocks.
//! - Cell certificates: a centre leaving its home cell, an end of a block crossing a grid
//!   line. Cells and blocks are widened by `1e-9` of their size, so rounding at a crossing
//!   cannot put a touching pair outside each other's neighbourhood.
//!
//! Cost per collision: the two balls re-predict their neighbours (about 13 each in a gas at
//! packing 0.26) and at most that many queue updates; memory is a few hundred bytes per
//! ball. It needs walls (a bounded grid) and linear motion; [`ElasticCells::supports`] says
//! whether a set of balls fits it, and the world with a candidate structure takes the rest.

use super::pairs::{Due, Walk, ball_gap, canonical_base};
use super::step::{ZenoGuard, elastic_exchange};
use super::walls::{WallHit, bounced, wall_hit};
use super::{ContactEvent, ContactKind, ObjectId, Response, Stats, Walls, WorldError, WorldKind};
use crate::math::{Real, Vec3};
use crate::plan::FlightPlan;
use crate::queue::EventQueue;
use crate::roots::quadratic_roots;
use rustc_hash::FxHashMap;

/// Cells and blocks are this much (relative) wider than they must be.
const WIDEN: Real = 1e-9;
/// Levels group diameters within this factor.
const LEVEL_FACTOR: Real = 2.0;
/// The most cells (over all levels) per ball, and at least this many in all, for which the
/// grid is worth it.
const CELLS_PER_BALL: usize = 64;
const CELLS_MIN: usize = 1 << 20;
/// The most block cells per ball, on average, for which the grid is worth it.
const BLOCK_CELLS_PER_BALL: Real = 64.0;
/// No ball in a list.
const NIL: u32 = u32::MAX;
/// Queue tie-breaks: cell events first, then pairs by `(a, b)`, then walls by ball.
const TIE_WALL: u64 = 1 << 63;

/// What a ball's scheduled event is.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Event {
    /// Nothing scheduled.
    Idle,
    /// The ball's pair events from here on are unknown: predict them again.
    Recheck,
    /// A pair certificate of the ball and `other` fails (a collision, or a graze), made while
    /// `other` had plan number `counter`.
    Pair {
        other: u32,
        counter: u32,
        graze: bool,
    },
    /// The ball reaches a wall.
    Wall(WallHit),
    /// The centre leaves its home cell along `axis`, upwards or downwards.
    Home { axis: u8, up: bool },
    /// An end (`hi` or lower) of the block at finer level `level` crosses a grid line.
    Block {
        level: u8,
        axis: u8,
        hi: bool,
        up: bool,
    },
}

/// A ball's next event: its time, its queue tie-break and what it is.
#[derive(Clone, Copy, Debug)]
struct Next {
    time: Real,
    tie: u64,
    event: Event,
}

impl Next {
    const IDLE: Next = Next {
        time: Real::INFINITY,
        tie: u64::MAX,
        event: Event::Idle,
    };

    #[inline]
    fn before(&self, other: &Next) -> bool {
        (self.time, self.tie) < (other.time, other.tie)
    }
}

/// The low 21 bits of `x`, spread to every third bit (one axis of a Z-curve key).
fn spread_bits(x: u64) -> u64 {
    let mut x = x & 0x1f_ffff;
    x = (x | x << 32) & 0x1f_0000_0000_ffff;
    x = (x | x << 16) & 0x1f_0000_ff00_00ff;
    x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
    x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
    x = (x | x << 2) & 0x1249_2492_4924_9249;
    x
}

/// Keeps the two earliest of `top` and `event` in `top`, in order (an event already first is
/// not taken again).
#[inline]
fn keep_earliest(top: &mut [Next; 2], event: Next) {
    if event.before(&top[0]) {
        top[1] = top[0];
        top[0] = event;
    } else if event.before(&top[1]) && (event.time, event.tie) != (top[0].time, top[0].tie) {
        top[1] = event;
    }
}

#[inline]
fn pair_tie(a: u32, b: u32) -> u64 {
    (u64::from(a.min(b)) << 32) | u64::from(a.max(b))
}

/// A ball's linear motion and radius in one cache line, read for every pair the grid offers.
#[derive(Clone, Copy, Debug)]
#[repr(align(64))]
struct Motion {
    t0: Real,
    position: Vec3,
    velocity: Vec3,
    radius: Real,
}

impl Motion {
    fn of(plan: &FlightPlan, radius: Real) -> Motion {
        Motion {
            t0: plan.t0,
            position: plan.position,
            velocity: plan.velocity,
            radius,
        }
    }

    #[inline]
    fn at(&self, t: Real) -> Vec3 {
        self.position + self.velocity * (t - self.t0)
    }
}

/// The levels' largest radii and cell counts, and each ball's level.
type Layout = (Vec<(Real, [u32; 3])>, Vec<u8>);

/// One level of the grid.
#[derive(Debug)]
struct Level {
    /// Cells per axis.
    n: [u32; 3],
    /// Cell size per axis.
    cell: Vec3,
    /// The largest radius of the level's balls.
    r_max: Real,
    /// The first home member of each cell (`NIL` for none).
    head: Vec<u32>,
    /// Coarser balls whose blocks hold the cell, by cell.
    visitors: FxHashMap<u32, Vec<u32>>,
}

impl Level {
    #[inline]
    fn index(&self, c: [u32; 3]) -> u32 {
        (c[2] * self.n[1] + c[1]) * self.n[0] + c[0]
    }
}

/// A ball's block at a finer level: the cell range per axis, both ends included.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Block {
    level: u8,
    lo: [u32; 3],
    hi: [u32; 3],
}

/// Elastic balls inside walls, on a hierarchical grid of cells: the whole simulation of a
/// hard-sphere system, with the world's events and statistics.
///
/// ```
/// # use kinetic_core::{ElasticCells, FlightPlan, Vec3, Walls, ContactKind};
/// let walls = Walls { min: Vec3::ZERO, max: Vec3::splat(10.0) };
/// let balls = [
///     (0.5, FlightPlan::linear(Vec3::new(2.0, 5.0, 5.0), Vec3::new(1.0, 0.0, 0.0))),
///     (0.5, FlightPlan::at_rest(Vec3::new(6.0, 5.0, 5.0))),
/// ];
/// let mut gas = ElasticCells::new(walls, &balls).unwrap();
/// gas.advance_to(10.0).unwrap();
/// let events = gas.drain_events();
/// assert_eq!(events[0].time, 3.0); // then the second ball moves on at speed 1
/// ```
#[derive(Debug)]
pub struct ElasticCells {
    now: Real,
    walls: Walls,
    /// Balls are numbered internally in memory order: `ext` gives each one's own id, `int`
    /// the internal number of each own id.
    ext: Vec<u32>,
    int: Vec<u32>,
    plans: Vec<FlightPlan>,
    /// The plans' linear motion, with the radii.
    motion: Vec<Motion>,
    radius: Vec<Real>,
    level: Vec<u8>,
    /// Plan numbers: bumped whenever a ball's plan changes.
    counter: Vec<u32>,
    home: Vec<[u32; 3]>,
    /// Home-cell lists: next and previous member.
    link: Vec<[u32; 2]>,
    blocks: Vec<Vec<Block>>,
    /// Each ball's next wall contact, found when its plan began.
    wall: Vec<Option<WallHit>>,
    /// Pair events consumed without a change of plans (grazes): `(other, its counter, time)`.
    skips: Vec<Vec<(u32, u32, Real)>>,
    next: Vec<Next>,
    /// Each ball's two earliest pair events known, in order: the first is its `next` unless
    /// a wall or cell event comes first. The second bounds every other pair event of the
    /// ball: none comes before it. When the first turns out stale, the second takes its
    /// place, and a `Recheck` at the same key bounds the rest. A cell crossing keeps both and
    /// predicts only the pairs of the cells entered.
    pair_next: Vec<[Next; 2]>,
    queue: EventQueue,
    levels: Vec<Level>,
    events: Vec<ContactEvent>,
    stats: Stats,
    zeno: ZenoGuard,
    /// A buffer for neighbour lists.
    neighbour_buffer: Vec<u32>,
}

impl ElasticCells {
    /// Whether balls of these radii (all moving linearly) inside `walls` fit the grid: a
    /// bounded number of cells and of block cells per ball.
    pub fn supports(walls: &Walls, radii: &[Real]) -> bool {
        Self::layout(walls, radii).is_some()
    }

    /// The levels' largest radii and cell counts, and each ball's level, or `None` when the
    /// grid would be too large.
    fn layout(walls: &Walls, radii: &[Real]) -> Option<Layout> {
        let mut sorted: Vec<Real> = radii.to_vec();
        if sorted.is_empty() || !sorted.iter().all(|r| r.is_finite() && *r > 0.0) {
            return None;
        }
        sorted.sort_by(Real::total_cmp);
        // Bands of diameters: each starts at its smallest and holds those below twice that.
        let mut bands: Vec<(Real, Real)> = Vec::new();
        for &r in &sorted {
            match bands.last_mut() {
                Some((lo, hi)) if r < *lo * LEVEL_FACTOR => *hi = r,
                _ => bands.push((r, r)),
            }
        }
        if bands.len() > 255 {
            return None;
        }
        let side = walls.max - walls.min;
        let mut levels = Vec::with_capacity(bands.len());
        let mut total: usize = 0;
        for &(_, r_max) in &bands {
            let width = 2.0 * r_max * (1.0 + WIDEN);
            let mut n = [1u32; 3];
            for k in 0..3 {
                let cells = (side[k] / width).floor();
                if !(cells.is_finite()) || cells > 1e6 {
                    return None;
                }
                n[k] = (cells as u32).max(1);
            }
            total = total.saturating_add(n.iter().map(|&c| c as usize).product());
            levels.push((r_max, n));
        }
        if total > CELLS_MIN.max(CELLS_PER_BALL * radii.len()) {
            return None;
        }
        let level: Vec<u8> = radii
            .iter()
            .map(|r| bands.iter().position(|&(_, hi)| *r <= hi).unwrap_or(0) as u8)
            .collect();
        // Block cells: each ball at each finer level.
        let mut block_cells = 0.0;
        for (&r, &l) in radii.iter().zip(&level) {
            for &(r_fine, n) in levels.iter().take(l as usize) {
                let reach = 2.0 * (r + r_fine) * (1.0 + WIDEN);
                block_cells += (0..3)
                    .map(|k| ((reach / (side[k] / n[k] as Real)).ceil() + 1.0).min(n[k] as Real))
                    .product::<Real>();
            }
        }
        if block_cells > BLOCK_CELLS_PER_BALL * radii.len() as Real + 1e6 {
            return None;
        }
        Some((levels, level))
    }

    /// The balls `(radius, plan)` inside `walls`, ids in order, at time 0 (each plan's state
    /// at its `t0` extrapolated). Every ball moves linearly and starts inside the walls.
    pub fn new(walls: Walls, balls: &[(Real, FlightPlan)]) -> Result<ElasticCells, WorldError> {
        if !(0..3).all(|k| walls.min[k].is_finite() && walls.max[k].is_finite())
            || !(0..3).all(|k| walls.min[k] < walls.max[k])
        {
            return Err(WorldError::InvalidWalls);
        }
        for (i, (r, plan)) in balls.iter().enumerate() {
            let object = i as u32;
            if !(r.is_finite() && *r > 0.0) {
                return Err(WorldError::InvalidRadius { object, value: *r });
            }
            if !plan.is_finite() {
                return Err(WorldError::NonFinitePlan { object });
            }
            if plan.acceleration != Vec3::ZERO {
                return Err(WorldError::UnsupportedShape {
                    object,
                    why: "the cell grid holds balls moving linearly (no acceleration)",
                });
            }
            let p = plan.position_at(0.0);
            if !(0..3).all(|k| p[k] - r >= walls.min[k] && p[k] + r <= walls.max[k]) {
                return Err(WorldError::OutsideWalls { object });
            }
        }
        let radii: Vec<Real> = balls.iter().map(|b| b.0).collect();
        let Some((layout, level)) = Self::layout(&walls, &radii) else {
            return Err(WorldError::UnsupportedShape {
                object: 0,
                why: "the cell grid for these sizes and walls would be too large",
            });
        };
        let side = walls.max - walls.min;
        let levels: Vec<Level> = layout
            .iter()
            .map(|&(r_max, n)| Level {
                n,
                cell: Vec3::new(
                    side.x / n[0] as Real,
                    side.y / n[1] as Real,
                    side.z / n[2] as Real,
                ),
                r_max,
                head: vec![NIL; n.iter().map(|&c| c as usize).product()],
                visitors: FxHashMap::default(),
            })
            .collect();
        let count = balls.len();
        // Balls are held in the order of their cells along a Z curve at the finest level, so
        // that neighbours sit close in memory; ties and the log use the balls' own ids.
        let finest = &levels[0];
        let z_key = |p: Vec3| -> u64 {
            (0..3).fold(0, |key, k| {
                let c = ((p[k] - walls.min[k]) / finest.cell[k]).floor();
                let c = if c > 0.0 {
                    (c as u64).min(u64::from(finest.n[k] - 1))
                } else {
                    0
                };
                key | spread_bits(c) << k
            })
        };
        let mut ext: Vec<u32> = (0..count as u32).collect();
        ext.sort_by_cached_key(|&e| (z_key(balls[e as usize].1.position_at(0.0)), e));
        let mut int = vec![0; count];
        for (i, &e) in ext.iter().enumerate() {
            int[e as usize] = i as u32;
        }
        let mut cells = ElasticCells {
            now: 0.0,
            walls,
            plans: ext.iter().map(|&e| balls[e as usize].1).collect(),
            motion: ext
                .iter()
                .map(|&e| Motion::of(&balls[e as usize].1, radii[e as usize]))
                .collect(),
            radius: ext.iter().map(|&e| radii[e as usize]).collect(),
            level: ext.iter().map(|&e| level[e as usize]).collect(),
            ext,
            int,
            counter: vec![0; count],
            home: vec![[0; 3]; count],
            link: vec![[NIL; 2]; count],
            blocks: vec![Vec::new(); count],
            wall: vec![None; count],
            skips: vec![Vec::new(); count],
            next: vec![Next::IDLE; count],
            pair_next: vec![[Next::IDLE; 2]; count],
            queue: EventQueue::with_capacity(count),
            levels,
            events: Vec::new(),
            stats: Stats::default(),
            zeno: ZenoGuard::default(),
            neighbour_buffer: Vec::new(),
        };
        for id in 0..count as u32 {
            let home = cells.home_of(id);
            cells.home[id as usize] = home;
            cells.link_in(id);
            let blocks = (0..cells.level[id as usize])
                .map(|l| cells.block_of(id, l))
                .collect::<Vec<_>>();
            for b in &blocks {
                cells.visit(id, b, true);
            }
            cells.blocks[id as usize] = blocks;
        }
        for id in 0..count as u32 {
            cells.wall[id as usize] = cells.wall_from_plan(id);
            cells.predict(id, false);
        }
        cells.sample();
        Ok(cells)
    }

    /// The current time.
    pub fn now(&self) -> Real {
        self.now
    }

    /// Number of balls.
    pub fn len(&self) -> usize {
        self.plans.len()
    }

    /// Whether there are no balls.
    pub fn is_empty(&self) -> bool {
        self.plans.is_empty()
    }

    /// Ball `id`'s current plan.
    pub fn plan(&self, id: u32) -> &FlightPlan {
        &self.plans[self.int[id as usize] as usize]
    }

    /// Ball `id`'s radius.
    pub fn radius(&self, id: u32) -> Real {
        self.radius[self.int[id as usize] as usize]
    }

    /// The statistics so far (collisions, bounces, cell events and stale entries re-checked;
    /// certificates are the balls' scheduled events).
    pub fn stats(&self) -> &Stats {
        &self.stats
    }

    /// The grid's own figures: levels, cells, block cells held, and pairs of nearby balls
    /// now.
    pub fn counters(&self) -> Vec<(&'static str, f64)> {
        let cells: usize = self.levels.iter().map(|l| l.head.len()).sum();
        let block_cells: usize = self
            .levels
            .iter()
            .map(|l| l.visitors.values().map(Vec::len).sum::<usize>())
            .sum();
        vec![
            ("levels", self.levels.len() as f64),
            ("cells", cells as f64),
            ("block_cells", block_cells as f64),
            ("nearby_pairs", self.nearby_pairs() as f64),
        ]
    }

    /// Takes the contact events so far, in time order, ties by `(a, b)`.
    pub fn drain_events(&mut self) -> Vec<ContactEvent> {
        let mut events = std::mem::take(&mut self.events);
        events.sort_by(|x, y| x.time.total_cmp(&y.time).then((x.a, x.b).cmp(&(y.a, y.b))));
        events
    }

    /// The time of the next event (+infinity for none).
    pub fn next_event_time(&self) -> Real {
        self.queue.next_time()
    }

    /// Processes every event up to time `t` in time order, then moves the clock to `t`.
    pub fn advance_to(&mut self, t: Real) -> Result<(), WorldError> {
        if t.is_nan() || t < self.now {
            return Err(WorldError::Backwards {
                now: self.now,
                to: t,
            });
        }
        while self.step(t)? {}
        self.now = t;
        Ok(())
    }

    /// Processes the next event if it happens at or before `until`; returns whether there
    /// was one. Tests call [`ElasticCells::validate`] between steps.
    pub fn step(&mut self, until: Real) -> Result<bool, WorldError> {
        let Some((id, time)) = self.queue.peek() else {
            return Ok(false);
        };
        if time > until || time.is_nan() {
            return Ok(false);
        }
        // The ball stays at the head of the queue while its event is processed: every branch
        // below schedules its next event, which moves it down once.
        if time > self.now {
            self.now = time;
        }
        let next = self.next[id as usize];
        self.next[id as usize] = Next::IDLE;
        let (kind, pair) = match next.event {
            Event::Idle => {
                self.queue.remove(id);
                ("recheck", (id, id))
            }
            Event::Recheck => {
                self.predict(id, false);
                ("recheck", (id, id))
            }
            Event::Pair {
                other,
                counter,
                graze,
            } => {
                if self.counter[other as usize] != counter {
                    let second = self.pair_next[id as usize][1];
                    if matches!(second.event, Event::Pair { .. }) {
                        let rest = Next {
                            event: Event::Recheck,
                            ..second
                        };
                        self.pair_next[id as usize] = [second, rest];
                        self.settle(id);
                        ("stale", (id, other))
                    } else {
                        self.predict(id, false);
                        ("recheck", (id, other))
                    }
                } else {
                    self.fire_pair(id, other, graze);
                    ("collision", (id, other))
                }
            }
            Event::Wall(hit) => {
                let plan = bounced(&self.plans[id as usize], hit, self.now);
                self.stats.bounces += 1;
                self.replan(id, plan);
                self.predict(id, true);
                ("bounce", (id, id))
            }
            Event::Home { axis, up } => {
                self.link_out(id);
                let c = &mut self.home[id as usize][axis as usize];
                *c = if up { *c + 1 } else { *c - 1 };
                self.link_in(id);
                self.predict_entered(id, None, axis as usize, up);
                ("crossing", (id, id))
            }
            Event::Block {
                level,
                axis,
                hi,
                up,
            } => {
                self.move_block(id, level, axis as usize, hi, up);
                if hi == up {
                    self.predict_entered(id, Some(level), axis as usize, up);
                } else {
                    // The block only left cells: the remembered pair events still stand.
                    self.settle(id);
                }
                ("crossing", (id, id))
            }
        };
        *self.stats.events_by_kind.entry(kind).or_insert(0) += 1;
        self.sample();
        let (a, b) = (self.ext[pair.0 as usize], self.ext[pair.1 as usize]);
        self.zeno.count(self.now, self.len(), a, b)?;
        Ok(true)
    }

    fn sample(&mut self) {
        let c = self.queue.len();
        let s = &mut self.stats;
        s.certificates_max = s.certificates_max.max(c);
        s.certificates_sum += c as f64;
        s.samples += 1;
    }

    /// A pair certificate fails: report the contact and respond. Balls whose plans do not
    /// change (a graze, or balls that are not approaching) skip that event of the pair.
    fn fire_pair(&mut self, a: u32, b: u32, graze: bool) {
        self.log(a, b);
        if !graze {
            let (ra, rb) = (self.radius[a as usize], self.radius[b as usize]);
            let (pa, pb) = (self.plans[a as usize], self.plans[b as usize]);
            if let Some((na, nb)) = elastic_exchange(&pa, ra, &pb, rb, self.now) {
                self.replan(a, na);
                self.replan(b, nb);
                self.predict(a, true);
                self.predict(b, true);
                return;
            }
        }
        let (ca, cb) = (self.counter[a as usize], self.counter[b as usize]);
        self.skips[a as usize].push((b, cb, self.now));
        self.skips[b as usize].push((a, ca, self.now));
        self.predict(a, false);
        self.predict(b, false);
    }

    fn log(&mut self, a: u32, b: u32) {
        let (a, b) = (self.ext[a as usize], self.ext[b as usize]);
        self.stats.begins += 1;
        self.events.push(ContactEvent {
            time: self.now,
            a: ObjectId(a.min(b)),
            b: ObjectId(a.max(b)),
            kind: ContactKind::Begin,
        });
    }

    /// Installs a new plan: the ball's old predictions are stale from now on.
    fn replan(&mut self, id: u32, plan: FlightPlan) {
        self.plans[id as usize] = plan;
        self.motion[id as usize] = Motion::of(&plan, self.radius[id as usize]);
        self.counter[id as usize] = self.counter[id as usize].wrapping_add(1);
        self.skips[id as usize].clear();
        self.wall[id as usize] = self.wall_from_plan(id);
    }

    /// The next event of the pair `(a, b)`: its time, and whether it is a graze.
    fn pair_due(&self, a: u32, b: u32) -> Option<(Real, bool)> {
        // Apart now and never approaching (linear motion: the gap grows from its value at
        // the pair's base time), or approaching but clearly missing: no event, as the walk
        // would find. Decided from the compact motions; the gap polynomial is made only for
        // the pairs that need the walk.
        let (ma, mb) = (&self.motion[a as usize], &self.motion[b as usize]);
        let base = ma.t0.max(mb.t0).min(self.now);
        let reach = ma.radius + mb.radius;
        let threshold2 = reach * reach;
        let db = ma.at(base) - mb.at(base);
        let c0 = db.dot(db) - threshold2;
        let v = ma.velocity - mb.velocity;
        let c1 = 2.0 * db.dot(v);
        if c0 <= 0.0 && c1 > 0.0 && base == self.now {
            // In contact now (just met, within rounding) and moving apart: the walk starts
            // inside or at zero, and the gap only grows.
            return None;
        }
        if c0 > 0.0 {
            let gap_now = if base == self.now {
                c0
            } else {
                let d = ma.at(self.now) - mb.at(self.now);
                d.dot(d) - threshold2
            };
            if gap_now > 0.0 {
                if c1 >= 0.0 {
                    return None;
                }
                let c2 = v.dot(v);
                let (p, q) = (4.0 * c2 * c0, c1 * c1);
                if p - q > 1e-6 * (p + q) {
                    return None;
                }
                // A clear first contact: the gap (the same coefficients as the gap polynomial
                // at `base`) has two roots ahead, and the walk would report the first as a
                // begin. It is taken directly, bit for bit the walk's, unless the pair has
                // events consumed (a graze) or the root is not clearly after now.
                let mut roots = [(0.0, false); 4];
                if q - p > 1e-6 * (p + q)
                    && quadratic_roots(c0, c1, c2, &mut roots) == 2
                    && base + roots[0].0 > self.now
                    && !self.skips[a as usize].iter().any(|s| s.0 == b)
                {
                    return Some((base + roots[0].0, false));
                }
            }
        }
        let (pa, pb) = (&self.plans[a as usize], &self.plans[b as usize]);
        let (ra, rb) = (self.radius[a as usize], self.radius[b as usize]);
        debug_assert_eq!(base, canonical_base(pa, pb, self.now));
        let fb = ball_gap(WorldKind::Free, pa, ra, pb, rb, base);
        let f = if base == self.now {
            fb
        } else {
            ball_gap(WorldKind::Free, pa, ra, pb, rb, self.now)
        };
        let mut walk = Walk::elastic(&fb, base, self.now, &f);
        if let Some(&(_, _, until)) = self.skips[a as usize]
            .iter()
            .find(|&&(o, c, _)| o == b && c == self.counter[b as usize])
        {
            while walk.due.is_some_and(|(t, _, _)| t <= until) {
                walk.consume(Response::Elastic);
            }
        }
        walk.due.map(|(t, _, due)| (t, due == Due::Graze))
    }

    /// Ball `id`'s next wall contact, found (as the world finds it) from the state at the
    /// start of its plan, so that it does not depend on when it is asked for.
    fn wall_from_plan(&self, id: u32) -> Option<WallHit> {
        let plan = &self.plans[id as usize];
        let made = plan.t0.min(self.now);
        wall_hit(plan, self.radius[id as usize], &self.walls, 3, made)
    }

    /// Ball `id`'s next wall contact, not before now.
    fn wall_next(&self, id: u32) -> Option<WallHit> {
        let mut hit = self.wall[id as usize]?;
        hit.time = hit.time.max(self.now);
        Some(hit)
    }

    /// Recomputes ball `id`'s next event from all its certificates; with `offer`, each pair's
    /// failure time is offered to the partner too (after a change of plan, or of neighbours).
    fn predict(&mut self, id: u32, offer: bool) {
        let mut others = std::mem::take(&mut self.neighbour_buffer);
        self.neighbours(id, &mut others);
        self.pair_next[id as usize] = [Next::IDLE; 2];
        self.predict_with(id, &others, offer);
        others.clear();
        self.neighbour_buffer = others;
    }

    /// Ball `id` crossed into new cells (its home cell moved along `axis`, or with `block`,
    /// that block's end grew along `axis`): its pairs with the balls of the cells entered
    /// are predicted and offered, and its two earliest pair events known are kept. The balls
    /// it left behind are still reached by those events or by a later full prediction.
    fn predict_entered(&mut self, id: u32, block: Option<u8>, axis: usize, up: bool) {
        let mut others = std::mem::take(&mut self.neighbour_buffer);
        let i = id as usize;
        match block {
            None => {
                let l = &self.levels[self.level[i] as usize];
                let home = self.home[i];
                let (mut lo, mut hi) = Self::around(l, home);
                let far = if up {
                    home[axis] + 1
                } else {
                    home[axis].wrapping_sub(1)
                };
                if far < l.n[axis] {
                    (lo[axis], hi[axis]) = (far, far);
                    self.members(l, lo, hi, id, &mut others);
                }
                if let Some(v) = l.visitors.get(&l.index(home)) {
                    others.extend_from_slice(v);
                }
            }
            Some(level) => {
                if let Some(b) = self.blocks[i].iter().find(|b| b.level == level) {
                    let (mut lo, mut hi) = (b.lo, b.hi);
                    let at = if up { b.hi[axis] } else { b.lo[axis] };
                    (lo[axis], hi[axis]) = (at, at);
                    self.members(&self.levels[level as usize], lo, hi, id, &mut others);
                }
            }
        }
        self.predict_with(id, &others, true);
        others.clear();
        self.neighbour_buffer = others;
    }

    /// Ball `id`'s next event: the earliest of its wall contact, its cell event, its two
    /// earliest pair events known, and its pairs with `others` (offered to them with `offer`).
    fn predict_with(&mut self, id: u32, others: &[u32], offer: bool) {
        let i = id as usize;
        let mut top = self.pair_next[i];
        for &other in others {
            let Some((time, graze)) = self.pair_due(id, other) else {
                continue;
            };
            let tie = pair_tie(self.ext[i], self.ext[other as usize]);
            let mine = Next {
                time,
                tie,
                event: Event::Pair {
                    other,
                    counter: self.counter[other as usize],
                    graze,
                },
            };
            keep_earliest(&mut top, mine);
            if offer {
                let theirs = Next {
                    time,
                    tie,
                    event: Event::Pair {
                        other: id,
                        counter: self.counter[i],
                        graze,
                    },
                };
                let o = other as usize;
                keep_earliest(&mut self.pair_next[o], theirs);
                if theirs.before(&self.next[o]) {
                    self.next[o] = theirs;
                    self.queue.schedule(other, time, tie);
                }
            }
        }
        self.pair_next[i] = top;
        self.settle(id);
    }

    /// Schedules ball `id`'s next event: the earliest of its wall contact, its cell event and
    /// its two earliest pair events known (the first of them on a tie).
    fn settle(&mut self, id: u32) {
        let i = id as usize;
        let mut best = Next::IDLE;
        if let Some(hit) = self.wall_next(id) {
            best = Next {
                time: hit.time,
                tie: TIE_WALL | u64::from(self.ext[id as usize]),
                event: Event::Wall(hit),
            };
        }
        let cell = self.cell_event(id);
        if cell.before(&best) {
            best = cell;
        }
        for pair in self.pair_next[i] {
            if pair.before(&best) {
                best = pair;
            }
        }
        self.next[i] = best;
        if best.time.is_finite() {
            self.queue.schedule(id, best.time, best.tie);
        } else {
            self.queue.remove(id);
        }
    }

    /// The cells of level `l` next to `home` (the 27 about it, clipped to the grid): the
    /// first and last per axis.
    fn around(l: &Level, home: [u32; 3]) -> ([u32; 3], [u32; 3]) {
        let lo = home.map(|c| c.saturating_sub(1));
        let hi = [0, 1, 2].map(|k| (home[k] + 1).min(l.n[k] - 1));
        (lo, hi)
    }

    /// Pushes the home members (other than `skip`) of the cells `lo..=hi` of level `l`.
    fn members(&self, l: &Level, lo: [u32; 3], hi: [u32; 3], skip: u32, out: &mut Vec<u32>) {
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                for x in lo[0]..=hi[0] {
                    let mut o = l.head[l.index([x, y, z]) as usize];
                    while o != NIL {
                        if o != skip {
                            out.push(o);
                        }
                        o = self.link[o as usize][0];
                    }
                }
            }
        }
    }

    /// The cell of coordinate `x` along `axis` at `level`, clamped to the grid.
    #[inline]
    fn cell_along(&self, level: u8, axis: usize, x: Real) -> u32 {
        let l = &self.levels[level as usize];
        let c = ((x - self.walls.min[axis]) / l.cell[axis]).floor();
        if c <= 0.0 {
            0
        } else {
            (c as u32).min(l.n[axis] - 1)
        }
    }

    /// The home cell of ball `id` now, from its position.
    fn home_of(&self, id: u32) -> [u32; 3] {
        let p = self.plans[id as usize].position_at(self.now);
        let l = self.level[id as usize];
        [0, 1, 2].map(|k| self.cell_along(l, k, p[k]))
    }

    /// The block of ball `id` at finer level `level` now, from its position.
    fn block_of(&self, id: u32, level: u8) -> Block {
        let p = self.plans[id as usize].position_at(self.now);
        let h = self.reach(id, level);
        Block {
            level,
            lo: [0, 1, 2].map(|k| self.cell_along(level, k, p[k] - h)),
            hi: [0, 1, 2].map(|k| self.cell_along(level, k, p[k] + h)),
        }
    }

    /// Half the side of ball `id`'s block at finer level `level`.
    #[inline]
    fn reach(&self, id: u32, level: u8) -> Real {
        (self.radius[id as usize] + self.levels[level as usize].r_max) * (1.0 + WIDEN)
    }

    fn link_in(&mut self, id: u32) {
        let l = &mut self.levels[self.level[id as usize] as usize];
        let cell = l.index(self.home[id as usize]) as usize;
        let first = l.head[cell];
        l.head[cell] = id;
        self.link[id as usize] = [first, NIL];
        if first != NIL {
            self.link[first as usize][1] = id;
        }
    }

    fn link_out(&mut self, id: u32) {
        let [next, prev] = self.link[id as usize];
        if prev == NIL {
            let l = &mut self.levels[self.level[id as usize] as usize];
            let cell = l.index(self.home[id as usize]) as usize;
            l.head[cell] = next;
        } else {
            self.link[prev as usize][0] = next;
        }
        if next != NIL {
            self.link[next as usize][1] = prev;
        }
        self.link[id as usize] = [NIL, NIL];
    }

    /// Adds (or removes) ball `id` as a visitor of the cells of `block` whose coordinate
    /// along `axis` is `at` (every cell of the block with `axis` = 3, see [`Self::visit`]).
    fn visit_slab(&mut self, id: u32, block: &Block, axis: usize, at: u32, add: bool) {
        let l = &mut self.levels[block.level as usize];
        let (mut lo, mut hi) = (block.lo, block.hi);
        if axis < 3 {
            (lo[axis], hi[axis]) = (at, at);
        }
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                for x in lo[0]..=hi[0] {
                    let cell = l.index([x, y, z]);
                    if add {
                        l.visitors.entry(cell).or_default().push(id);
                    } else if let Some(list) = l.visitors.get_mut(&cell) {
                        if let Some(i) = list.iter().position(|&v| v == id) {
                            list.swap_remove(i);
                        }
                        if list.is_empty() {
                            l.visitors.remove(&cell);
                        }
                    }
                }
            }
        }
    }

    fn visit(&mut self, id: u32, block: &Block, add: bool) {
        self.visit_slab(id, block, 3, 0, add);
    }

    /// An end of ball `id`'s block at `level` crossed a grid line along `axis`.
    fn move_block(&mut self, id: u32, level: u8, axis: usize, hi: bool, up: bool) {
        let i = id as usize;
        let Some(k) = self.blocks[i].iter().position(|b| b.level == level) else {
            return;
        };
        let mut b = self.blocks[i][k];
        match (hi, up) {
            (true, true) => {
                b.hi[axis] += 1;
                self.visit_slab(id, &b, axis, b.hi[axis], true);
            }
            (true, false) => {
                self.visit_slab(id, &b, axis, b.hi[axis], false);
                b.hi[axis] -= 1;
            }
            (false, true) => {
                self.visit_slab(id, &b, axis, b.lo[axis], false);
                b.lo[axis] += 1;
            }
            (false, false) => {
                b.lo[axis] -= 1;
                self.visit_slab(id, &b, axis, b.lo[axis], true);
            }
        }
        self.blocks[i][k] = b;
    }

    /// The time the coordinate `axis` of ball `id`'s centre, offset by `shift`, reaches the
    /// grid line `line` of `level` (moving up when `up`), not before now.
    #[inline]
    fn line_time(&self, id: u32, axis: usize, shift: Real, level: u8, line: u32) -> Real {
        let plan = &self.plans[id as usize];
        let g = self.walls.min[axis] + line as Real * self.levels[level as usize].cell[axis];
        let t = plan.t0 + (g - (plan.position[axis] + shift)) / plan.velocity[axis];
        t.max(self.now)
    }

    /// Ball `id`'s next cell event: its centre leaving its home cell, or an end of one of
    /// its blocks crossing a grid line.
    fn cell_event(&self, id: u32) -> Next {
        let i = id as usize;
        let v = self.plans[i].velocity;
        let level = self.level[i];
        let n = self.levels[level as usize].n;
        let mut best = Next::IDLE;
        let mut take = |time: Real, event: Event| {
            if time < best.time {
                best = Next {
                    time,
                    tie: 0,
                    event,
                };
            }
        };
        let home = self.home[i];
        for k in 0..3 {
            if v[k] > 0.0 && home[k] + 1 < n[k] {
                let t = self.line_time(id, k, 0.0, level, home[k] + 1);
                take(
                    t,
                    Event::Home {
                        axis: k as u8,
                        up: true,
                    },
                );
            } else if v[k] < 0.0 && home[k] > 0 {
                let t = self.line_time(id, k, 0.0, level, home[k]);
                take(
                    t,
                    Event::Home {
                        axis: k as u8,
                        up: false,
                    },
                );
            }
        }
        for b in &self.blocks[i] {
            let h = self.reach(id, b.level);
            let n = self.levels[b.level as usize].n;
            for k in 0..3 {
                let ax = k as u8;
                let level = b.level;
                if v[k] > 0.0 {
                    if b.lo[k] + 1 < n[k] {
                        let t = self.line_time(id, k, -h, level, b.lo[k] + 1);
                        take(
                            t,
                            Event::Block {
                                level,
                                axis: ax,
                                hi: false,
                                up: true,
                            },
                        );
                    }
                    if b.hi[k] + 1 < n[k] {
                        let t = self.line_time(id, k, h, level, b.hi[k] + 1);
                        take(
                            t,
                            Event::Block {
                                level,
                                axis: ax,
                                hi: true,
                                up: true,
                            },
                        );
                    }
                } else if v[k] < 0.0 {
                    if b.lo[k] > 0 {
                        let t = self.line_time(id, k, -h, level, b.lo[k]);
                        take(
                            t,
                            Event::Block {
                                level,
                                axis: ax,
                                hi: false,
                                up: false,
                            },
                        );
                    }
                    if b.hi[k] > 0 {
                        let t = self.line_time(id, k, h, level, b.hi[k]);
                        take(
                            t,
                            Event::Block {
                                level,
                                axis: ax,
                                hi: true,
                                up: false,
                            },
                        );
                    }
                }
            }
        }
        best
    }

    /// The balls that can touch ball `id` before its next cell event: the home members of
    /// its 27 neighbour cells, the coarser balls visiting its home cell, and the home members
    /// of its blocks' cells.
    fn neighbours(&self, id: u32, out: &mut Vec<u32>) {
        let i = id as usize;
        let l = &self.levels[self.level[i] as usize];
        let home = self.home[i];
        let (lo, hi) = Self::around(l, home);
        self.members(l, lo, hi, id, out);
        if let Some(v) = l.visitors.get(&l.index(home)) {
            out.extend_from_slice(v);
        }
        for b in &self.blocks[i] {
            self.members(&self.levels[b.level as usize], b.lo, b.hi, id, out);
        }
    }

    /// The number of pairs of nearby balls (each counted once).
    pub fn nearby_pairs(&self) -> usize {
        let mut out = Vec::new();
        let mut total = 0;
        for id in 0..self.len() as u32 {
            out.clear();
            self.neighbours(id, &mut out);
            total += out.len();
        }
        total / 2
    }

    /// The kinetic energy now (masses radius cubed, as the response has them).
    pub fn kinetic_energy(&self) -> Real {
        self.plans
            .iter()
            .zip(&self.radius)
            .map(|(p, r)| 0.5 * r * r * r * p.velocity_at(self.now).length_squared())
            .sum()
    }

    /// The deepest overlap of two balls now (`r_a + r_b - |p_a - p_b|`, negative when all
    /// are apart), over the pairs of nearby balls.
    pub fn max_overlap(&self) -> Real {
        let mut out = Vec::new();
        let mut worst = Real::NEG_INFINITY;
        for id in 0..self.len() as u32 {
            out.clear();
            self.neighbours(id, &mut out);
            let p = self.plans[id as usize].position_at(self.now);
            for &o in &out {
                let q = self.plans[o as usize].position_at(self.now);
                let d = self.radius[id as usize] + self.radius[o as usize] - (p - q).length();
                worst = worst.max(d);
            }
        }
        worst
    }

    /// Recomputes the invariants from scratch: home cells and lists, blocks and visitors,
    /// the queue; and, over every pair of balls, that no certificate fails before the
    /// earlier of its two balls' scheduled events (the grid misses no pair). Quadratic in the
    /// number of balls: for tests.
    pub fn validate(&self) -> Result<(), String> {
        self.queue.validate()?;
        let count = self.len();
        let mut listed = 0;
        for (li, l) in self.levels.iter().enumerate() {
            for (cell, &first) in l.head.iter().enumerate() {
                let mut o = first;
                let mut prev = NIL;
                while o != NIL {
                    listed += 1;
                    if self.level[o as usize] as usize != li
                        || l.index(self.home[o as usize]) as usize != cell
                        || self.link[o as usize][1] != prev
                    {
                        return Err(format!("cells: ball {o} listed in the wrong cell {cell}"));
                    }
                    (prev, o) = (o, self.link[o as usize][0]);
                }
            }
        }
        if listed != count {
            return Err(format!("cells: {listed} balls listed, {count} held"));
        }
        for id in 0..count as u32 {
            let i = id as usize;
            let p = self.plans[i].position_at(self.now);
            let l = &self.levels[self.level[i] as usize];
            for k in 0..3 {
                let tol = WIDEN * l.cell[k];
                let lo = self.walls.min[k] + self.home[i][k] as Real * l.cell[k];
                if p[k] < lo - tol && self.home[i][k] > 0
                    || p[k] > lo + l.cell[k] + tol && self.home[i][k] + 1 < l.n[k]
                {
                    return Err(format!(
                        "cells: ball {id} at {p} is outside its home cell {:?}",
                        self.home[i]
                    ));
                }
                let r = self.radius[i];
                if p[k] - r < self.walls.min[k] - tol || p[k] + r > self.walls.max[k] + tol {
                    return Err(format!("cells: ball {id} at {p} is outside the walls"));
                }
            }
            if self.blocks[i].len() != self.level[i] as usize {
                return Err(format!(
                    "cells: ball {id} has {} blocks",
                    self.blocks[i].len()
                ));
            }
            for b in &self.blocks[i] {
                let exact = (self.radius[i] + self.levels[b.level as usize].r_max) * (1.0 - WIDEN);
                for k in 0..3 {
                    let need_lo = self.cell_along(b.level, k, p[k] - exact);
                    let need_hi = self.cell_along(b.level, k, p[k] + exact);
                    if b.lo[k] > need_lo || b.hi[k] < need_hi {
                        return Err(format!(
                            "cells: ball {id}'s block {:?}..{:?} at level {} misses cells \
                             {need_lo}..{need_hi} along axis {k}",
                            b.lo, b.hi, b.level
                        ));
                    }
                }
                let fine = &self.levels[b.level as usize];
                for z in b.lo[2]..=b.hi[2] {
                    for y in b.lo[1]..=b.hi[1] {
                        for x in b.lo[0]..=b.hi[0] {
                            let cell = fine.index([x, y, z]);
                            let n = fine
                                .visitors
                                .get(&cell)
                                .map_or(0, |v| v.iter().filter(|&&o| o == id).count());
                            if n != 1 {
                                return Err(format!(
                                    "cells: ball {id} visits cell {cell} of level {} {n} times",
                                    b.level
                                ));
                            }
                        }
                    }
                }
            }
            let next = self.next[i];
            let queued = self.queue.time_of(id).unwrap_or(Real::INFINITY);
            if queued != next.time {
                return Err(format!(
                    "cells: ball {id} next at {} but queued at {queued}",
                    next.time
                ));
            }
            let [first, second] = self.pair_next[i];
            if first.before(&next) || second.before(&first) {
                return Err(format!(
                    "cells: ball {id}'s pair events at {} and {} are out of order with its \
                     next event at {}",
                    first.time, second.time, next.time
                ));
            }
            if first.time.is_infinite() && matches!(second.event, Event::Pair { .. }) {
                return Err(format!(
                    "cells: ball {id} has a second pair event and no first"
                ));
            }
            if next.time < self.now {
                return Err(format!(
                    "cells: ball {id} was due at {}, now is {}",
                    next.time, self.now
                ));
            }
            if self.wall_from_plan(id) != self.wall[i] {
                return Err(format!("cells: ball {id}'s wall contact is not its plan's"));
            }
            if let Some(hit) = self.wall_next(id)
                && hit.time < next.time
            {
                return Err(format!(
                    "cells: ball {id} reaches a wall at {} unscheduled",
                    hit.time
                ));
            }
            let cell = self.cell_event(id);
            if cell.time < next.time {
                return Err(format!(
                    "cells: ball {id}'s cell event at {} unscheduled",
                    cell.time
                ));
            }
        }
        let visits: usize = self
            .blocks
            .iter()
            .flatten()
            .map(|b| {
                (0..3)
                    .map(|k| (b.hi[k] - b.lo[k] + 1) as usize)
                    .product::<usize>()
            })
            .sum();
        let held: usize = self
            .levels
            .iter()
            .map(|l| l.visitors.values().map(Vec::len).sum::<usize>())
            .sum();
        if visits != held {
            return Err(format!(
                "cells: blocks cover {visits} cells, visitors hold {held}"
            ));
        }
        for a in 0..count as u32 {
            for b in a + 1..count as u32 {
                let Some((t, _)) = self.pair_due(a, b) else {
                    continue;
                };
                let due = self.next[a as usize].time.min(self.next[b as usize].time);
                if t < due {
                    return Err(format!(
                        "cells: pair ({a}, {b}) fails at {t}, but its balls are next due at {due}"
                    ));
                }
            }
        }
        Ok(())
    }
}
