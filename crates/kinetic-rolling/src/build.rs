//! Building: the whole tree at once, and rebuilding a subtree (partial rebuilding keeps the
//! tree balanced).

use crate::tree::{Item, Kind, ListLayout, NONE, Node, RollingTree, Side, Space, Step};
use crate::tree::{half_side, key, plan};
use kinetic_core::kds::{Bodies, KineticSortedList, PairChange, ScalarKey};
use rustc_hash::FxHashMap;

/// New list items and their keys, per axis.
pub(crate) type Fresh = [Vec<(u32, ScalarKey)>; 2];

impl RollingTree {
    /// Builds the topology over `balls` (sorted by radius, then id) below `parent`; returns
    /// the subtree's root. The paths of the balls get one step per new internal node.
    pub(crate) fn build_topology(&mut self, balls: &[u32], parent: u32, depth: u32) -> u32 {
        let k = self.alloc_node(Node {
            parent,
            depth,
            child: [NONE; 2],
            rho: 0.0,
            size: balls.len() as u32,
            ball: NONE,
        });
        if let [b] = balls {
            self.nodes[k as usize].ball = *b;
            self.leaf[*b as usize] = k;
            return k;
        }
        // The paper's split: the floor(n/2) smallest balls and the ceil(n/2) largest.
        let (small, large) = balls.split_at(balls.len() / 2);
        self.nodes[k as usize].rho = self.radius[large[0] as usize];
        for (half, side) in [(small, Side::Small), (large, Side::Large)] {
            for &b in half {
                debug_assert_eq!(self.paths[b as usize].len(), depth as usize);
                self.paths[b as usize].push(Step {
                    node: k,
                    side,
                    item: NONE,
                    item2: NONE,
                    inside: 0,
                });
            }
        }
        let s = self.build_topology(small, k, depth + 1);
        let l = self.build_topology(large, k, depth + 1);
        self.nodes[k as usize].child = [s, l];
        k
    }

    fn alloc_node(&mut self, node: Node) -> u32 {
        let k = match self.free_nodes.pop() {
            Some(k) => {
                self.nodes[k as usize] = node;
                k
            }
            None => {
                self.nodes.push(node);
                (self.nodes.len() - 1) as u32
            }
        };
        if self.layout == ListLayout::PerNode && self.spaces.len() <= k as usize {
            self.spaces.resize_with(k as usize + 1, || None);
        }
        k
    }

    /// Gives every internal node of the subtree `root` its list items (plus the `fresh` ones
    /// the caller made) and reports its contained (point, box) pairs as new candidates.
    pub(crate) fn populate(
        &mut self,
        root: u32,
        bodies: &Bodies,
        changes: &mut Vec<PairChange>,
        mut fresh: Fresh,
    ) {
        let internal: Vec<u32> = self
            .nodes_of(root)
            .into_iter()
            .filter(|&k| !self.nodes[k as usize].is_leaf())
            .collect();
        for &k in &internal {
            match self.layout {
                ListLayout::PerNode => self.fill_node_space(k, bodies),
                ListLayout::Global => self.make_boxes(k, bodies, &mut fresh),
            }
        }
        if self.layout == ListLayout::Global {
            self.add_global_items(fresh);
        }
        for &k in &internal {
            let d = self.nodes[k as usize].depth as usize;
            for (j, i) in self.node_pairs(k) {
                changes.push(PairChange {
                    a: j,
                    b: i,
                    delta: 1,
                });
                let step = &mut self.paths[j as usize][d];
                step.inside += 1;
                self.max_inside = self.max_inside.max(step.inside);
            }
        }
    }

    /// Per-node layout: the node's own two lists, built sorted in one go.
    fn fill_node_space(&mut self, k: u32, bodies: &Bodies) {
        let n = self.nodes[k as usize];
        let d = n.depth as usize;
        let mut space = Space::default();
        let mut keys: Fresh = [Vec::new(), Vec::new()];
        for j in self.balls_of(n.child[0]) {
            let id = space.alloc(Item {
                ball: j,
                node: k,
                kind: Kind::Point,
            });
            self.paths[j as usize][d].item = id;
            let p = plan(bodies, j);
            for (a, ks) in keys.iter_mut().enumerate() {
                ks.push((id, key(&p, a, 0.0)));
            }
        }
        self.new_boxes(&mut space, k, bodies, &mut keys);
        for (a, ks) in keys.into_iter().enumerate() {
            space.lists[a] =
                KineticSortedList::from_items(self.now, ks).expect("finite keys, distinct ids");
        }
        let due = space.lists.each_ref().map(|l| l.next_event_time());
        self.certs += space.lists.iter().map(|l| l.certificates()).sum::<usize>();
        self.spaces[k as usize] = Some(Box::new(space));
        for (a, t) in due.into_iter().enumerate() {
            self.reschedule(k as usize, a, t);
        }
    }

