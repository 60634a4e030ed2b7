//! Hard-sphere systems, as event-driven molecular dynamics (DynamO, EDMD) benchmarks them: a
//! gas of equal spheres, or a binary mixture of large and small spheres with equal volume
//! fractions, at a packing fraction, inside walls or in a periodic box, with elastic response
//! and Maxwell-Boltzmann velocities at temperature 1.
//!
//! Units as DynamO's: the large spheres have diameter 1 and mass 1; a small sphere of diameter
//! `ratio` has mass `ratio^3` (the scene format's masses go as radius cubed); kT = 1.
//!
//! The start is non-overlapping. Up to [`RANDOM_MAX`]: random sequential placement, large
//! spheres first, with one cell grid per species, so building 256000 spheres is linear work.
//! Denser systems (up to [`PACKING_MAX`]), and any that random placement cannot fill, start
//! on a face-centred cubic lattice, the species
//! shuffled over its sites (with vacancies where `n` is not four times a cube), which the run
//! melts. Random centres are at least their radius inside the box, so spheres on opposite
//! faces of a periodic box do not overlap through it. The horizon is set from
//! Enskog's collision rate (with the Boublik-Mansoori-Carnahan-Starling-Leland contact
//! values) so that the run holds about the number of collisions asked for.

use glam::DVec3;
use kinetic_collide::scene::{Scene, SceneObject};
use kinetic_collide::spheres::PeriodicBox;
use kinetic_collide::{Response, Walls, WorldKind};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use std::f64::consts::PI;

/// The densest packing fraction placed at random: random sequential placement of equal spheres
/// jams near 0.38 and slows down well before (32000 spheres at 0.35 do not fit in a thousand
/// tries a sphere), and a mixture fills less easily. Denser systems start on a lattice, and
/// so does a system that random placement cannot fill.
pub const RANDOM_MAX: f64 = 0.3;

/// The densest packing fraction the generator accepts (fluids melt from a lattice start up to
/// about the freezing point, 0.494, and stay glassy or crystalline beyond).
pub const PACKING_MAX: f64 = 0.55;

/// A hard-sphere system.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HardSpheres {
    /// Number of spheres.
    pub n: usize,
    /// Small over large diameter, in (0, 1]; 1 is the monodisperse gas.
    pub ratio: f64,
    /// Fraction of the walls' box the spheres fill.
    pub packing: f64,
    /// About how many collisions the horizon should hold.
    pub collisions: f64,
    /// The random seed.
    pub seed: u64,
    /// A periodic box instead of walls.
    pub periodic: bool,
}

/// The most spheres a system may have: the scene's text takes about 150 bytes a sphere, so
/// 15 GB here, and a run needs about as much again.
pub const MAX_SPHERES: usize = 100_000_000;

/// What is wrong with a hard-sphere request.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum HardSpheresError {
    /// A parameter out of its range.
    #[error("{name}: {why} (got {value})")]
    Parameter {
        /// The parameter.
        name: &'static str,
        /// Its range.
        why: &'static str,
        /// What was given.
        value: f64,
    },
    /// The lattice start does not fit: its nearest sites are closer than a large diameter.
    #[error(
        "{n} spheres at packing {packing} do not fit a lattice start{}",
        if *packing > 0.5 { "" } else { " inside walls: use more spheres or a periodic box" }
    )]
    TooDense {
        /// Spheres asked for.
        n: usize,
        /// The packing fraction.
        packing: f64,
    },
}

/// One species of a system: how many, their diameter and mass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Species {
    /// Number of spheres.
    pub count: usize,
    /// Diameter.
    pub diameter: f64,
    /// Mass.
    pub mass: f64,
}

impl HardSpheres {
    /// The monodisperse gas of DynamO's benchmark: `n` spheres at packing fraction 0.26.
    pub fn gas(n: usize) -> HardSpheres {
        HardSpheres {
            n,
            ratio: 1.0,
            packing: 0.26,
            collisions: 1e6,
            seed: 1,
            periodic: false,
        }
    }

    /// A binary mixture with equal volume fractions at packing fraction 0.26.
    pub fn mixture(n: usize, ratio: f64) -> HardSpheres {
        HardSpheres {
            ratio,
            ..HardSpheres::gas(n)
        }
    }

