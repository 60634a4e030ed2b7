//! Building the simulation: checking the box and the spheres, ordering spheres along a
//! Z-curve of cells, listing neighbours and predicting every sphere's first event.

use super::calendar::Calendar;
use super::grid::CentreGrid;
use super::lists::Lists;
use super::runners::SavedRunners;
use super::{ListCentre, ListedSpheres, NEIGHBOURS, Period, PeriodicBox, SHELL, SLACK};
use crate::bulk::{Sums, mass};
use kinetic_core::FlightPlan;
use kinetic_core::elastic::Motion;
use kinetic_core::elastic::ZenoGuard;
use kinetic_core::{MAX_MAGNITUDE, Stats, Walls, WorldError};
use kinetic_core::{Real, Vec3};
use rustc_hash::FxHashMap;

/// Interleaves the low 21 bits of three cell coordinates (a Z-curve key).
fn z_key(c: [u32; 3]) -> u64 {
    let spread = |x: u32| {
        let mut x = u64::from(x) & 0x1f_ffff;
        x = (x | x << 32) & 0x1f_0000_0000_ffff;
        x = (x | x << 16) & 0x1f_0000_ff00_00ff;
        x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
        x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
        (x | x << 2) & 0x1249_2492_4924_9249
    };
    spread(c[0]) | spread(c[1]) << 1 | spread(c[2]) << 2
}

fn invalid(what: String) -> WorldError {
    WorldError::InvalidShape(what)
}

impl ListedSpheres {
    /// The shell factor for spheres filling a share `packing` of a box of `side`, the
    /// largest of radius `r_max`: the factor at which a sphere lists about [`NEIGHBOURS`]
    /// others (equal spheres list `8 packing shell^3`), within [`SHELL`], or, in a periodic
    /// box, less where the box is small, so that it is three list reaches wide; `None` when
    /// the box is too small even for a thin shell.
    fn shell_factor(side: Vec3, r_max: Real, packing: Real, periodic: bool) -> Option<Real> {
        let fit = if periodic {
            side.min_element() / (3.0 * 2.0 * r_max * (1.0 + 1e-6))
        } else {
            Real::INFINITY
        };
        let wanted = (NEIGHBOURS / (8.0 * packing)).cbrt();
        let shell = if wanted.is_finite() {
            wanted.clamp(SHELL.0, SHELL.1)
        } else {
            SHELL.1
        };
        let shell = shell.min(fit);
        (shell >= 1.01).then_some(shell)
    }

    /// Elastic spheres `(radius, plan)` in the periodic box `cell`: the sphere with index `i`
    /// gets id `i`. Plans must be linear (no acceleration), start inside the box, and the
    /// box must be at least about 3.1 largest diameters wide along each axis.
    pub fn periodic(cell: PeriodicBox, spheres: &[(Real, FlightPlan)]) -> Result<Self, WorldError> {
        Self::build(Period::of(&cell), None, spheres)
    }

    /// Elastic spheres `(radius, plan)` inside `walls`, bouncing off them as the world's
    /// balls do: the sphere with index `i` gets id `i`. Plans must be linear (no
    /// acceleration), and each sphere must start inside the walls. Spheres of similar sizes
    /// suit it (each lists the spheres within a reach set by the largest); for sizes spread
    /// widely, [`crate::ElasticCells`] keeps one grid level per size.
    pub fn in_walls(walls: Walls, spheres: &[(Real, FlightPlan)]) -> Result<Self, WorldError> {
        let side = walls.max - walls.min;
        if !(side.is_finite() && side.min_element() > 0.0) || side.max_element() > MAX_MAGNITUDE {
            return Err(invalid(format!(
                "walls: max {:?} must be above min {:?}, both finite",
                walls.max, walls.min
            )));
        }
        for (i, (r, plan)) in spheres.iter().enumerate() {
            let p = plan.position_at(plan.t0);
            if r.is_finite()
                && !((p - *r).cmpge(walls.min).all() && (p + *r).cmple(walls.max).all())
            {
                return Err(invalid(format!(
                    "object {i}: ball at {p:?} of radius {r} is not inside the walls"
                )));
            }
        }
        Self::build(Period::none(walls.min, walls.max), Some(walls), spheres)
    }

