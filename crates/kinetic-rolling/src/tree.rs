//! The collision tree's types and the small queries the operations share.

use kinetic_core::kds::{Bodies, EventQueue, KineticSortedList, ScalarKey};
use kinetic_core::{FlightPlan, Real};

/// No node, item or ball.
pub(crate) const NONE: u32 = u32::MAX;

/// Threshold boxes are made this much (relatively) larger than the paper's, so that a contact
/// on a box's edge (equal radii meeting along an axis) lies strictly inside it and the box
/// event comes first. Lemma 4's constant is unaffected.
const INFLATE: Real = 1.0 + 1e-9;

/// A weight-balanced node has no half larger than `ALPHA` of it, plus one.
const ALPHA: f64 = 0.75;

/// Where the sorted lists live.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ListLayout {
    /// Two sorted lists (x, y) per node of the collision tree (Theorem 1).
    PerNode,
    /// Two global sorted lists of every tangency point and every threshold box (the paper's
    /// second remark).
    Global,
}

/// The half of a node a ball belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Side {
    /// The smaller balls: tangency points.
    Small = 0,
    /// The larger balls: threshold boxes.
    Large = 1,
}

/// What an item of a sorted list stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    Point,
    Min,
    Max,
}

/// An item of a sorted list: a tangency point, or one side of a threshold box at `node`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Item {
    pub ball: u32,
    /// The node of a box; for a point in the global layout, `NONE` (shared by all nodes).
    pub node: u32,
    pub kind: Kind,
}

/// The sorted lists (x and y) of one node, or the two global ones, with their items.
#[derive(Debug, Default)]
pub(crate) struct Space {
    pub lists: [KineticSortedList; 2],
    pub items: Vec<Item>,
    free: Vec<u32>,
}

impl Space {
    pub(crate) fn alloc(&mut self, item: Item) -> u32 {
        match self.free.pop() {
            Some(id) => {
                self.items[id as usize] = item;
                id
            }
            None => {
                self.items.push(item);
                (self.items.len() - 1) as u32
            }
        }
    }

    pub(crate) fn release(&mut self, id: u32) {
        self.free.push(id);
    }
}

/// A ball's membership in one node on its path from the root.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Step {
    pub node: u32,
    pub side: Side,
    /// The point item (small side) or the box's min item (large side).
    pub item: u32,
    /// The box's max item (large side).
    pub item2: u32,
    /// Small side: how many boxes of the node contain the tangency point.
    pub inside: u32,
}

/// A node of the collision tree; a leaf holds one ball.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Node {
    pub parent: u32,
    pub depth: u32,
    /// `[S, L]` subtrees; `NONE` for a leaf.
    pub child: [u32; 2],
    /// Every ball of `S` is at most `rho`, every ball of `L` at least.
    pub rho: Real,
    pub size: u32,
    /// The ball of a leaf.
    pub ball: u32,
}

impl Node {
    pub(crate) fn is_leaf(&self) -> bool {
        self.child[0] == NONE
    }
}

/// The collision tree of Section 2 as a [`kinetic_core::CandidateStructure`].
#[derive(Debug)]
pub struct RollingTree {
    pub(crate) layout: ListLayout,
    pub(crate) now: Real,
    pub(crate) nodes: Vec<Node>,
    pub(crate) free_nodes: Vec<u32>,
    pub(crate) root: u32,
    /// Per ball: its leaf (`NONE` when absent), radius and path from the root.
    pub(crate) leaf: Vec<u32>,
    pub(crate) radius: Vec<Real>,
    pub(crate) paths: Vec<Vec<Step>>,
    /// Per node (per-node layout) or one (global layout).
    pub(crate) spaces: Vec<Option<Box<Space>>>,
    /// Global layout: each ball's point item.
    pub(crate) point_item: Vec<u32>,
    /// The next swap of each list, keyed by list id `2 * space + axis`.
    pub(crate) queue: EventQueue,
    pub(crate) certs: usize,
    pub(crate) max_inside: u32,
    pub(crate) rebuilds: u64,
    pub(crate) unrelated_swaps: u64,
}

impl RollingTree {
    /// An empty collision tree with the given list layout.
    pub fn new(layout: ListLayout) -> RollingTree {
        RollingTree {
            layout,
            now: 0.0,
            nodes: Vec::new(),
            free_nodes: Vec::new(),
            root: NONE,
            leaf: Vec::new(),
            radius: Vec::new(),
            paths: Vec::new(),
            spaces: Vec::new(),
            point_item: Vec::new(),
            queue: EventQueue::new(),
            certs: 0,
            max_inside: 0,
            rebuilds: 0,
            unrelated_swaps: 0,
        }
    }

    /// The layout of its sorted lists.
    pub fn layout(&self) -> ListLayout {
        self.layout
    }

    /// The largest number of threshold boxes of one node that held one tangency point at
    /// once, so far (Lemma 4 bounds it by a constant).
    pub fn max_boxes_per_point(&self) -> u32 {
        self.max_inside
    }

    /// The depth of the tree (0 for at most one ball).
    pub fn depth(&self) -> u32 {
        self.nodes_of(self.root)
            .iter()
            .map(|&k| self.nodes[k as usize].depth)
            .max()
            .unwrap_or(0)
    }

