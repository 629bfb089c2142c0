//! The four ray sets of the bench, generated once per scene from a fixed seed and shared
//! by every structure: primary (coherent), shadow (towards a light, any-hit), diffuse
//! (cosine-weighted bounces: incoherent) and random (uniform in the scene box).

use dynray_accel::{Accel, BatchQuery};
use dynray_geom::{Hit, Ray, Vec3};
use dynray_render::CameraRays;
use dynray_scene::{Frame, LightKind};
use rand::{rngs::StdRng, Rng, SeedableRng};
use serde::Serialize;

/// Seed of every random ray set: the same scene and size always give the same rays.
pub const SEED: u64 = 0x00d7_7a11_5eed;

/// A kind of ray.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum RayKind {
    /// One ray per pixel centre from the camera (closest hit).
    Primary,
    /// From each primary hit to the first light (any hit, `occluded`).
    Shadow,
    /// A cosine-weighted bounce from each primary hit (closest hit).
    Diffuse,
    /// Uniform origins in the scene box, uniform directions (closest hit).
    Random,
}

impl RayKind {
    /// All kinds, in report order.
    pub const ALL: [RayKind; 4] = [RayKind::Primary, RayKind::Shadow, RayKind::Diffuse, RayKind::Random];

    /// The `--rays` spelling.
    pub fn name(self) -> &'static str {
        match self {
            RayKind::Primary => "primary",
            RayKind::Shadow => "shadow",
            RayKind::Diffuse => "diffuse",
            RayKind::Random => "random",
        }
    }

    /// True for any-hit rays (timed with `occluded`).
    pub fn is_shadow(self) -> bool {
        self == RayKind::Shadow
    }
}

impl std::str::FromStr for RayKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        RayKind::ALL
            .iter()
            .copied()
            .find(|k| k.name() == s)
            .ok_or_else(|| format!("unknown ray kind `{s}` (expected one of: primary, shadow, diffuse, random)"))
    }
}

/// Primary rays, one per pixel, row-major from the top-left (heat maps rely on the order).
pub fn primary(frame: &Frame, width: u32, height: u32) -> Vec<Ray> {
    let cam = CameraRays::new(&frame.camera, width, height);
    (0..height).flat_map(|y| (0..width).map(move |x| (x, y))).map(|(x, y)| cam.primary(x, y)).collect()
}

/// A point just off the surface of `hit`, on the side `towards` points to, and the
/// geometric normal facing that side. Offset as the Whitted integrator does: relative to
/// the scene size and to the point's magnitude.
fn surface_point(frame: &Frame, ray: &Ray, hit: &Hit, towards: Vec3, scene_eps: f32) -> (Vec3, Vec3) {
    let [a, b, c] = frame.mesh.indices[hit.prim as usize];
    let (p0, p1, p2) = (frame.mesh.position(a), frame.mesh.position(b), frame.mesh.position(c));
    let p = p0 * (1.0 - hit.u - hit.v) + p1 * hit.u + p2 * hit.v;
    let mut n = (p1 - p0).cross(p2 - p0).normalize_or_zero();
    if n == Vec3::ZERO || !n.is_finite() {
        n = -ray.dir.normalize_or_zero();
    }
    let n = if n.dot(towards) >= 0.0 { n } else { -n };
    let eps = scene_eps + p.abs().max_element() * 1e-5;
    (p + n * eps, n)
}

fn scene_eps(frame: &Frame) -> f32 {
    let d = frame.mesh.bounds().extent().length();
    if d.is_finite() && d > 0.0 {
        d * 1e-5
    } else {
        1e-5
    }
}

/// Shadow rays from every primary hit to the frame's first light (none without a light).
pub fn shadow(frame: &Frame, primary: &[Ray], hits: &[Hit]) -> Vec<Ray> {
    let Some(light) = frame.lights.first() else { return Vec::new() };
    let eps = scene_eps(frame);
    let mut out = Vec::with_capacity(hits.len());
    for (r, h) in primary.iter().zip(hits).filter(|(_, h)| h.is_hit()) {
        let hp = r.at(h.t);
        let dir = match light.kind {
            LightKind::Point { position, .. } | LightKind::Spot { position, .. } => (position - hp).normalize_or_zero(),
            LightKind::Directional { direction } => -direction.normalize_or_zero(),
        };
        if dir == Vec3::ZERO || !dir.is_finite() {
            continue;
        }
        let (o, _) = surface_point(frame, r, h, dir, eps);
        let ray = match light.kind {
            // Re-aim from the offset origin so the ray ends just short of the light.
            LightKind::Point { position, .. } | LightKind::Spot { position, .. } => {
                let d = position - o;
                Ray::with_interval(o, d.normalize_or_zero(), 0.0, (d.length() - eps).max(0.0))
            }
            LightKind::Directional { .. } => Ray::with_interval(o, dir, 0.0, f32::INFINITY),
        };
        out.push(ray);
    }
    out
}

