//! Frames: `Scene::frame_into` reuses the frame's buffers, keeps triangle order stable
//! across times, says which actor each triangle came from, and produces, for actors kept
//! in local space with a transform, exactly the bits the loaders once baked.

mod support;

use dynray_geom::TriangleMesh;
use dynray_scene::{load_file, Actor, Frame, Material, Motion, Scene, Transform};
use glam::{Mat4, Vec3};
use std::path::{Path, PathBuf};
use support::model;

fn examples() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "scn"))
        .collect();
    v.sort();
    assert!(v.len() >= 4, "expected the example scenes in {}", dir.display());
    v
}

/// The flattened mesh as the scene model used to produce it: each actor's mesh baked
/// into world space with `TriangleMesh::transform` (as `scn/build.rs` and the glTF loader
/// did, skipping `Transform::IDENTITY` as the builder skipped identity matrices), then
/// concatenated with `TriangleMesh::append`, normals and uvs filled with zeros where an
/// actor has none and another has some.
fn baked_reference(s: &Scene) -> TriangleMesh {
    let mut mesh = TriangleMesh::default();
    let any_normals = s.actors.iter().any(|a| a.mesh.normals.is_some());
    let any_uvs = s.actors.iter().any(|a| a.mesh.uvs.is_some());
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    for a in &s.actors {
        let mut m = a.mesh.clone();
        if !a.transform.is_identity() {
            m.transform(&a.transform.matrix());
        }
        mesh.append(&m);
        if any_normals {
            match &m.normals {
                Some(n) => normals.extend_from_slice(n),
                None => normals.resize(normals.len() + m.vertex_count(), [0.0; 3]),
            }
        }
        if any_uvs {
            match &m.uvs {
                Some(t) => uvs.extend_from_slice(t),
                None => uvs.resize(uvs.len() + m.vertex_count(), [0.0; 2]),
            }
        }
    }
    mesh.normals = any_normals.then_some(normals);
    mesh.uvs = any_uvs.then_some(uvs);
    mesh
}

fn bits3(v: &[[f32; 3]]) -> Vec<[u32; 3]> {
    v.iter().map(|p| p.map(f32::to_bits)).collect()
}

fn assert_same_as_baked(what: &str, s: &Scene) {
    let f = s.frame(0.0);
    let r = baked_reference(s);
    assert_eq!(bits3(&f.mesh.positions), bits3(&r.positions), "{what}: positions differ from the baked ones");
    assert_eq!(
        f.mesh.normals.as_deref().map(bits3),
        r.normals.as_deref().map(bits3),
        "{what}: normals differ from the baked ones"
    );
    assert_eq!(f.mesh.indices, r.indices, "{what}: triangles");
    assert_eq!(f.mesh.uvs, r.uvs, "{what}: uvs");
    let mats: Vec<u32> = s.actors.iter().flat_map(|a| a.materials.iter().copied()).collect();
    assert_eq!(f.materials_of, mats, "{what}: materials per triangle");
}

#[test]
fn example_scenes_give_the_baked_bits() {
    let mut transformed = 0;
    for p in examples() {
        let s = load_file(&p).unwrap_or_else(|e| panic!("{e}"));
        transformed += s.actors.iter().filter(|a| !a.transform.is_identity()).count();
        // Only animated actors (with a node; `examples/animated.scn`) are dynamic, and
        // at time 0 they too give the bits of their transform (their pose at time 0).
        assert!(s.actors.iter().all(|a| (a.motion == Motion::Static) == a.node.is_none()));
        assert_same_as_baked(&p.display().to_string(), &s);
    }
    assert!(transformed > 0, "the examples should place some actors with a transform");
}

#[test]
fn gltf_models_give_the_baked_bits() {
    for rel in
        ["CesiumMan/glTF/CesiumMan.gltf", "Duck/glTF-Binary/Duck.glb", "AnimatedMorphCube/glTF/AnimatedMorphCube.gltf"]
    {
        let Some(p) = model(rel) else { continue };
        let mut s = load_file(&p).unwrap();
        assert!(s.actors.iter().all(|a| !a.transform.is_identity()), "{rel}: the node matrix stays on the actor");
        // A skinned actor (CesiumMan) is placed by its skin, posed at every t; its rest
        // placement, the actor's transform, must still give the baked bits. The others
        // (the morph cube at t = 0, weights zero) give them through the rig.
        for a in s.actors.iter_mut().filter(|a| a.deform.as_ref().is_some_and(|d| d.skin.is_some())) {
            a.node = None;
            a.deform = None;
        }
        assert_same_as_baked(rel, &s);
    }
}

/// Two actors with normals, uvs on neither, one placed by a rotation and scale.
fn two_actors() -> Scene {
    let tri = |z: f32| {
        let mut m = TriangleMesh::new(vec![[0.0, 0.0, z], [1.0, 0.0, z], [0.0, 1.0, z]], vec![[0, 1, 2]]);
        m.normals = Some(vec![[0.0, 0.0, 1.0]; 3]);
        m
    };
    let mut quad = tri(-1.0);
    quad.positions.push([1.0, 1.0, -1.0]);
    quad.normals.as_mut().unwrap().push([0.0, 0.0, 2.0]);
    quad.indices.push([1, 3, 2]);
    let place = Transform::new(Mat4::from_scale_rotation_translation(
        Vec3::new(2.0, 2.0, 0.5),
        glam::Quat::from_rotation_y(0.3),
        Vec3::new(0.0, 1.0, -4.0),
    ));
    let mut s = Scene { materials: vec![Material::default(), Material::default()], ..Default::default() };
    s.actors.push(Actor::new(Some("a".into()), tri(0.0), 0));
    s.actors.push(Actor::new(Some("b".into()), quad, 1).with_transform(place));
    s.add_default_light();
    s
}

