use super::*;
use crate::{Accel, AccelKind, Brute, UpdateAction, UpdatePolicy};
use dynray_geom::{Hit, Ray};

/// A unit cube's 12 triangles around the origin.
fn cube() -> TriangleMesh {
    let p = |x: f32, y: f32, z: f32| [x - 0.5, y - 0.5, z - 0.5];
    let positions = vec![
        p(0., 0., 0.),
        p(1., 0., 0.),
        p(1., 1., 0.),
        p(0., 1., 0.),
        p(0., 0., 1.),
        p(1., 0., 1.),
        p(1., 1., 1.),
        p(0., 1., 1.),
    ];
    let indices = vec![
        [0, 2, 1],
        [0, 3, 2],
        [4, 5, 6],
        [4, 6, 7],
        [0, 1, 5],
        [0, 5, 4],
        [3, 6, 2],
        [3, 7, 6],
        [0, 4, 7],
        [0, 7, 3],
        [1, 2, 6],
        [1, 6, 5],
    ];
    TriangleMesh::new(positions, indices)
}

/// A frame: a static floor, a waving strip (deforming), two rigid cubes (same mesh).
struct Scene {
    cube: TriangleMesh,
    mesh: TriangleMesh,
    placements: [Mat4; 2],
}

impl Scene {
    fn at(f: u32) -> Scene {
        let cube = cube();
        let mut mesh = TriangleMesh::new(
            vec![[-4., -1., -4.], [4., -1., -4.], [4., -1., 4.], [-4., -1., 4.]],
            vec![[0, 2, 1], [0, 3, 2]],
        );
        let wave = (f as f32 * 0.7).sin();
        let base = mesh.positions.len() as u32;
        for i in 0..6 {
            let x = i as f32 - 2.5;
            mesh.positions.push([x, 0.3 * wave * x.cos(), -2.0]);
            mesh.positions.push([x, 1.0 + 0.2 * wave, -2.5]);
        }
        for i in 0..5u32 {
            let a = base + 2 * i;
            mesh.indices.push([a, a + 2, a + 1]);
            mesh.indices.push([a + 1, a + 2, a + 3]);
        }
        let angle = f as f32 * 0.3;
        let placements = [
            Mat4::from_translation(Vec3::new(-1.5, 0.2 * f as f32, 0.5)) * Mat4::from_rotation_y(angle),
            Mat4::from_scale_rotation_translation(
                Vec3::new(1.3, 0.7, 1.0),
                glam::Quat::from_rotation_x(-angle),
                Vec3::new(1.5, 0.0, 1.0),
            ),
        ];
        for m in &placements {
            let base = mesh.positions.len() as u32;
            mesh.positions.extend(cube.positions.iter().map(|p| m.transform_point3(Vec3::from_array(*p)).to_array()));
            mesh.indices.extend(cube.indices.iter().map(|t| t.map(|i| i + base)));
        }
        Scene { cube, mesh, placements }
    }

    fn actors(&self) -> Vec<ActorGeometry<'_>> {
        vec![
            ActorGeometry { triangles: 0..2, vertices: 0..4, motion: ActorMotion::Static },
            ActorGeometry { triangles: 2..12, vertices: 4..16, motion: ActorMotion::Deforming },
            ActorGeometry {
                triangles: 12..24,
                vertices: 16..24,
                motion: ActorMotion::Rigid { local: &self.cube, to_world: self.placements[0] },
            },
            ActorGeometry {
                triangles: 24..36,
                vertices: 24..32,
                motion: ActorMotion::Rigid { local: &self.cube, to_world: self.placements[1] },
            },
        ]
    }
}

/// Rays from around the scene towards points inside it (seeded, deterministic).
fn rays() -> Vec<Ray> {
    let mut s = 0x2545_f491_u32;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        s as f32 / u32::MAX as f32
    };
    (0..3000)
        .map(|_| {
            let o = Vec3::new(next() * 12. - 6., next() * 6. - 1., next() * 12. - 6.);
            let target = Vec3::new(next() * 6. - 3., next() * 2. - 1., next() * 6. - 3.);
            Ray::new(o, target - o)
        })
        .collect()
}

