//! `listed`: elastic spheres of similar sizes in a periodic box or inside walls, the hard-sphere
//! fluids of event-driven molecular dynamics, with neighbour lists and one scheduled event per
//! sphere.
//!
//! The certificates are the world's: a disjointness certificate per pair of listed spheres
//! (the same gap polynomial and root formula, so a pair whose image does not wrap fails at the
//! world's time, bit for bit), and a shell certificate per sphere that says its list still
//! holds every sphere it could touch.
//!
//! - **Images.** A pair meets through its nearest image now: its gap is that of
//!   `(x_a - x_b) - s L`, with `s` the integers that make the difference smallest. The box
//!   must be at least three list reaches wide, so a sphere meets at most one image of another.
//!   A sphere's plan is the world's; when a collision gives it a new plan whose start lies
//!   outside the box, the start is wrapped into it (a whole number of periods).
//! - **Neighbour lists with a shell.** Each sphere has a list centre (a point within its
//!   shell when the list was made) and lists the spheres whose centres were within
//!   `s (r_a + r_b)` of it, with a shell factor `s` chosen from the packing so that a sphere
//!   lists about 14 others. While each sphere stays within `(s - 1) r` of its centre, an
//!   unlisted pair cannot touch; a sphere that reaches its shell re-centres (a mean free
//!   path ahead along its flight) and lists again from a cell grid of centres. Lists are
//!   symmetric: re-listing one sphere updates its neighbours' lists.
//! - **One event per sphere**, the earliest of its shell crossing and its listed pairs,
//!   predicted against the partners' current plans and tagged with the partner's plan
//!   number. A pair is always covered by the sphere that predicted it last: that sphere's
//!   event is not later than the pair's failure. An event whose partner has changed plan
//!   since is stale and only makes its sphere predict again.
//! - **Lazy positions**: a sphere's state changes only at its own events.
//!
//! - **Walls** (instead of a period): no images; each sphere's own event is the earlier of
//!   its shell crossing and its wall certificate, the world's (the wall contact of its plan,
//!   computed when the plan starts), and a wall contact reverses the velocity across the wall
//!   as the world's bounce does. The grid of list centres does not wrap.
//!
//! Statistics add the collision virial, from which the run's pressure follows in a periodic
//! box, and the impulse on the walls, from which it follows inside walls.

mod build;
mod calendar;
mod event;
mod first_pass;
mod grid;
mod lists;
mod predict;
mod runners;
mod validate;

use crate::bulk::{Bulk, Sums, ball_volume};
use calendar::Calendar;
use kinetic_core::elastic::Motion;
use kinetic_core::elastic::ROUNDING;
use kinetic_core::elastic::WallHit;
use kinetic_core::elastic::ZenoGuard;
use kinetic_core::{ContactEvent, Stats, Walls};
use kinetic_core::{Real, Vec3};
use rustc_hash::FxHashMap;

/// A sphere lists the spheres within a shell factor times the sum of radii: about this many
/// of them. Measured on fluids at packings 0.26 and 0.45, about 14 neighbours are fastest
/// (fewer shell crossings in thin fluids, few enough pairs in dense ones).
const NEIGHBOURS: Real = 14.0;
/// The least and greatest shell factors.
const SHELL: (Real, Real) = (1.3, 2.5);
/// Reaches used to list pairs are this much (relative) wider, and shells this much narrower,
/// than the geometry needs: rounding at a shell crossing cannot hide a pair.
const SLACK: Real = 1e-9;
/// No sphere.
const NIL: u32 = u32::MAX;
/// The tie-break of shell crossings: after every pair event at the same time.
const TIE_SHELL: u64 = u64::MAX;
/// The tie-break of wall contacts: after every pair event at the same time, before a shell
/// crossing.
const TIE_WALL: u64 = u64::MAX - 1;

/// An axis-aligned periodic box: space repeats with period `max - min` along each axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeriodicBox {
    /// The lower corner.
    pub min: Vec3,
    /// The upper corner.
    pub max: Vec3,
}

/// What a sphere's scheduled event is.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
enum Kind {
    /// Nothing scheduled.
    #[default]
    Idle,
    /// A pair certificate fails: a collision, or a graze.
    Pair,
    /// The sphere reaches its shell.
    Shell,
    /// The sphere reaches a wall.
    Wall,
}

/// A sphere's next event: time, queue tie-break, and for a pair the partner and the
/// partner's plan number when it was predicted.
#[derive(Clone, Copy, Debug)]
struct Next {
    time: Real,
    tie: u64,
    other: u32,
    counter: u32,
    kind: Kind,
    graze: bool,
}

