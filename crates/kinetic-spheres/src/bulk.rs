//! Bulk figures of a hard-sphere run (collision rate, temperature, pressure), summed as the
//! run goes by the neighbour lists and the cell grid alike. Masses are `(2 r)^3`: a sphere of
//! diameter 1 has mass 1.

use kinetic_core::{Real, Vec3};

/// Bulk figures of a run: collision rate, temperature and pressure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bulk {
    /// Collisions per sphere per unit time.
    pub collision_rate: Real,
    /// `kT`: twice the kinetic energy per sphere over three (mass `(2 r)^3`).
    pub temperature: Real,
    /// Pressure: in a periodic box from the collision virial, `(N kT + W / (3 t)) / V`; inside
    /// walls the impulse the walls gave per unit of their area and of time.
    pub pressure: Real,
    /// `P V / (N kT)`.
    pub compressibility: Real,
    /// Fraction of the box the spheres fill.
    pub packing: Real,
}

/// The mass of a sphere of radius `radius`.
pub(crate) fn mass(radius: Real) -> Real {
    (2.0 * radius).powi(3)
}

/// The volume of a sphere of radius `radius`.
pub(crate) fn ball_volume(radius: Real) -> Real {
    4.0 / 3.0 * std::f64::consts::PI * radius.powi(3)
}

/// What a run sums for its bulk figures from a start time.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Sums {
    /// The time the sums start from.
    pub(crate) start: Real,
    /// Collisions (pairs whose velocities were exchanged).
    pub(crate) collisions: u64,
    /// The sum over collisions of `r_ab . dp_a` (contact vector times impulse): the collision
    /// virial.
    pub(crate) virial: Real,
    /// The impulse the walls gave, summed over their contacts.
    pub(crate) wall_impulse: Real,
}

impl Sums {
    /// Sums starting at `start`, empty.
    pub(crate) fn from(start: Real) -> Sums {
        Sums {
            start,
            ..Sums::default()
        }
    }

    /// The figures at `now` of `n` spheres of twice kinetic energy `two_kinetic` filling
    /// `filled` of a box of sides `side`: inside walls (`walls`) the pressure is the impulse
    /// the walls gave per unit of their area and of time, in a periodic box the virial's.
    pub(crate) fn figures(
        &self,
        now: Real,
        n: usize,
        two_kinetic: Real,
        side: Vec3,
        walls: bool,
        filled: Real,
    ) -> Bulk {
        let n = n.max(1) as Real;
        let volume = side.x * side.y * side.z;
        let elapsed = now - self.start;
        let kt = two_kinetic / (3.0 * n);
        let per_time = if elapsed > 0.0 { 1.0 / elapsed } else { 0.0 };
        let pressure = if walls {
            let area = 2.0 * (side.x * side.y + side.y * side.z + side.z * side.x);
            self.wall_impulse * per_time / area
        } else {
            (n * kt + self.virial * per_time / 3.0) / volume
        };
        Bulk {
            collision_rate: 2.0 * self.collisions as Real * per_time / n,
            temperature: kt,
            pressure,
            compressibility: if kt > 0.0 {
                pressure * volume / (n * kt)
            } else {
                1.0
            },
            packing: filled / volume,
        }
    }
}