#[test]
fn split_equals_brute_force_on_the_frame_bit_for_bit() {
    for kind in [AccelKind::Bvh, AccelKind::Bvh2, AccelKind::Bih, AccelKind::KdTree, AccelKind::Grid] {
        let spec = crate::AccelSpec::new(kind);
        let s0 = Scene::at(0);
        let (mut live, _) =
            LiveScene::build(&spec, UpdatePolicy::Refit, SceneLayout::Split, &s0.actors(), &s0.mesh, None).unwrap();
        for f in 0..4 {
            let s = Scene::at(f);
            if f > 0 {
                let r = live.update(&s.actors(), &s.mesh, None).unwrap();
                assert_ne!(r.action, UpdateAction::Kept, "{kind:?} frame {f}");
            }
            let tl = live.two_level().expect("two levels");
            assert_eq!(tl.counts(), (4, 4), "static, strip, two cubes in world space");
            live.accel().validate(&s.mesh).unwrap();
            let brute = Brute::build(&s.mesh).unwrap();
            let mut hits = 0;
            for r in rays() {
                let (a, b) = (live.accel().intersect(&r), brute.intersect(&r));
                assert!(a.same_as(&b), "{kind:?} frame {f}: {a:?} vs brute {b:?} for {r:?}");
                assert_eq!(live.accel().occluded(&r), brute.occluded(&r));
                hits += a.is_hit() as u32;
            }
            assert!(hits > 1000, "{hits} hits: the rays must exercise the scene");
        }
    }
}

#[test]
fn instances_equal_the_instanced_oracle_and_name_the_flat_triangle() {
    let spec = crate::AccelSpec::new(AccelKind::Bvh);
    let s0 = Scene::at(0);
    let (mut live, _) =
        LiveScene::build(&spec, UpdatePolicy::Refit, SceneLayout::Instanced, &s0.actors(), &s0.mesh, None).unwrap();
    assert_eq!(live.two_level().unwrap().counts(), (3, 4), "the two cubes share one part");
    for f in 0..4 {
        let s = Scene::at(f);
        if f > 0 {
            live.update(&s.actors(), &s.mesh, None).unwrap();
            let parts = live.last_parts().unwrap();
            assert_eq!((parts.moved, parts.refit, parts.kept), (2, 1, 2), "frame {f}: {parts:?}");
        }
        live.accel().validate(&s.mesh).unwrap();
        let tl = live.two_level().unwrap();
        let brute = Brute::build(&s.mesh).unwrap();
        let (mut same_prim, mut n) = (0, 0);
        for r in rays() {
            let a = live.accel().intersect(&r);
            let oracle = tl.intersect_brute(&r, &|p| tl.part_mesh(p));
            assert!(a.same_as(&oracle), "frame {f}: {a:?} vs instanced oracle {oracle:?}");
            let flat: Hit = brute.intersect(&r);
            if flat.is_hit() || a.is_hit() {
                n += 1;
                if a.prim == flat.prim {
                    same_prim += 1;
                    assert!((a.t - flat.t).abs() <= 1e-5 * flat.t.abs().max(1.0), "{a:?} vs {flat:?}");
                }
            }
        }
        assert!(same_prim as f64 >= 0.995 * n as f64, "frame {f}: {same_prim} of {n} hits on the flat triangle");
    }
}

#[test]
fn a_still_frame_keeps_everything_and_a_new_scene_is_rebuilt() {
    let spec = crate::AccelSpec::new(AccelKind::Bvh);
    let s = Scene::at(2);
    let (mut live, _) = LiveScene::build(
        &spec,
        UpdatePolicy::Auto { max_cost_ratio: 1.3 },
        SceneLayout::Instanced,
        &s.actors(),
        &s.mesh,
        None,
    )
    .unwrap();
    assert_eq!(live.update(&s.actors(), &s.mesh, None).unwrap().action, UpdateAction::Kept);
    // Another scene: the strip's actor gone, its triangles now the floor's.
    let mut actors = s.actors();
    actors.remove(1);
    actors[0].triangles = 0..12;
    actors[0].vertices = 0..16;
    let r = live.update(&actors, &s.mesh, None).unwrap();
    assert_eq!(r.action, UpdateAction::Rebuilt);
    assert_eq!(live.two_level().unwrap().counts(), (2, 3));
    live.accel().validate(&s.mesh).unwrap();
}

#[test]
fn actors_that_do_not_tile_the_frame_are_an_error() {
    let spec = crate::AccelSpec::new(AccelKind::Bvh);
    let s = Scene::at(0);
    let mut actors = s.actors();
    actors[1].triangles = 3..12;
    let e = LiveScene::build(&spec, UpdatePolicy::Refit, SceneLayout::Split, &actors, &s.mesh, None).err().unwrap();
    assert!(e.to_string().contains("actor 1"), "{e}");
    let mut actors = s.actors();
    actors.pop();
    let e = LiveScene::build(&spec, UpdatePolicy::Refit, SceneLayout::Split, &actors, &s.mesh, None).err().unwrap();
    assert!(e.to_string().contains("cover 24 of the frame's 36"), "{e}");
}

