//! The two-level structure's outline: the top-level tree's nodes in world space from depth
//! 0, its leaves being the instances' world bounds (a rigid instance's transformed and
//! widened local box). Nothing is drawn below an instance: its part has an outline of its
//! own ([`TwoLevel::part`]), but in the part's space and for a local part shared by several
//! instances, so drawing it would mean one transformed copy per instance; the viewer asks
//! a part for it when it wants it.

use super::TwoLevel;
use crate::bvh2::outline::outline_nodes;
use crate::OutlineBox;

impl TwoLevel {
    /// Pushes the top-level nodes with depth `<= max_depth` onto `out`, parents first; a
    /// frame without instances pushes nothing.
    pub(super) fn outline_top(&self, max_depth: u32, out: &mut Vec<OutlineBox>) {
        outline_nodes(&self.top, max_depth, out);
    }
}

#[cfg(test)]
mod tests {
    use crate::outline::checks::{self, Cover};
    use crate::two_level::{ActorGeometry, ActorMotion, LiveScene, SceneLayout};
    use crate::{AccelKind, AccelSpec, UpdatePolicy};
    use dynray_geom::{TriangleMesh, Vec3};
    use glam::Mat4;

    #[test]
    fn outline_is_the_top_tree_down_to_the_instances() {
        // Five rigid copies of one sphere in a row, and a static floor.
        let local = dynray_scene::shapes::uv_sphere(Vec3::ZERO, 0.5, 8, 12);
        let mut mesh = TriangleMesh::new(
            vec![[-8., -1., -2.], [8., -1., -2.], [8., -1., 2.], [-8., -1., 2.]],
            vec![[0, 2, 1], [0, 3, 2]],
        );
        let placements: Vec<Mat4> = (0..5)
            .map(|i| {
                Mat4::from_translation(Vec3::new(3.0 * i as f32 - 6.0, 0.2 * i as f32, 0.0))
                    * Mat4::from_rotation_y(0.3 * i as f32)
            })
            .collect();
        let mut actors = vec![ActorGeometry { triangles: 0..2, vertices: 0..4, motion: ActorMotion::Static }];
        for m in &placements {
            let (t0, v0) = (mesh.triangle_count() as u32, mesh.positions.len() as u32);
            mesh.positions.extend(local.positions.iter().map(|p| m.transform_point3(Vec3::from_array(*p)).to_array()));
            mesh.indices.extend(local.indices.iter().map(|t| t.map(|i| i + v0)));
            actors.push(ActorGeometry {
                triangles: t0..mesh.triangle_count() as u32,
                vertices: v0..mesh.positions.len() as u32,
                motion: ActorMotion::Rigid { local: &local, to_world: *m },
            });
        }
        let spec = AccelSpec::new(AccelKind::Bvh);
        let (live, _) =
            LiveScene::build(&spec, UpdatePolicy::Refit, SceneLayout::Instanced, &actors, &mesh, None).unwrap();
        let tl = live.two_level().expect("two levels");
        assert_eq!(tl.counts(), (2, 6), "the floor's part and the sphere's, six instances");
        let deepest = checks::check(tl, &mesh, Cover::Centroids);
        assert!(deepest >= 2, "depth {deepest}");
        // The leaves are exactly the instances' world boxes.
        let full = checks::outline(tl, u32::MAX);
        let mut leaves: Vec<_> = full.iter().filter(|b| b.leaf).map(|b| b.bounds).collect();
        let mut boxes: Vec<_> = tl.instances().iter().map(|i| i.bounds).collect();
        let key = |b: &dynray_geom::Aabb| (b.min.x.to_bits(), b.min.y.to_bits(), b.max.z.to_bits());
        leaves.sort_by_key(key);
        boxes.sort_by_key(key);
        assert_eq!(leaves, boxes);
        checks::appends(tl);
        // Through the live scene's `dyn Accel`, the same outline.
        assert_eq!(checks::outline(live.accel(), 3), checks::outline(tl, 3));
    }
}
