//! Choosing the structure for a set of free-flying objects ("model no more than a scene
//! needs"): the one home of the flight structures' names and of the rules that pick among
//! them, measured rather than taken from the paper's theorems (the sweep's and the guards'
//! bounds are worst cases; on the scenes people run, the grids are faster).
//!
//! - [`for_flights`]: exact event simulation over a horizon (the command-line tool, the
//!   library's default world): by the spread of sizes, the loose grid, the grid or the sweep.
//! - [`for_steps`]: a stepping engine that re-plans its bodies every few steps (the rapier
//!   adapter): the loose grid for alike sizes, the grid otherwise.

use crate::cell_math::levels_for;
use crate::shape::fatness;
use kinetic_core::{Real, Shape};

/// The scale factor (ratio of inner radii) up to which the paper's Theorem 6 bounds the
/// sweep's candidates; beyond it, the paper uses guards.
pub const SIGMA_MAX: Real = 8.0;

/// The largest fatness the guard grids are built for: objects fatter than this (or than the
/// fattest object, if less) are paired with every object instead of guarded. A grid for
/// fatness rho has about (sqrt 3 (rho + 1)^2)^3 guards per object, so this caps the grid at
/// 44 planes per axis.
pub const RHO_MAX: Real = 4.0;

/// Sizes (outer radii, largest over smallest) spread by at most this factor: the loose grid,
/// in [`for_flights`], for many objects (measured fastest on balls of sizes 1:250 at 3e3 to
/// 1e4, 1.3x to 2.2x the grid, and the grid 1.9x to 3.4x faster on sizes 1:1000: the bound
/// is between the two). Fewer objects take the loose grid only within [`loose_spread`].
pub const LOOSE_SPREAD: Real = 500.0;
/// Below [`LOOSE_SPREAD`], the loose grid's bound for `n` objects in a free world:
/// `LOOSE_N_SPREAD (n / LOOSE_N)^0.6`, within `LOOSE_N_SPREAD` and [`LOOSE_SPREAD`]. The
/// loose grid's time over the grid's grows about as `spread^0.56` and shrinks about as
/// `n^-0.33` (fitted on balls of sizes 1:100, 1:250 and 1:1000 at 300 to 1e4 objects): at
/// 1:250 the grid is 1.4x faster at 300 objects and 1.2x at 1,000, the loose grid 1.3x
/// faster at 3,000, and at 1:100 the loose grid is faster from 300 objects on.
pub const LOOSE_N_SPREAD: Real = 100.0;
/// See [`LOOSE_N_SPREAD`].
pub const LOOSE_N: Real = 300.0;
/// Sizes spread by at most this factor (and more than [`LOOSE_SPREAD`]): the hierarchical
/// grid in a free world; beyond it, the sweep, in [`for_flights`] (the grid fastest on sizes
/// 1:1000 at 1e3 to 1e4, the sweep on sizes 1:10^4: the bound is between the two).
pub const GRID_SPREAD: Real = 3000.0;
/// Moving bodies whose radii (the middle 98%) are within this factor get the loose grid, in
/// [`for_steps`].
pub const SIZES_ALIKE: Real = 8.0;

/// The brute force's cost per pair of balls moving linearly (its one certificate), in
/// microseconds, fitted on the choice family at 10 to 300 objects (`docs/results/choice.md`)...
pub const PAIR_COST: Real = 0.28;
/// ... twice that where pairs are heavier: cuboids and hulls (conservative advancement),
/// accelerations (certificates of degree 4)...
pub const HEAVY_PAIR_FACTOR: Real = 2.0;
/// ... and a box structure's cost per object (its build)...
pub const OBJECT_COST: Real = 2.8;
/// ... and per crossing (an object travelling its own diameter: a region left, a box end
/// passed, a cell crossed)...
pub const CROSSING_COST: Real = 0.71;
/// ... and per contact the objects make (a new candidate pair to certify), fitted on the gas
/// and the dense gas at 100 and 300 objects (2% and 15% of space filled).
pub const CONTACT_COST: Real = 1.2;
/// Elastic scenes above this many objects never get the brute force: each bounce re-plans two
/// objects, which costs it two certificates per object. Up to this many, the brute force
/// costs least whatever the objects do: [`crate::Auto`] holds it while it holds no more.
pub const ELASTIC_BRUTE_MAX: usize = 32;

