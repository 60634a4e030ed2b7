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

mod build;
mod cells;
mod event;
mod fast;
mod levels;
mod pairs;
mod structure;
mod tracks;
mod update;
mod validate;
mod visitors;

use kinetic_core::kds::{EventQueue, ScalarKey};
use kinetic_core::{Real, Vec3};
use rustc_hash::FxHashMap;
use std::collections::BTreeSet;
use visitors::Cell;

/// Hysteresis of a release (a footprint shrinking, two boxes parting), relative to the cell
/// or the smaller box.
const HYSTERESIS: Real = 1e-6;
/// The same, relative to the coordinates: several float spacings, so that a release is never
/// undone by rounding at large coordinates.
const HYSTERESIS_ABS: Real = 1e-12;

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
    /// Whether it is an own track, with certificates of its own (1), or derived (0).
    fn own(&self) -> usize {
        usize::from(self.shift.is_none())
    }

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
    pairs: visitors::Ids,
    /// A fast object's region (it then has no tracks and is in no cell): the box its box
    /// sweeps over the least flight, widened by [`FAST_MARGIN`] of its width.
    region: Option<(Vec3, Vec3)>,
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
    /// Scratch lists of cells (an event's, a re-plan's old and new).
    keys: Vec<CellKey>,
    old_keys: Vec<CellKey>,
    /// The least flight: 0 for none (no object is ever fast).
    least_flight: Real,
    /// The fast objects.
    fast: Vec<u32>,
    /// Per level, bounds of the cells its owners have entered (they only grow): a fast
    /// object's region looks for owners within them only.
    owned: Vec<(i32, [[i64; 2]; 3])>,
    fast_anchors: u64,
    /// The members' own tracks (those that are not derived), kept as tracks come and go:
    /// the statistics count the certificates after every event.
    own_tracks: usize,
}

impl Grid {
    /// The finest cells and the ratio between levels the grid takes for objects of outer
    /// radii `radii` (the smallest box width, and the power of two that spreads the middle
    /// 98% of the widths over a few levels); `None` without a positive finite radius.
    pub fn levels_for(radii: impl IntoIterator<Item = Real>) -> Option<(Real, Real)> {
        crate::cell_math::levels_for(radii.into_iter().map(|r| 2.0 * r))
    }

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
}