    /// The number of internal nodes (each with its own detection structure).
    pub fn internal_nodes(&self) -> usize {
        self.nodes_of(self.root)
            .iter()
            .filter(|&&k| !self.nodes[k as usize].is_leaf())
            .count()
    }

    pub(crate) fn space_of(&self, node: u32) -> usize {
        match self.layout {
            ListLayout::PerNode => node as usize,
            ListLayout::Global => 0,
        }
    }

    pub(crate) fn space(&self, sp: usize) -> &Space {
        self.spaces[sp].as_deref().expect("a live space")
    }

    pub(crate) fn space_mut(&mut self, sp: usize) -> &mut Space {
        self.spaces[sp].as_deref_mut().expect("a live space")
    }

    /// The point item of ball `j` in the lists of `node` (where `j` is small).
    pub(crate) fn point_of(&self, j: u32, node: u32) -> u32 {
        match self.layout {
            ListLayout::PerNode => {
                self.paths[j as usize][self.nodes[node as usize].depth as usize].item
            }
            ListLayout::Global => self.point_item[j as usize],
        }
    }

    /// The step of ball `b` at `node`, if `b` is below it.
    pub(crate) fn step_at(&self, b: u32, node: u32) -> Option<&Step> {
        let d = self.nodes[node as usize].depth as usize;
        self.paths[b as usize].get(d).filter(|s| s.node == node)
    }

    /// Whether the tangency point of small ball `j` lies in the threshold box of large ball
    /// `i` at `node`, by the order of the sorted lists (strictly between the box's sides on
    /// both axes).
    pub(crate) fn contains(&self, node: u32, j: u32, i: u32) -> bool {
        self.sides(node, j, i).iter().flatten().all(|&x| x)
    }

    /// Per axis: whether the point of `j` is after the box's min and before its max.
    pub(crate) fn sides(&self, node: u32, j: u32, i: u32) -> [[bool; 2]; 2] {
        let sp = self.space(self.space_of(node));
        let p = self.point_of(j, node);
        let d = self.nodes[node as usize].depth as usize;
        let s = &self.paths[i as usize][d];
        sp.lists.each_ref().map(|l| {
            let pos = |item| l.position(item).expect("an item in its list");
            [pos(s.item) < pos(p), pos(p) < pos(s.item2)]
        })
    }

    /// The balls in the subtree of `node`, in tree order.
    pub(crate) fn balls_of(&self, node: u32) -> Vec<u32> {
        self.nodes_of(node)
            .into_iter()
            .map(|k| self.nodes[k as usize])
            .filter(|n| n.is_leaf())
            .map(|n| n.ball)
            .collect()
    }

    /// The nodes of the subtree of `node`, parents before children.
    pub(crate) fn nodes_of(&self, node: u32) -> Vec<u32> {
        let mut out = Vec::new();
        if node == NONE {
            return out;
        }
        let mut stack = vec![node];
        while let Some(k) = stack.pop() {
            out.push(k);
            let n = &self.nodes[k as usize];
            if !n.is_leaf() {
                stack.push(n.child[1]);
                stack.push(n.child[0]);
            }
        }
        out
    }

    /// The half a ball of radius `r` joins at `node`.
    pub(crate) fn route(&self, node: u32, r: Real) -> Side {
        let n = &self.nodes[node as usize];
        if r < n.rho {
            Side::Small
        } else if r > n.rho {
            Side::Large
        } else if self.nodes[n.child[0] as usize].size <= self.nodes[n.child[1] as usize].size {
            Side::Small
        } else {
            Side::Large
        }
    }

    /// Runs `f` on list `axis` of space `sp` at the current time, then keeps the certificate
    /// count and the global queue up to date.
    pub(crate) fn with_list<R>(
        &mut self,
        sp: usize,
        axis: usize,
        f: impl FnOnce(&mut KineticSortedList) -> R,
    ) -> R {
        let now = self.now;
        let list = &mut self.spaces[sp].as_deref_mut().expect("a live space").lists[axis];
        let before = list.certificates();
        list.advance_clock(now)
            .expect("every swap before now was processed");
        let out = f(list);
        let (after, due) = (list.certificates(), list.next_event_time());
        self.certs = self.certs + after - before;
        self.reschedule(sp, axis, due);
        out
    }

    pub(crate) fn reschedule(&mut self, sp: usize, axis: usize, due: Real) {
        let id = (2 * sp + axis) as u32;
        if due.is_finite() {
            self.queue.schedule(id, due, u64::from(id));
        } else {
            self.queue.remove(id);
        }
    }
}

/// Whether a node with halves of `s` and `l` balls is balanced.
pub(crate) fn balanced(s: u32, l: u32) -> bool {
    s > 0 && l > 0 && f64::from(s.max(l)) <= ALPHA * f64::from(s + l) + 1.0
}

/// Half the side of the threshold box of a ball of radius `r` at a node with `rho`.
pub(crate) fn half_side(r: Real, rho: Real) -> Real {
    2.0 * (r * rho).sqrt() * INFLATE
}

/// The flight plan of a live ball.
pub(crate) fn plan(bodies: &Bodies, b: u32) -> FlightPlan {
    bodies[b as usize].as_ref().expect("a live ball").plan
}

/// The key of coordinate `axis` of a tangency point, moved by `offset`.
pub(crate) fn key(plan: &FlightPlan, axis: usize, offset: Real) -> ScalarKey {
    ScalarKey::from_plan(plan, axis, offset)
}
