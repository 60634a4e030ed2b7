//! The audit: recompute the invariants from scratch.

use super::KineticSortedList;
use crate::certificates::order::above_just_after;

impl KineticSortedList {
    /// Checks, from scratch: the index matches the order; every neighbour pair has its
    /// certificate scheduled no earlier than now; any pair out of order just after now is
    /// due now (its swap is pending at this very time), up to rounding of the root.
    pub fn validate(&self) -> Result<(), String> {
        self.queue.validate()?;
        let present = self.keys.iter().filter(|k| k.is_some()).count();
        if present != self.order.len() {
            return Err(format!(
                "{present} keys but {} items in order",
                self.order.len()
            ));
        }
        let tol = 1e-9 * self.now.abs().max(1.0);
        for (i, &id) in self.order.iter().enumerate() {
            if self.pos.get(id as usize) != Some(&(i as u32)) {
                return Err(format!("item {id} at position {i} is indexed elsewhere"));
            }
            let Some(&(x, y)) = self.order.get(i..i + 2).map(|w| (&w[0], &w[1])).as_ref() else {
                if self.queue.time_of(id).is_some() {
                    return Err(format!("last item {id} has a scheduled certificate"));
                }
                continue;
            };
            let (x, y) = (*x, *y);
            let due = self.queue.time_of(x);
            let Some(cert) = self.certs[x as usize] else {
                return Err(format!("items {x}, {y} have no certificate"));
            };
            if due.unwrap_or(f64::INFINITY) != cert.failure_time() {
                return Err(format!(
                    "certificate of {x}, {y} is scheduled at {due:?}, fails at {}",
                    cert.failure_time()
                ));
            }
            let due = cert.failure_time();
            if due < self.now {
                return Err(format!(
                    "certificate of {x}, {y} was due at {due}, now is {}",
                    self.now
                ));
            }
            let (lx, ly) = (self.local(x), self.local(y));
            let gap = ly[0] - lx[0];
            let scale = lx[0].abs().max(ly[0].abs()).max(1.0);
            if above_just_after(&lx, &ly) && due > self.now + tol && gap < -1e-9 * scale {
                return Err(format!(
                    "items {x}, {y} are out of order at {} (gap {gap}) but swap only at {due}",
                    self.now
                ));
            }
        }
        Ok(())
    }
}
