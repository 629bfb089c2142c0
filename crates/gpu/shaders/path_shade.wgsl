// The CPU path tracer (crates/render/src/path/) as the wavefront's third mode: per hit,
// emission weighted by MIS against the previous vertex's light sample, one light sample
// with its shadow ray traced here (next-event estimation, power heuristic), then one
// BSDF sample continues the path (at most one child per hit), with Russian roulette
// from depth RR_DEPTH. The emitters and BSDFs are tables the host converts from the
// CPU's own structures (dynray_render::EmitterTable, BsdfDesc). Every random number is a
// stateless hash of (sample key, sample index, depth, dimension): pt_random. Needs
// render_scene.wgsl, render_work.wgsl, whitted_shade.wgsl and bvh_traverse.wgsl.

const PI_F: f32 = 3.14159265358979;
const TAU_F: f32 = 6.28318530717959;
const INV_PI_F: f32 = 0.318309886183791;
// Mitsuba's RayEpsilon (1500 · 2^-24) and ShadowEpsilon (10 × it), as path/mod.rs.
const RAY_EPSILON: f32 = 8.9406967e-5;
const SHADOW_EPSILON: f32 = 8.9406967e-4;
// path/mod.rs RR_DEPTH.
const RR_DEPTH: u32 = 5u;

const EMITTER_AREA: u32 = 0u;
const EMITTER_POINT: u32 = 1u;
const EMITTER_DIRECTIONAL: u32 = 2u;
const EMITTER_ENVIRONMENT: u32 = 3u;