/// Cosine-weighted bounce rays from every primary hit, on the side the ray came from.
pub fn diffuse(frame: &Frame, primary: &[Ray], hits: &[Hit]) -> Vec<Ray> {
    let mut rng = StdRng::seed_from_u64(SEED ^ 0xd1ff);
    let eps = scene_eps(frame);
    let mut out = Vec::with_capacity(hits.len());
    for (r, h) in primary.iter().zip(hits).filter(|(_, h)| h.is_hit()) {
        let (o, n) = surface_point(frame, r, h, -r.dir, eps);
        // Malley's method: a uniform disk sample lifted onto the hemisphere.
        let (r1, r2): (f32, f32) = (rng.gen(), rng.gen());
        let (rad, phi) = (r1.sqrt(), std::f32::consts::TAU * r2);
        let (x, y, z) = (rad * phi.cos(), rad * phi.sin(), (1.0 - r1).max(0.0).sqrt());
        let (t, b) = orthonormal_basis(n);
        let d = (t * x + b * y + n * z).normalize_or_zero();
        if d != Vec3::ZERO {
            out.push(Ray::new(o, d));
        }
    }
    out
}

/// Two unit vectors completing `n` to an orthonormal basis (Duff et al. 2017).
fn orthonormal_basis(n: Vec3) -> (Vec3, Vec3) {
    let s = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    (Vec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x), Vec3::new(b, s + n.y * n.y * a, -n.y))
}

/// `count` rays with origins uniform in the scene's box and directions uniform on the sphere.
pub fn random(frame: &Frame, count: usize) -> Vec<Ray> {
    let mut rng = StdRng::seed_from_u64(SEED ^ 0x7a4d);
    let b = frame.mesh.bounds();
    (0..count)
        .map(|_| {
            let o = b.min + (b.max - b.min) * Vec3::new(rng.gen(), rng.gen(), rng.gen());
            let z: f32 = rng.gen_range(-1.0..=1.0);
            let phi = std::f32::consts::TAU * rng.gen::<f32>();
            let s = (1.0 - z * z).max(0.0).sqrt();
            Ray::new(o, Vec3::new(s * phi.cos(), s * phi.sin(), z))
        })
        .collect()
}

/// The ray sets of one scene.
pub struct RaySets {
    /// `(kind, rays)` in the order asked for.
    pub sets: Vec<(RayKind, Vec<Ray>)>,
}

/// Generates the asked kinds for `frame` at `width` × `height`; primary hits (needed by
/// shadow and diffuse rays) come from `reference`, any structure built on the frame's mesh
/// (they are checked against brute force with the rest).
pub fn generate(frame: &Frame, width: u32, height: u32, kinds: &[RayKind], reference: &dyn Accel) -> RaySets {
    let prim = primary(frame, width, height);
    let needs_hits = kinds.iter().any(|k| matches!(k, RayKind::Shadow | RayKind::Diffuse));
    let hits = if needs_hits { reference.intersect_batch(&prim) } else { Vec::new() };
    let n = prim.len();
    let sets = kinds
        .iter()
        .map(|&k| {
            let rays = match k {
                RayKind::Primary => prim.clone(),
                RayKind::Shadow => shadow(frame, &prim, &hits),
                RayKind::Diffuse => diffuse(frame, &prim, &hits),
                RayKind::Random => random(frame, n),
            };
            (k, rays)
        })
        .collect();
    RaySets { sets }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_orthonormal() {
        for n in [Vec3::Z, -Vec3::Z, Vec3::X, Vec3::new(0.3, -0.5, 0.81).normalize()] {
            let (t, b) = orthonormal_basis(n);
            assert!(t.dot(n).abs() < 1e-5 && b.dot(n).abs() < 1e-5 && t.dot(b).abs() < 1e-5, "{n}");
            assert!((t.length() - 1.0).abs() < 1e-5 && (b.length() - 1.0).abs() < 1e-5);
        }
    }

    #[test]
    fn kinds_round_trip_and_unknown_is_named() {
        for k in RayKind::ALL {
            assert_eq!(k.name().parse::<RayKind>().unwrap(), k);
        }
        assert!("glossy".parse::<RayKind>().unwrap_err().contains("glossy"));
    }
}