/// Whether the brute force is the cheaper choice for `n` objects that cross their own size
/// `crossings` times in all over the run (see `kinetic_collide::structures::crossings`) and
/// make about `contacts` contacts (`kinetic_collide::structures::contacts`: more where they
/// crowd): its `n (n - 1) / 2` pair certificates against a box structure's cost per object,
/// per crossing and per contact. It is, for a few dozen objects, for a hundred that crowd,
/// and for a few hundred that travel far on a long horizon without bouncing. `shapes`: some
/// objects are cuboids or hulls; `elastic`: balls bounce.
pub fn brute_force_pays(
    n: usize,
    crossings: Real,
    contacts: Real,
    shapes: bool,
    elastic: bool,
) -> bool {
    if elastic && n > ELASTIC_BRUTE_MAX {
        return false;
    }
    let pair = if shapes {
        PAIR_COST * HEAVY_PAIR_FACTOR
    } else {
        PAIR_COST
    };
    let nf = n as Real;
    let boxes = OBJECT_COST * nf + CROSSING_COST * crossings + CONTACT_COST * contacts.max(0.0);
    pair * nf * (nf - 1.0) / 2.0 <= boxes
}

/// A structure for free-flying objects.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Choice {
    /// [`crate::Sweep`].
    Sweep,
    /// [`crate::Guards`].
    Guards,
    /// [`crate::Grid`].
    Grid,
    /// [`crate::LooseGrid`].
    Loose,
}

impl Choice {
    /// Every flight structure.
    pub const ALL: [Choice; 4] = [Choice::Sweep, Choice::Guards, Choice::Grid, Choice::Loose];

    /// Its name, on the command line and in statistics (its structure's
    /// [`kinetic_core::CandidateStructure::name`]).
    pub const fn name(self) -> &'static str {
        match self {
            Choice::Sweep => "sweep",
            Choice::Guards => "guards",
            Choice::Grid => "grid",
            Choice::Loose => "loose-grid",
        }
    }

    /// The structure by its name.
    pub fn from_name(name: &str) -> Option<Choice> {
        Choice::ALL.into_iter().find(|c| c.name() == name)
    }
}

/// The spread of `radii` (largest over smallest positive one; 1 for none).
pub fn spread(radii: impl IntoIterator<Item = Real>) -> Real {
    let (lo, hi) = radii
        .into_iter()
        .filter(|&r| r > 0.0)
        .fold((Real::INFINITY, 0.0 as Real), |(lo, hi), r| {
            (lo.min(r), hi.max(r))
        });
    if hi > 0.0 { hi / lo } else { 1.0 }
}

/// The structure for an exact event simulation of objects whose outer radii spread by
/// `spread` (see [`spread`]), measured fastest on the choice family
/// (`docs/results/choice.md`):
///
/// 1. objects that barely move (`resting`, see [`barely_moving`]) within [`GRID_SPREAD`]:
///    the hierarchical grid, the cheapest to build;
/// 2. within [`LOOSE_SPREAD`], and in a free world within [`loose_spread`] for `n` objects
///    (the grid wins at wide spreads until the objects are many): the loose grid, one
///    certificate per object;
/// 3. within [`GRID_SPREAD`], in a free world: the hierarchical grid, exact box pairs level
///    by level;
/// 4. a wider spread, or a plane world (`plane`: balls rolling on a plane, whose discs the
///    sweep's lists hold 1.5x to 4x faster than the grid at sizes 1:1000): the sweep, whose
///    sorted lists do not care about sizes.
///
/// The guards are never picked: on every scene measured, one of the three is faster.
pub fn for_flights(spread: Real, n: usize, resting: bool, plane: bool) -> Choice {
    if resting && spread <= GRID_SPREAD {
        Choice::Grid
    } else if spread <= LOOSE_SPREAD && (plane || spread <= loose_spread(n)) {
        Choice::Loose
    } else if spread <= GRID_SPREAD && !plane {
        Choice::Grid
    } else {
        Choice::Sweep
    }
}

/// The hierarchical grid's cell crossings per own-size crossing, relative to objects of alike
/// sizes, for objects of outer radii `radii`. The grid files an object at the level whose
/// cells are the first as wide as it, so its cells are 1 to `ratio` times its width for the
/// grid's ratio between levels (`ratio` 2 for alike sizes, 16 for sizes 1:1000): over sizes
/// spread evenly on a log scale, an object crosses `(1 - 1/ratio) / ln ratio` cells per
/// own-size crossing. [`CROSSING_COST`] was fitted at `ratio` 2, so this is that share over
/// its value at 2 (1 for alike sizes, 0.47 at `ratio` 16): what [`brute_force_pays`] weighs
/// against the pairs where the grid is the box structure.
pub fn grid_crossing_share(radii: impl IntoIterator<Item = Real>) -> Real {
    let share = |ratio: Real| (1.0 - 1.0 / ratio) / ratio.ln();
    levels_for(radii.into_iter()).map_or(1.0, |(_, ratio)| share(ratio) / share(2.0))
}

