//! A cell's objects: its owners, and its visitors from the levels below (a short list while
//! there are few, a set once there are many). Most cells hold a few objects: their lists are
//! kept inline, so a cell entered and left costs no allocation.

use rustc_hash::FxHashSet;
use smallvec::SmallVec;

/// A cell's owners, or its visitors while few: inline up to this many.
pub(super) type Ids = SmallVec<[u32; 4]>;

/// A cell's objects: those living at its level, and visitors from below.
#[derive(Clone, Debug, Default)]
pub(super) struct Cell {
    pub(super) owners: Ids,
    pub(super) visitors: Visitors,
}

/// A cell's visitors: a short list while there are few (most cells), a set once there are
/// many (a coarse cell may hold thousands of small visitors).
#[derive(Clone, Debug)]
pub(super) enum Visitors {
    Few(Ids),
    Many(FxHashSet<u32>),
}

/// The most visitors a cell keeps in a list.
const FEW_VISITORS: usize = 16;

impl Default for Visitors {
    fn default() -> Self {
        Visitors::Few(Ids::new())
    }
}

impl Visitors {
    pub(super) fn insert(&mut self, id: u32) {
        match self {
            Visitors::Few(v) if v.len() < FEW_VISITORS => v.push(id),
            Visitors::Few(v) => {
                let mut set: FxHashSet<u32> = v.drain(..).collect();
                set.insert(id);
                *self = Visitors::Many(set);
            }
            Visitors::Many(set) => {
                set.insert(id);
            }
        }
    }

    pub(super) fn remove(&mut self, id: u32) {
        match self {
            Visitors::Few(v) => {
                if let Some(i) = v.iter().position(|&x| x == id) {
                    v.swap_remove(i);
                }
            }
            Visitors::Many(set) => {
                set.remove(&id);
            }
        }
    }

    pub(super) fn is_empty(&self) -> bool {
        match self {
            Visitors::Few(v) => v.is_empty(),
            Visitors::Many(set) => set.is_empty(),
        }
    }

    pub(super) fn iter(&self) -> impl Iterator<Item = &u32> {
        let (few, many) = match self {
            Visitors::Few(v) => (Some(v.iter()), None),
            Visitors::Many(set) => (None, Some(set.iter())),
        };
        few.into_iter().flatten().chain(many.into_iter().flatten())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn listed(v: &Visitors) -> Vec<u32> {
        let mut ids: Vec<u32> = v.iter().copied().collect();
        ids.sort_unstable();
        ids
    }

    #[test]
    fn visitors_turn_from_a_list_into_a_set_and_keep_every_id_once() {
        let mut v = Visitors::default();
        assert!(v.is_empty());
        for id in 0..FEW_VISITORS as u32 {
            v.insert(id);
        }
        assert!(matches!(v, Visitors::Few(_)));
        v.remove(3);
        v.remove(99);
        assert_eq!(listed(&v).len(), FEW_VISITORS - 1);
        for id in 100..110 {
            v.insert(id);
        }
        assert!(matches!(v, Visitors::Many(_)));
        let mut want: Vec<u32> = (0..FEW_VISITORS as u32).filter(|&i| i != 3).collect();
        want.extend(100..110);
        assert_eq!(listed(&v), want);
        for id in want {
            v.remove(id);
        }
        assert!(v.is_empty());
        assert!(listed(&v).is_empty());
    }
}
