//! The audit: every invariant of the grid recomputed from scratch.

use super::visitors::Cell;
use super::{CellKey, Grid, HYSTERESIS, HYSTERESIS_ABS, Track};
use kinetic_core::Real;
use kinetic_core::kds::{Bodies, ScalarKey, ordered_pair};
use rustc_hash::FxHashMap;

/// Every listing of the cells `cells` as `(cell, object) -> whether an owner`; an error
/// (prefixed `name`) for an empty cell kept or an object listed twice in one cell.
fn cell_listings(
    cells: &FxHashMap<CellKey, Cell>,
    name: &str,
) -> Result<FxHashMap<(CellKey, u32), bool>, String> {
    let mut listed = FxHashMap::default();
    for (key, cell) in cells {
        if cell.owners.is_empty() && cell.visitors.is_empty() {
            return Err(format!("{name}: empty cell {key:?} kept"));
        }
        let owners = cell.owners.iter().map(|&id| (id, true));
        for (id, owner) in owners.chain(cell.visitors.iter().map(|&id| (id, false))) {
            if listed.insert((*key, id), owner).is_some() {
                return Err(format!("{name}: object {id} twice in cell {key:?}"));
            }
        }
    }
    Ok(listed)
}

impl Grid {
    /// Recomputes the invariants from scratch ([`kinetic_core::CandidateStructure::validate`]).
    pub(super) fn check(&self, bodies: &Bodies, now: Real) -> Result<(), String> {
        self.crossings_queue.validate()?;
        self.pairs_queue.validate()?;
        let own: usize = self
            .members
            .iter()
            .flatten()
            .flat_map(|m| &m.tracks)
            .map(|t| t.own())
            .sum();
        if own != self.own_tracks {
            return Err(format!(
                "grid: {own} own tracks, counted {} as they came and went",
                self.own_tracks
            ));
        }
        let at = |key: &ScalarKey| key.value_at(now);
        let listed = cell_listings(&self.cells, "grid")?;
        let mut covered = 0usize;
        let mut keys = Vec::new();
        for (id, m) in self.members.iter().enumerate() {
            let Some(m) = m else { continue };
            let id = id as u32;
            if bodies.get(id as usize).is_none_or(Option::is_none) {
                return Err(format!("grid: object {id} held but not live"));
            }
            let want = self.make_member(bodies, id);
            if want.level != m.level {
                return Err(format!(
                    "grid: object {id} at level {}, box says {}",
                    m.level, want.level
                ));
            }
            let listed_fast = self.fast.iter().filter(|&&f| f == id).count();
            if let Some((rlo, rhi)) = m.region {
                if listed_fast != 1 || !m.tracks.is_empty() {
                    return Err(format!(
                        "grid: fast object {id} listed {listed_fast} times, with {} tracks",
                        m.tracks.len()
                    ));
                }
                for k in 0..3 {
                    let (lo, hi) = (at(&m.lo[k]), at(&m.hi[k]));
                    let tol = 1e-9 * (m.width + lo.abs() + hi.abs());
                    if lo < rlo[k] - tol || hi > rhi[k] + tol {
                        return Err(format!(
                            "grid: fast object {id} axis {k}: box [{lo}, {hi}] out of its region [{}, {}]",
                            rlo[k], rhi[k]
                        ));
                    }
                }
                continue;
            }
            if listed_fast != 0 {
                return Err(format!("grid: object {id} in cells but listed fast"));
            }
            let levels: Vec<i32> = self.occupied.range(m.level..).copied().collect();
            let have: Vec<i32> = m.tracks.iter().map(|t| t.level).collect();
            if levels != have {
                return Err(format!(
                    "grid: object {id} tracks levels {have:?}, not {levels:?}"
                ));
            }
            for t in &m.tracks {
                let shift = self.shift_to(m.level, t.level);
                if t.shift != shift
                    || shift.is_some_and(|s| t.cells != Track::derived(&m.tracks[0], 0, s).cells)
                {
                    return Err(format!(
                        "grid: object {id} at level {}: derived {:?}, should be {shift:?} from its own cells",
                        t.level, t.shift
                    ));
                }
                let s = self.cell_size(t.level);
                for k in 0..3 {
                    let [a, b] = t.cells[k];
                    let (lo, hi) = (at(&m.lo[k]), at(&m.hi[k]));
                    let tol = 1e-9 * (s + lo.abs() + hi.abs());
                    let slack = HYSTERESIS * s + HYSTERESIS_ABS * (lo.abs() + hi.abs()) + tol;
                    if a > b
                        || lo < s * a as Real - tol
                        || hi > s * (b + 1) as Real + tol
                        || (a < b && lo > s * (a + 1) as Real + slack)
                        || (a < b && hi < s * b as Real - slack)
                    {
                        return Err(format!(
                            "grid: object {id} at level {} axis {k}: cells {a}..={b} of side {s} for box [{lo}, {hi}]",
                            t.level
                        ));
                    }
                    if t.due[k].iter().any(|&d| d < now) {
                        return Err(format!(
                            "grid: object {id} has a footprint certificate due before {now}"
                        ));
                    }
                }
                Self::cells_of(t, None, &mut keys);
                let bounds = self.owned.iter().find(|(l, _)| *l == m.level).map(|x| x.1);
                for key in &keys {
                    let inside = |b: [[i64; 2]; 3]| {
                        [key.1, key.2, key.3]
                            .iter()
                            .zip(b)
                            .all(|(c, [a, z])| a <= *c && *c <= z)
                    };
                    if t.level == m.level && !bounds.is_some_and(inside) {
                        return Err(format!(
                            "grid: object {id} owns cell {key:?} outside its level's bounds {bounds:?}"
                        ));
                    }
                    if listed.get(&(*key, id)) != Some(&(t.level == m.level)) {
                        return Err(format!(
                            "grid: object {id} not listed right in cell {key:?}"
                        ));
                    }
                }
                covered += keys.len();
            }
        }
        if covered != listed.len() {
            return Err(format!(
                "grid: {} listings for {covered} footprint cells",
                listed.len()
            ));
        }
        // Grid pairs: counted over the shared cells, owners with everyone.
        let mut want: FxHashMap<(u32, u32), u32> = FxHashMap::default();
        for cell in self.cells.values() {
            for (i, &x) in cell.owners.iter().enumerate() {
                for &y in cell.owners[i + 1..].iter().chain(cell.visitors.iter()) {
                    *want.entry(ordered_pair(x, y)).or_default() += 1;
                }
            }
        }
        // A fast member pairs with every member whose zone meets its region, once.
        for &f in &self.fast {
            for (x, m) in self.members.iter().enumerate() {
                let x = x as u32;
                if m.is_none()
                    || x == f
                    || (m.as_ref().is_some_and(|m| m.region.is_some()) && x < f)
                {
                    continue;
                }
                if self.fast_pair(f, x) {
                    *want.entry(ordered_pair(x, f)).or_default() += 1;
                }
            }
        }
        if want.len() != self.pair_of.len() {
            return Err(format!(
                "grid: {} grid pairs kept, {} share cells",
                self.pair_of.len(),
                want.len()
            ));
        }
        let mut reported = 0;
        for (key, count) in want {
            let Some(&i) = self.pair_of.get(&key) else {
                return Err(format!(
                    "grid: pair {key:?} shares {count} cells but is not kept"
                ));
            };
            let slot = self.slots[i as usize]
                .as_ref()
                .ok_or("grid: a kept pair without a slot")?;
            if slot.count != count || (slot.a, slot.b) != key {
                return Err(format!(
                    "grid: pair {key:?} counted {} of {count}",
                    slot.count
                ));
            }
            if slot.reported != slot.inside.iter().all(|&x| x) {
                return Err(format!(
                    "grid: pair {key:?} reported {} against its axes",
                    slot.reported
                ));
            }
            reported += slot.reported as usize;
            let witness = slot.witness as usize;
            if !slot.reported && (witness >= 3 || slot.inside[witness]) {
                return Err(format!(
                    "grid: pair {key:?} is not a candidate but has no axis apart to watch"
                ));
            }
            let (ma, mb) = (self.member(key.0), self.member(key.1));
            // A candidate's three axes are watched; a pair apart watches its witness alone.
            for k in (0..3).filter(|&k| slot.reported || k == witness) {
                let p1 = at(&mb.hi[k]) - at(&ma.lo[k]);
                let p2 = at(&ma.hi[k]) - at(&mb.lo[k]);
                let tol = 1e-9 * (ma.width + mb.width)
                    + 1e-12 * (at(&ma.lo[k]).abs() + at(&mb.lo[k]).abs());
                let e = HYSTERESIS * ma.width.min(mb.width)
                    + tol
                    + HYSTERESIS_ABS * (at(&ma.lo[k]).abs() + at(&mb.lo[k]).abs());
                let ok = if slot.inside[k] {
                    p1 >= -e && p2 >= -e
                } else {
                    p1 <= tol || p2 <= tol
                };
                if !ok {
                    return Err(format!(
                        "grid: pair {key:?} axis {k} inside = {} but the ends are {p1}, {p2} apart",
                        slot.inside[k]
                    ));
                }
                if slot.due[k] < now {
                    return Err(format!(
                        "grid: pair {key:?} has a certificate due before {now}"
                    ));
                }
            }
        }
        if reported != self.box_pairs {
            return Err(format!(
                "grid: {} box pairs counted, {reported} reported",
                self.box_pairs
            ));
        }
        Ok(())
    }
}
