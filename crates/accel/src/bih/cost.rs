//! The BIH's surface-area-heuristic cost: what `AccelStats::sah_cost` reports and the
//! `auto` update policy watches as refits loosen the clip planes.
//!
//! A BIH node stores only its two clip planes; each child's box is its parent's box cut
//! by its plane on the split axis (seed 000 §2.2), starting from the scene box. The cost
//! is the BVH's formula over those boxes, with the BVH's default constants (traversal 1,
//! triangle test 1): `Σ_inner area + Σ_leaf n · area`, over the root's area.

use super::node::BihNode;
use super::Bih;
use dynray_geom::Aabb;

impl Bih {
    /// The normalised SAH cost of the tree (`None` for an empty or flat scene box).
    pub fn sah_cost(&self) -> Option<f64> {
        let root_area = self.bounds.surface_area() as f64;
        if self.nodes.is_empty() || root_area.is_nan() || root_area <= 0.0 {
            return None;
        }
        let mut sum = 0.0f64;
        let mut stack: Vec<(u32, Aabb)> = vec![(0, self.bounds)];
        while let Some((i, b)) = stack.pop() {
            let node: &BihNode = &self.nodes[i as usize];
            let area = if b.is_empty() { 0.0 } else { b.surface_area() as f64 };
            if node.is_leaf() {
                sum += node.count as f64 * area;
                continue;
            }
            sum += area;
            let axis = node.axis();
            let (left, right) = (i + 1, node.index());
            let mut lb = b;
            lb.max[axis] = lb.max[axis].min(node.clip[0]);
            let mut rb = b;
            rb.min[axis] = rb.min[axis].max(node.clip[1]);
            if left == right {
                // A one-child node: the finite plane cuts the one child's box.
                let child = if node.clip[1] == f32::INFINITY { lb } else { rb };
                stack.push((left, child));
            } else {
                stack.push((left, lb));
                stack.push((right, rb));
            }
        }
        Some(sum / root_area)
    }
}