    /// Checks the parameters.
    pub fn check(&self) -> Result<(), HardSpheresError> {
        let bad = |name, why, value| Err(HardSpheresError::Parameter { name, why, value });
        if self.n == 0 {
            return bad("n", "at least one sphere", 0.0);
        }
        if self.n > MAX_SPHERES {
            return bad(
                "n",
                "at most 100,000,000 spheres (the scene's text would not fit in memory)",
                self.n as f64,
            );
        }
        if !(self.ratio > 0.0 && self.ratio <= 1.0) {
            return bad("ratio", "small over large diameter, in (0, 1]", self.ratio);
        }
        if !(self.packing > 0.0 && self.packing <= PACKING_MAX) {
            return bad("packing", "in (0, 0.55]", self.packing);
        }
        if !(self.collisions.is_finite() && self.collisions > 0.0) {
            return bad("collisions", "finite and > 0", self.collisions);
        }
        Ok(())
    }

    /// The species, large first: one for the gas; for a mixture, large and small spheres in
    /// numbers that give them equal volumes (`n ratio^3 / (1 + ratio^3)` large, at least one).
    pub fn species(&self) -> Vec<Species> {
        if self.ratio == 1.0 {
            return vec![Species {
                count: self.n,
                diameter: 1.0,
                mass: 1.0,
            }];
        }
        let r3 = self.ratio.powi(3);
        let large = ((self.n as f64 * r3 / (1.0 + r3)).round() as usize).clamp(1, self.n);
        let mut species = vec![Species {
            count: large,
            diameter: 1.0,
            mass: 1.0,
        }];
        if self.n > large {
            species.push(Species {
                count: self.n - large,
                diameter: self.ratio,
                mass: r3,
            });
        }
        species
    }

    /// The side of the walls' cube: the spheres fill `packing` of it.
    pub fn side(&self) -> f64 {
        let volume: f64 = self
            .species()
            .iter()
            .map(|s| s.count as f64 * PI / 6.0 * s.diameter.powi(3))
            .sum();
        (volume / self.packing).cbrt()
    }

    /// Enskog's collision rate of the whole system (collisions per unit time) at kT = 1, with
    /// the BMCSL contact values of the pair distribution. Walls make the real rate a few per
    /// cent lower.
    pub fn collision_rate(&self) -> f64 {
        let species = self.species();
        let volume = self.side().powi(3);
        let density: Vec<f64> = species.iter().map(|s| s.count as f64 / volume).collect();
        let zeta = |k: i32| -> f64 {
            PI / 6.0
                * species
                    .iter()
                    .zip(&density)
                    .map(|(s, n)| n * s.diameter.powi(k))
                    .sum::<f64>()
        };
        let (z2, z3) = (zeta(2), zeta(3));
        let mut rate = 0.0;
        for (i, si) in species.iter().enumerate() {
            for (j, sj) in species.iter().enumerate().skip(i) {
                let s = si.diameter * sj.diameter / (si.diameter + sj.diameter);
                let g = 1.0 / (1.0 - z3)
                    + 3.0 * z2 * s / (1.0 - z3).powi(2)
                    + 2.0 * (z2 * s).powi(2) / (1.0 - z3).powi(3);
                let sigma = (si.diameter + sj.diameter) / 2.0;
                let mu = si.mass * sj.mass / (si.mass + sj.mass);
                let half = if i == j { 0.5 } else { 1.0 };
                rate += half
                    * density[i]
                    * density[j]
                    * sigma
                    * sigma
                    * g
                    * (8.0 * PI / mu).sqrt()
                    * volume;
            }
        }
        rate
    }

