//! Triangle meshes as flat arrays, the form every loader produces and every structure reads.

use crate::{Aabb, Triangle};
use glam::Vec3;

/// Why a mesh is unusable.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MeshError {
    /// No triangles at all.
    #[error("the mesh has no triangles")]
    Empty,
    /// A triangle names a vertex that does not exist.
    #[error("triangle {triangle} uses vertex {index}, but the mesh has only {vertices} vertices")]
    IndexOutOfRange {
        /// Triangle index.
        triangle: usize,
        /// The offending vertex index.
        index: u32,
        /// Number of vertices.
        vertices: usize,
    },
    /// A coordinate is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate {value:?}")]
    NonFinite {
        /// Vertex index.
        vertex: usize,
        /// The vertex position.
        value: [f32; 3],
    },
    /// A flat array's length is not a multiple of 3 (see [`TriangleMesh::from_flat`]).
    #[error("{what} has {len} values, not a multiple of 3")]
    FlatLength {
        /// `positions` or `indices`.
        what: &'static str,
        /// Values given.
        len: usize,
    },
    /// More vertices and corners than `u32` indices can number (see
    /// [`crate::SmoothNormals::new`], which may add a vertex per corner).
    #[error("{vertices} vertices and {triangles} triangles are too many to number with 32-bit indices")]
    TooLarge {
        /// Vertices.
        vertices: usize,
        /// Triangles.
        triangles: usize,
    },
    /// Normals or uvs are present but not one per vertex (or positions or values given
    /// to [`crate::SmoothNormals`] are not one per vertex of the mesh it was built for).
    #[error("{what} has {got} entries for {vertices} vertices")]
    AttributeCount {
        /// `normals`, `uvs`, `positions` or `values`.
        what: &'static str,
        /// Entries found.
        got: usize,
        /// Vertices.
        vertices: usize,
    },
}

/// An indexed triangle mesh: `positions` and, per triangle, three vertex indices.
/// Optional per-vertex `normals` and `uvs` have one entry per position.
///
/// Triangle `i` is `indices[i]`; structures refer to triangles by this index and never
/// reorder or mutate the mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Vertex indices per triangle.
    pub indices: Vec<[u32; 3]>,
    /// Optional vertex normals (one per position).
    pub normals: Option<Vec<[f32; 3]>>,
    /// Optional texture coordinates (one per position).
    pub uvs: Option<Vec<[f32; 2]>>,
}

impl TriangleMesh {
    /// Mesh from positions and triangles, without attributes.
    pub fn new(positions: Vec<[f32; 3]>, indices: Vec<[u32; 3]>) -> Self {
        Self { positions, indices, normals: None, uvs: None }
    }

    /// A validated mesh from flat slices, as other libraries and numpy hold them:
    /// `positions` is x, y, z per vertex, `indices` three vertex indices per triangle.
    /// Errors on lengths that are not multiples of 3, and as [`TriangleMesh::validate`].
    pub fn from_flat(positions: &[f32], indices: &[u32]) -> Result<Self, MeshError> {
        for (what, len) in [("positions", positions.len()), ("indices", indices.len())] {
            if len % 3 != 0 {
                return Err(MeshError::FlatLength { what, len });
            }
        }
        let mesh = Self::new(
            positions.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect(),
            indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
        );
        mesh.validate()?;
        Ok(mesh)
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Position of vertex `i`.
    #[inline]
    pub fn position(&self, i: u32) -> Vec3 {
        Vec3::from_array(self.positions[i as usize])
    }

    /// Triangle `i` with its vertices in winding order.
    #[inline]
    pub fn triangle(&self, i: usize) -> Triangle {
        let [a, b, c] = self.indices[i];
        Triangle::new(self.position(a), self.position(b), self.position(c))
    }

    /// All triangles in index order.
    pub fn triangles(&self) -> impl ExactSizeIterator<Item = Triangle> + '_ {
        (0..self.indices.len()).map(|i| self.triangle(i))
    }

