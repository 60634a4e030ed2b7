//! Balls joining, leaving and changing flight plans while the structure runs.

use crate::build::Fresh;
use crate::tree::{Item, Kind, ListLayout, NONE, RollingTree, Side, Step};
use crate::tree::{balanced, half_side, key, plan};
use kinetic_core::Real;
use kinetic_core::kds::{Bodies, PairChange};

impl RollingTree {
    fn make_room(&mut self, b: u32, bodies: &Bodies) {
        let need = b as usize + 1;
        if self.leaf.len() < need {
            self.leaf.resize(need, NONE);
            self.radius.resize(need, 0.0);
            self.paths.resize_with(need, Vec::new);
            self.point_item.resize(need, NONE);
        }
        self.radius[b as usize] = bodies[b as usize]
            .as_ref()
            .expect("a live ball")
            .shape
            .outer_radius();
        self.paths[b as usize].clear();
        if self.layout == ListLayout::Global && self.spaces.is_empty() {
            self.spaces.push(Some(Box::default()));
        }
    }

    /// Global layout: a new point item for ball `b`, with its keys.
    fn new_point(&mut self, b: u32, bodies: &Bodies, fresh: &mut Fresh) {
        let id = self.space_mut(0).alloc(Item {
            ball: b,
            node: NONE,
            kind: Kind::Point,
        });
        self.point_item[b as usize] = id;
        let p = plan(bodies, b);
        for (a, ks) in fresh.iter_mut().enumerate() {
            ks.push((id, key(&p, a, 0.0)));
        }
    }

    /// Builds the tree over `ids` at once (the tree is empty).
    pub(crate) fn bulk_build(
        &mut self,
        ids: &[u32],
        bodies: &Bodies,
        now: Real,
        changes: &mut Vec<PairChange>,
    ) {
        self.now = now;
        let mut fresh: Fresh = [Vec::new(), Vec::new()];
        for &b in ids {
            self.make_room(b, bodies);
            if self.layout == ListLayout::Global {
                self.new_point(b, bodies, &mut fresh);
            }
        }
        let mut balls = ids.to_vec();
        self.sort_by_radius(&mut balls);
        self.root = self.build_topology(&balls, NONE, 0);
        self.populate(self.root, bodies, changes, fresh);
    }

    /// One ball joins: it walks down to a leaf, joining a half of each node on the way; the
    /// highest node that this would unbalance is rebuilt instead (or the leaf, which becomes
    /// a node of two).
    pub(crate) fn insert_ball(
        &mut self,
        b: u32,
        bodies: &Bodies,
        now: Real,
        changes: &mut Vec<PairChange>,
    ) {
        self.now = now;
        self.make_room(b, bodies);
        if self.layout == ListLayout::Global {
            let mut fresh: Fresh = [Vec::new(), Vec::new()];
            self.new_point(b, bodies, &mut fresh);
            self.add_global_items(fresh);
        }
        if self.root == NONE {
            self.root = self.build_topology(&[b], NONE, 0);
            return;
        }
        let r = self.radius[b as usize];
        let mut route = Vec::new();
        let mut k = self.root;
        while !self.nodes[k as usize].is_leaf() {
            let side = self.route(k, r);
            route.push((k, side));
            k = self.nodes[k as usize].child[side as usize];
        }
        let scapegoat = route.iter().position(|&(k, side)| {
            let [s, l] = self.halves(k);
            match side {
                Side::Small => !balanced(s + 1, l),
                Side::Large => !balanced(s, l + 1),
            }
        });
        let stop = scapegoat.unwrap_or(route.len());
        for &(k, side) in &route[..stop] {
            self.add_to_node(k, b, side, bodies, changes);
            self.nodes[k as usize].size += 1;
        }
        let target = scapegoat.map_or(k, |i| route[i].0);
        self.rebuild_subtree(target, Some(b), None, bodies, changes);
    }

    /// One ball leaves: it leaves each node on its path, its parent is replaced by its
    /// sibling, or the highest node this would unbalance is rebuilt without it.
    pub(crate) fn remove_ball(
        &mut self,
        b: u32,
        bodies: &Bodies,
        now: Real,
        changes: &mut Vec<PairChange>,
    ) {
        self.now = now;
        let route: Vec<(u32, Side)> = self.paths[b as usize]
            .iter()
            .map(|s| (s.node, s.side))
            .collect();
        let leaf = self.leaf[b as usize];
        if route.is_empty() {
            self.free_node(leaf);
            self.root = NONE;
        } else {
            let last = route.len() - 1;
            let scapegoat = route[..last].iter().position(|&(k, side)| {
                let [s, l] = self.halves(k);
                match side {
                    Side::Small => !balanced(s - 1, l),
                    Side::Large => !balanced(s, l - 1),
                }
            });
            let stop = scapegoat.unwrap_or(route.len());
            for &(k, _) in &route[..stop] {
                self.remove_from_node(k, b, changes);
                self.nodes[k as usize].size -= 1;
            }
            match scapegoat {
                Some(i) => self.rebuild_subtree(route[i].0, None, Some(b), bodies, changes),
                None => self.splice(route[last].0, leaf),
            }
        }
        if self.layout == ListLayout::Global {
            let id = self.point_item[b as usize];
            self.remove_global_items(&[id]);
            self.point_item[b as usize] = NONE;
        }
        self.leaf[b as usize] = NONE;
        self.paths[b as usize].clear();
    }