// EmitterDesc of crates/render/src/path/tables.rs: 80 bytes.
struct PtEmitter {
    // Point: position. Directional: unit direction towards the light.
    position: vec3<f32>,
    kind: u32,
    // Spot: the cone axis, normalised (zero for a point light).
    direction: vec3<f32>,
    falloff: i32,
    // Point: radiant intensity π·colour. Directional: irradiance.
    color: vec3<f32>,
    cos_inner: f32,
    cos_outer: f32,
    // Area: its triangles area[first .. first + count], total area.
    first: u32,
    count: u32,
    total: f32,
    // 1 for a spot light (cone_factor applies).
    spot: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

const LOBE_DIFFUSE: u32 = 0u;
const LOBE_PHONG: u32 = 1u;
const LOBE_MIRROR: u32 = 2u;
const LOBE_CONDUCTOR: u32 = 3u;
const LOBE_DIELECTRIC: u32 = 4u;

const MF_NONE: u32 = 0u;
const MF_BECKMANN: u32 = 1u;
const MF_GGX: u32 = 2u;

// LobeDesc of tables.rs: 64 bytes.
struct PtLobe {
    // Diffuse, Phong, Mirror: the colour. Conductor: eta. Dielectric: r.
    a: vec3<f32>,
    kind: u32,
    // Conductor: k. Dielectric: t.
    b: vec3<f32>,
    // The probability of choosing the lobe.
    prob: f32,
    // Conductor: the specular reflectance factor.
    c: vec3<f32>,
    // Phong: the exponent. Dielectric: eta (inside over outside).
    p0: f32,
    ax: f32,
    ay: f32,
    // Conductor: MF_NONE (smooth), MF_BECKMANN, MF_GGX.
    dist: u32,
    _pad: u32,
}

// A material's BSDF (BsdfDesc) and emission: 288 bytes.
struct PtMaterial {
    emission: vec3<f32>,
    lobe_count: u32,
    two_sided: u32,
    has_smooth: u32,
    _pad0: u32,
    _pad1: u32,
    lobes: array<PtLobe, 4>,
}

struct PathParams {
    // Radiance of escaping rays (black: no environment emitter).
    environment: vec3<f32>,
    emitter_count: u32,
    // Longest path in segments (Mitsuba's max_depth).
    max_depth: u32,
    any_hittable: u32,
    // Camera rays' clip planes (CameraRays::clip), used where has_clip is 1.
    clip_near: f32,
    clip_far: f32,
    has_clip: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(12) var<storage, read> pt_emitters: array<PtEmitter>;
// Emissive triangles grouped by emitter: (triangle, bits of the running area sum).
@group(0) @binding(13) var<storage, read> pt_area: array<vec2<u32>>;
// Per triangle, its actor's area emitter (0xffffffff: none).
@group(0) @binding(14) var<storage, read> pt_emitter_of_prim: array<u32>;
// Per material (the same indices as `materials`), its BSDF and emission.
@group(0) @binding(15) var<storage, read> pt_materials: array<PtMaterial>;
@group(0) @binding(16) var<uniform> pt: PathParams;

// A uniform number in [0, 1) for dimension `dim` at depth `depth` of pixel sample `k`
// (keyed `key`, the first next_u32 of the CPU's sampler of that sample and pass): the
// PCG hash chained over the four integers, as choice_random over three; top 24 bits.
fn pt_random(key: u32, k: u32, depth: u32, dim: u32) -> f32 {
    let h = pcg_hash(key ^ pcg_hash(k ^ pcg_hash((depth << 3u) ^ dim)));
    return f32(h >> 8u) * (1.0 / 16777216.0);
}

// Dimensions per depth: light choice, light point (2), triangle; BSDF lobe, direction
// (2); Russian roulette.
const DIM_LIGHT_PICK: u32 = 0u;
const DIM_LIGHT_U: u32 = 1u;
const DIM_LIGHT_TRI: u32 = 3u;
const DIM_BSDF_LOBE: u32 = 4u;
const DIM_BSDF_U: u32 = 5u;
const DIM_RR: u32 = 7u;

// f32::copysign(1, x).
fn sign_of(x: f32) -> f32 {
    return bitcast<f32>((bitcast<u32>(x) & 0x80000000u) | 0x3f800000u);
}

// local.rs `Local`: Duff et al.'s basis around unit n.
struct Basis {
    s: vec3<f32>,
    t: vec3<f32>,
    n: vec3<f32>,
}

fn basis(n: vec3<f32>) -> Basis {
    let sign = sign_of(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let s = vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let t = vec3<f32>(b, sign + n.y * n.y * a, -n.y);
    return Basis(s, t, n);
}

fn to_local(f: Basis, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot3(v, f.s), dot3(v, f.t), dot3(v, f.n));
}

fn to_world(f: Basis, v: vec3<f32>) -> vec3<f32> {
    return f.s * v.x + f.t * v.y + f.n * v.z;
}

// local.rs warps.
fn square_to_disk(u: vec2<f32>) -> vec2<f32> {
    let a = 2.0 * u.x - 1.0;
    let b = 2.0 * u.y - 1.0;
    if a == 0.0 && b == 0.0 {
        return vec2<f32>(0.0);
    }
    var r: f32;
    var phi: f32;
    if abs(a) > abs(b) {
        r = a;
        phi = (PI_F / 4.0) * (b / a);
    } else {
        r = b;
        phi = PI_F / 2.0 - (PI_F / 4.0) * (a / b);
    }
    return vec2<f32>(r * cos(phi), r * sin(phi));
}

fn cosine_hemisphere(u: vec2<f32>) -> vec3<f32> {
    let d = square_to_disk(u);
    return vec3<f32>(d.x, d.y, sqrt(max(1.0 - d.x * d.x - d.y * d.y, 0.0)));
}

fn uniform_sphere(u: vec2<f32>) -> vec3<f32> {
    let z = 1.0 - 2.0 * u.x;
    let r = sqrt(max(1.0 - z * z, 0.0));
    let phi = TAU_F * u.y;
    return vec3<f32>(r * cos(phi), r * sin(phi), z);
}

fn uniform_triangle(u: vec2<f32>) -> vec2<f32> {
    let s = sqrt(u.x);
    return vec2<f32>(1.0 - s, u.y * s);
}

// mis.rs `power_heuristic`.
fn power_heuristic(a: f32, b: f32) -> f32 {
    let a2 = a * a;
    let b2 = b * b;
    if a2 == inf_f() {
        return select(1.0, 0.5, b2 == inf_f());
    }
    if b2 == inf_f() {
        return 0.0;
    }
    let s = a2 + b2;
    if s > 0.0 {
        return a2 / s;
    }
    return 0.0;
}

// fresnel.rs `dielectric`: (R, cos θt, eta_it, eta_ti).
fn fresnel_dielectric(cos_i: f32, eta: f32) -> vec4<f32> {
    let outside = cos_i >= 0.0;
    let eta_it = select(1.0 / eta, eta, outside);
    let eta_ti = select(eta, 1.0 / eta, outside);
    let cos_t_sqr = 1.0 - eta_ti * eta_ti * (1.0 - cos_i * cos_i);
    let ci = abs(cos_i);
    let ct = sqrt(max(cos_t_sqr, 0.0));
    var r: f32;
    if eta == 1.0 {
        r = 0.0;
    } else if ci == 0.0 {
        r = 1.0;
    } else {
        let a_s = (eta_it * ct - ci) / (eta_it * ct + ci);
        let a_p = (eta_it * ci - ct) / (eta_it * ci + ct);
        r = 0.5 * (a_s * a_s + a_p * a_p);
    }
    return vec4<f32>(clamp(r, 0.0, 1.0), select(ct, -ct, outside), eta_it, eta_ti);
}

fn fresnel_conductor1(c: f32, eta: f32, k: f32) -> f32 {
    let cos2 = c * c;
    let sin2 = 1.0 - cos2;
    let eta2 = eta * eta;
    let k2 = k * k;
    let t0 = eta2 - k2 - sin2;
    let a2pb2 = sqrt(max(t0 * t0 + 4.0 * eta2 * k2, 0.0));
    let a = sqrt(max(0.5 * (a2pb2 + t0), 0.0));
    let t1 = a2pb2 + cos2;
    let t2 = 2.0 * c * a;
    let rs = (t1 - t2) / (t1 + t2);
    let t3 = cos2 * a2pb2 + sin2 * sin2;
    let t4 = t2 * sin2;
    let rp = rs * (t3 - t4) / (t3 + t4);
    let r = 0.5 * (rp + rs);
    if is_finite_f(r) {
        return clamp(r, 0.0, 1.0);
    }
    return 1.0;
}

// fresnel.rs `conductor`.
fn fresnel_conductor(cos_i: f32, eta: vec3<f32>, k: vec3<f32>) -> vec3<f32> {
    let c = clamp(cos_i, 0.0, 1.0);
    return vec3<f32>(fresnel_conductor1(c, eta.x, k.x), fresnel_conductor1(c, eta.y, k.y), fresnel_conductor1(c, eta.z, k.z));
}

// microfacet.rs `Microfacet`, its kind in l.dist and roughness in l.ax, l.ay.
fn mf_d(l: PtLobe, m: vec3<f32>) -> f32 {
    if m.z <= 0.0 {
        return 0.0;
    }
    let cos2 = m.z * m.z;
    let e = (m.x * m.x / (l.ax * l.ax) + m.y * m.y / (l.ay * l.ay)) / cos2;
    var v: f32;
    if l.dist == MF_BECKMANN {
        v = exp(-e) / (PI_F * l.ax * l.ay * cos2 * cos2);
    } else {
        let k = 1.0 + e;
        v = 1.0 / (PI_F * l.ax * l.ay * cos2 * cos2 * k * k);
    }
    if is_finite_f(v) {
        return v;
    }
    return 0.0;
}

fn mf_g1(l: PtLobe, v: vec3<f32>, m: vec3<f32>) -> f32 {
    if dot3(v, m) * v.z <= 0.0 {
        return 0.0;
    }
    let xy2 = v.x * v.x * l.ax * l.ax + v.y * v.y * l.ay * l.ay;
    if xy2 <= 0.0 {
        return 1.0;
    }
    let alpha2_tan2 = xy2 / (v.z * v.z);
    if l.dist == MF_GGX {
        return 2.0 / (1.0 + sqrt(1.0 + alpha2_tan2));
    }
    let a = 1.0 / sqrt(alpha2_tan2);
    if a >= 1.6 {
        return 1.0;
    }
    let a2 = a * a;
    return (3.535 * a + 2.181 * a2) / (1.0 + 2.276 * a + 2.577 * a2);
}

fn mf_g(l: PtLobe, wo: vec3<f32>, wi: vec3<f32>, m: vec3<f32>) -> f32 {
    return mf_g1(l, wo, m) * mf_g1(l, wi, m);
}

fn mf_pdf(l: PtLobe, wo: vec3<f32>, m: vec3<f32>) -> f32 {
    if l.dist == MF_GGX {
        if wo.z <= 0.0 {
            return 0.0;
        }
        return mf_g1(l, wo, m) * abs(dot3(wo, m)) * mf_d(l, m) / wo.z;
    }
    return mf_d(l, m) * max(m.z, 0.0);
}

fn mf_sample(l: PtLobe, wo: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    if l.dist == MF_GGX {
        // Visible normals (Heitz 2018).
        let vh = normalize_glam(vec3<f32>(l.ax * wo.x, l.ay * wo.y, wo.z));
        let lensq = vh.x * vh.x + vh.y * vh.y;
        var t1 = vec3<f32>(1.0, 0.0, 0.0);
        if lensq > 0.0 {
            t1 = vec3<f32>(-vh.y, vh.x, 0.0) / sqrt(lensq);
        }
        let t2 = cross3(vh, t1);
        let r = sqrt(u.x);
        let phi = TAU_F * u.y;
        let p1 = r * cos(phi);
        let s = 0.5 * (1.0 + vh.z);
        let p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * r * sin(phi);
        let nh = t1 * p1 + t2 * p2 + vh * sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0));
        return normalize_glam(vec3<f32>(l.ax * nh.x, l.ay * nh.y, max(nh.z, 1e-6)));
    }
    // Beckmann by D cos θ.
    let lg = log(max(1.0 - u.x, 1.17549435e-38));
    var phi: f32;
    var tan2: f32;
    if l.ax == l.ay {
        phi = TAU_F * u.y;
        tan2 = -l.ax * l.ax * lg;
    } else {
        phi = atan(l.ay / l.ax * tan(TAU_F * u.y + 0.5 * PI_F));
        if u.y > 0.5 {
            phi = phi + PI_F;
        }
        let sp = sin(phi);
        let cp = cos(phi);
        tan2 = -lg / (cp * cp / (l.ax * l.ax) + sp * sp / (l.ay * l.ay));
    }
    let c = 1.0 / sqrt(1.0 + tan2);
    let sn = sqrt(max(1.0 - c * c, 0.0));
    return vec3<f32>(sn * cos(phi), sn * sin(phi), c);
}