    /// Allocates the two items of ball `i`'s box at node `k` and records them in its path.
    pub(crate) fn new_box(&mut self, space: &mut Space, i: u32, k: u32) -> (u32, u32) {
        let item = |kind| Item {
            ball: i,
            node: k,
            kind,
        };
        let (min, max) = (space.alloc(item(Kind::Min)), space.alloc(item(Kind::Max)));
        let d = self.nodes[k as usize].depth as usize;
        let step = &mut self.paths[i as usize][d];
        (step.item, step.item2) = (min, max);
        (min, max)
    }

    /// The boxes of every large ball of node `k`: new items in `space`, their keys in `keys`.
    fn new_boxes(&mut self, space: &mut Space, k: u32, bodies: &Bodies, keys: &mut Fresh) {
        let n = self.nodes[k as usize];
        for i in self.balls_of(n.child[1]) {
            let (min, max) = self.new_box(space, i, k);
            let h = half_side(self.radius[i as usize], n.rho);
            let p = plan(bodies, i);
            for (a, ks) in keys.iter_mut().enumerate() {
                ks.push((min, key(&p, a, -h)));
                ks.push((max, key(&p, a, h)));
            }
        }
    }

    /// Global layout: the boxes of node `k`, added to `fresh`.
    fn make_boxes(&mut self, k: u32, bodies: &Bodies, fresh: &mut Fresh) {
        let mut space = self.spaces[0].take().expect("the global space");
        self.new_boxes(&mut space, k, bodies, fresh);
        self.spaces[0] = Some(space);
    }

    /// Global layout: new items go into the global lists, in bulk when they are empty.
    pub(crate) fn add_global_items(&mut self, fresh: Fresh) {
        for (a, ks) in fresh.into_iter().enumerate() {
            if self.space(0).lists[a].is_empty() {
                self.with_list(0, a, |l| {
                    let now = l.now();
                    *l = KineticSortedList::from_items(now, ks).expect("finite keys, distinct ids");
                });
            } else {
                for (id, k) in ks {
                    self.with_list(0, a, |l| l.insert(id, k).expect("a new item"));
                }
            }
        }
    }

    /// The (small ball, large ball) pairs of node `k` whose point lies in the box, by a sweep
    /// along the x list.
    pub(crate) fn node_pairs(&self, k: u32) -> Vec<(u32, u32)> {
        let n = self.nodes[k as usize];
        let d = n.depth as usize;
        let lx = &self.space(self.space_of(k)).lists[0];
        let pos = |item| lx.position(item).expect("an item in its list");
        let mut sweep: Vec<(usize, u8, u32)> = Vec::new();
        for j in self.balls_of(n.child[0]) {
            sweep.push((pos(self.point_of(j, k)), 1, j));
        }
        for i in self.balls_of(n.child[1]) {
            let s = &self.paths[i as usize][d];
            sweep.push((pos(s.item), 0, i));
            sweep.push((pos(s.item2), 2, i));
        }
        sweep.sort_unstable();
        let mut open: Vec<u32> = Vec::new();
        let mut slot: FxHashMap<u32, usize> = FxHashMap::default();
        let mut out = Vec::new();
        for (_, tag, b) in sweep {
            match tag {
                0 => {
                    slot.insert(b, open.len());
                    open.push(b);
                }
                2 => {
                    if let Some(s) = slot.remove(&b) {
                        open.swap_remove(s);
                        if let Some(&moved) = open.get(s) {
                            slot.insert(moved, s);
                        }
                    }
                }
                _ => out.extend(
                    open.iter()
                        .filter(|&&i| self.contains(k, b, i))
                        .map(|&i| (b, i)),
                ),
            }
        }
        out
    }

