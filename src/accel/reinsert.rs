//! Insertion-based optimisation of a built BVH: subtrees are taken out and put back where the
//! tree's SAH cost drops most (the reinsertion move of Bittner, Hapala and Havran 2013, with the
//! parallel search of Meister and Bittner 2018). This module owns the move, its branch-and-bound
//! search, the passes that apply it and the re-flattening into the builder's node order
//! (depth first, siblings adjacent, children after their parent). It sees only boxes and
//! topology ([`TreeNode`]); `crate::accel::bvh` runs [`optimize`] after a binned-SAH build
//! (`BuildConfig::reinsertion_passes`) and moves the leaves' primitives along.
//!
//! # The move
//!
//! Taking node `N` out frees its parent `P` (the sibling `S` takes `P`'s place) and shrinks the
//! ancestors above; putting `N` back as the sibling of node `X` reuses `P` as their new parent
//! and grows `X`'s ancestors. Leaves keep their primitives, so only interior areas change and
//! the move's gain is exact: `removal = A(P) + sum of the ancestors' shrinkage` against
//! `insertion = A(X ∪ N) + sum of X's ancestors' growth`. A move is applied only if it lowers
//! the cost and keeps the tree's depth below the caller's limit, so the cost never rises and
//! the builder's depth bound still holds.
//!
//! # A pass
//!
//! Every node but the root searches, in parallel on the frozen tree, for its best new sibling
//! (best-first from the root, pruned by the lower bound `induced cost + A(N)`, at most
//! [`SEARCH_LIMIT`] nodes expanded). The proposals are then applied one by one, best gain
//! first, each re-evaluated on the tree as it is by then (an earlier move may have changed it),
//! so the result depends only on the input. Passes stop when one gains less than
//! [`MIN_PASS_GAIN`] of the cost. Trees of more than [`MAX_OPTIMIZED_NODES`] nodes are left as
//! built (see there).

use glam::Vec3;
use rayon::prelude::*;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Most nodes one search expands. Bounds a pass at `nodes * SEARCH_LIMIT` expansions.
pub(crate) const SEARCH_LIMIT: usize = 64;
/// A pass that lowers the cost by less than this fraction ends the optimisation.
pub(crate) const MIN_PASS_GAIN: f64 = 0.002;
/// Trees with more nodes than this are not optimised. A pass costs about one build (each
/// node's search expands up to [`SEARCH_LIMIT`] nodes): on 2 cores two passes add 0.17 s to the
/// atrium's 262k triangles and 1.3 s to 1.9M, so above ~4M triangles (10M+ scenes) they would
/// add many seconds to every rebuild for the same few percent of SAH cost.
pub(crate) const MAX_OPTIMIZED_NODES: usize = 4 << 20;

const NONE: u32 = u32::MAX;

/// An axis-aligned box (never empty here: every node holds a primitive).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Bounds {
    pub(crate) min: Vec3,
    pub(crate) max: Vec3,
}

impl Bounds {
    fn union(&self, o: &Bounds) -> Bounds {
        Bounds { min: self.min.min(o.min), max: self.max.max(o.max) }
    }

    /// Surface area, as `Bounds::surface_area` computes it (f32), widened for summing.
    fn area(&self) -> f64 {
        let d = self.max - self.min;
        (2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)) as f64
    }
}

/// A node as the optimiser reads and writes it: its box, the index of its first child for an
/// interior node (the second follows), and the index it had in the input (a leaf's primitives
/// stay with it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TreeNode {
    pub(crate) bounds: Bounds,
    pub(crate) first_child: Option<u32>,
    pub(crate) source: u32,
}