/// The sweep's cost per box end passed (`kinetic_collide::structures::passes`), in
/// microseconds: its sorted lists swap 1.1 to 1.5 times a pass, and a pass costs it 0.45 to
/// 0.86 us on balls (the gas, sizes 1:1000 and 1:10^4, rolling balls 1:1000, at 100 to 1,000
/// objects). Its own size does not matter to the sweep, so where sizes spread it passes far
/// fewer ends than the small objects cross their own sizes.
pub const SWEEP_PASS_COST: Real = 0.6;

/// The sweep's `passes` as the crossings of [`brute_force_pays`] that cost the same.
pub fn sweep_crossings(passes: Real) -> Real {
    passes * SWEEP_PASS_COST / CROSSING_COST
}

/// The widest spread of sizes for which `n` objects in a free world get the loose grid (see
/// [`LOOSE_N_SPREAD`]).
pub fn loose_spread(n: usize) -> Real {
    (LOOSE_N_SPREAD * (n as Real / LOOSE_N).powf(0.6)).clamp(LOOSE_N_SPREAD, LOOSE_SPREAD)
}

/// Objects that cross their own size fewer than this many times each, on average over the
/// run, barely move: all a structure costs them is its build...
pub const RESTING_CROSSINGS: Real = 0.1;
/// ... which is the grid's cheapest up to this many objects; above, its memory (2 kB an
/// object at rest, against the loose grid's 0.8 kB) costs more than its build saves.
pub const RESTING_GRID_MAX: usize = 200_000;

/// Whether `n` objects crossing their own size `crossings` times in all barely move (see
/// [`RESTING_CROSSINGS`]) and are few enough for the grid ([`RESTING_GRID_MAX`]).
pub fn barely_moving(n: usize, crossings: Real) -> bool {
    n <= RESTING_GRID_MAX && crossings <= RESTING_CROSSINGS * n as Real
}

/// The structure for a stepping engine's moving bodies of outer radii `radii`: the loose grid
/// when the middle 98% are within [`SIZES_ALIKE`] (a rain, a pile: bodies re-planned every
/// few steps keep their regions), the grid otherwise (a debris field, where small pieces
/// drift as fast as large ones and would leave regions sized by their own width every few
/// steps), and the grid for none.
pub fn for_steps(radii: impl IntoIterator<Item = Real>) -> Choice {
    let mut r: Vec<Real> = radii
        .into_iter()
        .filter(|r| *r > 0.0 && r.is_finite())
        .collect();
    if r.is_empty() {
        return Choice::Grid;
    }
    // The radii at two ranks, each found in linear time (no need to sort them all).
    let mut pick = |q: Real| {
        let rank = ((r.len() - 1) as Real * q).round() as usize;
        *r.select_nth_unstable_by(rank, Real::total_cmp).1
    };
    let (large, small) = (pick(0.99), pick(0.01));
    if large <= SIZES_ALIKE * small {
        Choice::Loose
    } else {
        Choice::Grid
    }
}

/// The scale factor sigma: largest over smallest inner radius (1 for fewer than two objects;
/// objects whose centre is not inside them are left out).
pub fn scale_factor<'a>(shapes: impl IntoIterator<Item = &'a Shape>) -> Real {
    spread(shapes.into_iter().map(Shape::inner_radius))
}

/// The fatness the guard grids should be built for: the fattest object's, at most
/// [`RHO_MAX`].
pub fn guard_fatness<'a>(shapes: impl IntoIterator<Item = &'a Shape>) -> Real {
    shapes
        .into_iter()
        .map(fatness)
        .filter(|&f| f <= RHO_MAX)
        .fold(1.0, Real::max)
}