fn mirror_dir(wo: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(-wo.x, -wo.y, wo.z);
}

fn flip_z(v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(v.x, v.y, -v.z);
}

fn lobe_is_delta(l: PtLobe) -> bool {
    return l.kind == LOBE_MIRROR || l.kind == LOBE_DIELECTRIC || (l.kind == LOBE_CONDUCTOR && l.dist == MF_NONE);
}

// bsdf.rs `Lobe::eval`: f · cos θi of a smooth lobe.
fn lobe_eval(l: PtLobe, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    if l.kind == LOBE_DIFFUSE {
        return l.a * (INV_PI_F * wi.z);
    }
    if l.kind == LOBE_PHONG {
        let c = dot3(mirror_dir(wo), wi);
        if c <= 0.0 {
            return vec3<f32>(0.0);
        }
        return l.a * ((l.p0 + 2.0) / TAU_F * powf(c, l.p0) * wi.z);
    }
    if l.kind == LOBE_CONDUCTOR && l.dist != MF_NONE {
        let h = normalize_or_zero(wo + wi);
        if h.z <= 0.0 {
            return vec3<f32>(0.0);
        }
        let f = fresnel_conductor(dot3(wi, h), l.a, l.b);
        return l.c * f * (mf_d(l, h) * mf_g(l, wo, wi, h) / (4.0 * wo.z));
    }
    return vec3<f32>(0.0);
}