/// Optimises the tree `nodes` (root at 0, children after their parent) with at most `passes`
/// passes, keeping its depth below `depth_limit`; returns its nodes in the builder's order, or
/// `None` for a tree of fewer than 3 or more than [`MAX_OPTIMIZED_NODES`] nodes.
pub(crate) fn optimize(nodes: &[TreeNode], passes: usize, depth_limit: usize) -> Option<Vec<TreeNode>> {
    if passes == 0 || nodes.len() < 3 || nodes.len() > MAX_OPTIMIZED_NODES {
        return None;
    }
    let mut tree = LinkedTree::new(nodes, depth_limit);
    let mut cost = tree.cost();
    for _ in 0..passes {
        let gain = tree.pass();
        cost -= gain;
        if gain <= MIN_PASS_GAIN * cost {
            break;
        }
    }
    Some(tree.flatten(nodes))
}

/// A tree with parent links, in the input's node indices (a move reuses the freed parent).
struct LinkedTree {
    bounds: Vec<Bounds>,
    parent: Vec<u32>,
    /// `[NONE, NONE]` for a leaf.
    children: Vec<[u32; 2]>,
    /// Levels below the node (0 for a leaf).
    height: Vec<u8>,
    root: u32,
    /// No move may make a leaf this deep.
    depth_limit: usize,
}

/// What taking a node out changes: its parent goes, its sibling takes the parent's place, and
/// `shrunk` ancestors (nearest first) get smaller boxes.
struct Removal {
    node: u32,
    parent: u32,
    sibling: u32,
    /// Cost that the removal saves: the parent's area and the ancestors' shrinkage.
    saving: f64,
    shrunk: Vec<(u32, Bounds)>,
}

/// A proposed move: `node` becomes the sibling of `target`, saving `gain`.
struct Proposal {
    node: u32,
    target: u32,
    gain: f64,
}

/// A node waiting in the search, with the growth its insertion causes above it.
#[derive(PartialEq)]
struct Candidate {
    induced: f64,
    node: u32,
}

impl Eq for Candidate {}

impl Ord for Candidate {
    /// Reversed: the smallest induced cost (then the smallest index) comes first.
    fn cmp(&self, o: &Self) -> Ordering {
        o.induced.total_cmp(&self.induced).then(o.node.cmp(&self.node))
    }
}

impl PartialOrd for Candidate {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

impl LinkedTree {
    fn new(nodes: &[TreeNode], depth_limit: usize) -> Self {
        let mut tree = LinkedTree {
            bounds: nodes.iter().map(|n| n.bounds).collect(),
            parent: vec![NONE; nodes.len()],
            children: vec![[NONE, NONE]; nodes.len()],
            height: vec![0; nodes.len()],
            root: 0,
            depth_limit,
        };
        for (i, n) in nodes.iter().enumerate() {
            if let Some(left) = n.first_child {
                tree.children[i] = [left, left + 1];
                tree.parent[left as usize] = i as u32;
                tree.parent[left as usize + 1] = i as u32;
            }
        }
        for i in (0..nodes.len()).rev() {
            tree.height[i] = tree.height_from_children(i as u32);
        }
        tree
    }

    fn is_leaf(&self, n: u32) -> bool {
        self.children[n as usize][0] == NONE
    }

    fn sibling(&self, n: u32) -> u32 {
        let [a, b] = self.children[self.parent[n as usize] as usize];
        if a == n {
            b
        } else {
            a
        }
    }

    fn height_from_children(&self, n: u32) -> u8 {
        let [a, b] = self.children[n as usize];
        if a == NONE {
            0
        } else {
            1 + self.height[a as usize].max(self.height[b as usize])
        }
    }

    /// Sum of the interior nodes' areas: the part of the SAH cost that moves change.
    fn cost(&self) -> f64 {
        (0..self.bounds.len() as u32).filter(|&n| !self.is_leaf(n)).map(|n| self.bounds[n as usize].area()).sum()
    }

    /// One pass: a proposal per node from the frozen tree, then the moves that still gain.
    /// Returns the cost saved.
    fn pass(&mut self) -> f64 {
        let root = self.root;
        let frozen = &*self;
        let mut proposals: Vec<Proposal> = (0..frozen.bounds.len() as u32).into_par_iter().filter(|&n| n != root).filter_map(|n| frozen.best_move(n)).collect();
        proposals.sort_by(|a, b| b.gain.total_cmp(&a.gain).then(a.node.cmp(&b.node)));
        proposals.iter().map(|p| self.apply(p)).sum()
    }