    fn build(
        period: Period,
        walls: Option<Walls>,
        spheres: &[(Real, FlightPlan)],
    ) -> Result<Self, WorldError> {
        let what = if walls.is_some() {
            "walls"
        } else {
            "periodic box"
        };
        let cell = PeriodicBox {
            min: period.min,
            max: period.min + period.side,
        };
        let side = period.side;
        if !(side.is_finite() && side.min_element() > 0.0) || side.max_element() > MAX_MAGNITUDE {
            return Err(invalid(format!(
                "periodic box: max {:?} must be above min {:?}, both finite",
                cell.max, cell.min
            )));
        }
        if spheres.len() >= (1 << 31) {
            return Err(invalid(format!("{what}: at most 2^31 spheres")));
        }
        let mut r_max: Real = 0.0;
        for (i, (r, plan)) in spheres.iter().enumerate() {
            if !(r.is_finite() && *r > 0.0) {
                return Err(invalid(format!("object {i}: radius {r} must be positive")));
            }
            if !plan.is_finite() || plan.acceleration != Vec3::ZERO {
                return Err(invalid(format!(
                    "object {i}: the {what} takes spheres moving linearly (finite, no acceleration)"
                )));
            }
            let p = plan.position_at(0.0);
            if walls.is_none() && !(p.cmpge(cell.min).all() && p.cmple(cell.max).all()) {
                return Err(invalid(format!(
                    "object {i}: centre {p:?} is outside the periodic box"
                )));
            }
            r_max = r_max.max(*r);
        }
        let filled: Real = spheres
            .iter()
            .map(|(r, _)| 4.0 / 3.0 * std::f64::consts::PI * r * r * r)
            .sum();
        let packing = filled / (side.x * side.y * side.z);
        let shell = if spheres.is_empty() {
            SHELL.0
        } else {
            Self::shell_factor(side, r_max, packing, walls.is_none()).ok_or_else(|| {
                invalid(format!(
                    "periodic box: each side must be at least {:.4} (3.03 largest diameters), got {side:?}",
                    6.06 * r_max
                ))
            })?
        };
        let n = spheres.len();
        let reach = shell * 2.0 * r_max * (1.0 + SLACK);
        let mut grid = CentreGrid::new(
            n,
            cell.min,
            side,
            reach.max(Real::MIN_POSITIVE),
            walls.is_none(),
        );
        // Memory order: by Z-curve of the starting cell, so neighbours sit close.
        let mut order: Vec<(u64, u32)> = spheres
            .iter()
            .enumerate()
            .map(|(i, (_, p))| (z_key(grid.cell(p.position_at(0.0))), i as u32))
            .collect();
        order.sort_unstable();
        let ext: Vec<u32> = order.iter().map(|&(_, i)| i).collect();
        let motion: Vec<Motion> = ext
            .iter()
            .map(|&e| {
                let (r, p) = &spheres[e as usize];
                Motion::of(p, *r)
            })
            .collect();
        let two_kinetic = motion
            .iter()
            .map(|m| mass(m.radius) * m.velocity.length_squared())
            .sum();
        let centre: Vec<ListCentre> = motion
            .iter()
            .map(|m| ListCentre {
                at: m.at(0.0),
                shell: (shell - 1.0) * m.radius * (1.0 - SLACK),
            })
            .collect();
        for (i, c) in centre.iter().enumerate() {
            grid.insert(i as u32, c.at, motion[i].radius);
        }
        let mut gas = ListedSpheres {
            now: 0.0,
            period,
            walls,
            wall: vec![None; n],
            ext,
            motion,
            counter: vec![0; n],
            centre,
            lists: Lists::new(n, 16),
            grid,
            queue: Calendar::new(n, 1.0, 1, 0.0),
            spares: vec![SavedRunners::NONE; n],
            skips: FxHashMap::default(),
            events: Vec::new(),
            stats: Stats::default(),
            sums: Sums::default(),
            two_kinetic,
            zeno: ZenoGuard::default(),
            list_factor: shell * (1.0 + SLACK),
            event_counts: [0; 5],
            spare_counts: [0; 2],
            sifted: None,
            #[cfg(target_arch = "x86_64")]
            wide: std::arch::is_x86_feature_detected!("avx"),
            found: Vec::new(),
        };
        gas.list_all();
        for id in 0..n as u32 {
            gas.wall[id as usize] = gas.wall_kept(id);
        }
        // The first events, then a calendar whose buckets hold a few dozen events each.
        let mut sum = 0.0;
        let mut finite = 0usize;
        for id in 0..n as u32 {
            gas.predict(id);
            let t = gas.queue.get(id).map_or(Real::INFINITY, |e| e.0);
            if t.is_finite() {
                sum += t;
                finite += 1;
            }
        }
        let mean = if finite > 0 {
            sum / finite as Real
        } else {
            1.0
        };
        let width = 32.0 * mean / n.max(1) as Real;
        let buckets = (8.0 * mean / width).ceil().clamp(1.0, 1e7) as usize;
        let mut queue = Calendar::new(n, width, buckets, 0.0);
        for id in 0..n as u32 {
            if let Some((time, tie, scheduled)) = gas.queue.get(id)
                && time.is_finite()
            {
                queue.schedule(id, time, tie, scheduled);
            }
        }
        gas.queue = queue;
        Ok(gas)
    }

