//! The k-d tree over the agents from which each agent's nearest neighbours are taken.

use super::{MAX_LEAF, Orca, OrcaAgent};
use crate::math::Vec2;

/// An agent as stored in the k-d tree.
#[derive(Clone, Copy, Debug)]
pub(super) struct TreeAgent {
    pub(super) pos: Vec2,
    pub(super) id: u64,
    pub(super) idx: u32,
}

/// A k-d tree node over `agents[begin..end]` with its bounding box.
#[derive(Clone, Copy, Debug)]
pub(super) struct Node {
    pub(super) begin: u32,
    pub(super) end: u32,
    /// Child node indices; `left == u32::MAX` for a leaf.
    pub(super) left: u32,
    pub(super) right: u32,
    pub(super) min: Vec2,
    pub(super) max: Vec2,
}

/// A neighbour candidate: squared distance, id, index into the caller's agent slice.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Neighbor {
    pub(super) d2: f64,
    pub(super) id: u64,
    pub(super) idx: u32,
}

impl Neighbor {
    #[inline]
    fn before(&self, o: &Neighbor) -> bool {
        (self.d2, self.id, self.idx) < (o.d2, o.id, o.idx)
    }
}

impl Orca {
    /// Rebuilds the k-d tree over the valid agents.
    pub(super) fn build_tree(&mut self, agents: &[OrcaAgent]) {
        self.tree.clear();
        self.nodes.clear();
        self.tree.extend(agents.iter().enumerate().filter(|(_, a)| a.is_valid()).map(|(k, a)| TreeAgent {
            pos: a.pos,
            id: a.id,
            idx: k as u32,
        }));
        if !self.tree.is_empty() {
            self.build_node(0, self.tree.len());
        }
    }

    fn build_node(&mut self, begin: usize, end: usize) -> u32 {
        let mut min = self.tree[begin].pos;
        let mut max = min;
        for t in &self.tree[begin + 1..end] {
            min = min.inf(&t.pos);
            max = max.sup(&t.pos);
        }
        let id = self.nodes.len() as u32;
        self.nodes.push(Node {
            begin: begin as u32,
            end: end as u32,
            left: u32::MAX,
            right: u32::MAX,
            min,
            max,
        });
        if end - begin > MAX_LEAF {
            let axis = if max.x - min.x > max.y - min.y { 0 } else { 1 };
            let split = 0.5 * (min[axis] + max[axis]);
            let (mut l, mut r) = (begin, end);
            while l < r {
                while l < r && self.tree[l].pos[axis] < split {
                    l += 1;
                }
                while r > l && self.tree[r - 1].pos[axis] >= split {
                    r -= 1;
                }
                if l < r {
                    self.tree.swap(l, r - 1);
                    l += 1;
                    r -= 1;
                }
            }
            let mid = if l == begin || l == end { begin + (end - begin) / 2 } else { l };
            let left = self.build_node(begin, mid);
            let right = self.build_node(mid, end);
            self.nodes[id as usize].left = left;
            self.nodes[id as usize].right = right;
        }
        id
    }

    /// Fills `self.neighbors` with up to `max_neighbors` agents other than `self_idx` closer than
    /// `neighbor_dist` to `pos`, sorted by (squared distance, id, index).
    pub(super) fn query_neighbors(&mut self, pos: Vec2, self_idx: usize) {
        self.neighbors.clear();
        if self.params.max_neighbors == 0 || self.nodes.is_empty() {
            return;
        }
        let range = self.params.neighbor_dist * self.params.neighbor_dist;
        let mut q = Query {
            tree: &self.tree,
            nodes: &self.nodes,
            pos,
            self_idx: self_idx as u32,
            max: self.params.max_neighbors,
            range,
            out: &mut self.neighbors,
        };
        q.visit(0);
    }
}

pub(super) struct Query<'a> {
    tree: &'a [TreeAgent],
    nodes: &'a [Node],
    pos: Vec2,
    self_idx: u32,
    max: usize,
    range: f64,
    out: &'a mut Vec<Neighbor>,
}

impl Query<'_> {
    #[inline]
    fn box_dist2(&self, n: &Node) -> f64 {
        let dx = (n.min.x - self.pos.x).max(0.0) + (self.pos.x - n.max.x).max(0.0);
        let dy = (n.min.y - self.pos.y).max(0.0) + (self.pos.y - n.max.y).max(0.0);
        dx * dx + dy * dy
    }

    /// Current pruning bound: the range, or the k-th distance once the list is full.
    #[inline]
    fn bound(&self) -> f64 {
        if self.out.len() == self.max { self.out[self.max - 1].d2 } else { self.range }
    }

    fn visit(&mut self, node: u32) {
        let n = self.nodes[node as usize];
        if n.left == u32::MAX {
            for t in &self.tree[n.begin as usize..n.end as usize] {
                if t.idx == self.self_idx {
                    continue;
                }
                let d2 = (t.pos - self.pos).norm_squared();
                if d2 >= self.range || d2.is_nan() {
                    continue;
                }
                let cand = Neighbor { d2, id: t.id, idx: t.idx };
                if self.out.len() == self.max {
                    if !cand.before(&self.out[self.max - 1]) {
                        continue;
                    }
                    self.out.pop();
                }
                let mut k = self.out.len();
                self.out.push(cand);
                while k > 0 && cand.before(&self.out[k - 1]) {
                    self.out[k] = self.out[k - 1];
                    k -= 1;
                }
                self.out[k] = cand;
            }
            return;
        }
        let (l, r) = (n.left, n.right);
        let dl = self.box_dist2(&self.nodes[l as usize]);
        let dr = self.box_dist2(&self.nodes[r as usize]);
        let (first, d_first, second, d_second) = if dl <= dr { (l, dl, r, dr) } else { (r, dr, l, dl) };
        if d_first <= self.bound() {
            self.visit(first);
            if d_second <= self.bound() {
                self.visit(second);
            }
        }
    }
}
