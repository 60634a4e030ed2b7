//! Building a sorted list in one go.

use super::{KineticSortedList, SortedListError};
use crate::certificates::{ScalarKey, order::above_just_after};
use crate::math::Real;

impl KineticSortedList {
    /// A list of `items` at time `now`, sorted in O(n log n) (ties by id).
    pub fn from_items(
        now: Real,
        items: impl IntoIterator<Item = (u32, ScalarKey)>,
    ) -> Result<KineticSortedList, SortedListError> {
        let mut list = KineticSortedList {
            now,
            ..KineticSortedList::default()
        };
        let mut locals = Vec::new();
        for (id, key) in items {
            check_key(id, &key)?;
            list.grow(id);
            if list.keys[id as usize].is_some() {
                return Err(SortedListError::Duplicate(id));
            }
            list.keys[id as usize] = Some(key);
            locals.push((key.local(now), id));
        }
        locals.sort_by(|(a, ia), (b, ib)| {
            if above_just_after(a, b) {
                std::cmp::Ordering::Greater
            } else if above_just_after(b, a) {
                std::cmp::Ordering::Less
            } else {
                ia.cmp(ib)
            }
        });
        list.order = locals.iter().map(|&(_, id)| id).collect();
        for (i, &id) in list.order.iter().enumerate() {
            list.pos[id as usize] = i as u32;
        }
        list.queue = crate::EventQueue::with_capacity(list.keys.len());
        for i in 0..list.order.len().saturating_sub(1) {
            list.refresh_certificate(i);
        }
        Ok(list)
    }
}

pub(super) fn check_key(id: u32, key: &ScalarKey) -> Result<(), SortedListError> {
    if [key.t0, key.k0, key.k1, key.k2]
        .iter()
        .all(|x| x.is_finite())
    {
        Ok(())
    } else {
        Err(SortedListError::NonFinite(id))
    }
}