    /// Rebuilds the subtree of `u` from scratch over its balls, plus `extra`, less `exclude`:
    /// the new candidate pairs are reported before the old ones are let go, so pairs in both
    /// keep their certificates.
    pub(crate) fn rebuild_subtree(
        &mut self,
        u: u32,
        extra: Option<u32>,
        exclude: Option<u32>,
        bodies: &Bodies,
        changes: &mut Vec<PairChange>,
    ) {
        let Node { parent, depth, .. } = self.nodes[u as usize];
        let mut balls = self.balls_of(u);
        if balls.len() > 1 {
            self.rebuilds += 1;
        }
        balls.retain(|&b| Some(b) != exclude);
        balls.extend(extra);
        let mut gone = Vec::new();
        self.teardown(u, &mut gone);
        self.sort_by_radius(&mut balls);
        let new = if balls.is_empty() {
            NONE
        } else {
            self.build_topology(&balls, parent, depth)
        };
        self.attach(parent, u, new);
        if new != NONE {
            self.populate(new, bodies, changes, [Vec::new(), Vec::new()]);
        }
        changes.extend(gone);
    }

    /// Sorts balls by radius, then id: the order the tree splits in.
    pub(crate) fn sort_by_radius(&self, balls: &mut [u32]) {
        balls.sort_by(|&x, &y| {
            self.radius[x as usize]
                .total_cmp(&self.radius[y as usize])
                .then(x.cmp(&y))
        });
    }

    /// Puts `new` where `old` was below `parent` (or at the root).
    pub(crate) fn attach(&mut self, parent: u32, old: u32, new: u32) {
        if parent == NONE {
            self.root = new;
        } else {
            let p = &mut self.nodes[parent as usize];
            let c = if p.child[0] == old { 0 } else { 1 };
            p.child[c] = new;
        }
        if new != NONE {
            self.nodes[new as usize].parent = parent;
        }
    }

    /// Removes the subtree of `u` with its list items; its candidate pairs go to `gone` as
    /// removals. The balls' paths are cut at `u`'s depth.
    pub(crate) fn teardown(&mut self, u: u32, gone: &mut Vec<PairChange>) {
        let nodes = self.nodes_of(u);
        for &k in &nodes {
            if !self.nodes[k as usize].is_leaf() {
                gone.extend(self.node_pairs(k).into_iter().map(|(a, b)| PairChange {
                    a,
                    b,
                    delta: -1,
                }));
            }
        }
        for &k in &nodes {
            if !self.nodes[k as usize].is_leaf() {
                self.drop_node_items(k);
            }
        }
        let depth = self.nodes[u as usize].depth as usize;
        for b in self.balls_of(u) {
            self.paths[b as usize].truncate(depth);
        }
        for k in nodes {
            self.free_node(k);
        }
    }

    /// Removes the list items of internal node `k` (its own lists, or its boxes in the
    /// global lists).
    pub(crate) fn drop_node_items(&mut self, k: u32) {
        match self.layout {
            ListLayout::PerNode => {
                if let Some(space) = self.spaces[k as usize].take() {
                    self.certs -= space.lists.iter().map(|l| l.certificates()).sum::<usize>();
                    for a in 0..2 {
                        self.reschedule(k as usize, a, f64::INFINITY);
                    }
                }
            }
            ListLayout::Global => {
                let d = self.nodes[k as usize].depth as usize;
                for i in self.balls_of(self.nodes[k as usize].child[1]) {
                    let s = self.paths[i as usize][d];
                    self.remove_global_items(&[s.item, s.item2]);
                }
            }
        }
    }

    /// Global layout: removes items from both lists and frees their ids.
    pub(crate) fn remove_global_items(&mut self, items: &[u32]) {
        for &id in items {
            for a in 0..2 {
                self.with_list(0, a, |l| l.remove(id).expect("an item in its list"));
            }
            self.space_mut(0).release(id);
        }
    }

    pub(crate) fn free_node(&mut self, k: u32) {
        let n = self.nodes[k as usize];
        if n.is_leaf() && n.ball != NONE && self.leaf[n.ball as usize] == k {
            self.leaf[n.ball as usize] = NONE;
        }
        self.nodes[k as usize] = Node {
            parent: NONE,
            depth: 0,
            child: [NONE; 2],
            rho: 0.0,
            size: 0,
            ball: NONE,
        };
        self.free_nodes.push(k);
    }
}
