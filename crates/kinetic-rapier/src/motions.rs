//! The moving bodies' records, in a vector indexed by the body handle's index: the broad phase
//! looks at every moved body once per position update, and a hash map's scattered entries made
//! that pass cost as much as the default broad phase's whole refit.

use rapier3d::prelude::RigidBodyHandle;

/// Records of type `T` by rigid-body handle; a slot whose handle is stale (a body removed and
/// its index reused) counts as empty.
#[derive(Clone, Debug)]
pub(crate) struct ByBody<T> {
    slots: Vec<Option<(RigidBodyHandle, T)>>,
}

impl<T> Default for ByBody<T> {
    fn default() -> Self {
        ByBody { slots: Vec::new() }
    }
}

fn index(h: RigidBodyHandle) -> usize {
    h.into_raw_parts().0 as usize
}

impl<T> ByBody<T> {
    pub(crate) fn get(&self, h: RigidBodyHandle) -> Option<&T> {
        match self.slots.get(index(h)) {
            Some(Some((k, v))) if *k == h => Some(v),
            _ => None,
        }
    }

    pub(crate) fn get_mut(&mut self, h: RigidBodyHandle) -> Option<&mut T> {
        match self.slots.get_mut(index(h)) {
            Some(Some((k, v))) if *k == h => Some(v),
            _ => None,
        }
    }

    /// The handle of the body whose record is at index `i`, if any.
    pub(crate) fn handle_at(&self, i: usize) -> Option<RigidBodyHandle> {
        self.slots.get(i)?.as_ref().map(|(h, _)| *h)
    }

    pub(crate) fn contains(&self, h: RigidBodyHandle) -> bool {
        self.get(h).is_some()
    }

    /// The record of `h`, made by `make` if it has none (a stale one is replaced).
    pub(crate) fn get_or_insert_with(
        &mut self,
        h: RigidBodyHandle,
        make: impl FnOnce() -> T,
    ) -> &mut T {
        let i = index(h);
        if self.slots.len() <= i {
            self.slots.resize_with(i + 1, || None);
        }
        let slot = &mut self.slots[i];
        if !matches!(slot, Some((k, _)) if *k == h) {
            *slot = Some((h, make()));
        }
        &mut slot.as_mut().expect("just filled").1
    }

    pub(crate) fn remove(&mut self, h: RigidBodyHandle) -> Option<T> {
        let slot = self.slots.get_mut(index(h))?;
        if !matches!(slot, Some((k, _)) if *k == h) {
            return None;
        }
        slot.take().map(|(_, v)| v)
    }

    pub(crate) fn iter(&self) -> impl Iterator<Item = (RigidBodyHandle, &T)> {
        self.slots.iter().flatten().map(|(h, v)| (*h, v))
    }
}

impl<T> std::ops::Index<RigidBodyHandle> for ByBody<T> {
    type Output = T;

    fn index(&self, h: RigidBodyHandle) -> &T {
        self.get(h).expect("a record for the body")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reused_index_is_a_different_body() {
        let mut m: ByBody<u32> = ByBody::default();
        let (a, a2) = (
            RigidBodyHandle::from_raw_parts(3, 0),
            RigidBodyHandle::from_raw_parts(3, 1),
        );
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
