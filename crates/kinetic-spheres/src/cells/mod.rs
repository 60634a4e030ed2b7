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

mod build;
mod event;
mod grid;
mod predict;
mod query;
mod validate;

use crate::bulk::Sums;
use kinetic_core::FlightPlan;
use kinetic_core::elastic::Motion;
use kinetic_core::elastic::WallHit;
use kinetic_core::elastic::ZenoGuard;
use kinetic_core::kds::EventQueue;
use kinetic_core::{ContactEvent, Stats, Walls};
use kinetic_core::{Real, Vec3};
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
/// # use kinetic_core::{FlightPlan, Vec3, Walls};
/// # use kinetic_spheres::ElasticCells;
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
    /// What the bulk figures sum since they were last started.
    sums: Sums,
    /// Twice the kinetic energy, `sum m v^2` (constant: collisions are elastic).
    two_kinetic: Real,
    zeno: ZenoGuard,
    /// A buffer for neighbour lists.
    neighbour_buffer: Vec<u32>,
}
