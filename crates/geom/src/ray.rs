//! Rays and the per-ray constants the watertight triangle test and the slab test need.

use glam::Vec3;

/// A ray `origin + t * dir` restricted to the closed interval `[tmin, tmax]`.
///
/// `dir` need not be normalised; `t` is measured in units of `dir`.
///
/// `#[repr(C)]` and Pod, 8 `f32`s in the order of `trace-rays`' (N, 8) rows (origin,
/// direction, tmin, tmax), so a flat `&[f32]` of such rows is a `&[Ray]` without copying
/// (`bytemuck::cast_slice`) and the same bytes upload to a GPU buffer.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Ray {
    /// Start point.
    pub origin: Vec3,
    /// Direction (any length, not all zero for a useful ray).
    pub dir: Vec3,
    /// Smallest accepted hit distance.
    pub tmin: f32,
    /// Largest accepted hit distance (may be `f32::INFINITY`).
    pub tmax: f32,
}

// 6 + 2 floats, no padding: what (N, 8) float32 ray arrays hold per row.
const _: () = assert!(std::mem::size_of::<Ray>() == 32);

impl Ray {
    /// A ray over `[0, ∞]`.
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Self { origin, dir, tmin: 0.0, tmax: f32::INFINITY }
    }

    /// A ray over `[tmin, tmax]`.
    pub fn with_interval(origin: Vec3, dir: Vec3, tmin: f32, tmax: f32) -> Self {
        Self { origin, dir, tmin, tmax }
    }

    /// The point at distance `t`.
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }
}

/// A ray with the constants of the watertight test (Woop, Benthin, Wald 2013) and the
/// reciprocal direction of the slab test, computed once per ray.
#[derive(Clone, Copy, Debug)]
pub struct PreparedRay {
    /// The ray itself.
    pub ray: Ray,
    /// `1 / dir` per axis (±∞ for a zero component).
    pub inv_dir: Vec3,
    /// Axis permutation: `kz` is the dominant axis of `dir`, `kx`, `ky` the others, swapped
    /// when `dir[kz] < 0` to keep the triangle winding.
    pub k: [usize; 3],
    /// Shear constants `dir[kx]/dir[kz]`, `dir[ky]/dir[kz]`, `1/dir[kz]`, in f64 like
    /// the whole triangle test.
    pub shear: [f64; 3],
    /// The origin permuted to `(kx, ky, kz)`, in f64.
    pub origin64: [f64; 3],
}

impl PreparedRay {
    /// Computes the per-ray constants. `#[inline]` so the wide BVH's walks (another crate,
    /// compiled for AVX2/AVX-512) take it inline at their first leaf: out of line it was
    /// ~8 % of the bunny's shadow and diffuse traversal profile.
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        // Written without branches on the direction: incoherent rays mispredicted the
        // dominant-axis and swap branches at about one ray in two (diffuse rays +5-7 %).
        // Coherent rays, whose branches were predicted, pay for the indexed loads instead:
        // occluded camera-ray packets -2 to -4 % (docs/structures.md, "Where it stands").
        let d = [ray.dir.x, ray.dir.y, ray.dir.z];
        let a = d.map(f32::abs);
        // Dominant axis; ties go to the lower axis so the choice is deterministic (x when
        // it is at least y and z, else y when it is at least z, else z; false on NaN).
        let x_first = (a[0] >= a[1]) & (a[0] >= a[2]);
        let y_over_z = a[1] >= a[2];
        let kz = (!x_first) as usize * (2 - y_over_z as usize);
        // (kx, ky) = ((kz + 1) % 3, (kz + 2) % 3), swapped when dir[kz] < 0 to keep the
        // triangle winding.
        const AXES: [[usize; 2]; 6] = [[1, 2], [2, 1], [2, 0], [0, 2], [0, 1], [1, 0]];
        let [kx, ky] = AXES[2 * kz + (d[kz] < 0.0) as usize];
        let (dx, dy, dz) = (d[kx] as f64, d[ky] as f64, d[kz] as f64);
        let shear = [dx / dz, dy / dz, 1.0 / dz];
        let o = [ray.origin.x, ray.origin.y, ray.origin.z];
        let origin64 = [o[kx] as f64, o[ky] as f64, o[kz] as f64];
        Self { ray: *ray, inv_dir: Vec3::ONE / ray.dir, k: [kx, ky, kz], shear, origin64 }
    }
}

impl From<&Ray> for PreparedRay {
    fn from(r: &Ray) -> Self {
        Self::new(r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_row_of_eight_floats_is_a_ray() {
        let rows = [1.0f32, 2.0, 3.0, 0.0, 0.0, -1.0, 0.5, f32::INFINITY, 4.0, 5.0, 6.0, 1.0, 0.0, 0.0, 0.0, 9.0];
        let rays: &[Ray] = bytemuck::cast_slice(&rows);
        assert_eq!(rays[0], Ray::with_interval(Vec3::new(1.0, 2.0, 3.0), Vec3::NEG_Z, 0.5, f32::INFINITY));
        assert_eq!(rays[1], Ray::with_interval(Vec3::new(4.0, 5.0, 6.0), Vec3::X, 0.0, 9.0));
    }

    /// The axis choice as first written, with branches: the specification `new` keeps.
    fn axes_with_branches(d: Vec3) -> [usize; 3] {
        let a = d.abs();
        let kz = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        [kx, ky, kz]
    }

    #[test]
    fn branch_free_axis_choice_is_the_branching_one() {
        // Every sign, tie, zero, infinity and NaN pattern over the three components.
        let values = [0.0f32, -0.0, 1.0, -1.0, 2.0, -2.0, 1e-40, f32::INFINITY, f32::NEG_INFINITY, f32::NAN];
        for &x in &values {
            for &y in &values {
                for &z in &values {
                    let d = Vec3::new(x, y, z);
                    let p = PreparedRay::new(&Ray::new(Vec3::new(0.5, -1.5, 2.5), d));
                    assert_eq!(p.k, axes_with_branches(d), "direction {d:?}");
                    let o = [0.5f32, -1.5, 2.5];
                    assert_eq!(p.origin64, p.k.map(|k| o[k] as f64), "direction {d:?}");
                    let dk = p.k.map(|k| d[k] as f64);
                    let shear = [dk[0] / dk[2], dk[1] / dk[2], 1.0 / dk[2]];
                    assert_eq!(p.shear.map(f64::to_bits), shear.map(f64::to_bits), "direction {d:?}");
                }
            }
        }
    }
}