    /// The removal of `node` (not the root), read off the tree without changing it.
    fn removal(&self, node: u32) -> Removal {
        let parent = self.parent[node as usize];
        let sibling = self.sibling(node);
        let mut saving = self.bounds[parent as usize].area();
        let mut shrunk = Vec::new();
        let (mut below, mut below_box) = (parent, self.bounds[sibling as usize]);
        let mut above = self.parent[parent as usize];
        while above != NONE {
            let [a, b] = self.children[above as usize];
            let other = if a == below { b } else { a };
            let new_box = below_box.union(&self.bounds[other as usize]);
            let old_box = self.bounds[above as usize];
            if new_box == old_box {
                break;
            }
            saving += old_box.area() - new_box.area();
            shrunk.push((above, new_box));
            (below, below_box, above) = (above, new_box, self.parent[above as usize]);
        }
        Removal { node, parent, sibling, saving, shrunk }
    }

    /// The box of `n` once `removal` is done.
    fn box_after(&self, removal: &Removal, n: u32) -> Bounds {
        removal.shrunk.iter().find(|(m, _)| *m == n).map_or(self.bounds[n as usize], |(_, b)| *b)
    }

    /// The best new sibling for `node`, if moving there saves anything. The search walks from
    /// `node` up to the root and searches, best first, the subtree hanging off each ancestor
    /// (nearest first, so local moves are found within the budget of [`SEARCH_LIMIT`]
    /// expansions). An ancestor at or above a new sibling gets its old box back, so its
    /// shrinkage and growth cancel: a target below the path's level `k` gains the parent's
    /// area and the shrinkage below `k`, less its own cost within the subtree.
    fn best_move(&self, node: u32) -> Option<Proposal> {
        let removal = self.removal(node);
        let node_box = self.bounds[node as usize];
        let mut search = Search::new(node_box);
        let mut saving = self.bounds[removal.parent as usize].area();
        self.search_subtree(&mut search, removal.sibling, saving, true);
        let (mut below, mut above) = (removal.parent, self.parent[removal.parent as usize]);
        let mut level = 0;
        while above != NONE && search.expansions_left > 0 {
            let [a, b] = self.children[above as usize];
            let off_path = if a == below { b } else { a };
            self.search_subtree(&mut search, off_path, saving, false);
            if let Some((_, new_box)) = removal.shrunk.get(level) {
                saving += self.bounds[above as usize].area() - new_box.area();
            }
            search.offer(above, saving - self.bounds[above as usize].area());
            (below, above, level) = (above, self.parent[above as usize], level + 1);
        }
        (search.best_target != NONE).then_some(Proposal { node, target: search.best_target, gain: search.best_gain })
    }

    /// Best-first search below `top` (itself included unless `skip_top`), which the removal
    /// leaves as it was: a target's gain is `saving` less its merged area and the growth of its
    /// ancestors up to `top`.
    fn search_subtree(&self, search: &mut Search, top: u32, saving: f64, skip_top: bool) {
        search.queue.clear();
        search.queue.push(Candidate { induced: 0.0, node: top });
        while let Some(c) = search.queue.pop() {
            if search.expansions_left == 0 || saving - (c.induced + search.node_area) <= search.best_gain {
                return;
            }
            search.expansions_left -= 1;
            let x_box = self.bounds[c.node as usize];
            let merged = x_box.union(&search.node_box).area();
            if !(skip_top && c.node == top) {
                search.offer(c.node, saving - (c.induced + merged));
            }
            let induced = c.induced + merged - x_box.area();
            if !self.is_leaf(c.node) && saving - (induced + search.node_area) > search.best_gain {
                for child in self.children[c.node as usize] {
                    search.queue.push(Candidate { induced, node: child });
                }
            }
        }
    }
}

/// The state of one node's search for a new sibling.
struct Search {
    node_box: Bounds,
    node_area: f64,
    /// Best gain so far (starts at the smallest worth a move).
    best_gain: f64,
    best_target: u32,
    expansions_left: usize,
    queue: BinaryHeap<Candidate>,
}

impl Search {
    fn new(node_box: Bounds) -> Self {
        let node_area = node_box.area();
        Search { node_box, node_area, best_gain: min_gain(node_area), best_target: NONE, expansions_left: SEARCH_LIMIT, queue: BinaryHeap::new() }
    }

