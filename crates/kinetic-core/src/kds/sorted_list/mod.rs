//! The kinetic sorted list: items with moving scalar keys kept in sorted order, with one
//! `order` certificate between each pair of neighbours.
//!
//! Split by operation: `build.rs` (construction and queries), `update.rs` (insert, remove,
//! change a key while running), `event.rs` (swap events), `validate.rs` (the audit).

mod build;
mod event;
mod update;
mod validate;

use crate::certificates::{OrderCertificate, ScalarKey};
use crate::math::Real;
use crate::queue::EventQueue;

/// A swap: `left` and `right` were neighbours in that order and exchanged places at `time`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Swap {
    /// When the swap happened.
    pub time: Real,
    /// The item that was on the left (lower key) before the swap.
    pub left: u32,
    /// The item that was on the right before the swap.
    pub right: u32,
}

/// A kinetic sorted list of items named by dense `u32` ids.
///
/// ```
/// # use kinetic_core::kds::{KineticSortedList, ScalarKey};
/// let mut list = KineticSortedList::new();
/// list.insert(0, ScalarKey::linear(0.0, 1.0)).unwrap(); // moves right
/// list.insert(1, ScalarKey::linear(5.0, -1.0)).unwrap(); // moves left
/// let mut swaps = Vec::new();
/// list.advance_to(10.0, |s| swaps.push(s)).unwrap();
/// assert_eq!(swaps.len(), 1);
/// assert_eq!(swaps[0].time, 2.5);
/// assert_eq!(list.order(), &[1, 0]);
/// ```
#[derive(Clone, Debug, Default)]
pub struct KineticSortedList {
    now: Real,
    /// Items in sorted order.
    order: Vec<u32>,
    /// Per item id: its key, or `None` when the id is not in the list.
    keys: Vec<Option<ScalarKey>>,
    /// Per item id: its index in `order`.
    pos: Vec<u32>,
    /// Per item id: the certificate between it and its right neighbour.
    certs: Vec<Option<OrderCertificate>>,
    /// Failure times, keyed by the left item of each certificate.
    queue: EventQueue,
    swaps: u64,
}

/// Misuse of a sorted list: the item named is absent, or already present.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SortedListError {
    /// The item is not in the list.
    #[error("item {0} is not in the sorted list")]
    Missing(u32),
    /// The item is in the list already.
    #[error("item {0} is already in the sorted list")]
    Duplicate(u32),
    /// A key has a non-finite coefficient.
    #[error("item {0} has a non-finite key")]
    NonFinite(u32),
    /// Time would go backwards.
    #[error("cannot go back in time from {now} to {to}")]
    Backwards {
        /// The list's current time.
        now: Real,
        /// The time asked for.
        to: Real,
    },
    /// The clock cannot skip a pending swap.
    #[error("a swap is due at {due}, before {to}")]
    Pending {
        /// When the pending swap is due.
        due: Real,
        /// The time asked for.
        to: Real,
    },
}

impl KineticSortedList {
    /// An empty list at time 0.
    pub fn new() -> KineticSortedList {
        KineticSortedList::default()
    }

    /// The current time.
    pub fn now(&self) -> Real {
        self.now
    }

    /// The items in sorted order.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// The number of items.
    pub fn len(&self) -> usize {
        self.order.len()
    }

    /// Whether the list is empty.
    pub fn is_empty(&self) -> bool {
        self.order.is_empty()
    }

    /// The number of certificates (neighbour pairs).
    pub fn certificates(&self) -> usize {
        self.order.len().saturating_sub(1)
    }

    /// The number of swaps processed so far.
    pub fn swap_count(&self) -> u64 {
        self.swaps
    }

    /// The index of `item` in the order, if present.
    #[inline]
    pub fn position(&self, item: u32) -> Option<usize> {
        // Absent items are marked in `pos` itself: one memory access, not two.
        match self.pos.get(item as usize) {
            Some(&p) if p != u32::MAX => Some(p as usize),
            _ => None,
        }
    }

    /// The key of `item`, if present.
    pub fn key(&self, item: u32) -> Option<&ScalarKey> {
        self.keys.get(item as usize).and_then(Option::as_ref)
    }

    /// The time of the next swap (+infinity for none).
    pub fn next_event_time(&self) -> Real {
        self.queue.next_time()
    }

    fn local(&self, item: u32) -> [Real; 3] {
        self.keys[item as usize]
            .expect("items in the order have keys")
            .local(self.now)
    }

    /// Recomputes the certificate between the items at positions `i` and `i + 1`.
    fn refresh_certificate(&mut self, i: usize) {
        let (x, y) = (self.order[i], self.order[i + 1]);
        let cert = OrderCertificate::new(&self.local(x), &self.local(y), self.now);
        self.install(x, cert);
    }

    fn install(&mut self, left: u32, cert: OrderCertificate) {
        let t = cert.failure_time();
        self.certs[left as usize] = Some(cert);
        if t.is_finite() {
            self.queue.schedule(left, t, 0);
        } else {
            self.queue.remove(left);
        }
    }

    fn drop_certificate(&mut self, left: u32) {
        self.certs[left as usize] = None;
        self.queue.remove(left);
    }

    fn grow(&mut self, item: u32) {
        let need = item as usize + 1;
        if self.keys.len() < need {
            self.keys.resize(need, None);
            self.pos.resize(need, u32::MAX);
            self.certs.resize(need, None);
        }
    }
}
