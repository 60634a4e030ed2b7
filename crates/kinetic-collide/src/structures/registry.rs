//! Every structure once: its name, what it applies to and how it is built.

use super::{cost, scene_measures};
use crate::scene::Scene;
use kinetic_core::{BruteForce, CandidateStructure, Response, Shape, WorldKind};
use kinetic_flight::{Grid, Guards, LooseGrid, Sweep};
use kinetic_rolling::{ListLayout, RollingTree};

/// The kinetic structures, by the names the command line and the statistics give them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Structure {
    /// Collision tree with threshold boxes (Section 2), plane worlds.
    RollingTree,
    /// The rolling tree with two global sorted lists (the paper's second remark).
    RollingGlobalLists,
    /// Sweep over boxes of similar-size objects (Section 3.1).
    Sweep,
    /// Guards and cones for arbitrary sizes (Section 3.2).
    Guards,
    /// The sweep's box pairs, found in a hierarchical kinetic grid (neighbours only).
    Grid,
    /// A loose kinetic grid: each object holds a region its box stays in for a while, and
    /// candidates are the objects whose regions overlap (one certificate per object).
    LooseGrid,
    /// Elastic balls in walls on a hierarchical grid of cells, one scheduled event per ball
    /// (the hard-sphere systems of molecular dynamics; `kinetic_collide::spheres`).
    Cells,
    /// Elastic balls of similar sizes (the largest at most twice the smallest) in walls, with
    /// the periodic structure's neighbour lists and one scheduled event per ball.
    Lists,
    /// Elastic balls in a periodic box, with neighbour lists and one scheduled event per ball
    /// (bulk hard-sphere fluids); the only structure for periodic scenes.
    Periodic,
    /// One certificate per pair: the exact reference.
    BruteForce,
}

/// Parts of the horizon a grid's region covers at least: an object crossing empty space
/// costs the grids at most about this many events over the run, however long the horizon
/// (two balls flying apart for 1e100 time units are done at once).
pub(crate) const FLIGHT_PARTS: f64 = 1000.0;

impl Structure {
    /// Every structure.
    pub const ALL: [Structure; 10] = [
        Structure::RollingTree,
        Structure::RollingGlobalLists,
        Structure::Sweep,
        Structure::Guards,
        Structure::Grid,
        Structure::LooseGrid,
        Structure::Cells,
        Structure::Lists,
        Structure::Periodic,
        Structure::BruteForce,
    ];

