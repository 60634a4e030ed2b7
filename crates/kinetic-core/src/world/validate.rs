//! The audit of the simulator.

use super::{Response, Simulator};
use crate::math::Real;

impl Simulator {
    /// Recomputes the invariants from scratch: the structure's own; every candidate pair
    /// scheduled at its due time, never in the past; and every pair of live objects that
    /// overlaps now is a candidate (the structure may not miss a contact).
    pub fn validate(&self) -> Result<(), String> {
        self.structure.validate(&self.bodies, self.now)?;
        self.pair_queue.validate()?;
        self.wall_queue.validate()?;
        for (slot, cert) in self.pairs.iter() {
            let due = cert.due_time();
            let queued = self.pair_queue.time_of(slot).unwrap_or(f64::INFINITY);
            if queued != due {
                return Err(format!(
                    "pair ({}, {}) due at {due} but queued at {queued}",
                    cert.a, cert.b
                ));
            }
            if due < self.now {
                return Err(format!(
                    "pair ({}, {}) was due at {due}, now is {}",
                    cert.a, cert.b, self.now
                ));
            }
            if self.response == Response::None {
                let (f0, slack) = self.separation(cert.a, cert.b);
                if cert.touching && f0 > slack && due > self.now {
                    return Err(format!(
                        "pair ({}, {}) marked touching but apart (gap {f0})",
                        cert.a, cert.b
                    ));
                }
                if !cert.touching && f0 < -slack && due > self.now {
                    return Err(format!(
                        "pair ({}, {}) overlaps (gap {f0}) but is not marked",
                        cert.a, cert.b
                    ));
                }
            }
        }
        // Every overlapping pair is a candidate. Touching balls overlap in x by their radii
        // (on a plane the reach 2 sqrt(ra rb) is at most ra + rb), so a sweep over x finds
        // every pair that could overlap.
        let mut spans: Vec<(Real, Real, u32)> = (0..self.bodies.len() as u32)
            .filter(|&i| self.bodies[i as usize].is_some())
            .map(|i| {
                let (x, r) = (self.plan_of(i).position_at(self.now).x, self.radius(i));
                (x - r, x + r, i)
            })
            .collect();
        spans.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.2.cmp(&q.2)));
        let mut open: Vec<(Real, u32)> = Vec::new();
        for &(lo, hi, b) in &spans {
            open.retain(|&(h, _)| h >= lo);
            for &(_, a) in &open {
                if self.pairs.find(a, b).is_none() && self.separation(a.min(b), a.max(b)).0 < 0.0 {
                    return Err(format!(
                        "objects {} and {} overlap but are not a candidate pair",
                        a.min(b),
                        a.max(b)
                    ));
                }
            }
            open.push((hi, b));
        }
        Ok(())
    }
}
