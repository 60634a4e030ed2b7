//! The cells: home cells and their member lists, blocks and their visitors, and when a
//! centre or a block end next crosses a grid line.

use super::{Block, ElasticCells, Event, Level, NIL, Next, WIDEN};
use kinetic_core::Real;

impl ElasticCells {
    /// The cells of level `l` next to `home` (the 27 about it, clipped to the grid): the
    /// first and last per axis.
    pub(super) fn around(l: &Level, home: [u32; 3]) -> ([u32; 3], [u32; 3]) {
        let lo = home.map(|c| c.saturating_sub(1));
        let hi = [0, 1, 2].map(|k| (home[k] + 1).min(l.n[k] - 1));
        (lo, hi)
    }

    /// Pushes the home members (other than `skip`) of the cells `lo..=hi` of level `l`.
    pub(super) fn members(
        &self,
        l: &Level,
        lo: [u32; 3],
        hi: [u32; 3],
        skip: u32,
        out: &mut Vec<u32>,
    ) {
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                for x in lo[0]..=hi[0] {
                    let mut o = l.head[l.index([x, y, z]) as usize];
                    while o != NIL {
                        if o != skip {
                            out.push(o);
                        }
                        o = self.link[o as usize][0];
                    }
                }
            }
        }
    }

    /// The cell of coordinate `x` along `axis` at `level`, clamped to the grid.
    #[inline]
    pub(super) fn cell_along(&self, level: u8, axis: usize, x: Real) -> u32 {
        let l = &self.levels[level as usize];
        let c = ((x - self.walls.min[axis]) / l.cell[axis]).floor();
        if c <= 0.0 {
            0
        } else {
            (c as u32).min(l.n[axis] - 1)
        }
    }

    /// The home cell of ball `id` now, from its position.
    pub(super) fn home_of(&self, id: u32) -> [u32; 3] {
        let p = self.plans[id as usize].position_at(self.now);
        let l = self.level[id as usize];
        [0, 1, 2].map(|k| self.cell_along(l, k, p[k]))
    }

    /// The block of ball `id` at finer level `level` now, from its position.
    pub(super) fn block_of(&self, id: u32, level: u8) -> Block {
        let p = self.plans[id as usize].position_at(self.now);
        let h = self.reach(id, level);
        Block {
            level,
            lo: [0, 1, 2].map(|k| self.cell_along(level, k, p[k] - h)),
            hi: [0, 1, 2].map(|k| self.cell_along(level, k, p[k] + h)),
        }
    }

    /// Half the side of ball `id`'s block at finer level `level`.
    #[inline]
    fn reach(&self, id: u32, level: u8) -> Real {
        (self.radius[id as usize] + self.levels[level as usize].r_max) * (1.0 + WIDEN)
    }

    pub(super) fn link_in(&mut self, id: u32) {
        let l = &mut self.levels[self.level[id as usize] as usize];
        let cell = l.index(self.home[id as usize]) as usize;
        let first = l.head[cell];
        l.head[cell] = id;
        self.link[id as usize] = [first, NIL];
        if first != NIL {
            self.link[first as usize][1] = id;
        }
    }

    pub(super) fn link_out(&mut self, id: u32) {
        let [next, prev] = self.link[id as usize];
        if prev == NIL {
            let l = &mut self.levels[self.level[id as usize] as usize];
            let cell = l.index(self.home[id as usize]) as usize;
            l.head[cell] = next;
        } else {
            self.link[prev as usize][0] = next;
        }
        if next != NIL {
            self.link[next as usize][1] = prev;
        }
        self.link[id as usize] = [NIL, NIL];
    }

    /// Adds (or removes) ball `id` as a visitor of the cells of `block` whose coordinate
    /// along `axis` is `at` (every cell of the block with `axis` = 3, see [`Self::visit`]).
    fn visit_slab(&mut self, id: u32, block: &Block, axis: usize, at: u32, add: bool) {
        let l = &mut self.levels[block.level as usize];
        let (mut lo, mut hi) = (block.lo, block.hi);
        if axis < 3 {
            (lo[axis], hi[axis]) = (at, at);
        }
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                for x in lo[0]..=hi[0] {
                    let cell = l.index([x, y, z]);
                    if add {
                        l.visitors.entry(cell).or_default().push(id);
                    } else if let Some(list) = l.visitors.get_mut(&cell) {
                        if let Some(i) = list.iter().position(|&v| v == id) {
                            list.swap_remove(i);
                        }
                        if list.is_empty() {
                            l.visitors.remove(&cell);
                        }
                    }
                }
            }
        }
    }

    pub(super) fn visit(&mut self, id: u32, block: &Block, add: bool) {
        self.visit_slab(id, block, 3, 0, add);
    }

    /// An end of ball `id`'s block at `level` crossed a grid line along `axis`.
    pub(super) fn move_block(&mut self, id: u32, level: u8, axis: usize, hi: bool, up: bool) {
        let i = id as usize;
        let Some(k) = self.blocks[i].iter().position(|b| b.level == level) else {
            return;
        };
        let mut b = self.blocks[i][k];
        match (hi, up) {
            (true, true) => {
                b.hi[axis] += 1;
                self.visit_slab(id, &b, axis, b.hi[axis], true);
            }
            (true, false) => {
                self.visit_slab(id, &b, axis, b.hi[axis], false);
                b.hi[axis] -= 1;
            }
            (false, true) => {
                self.visit_slab(id, &b, axis, b.lo[axis], false);
                b.lo[axis] += 1;
            }
            (false, false) => {
                b.lo[axis] -= 1;
                self.visit_slab(id, &b, axis, b.lo[axis], true);
            }
        }
        self.blocks[i][k] = b;
    }

    /// The time the coordinate `axis` of ball `id`'s centre, offset by `shift`, reaches the
    /// grid line `line` of `level` (moving up when `up`), not before now.
    #[inline]
    fn line_time(&self, id: u32, axis: usize, shift: Real, level: u8, line: u32) -> Real {
        let plan = &self.plans[id as usize];
        let g = self.walls.min[axis] + line as Real * self.levels[level as usize].cell[axis];
        let t = plan.t0 + (g - (plan.position[axis] + shift)) / plan.velocity[axis];
        t.max(self.now)
    }

    /// Ball `id`'s next cell event: its centre leaving its home cell, or an end of one of
    /// its blocks crossing a grid line.
    pub(super) fn cell_event(&self, id: u32) -> Next {
        let i = id as usize;
        let v = self.plans[i].velocity;
        let level = self.level[i];
        let n = self.levels[level as usize].n;
        let mut best = Next::IDLE;
        let mut take = |time: Real, event: Event| {
            if time < best.time {
                best = Next {
                    time,
                    tie: 0,
                    event,
                };
            }
        };
        let home = self.home[i];
        for k in 0..3 {
            if v[k] > 0.0 && home[k] + 1 < n[k] {
                let t = self.line_time(id, k, 0.0, level, home[k] + 1);
                take(
                    t,
                    Event::Home {
                        axis: k as u8,
                        up: true,
                    },
                );
            } else if v[k] < 0.0 && home[k] > 0 {
                let t = self.line_time(id, k, 0.0, level, home[k]);
                take(
                    t,
                    Event::Home {
                        axis: k as u8,
                        up: false,
                    },
                );
            }
        }
        for b in &self.blocks[i] {
            let h = self.reach(id, b.level);
            let n = self.levels[b.level as usize].n;
            for k in 0..3 {
                let ax = k as u8;
                let level = b.level;
                if v[k] > 0.0 {
                    if b.lo[k] + 1 < n[k] {
                        let t = self.line_time(id, k, -h, level, b.lo[k] + 1);
                        take(
                            t,
                            Event::Block {
                                level,
                                axis: ax,
                                hi: false,
                                up: true,
                            },
                        );
                    }
                    if b.hi[k] + 1 < n[k] {
                        let t = self.line_time(id, k, h, level, b.hi[k] + 1);
                        take(
                            t,
                            Event::Block {
                                level,
                                axis: ax,
                                hi: true,
                                up: true,
                            },
                        );
                    }
                } else if v[k] < 0.0 {
                    if b.lo[k] > 0 {
                        let t = self.line_time(id, k, -h, level, b.lo[k]);
                        take(
                            t,
                            Event::Block {
                                level,
                                axis: ax,
                                hi: false,
                                up: false,
                            },
                        );
                    }
                    if b.hi[k] > 0 {
                        let t = self.line_time(id, k, h, level, b.hi[k]);
                        take(
                            t,
                            Event::Block {
                                level,
                                axis: ax,
                                hi: true,
                                up: false,
                            },
                        );
                    }
                }
            }
        }
        best
    }

    /// The balls that can touch ball `id` before its next cell event: the home members of
    /// its 27 neighbour cells, the coarser balls visiting its home cell, and the home members
    /// of its blocks' cells.
    pub(super) fn neighbours(&self, id: u32, out: &mut Vec<u32>) {
        let i = id as usize;
        let l = &self.levels[self.level[i] as usize];
        let home = self.home[i];
        let (lo, hi) = Self::around(l, home);
        self.members(l, lo, hi, id, out);
        if let Some(v) = l.visitors.get(&l.index(home)) {
            out.extend_from_slice(v);
        }
        for b in &self.blocks[i] {
            self.members(&self.levels[b.level as usize], b.lo, b.hi, id, out);
        }
    }
}