    /// Its name, on the command line and in the statistics (the name its candidate structure
    /// gives, [`kinetic_core::CandidateStructure::name`]).
    pub const fn name(self) -> &'static str {
        match self {
            Structure::RollingTree => "rolling-tree",
            Structure::RollingGlobalLists => "rolling-global-lists",
            Structure::Sweep => "sweep",
            Structure::Guards => "guards",
            Structure::Grid => "grid",
            Structure::LooseGrid => "loose-grid",
            Structure::Cells => "cells",
            Structure::Lists => "lists",
            Structure::Periodic => "periodic",
            Structure::BruteForce => "brute-force",
        }
    }

    /// The structure of that name.
    pub fn from_name(name: &str) -> Option<Structure> {
        Structure::ALL.into_iter().find(|s| s.name() == name)
    }

    /// Whether the structure runs `scene` (its world, shapes, response and walls).
    pub fn applies_to(self, scene: &Scene) -> bool {
        if scene.periodic.is_some() {
            return self == Structure::Periodic;
        }
        match self {
            Structure::Periodic => false,
            Structure::BruteForce | Structure::Sweep | Structure::Grid | Structure::LooseGrid => {
                true
            }
            Structure::RollingTree | Structure::RollingGlobalLists => {
                scene.world == WorldKind::Plane
            }
            Structure::Guards => scene.world == WorldKind::Free,
            Structure::Cells => super::scene_world::cell_balls(scene).is_some(),
            Structure::Lists => super::scene_world::listed_balls(scene).is_some(),
        }
    }

    /// Whether it runs inside a [`crate::World`] (every structure but the hard-sphere
    /// simulators, which run whole scenes).
    pub const fn runs_in_a_world(self) -> bool {
        !matches!(
            self,
            Structure::Cells | Structure::Lists | Structure::Periodic
        )
    }

    /// The structure `scene` gets when none is named.
    ///
    /// A periodic box gets the periodic structure, the only one that wraps. Elastic balls
    /// moving linearly inside walls get the neighbour lists when their sizes are within a
    /// factor of two (the cell grid would hold them on one level), else the cell grid when it
    /// fits their sizes: one scheduled event per ball either way. Otherwise the cost model
    /// shortlists: the brute force where its pairs cost less than a box structure's objects,
    /// crossings and contacts (a few dozen objects, or a few hundred flying far without
    /// bouncing), else the box structure that fits the spread of sizes and whether the objects
    /// stay within their first loose regions (the loose grid, the grid or the sweep). Plane
    /// worlds are held by the same box structures (a rolling ball's disc holds its contacts).
    /// The paper's other structures (rolling tree, guards) stay selectable by name.
    pub fn for_scene(scene: &Scene) -> Structure {
        if scene.periodic.is_some() {
            return Structure::Periodic;
        }
        if super::scene_world::listed_balls(scene).is_some() {
            return Structure::Lists;
        }
        if super::scene_world::cell_balls(scene).is_some() {
            return Structure::Cells;
        }
        let elastic = scene.response == Response::Elastic;
        let n = scene.objects.len();
        let boxes = Structure::boxes_for(scene);
        let cells = Structure::crossings_on(boxes, scene, scene_measures::crossings(scene));
        let contacts = scene_measures::contacts(scene);
        let heavy = scene_measures::heavy_pairs(scene);
        if cost::brute_force_pays(n, cells, contacts, heavy, elastic) {
            return Structure::BruteForce;
        }
        boxes
    }

    /// The crossings a box structure pays for on `scene`, whose objects cross their own sizes
    /// `crossings` times: the grid's cells, the sweep's box ends passed counted as crossings of
    /// the same cost, the loose grid's own crossings.
    fn crossings_on(boxes: Structure, scene: &Scene, crossings: f64) -> f64 {
        match boxes {
            Structure::Grid => crossings * cost::grid_crossing_share(scene_measures::radii(scene)),
            Structure::Sweep => cost::sweep_crossings(scene_measures::passes(scene)),
            _ => crossings,
        }
    }

    /// The box structure the cost model picks for `scene` (the grid, the sweep or the loose
    /// grid, by the spread of sizes, the number of objects and the sweep's estimated work
    /// against the grid's).
    pub(crate) fn boxes_for(scene: &Scene) -> Structure {
        let n = scene.objects.len();
        let crossings = scene_measures::crossings(scene);
        let share = Structure::sweep_share(scene, crossings);
        cost::for_flights(scene.size_ratio(), n, share)
    }

    /// The sweep's estimated work on `scene` over the grid's (see [`cost::SWEEP_SHARE`]),
    /// for objects crossing their own sizes `crossings` times: infinite where the grid has
    /// none.
    pub(crate) fn sweep_share(scene: &Scene, crossings: f64) -> f64 {
        let grid = Structure::crossings_on(Structure::Grid, scene, crossings);
        let sweep = Structure::crossings_on(Structure::Sweep, scene, crossings);
        if grid > 0.0 {
            sweep / grid
        } else {
            f64::INFINITY
        }
    }

    /// A fresh, empty candidate structure of this kind for a world of `kind` whose objects
    /// are `shapes` (the guards size their grids by the fattest), whose grids give every
    /// region at least `least_flight` time units of flight; or why it does not apply.
    pub(crate) fn build(
        self,
        kind: WorldKind,
        shapes: &[Shape],
        least_flight: f64,
    ) -> Result<Box<dyn CandidateStructure>, &'static str> {
        let plane = kind == WorldKind::Plane;
        match self {
            Structure::BruteForce => Ok(Box::new(BruteForce::new())),
            Structure::RollingTree if plane => Ok(Box::new(RollingTree::new(ListLayout::PerNode))),
            Structure::RollingGlobalLists if plane => {
                Ok(Box::new(RollingTree::new(ListLayout::Global)))
            }
            Structure::RollingTree | Structure::RollingGlobalLists => {
                Err("applies to \"plane\" worlds only")
            }
            // A ball rolling on the plane touches another at a distance of 2 sqrt(ra rb), at
            // most ra + rb: the discs' boxes hold every contact, so the box structures serve.
            Structure::Guards if plane => Err("applies to \"free\" worlds only"),
            Structure::Guards => Ok(Box::new(Guards::new(Guards::fatness_for(shapes)))),
            Structure::Sweep => Ok(Box::new(Sweep::new())),
            Structure::Grid => Ok(Box::new(Grid::new().with_least_flight(least_flight))),
            Structure::LooseGrid => Ok(Box::new(
                LooseGrid::new().with_least_flight(least_flight).staggered(),
            )),
            Structure::Cells | Structure::Lists | Structure::Periodic => Err(
                "runs whole scenes, not inside a world; frames are drawn from a world (use \
                 --structure grid)",
            ),
        }
    }
}

impl std::fmt::Display for Structure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_match_the_structures_own() {
        for s in Structure::ALL {
            assert_eq!(Structure::from_name(s.name()), Some(s));
            for kind in [WorldKind::Free, WorldKind::Plane] {
                if let Ok(built) = s.build(kind, &[], 0.0) {
                    assert_eq!(built.name(), s.name(), "{s:?} in {kind:?}");
                }
            }
        }
        assert_eq!(Structure::from_name("loose"), None);
    }
}