    /// Bounding box of the referenced geometry (all positions).
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(self.positions.iter().map(|p| Vec3::from_array(*p)))
    }

    /// Checks what every structure assumes: at least one triangle, indices in range,
    /// finite coordinates, attribute arrays sized like `positions`.
    pub fn validate(&self) -> Result<(), MeshError> {
        if self.indices.is_empty() {
            return Err(MeshError::Empty);
        }
        let n = self.positions.len();
        for (what, got) in [("normals", self.normals.as_ref().map(Vec::len)), ("uvs", self.uvs.as_ref().map(Vec::len))]
        {
            if let Some(got) = got.filter(|&g| g != n) {
                return Err(MeshError::AttributeCount { what, got, vertices: n });
            }
        }
        if let Some((vertex, value)) = self.positions.iter().enumerate().find(|(_, p)| !p.iter().all(|c| c.is_finite()))
        {
            return Err(MeshError::NonFinite { vertex, value: *value });
        }
        for (triangle, tri) in self.indices.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&i| i as usize >= n) {
                return Err(MeshError::IndexOutOfRange { triangle, index, vertices: n });
            }
        }
        Ok(())
    }

    /// Appends `other`, renumbering its indices; attributes survive only when both have them.
    pub fn append(&mut self, other: &TriangleMesh) {
        let base = self.positions.len() as u32;
        let had_vertices = !self.positions.is_empty();
        self.normals = match (self.normals.take(), &other.normals) {
            (Some(mut a), Some(b)) => {
                a.extend_from_slice(b);
                Some(a)
            }
            (None, Some(b)) if !had_vertices => Some(b.clone()),
            _ => None,
        };
        self.uvs = match (self.uvs.take(), &other.uvs) {
            (Some(mut a), Some(b)) => {
                a.extend_from_slice(b);
                Some(a)
            }
            (None, Some(b)) if !had_vertices => Some(b.clone()),
            _ => None,
        };
        self.positions.extend_from_slice(&other.positions);
        self.indices.extend(other.indices.iter().map(|t| t.map(|i| i + base)));
    }

    /// Applies an affine point transform to positions and the matching normal transform
    /// (inverse transpose of the linear part) to normals.
    pub fn transform(&mut self, m: &glam::Mat4) {
        for p in &mut self.positions {
            *p = m.transform_point3(Vec3::from_array(*p)).to_array();
        }
        if let Some(ns) = &mut self.normals {
            let nm = glam::Mat3::from_mat4(*m).inverse().transpose();
            for n in ns {
                *n = (nm * Vec3::from_array(*n)).normalize_or_zero().to_array();
            }
        }
        // A mirroring transform flips the winding; the triangle test is two-sided and
        // shading uses interpolated normals, so nothing else changes.
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad() -> TriangleMesh {
        TriangleMesh::new(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
            vec![[0, 1, 2], [0, 2, 3]],
        )
    }

    #[test]
    fn from_flat_builds_and_checks() {
        let p = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0];
        assert_eq!(TriangleMesh::from_flat(&p, &[0, 1, 2, 0, 2, 3]).unwrap(), quad());
        assert!(matches!(
            TriangleMesh::from_flat(&p[..11], &[0, 1, 2]),
            Err(MeshError::FlatLength { what: "positions", len: 11 })
        ));
        assert!(matches!(TriangleMesh::from_flat(&p, &[0, 1]), Err(MeshError::FlatLength { what: "indices", len: 2 })));
        assert!(matches!(TriangleMesh::from_flat(&p, &[0, 1, 4]), Err(MeshError::IndexOutOfRange { index: 4, .. })));
    }

    #[test]
    fn valid_mesh_passes() {
        assert_eq!(quad().validate(), Ok(()));
    }

    #[test]
    fn empty_mesh_is_rejected() {
        assert_eq!(TriangleMesh::default().validate(), Err(MeshError::Empty));
    }

    #[test]
    fn index_out_of_range_is_rejected() {
        let mut m = quad();
        m.indices[1][2] = 4;
        assert_eq!(m.validate(), Err(MeshError::IndexOutOfRange { triangle: 1, index: 4, vertices: 4 }));
    }

    #[test]
    fn nan_vertex_is_rejected() {
        let mut m = quad();
        m.positions[2][1] = f32::NAN;
        assert!(matches!(m.validate(), Err(MeshError::NonFinite { vertex: 2, .. })));
    }

    #[test]
    fn append_renumbers() {
        let mut a = quad();
        a.append(&quad());
        assert_eq!(a.indices[3], [4, 6, 7]);
        assert_eq!(a.triangle_count(), 4);
        assert_eq!(a.validate(), Ok(()));
    }
}