    /// Lists every pair whose centres are within the list reach.
    fn list_all(&mut self) {
        let mut found = std::mem::take(&mut self.found);
        for i in 0..self.len() as u32 {
            let (centre, radius) = (self.centre[i as usize].at, self.motion[i as usize].radius);
            self.grid.near(centre, radius, self.list_factor, &mut found);
            for &k in &found {
                if k > i {
                    self.lists.push(i, k);
                    self.lists.push(k, i);
                }
            }
        }
        self.found = found;
    }

    /// Where sphere `id`'s new list centre goes: ahead of it along its flight by about a mean
    /// free path (the fluid's mean free time at the sphere's speed), at most half its shell.
    /// The sphere first flies towards the centre and past it, so it stays within its shell
    /// longer than from a centre where it is: in a thin fluid, where a sphere crosses its
    /// shell after a few flights, a fifth fewer shell crossings.
    pub(super) fn new_centre(&self, id: u32) -> Vec3 {
        let i = id as usize;
        let m = &self.motion[i];
        let here = m.at(self.now);
        let speed = m.velocity.length();
        let collisions = self.event_counts[0];
        if speed == 0.0 || collisions == 0 {
            return here;
        }
        let free_time = self.now * self.len() as Real / (2.0 * collisions as Real);
        let ahead = free_time.min(0.5 * self.centre[i].shell / speed);
        if ahead.is_finite() && ahead > 0.0 {
            here + m.velocity * ahead
        } else {
            here
        }
    }

    /// Sphere `id` reached its shell: it re-centres ahead of where it is and lists again.
    /// Most of its neighbours stay: only those that leave or join change their rows (a stamp
    /// per sphere says which were listed), and its own row is written afresh.
    pub(super) fn relist(&mut self, id: u32) {
        let i = id as usize;
        let (was, kept) = self.lists.stamps(id);
        self.centre[i].at = self.new_centre(id);
        self.grid.remove(id);
        let (centre, radius) = (self.centre[i].at, self.motion[i].radius);
        let mut found = std::mem::take(&mut self.found);
        self.grid.near(centre, radius, self.list_factor, &mut found);
        self.lists.clear(id);
        for &k in &found {
            self.lists.push(id, k);
            if !self.lists.restamp(k, was, kept) {
                self.lists.push(k, id);
            }
        }
        self.found = found;
        // The old neighbours still stamped as listed left.
        self.lists.drop_left(id, was);
        self.grid.insert(id, centre, radius);
    }
}
