//! The one home of the structure choice: every structure once ([`Structure`]: its name, what
//! it applies to, how it is built), the default a scene starts on ([`Structure::for_scene`])
//! and the one a [`crate::World`] starts with ([`Auto`]), the cost model behind both, whose
//! fitted constants stay private here, the estimates of a build from samples, and the race that measures the shortlist as a run goes
//! ([`Race`]) and settles the choice. The command-line tool, `compare`, the library's scene
//! runner, `World::new` and the benches all go through it.

mod auto;
mod build_estimate;
mod cost;
mod race;
mod registry;
mod scene_measures;
mod scene_world;

pub(crate) use auto::Auto;
pub(crate) use build_estimate::build_cost;
pub use race::Slice;
pub(crate) use race::{BRUTE_FORCE_TRIAL_MAX, Race};
pub(crate) use registry::FLIGHT_PARTS;
pub use registry::Structure;
pub(crate) use scene_world::{cell_balls, listed_balls, periodic_balls};