// bsdf.rs `Lobe::pdf`.
fn lobe_pdf(l: PtLobe, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    if l.kind == LOBE_DIFFUSE {
        return INV_PI_F * wi.z;
    }
    if l.kind == LOBE_PHONG {
        let c = dot3(mirror_dir(wo), wi);
        if c <= 0.0 {
            return 0.0;
        }
        return (l.p0 + 1.0) / TAU_F * powf(c, l.p0);
    }
    if l.kind == LOBE_CONDUCTOR && l.dist != MF_NONE {
        let h = normalize_or_zero(wo + wi);
        let d = dot3(wo, h);
        if h.z <= 0.0 || d <= 0.0 {
            return 0.0;
        }
        return mf_pdf(l, wo, h) / (4.0 * d);
    }
    return 0.0;
}

struct BsdfSample {
    wi: vec3<f32>,
    weight: vec3<f32>,
    pdf: f32,
    delta: bool,
    eta: f32,
    ok: bool,
}

fn no_sample() -> BsdfSample {
    var s: BsdfSample;
    s.ok = false;
    return s;
}

fn a_sample(wi: vec3<f32>, weight: vec3<f32>, pdf: f32, delta: bool, eta: f32) -> BsdfSample {
    return BsdfSample(wi, weight, pdf, delta, eta, true);
}

