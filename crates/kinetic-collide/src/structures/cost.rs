//! The cost model that shortlists the default structure for a scene: what the brute force
//! pays per pair against what a box structure pays per object, per crossing and per
//! contact, and which box structure fits the spread of sizes. Its constants were measured
//! on the choice family (`cargo bench --bench choice`, `docs/results/choice.md`); they are
//! private to the registry and say in their docs what they were measured on.

use super::Structure;
use kinetic_core::Real;
use kinetic_flight::Grid;

/// Sizes (outer radii, largest over smallest) spread by at most this factor: the loose grid is
/// tried by the race ([`super::Race`]), and named by [`for_flights`] for more objects than
/// [`LOOSE_GRID_MIN`]. Wider, a few large objects hold regions that every region checks; on
/// the choice family (`cargo bench --bench choice -- --family 300 3000 10000`) the grid was
/// 1.2x to 10x faster from sizes 1:60 on (asteroids and cuboids 1:60, balls 1:100 and 1:250,
/// balls 1:1000 rolling on a plane), and on 40 draws of the choice space the loose grid ran
/// 2x to 50x the grid's time at sizes 1:36 to 1:3,773 (`cargo bench --bench choice`).
pub(crate) const LOOSE_SPREAD: Real = 4.0;
/// Sizes spread by at most this factor: the hierarchical grid, in [`for_flights`]; beyond
/// it, the sweep. The grid was the fastest on every spread measured: balls of sizes 1:10^4
/// in the choice family (1.2x to 1.3x the sweep at 300 to 10,000 objects), and the same gas
/// at sizes 1:3x10^4 and 1:10^5 (1.3x the sweep at 300 objects, 2.5x at 3,000). Wider spreads
/// were not measured; the sweep's sorted lists do not care about sizes, where the grid's
/// levels grow with them.
pub(crate) const GRID_SPREAD: Real = 1e5;
/// Fewer objects than this whose sizes spread by more than [`FEW_SPREAD`]: the sweep, in
/// [`for_flights`]. On 160 scenes drawn from the choice space at 10 to 1,500 objects
/// (`cargo bench --bench choice -- --draws 80 --max-objects 1500`, seeds 1 and 1001), the
/// sweep was as fast as the grid or faster (up to 100x) on every such scene but one of 30
/// objects (sizes 1:56,000: the sweep 0.6 ms, the grid 0.4 ms).
pub(crate) const FEW_OBJECTS: usize = 150;
/// See [`FEW_OBJECTS`]: the bound sits between sizes 1:100 (the grid 1.2x to 4x faster at
/// 119 and 133 objects) and 1:300 to 1:500 (the sweep 1.2x to 4x faster at 17 to 102
/// objects).
pub(crate) const FEW_SPREAD: Real = 500.0;
/// Where the sweep's estimated work is under this share of the grid's, the sweep, in
/// [`for_flights`]: the box ends the objects pass ([`sweep_crossings`]) against the cells
/// the grid's objects cross (crossings times [`grid_crossing_share`]). The grid's estimate
/// counts every cell an object crosses, where a fast small object flies in a region and
/// crosses far fewer, so it runs up to ten times its crossing events; on the 160 draws of
/// [`FEW_OBJECTS`], the sweep was faster or within 1.07x wherever its estimate was under a
/// third of the grid's, save one run of 0.4 ms, and the grid was faster on most above.
pub(crate) const SWEEP_SHARE: Real = 1.0 / 3.0;
/// Where the sweep's estimated work is over this many times the grid's (see
/// [`SWEEP_SHARE`]), the race does not try the sweep. On the 320 small draws of the choice
/// space (`cargo bench --bench choice -- --draws 80 --max-objects 1500`, seeds 1, 1001, 2001
/// and 3001) and the 40 of `--draws 40`, the sweep was never more than 1.02x faster than the
/// grid there (268 objects, 0.59 s against 0.60 s), and up to 22x slower; on 67,609 balls
/// with bullets its trial cost 4% of the run (its build, 0.22 s, and a slice cut short at
/// once).
pub(crate) const SWEEP_SKIP: Real = 10.0;

/// Whether a race should try the sweep, whose estimated work is `sweep_share` of the grid's
/// (see [`SWEEP_SKIP`]; infinite: not known).
pub(crate) fn sweep_worth_trying(sweep_share: Real) -> bool {
    !(sweep_share.is_finite() && sweep_share > SWEEP_SKIP)
}

