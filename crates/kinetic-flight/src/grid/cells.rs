//! Objects entering and leaving cells, levels filling, and objects put into the grid and
//! taken out of it.

use super::FAST_SPAN;
use super::{CellKey, Grid, Track};
use kinetic_core::Real;
use kinetic_core::kds::PairChange;

impl Grid {
    /// Puts member `id` (in `members`, with no tracks, region or pairs) into the grid: fast,
    /// with a region, or into the cells of its levels.
    pub(super) fn settle(&mut self, id: u32, now: Real, changes: &mut Vec<PairChange>) {
        let m = self.member(id);
        if self.is_fast(m, now, FAST_SPAN) {
            self.fast.push(id);
            self.anchor_fast(id, now, changes);
        } else {
            // Out of the members while its level fills, or it would visit there itself.
            let m = self.members[id as usize].take().expect("a member");
            self.occupy(m.level, now, changes);
            self.members[id as usize] = Some(m);
            self.place(id, now, changes);
        }
    }

    pub(super) fn enter(
        &mut self,
        id: u32,
        key: CellKey,
        owner: bool,
        now: Real,
        changes: &mut Vec<PairChange>,
    ) {
        if owner {
            let (level, cell) = (key.0, [key.1, key.2, key.3]);
            match self.owned.iter_mut().find(|(l, _)| *l == level) {
                Some((_, b)) => {
                    for k in 0..3 {
                        b[k] = [b[k][0].min(cell[k]), b[k][1].max(cell[k])];
                    }
                }
                None => self.owned.push((level, cell.map(|c| [c, c]))),
            }
        }
        let cell = self.cells.entry(key).or_default();
        let mut partners = std::mem::take(&mut self.scratch);
        partners.clear();
        partners.extend_from_slice(&cell.owners);
        if owner {
            partners.extend(cell.visitors.iter().copied());
            cell.owners.push(id);
        } else {
            cell.visitors.insert(id);
        }
        for &p in &partners {
            self.pair_up(id, p, now, changes);
        }
        self.scratch = partners;
    }

    pub(super) fn leave(
        &mut self,
        id: u32,
        key: CellKey,
        owner: bool,
        changes: &mut Vec<PairChange>,
    ) {
        let Some(cell) = self.cells.get_mut(&key) else {
            return;
        };
        if owner {
            if let Some(i) = cell.owners.iter().position(|&x| x == id) {
                cell.owners.swap_remove(i);
            }
        } else {
            cell.visitors.remove(id);
        }
        let mut partners = std::mem::take(&mut self.scratch);
        partners.clear();
        partners.extend_from_slice(&cell.owners);
        if owner {
            partners.extend(cell.visitors.iter().copied());
        }
        if cell.owners.is_empty() && cell.visitors.is_empty() {
            self.cells.remove(&key);
        }
        for &p in &partners {
            self.pair_down(id, p, changes);
        }
        self.scratch = partners;
    }

    /// Makes `level` occupied: every member below it becomes a visitor there.
    pub(super) fn occupy(&mut self, level: i32, now: Real, changes: &mut Vec<PairChange>) {
        if !self.occupied.insert(level) {
            return;
        }
        let below: Vec<u32> = (0..self.members.len() as u32)
            .filter(|&id| {
                self.members[id as usize]
                    .as_ref()
                    .is_some_and(|m| m.level < level && !m.tracks.is_empty())
            })
            .collect();
        let mut keys = Vec::new();
        for id in below {
            let m = self.member(id);
            let track = self.track_at(m, &m.tracks[0], level, now);
            Self::cells_of(&track, None, &mut keys);
            let m = self.members[id as usize].as_mut().expect("a member");
            let at = m.tracks.partition_point(|t| t.level < level);
            self.own_tracks += track.own();
            m.tracks.insert(at, track);
            for &key in &keys {
                self.enter(id, key, false, now, changes);
            }
            self.schedule_member(id);
        }
    }

    /// Puts member `id` (already in `members`, no tracks) into the cells of its levels.
    pub(super) fn place(&mut self, id: u32, now: Real, changes: &mut Vec<PairChange>) {
        let level = self.member(id).level;
        let levels = self.occupied.range(level..).count();
        self.members[id as usize]
            .as_mut()
            .expect("a member")
            .tracks
            .reserve_exact(levels);
        let mut keys = std::mem::take(&mut self.keys);
        for k in 0..levels {
            let l = *self
                .occupied
                .range(level..)
                .nth(k)
                .expect("an occupied level");
            let m = self.member(id);
            let track = match m.tracks.first() {
                Some(own) => self.track_at(m, own, l, now),
                None => self.footprint(m, l, now),
            };
            Self::cells_of(&track, None, &mut keys);
            self.own_tracks += track.own();
            self.members[id as usize]
                .as_mut()
                .expect("a member")
                .tracks
                .push(track);
            for &key in &keys {
                self.enter(id, key, l == level, now, changes);
            }
        }
        self.keys = keys;
        self.schedule_member(id);
        self.fast_links(id, now, changes);
    }

    /// Takes member `id` out of every cell or out of the fast ones (all its pairs go) and
    /// out of the queue: it is left with no tracks and no region.
    pub(super) fn unplace(&mut self, id: u32, changes: &mut Vec<PairChange>) {
        let m = self.members[id as usize].as_mut().expect("a member");
        let (level, tracks) = (m.level, std::mem::take(&mut m.tracks));
        self.own_tracks -= tracks.iter().map(Track::own).sum::<usize>();
        if m.region.take().is_some()
            && let Some(i) = self.fast.iter().position(|&x| x == id)
        {
            self.fast.swap_remove(i);
        }
        let mut keys = std::mem::take(&mut self.keys);
        for track in &tracks {
            Self::cells_of(track, None, &mut keys);
            for &key in &keys {
                self.leave(id, key, track.level == level, changes);
            }
        }
        self.keys = keys;
        // What is left are pairs with fast members, or a fast member's own.
        for i in self.member(id).pairs.clone() {
            let slot = self.slots[i as usize].as_ref().expect("a slot");
            let other = if slot.a == id { slot.b } else { slot.a };
            self.pair_down(id, other, changes);
        }
        self.crossings_queue.remove(id);
    }
}
