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
//!   than one in 8, are big (cells sized by a lone first speck), the cells are sized afresh;
//!   again only once twice as many are big as right after, so that sizes spread too wide
//!   for any cell cost a few refiles, not one per anchor.
//! - Horizon ([`LooseGrid::with_horizon`]): a region covers at most this much time of flight,
//!   so a body drifting slowly holds a region close to its box.
//! - Least flight ([`LooseGrid::with_least_flight`]): a region covers at least this much time
//!   of flight, so a body that crosses its own width many times in that time (a shot fired
//!   at 1e8 units per second) holds one long region per that time instead of one per two
//!   widths: its re-anchors are bounded by the time it flies, not by how far it goes. A
//!   region more than 8 cells long is big and sits in the big list.
//!
//! - Staggered start ([`LooseGrid::staggered`]): objects filed together get regions as if
//!   anchored at times spread over their last flight, so that their re-anchors do not come
//!   in one wave a flight after the build.
//!
//! The candidates are a superset of the sweep's (boxes inside overlapping regions), so a
//! caller that needs exact contacts certifies them itself. It suits bodies whose plans keep
//! failing (a settling pile) and crowds that fall together, where a structure of exact box
//! pairs pays for every box event and re-plan with certificates of all its neighbours.

mod anchor;
mod cells;
mod region;
mod structure;
mod validate;

use kinetic_core::kds::EventQueue;
use kinetic_core::{Real, Vec3};
use rustc_hash::FxHashMap;

/// A region stretches over the travel of this many box widths by default...
pub const TRAVEL: Real = 2.0;
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
    /// Whether objects filed together get staggered regions ([`LooseGrid::staggered`]).
    staggered: bool,
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
    /// The cells are sized afresh only once more regions than this are big: twice as many
    /// as right after the last time (the median may not move, and sizes spread wide keep
    /// many regions big whatever the cells; a refile at every anchor would cost n^2).
    refile_above: usize,
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
            staggered: false,
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
            refile_above: MANY_BIG,
            scratch: Vec::new(),
        }
    }

    /// The same loose grid whose regions are wider than the swept box by `margin` box widths
    /// on every side (at least 1e-6): fewer, tighter candidates and more re-anchors of
    /// jittering objects.
    pub fn with_margin(mut self, margin: Real) -> LooseGrid {
        self.margin = margin.max(1e-6);
        self
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

    /// The same loose grid whose objects, when filed together (a build), get regions as if
    /// anchored at times spread over the last flight, rather than all from now: their
    /// re-anchors then come at the rate they keep over a long run from the start, instead
    /// of none for a flight and then all at once. A run timed on its first stretch (a
    /// structure tried mid-run against another) then measures its lasting pace.
    pub fn staggered(mut self) -> LooseGrid {
        self.staggered = true;
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
}