#[test]
fn frame_into_reuses_every_buffer() {
    let s = two_actors();
    let mut f = Frame::default();
    s.frame_into(0.0, &mut f);
    let first = f.clone();
    let ptrs = |f: &Frame| {
        (
            (f.mesh.positions.as_ptr() as usize, f.mesh.positions.capacity()),
            (f.mesh.indices.as_ptr() as usize, f.mesh.indices.capacity()),
            f.mesh.normals.as_ref().map(|n| (n.as_ptr() as usize, n.capacity())),
            (f.materials_of.as_ptr() as usize, f.materials_of.capacity()),
            (f.actor_ranges.as_ptr() as usize, f.actor_ranges.capacity()),
            (f.materials.as_ptr() as usize, f.materials.capacity()),
            (f.lights.as_ptr() as usize, f.lights.capacity()),
        )
    };
    let before = ptrs(&f);
    s.frame_into(0.5, &mut f);
    assert_eq!(ptrs(&f), before, "a second fill of the same scene allocates nothing");
    assert_eq!(Frame { time: 0.0, ..f.clone() }, first, "and gives the same frame");
    assert_eq!(f.time, 0.5);
}

#[test]
fn frame_into_leaves_nothing_of_the_previous_scene() {
    let big = load_file(&examples()[0]).unwrap();
    let small = two_actors();
    let mut f = big.frame(0.0);
    small.frame_into(0.0, &mut f);
    assert_eq!(f, small.frame(0.0));
    // A scene without normals after one with them.
    let mut flat = two_actors();
    for a in &mut flat.actors {
        a.mesh.normals = None;
    }
    flat.frame_into(0.0, &mut f);
    assert_eq!(f, flat.frame(0.0));
    assert_eq!(f.mesh.normals, None);
}

#[test]
fn triangle_order_is_stable_and_ranges_name_the_actor() {
    let s = two_actors();
    let a = s.frame(0.0);
    let b = s.frame(12.25);
    assert_eq!(a.mesh, b.mesh, "static scenes are the same at every time");
    assert_eq!(a.actor_ranges, vec![0..1, 1..3]);
    assert_eq!(a.materials_of, vec![0, 1, 1]);
    assert_eq!((a.actor_of(0), a.actor_of(1), a.actor_of(2), a.actor_of(3)), (Some(0), Some(1), Some(1), None));
    assert_eq!(a.actor_of(u32::MAX), None, "a miss is on no actor");
    // Actor 1's triangles come in its own order, offset by actor 0's three vertices.
    assert_eq!(a.mesh.indices[1..], [[3, 4, 5], [4, 6, 5]]);
    // Its normals are transformed and renormalised; actor 0's are copied.
    let n = a.mesh.normals.as_ref().unwrap();
    assert_eq!(n[0], [0.0, 0.0, 1.0]);
    assert!((Vec3::from_array(n[6]).length() - 1.0).abs() < 1e-6);
}

#[test]
fn every_example_frame_has_ranges_covering_its_triangles() {
    for p in examples() {
        let s = load_file(&p).unwrap();
        let f = s.frame(0.0);
        assert_eq!(f.actor_ranges.len(), s.actors.len());
        let mut next = 0;
        for (r, a) in f.actor_ranges.iter().zip(&s.actors) {
            assert_eq!(r.start, next, "{}: ranges are contiguous", p.display());
            assert_eq!((r.end - r.start) as usize, a.mesh.triangle_count());
            next = r.end;
        }
        assert_eq!(next as usize, f.mesh.triangle_count());
    }
}

#[test]
fn world_bounds_follow_the_transform() {
    let s = two_actors();
    let f = s.frame(0.0);
    assert_eq!(s.bounds(), f.mesh.bounds(), "Scene::bounds is the frame's");
    assert_eq!(s.actors[1].bounds(), s.actors[1].world_mesh().bounds());
}

#[test]
fn uvs_of_one_actor_survive_an_actor_without_them_and_textures_are_shared() {
    // Regression: the frame once dropped every uv when one actor had none, and with
    // them the texture of a textured mesh placed beside a box or sphere.
    let mut s = two_actors();
    s.actors[1].mesh.uvs = Some(vec![[0.25, 0.5], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]);
    let texel = dynray_scene::Texture::from_linear("t", 1, 1, vec![Vec3::ONE]).unwrap();
    s.textures.push(std::sync::Arc::new(texel));
    let f = s.frame(0.0);
    let uvs = f.mesh.uvs.as_ref().expect("uvs kept");
    assert_eq!(uvs[..3], [[0.0, 0.0]; 3], "actor a has none: zeros");
    assert_eq!(uvs[3], [0.25, 0.5], "actor b's own");
    assert_eq!(f.textures.len(), 1);
    assert!(std::sync::Arc::ptr_eq(&f.textures[0], &s.textures[0]), "a frame shares texels, never copies");
}
