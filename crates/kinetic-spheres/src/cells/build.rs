//! Building the grid: its levels and cells for the balls given, and the balls in them.

use super::{BLOCK_CELLS_PER_BALL, CELLS_MIN, CELLS_PER_BALL, LEVEL_FACTOR};
use super::{ElasticCells, Layout, Level, NIL, Next, WIDEN};
use crate::bulk::{Sums, mass};
use kinetic_core::FlightPlan;
use kinetic_core::elastic::Motion;
use kinetic_core::elastic::ZenoGuard;
use kinetic_core::kds::EventQueue;
use kinetic_core::{Real, Vec3};
use kinetic_core::{Stats, Walls, WorldError};
use rustc_hash::FxHashMap;

/// The low 21 bits of `x`, spread to every third bit (one axis of a Z-curve key).
fn spread_bits(x: u64) -> u64 {
    let mut x = x & 0x1f_ffff;
    x = (x | x << 32) & 0x1f_0000_0000_ffff;
    x = (x | x << 16) & 0x1f_0000_ff00_00ff;
    x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
    x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
    x = (x | x << 2) & 0x1249_2492_4924_9249;
    x
}

impl ElasticCells {
    /// Whether balls of these radii (all moving linearly) inside `walls` fit the grid: a
    /// bounded number of cells and of block cells per ball.
    pub fn supports(walls: &Walls, radii: &[Real]) -> bool {
        Self::layout(walls, radii).is_some()
    }

    /// The levels' largest radii and cell counts, and each ball's level, or `None` when the
    /// grid would be too large.
    fn layout(walls: &Walls, radii: &[Real]) -> Option<Layout> {
        let mut sorted: Vec<Real> = radii.to_vec();
        if sorted.is_empty() || !sorted.iter().all(|r| r.is_finite() && *r > 0.0) {
            return None;
        }
        sorted.sort_by(Real::total_cmp);
        // Bands of diameters: each starts at its smallest and holds those below twice that.
        let mut bands: Vec<(Real, Real)> = Vec::new();
        for &r in &sorted {
            match bands.last_mut() {
                Some((lo, hi)) if r < *lo * LEVEL_FACTOR => *hi = r,
                _ => bands.push((r, r)),
            }
        }
        if bands.len() > 255 {
            return None;
        }
        let side = walls.max - walls.min;
        let mut levels = Vec::with_capacity(bands.len());
        let mut total: usize = 0;
        for &(_, r_max) in &bands {
            let width = 2.0 * r_max * (1.0 + WIDEN);
            let mut n = [1u32; 3];
            for k in 0..3 {
                let cells = (side[k] / width).floor();
                if !(cells.is_finite()) || cells > 1e6 {
                    return None;
                }
                n[k] = (cells as u32).max(1);
            }
            total = total.saturating_add(n.iter().map(|&c| c as usize).product());
            levels.push((r_max, n));
        }
        if total > CELLS_MIN.max(CELLS_PER_BALL * radii.len()) {
            return None;
        }
        let level: Vec<u8> = radii
            .iter()
            .map(|r| bands.iter().position(|&(_, hi)| *r <= hi).unwrap_or(0) as u8)
            .collect();
        // Block cells: each ball at each finer level.
        let mut block_cells = 0.0;
        for (&r, &l) in radii.iter().zip(&level) {
            for &(r_fine, n) in levels.iter().take(l as usize) {
                let reach = 2.0 * (r + r_fine) * (1.0 + WIDEN);
                block_cells += (0..3)
                    .map(|k| ((reach / (side[k] / n[k] as Real)).ceil() + 1.0).min(n[k] as Real))
                    .product::<Real>();
            }
        }
        if block_cells > BLOCK_CELLS_PER_BALL * radii.len() as Real + 1e6 {
            return None;
        }
        Some((levels, level))
    }

