//! Swap events.

use super::{KineticSortedList, SortedListError, Swap};
use crate::math::Real;

impl KineticSortedList {
    /// Processes the next swap if it happens at or before `until`.
    #[inline]
    pub fn process_next_event(&mut self, until: Real) -> Option<Swap> {
        let (left, time) = self.queue.peek()?;
        if time > until {
            return None;
        }
        self.queue.pop();
        if time > self.now {
            self.now = time;
        }
        let i = self.pos[left as usize] as usize;
        let right = self.order[i + 1];
        self.order.swap(i, i + 1);
        self.pos[left as usize] = (i + 1) as u32;
        self.pos[right as usize] = i as u32;
        self.swaps += 1;
        // The same two items, reversed: the cached next sign change, no recomputation.
        let cert = self.certs[left as usize]
            .expect("a scheduled item has a certificate")
            .swapped();
        self.install(right, cert);
        if i + 2 < self.order.len() {
            self.refresh_certificate(i + 1);
        } else {
            self.certs[left as usize] = None;
        }
        if i > 0 {
            self.refresh_certificate(i - 1);
        }
        Some(Swap { time, left, right })
    }

    /// Processes every swap up to time `t` in time order, calling `on_swap` for each, and
    /// moves the list's clock to `t`.
    pub fn advance_to(
        &mut self,
        t: Real,
        mut on_swap: impl FnMut(Swap),
    ) -> Result<(), SortedListError> {
        if t < self.now || t.is_nan() {
            return Err(SortedListError::Backwards {
                now: self.now,
                to: t,
            });
        }
        while let Some(swap) = self.process_next_event(t) {
            on_swap(swap);
        }
        self.now = t;
        Ok(())
    }

    /// Moves the list's clock to `t` without processing anything: for a list that is one of
    /// many driven by an outside event queue, before it is changed at time `t`. Swaps due at
    /// exactly `t` stay pending; one due before `t` is an error (it would be skipped).
    pub fn advance_clock(&mut self, t: Real) -> Result<(), SortedListError> {
        if t < self.now || t.is_nan() {
            return Err(SortedListError::Backwards {
                now: self.now,
                to: t,
            });
        }
        let due = self.next_event_time();
        if due < t {
            return Err(SortedListError::Pending { due, to: t });
        }
        self.now = t;
        Ok(())
    }
}
