//! What an integrator learns about a ray's closest hit: a surface interaction, whatever
//! kind of geometry was hit, so that no integrator reads mesh arrays.

use dynray_geom::{Vec2, Vec3};
use dynray_scene::{Color, Material};

/// Which piece of the scene a hit is on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct GeometryRef {
    /// Index of the geometry in the [`crate::SceneIntersector`] (0: the frame's triangles).
    pub geometry: u32,
    /// Instance of that geometry (0 where the geometry is not instanced).
    pub instance: u32,
    /// Primitive within the geometry: the triangle index in the frame's mesh for
    /// triangles.
    pub prim: u32,
}

/// A ray's closest hit, ready for shading.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceHit<'a> {
    /// Ray parameter of the hit.
    pub t: f32,
    /// Hit point (for triangles, from the barycentrics: on the triangle's plane).
    pub p: Vec3,
    /// Unit geometric normal, as the geometry orients it (outwards for triangles wound
    /// counter-clockwise); never flipped towards the ray.
    pub ng: Vec3,
    /// Unit shading normal (interpolated vertex normals where the geometry has them,
    /// otherwise `ng`); not flipped towards the ray either.
    pub ns: Vec3,
    /// Surface parameters: texture coordinates where the geometry has them, otherwise
    /// the primitive's own parameterisation (barycentric `(u, v)` for triangles).
    pub uv: Vec2,
    /// The material at the hit.
    pub material: &'a Material,
    /// The material's diffuse texture at the hit (linear RGB), white where it has none
    /// or the geometry has no texture coordinates; the geometry resolves it (with
    /// [`Material::diffuse_texel`]) so shading never reads textures or mesh arrays.
    /// Shade with [`SurfaceHit::diffuse`] and [`SurfaceHit::ambient`].
    pub texel: Color,
    /// Which geometry, instance and primitive.
    pub at: GeometryRef,
}

impl SurfaceHit<'_> {
    /// Lambertian reflectance at the hit: the material's diffuse colour times its
    /// texture. Every integrator and the `albedo` AOV read the base colour here.
    pub fn diffuse(&self) -> Color {
        self.material.diffuse * self.texel
    }

    /// Reflectance for ambient light at the hit: the material's ambient colour times its
    /// texture (a textured surface is textured in shadow too).
    pub fn ambient(&self) -> Color {
        self.material.ambient * self.texel
    }
}