/// The paper's rule: the sweep when the scale factor is at most [`SIGMA_MAX`], guards
/// otherwise (what Theorems 6 and 10 favour; slower than [`for_flights`] on real scenes).
pub fn paper_choice<'a>(shapes: impl IntoIterator<Item = &'a Shape>) -> Choice {
    if scale_factor(shapes) <= SIGMA_MAX {
        Choice::Sweep
    } else {
        Choice::Guards
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_differ() {
        for c in Choice::ALL {
            assert_eq!(Choice::from_name(c.name()), Some(c));
        }
        assert_eq!(Choice::from_name("loose"), None);
    }

    #[test]
    fn flights_by_spread() {
        assert_eq!(spread([]), 1.0);
        assert_eq!(spread([2.0, 0.0, 0.5]), 4.0);
        let many = 100_000;
        assert_eq!(for_flights(1.0, many, false, false), Choice::Loose);
        assert_eq!(for_flights(LOOSE_SPREAD, many, false, false), Choice::Loose);
        assert_eq!(
            for_flights(LOOSE_SPREAD * 1.01, many, false, false),
            Choice::Grid
        );
        assert_eq!(
            for_flights(LOOSE_SPREAD * 1.01, many, false, true),
            Choice::Sweep
        );
        assert_eq!(
            for_flights(GRID_SPREAD * 1.01, many, false, false),
            Choice::Sweep
        );
        assert_eq!(for_flights(1.0, many, true, false), Choice::Grid);
        assert_eq!(for_flights(1.0, many, true, true), Choice::Grid);
        assert_eq!(
            for_flights(GRID_SPREAD * 1.01, many, true, false),
            Choice::Sweep
        );
        // Sizes 1:250: the grid for a few hundred objects, the loose grid for thousands; on
        // a plane the loose grid either way. Sizes 1:100: the loose grid for any number.
        assert_eq!(for_flights(250.0, 300, false, false), Choice::Grid);
        assert_eq!(for_flights(250.0, 1000, false, false), Choice::Grid);
        assert_eq!(for_flights(250.0, 3000, false, false), Choice::Loose);
        assert_eq!(for_flights(250.0, 300, false, true), Choice::Loose);
        assert_eq!(for_flights(100.0, 10, false, false), Choice::Loose);
        assert_eq!(loose_spread(10), LOOSE_N_SPREAD);
        assert_eq!(loose_spread(many), LOOSE_SPREAD);
        assert!(barely_moving(1000, 50.0));
        assert!(!barely_moving(1000, 500.0));
        assert!(!barely_moving(1_000_000, 0.0));
    }

    #[test]
    fn the_brute_force_for_few_objects_crowds_or_long_flights() {
        assert!(brute_force_pays(10, 0.0, 0.0, false, false));
        assert!(!brute_force_pays(100, 0.0, 0.0, false, false));
        // 100 balls each crossing its size 60 times over the run.
        assert!(brute_force_pays(100, 6000.0, 0.0, false, false));
        assert!(!brute_force_pays(100, 2000.0, 0.0, true, false));
        assert!(!brute_force_pays(100, 6000.0, 0.0, false, true));
        assert!(!brute_force_pays(1000, 1e5, 0.0, false, false));
        assert!(!brute_force_pays(30, 0.0, 0.0, true, false));
        // 100 balls crossing their size 10 times each: in a sparse gas (2% of space filled,
        // 0.12 contacts per crossing) a box structure; in a crowd (15%, 0.9) the brute force.
        assert!(!brute_force_pays(100, 1000.0, 120.0, false, false));
        assert!(brute_force_pays(100, 1000.0, 900.0, false, false));
    }

    #[test]
    fn the_grid_crosses_fewer_cells_where_sizes_spread() {
        assert_eq!(grid_crossing_share([]), 1.0);
        // Alike sizes: levels a factor 2 apart, the share the crossing cost was fitted at.
        assert_eq!(grid_crossing_share([1.0; 100]), 1.0);
        // Sizes 1:1000, evenly on a log scale: levels 16 apart, cells about twice as wide
        // as their objects on average against alike sizes.
        let wide: Vec<Real> = (0..=300)
            .map(|i| 0.005 * (1000.0 as Real).powf(i as Real / 300.0))
            .collect();
        let share = grid_crossing_share(wide.iter().copied());
        assert!((share - 0.47).abs() < 0.01, "{share}");
        // Sizes 1:64: levels 4 apart, between the two.
        let mid = grid_crossing_share(wide.iter().map(|r| r.powf(0.6)));
        assert!(share < mid && mid < 1.0, "{mid}");
    }

    #[test]
    fn steps_by_middle_sizes() {
        assert_eq!(for_steps([]), Choice::Grid);
        assert_eq!(for_steps([1.0; 50]), Choice::Loose);
        // One boulder among pebbles is outside the middle 98%.
        let mut r = vec![1.0; 200];
        r.push(1000.0);
        assert_eq!(for_steps(r.iter().copied()), Choice::Loose);
        let spread_wide: Vec<Real> = (0..200).map(|i| 1.0 + i as Real).collect();
        assert_eq!(for_steps(spread_wide), Choice::Grid);
        // The ranks as a full sort gives them, on spreads either side of the line.
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(4);
        let mut both = [0; 2];
        for k in 0..400 {
            let spread = 1.0 + 14.0 * (k as Real / 400.0);
            let n = rng.random_range(1..300);
            let r: Vec<Real> = (0..n).map(|_| rng.random_range(1.0..=spread)).collect();
            let mut sorted = r.clone();
            sorted.sort_unstable_by(Real::total_cmp);
            let at = |q: Real| sorted[((n - 1) as Real * q).round() as usize];
            let want = if at(0.99) <= SIZES_ALIKE * at(0.01) {
                Choice::Loose
            } else {
                Choice::Grid
            };
            assert_eq!(for_steps(r), want, "spread {spread}, {n} radii");
            both[usize::from(want == Choice::Loose)] += 1;
        }
        assert!(both[0] > 0 && both[1] > 0, "{both:?}");
    }
}
