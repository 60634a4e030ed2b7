//! The audit of the simulator.

use super::{Response, World};

impl World {
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
                let f0 = self.gap(cert.a, cert.b).c[0];
                let scale = self.radius(cert.a).max(self.radius(cert.b));
                let slack = 1e-9 * scale * scale;
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
        let live: Vec<u32> = (0..self.bodies.len() as u32)
            .filter(|&i| self.bodies[i as usize].is_some())
            .collect();
        if live.len() <= 2000 {
            for (i, &a) in live.iter().enumerate() {
                for &b in &live[i + 1..] {
                    if self.pairs.find(a, b).is_none() && self.gap(a, b).c[0] < 0.0 {
                        return Err(format!(
                            "objects {a} and {b} overlap but are not a candidate pair"
                        ));
                    }
                }
            }
        }
        Ok(())
    }
}