// bsdf.rs `Lobe::sample`.
fn lobe_sample(l: PtLobe, wo: vec3<f32>, u1: f32, u2: vec2<f32>) -> BsdfSample {
    if l.kind == LOBE_DIELECTRIC {
        // sample_dielectric: reflect with probability R, else refract (radiance × eta_ti²).
        if wo.z == 0.0 {
            return no_sample();
        }
        let fr = fresnel_dielectric(wo.z, l.p0);
        if u1 < fr.x {
            return a_sample(mirror_dir(wo), l.a, fr.x, true, 1.0);
        }
        let eta_ti = fr.w;
        let wi = vec3<f32>(-eta_ti * wo.x, -eta_ti * wo.y, fr.y);
        return a_sample(wi, l.b * (eta_ti * eta_ti), 1.0 - fr.x, true, fr.z);
    }
    if wo.z <= 0.0 {
        return no_sample();
    }
    if l.kind == LOBE_DIFFUSE {
        let wi = cosine_hemisphere(u2);
        if wi.z > 0.0 {
            return a_sample(wi, l.a, INV_PI_F * wi.z, false, 1.0);
        }
        return no_sample();
    }
    if l.kind == LOBE_MIRROR {
        return a_sample(mirror_dir(wo), l.a, 1.0, true, 1.0);
    }
    if l.kind == LOBE_CONDUCTOR && l.dist == MF_NONE {
        let f = fresnel_conductor(wo.z, l.a, l.b);
        return a_sample(mirror_dir(wo), l.c * f, 1.0, true, 1.0);
    }
    var wi: vec3<f32>;
    if l.kind == LOBE_PHONG {
        let c = powf(u2.x, 1.0 / (l.p0 + 1.0));
        let sn = sqrt(max(1.0 - c * c, 0.0));
        let phi = TAU_F * u2.y;
        let f = basis(mirror_dir(wo));
        wi = to_world(f, vec3<f32>(sn * cos(phi), sn * sin(phi), c));
        let pdf = lobe_pdf(l, wo, wi);
        if pdf > 0.0 {
            return a_sample(wi, lobe_eval(l, wo, wi) / pdf, pdf, false, 1.0);
        }
        return no_sample();
    }
    // Rough conductor.
    let m = mf_sample(l, wo, u2);
    let d = dot3(wo, m);
    if d <= 0.0 {
        return no_sample();
    }
    wi = m * (2.0 * d) - wo;
    if wi.z <= 0.0 {
        return no_sample();
    }
    let pdf = mf_pdf(l, wo, m) / (4.0 * d);
    if !(pdf > 0.0) {
        return no_sample();
    }
    let f = fresnel_conductor(d, l.a, l.b);
    let weight = l.c * f * (mf_d(l, m) * mf_g(l, wo, wi, m) / (4.0 * wo.z)) / pdf;
    return a_sample(wi, weight, pdf, false, 1.0);
}

// Bsdf::side: flipped to the upper side for a two-sided BSDF seen from below.
fn side_flip(b: PtMaterial, l: PtLobe, wo: vec3<f32>) -> bool {
    return b.two_sided != 0u && wo.z < 0.0 && l.kind != LOBE_DIELECTRIC;
}

// Bsdf::eval.
fn bsdf_eval(m: u32, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    let b = pt_materials[m];
    var f = vec3<f32>(0.0);
    for (var i = 0u; i < b.lobe_count; i = i + 1u) {
        let l = b.lobes[i];
        if lobe_is_delta(l) {
            continue;
        }
        if side_flip(b, l, wo) {
            f = f + lobe_eval(l, flip_z(wo), flip_z(wi));
        } else {
            f = f + lobe_eval(l, wo, wi);
        }
    }
    return f;
}

// Bsdf::pdf.
fn bsdf_pdf(m: u32, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    let b = pt_materials[m];
    var p = 0.0;
    for (var i = 0u; i < b.lobe_count; i = i + 1u) {
        let l = b.lobes[i];
        if lobe_is_delta(l) {
            continue;
        }
        if side_flip(b, l, wo) {
            p = p + l.prob * lobe_pdf(l, flip_z(wo), flip_z(wi));
        } else {
            p = p + l.prob * lobe_pdf(l, wo, wi);
        }
    }
    return p;
}