    fn offer(&mut self, target: u32, gain: f64) {
        if gain > self.best_gain {
            self.best_gain = gain;
            self.best_target = target;
        }
    }
}

/// Gains below this are taken for rounding and not acted on.
fn min_gain(node_area: f64) -> f64 {
    1e-6 * node_area
}

impl LinkedTree {
    /// Applies `p` if it still saves cost on the tree as it is now and keeps the depth bound;
    /// returns the cost saved.
    fn apply(&mut self, p: &Proposal) -> f64 {
        let (node, target) = (p.node, p.target);
        if node == self.root || target == self.parent[node as usize] || self.is_in_subtree(target, node) {
            return 0.0;
        }
        let removal = self.removal(node);
        if target == removal.sibling {
            return 0.0;
        }
        let (cost, depth) = self.insertion_after(&removal, target);
        let gain = removal.saving - cost;
        // Both `node` and `target` move one level below `target`'s place.
        let deepest = depth + 1 + self.height[node as usize].max(self.height[target as usize]) as usize;
        let fits = deepest < self.depth_limit;
        if gain <= min_gain(self.bounds[node as usize].area()) || !fits {
            return 0.0;
        }
        self.detach(node);
        self.attach(node, target, removal.parent);
        gain
    }

    /// Whether `n` is `root` or below it.
    fn is_in_subtree(&self, mut n: u32, root: u32) -> bool {
        while n != NONE {
            if n == root {
                return true;
            }
            n = self.parent[n as usize];
        }
        false
    }

    /// The cost of inserting `removal.node` as the sibling of `target` once `removal` is done,
    /// and the depth `target` has then.
    fn insertion_after(&self, removal: &Removal, target: u32) -> (f64, usize) {
        let node_box = self.bounds[removal.node as usize];
        let mut cost = self.box_after(removal, target).union(&node_box).area();
        let mut depth = 0;
        let mut above = self.parent[target as usize];
        while above != NONE {
            if above == removal.parent {
                above = self.parent[above as usize];
                continue;
            }
            let b = self.box_after(removal, above);
            cost += b.union(&node_box).area() - b.area();
            depth += 1;
            above = self.parent[above as usize];
        }
        (cost, depth)
    }

    /// Takes `node` out: its sibling takes its parent's place, which is left unlinked.
    fn detach(&mut self, node: u32) {
        let parent = self.parent[node as usize];
        let sibling = self.sibling(node);
        let grandparent = self.parent[parent as usize];
        self.parent[sibling as usize] = grandparent;
        if grandparent == NONE {
            self.root = sibling;
        } else {
            self.replace_child(grandparent, parent, sibling);
            self.refit_upward(grandparent);
        }
    }

    /// Puts `node` back as the sibling of `target`, under `free` (an unlinked interior node).
    fn attach(&mut self, node: u32, target: u32, free: u32) {
        let above = self.parent[target as usize];
        if above == NONE {
            self.root = free;
        } else {
            self.replace_child(above, target, free);
        }
        self.parent[free as usize] = above;
        self.children[free as usize] = [target, node];
        self.parent[target as usize] = free;
        self.parent[node as usize] = free;
        // `free` still holds its old box, which may equal the new one: set it before refitting.
        self.bounds[free as usize] = self.bounds[target as usize].union(&self.bounds[node as usize]);
        self.height[free as usize] = self.height_from_children(free);
        self.refit_upward(above);
    }

    fn replace_child(&mut self, parent: u32, old: u32, new: u32) {
        for c in &mut self.children[parent as usize] {
            if *c == old {
                *c = new;
            }
        }
    }