/// The brute force's cost per pair of balls moving linearly (its one certificate), in
/// microseconds, fitted on the choice family at 10 to 300 objects.
pub(crate) const PAIR_COST: Real = 0.28;
/// How much more a heavier pair costs the brute force than a linear ball pair: cuboids and
/// hulls (conservative advancement), accelerations (certificates of degree 4).
pub(crate) const HEAVY_PAIR_FACTOR: Real = 2.0;
/// A box structure's cost per object (its build), in microseconds, fitted on the choice
/// family at 10 to 300 objects.
pub(crate) const OBJECT_COST: Real = 2.8;
/// A box structure's cost per crossing (an object travelling its own diameter: a region
/// left, a box end passed, a cell crossed), in microseconds, fitted on the choice family.
pub(crate) const CROSSING_COST: Real = 0.71;
/// A box structure's cost per contact the objects make (a new candidate pair to certify), in
/// microseconds, fitted on the gas and the dense gas at 100 and 300 objects (2% and 15% of
/// space filled).
pub(crate) const CONTACT_COST: Real = 1.2;
/// Above this many objects the model never names the brute force: the run starts on a box
/// structure, and the race brings the brute force in where the paces it measures say its
/// build is paid back (see [`super::Race`]). On 280 scenes drawn from the choice space
/// (`cargo bench --bench choice -- --draws 80 --max-objects 1500`, seeds 1, 1001 and 2001,
/// and `--draws 40`), the brute force was the fastest for 66 to 90 balls flying far (0.8 ms
/// to 1.8 ms, against 1.4 ms to 3.4 ms for the next), and where the model named it for 99 to
/// 559 objects the grid or the sweep ran 1.3x to 3.7x faster.
pub(crate) const BRUTE_FORCE_MODEL_MAX: usize = 96;
/// Elastic scenes above this many objects never get the brute force: each bounce re-plans two
/// objects, which costs it two certificates per object. Up to this many, the brute force
/// costs least whatever the objects do: [`super::Auto`] holds it while it holds no more.
pub(crate) const ELASTIC_BRUTE_MAX: usize = 32;

/// Whether the brute force is the cheaper choice for `n` objects that cross their own size
/// `crossings` times in all over the run (see [`super::scene_measures::crossings`]) and
/// make about `contacts` contacts ([`super::scene_measures::contacts`]: more where they
/// crowd): its `n (n - 1) / 2` pair certificates against a box structure's cost per object,
/// per crossing and per contact, up to [`BRUTE_FORCE_MODEL_MAX`] objects. It is, for a few
/// dozen objects, and for a few more that crowd or travel far on a long horizon without
/// bouncing. `shapes`: some objects are cuboids or hulls; `elastic`: balls bounce.
pub(crate) fn brute_force_pays(
    n: usize,
    crossings: Real,
    contacts: Real,
    shapes: bool,
    elastic: bool,
) -> bool {
    if n > BRUTE_FORCE_MODEL_MAX || (elastic && n > ELASTIC_BRUTE_MAX) {
        return false;
    }
    let pair = if shapes {
        PAIR_COST * HEAVY_PAIR_FACTOR
    } else {
        PAIR_COST
    };
    let nf = n as Real;
    pair * nf * (nf - 1.0) / 2.0 <= boxes_cost(n, crossings, contacts)
}

/// What a box structure costs, in microseconds, for `n` objects, `crossings` crossings and
/// `contacts` contacts (see [`brute_force_pays`]).
pub(crate) fn boxes_cost(n: usize, crossings: Real, contacts: Real) -> Real {
    OBJECT_COST * n as Real + CROSSING_COST * crossings + CONTACT_COST * contacts.max(0.0)
}