// Bsdf::sample: a lobe by its probability, the rest of u1 reused within it.
fn bsdf_sample(m: u32, wo: vec3<f32>, u1: f32, u2: vec2<f32>) -> BsdfSample {
    let b = pt_materials[m];
    if b.lobe_count == 0u {
        return no_sample();
    }
    var u = u1;
    var chosen = b.lobe_count - 1u;
    for (var i = 0u; i < b.lobe_count; i = i + 1u) {
        let p = b.lobes[i].prob;
        if u < p {
            chosen = i;
            break;
        }
        u = u - p;
    }
    let l = b.lobes[chosen];
    let p = l.prob;
    // 1 - f32::EPSILON / 2, by its bits.
    u = clamp(u / p, 0.0, bitcast<f32>(0x3f7fffffu));
    let flipped = side_flip(b, l, wo);
    var o = wo;
    if flipped {
        o = flip_z(wo);
    }
    var s = lobe_sample(l, o, u, u2);
    if !s.ok {
        return s;
    }
    if flipped {
        s.wi = flip_z(s.wi);
    }
    if s.delta {
        s.weight = s.weight / p;
        s.pdf = s.pdf * p;
    } else {
        let pdf = bsdf_pdf(m, wo, s.wi);
        if !(pdf > 0.0) {
            return no_sample();
        }
        s.weight = bsdf_eval(m, wo, s.wi) / pdf;
        s.pdf = pdf;
    }
    return s;
}

struct LightSample {
    wi: vec3<f32>,
    dist: f32,
    weight: vec3<f32>,
    pdf: f32,
    delta: bool,
    ok: bool,
}

fn no_light() -> LightSample {
    var s: LightSample;
    s.ok = false;
    return s;
}

fn finite3(v: vec3<f32>) -> bool {
    return is_finite3(v);
}

// lights.rs `Lights::sample` for shading point p, numbers u0 (pick), u (point), u3
// (triangle).
fn sample_light(p: vec3<f32>, u0: f32, u: vec2<f32>, u3: f32) -> LightSample {
    let n = pt.emitter_count;
    if n == 0u {
        return no_light();
    }
    let pick = min(u32(u0 * f32(n)), n - 1u);
    let sel = 1.0 / f32(n);
    let e = pt_emitters[pick];
    if e.kind == EMITTER_AREA {
        let target_area = u3 * e.total;
        // partition_point(|c| c <= target) over the group's running sums.
        var lo = 0u;
        var hi = e.count;
        loop {
            if lo >= hi {
                break;
            }
            let mid = (lo + hi) / 2u;
            if bitcast<f32>(pt_area[e.first + mid].y) <= target_area {
                lo = mid + 1u;
            } else {
                hi = mid;
            }
        }
        let i = min(lo, e.count - 1u);
        let prim = pt_area[e.first + i].x;
        let p0 = vertex(indices[3u * prim]);
        let p1 = vertex(indices[3u * prim + 1u]);
        let p2 = vertex(indices[3u * prim + 2u]);
        let bc = uniform_triangle(u);
        let q = p0 * (1.0 - bc.x - bc.y) + p1 * bc.x + p2 * bc.y;
        let nl = normalize_or_zero(cross3(p1 - p0, p2 - p0));
        let to = q - p;
        let d2 = dot3(to, to);
        let dist = sqrt(d2);
        if !(dist > 0.0) {
            return no_light();
        }
        let wi = to / dist;
        let cos_l = -dot3(nl, wi);
        if !(cos_l > 0.0) {
            return no_light();
        }
        let pdf = sel * d2 / (cos_l * e.total);
        let mat = min(material_ids[prim], scene.material_count - 1u);
        let weight = pt_materials[mat].emission / pdf;
        if !(is_finite_f(pdf) && finite3(weight)) {
            return no_light();
        }
        return LightSample(wi, dist, weight, pdf, false, true);
    }
    if e.kind == EMITTER_POINT {
        let to = e.position - p;
        let dist = sqrt(dot3(to, to));
        if !(dist > 0.0 && is_finite_f(dist)) {
            return no_light();
        }
        let wi = to / dist;
        let att = powi(dist, clamp(e.falloff, -8, 8));
        var cone = 1.0;
        if e.spot != 0u {
            var l: Light;
            l.kind = LIGHT_SPOT;
            l.direction = e.direction;
            l.cos_inner = e.cos_inner;
            l.cos_outer = e.cos_outer;
            cone = cone_factor(l, -wi);
        }
        let weight = e.color * cone / (att * sel);
        if !finite3(weight) {
            return no_light();
        }
        return LightSample(wi, dist, weight, 1.0, true, true);
    }
    if e.kind == EMITTER_DIRECTIONAL {
        return LightSample(e.position, inf_f(), e.color / sel, 1.0, true, true);
    }
    let wi = uniform_sphere(u);
    let pdf = sel / (4.0 * PI_F);
    return LightSample(wi, inf_f(), pt.environment / pdf, pdf, false, true);
}