    /// The balls `(radius, plan)` inside `walls`, ids in order, at time 0 (each plan's state
    /// at its `t0` extrapolated). Every ball moves linearly and starts inside the walls.
    pub fn new(walls: Walls, balls: &[(Real, FlightPlan)]) -> Result<ElasticCells, WorldError> {
        if !(0..3).all(|k| walls.min[k].is_finite() && walls.max[k].is_finite())
            || !(0..3).all(|k| walls.min[k] < walls.max[k])
        {
            return Err(WorldError::InvalidWalls);
        }
        for (i, (r, plan)) in balls.iter().enumerate() {
            let object = i as u32;
            if !(r.is_finite() && *r > 0.0) {
                return Err(WorldError::InvalidRadius { object, value: *r });
            }
            if !plan.is_finite() {
                return Err(WorldError::NonFinitePlan { object });
            }
            if plan.acceleration != Vec3::ZERO {
                return Err(WorldError::UnsupportedShape {
                    object,
                    why: "the cell grid holds balls moving linearly (no acceleration)",
                });
            }
            let p = plan.position_at(0.0);
            if !(0..3).all(|k| p[k] - r >= walls.min[k] && p[k] + r <= walls.max[k]) {
                return Err(WorldError::OutsideWalls { object });
            }
        }
        let radii: Vec<Real> = balls.iter().map(|b| b.0).collect();
        let Some((layout, level)) = Self::layout(&walls, &radii) else {
            return Err(WorldError::UnsupportedShape {
                object: 0,
                why: "the cell grid for these sizes and walls would be too large",
            });
        };
        let side = walls.max - walls.min;
        let levels: Vec<Level> = layout
            .iter()
            .map(|&(r_max, n)| Level {
                n,
                cell: Vec3::new(
                    side.x / n[0] as Real,
                    side.y / n[1] as Real,
                    side.z / n[2] as Real,
                ),
                r_max,
                head: vec![NIL; n.iter().map(|&c| c as usize).product()],
                visitors: FxHashMap::default(),
            })
            .collect();
        let count = balls.len();
        // Balls are held in the order of their cells along a Z curve at the finest level, so
        // that neighbours sit close in memory; ties and the log use the balls' own ids.
        let finest = &levels[0];
        let z_key = |p: Vec3| -> u64 {
            (0..3).fold(0, |key, k| {
                let c = ((p[k] - walls.min[k]) / finest.cell[k]).floor();
                let c = if c > 0.0 {
                    (c as u64).min(u64::from(finest.n[k] - 1))
                } else {
                    0
                };
                key | spread_bits(c) << k
            })
        };
        let mut ext: Vec<u32> = (0..count as u32).collect();
        ext.sort_by_cached_key(|&e| (z_key(balls[e as usize].1.position_at(0.0)), e));
        let mut int = vec![0; count];
        for (i, &e) in ext.iter().enumerate() {
            int[e as usize] = i as u32;
        }
        let mut cells = ElasticCells {
            now: 0.0,
            walls,
            plans: ext.iter().map(|&e| balls[e as usize].1).collect(),
            motion: ext
                .iter()
                .map(|&e| Motion::of(&balls[e as usize].1, radii[e as usize]))
                .collect(),
            radius: ext.iter().map(|&e| radii[e as usize]).collect(),
            level: ext.iter().map(|&e| level[e as usize]).collect(),
            ext,
            int,
            counter: vec![0; count],
            home: vec![[0; 3]; count],
            link: vec![[NIL; 2]; count],
            blocks: vec![Vec::new(); count],
            wall: vec![None; count],
            skips: vec![Vec::new(); count],
            next: vec![Next::IDLE; count],
            pair_next: vec![[Next::IDLE; 2]; count],
            queue: EventQueue::with_capacity(count),
            levels,
            events: Vec::new(),
            stats: Stats::default(),
            sums: Sums::default(),
            two_kinetic: balls
                .iter()
                .map(|(r, p)| mass(*r) * p.velocity_at(0.0).length_squared())
                .sum(),
            zeno: ZenoGuard::default(),
            neighbour_buffer: Vec::new(),
        };
        for id in 0..count as u32 {
            let home = cells.home_of(id);
            cells.home[id as usize] = home;
            cells.link_in(id);
            let blocks = (0..cells.level[id as usize])
                .map(|l| cells.block_of(id, l))
                .collect::<Vec<_>>();
            for b in &blocks {
                cells.visit(id, b, true);
            }
            cells.blocks[id as usize] = blocks;
        }
        for id in 0..count as u32 {
            cells.wall[id as usize] = cells.wall_from_plan(id);
            cells.predict(id, false);
        }
        cells.sample();
        Ok(cells)
    }
}