    /// The scene: walls (or a periodic box) from the origin to `side` on every axis, the
    /// spheres placed apart, velocities drawn from Maxwell-Boltzmann at kT = 1 (the whole
    /// system's momentum removed), and a horizon of about `collisions` collisions.
    pub fn build(&self) -> Result<Scene, HardSpheresError> {
        self.check()?;
        let side = self.side();
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        let species = self.species();
        let random = if self.packing <= RANDOM_MAX {
            self.random_start(&species, side, &mut rng)
        } else {
            None
        };
        let objects = match random {
            Some(objects) => objects,
            None => self.lattice_start(&species, side, &mut rng)?,
        };
        // No drift: the system's momentum is zero.
        let total_mass: f64 = objects.iter().map(|(m, _)| m).sum();
        let drift = objects.iter().map(|(m, o)| o.velocity * *m).sum::<DVec3>() / total_mass;
        let objects = objects
            .into_iter()
            .map(|(_, mut o)| {
                o.velocity -= drift;
                o
            })
            .collect();
        let bounds = (DVec3::ZERO, DVec3::splat(side));
        Ok(Scene {
            world: WorldKind::Free,
            horizon: self.collisions / self.collision_rate(),
            response: Response::Elastic,
            walls: (!self.periodic).then_some(Walls {
                min: bounds.0,
                max: bounds.1,
            }),
            periodic: self.periodic.then_some(PeriodicBox {
                min: bounds.0,
                max: bounds.1,
            }),
            objects,
        })
    }

    /// Random sequential placement, with each sphere's velocity drawn as it is placed; `None`
    /// when it gives up (the box is too full for a thousand tries a sphere).
    fn random_start(
        &self,
        species: &[Species],
        side: f64,
        rng: &mut ChaCha8Rng,
    ) -> Option<Vec<(f64, SceneObject)>> {
        let mut placer = Placer::new(species, side);
        let mut objects = Vec::with_capacity(self.n);
        let mut attempts = 0usize;
        for (k, s) in species.iter().enumerate() {
            let r = s.diameter / 2.0;
            let sd = s.mass.recip().sqrt();
            for _ in 0..s.count {
                let position = loop {
                    attempts += 1;
                    if attempts > 1000 * self.n + 100_000 {
                        return None;
                    }
                    let p = DVec3::new(
                        rng.random_range(r..side - r),
                        rng.random_range(r..side - r),
                        rng.random_range(r..side - r),
                    );
                    if placer.free(p, r) {
                        break p;
                    }
                };
                placer.add(k, position);
                let velocity = DVec3::new(
                    rng.sample::<f64, _>(StandardNormal),
                    rng.sample::<f64, _>(StandardNormal),
                    rng.sample::<f64, _>(StandardNormal),
                ) * sd;
                objects.push((s.mass, SceneObject::ball(r, position, velocity)));
            }
        }
        Some(objects)
    }

    /// A face-centred cubic lattice of `4 k^3 >= n` sites (`n` of them taken at random), the
    /// species shuffled over them; inside walls the lattice is drawn in by the largest radius
    /// so that every sphere starts inside.
    fn lattice_start(
        &self,
        species: &[Species],
        side: f64,
        rng: &mut ChaCha8Rng,
    ) -> Result<Vec<(f64, SceneObject)>, HardSpheresError> {
        let k = ((self.n as f64 / 4.0).cbrt().ceil() as usize).max(1);
        let r_max = species.iter().map(|s| s.diameter / 2.0).fold(0.0, f64::max);
        // Fractions of the span: a site at (i + o) / k, o in {1/4, 3/4}; inside walls mapped
        // onto [r_max, side - r_max].
        let (lo, span, cells) = if self.periodic {
            (0.0, side, k as f64)
        } else {
            (r_max, side - 2.0 * r_max, k as f64 - 0.5)
        };
        let cell = span / cells;
        let nearest = cell / 2f64.sqrt();
        if !(span > 0.0 && nearest >= 2.0 * r_max) {
            return Err(HardSpheresError::TooDense {
                n: self.n,
                packing: self.packing,
            });
        }
        let offset = if self.periodic { 0.0 } else { 0.25 };
        let mut sites = Vec::with_capacity(4 * k * k * k);
        for i in 0..k {
            for j in 0..k {
                for l in 0..k {
                    for o in [
                        [0.25, 0.25, 0.25],
                        [0.75, 0.75, 0.25],
                        [0.75, 0.25, 0.75],
                        [0.25, 0.75, 0.75],
                    ] {
                        let f = DVec3::new(i as f64 + o[0], j as f64 + o[1], l as f64 + o[2]);
                        sites.push(DVec3::splat(lo) + (f - offset) * cell);
                    }
                }
            }
        }
        // n sites at random, then the species in random order over them.
        for i in 0..self.n {
            let j = rng.random_range(i..sites.len());
            sites.swap(i, j);
        }
        sites.truncate(self.n);
        let mut kinds: Vec<usize> = species
            .iter()
            .enumerate()
            .flat_map(|(k, s)| std::iter::repeat_n(k, s.count))
            .collect();
        for i in (1..kinds.len()).rev() {
            let j = rng.random_range(0..=i);
            kinds.swap(i, j);
        }
        Ok(sites
            .into_iter()
            .zip(kinds)
            .map(|(p, k)| {
                let s = species[k];
                let sd = s.mass.recip().sqrt();
                let velocity = DVec3::new(
                    rng.sample::<f64, _>(StandardNormal),
                    rng.sample::<f64, _>(StandardNormal),
                    rng.sample::<f64, _>(StandardNormal),
                ) * sd;
                (s.mass, SceneObject::ball(s.diameter / 2.0, p, velocity))
            })
            .collect())
    }
}

