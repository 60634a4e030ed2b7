//! Changing the list while it runs: insert, remove, change a key.

use super::build::check_key;
use super::{KineticSortedList, SortedListError};
use crate::certificates::{ScalarKey, order::above_just_after};

impl KineticSortedList {
    /// Inserts `item` with `key` at the current time, in O(log n) search plus the shift.
    pub fn insert(&mut self, item: u32, key: ScalarKey) -> Result<(), SortedListError> {
        check_key(item, &key)?;
        self.grow(item);
        if self.keys[item as usize].is_some() {
            return Err(SortedListError::Duplicate(item));
        }
        let here = key.local(self.now);
        let i = self
            .order
            .partition_point(|&other| !above_just_after(&self.local(other), &here));
        self.keys[item as usize] = Some(key);
        self.order.insert(i, item);
        self.renumber_from(i);
        if i + 1 < self.order.len() {
            self.refresh_certificate(i);
        }
        if i > 0 {
            self.refresh_certificate(i - 1);
        }
        Ok(())
    }

    /// Removes `item`; its neighbours get a certificate of their own.
    pub fn remove(&mut self, item: u32) -> Result<ScalarKey, SortedListError> {
        let key = self
            .key(item)
            .copied()
            .ok_or(SortedListError::Missing(item))?;
        let i = self.pos[item as usize] as usize;
        self.drop_certificate(item);
        self.keys[item as usize] = None;
        self.pos[item as usize] = u32::MAX;
        self.order.remove(i);
        self.renumber_from(i);
        if i > 0 {
            if i < self.order.len() {
                self.refresh_certificate(i - 1);
            } else {
                let left = self.order[i - 1];
                self.drop_certificate(left);
            }
        }
        Ok(key)
    }

    /// Gives `item` a new key from the current time on (a flight-plan change). Only the two
    /// certificates of `item` are recomputed; if the item is now out of place they fail at
    /// once and swaps move it, each an ordinary event.
    pub fn set_key(&mut self, item: u32, key: ScalarKey) -> Result<(), SortedListError> {
        check_key(item, &key)?;
        if self.key(item).is_none() {
            return Err(SortedListError::Missing(item));
        }
        self.keys[item as usize] = Some(key);
        let i = self.pos[item as usize] as usize;
        if i + 1 < self.order.len() {
            self.refresh_certificate(i);
        }
        if i > 0 {
            self.refresh_certificate(i - 1);
        }
        Ok(())
    }

    fn renumber_from(&mut self, i: usize) {
        for (j, &id) in self.order.iter().enumerate().skip(i) {
            self.pos[id as usize] = j as u32;
        }
    }
}