    /// Replaces node `p`, whose child `leaf` just lost its ball, by `leaf`'s sibling.
    fn splice(&mut self, p: u32, leaf: u32) {
        let n = self.nodes[p as usize];
        let sib = if n.child[0] == leaf {
            n.child[1]
        } else {
            n.child[0]
        };
        let d = n.depth as usize;
        match self.layout {
            ListLayout::PerNode => self.drop_node_items(p),
            // The leaving ball's items are gone already; the sibling's boxes remain.
            ListLayout::Global if sib == n.child[1] => {
                for i in self.balls_of(sib) {
                    let s = self.paths[i as usize][d];
                    self.remove_global_items(&[s.item, s.item2]);
                }
            }
            ListLayout::Global => {}
        }
        for x in self.balls_of(sib) {
            self.paths[x as usize].remove(d);
        }
        for k in self.nodes_of(sib) {
            self.nodes[k as usize].depth -= 1;
        }
        self.attach(n.parent, p, sib);
        self.free_node(leaf);
        self.free_node(p);
    }

    /// The sizes of the two halves of internal node `k`.
    fn halves(&self, k: u32) -> [u32; 2] {
        self.nodes[k as usize]
            .child
            .map(|c| self.nodes[c as usize].size)
    }

    /// Ball `b` joins half `side` of node `k`: its items go into the node's lists, and its
    /// point-in-box containments there become candidate pairs.
    fn add_to_node(
        &mut self,
        k: u32,
        b: u32,
        side: Side,
        bodies: &Bodies,
        changes: &mut Vec<PairChange>,
    ) {
        let n = self.nodes[k as usize];
        let d = n.depth as usize;
        debug_assert_eq!(self.paths[b as usize].len(), d);
        let sp = self.space_of(k);
        let p = plan(bodies, b);
        let mut space = self.spaces[sp].take().expect("a live space");
        let mut step = Step {
            node: k,
            side,
            item: NONE,
            item2: NONE,
            inside: 0,
        };
        self.paths[b as usize].push(step);
        let mut keys: Vec<(u32, Real)> = Vec::new();
        match side {
            Side::Small => {
                step.item = match self.layout {
                    ListLayout::PerNode => {
                        let id = space.alloc(Item {
                            ball: b,
                            node: k,
                            kind: Kind::Point,
                        });
                        keys.push((id, 0.0));
                        id
                    }
                    ListLayout::Global => self.point_item[b as usize],
                };
                self.paths[b as usize][d] = step;
            }
            Side::Large => {
                let (min, max) = self.new_box(&mut space, b, k);
                let h = half_side(self.radius[b as usize], n.rho);
                keys.extend([(min, -h), (max, h)]);
            }
        }
        self.spaces[sp] = Some(space);
        for (id, offset) in keys {
            for a in 0..2 {
                self.with_list(sp, a, |l| {
                    l.insert(id, key(&p, a, offset)).expect("new item")
                });
            }
        }
        match side {
            Side::Small => {
                for i in self.balls_of(n.child[1]) {
                    if self.contains(k, b, i) {
                        changes.push(PairChange {
                            a: b,
                            b: i,
                            delta: 1,
                        });
                        self.paths[b as usize][d].inside += 1;
                    }
                }
                self.max_inside = self.max_inside.max(self.paths[b as usize][d].inside);
            }
            Side::Large => {
                for j in self.balls_of(n.child[0]) {
                    if self.contains(k, j, b) {
                        changes.push(PairChange { a: j, b, delta: 1 });
                        let s = &mut self.paths[j as usize][d];
                        s.inside += 1;
                        self.max_inside = self.max_inside.max(s.inside);
                    }
                }
            }
        }
    }

    /// Ball `b` leaves node `k`: its candidate pairs there go, and its items.
    fn remove_from_node(&mut self, k: u32, b: u32, changes: &mut Vec<PairChange>) {
        let n = self.nodes[k as usize];
        let d = n.depth as usize;
        let step = self.paths[b as usize][d];
        let sp = self.space_of(k);
        let items: Vec<u32> = match step.side {
            Side::Small => {
                for i in self.balls_of(n.child[1]) {
                    if self.contains(k, b, i) {
                        changes.push(PairChange {
                            a: b,
                            b: i,
                            delta: -1,
                        });
                    }
                }
                match self.layout {
                    ListLayout::PerNode => vec![step.item],
                    ListLayout::Global => Vec::new(),
                }
            }
            Side::Large => {
                for j in self.balls_of(n.child[0]) {
                    if self.contains(k, j, b) {
                        changes.push(PairChange { a: j, b, delta: -1 });
                        self.paths[j as usize][d].inside -= 1;
                    }
                }
                vec![step.item, step.item2]
            }
        };
        for id in items {
            for a in 0..2 {
                self.with_list(sp, a, |l| l.remove(id).expect("an item in its list"));
            }
            self.space_mut(sp).release(id);
        }
    }

    /// Ball `b` has a new flight plan: every key of it is replaced; the lists' certificates
    /// next to it fail at once if it is out of place, and swaps move it.
    pub(crate) fn replan_ball(&mut self, b: u32, bodies: &Bodies, now: Real) {
        self.now = now;
        let p = plan(bodies, b);
        let mut keys: Vec<(usize, u32, Real)> = Vec::new();
        for s in &self.paths[b as usize] {
            let sp = self.space_of(s.node);
            match (s.side, self.layout) {
                (Side::Small, ListLayout::PerNode) => keys.push((sp, s.item, 0.0)),
                (Side::Small, ListLayout::Global) => {}
                (Side::Large, _) => {
                    let h = half_side(self.radius[b as usize], self.nodes[s.node as usize].rho);
                    keys.extend([(sp, s.item, -h), (sp, s.item2, h)]);
                }
            }
        }
        if self.layout == ListLayout::Global {
            keys.push((0, self.point_item[b as usize], 0.0));
        }
        for (sp, id, offset) in keys {
            for a in 0..2 {
                self.with_list(sp, a, |l| {
                    l.set_key(id, key(&p, a, offset)).expect("an item")
                });
            }
        }
    }
}
