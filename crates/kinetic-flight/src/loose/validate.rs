//! The audit: every invariant of the loose grid recomputed from scratch.

use super::LooseGrid;
use super::cells::cell_keys;
use kinetic_core::Real;
use kinetic_core::kds::Bodies;

impl LooseGrid {
    /// Recomputes the invariants from scratch
    /// ([`kinetic_core::CandidateStructure::validate`]).
    pub(super) fn check(&self, bodies: &Bodies, now: Real) -> Result<(), String> {
        self.exits.validate()?;
        let mut covered = 0;
        let mut live = Vec::new();
        for (id, m) in self.members.iter().enumerate() {
            let Some(m) = m else { continue };
            let id = id as u32;
            if bodies.get(id as usize).is_none_or(Option::is_none) {
                return Err(format!("loose: object {id} held but not live"));
            }
            live.push(id);
            // Its box now is inside its region, and stays so until its exit.
            let keys = Self::box_keys(bodies, id, now);
            let tol = 1e-9 * (m.hi - m.lo).max_element()
                + 1e-12 * m.lo.abs().max(m.hi.abs()).max_element();
            for (k, (l, u)) in keys.iter().enumerate() {
                if l[0] < m.lo[k] - tol || u[0] > m.hi[k] + tol {
                    return Err(format!(
                        "loose: object {id} axis {k}: box [{}, {}] outside its region [{}, {}]",
                        l[0], u[0], m.lo[k], m.hi[k]
                    ));
                }
            }
            if m.exit < now {
                return Err(format!("loose: object {id} left its region at {}", m.exit));
            }
            let queued = self.exits.time_of(id);
            if queued != m.exit.is_finite().then_some(m.exit) {
                return Err(format!(
                    "loose: object {id} exits at {}, queued at {queued:?}",
                    m.exit
                ));
            }
            match self.footprint(m.lo, m.hi) {
                None => {
                    if !m.big || !m.slots.is_empty() {
                        return Err(format!("loose: object {id} is big but filed in cells"));
                    }
                    if self.big.iter().filter(|&&x| x == id).count() != 1 {
                        return Err(format!("loose: big object {id} not listed once"));
                    }
                }
                Some(f) => {
                    let mut want = Vec::new();
                    for key in cell_keys(f) {
                        let Some(&slot) = self.cells.get(&key) else {
                            return Err(format!("loose: object {id}: cell {key:?} missing"));
                        };
                        want.push(slot);
                    }
                    if m.big || m.slots != want {
                        return Err(format!("loose: object {id} filed in the wrong cells"));
                    }
                    for &slot in &m.slots {
                        let n = self.occupants[slot as usize]
                            .iter()
                            .filter(|&&x| x == id)
                            .count();
                        if n != 1 {
                            return Err(format!("loose: object {id} listed {n} times in a cell"));
                        }
                    }
                    covered += m.slots.len();
                }
            }
        }
        if self.big.len() != self.members.iter().flatten().filter(|m| m.big).count() {
            return Err(format!("loose: {} big objects listed", self.big.len()));
        }
        if live.len() != self.live {
            return Err(format!(
                "loose: {} objects counted, {} live",
                self.live,
                live.len()
            ));
        }
        // Every listing is a member's, and every cell kept holds some.
        let listed: usize = self.occupants.iter().map(Vec::len).sum();
        let mut slots: Vec<u32> = self.cells.values().copied().collect();
        slots.sort_unstable();
        slots.dedup();
        if slots.len() != self.cells.len()
            || slots.iter().any(|&s| self.occupants[s as usize].is_empty())
            || self
                .free
                .iter()
                .any(|&s| !self.occupants[s as usize].is_empty())
        {
            return Err("loose: a cell is shared, empty but kept, or freed but not empty".into());
        }
        if covered != listed {
            return Err(format!(
                "loose: {listed} listings for {covered} filed cells"
            ));
        }
        // Partners: exactly the overlapping regions, both ways.
        let mut pairs = 0;
        for (i, &a) in live.iter().enumerate() {
            let ma = self.member(a);
            let mut want: Vec<u32> = live[..i]
                .iter()
                .chain(&live[i + 1..])
                .copied()
                .filter(|&b| {
                    let mb = self.member(b);
                    ma.lo.cmple(mb.hi).all() && mb.lo.cmple(ma.hi).all()
                })
                .collect();
            let mut have = ma.partners.clone();
            want.sort_unstable();
            have.sort_unstable();
            if want != have {
                return Err(format!(
                    "loose: object {a} has partners {have:?}, regions say {want:?}"
                ));
            }
            pairs += have.len();
        }
        if pairs != 2 * self.pairs {
            return Err(format!(
                "loose: {} pairs counted, {} held",
                self.pairs,
                pairs / 2
            ));
        }
        Ok(())
    }
}
