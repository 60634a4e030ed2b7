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

mod dominance;
mod guard_grid;
mod lists;
mod structure;
mod validate;
mod watch;

pub use guard_grid::GuardGrid;

use crate::axes::AxisLists;
use crate::cones::ConeSet;
use crate::shape::fatness;
use kinetic_core::kds::{EventQueue, OrderCertificate};
use kinetic_core::{Real, Shape};
use rustc_hash::{FxHashMap, FxHashSet};

/// Relative inflation of the boxes.
const INFLATE: Real = 1.0 + 1e-9;

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

/// The largest fatness the guard grids are built for: objects fatter than this (or than the
/// fattest object, if less) are paired with every object instead of guarded. A grid for
/// fatness rho has about (sqrt 3 (rho + 1)^2)^3 guards per object, so this caps the grid at
/// 44 planes per axis.
pub const RHO_MAX: Real = 4.0;

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

    /// The fatness to build the guard grids for, for objects `shapes`: the fattest object's,
    /// at most [`RHO_MAX`] (1, a ball's, for none).
    pub fn fatness_for<'a>(shapes: impl IntoIterator<Item = &'a Shape>) -> Real {
        shapes
            .into_iter()
            .map(fatness)
            .filter(|&f| f <= RHO_MAX)
            .fold(1.0, Real::max)
    }

    /// The guard grid.
    pub fn grid(&self) -> GuardGrid {
        self.grid
    }

    /// Number of watches (boxes overlapping a smaller object's guard cube).
    pub fn watches(&self) -> usize {
        self.watch_index.len()
    }
}
