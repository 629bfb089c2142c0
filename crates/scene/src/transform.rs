//! An actor's object-to-world transform, and the one way it is applied to geometry.
//!
//! Frames are compared bit for bit (golden images), so how a transform touches a mesh is
//! part of the contract: positions go through [`Mat4::transform_point3`], normals through
//! the inverse transpose of the linear part followed by `normalize_or_zero`, exactly as
//! [`TriangleMesh::transform`] does (a test pins the two together).

use dynray_geom::TriangleMesh;
use glam::{Mat3, Mat4, Vec3};

/// Object-to-world placement of an actor: an affine `f32` matrix, or nothing at all.
///
/// [`Transform::IDENTITY`] is not applied: world geometry is the local geometry, bit for
/// bit. [`Transform::new`] is always applied, even with an identity matrix, because
/// applying one is not a no-op on the bits: `-0.0 + 0.0` gives `+0.0`, and normals are
/// renormalised. The glTF loader relies on that to keep its output unchanged (it has
/// always transformed every node, identity or not); the `.scn` builder gives actors
/// without a transform [`Transform::IDENTITY`], as it always skipped them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    /// Maps object points to world points.
    matrix: Mat4,
    /// `false` only for [`Transform::IDENTITY`]: the frame copies local geometry.
    applied: bool,
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Transform {
    /// No transform: world space is the actor's local space, and nothing is computed.
    pub const IDENTITY: Transform = Transform { matrix: Mat4::IDENTITY, applied: false };

    /// The transform mapping object points `p` to `matrix.transform_point3(p)`; applied
    /// even when `matrix` is the identity (see the type's docs).
    pub fn new(matrix: Mat4) -> Self {
        Self { matrix, applied: true }
    }

    /// The object-to-world matrix ([`Mat4::IDENTITY`] for [`Transform::IDENTITY`]).
    pub fn matrix(&self) -> Mat4 {
        self.matrix
    }

    /// Whether this is [`Transform::IDENTITY`], which leaves geometry untouched.
    /// `Transform::new(Mat4::IDENTITY)` is not: it is applied, and says `false`.
    pub fn is_identity(&self) -> bool {
        !self.applied
    }

    /// `p` in world space.
    #[inline]
    pub fn point(&self, p: [f32; 3]) -> [f32; 3] {
        if self.applied {
            self.matrix.transform_point3(Vec3::from_array(p)).to_array()
        } else {
            p
        }
    }

    /// A function taking object-space normals to world space (unit length, or zero for a
    /// zero normal). The inverse transpose is computed once here, not per normal.
    pub fn normal_fn(&self) -> impl Fn([f32; 3]) -> [f32; 3] {
        let nm = Mat3::from_mat4(self.matrix).inverse().transpose();
        let applied = self.applied;
        move |n| if applied { (nm * Vec3::from_array(n)).normalize_or_zero().to_array() } else { n }
    }

    /// Applies the transform to `mesh` in place: what the frame does to an actor's copy.
    pub fn apply(&self, mesh: &mut TriangleMesh) {
        if self.applied {
            mesh.transform(&self.matrix);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A mesh whose bits a careless transform would change: signed zeros, a non-unit
    /// normal, a zero normal, large and tiny coordinates.
    fn awkward() -> TriangleMesh {
        let mut m = TriangleMesh::new(
            vec![[-0.0, 0.0, -0.0], [1e-30, -3.5, 7.25e6], [0.1, 0.2, 0.3], [-1.0, 2.0, -0.0]],
            vec![[0, 1, 2], [0, 2, 3]],
        );
        m.normals = Some(vec![[0.0, 2.0, 0.0], [0.0; 3], [0.3, -0.4, 1e-3], [-0.0, 0.0, -1.0]]);
        m
    }

    fn bits(v: &[[f32; 3]]) -> Vec<[u32; 3]> {
        v.iter().map(|p| p.map(f32::to_bits)).collect()
    }

    #[test]
    fn point_and_normal_fn_match_mesh_transform_bit_for_bit() {
        let mats = [
            Mat4::IDENTITY,
            Mat4::from_translation(Vec3::new(1.5, -2.0, 0.25)),
            Mat4::from_scale_rotation_translation(
                Vec3::new(2.0, -0.5, 3.0),
                glam::Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.7),
                Vec3::new(-4.0, 0.1, 9.0),
            ),
        ];
        for m in mats {
            let t = Transform::new(m);
            let mut expected = awkward();
            expected.transform(&m);
            let local = awkward();
            let pos: Vec<_> = local.positions.iter().map(|&p| t.point(p)).collect();
            let nf = t.normal_fn();
            let nrm: Vec<_> = local.normals.as_ref().unwrap().iter().map(|&n| nf(n)).collect();
            assert_eq!(bits(&pos), bits(&expected.positions), "positions under {m}");
            assert_eq!(bits(&nrm), bits(expected.normals.as_ref().unwrap()), "normals under {m}");
            let mut applied = awkward();
            t.apply(&mut applied);
            assert_eq!(bits(&applied.positions), bits(&expected.positions));
        }
    }

    #[test]
    fn identity_leaves_bits_alone_but_an_applied_identity_does_not() {
        let local = awkward();
        let id = Transform::IDENTITY;
        assert!(id.is_identity());
        assert_eq!(bits(&local.positions.iter().map(|&p| id.point(p)).collect::<Vec<_>>()), bits(&local.positions));
        let nf = id.normal_fn();
        assert_eq!(nf([0.0, 2.0, 0.0]), [0.0, 2.0, 0.0], "IDENTITY does not renormalise");
        let applied = Transform::new(Mat4::IDENTITY);
        assert!(!applied.is_identity());
        assert_eq!(applied.point([-0.0, 1.0, 1.0])[0].to_bits(), 0.0f32.to_bits(), "-0.0 + 0.0 is +0.0");
        assert_eq!(applied.normal_fn()([0.0, 2.0, 0.0]), [0.0, 1.0, 0.0]);
    }
}
