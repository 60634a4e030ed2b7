//! Choosing the structure for a set of free-flying objects ("model no more than a scene
//! needs"): the sweep while sizes are similar, guards when they are not.

use crate::shape::fatness;
use kinetic_core::{Real, Shape};

/// The largest scale factor (ratio of inner radii) for which the sweep is chosen.
pub const SIGMA_MAX: Real = 8.0;

/// The largest fatness the guard grids are built for: objects fatter than this (or than the
/// fattest object, if less) are paired with every object instead of guarded. A grid for
/// fatness rho has about (sqrt 3 (rho + 1)^2)^3 guards per object, so this caps the grid at
/// 44 planes per axis.
pub const RHO_MAX: Real = 4.0;

/// A structure for free-flying objects.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
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

/// The scale factor sigma: largest over smallest inner radius (1 for fewer than two objects;
/// objects whose centre is not inside them are left out).
pub fn scale_factor<'a>(shapes: impl IntoIterator<Item = &'a Shape>) -> Real {
    let (lo, hi) = shapes
        .into_iter()
        .map(Shape::inner_radius)
        .filter(|&r| r > 0.0)
        .fold((Real::INFINITY, 0.0 as Real), |(lo, hi), r| {
            (lo.min(r), hi.max(r))
        });
    if hi > 0.0 { hi / lo } else { 1.0 }
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

/// The sweep when the scale factor is at most [`SIGMA_MAX`], guards otherwise.
pub fn choose<'a>(shapes: impl IntoIterator<Item = &'a Shape>) -> Choice {
    if scale_factor(shapes) <= SIGMA_MAX {
        Choice::Sweep
    } else {
        Choice::Guards
    }
}