/// What the queue carries with a sphere's event besides its time and tie-break: the kind,
/// and for a pair the partner and the partner's plan number when it was predicted.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Scheduled {
    kind: Kind,
    graze: bool,
    other: u32,
    counter: u32,
}

impl Next {
    /// What the queue carries of it.
    fn scheduled(&self) -> Scheduled {
        Scheduled {
            kind: self.kind,
            graze: self.graze,
            other: self.other,
            counter: self.counter,
        }
    }

    const IDLE: Next = Next {
        time: Real::INFINITY,
        tie: u64::MAX,
        other: NIL,
        counter: 0,
        kind: Kind::Idle,
        graze: false,
    };
}

/// Where a sphere's list was made, and how far from there the sphere may go before its list
/// must be made again: one half cache line, read at every prediction.
#[derive(Clone, Copy, Debug)]
#[repr(align(32))]
struct ListCentre {
    at: Vec3,
    shell: Real,
}

/// The box's period along each axis.
#[derive(Clone, Copy, Debug)]
struct Period {
    min: Vec3,
    side: Vec3,
    inv_side: Vec3,
    half_side: Vec3,
}

impl Period {
    /// The period of `cell`.
    fn of(cell: &PeriodicBox) -> Period {
        let side = cell.max - cell.min;
        Period {
            min: cell.min,
            side,
            inv_side: Vec3::ONE / side,
            half_side: side * 0.5,
        }
    }

    /// No period (inside walls from `min` to `max`): every difference is its own nearest
    /// image, and no point lies outside.
    fn none(min: Vec3, max: Vec3) -> Period {
        Period {
            min,
            side: max - min,
            inv_side: Vec3::ZERO,
            half_side: Vec3::INFINITY,
        }
    }

    /// The image shift `s L` that makes the difference `d` smallest.
    #[inline]
    fn nearest(&self, d: Vec3) -> Vec3 {
        round(d * self.inv_side) * self.side
    }

    /// The difference `d` of two centres taken to the nearest image, and the shift taken off
    /// it (zero unless `d` is beyond half the box on some axis: listed pairs are within a
    /// third of the box of their nearest image).
    #[inline]
    fn apart(&self, d: Vec3) -> (Vec3, Vec3) {
        if d.abs().cmplt(self.half_side).all() {
            (d, Vec3::ZERO)
        } else {
            let shift = self.nearest(d);
            (d - shift, shift)
        }
    }

    /// The whole periods by which `p` lies outside the box (zero inside).
    #[inline]
    fn outside(&self, p: Vec3) -> Vec3 {
        let x = (p - self.min) * self.inv_side;
        if x.cmpge(Vec3::ZERO).all() && x.cmplt(Vec3::ONE).all() {
            Vec3::ZERO // inside: floor would give zeros, without its library call
        } else {
            x.floor() * self.side
        }
    }
}

/// Rounds each coordinate to the nearest integer (ties to even) for magnitudes below 2^51,
/// without a library call.
#[inline]
fn round(v: Vec3) -> Vec3 {
    (v + ROUNDING) - ROUNDING
}