/// Random sequential placement: one cell grid per species, cells at least as wide as its
/// diameter.
struct Placer {
    grids: Vec<Cells>,
}

struct Cells {
    radius: f64,
    cell: f64,
    per_axis: usize,
    cells: Vec<Vec<DVec3>>,
}

impl Cells {
    fn index(&self, c: [usize; 3]) -> usize {
        (c[2] * self.per_axis + c[1]) * self.per_axis + c[0]
    }

    fn cell_of(&self, x: f64) -> usize {
        ((x / self.cell).max(0.0) as usize).min(self.per_axis - 1)
    }
}

impl Placer {
    fn new(species: &[Species], side: f64) -> Placer {
        let grids = species
            .iter()
            .map(|s| {
                // Cells as wide as a diameter, but never many more cells than spheres: a
                // speck among large spheres would otherwise ask for a table of 1e18 cells.
                let most = (8.0 * s.count as f64).cbrt().ceil().max(1.0);
                let per_axis = (side / s.diameter).floor().clamp(1.0, most) as usize;
                Cells {
                    radius: s.diameter / 2.0,
                    cell: side / per_axis as f64,
                    per_axis,
                    cells: vec![Vec::new(); if s.count > 0 { per_axis.pow(3) } else { 0 }],
                }
            })
            .collect();
        Placer { grids }
    }

    /// Whether a sphere of radius `r` at `p` overlaps none placed so far.
    fn free(&self, p: DVec3, r: f64) -> bool {
        self.grids.iter().all(|g| {
            if g.cells.is_empty() {
                return true;
            }
            let reach = r + g.radius;
            let lo = [0, 1, 2].map(|k| g.cell_of(p[k] - reach));
            let hi = [0, 1, 2].map(|k| g.cell_of(p[k] + reach));
            (lo[2]..=hi[2]).all(|z| {
                (lo[1]..=hi[1]).all(|y| {
                    (lo[0]..=hi[0]).all(|x| {
                        g.cells[g.index([x, y, z])]
                            .iter()
                            .all(|q| (*q - p).length_squared() >= reach * reach)
                    })
                })
            })
        })
    }