#[test]
fn a_frame_without_motion_and_the_flat_layout_are_one_structure() {
    let spec = crate::AccelSpec::new(AccelKind::Bvh);
    let s = Scene::at(0);
    let still: Vec<_> = s.actors().into_iter().map(|a| ActorGeometry { motion: ActorMotion::Static, ..a }).collect();
    let (live, _) =
        LiveScene::build(&spec, UpdatePolicy::Refit, SceneLayout::Instanced, &still, &s.mesh, None).unwrap();
    assert_eq!(live.layout(), SceneLayout::Flat);
    let (live, _) =
        LiveScene::build(&spec, UpdatePolicy::Refit, SceneLayout::Flat, &s.actors(), &s.mesh, None).unwrap();
    assert!(live.two_level().is_none());
}

#[test]
fn the_top_level_holds_every_instance_and_stays_shallow() {
    let boxes: Vec<Aabb> = (0..1000)
        .map(|i| {
            let c = Vec3::new((i % 10) as f32, ((i / 10) % 10) as f32, (i / 100) as f32) * 2.0;
            Aabb::new(c, c + Vec3::ONE)
        })
        .collect();
    let (nodes, order) = top::build(&boxes);
    assert_eq!(nodes.len(), 2 * boxes.len() - 1);
    let mut sorted = order.clone();
    sorted.sort();
    assert_eq!(sorted, (0..1000).collect::<Vec<u32>>());
    assert!(validate::top_depth(&nodes) <= 20, "depth {}", validate::top_depth(&nodes));
    // All boxes identical: the sweep finds no better split; the median keeps it shallow.
    let same = vec![Aabb::new(Vec3::ZERO, Vec3::ONE); 5000];
    let (nodes, _) = top::build(&same);
    assert!((validate::top_depth(&nodes) as usize) < top::STACK);
}

/// A frame of one deforming actor is one world-space part under the top level: coherent
/// batches reach its wide tree's packets, with the answers of `intersect`, bit for bit.
#[test]
fn a_lone_world_part_forwards_coherent_batches_to_its_packets() {
    let s = Scene::at(2);
    let strip = TriangleMesh::new(
        s.mesh.positions[4..16].to_vec(),
        s.mesh.indices[2..12].iter().map(|t| t.map(|i| i - 4)).collect(),
    );
    let actors = [ActorGeometry { triangles: 0..10, vertices: 0..12, motion: ActorMotion::Deforming }];
    let spec = crate::AccelSpec::new(AccelKind::Bvh);
    let (live, _) = LiveScene::build(&spec, UpdatePolicy::Refit, SceneLayout::Split, &actors, &strip, None).unwrap();
    let tl = live.two_level().expect("two levels");
    assert_eq!(tl.counts(), (1, 1));
    assert!(live.accel().traces_packets());
    // Packets of 8 rays from one eye per packet, some with NaN or zero-length intervals.
    let mut rays = rays();
    let b = strip.bounds();
    for (k, g) in rays.chunks_mut(8).enumerate() {
        let o = g[0].origin;
        // Aimed at a 4 × 2 block of points across the strip's box, one block per packet.
        let at = b.min + (b.max - b.min) * Vec3::new((k % 7) as f32 / 7.0, (k % 3) as f32 / 3.0, 0.5);
        for (i, r) in g.iter_mut().enumerate() {
            r.origin = o;
            r.dir = at + Vec3::new((i % 4) as f32 * 0.05, (i / 4) as f32 * 0.05, 0.0) - o;
        }
        match k % 5 {
            0 => g[3].tmax = f32::NAN,
            1 => g[1].tmax = 0.0,
            _ => {}
        }
    }
    let mut got = vec![Hit::MISS; rays.len()];
    live.accel().intersect_coherent_into(&rays, &mut got);
    let brute = Brute::build(&strip).unwrap();
    let mut hits = 0;
    for (r, g) in rays.iter().zip(&got) {
        let want = live.accel().intersect(r);
        assert!(g.same_as(&want) && g.u.to_bits() == want.u.to_bits(), "{g:?} vs {want:?} for {r:?}");
        if !r.tmax.is_nan() {
            assert!(g.same_as(&brute.intersect(r)), "{r:?}");
        }
        hits += g.is_hit() as usize;
    }
    assert!(hits > 1000, "{hits} hits");
    // Several parts: one ray at a time, the same answers.
    let (split, _) =
        LiveScene::build(&spec, UpdatePolicy::Refit, SceneLayout::Split, &s.actors(), &s.mesh, None).unwrap();
    assert!(!split.accel().traces_packets());
    split.accel().intersect_coherent_into(&rays, &mut got);
    assert!(rays.iter().zip(&got).all(|(r, g)| g.same_as(&split.accel().intersect(r))));
}