// Lights::pdf_area: the density (solid angle at `from`) of light sampling picking the
// point p of triangle prim, geometric normal ng.
fn pdf_area(prim: u32, p: vec3<f32>, ng: vec3<f32>, from_p: vec3<f32>) -> f32 {
    let ei = pt_emitter_of_prim[prim];
    if ei == 0xffffffffu || pt.emitter_count == 0u {
        return 0.0;
    }
    let e = pt_emitters[ei];
    if e.kind != EMITTER_AREA {
        return 0.0;
    }
    let to = p - from_p;
    let d2 = dot3(to, to);
    let cos_l = abs(dot3(ng, to)) / sqrt(d2);
    if !(cos_l > 0.0) {
        return 0.0;
    }
    return (1.0 / f32(pt.emitter_count)) * d2 / (cos_l * e.total);
}

fn pdf_environment() -> f32 {
    if max_element(pt.environment) > 0.0 && pt.emitter_count > 0u {
        return (1.0 / f32(pt.emitter_count)) / (4.0 * PI_F);
    }
    return 0.0;
}

// path/mod.rs `offset`: p moved off its surface to the side d goes.
fn pt_offset(p: vec3<f32>, ng: vec3<f32>, d: vec3<f32>) -> vec3<f32> {
    var mag = (1.0 + max_element(abs(p))) * RAY_EPSILON;
    if !is_finite_f(mag) {
        mag = 0.0;
    }
    return select(p - ng * mag, p + ng * mag, dot3(ng, d) >= 0.0);
}

// The MIS weight of emission a BSDF-sampled ray found, given the light density of what
// it hit: 1 after the camera or a delta bounce (prev_smooth 0).
fn mis_bsdf(r: RayRec, light_pdf: f32) -> f32 {
    if r.prev_smooth == 0u {
        return 1.0;
    }
    return power_heuristic(r.prev_pdf, light_pdf);
}

// Zeroes NaN and infinite channels (PathTracer::radiance does so for a sample's sum).
fn finite_or_zero(c: vec3<f32>) -> vec3<f32> {
    return select(c, vec3<f32>(0.0), vec3<bool>(!is_finite_f(c.x), !is_finite_f(c.y), !is_finite_f(c.z)));
}

// Slots: rays_in (the wave), hits, flags (1 = hit), contrib (the environment, weighted
// by MIS, on a miss). Camera rays (level 1) run between the camera's clip planes.
@compute @workgroup_size(64)
fn pt_trace(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = wave_index(gid);
    if i >= work.n {
        return;
    }
    let r = rays_in[i];
    var tmin = 0.0;
    var tmax = inf_f();
    if r.level == 1u && pt.has_clip != 0u {
        var c = 1.0;
        if scene.cam_parallel == 0u {
            c = dot3(r.dir, scene.cam_forward);
        }
        tmin = pt.clip_near / c;
        tmax = pt.clip_far / c;
    }
    let h = closest_hit(prepare(r.org, r.dir, tmin, tmax));
    hits[i] = h;
    if h.prim == NO_HIT {
        flags[i] = 0u;
        var c = vec3<f32>(0.0);
        if max_element(pt.environment) > 0.0 {
            c = r.thr * pt.environment * mis_bsdf(r, pdf_environment());
        }
        contrib[i] = vec4<f32>(finite_or_zero(c), 0.0);
    } else {
        flags[i] = 1u;
        contrib[i] = vec4<f32>(0.0);
    }
}