    fn add(&mut self, species: usize, p: DVec3) {
        let g = &mut self.grids[species];
        let c = [0, 1, 2].map(|k| g.cell_of(p[k]));
        let i = g.index(c);
        g.cells[i].push(p);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mixture_counts_match_dynamo_benchmark() {
        let s = HardSpheres::mixture(32000, 0.1).species();
        assert_eq!((s[0].count, s[1].count), (32, 31968));
        let s = HardSpheres::mixture(4000, 0.5).species();
        assert_eq!((s[0].count, s[1].count), (444, 3556));
        assert_eq!(HardSpheres::gas(4000).species().len(), 1);
    }

    #[test]
    fn packing_and_enskog_rate_of_the_gas() {
        let h = HardSpheres::gas(4000);
        let v = 4000.0 * PI / 6.0;
        assert!((v / h.side().powi(3) - 0.26).abs() < 1e-12);
        // Per sphere: 4 n sigma^2 g sqrt(pi kT / m), g from Carnahan-Starling.
        let n = 4000.0 / h.side().powi(3);
        let g = (1.0 - 0.13) / (1.0f64 - 0.26).powi(3);
        let per_sphere = 4.0 * n * g * PI.sqrt();
        let rate = h.collision_rate();
        assert!(
            (rate - per_sphere * 4000.0 / 2.0).abs() < 1e-9 * rate,
            "{rate}"
        );
    }

    #[test]
    fn spheres_start_apart_inside_the_walls_with_no_drift() {
        for ratio in [1.0, 0.5, 0.2] {
            let h = HardSpheres {
                n: 2000,
                ..HardSpheres::mixture(2000, ratio)
            };
            let scene = h.build().unwrap();
            let side = h.side();
            let balls: Vec<(DVec3, f64)> = scene
                .objects
                .iter()
                .map(|o| (o.position, kinetic_collide::scene::outer_radius(&o.shape)))
                .collect();
            for (i, &(p, r)) in balls.iter().enumerate() {
                assert!((0..3).all(|k| p[k] >= r && p[k] <= side - r));
                for &(q, s) in &balls[i + 1..] {
                    assert!((p - q).length() >= r + s, "overlap at ratio {ratio}");
                }
            }
            let momentum: DVec3 = scene
                .objects
                .iter()
                .map(|o| o.velocity * kinetic_collide::scene::outer_radius(&o.shape).powi(3))
                .sum();
            assert!(momentum.length() < 1e-9, "{momentum}");
            // Temperature about 1: the mean of m v^2 / 3.
            let kt: f64 = scene
                .objects
                .iter()
                .map(|o| {
                    let m = (2.0 * kinetic_collide::scene::outer_radius(&o.shape)).powi(3);
                    m * o.velocity.length_squared() / 3.0
                })
                .sum::<f64>()
                / 2000.0;
            assert!((kt - 1.0).abs() < 0.1, "kT {kt} at ratio {ratio}");
        }
    }

    #[test]
    fn dense_starts_are_apart_through_periodic_faces_and_inside_walls() {
        for (periodic, ratio, packing, n) in [
            (true, 1.0, 0.55, 500),
            (true, 0.8, 0.5, 864),
            (false, 1.0, 0.45, 4000),
            (true, 1.0, 0.3, 400),
            (true, 1.0, 0.35, 4000),
        ] {
            let h = HardSpheres {
                n,
                packing,
                periodic,
                ..HardSpheres::mixture(n, ratio)
            };
            let scene = h.build().unwrap();
            assert_eq!(scene.objects.len(), n);
            assert_eq!(
                (scene.periodic.is_some(), scene.walls.is_none()),
                (periodic, periodic)
            );
            let side = h.side();
            let balls: Vec<(DVec3, f64)> = scene
                .objects
                .iter()
                .map(|o| (o.position, kinetic_collide::scene::outer_radius(&o.shape)))
                .collect();
            let filled: f64 = balls.iter().map(|b| 4.0 / 3.0 * PI * b.1.powi(3)).sum();
            assert!((filled / side.powi(3) - packing).abs() < 1e-9);
            for (i, &(p, r)) in balls.iter().enumerate() {
                if periodic {
                    assert!((0..3).all(|k| p[k] >= 0.0 && p[k] <= side));
                } else {
                    assert!((0..3).all(|k| p[k] >= r && p[k] <= side - r));
                }
                for &(q, s) in &balls[i + 1..] {
                    let mut d = p - q;
                    if periodic {
                        d -= (d / side).round() * side;
                    }
                    assert!(
                        d.length() >= (r + s) * (1.0 - 1e-12),
                        "overlap at {packing}"
                    );
                }
            }
        }
        // Too dense for a lattice inside walls with few spheres, or beyond the range.
        let e = HardSpheres {
            packing: 0.55,
            ..HardSpheres::gas(4)
        }
        .build()
        .unwrap_err();
        assert!(e.to_string().contains("lattice"), "{e}");
    }

    #[test]
    fn bad_parameters_are_named() {
        let e = HardSpheres {
            ratio: 0.0,
            ..HardSpheres::gas(10)
        }
        .build()
        .unwrap_err();
        assert!(e.to_string().starts_with("ratio:"), "{e}");
        let e = HardSpheres {
            packing: 0.6,
            ..HardSpheres::gas(10)
        }
        .build()
        .unwrap_err();
        assert!(e.to_string().starts_with("packing:"), "{e}");
    }
}