/// The structure for an exact event simulation of `n` objects whose outer radii spread by
/// `spread` (see [`crate::scene::radius_spread`]), measured fastest on the choice family
/// (`docs/results/choice.md`), in a free world or rolling on a plane alike:
///
/// 1. more than [`LOOSE_GRID_MIN`] objects of alike sizes (within [`LOOSE_SPREAD`]): the
///    loose grid, one certificate and a small region per object;
/// 2. within [`GRID_SPREAD`]: the hierarchical grid, exact box pairs level by level, unless
///    fewer than [`FEW_OBJECTS`] spread past [`FEW_SPREAD`], or the sweep's estimated work is
///    under [`SWEEP_SHARE`] of the grid's (`sweep_share`: the sweep's over the grid's,
///    infinite where unknown);
/// 3. otherwise the sweep, whose sorted lists do not care about sizes.
///
/// The guards are never picked: on every scene measured, one of the three is faster. The
/// race tries the loose grid against the grid where sizes are alike.
pub(crate) fn for_flights(spread: Real, n: usize, sweep_share: Real) -> Structure {
    let few = n < FEW_OBJECTS && spread > FEW_SPREAD;
    if spread <= LOOSE_SPREAD && n > LOOSE_GRID_MIN {
        Structure::LooseGrid
    } else if spread <= GRID_SPREAD && !few && sweep_share >= SWEEP_SHARE {
        Structure::Grid
    } else {
        Structure::Sweep
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
pub(crate) fn grid_crossing_share(radii: impl IntoIterator<Item = Real>) -> Real {
    let share = |ratio: Real| (1.0 - 1.0 / ratio) / ratio.ln();
    Grid::levels_for(radii).map_or(1.0, |(_, ratio)| share(ratio) / share(2.0))
}

/// The sweep's cost per box end passed ([`super::scene_measures::passes`]), in
/// microseconds: its sorted lists swap 1.1 to 1.5 times a pass, and a pass costs it 0.45 to
/// 0.86 us on balls (the gas, sizes 1:1000 and 1:10^4, rolling balls 1:1000, at 100 to 1,000
/// objects). Its own size does not matter to the sweep, so where sizes spread it passes far
/// fewer ends than the small objects cross their own sizes.
pub(crate) const SWEEP_PASS_COST: Real = 0.6;

/// The sweep's `passes` as the crossings of [`brute_force_pays`] that cost the same.
pub(crate) fn sweep_crossings(passes: Real) -> Real {
    passes * SWEEP_PASS_COST / CROSSING_COST
}

/// Above this many objects of alike sizes, the loose grid, in [`for_flights`]; up to it, the
/// grid, and the race tries the loose grid. The grid's memory (2 kB an object at rest,
/// against the loose grid's 0.8 kB) then costs more than its build saves. Below it, the grid
/// widens its cells to about one object each where they are sparse, where the loose grid's
/// regions stay two sizes of travel: on scenes of alike sizes written outside the project
/// (`docs/results/choice.md`), the grid ran 1.04x to 26x faster on nine (50,000 sparse
/// specks: 0.07 s against 0.52 s; 20,000 drifting balls 2.9x; a rain 6.5x), and the loose
/// grid 1.02x to 1.44x on five (a fountain under gravity, lanes of balls crossing on a
/// plane); on the 40 draws of the choice space, 0.90x to 1.14x either way.
pub(crate) const LOOSE_GRID_MIN: usize = 200_000;

#[cfg(test)]
mod tests {
    use super::*;

    /// The rule where the sweep's work is not known.
    fn ff(spread: Real, n: usize) -> Structure {
        for_flights(spread, n, Real::INFINITY)
    }

    #[test]
    fn flights_by_spread() {
        let many = 1000;
        // Alike sizes: the grid, the loose grid only for more objects than the grid's memory
        // suits.
        assert_eq!(ff(1.0, many), Structure::Grid);
        assert_eq!(ff(LOOSE_SPREAD, LOOSE_GRID_MIN), Structure::Grid);
        assert_eq!(ff(1.0, LOOSE_GRID_MIN + 1), Structure::LooseGrid);
        assert_eq!(ff(LOOSE_SPREAD, LOOSE_GRID_MIN + 1), Structure::LooseGrid);
        assert_eq!(ff(LOOSE_SPREAD * 1.01, LOOSE_GRID_MIN + 1), Structure::Grid);
        assert_eq!(ff(GRID_SPREAD, many), Structure::Grid);
        assert_eq!(ff(GRID_SPREAD * 1.01, many), Structure::Sweep);
        // A few objects of widely spread sizes: the sweep.
        let few = FEW_OBJECTS - 1;
        assert_eq!(ff(FEW_SPREAD, few), Structure::Grid);
        assert_eq!(ff(FEW_SPREAD * 1.01, few), Structure::Sweep);
        assert_eq!(ff(FEW_SPREAD * 1.01, FEW_OBJECTS), Structure::Grid);
        // The sweep where its estimated work is under a third of the grid's.
        assert_eq!(for_flights(100.0, many, 0.5), Structure::Grid);
        assert_eq!(for_flights(100.0, many, 0.2), Structure::Sweep);
        assert_eq!(for_flights(2.0, many, 0.2), Structure::Sweep);
        // Not even tried where it would do ten times the grid's work.
        assert!(sweep_worth_trying(5.0));
        assert!(!sweep_worth_trying(20.0));
        assert!(sweep_worth_trying(Real::INFINITY));
    }

    #[test]
    fn the_brute_force_for_few_objects_crowds_or_long_flights() {
        assert!(brute_force_pays(10, 0.0, 0.0, false, false));
        assert!(!brute_force_pays(60, 0.0, 0.0, false, false));
        // 60 balls each crossing its size 30 times over the run.
        assert!(brute_force_pays(60, 1800.0, 0.0, false, false));
        assert!(!brute_force_pays(60, 600.0, 0.0, true, false));
        assert!(!brute_force_pays(60, 1800.0, 0.0, false, true));
        assert!(!brute_force_pays(30, 0.0, 0.0, true, false));
        // 60 balls crossing their size 5 times each: in a sparse gas (2% of space filled,
        // 0.12 contacts per crossing) a box structure; in a crowd (15%, 0.9) the brute force.
        assert!(!brute_force_pays(60, 300.0, 36.0, false, false));
        assert!(brute_force_pays(60, 300.0, 270.0, false, false));
        // Above 96 objects, never: the race measures whether it pays back.
        assert!(brute_force_pays(90, 5400.0, 0.0, false, false));
        assert!(!brute_force_pays(100, 6000.0, 0.0, false, false));
        assert!(!brute_force_pays(100, 1000.0, 900.0, false, false));
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
}
