//! The moving bodies' records, in a vector indexed by the body key's index: the broad phase
//! looks at every moved body once per position update, and a hash map's scattered entries made
//! that pass cost as much as the default broad phase's whole refit.

use crate::Key;

/// Records of type `T` by body key; a slot whose handle is stale (a body removed and
/// its index reused) counts as empty. The handles sit apart from the records, so that finding
/// which body holds an index reads 8 bytes, not a whole record.
#[derive(Clone, Debug)]
pub(crate) struct ByBody<T> {
    keys: Vec<Option<Key>>,
    values: Vec<Option<T>>,
}

impl<T> Default for ByBody<T> {
    fn default() -> Self {
        ByBody {
            keys: Vec::new(),
            values: Vec::new(),
        }
    }
}

fn index(h: Key) -> usize {
    h.index as usize
}

impl<T> ByBody<T> {
    pub(crate) fn get(&self, h: Key) -> Option<&T> {
        let i = index(h);
        match self.keys.get(i) {
            Some(Some(k)) if *k == h => self.values[i].as_ref(),
            _ => None,
        }
    }

    pub(crate) fn get_mut(&mut self, h: Key) -> Option<&mut T> {
        let i = index(h);
        match self.keys.get(i) {
            Some(Some(k)) if *k == h => self.values[i].as_mut(),
            _ => None,
        }
    }

    /// Asks for the memory of `h`'s record, to be read soon.
    pub(crate) fn prefetch(&self, h: Key) {
        if let Some(slot) = self.values.get(index(h)) {
            kinetic_core::prefetch_all(slot);
        }
    }

    /// The key of the body whose record is at index `i`, if any.
    pub(crate) fn key_at(&self, i: usize) -> Option<Key> {
        *self.keys.get(i)?
    }

    pub(crate) fn contains(&self, h: Key) -> bool {
        self.get(h).is_some()
    }

    /// Room for records up to index `last`, made at once (a bulk of new bodies).
    pub(crate) fn reach(&mut self, last: usize) {
        if self.keys.len() <= last {
            self.keys.resize(last + 1, None);
            self.values.resize_with(last + 1, || None);
        }
    }

    /// The record of `h`, made by `make` if it has none (a stale one is replaced).
    pub(crate) fn get_or_insert_with(&mut self, h: Key, make: impl FnOnce() -> T) -> &mut T {
        let i = index(h);
        self.reach(i);
        if self.keys[i] != Some(h) {
            self.keys[i] = Some(h);
            self.values[i] = Some(make());
        }
        self.values[i].as_mut().expect("just filled")
    }

    pub(crate) fn remove(&mut self, h: Key) -> Option<T> {
        let i = index(h);
        if self.keys.get(i) != Some(&Some(h)) {
            return None;
        }
        self.keys[i] = None;
        self.values[i].take()
    }

    pub(crate) fn iter(&self) -> impl Iterator<Item = (Key, &T)> {
        self.keys
            .iter()
            .zip(&self.values)
            .filter_map(|(k, v)| Some(((*k)?, v.as_ref()?)))
    }
}

impl<T> std::ops::Index<Key> for ByBody<T> {
    type Output = T;

    fn index(&self, h: Key) -> &T {
        self.get(h).expect("a record for the body")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reused_index_is_a_different_body() {
        let mut m: ByBody<u32> = ByBody::default();
        let (a, a2) = (Key::new(3, 0), Key::new(3, 1));
        *m.get_or_insert_with(a, || 7) += 1;
        assert_eq!(m.get(a), Some(&8));
        assert_eq!(m.get(a2), None);
        assert_eq!(m.remove(a2), None);
        // The new body with the same index replaces the stale record.
        assert_eq!(*m.get_or_insert_with(a2, || 1), 1);
        assert_eq!(m.get(a), None);
        assert_eq!(m.iter().count(), 1);
        assert_eq!(m.remove(a2), Some(1));
        assert!(m.iter().next().is_none());
    }
}