    /// Recomputes boxes and heights from `n` up, as far as they change.
    fn refit_upward(&mut self, mut n: u32) {
        while n != NONE {
            let [a, b] = self.children[n as usize];
            let new_box = self.bounds[a as usize].union(&self.bounds[b as usize]);
            let new_height = self.height_from_children(n);
            if new_box == self.bounds[n as usize] && new_height == self.height[n as usize] {
                return;
            }
            self.bounds[n as usize] = new_box;
            self.height[n as usize] = new_height;
            n = self.parent[n as usize];
        }
    }

    /// The tree in the builder's order (depth first, siblings adjacent, children after their
    /// parent), each node naming its index in `input`.
    fn flatten(&self, input: &[TreeNode]) -> Vec<TreeNode> {
        let mut nodes = Vec::with_capacity(input.len());
        let mut stack = vec![(self.root, 0usize)];
        nodes.push(input[self.root as usize]);
        while let Some((old, new)) = stack.pop() {
            let first_child = (!self.is_leaf(old)).then_some(nodes.len() as u32);
            nodes[new] = TreeNode { bounds: self.bounds[old as usize], first_child, source: old };
            if first_child.is_some() {
                let [a, b] = self.children[old as usize];
                nodes.extend([input[a as usize], input[b as usize]]);
                let left = nodes.len() - 2;
                stack.push((b, left + 1));
                stack.push((a, left));
            }
        }
        nodes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic pseudo-random numbers in [0, 1).
    struct Lcg(u64);

    impl Lcg {
        fn next(&mut self) -> f32 {
            self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (self.0 >> 40) as f32 / (1u64 << 24) as f32
        }

        fn point(&mut self, scale: f32) -> Vec3 {
            Vec3::new(self.next(), self.next(), self.next()) * scale
        }
    }

    fn random_boxes(count: usize, seed: u64) -> Vec<Bounds> {
        let mut rng = Lcg(seed);
        (0..count)
            .map(|_| {
                let min = rng.point(100.0);
                Bounds { min, max: min + rng.point(4.0) + Vec3::splat(0.01) }
            })
            .collect()
    }

    /// A tree of one box per leaf in the builder's form, split in the middle of the input order
    /// (a poor tree: plenty to optimise).
    fn tree_over(boxes: &[Bounds]) -> Vec<TreeNode> {
        let union = |r: std::ops::Range<usize>| boxes[r.clone()].iter().skip(1).fold(boxes[r.start], |b, o| b.union(o));
        let mut nodes = vec![TreeNode { bounds: union(0..boxes.len()), first_child: None, source: 0 }];
        let mut stack = vec![(0, 0..boxes.len())];
        while let Some((at, range)) = stack.pop() {
            if range.len() > 1 {
                let mid = range.start + range.len() / 2;
                let left = nodes.len();
                nodes[at].first_child = Some(left as u32);
                for r in [range.start..mid, mid..range.end] {
                    nodes.push(TreeNode { bounds: union(r.clone()), first_child: None, source: 0 });
                    stack.push((nodes.len() - 1, r));
                }
            }
        }
        nodes.iter().enumerate().map(|(i, n)| TreeNode { source: i as u32, ..*n }).collect()
    }

    /// Interior areas plus leaf areas (one primitive per leaf).
    fn cost(nodes: &[TreeNode]) -> f64 {
        nodes.iter().map(|n| n.bounds.area()).sum()
    }

    fn depth(nodes: &[TreeNode]) -> usize {
        let mut depth = vec![0; nodes.len()];
        for (i, n) in nodes.iter().enumerate() {
            if let Some(c) = n.first_child {
                depth[c as usize] = depth[i] + 1;
                depth[c as usize + 1] = depth[i] + 1;
            }
        }
        depth.into_iter().max().unwrap_or(0)
    }

    /// Every input leaf once with its box, each interior box the union of its children's,
    /// siblings adjacent after their parent, every node reached once.
    fn assert_well_formed(input: &[TreeNode], output: &[TreeNode]) {
        assert_eq!(input.len(), output.len());
        let mut reached = vec![0; output.len()];
        reached[0] = 1;
        let mut leaves_seen = vec![0; input.len()];
        for (i, n) in output.iter().enumerate() {
            assert_eq!(reached[i], 1, "node {i} reached {} times", reached[i]);
            match n.first_child {
                Some(c) => {
                    let c = c as usize;
                    assert!(c > i && c + 1 < output.len());
                    reached[c] += 1;
                    reached[c + 1] += 1;
                    assert_eq!(n.bounds, output[c].bounds.union(&output[c + 1].bounds));
                }
                None => {
                    let source = &input[n.source as usize];
                    assert!(source.first_child.is_none() && source.bounds == n.bounds);
                    leaves_seen[n.source as usize] += 1;
                }
            }
        }
        let leaves = input.iter().filter(|n| n.first_child.is_none()).count();
        assert_eq!(leaves_seen.iter().filter(|&&s| s == 1).count(), leaves);
        assert!(leaves_seen.iter().all(|&s| s <= 1));
    }

    /// Optimises the tree over `boxes`, checks it, and returns the cost before and after.
    fn assert_optimizes(boxes: &[Bounds], depth_limit: usize) -> (f64, f64) {
        let input = tree_over(boxes);
        let Some(output) = optimize(&input, 3, depth_limit) else {
            assert!(input.len() < 3);
            return (cost(&input), cost(&input));
        };
        assert_well_formed(&input, &output);
        assert!(depth(&output) < depth_limit.max(depth(&input) + 1));
        assert!(cost(&output) <= cost(&input), "{} > {}", cost(&output), cost(&input));
        (cost(&input), cost(&output))
    }

    #[test]
    fn random_boxes_get_cheaper_and_stay_well_formed() {
        for (count, seed) in [(3, 1), (17, 2), (100, 3), (1000, 4), (20_000, 5)] {
            let (before, after) = assert_optimizes(&random_boxes(count, seed), 64);
            if count >= 100 {
                assert!(after < 0.9 * before, "{count} boxes: {after} against {before}");
            }
        }
    }

    #[test]
    fn the_same_input_gives_the_same_tree() {
        let input = tree_over(&random_boxes(5000, 9));
        assert_eq!(optimize(&input, 3, 64), optimize(&input, 3, 64));
    }

    #[test]
    fn degenerate_inputs_stay_well_formed() {
        let same_centre: Vec<Bounds> = (0..200).map(|i| Bounds { min: Vec3::splat(-(i as f32) - 1.0), max: Vec3::splat(i as f32 + 1.0) }).collect();
        let identical = vec![Bounds { min: Vec3::ZERO, max: Vec3::ONE }; 100];
        let row: Vec<Bounds> = (0..5000).map(|i| Bounds { min: Vec3::new(i as f32, 0.0, 0.0), max: Vec3::new(i as f32 + 1.0, 0.01, 0.01) }).collect();
        for boxes in [&same_centre[..], &identical, &row, &row[..1], &row[..2], &row[..3]] {
            assert_optimizes(boxes, 64);
        }
    }

    #[test]
    fn no_move_reaches_the_depth_limit() {
        // A row halved in input order is 13 deep; a limit of 15 leaves moves 1 level of slack.
        let row: Vec<Bounds> = (0..5000)
            .map(|i| Bounds { min: Vec3::new((i * 7919 % 5000) as f32, 0.0, 0.0), max: Vec3::new((i * 7919 % 5000) as f32 + 1.0, 1.0, 1.0) })
            .collect();
        let input = tree_over(&row);
        assert_eq!(depth(&input), 13);
        let output = optimize(&input, 3, 15).unwrap();
        assert_well_formed(&input, &output);
        assert!(depth(&output) < 15);
        assert!(cost(&output) < cost(&input));
    }

    #[test]
    fn zero_passes_and_tiny_trees_are_left_alone() {
        let input = tree_over(&random_boxes(100, 7));
        assert_eq!(optimize(&input, 0, 64), None);
        assert_eq!(optimize(&tree_over(&random_boxes(1, 7)), 3, 64), None);
    }
}
