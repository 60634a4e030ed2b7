//! Three kinetic sorted lists, one per axis, of items that follow the objects' flight plans
//! (box ends, guard-cube ends): what the sweep and the guards share.

use kinetic_core::Real;
use kinetic_core::kds::{Bodies, KineticSortedList, ScalarKey, Swap};

/// An object's items: for each one, its id and key on each axis.
pub(crate) type AxisItems = Vec<[(u32, ScalarKey); 3]>;

/// One kinetic sorted list per axis.
#[derive(Debug, Default)]
pub(crate) struct AxisLists {
    lists: [KineticSortedList; 3],
}

impl AxisLists {
    /// The list of `axis`.
    pub(crate) fn list(&self, axis: usize) -> &KineticSortedList {
        &self.lists[axis]
    }

    /// The position of `item` in the list of `axis`.
    #[inline]
    pub(crate) fn position(&self, axis: usize, item: u32) -> usize {
        self.lists[axis]
            .position(item)
            .expect("an item of the list")
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.lists[0].is_empty()
    }

    /// Brings every list's clock to `now` (every swap before it was processed).
    pub(crate) fn sync(&mut self, now: Real) {
        for l in &mut self.lists {
            l.advance_clock(now)
                .expect("every swap before now was processed");
        }
    }

    /// Lists of `items` at `now`, built in one go.
    pub(crate) fn build(now: Real, items: impl IntoIterator<Item = [(u32, ScalarKey); 3]>) -> Self {
        let mut per_axis: [Vec<(u32, ScalarKey)>; 3] = Default::default();
        for it in items {
            for (axis, x) in it.into_iter().enumerate() {
                per_axis[axis].push(x);
            }
        }
        AxisLists {
            lists: per_axis
                .map(|items| KineticSortedList::from_items(now, items).expect("valid keys")),
        }
    }

    pub(crate) fn insert(&mut self, items: AxisItems) {
        for it in items {
            for (axis, (item, key)) in it.into_iter().enumerate() {
                self.lists[axis].insert(item, key).expect("a new item");
            }
        }
    }

    pub(crate) fn remove(&mut self, items: AxisItems) {
        for it in items {
            for (axis, (item, _)) in it.into_iter().enumerate() {
                self.lists[axis].remove(item).expect("an item");
            }
        }
    }

    /// Whether `items`, keyed anew, are still in order among their neighbours at `now` (a
    /// re-plan that starts where the old plan is); not after a teleport, or a spin started or
    /// stopped, which moves a box at once.
    pub(crate) fn keeps_order(&self, items: &AxisItems, now: Real) -> bool {
        (0..3).all(|axis| {
            let list = &self.lists[axis];
            let value = |item: u32| {
                let own = items
                    .iter()
                    .find(|it| it[axis].0 == item)
                    .map(|it| &it[axis].1);
                own.or_else(|| list.key(item)).map(|k| k.value_at(now))
            };
            items.iter().all(|it| {
                let item = it[axis].0;
                let i = self.position(axis, item);
                let v = value(item);
                let before = i.checked_sub(1).map(|j| list.order()[j]);
                let after = list.order().get(i + 1).copied();
                before.is_none_or(|b| value(b) <= v) && after.is_none_or(|a| v <= value(a))
            })
        })
    }

    /// New keys from now on (a re-plan whose items stay in order now; an item out of place
    /// would fail its certificates at once and move by swaps, one event each).
    pub(crate) fn set_keys(&mut self, items: AxisItems) {
        for it in items {
            for (axis, (item, key)) in it.into_iter().enumerate() {
                self.lists[axis].set_key(item, key).expect("an item");
            }
        }
    }

    pub(crate) fn next_event_time(&self) -> Real {
        self.lists
            .iter()
            .map(|l| l.next_event_time())
            .fold(Real::INFINITY, Real::min)
    }

    /// Processes the earliest swap of the three lists (the lowest axis on a tie).
    pub(crate) fn next_swap(&mut self) -> Option<(usize, Swap)> {
        let (axis, t) = (0..3).map(|k| (k, self.lists[k].next_event_time())).fold(
            (0, Real::INFINITY),
            |best, x| if x.1 < best.1 { x } else { best },
        );
        self.lists[axis].process_next_event(t).map(|s| (axis, s))
    }

    pub(crate) fn certificates(&self) -> usize {
        self.lists.iter().map(|l| l.certificates()).sum()
    }

    pub(crate) fn swaps(&self) -> u64 {
        self.lists.iter().map(|l| l.swap_count()).sum()
    }

    /// The audit: each list sorted, and exactly the live objects present (`present`) with the
    /// keys their plans give now (`items`).
    pub(crate) fn validate(
        &self,
        name: &str,
        bodies: &Bodies,
        now: Real,
        present: impl Fn(u32) -> bool,
        items: impl Fn(u32) -> AxisItems,
    ) -> Result<(), String> {
        for (axis, l) in self.lists.iter().enumerate() {
            l.validate()
                .map_err(|e| format!("{name} list {axis}: {e}"))?;
        }
        for (id, body) in bodies.iter().enumerate() {
            let id = id as u32;
            match body {
                Some(_) if present(id) => {
                    for it in items(id) {
                        for (axis, (item, want)) in it.into_iter().enumerate() {
                            let have = self.lists[axis]
                                .key(item)
                                .ok_or(format!("object {id}: item {item} missing"))?;
                            let (x, y) = (have.value_at(now), want.value_at(now));
                            if (x - y).abs() > 1e-9 * (1.0 + x.abs()) {
                                return Err(format!(
                                    "object {id}: item {item} on axis {axis} at {x}, plan says {y}"
                                ));
                            }
                        }
                    }
                }
                Some(_) => return Err(format!("object {id} is live but not in the {name}")),
                None if present(id) => {
                    return Err(format!("object {id} is gone but still in the {name}"));
                }
                None => {}
            }
        }
        Ok(())
    }
}
