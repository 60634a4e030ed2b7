//! Objects in the three sorted lists: their boxes and guard cubes, and which boxes overlap
//! which cubes (the watches to keep).

use super::{End, Guards, INFLATE, decode, item};
use crate::axes::AxisItems;
use kinetic_core::Real;
use kinetic_core::kds::{Bodies, PairChange, ScalarKey};

impl Guards {
    pub(super) fn present(&self, id: u32) -> bool {
        self.half.get(id as usize).is_some_and(|&h| h > 0.0)
    }

    pub(super) fn plan(bodies: &Bodies, id: u32) -> &kinetic_core::FlightPlan {
        &bodies[id as usize].as_ref().expect("a live object").plan
    }

    /// The list items of object `id` with their keys, per axis.
    pub(super) fn items(&self, bodies: &Bodies, id: u32) -> AxisItems {
        let plan = Self::plan(bodies, id);
        let (half, r) = (self.half[id as usize], self.inner[id as usize]);
        let key = |axis, off| ScalarKey::from_plan(plan, axis, off);
        let mut out = vec![
            std::array::from_fn(|k| (item(id, End::BoxLo), key(k, -half))),
            std::array::from_fn(|k| (item(id, End::BoxHi), key(k, half))),
        ];
        if !self.wild[id as usize] {
            let (lo, hi) = (self.grid.offset(r, 0), self.grid.offset(r, self.grid.m - 1));
            out.push(std::array::from_fn(|k| (item(id, End::CubeLo), key(k, lo))));
            out.push(std::array::from_fn(|k| (item(id, End::CubeHi), key(k, hi))));
        }
        out
    }

    /// Whether `boxer` guards against `guarded`: both guarded and `boxer` at least as large.
    pub(super) fn guards_against(&self, guarded: u32, boxer: u32) -> bool {
        guarded != boxer
            && !self.wild[guarded as usize]
            && !self.wild[boxer as usize]
            && self.inner[boxer as usize] >= self.inner[guarded as usize]
    }

    /// Whether the box of `boxer` overlaps the guard cube of `guarded`, from the list orders.
    pub(super) fn cube_overlap(&self, guarded: u32, boxer: u32) -> bool {
        (0..3).all(|axis| {
            let p = |it| self.lists.position(axis, it);
            p(item(guarded, End::CubeLo)) < p(item(boxer, End::BoxHi))
                && p(item(boxer, End::BoxLo)) < p(item(guarded, End::CubeHi))
        })
    }

    pub(super) fn sync(&mut self, now: Real) {
        self.now = now;
        self.lists.sync(now);
    }

    fn grow(&mut self, id: u32) {
        let need = id as usize + 1;
        if self.half.len() < need {
            self.half.resize(need, 0.0);
            self.inner.resize(need, 0.0);
            self.wild.resize(need, false);
            self.links.resize(need, Vec::new());
            self.watches_of.resize(need, Vec::new());
        }
    }

    /// Registers object `id`'s sizes.
    pub(super) fn admit(&mut self, bodies: &Bodies, id: u32) {
        self.grow(id);
        let shape = &bodies[id as usize].as_ref().expect("a live object").shape;
        let (inner, outer) = (shape.inner_radius(), shape.outer_radius());
        let wild = !(inner > 0.0 && outer <= self.grid.rho * inner * (1.0 + 1e-12));
        self.half[id as usize] = outer * INFLATE;
        self.inner[id as usize] = if wild { 0.0 } else { inner };
        self.wild[id as usize] = wild;
        if wild {
            self.wild_count += 1;
        }
    }

    /// Every (guarded, boxer) whose box overlaps the guard cube, by a sweep along x.
    pub(super) fn cube_pairs(&self) -> Vec<(u32, u32)> {
        let mut out = Vec::new();
        let (mut boxes, mut cubes): (Vec<u32>, Vec<u32>) = (Vec::new(), Vec::new());
        for &it in self.lists.list(0).order() {
            let (o, end) = decode(it);
            match end {
                End::BoxLo => {
                    for &g in &cubes {
                        if self.guards_against(g, o) && self.cube_overlap(g, o) {
                            out.push((g, o));
                        }
                    }
                    boxes.push(o);
                }
                End::CubeLo => {
                    for &b in &boxes {
                        if self.guards_against(o, b) && self.cube_overlap(o, b) {
                            out.push((o, b));
                        }
                    }
                    cubes.push(o);
                }
                End::BoxHi => boxes.retain(|&b| b != o),
                End::CubeHi => cubes.retain(|&c| c != o),
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Pairs object `id` (just added) with the others.
    pub(super) fn pair_new(&mut self, id: u32, bodies: &Bodies, changes: &mut Vec<PairChange>) {
        for other in 0..bodies.len() as u32 {
            if other == id || !self.present(other) {
                continue;
            }
            if self.wild[id as usize] || self.wild[other as usize] {
                self.link(id, other, 1, changes);
                continue;
            }
            for (g, b) in [(id, other), (other, id)] {
                if self.guards_against(g, b) && self.cube_overlap(g, b) {
                    self.open_watch(bodies, g, b, changes);
                }
            }
        }
    }
}