// Slots: rays_in (the wave), hits, list_in (wave indices of the hits), rays_out and
// flags (two child slots per shaded ray; the path uses the first), contrib, counters.
// work.b: the batch's first sample (so that `work.b + sample` is the pixel sample k).
// path/mod.rs `PathTracer::trace`, one iteration of its loop per dispatch. The ray's
// `level` is the CPU's depth + 1, `weight` its η product, `prev_pdf`/`prev_smooth` the
// previous vertex's BSDF sample.
@compute @workgroup_size(64)
fn pt_shade(@builtin(global_invocation_id) gid: vec3<u32>) {
    let j = wave_index(gid);
    if j >= work.n {
        return;
    }
    let i = list_in[j];
    let r = rays_in[i];
    let h = hits[i];
    flags[2u * j] = 0u;
    flags[2u * j + 1u] = 0u;
    let depth = r.level - 1u;
    let k = work.b + r.sample;
    let s = surface(r.dir, h);
    // The CPU's SurfaceHit: the winding's normal and the unflipped shading normal.
    let ng = select(-s.ng, s.ng, s.entering);
    let ns = s.ns_raw;
    let p = s.p;
    let mat = s.material;
    let wo = -normalize_or_zero(r.dir);
    var result = vec3<f32>(0.0);
    let e = pt_materials[mat].emission;
    if max_element(e) > 0.0 && dot3(ng, wo) > 0.0 {
        result = result + r.thr * e * mis_bsdf(r, pdf_area(h.prim, p, ng, r.org));
    }
    var shadow = 0u;
    var go_on = depth + 1u < pt.max_depth;
    var child: RayRec;
    if go_on {
        let f = basis(ns);
        let wo_l = to_local(f, wo);
        // Next-event estimation.
        if pt_materials[mat].has_smooth != 0u && pt.emitter_count > 0u {
            let ls = sample_light(
                p,
                pt_random(r.key, k, depth, DIM_LIGHT_PICK),
                vec2<f32>(pt_random(r.key, k, depth, DIM_LIGHT_U), pt_random(r.key, k, depth, DIM_LIGHT_U + 1u)),
                pt_random(r.key, k, depth, DIM_LIGHT_TRI),
            );
            if ls.ok {
                let wi_l = to_local(f, ls.wi);
                let fv = bsdf_eval(mat, wo_l, wi_l);
                if max_element(fv) > 0.0 {
                    let origin = pt_offset(p, ng, ls.wi);
                    var tmax = inf_f();
                    if is_finite_f(ls.dist) {
                        let moved = origin - p;
                        tmax = (ls.dist - sqrt(dot3(moved, moved))) * (1.0 - SHADOW_EPSILON);
                    }
                    shadow = 1u;
                    if tmax > 0.0 && !any_hit(prepare(origin, ls.wi, 0.0, tmax)) {
                        var w = 1.0;
                        if !ls.delta {
                            w = power_heuristic(ls.pdf, bsdf_pdf(mat, wo_l, wi_l));
                        }
                        result = result + r.thr * fv * ls.weight * w;
                    }
                }
            }
        }
        // The next segment only matters if it can gather emission or shade again.
        if pt.any_hittable == 0u && depth + 2u >= pt.max_depth {
            go_on = false;
        }
        if go_on {
            let bs = bsdf_sample(
                mat,
                wo_l,
                pt_random(r.key, k, depth, DIM_BSDF_LOBE),
                vec2<f32>(pt_random(r.key, k, depth, DIM_BSDF_U), pt_random(r.key, k, depth, DIM_BSDF_U + 1u)),
            );
            var wi = vec3<f32>(0.0);
            if bs.ok {
                wi = normalize_or_zero(to_world(f, bs.wi));
            }
            if !bs.ok || all_zero(wi) || !finite3(bs.weight) {
                go_on = false;
            } else {
                var thr = r.thr * bs.weight;
                let eta = r.weight * bs.eta;
                let t_max = max_element(thr);
                if !(t_max > 0.0) {
                    go_on = false;
                } else if depth + 1u >= RR_DEPTH {
                    let q = min(t_max * eta * eta, 0.95);
                    if pt_random(r.key, k, depth, DIM_RR) >= q {
                        go_on = false;
                    } else {
                        thr = thr / q;
                    }
                }
                child.org = pt_offset(p, ng, wi);
                child.dir = wi;
                child.sample = r.sample;
                child.level = r.level + 1u;
                child.thr = thr;
                child.weight = eta;
                child.path = r.path;
                child.key = r.key;
                child.prev_pdf = bs.pdf;
                child.prev_smooth = select(1u, 0u, bs.delta);
            }
        }
    }
    contrib[i] = vec4<f32>(finite_or_zero(result), 0.0);
    if go_on {
        flags[2u * j] = 1u;
        rays_out[2u * j] = child;
    }
    count_rays(shadow, 0u);
}