/// Elastic spheres of similar sizes in a periodic box ([`ListedSpheres::periodic`]) or inside
/// walls ([`ListedSpheres::in_walls`]): the whole simulation of a hard-sphere fluid, with the
/// world's events and statistics.
///
/// ```
/// # use kinetic_core::{FlightPlan, Vec3};
/// # use kinetic_spheres::{PeriodicBox, ListedSpheres};
/// let cell = PeriodicBox { min: Vec3::ZERO, max: Vec3::splat(10.0) };
/// let spheres = [
///     (0.5, FlightPlan::linear(Vec3::new(1.0, 5.0, 5.0), Vec3::new(-1.0, 0.0, 0.0))),
///     (0.5, FlightPlan::at_rest(Vec3::new(8.0, 5.0, 5.0))),
/// ];
/// let mut gas = ListedSpheres::periodic(cell, &spheres).unwrap();
/// gas.advance_to(5.0).unwrap();
/// let events = gas.drain_events();
/// // The first sphere leaves through x = 0 and meets the second's image at t = 2.
/// assert_eq!(events[0].time, 2.0);
/// ```
#[derive(Clone, Debug)]
pub struct ListedSpheres {
    now: Real,
    period: Period,
    /// The walls, inside walls (no period then).
    walls: Option<Walls>,
    /// Each sphere's wall certificate: its plan's first wall contact (inside walls).
    wall: Vec<Option<WallHit>>,
    /// Spheres are numbered internally in memory order (cell by cell): `ext` gives each
    /// one's own id.
    ext: Vec<u32>,
    motion: Vec<Motion>,
    /// Plan numbers: bumped whenever a sphere's plan changes.
    counter: Vec<u32>,
    /// List centres, with the sphere's distance from it at which the list must be remade.
    centre: Vec<ListCentre>,
    lists: lists::Lists,
    grid: grid::CentreGrid,
    /// Each sphere's next event.
    queue: Calendar<Scheduled>,
    /// What each sphere's last prediction found after its next event.
    spares: Vec<runners::SavedRunners>,
    /// Pair events consumed without a change of plans (grazes): `(other, its counter, time)`.
    skips: FxHashMap<u32, Vec<(u32, u32, Real)>>,
    events: Vec<ContactEvent>,
    stats: Stats,
    /// What the bulk figures sum since they were last started.
    sums: Sums,
    /// Twice the kinetic energy, `sum m v^2` (constant: collisions are elastic).
    two_kinetic: Real,
    zeno: ZenoGuard,
    /// A pair is listed when its centres are within this many times its sum of radii.
    list_factor: Real,
    /// Events processed: collisions, stale events, shell crossings, grazes, wall contacts.
    event_counts: [u64; 5],
    /// Stale events that took a runner-up, and that took the shell crossing.
    spare_counts: [u64; 2],
    /// Room for what the first pass of a prediction writes.
    sifted: Option<Box<first_pass::FirstPassOut>>,
    /// Whether the first pass goes four pairs at a time (the processor has AVX).
    #[cfg(target_arch = "x86_64")]
    wide: bool,
    /// Room for the spheres a relist finds.
    found: Vec<u32>,
}

impl ListedSpheres {
    /// The current time.
    pub fn now(&self) -> Real {
        self.now
    }

    /// Number of spheres.
    pub fn len(&self) -> usize {
        self.ext.len()
    }

    /// Whether there are no spheres.
    pub fn is_empty(&self) -> bool {
        self.ext.is_empty()
    }

    /// The run's statistics so far.
    pub fn stats(&self) -> Stats {
        let mut stats = self.stats.clone();
        for (name, &count) in event::EVENT_NAMES.iter().zip(&self.event_counts) {
            if count > 0 {
                stats.events_by_kind.insert(name, count);
            }
        }
        stats
    }

    /// Starts the bulk figures afresh from now (after the system has equilibrated).
    pub fn reset_bulk(&mut self) {
        self.sums = Sums::from(self.now);
    }

    /// Takes the contact events found so far.
    pub fn drain_events(&mut self) -> Vec<ContactEvent> {
        std::mem::take(&mut self.events)
    }

    /// The time of the next event, or infinity.
    pub fn next_event_time(&self) -> Real {
        self.queue.next_time()
    }

    /// Collision rate, temperature and pressure over the run so far.
    pub fn bulk(&self) -> Bulk {
        let filled = self.motion.iter().map(|m| ball_volume(m.radius)).sum();
        let (side, walls) = (self.period.side, self.walls.is_some());
        let n = self.len();
        self.sums
            .figures(self.now, n, self.two_kinetic, side, walls, filled)
    }

    /// The structure's own counters: neighbours listed, list capacity, cells, and the stale
    /// events that took a runner-up or the shell crossing instead of predicting again.
    pub fn counters(&self) -> Vec<(&'static str, f64)> {
        let n = self.len().max(1) as Real;
        vec![
            ("neighbours_per_sphere", self.lists.total() as f64 / n),
            ("list_capacity", self.lists.stride() as f64),
            ("cells", self.grid.cells() as f64),
            ("stale_to_runner_up", self.spare_counts[0] as f64),
            ("stale_to_shell", self.spare_counts[1] as f64),
        ]
    }

    /// The centre of sphere `id` (its own id) at the current time, unwrapped.
    pub fn position(&self, id: u32) -> Option<Vec3> {
        let i = self.ext.iter().position(|&e| e == id)?;
        Some(self.motion[i].at(self.now))
    }

    /// Advances to `time`, processing every event up to it.
    pub fn advance_to(&mut self, time: Real) -> Result<(), kinetic_core::WorldError> {
        while self.step(time)? {}
        if time > self.now {
            self.now = time;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod walls_tests;
