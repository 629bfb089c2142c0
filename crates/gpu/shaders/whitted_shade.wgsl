// The CPU Whitted integrator's shading (crates/render/src/whitted.rs, shadow.rs,
// facing.rs, intersector.rs) in f32, operation for operation: Phong per light with
// shadow rays that pass through transparent surfaces, then the mirror and Fresnel-split
// refraction rays, bounded by level and weight. What differs from the CPU is only how the
// device rounds (pow, fused multiply-adds the shader compiler may form), which the image
// tests bound. Needs render_scene.wgsl, render_work.wgsl and bvh_traverse.wgsl.

// +inf (a function: constant expressions may not overflow).
fn inf_f() -> f32 {
    return bitcast<f32>(0x7f800000u);
}

fn is_finite_f(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

fn is_finite3(v: vec3<f32>) -> bool {
    return is_finite_f(v.x) && is_finite_f(v.y) && is_finite_f(v.z);
}

fn is_nan_f(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7fffffffu) > 0x7f800000u;
}

// glam's Vec3::dot, in its order.
fn dot3(a: vec3<f32>, b: vec3<f32>) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

// glam's f32::max: the other operand when one is NaN.
fn fmax(a: f32, b: f32) -> f32 {
    if is_nan_f(a) {
        return b;
    }
    if is_nan_f(b) {
        return a;
    }
    return max(a, b);
}

// Vec3::max_element: x.max(y.max(z)).
fn max_element(v: vec3<f32>) -> f32 {
    return fmax(v.x, fmax(v.y, v.z));
}

fn cross3(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
}

// Vec3::normalize: v · (1 / sqrt(v·v)).
fn normalize_glam(v: vec3<f32>) -> vec3<f32> {
    return v * (1.0 / sqrt(dot3(v, v)));
}

// Vec3::normalize_or_zero.
fn normalize_or_zero(v: vec3<f32>) -> vec3<f32> {
    let rcp = 1.0 / sqrt(dot3(v, v));
    if is_finite_f(rcp) && rcp > 0.0 {
        return v * rcp;
    }
    return vec3<f32>(0.0);
}

fn all_zero(v: vec3<f32>) -> bool {
    return v.x == 0.0 && v.y == 0.0 && v.z == 0.0;
}

// f32::powf for x >= 0 (WGSL's pow is undefined at 0 and gives NaN for 0^0).
fn powf(x: f32, y: f32) -> f32 {
    if y == 0.0 {
        return 1.0;
    }
    if x == 0.0 {
        return select(inf_f(), 0.0, y > 0.0);
    }
    return pow(x, y);
}

// f32::powi as compiler-rt's __powisf2 computes it (square and multiply).
fn powi(x: f32, n: i32) -> f32 {
    var a = x;
    var b = n;
    var r = 1.0;
    loop {
        if (b & 1) != 0 {
            r = r * a;
        }
        b = b / 2;
        if b == 0 {
            break;
        }
        a = a * a;
    }
    return select(r, 1.0 / r, n < 0);
}

fn attenuation(dist: f32, falloff: i32) -> f32 {
    if falloff == 0 {
        return 1.0;
    }
    return 1.0 / powi(dist, falloff);
}

fn cone_factor(light: Light, to_point: vec3<f32>) -> f32 {
    if light.kind != LIGHT_SPOT {
        return 1.0;
    }
    let c = dot3(light.direction, to_point);
    if c >= light.cos_inner {
        return 1.0;
    }
    if c <= light.cos_outer || light.cos_inner <= light.cos_outer {
        return 0.0;
    }
    let x = (c - light.cos_outer) / (light.cos_inner - light.cos_outer);
    return x * x * (3.0 - 2.0 * x);
}

fn reflect3(d: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return d - n * (2.0 * dot3(d, n));
}

const MIN_EXIT_COS: f32 = 1e-3;

// facing.rs `adapt`.
fn adapt(wo: vec3<f32>, ng: vec3<f32>, ns: vec3<f32>) -> vec3<f32> {
    if all_zero(wo) {
        return ns;
    }
    let r = reflect3(-wo, ns);
    let up = dot3(r, ng);
    if up >= MIN_EXIT_COS {
        return ns;
    }
    let tangent = normalize_or_zero(r - ng * up);
    if all_zero(tangent) {
        return ng;
    }
    let kept = tangent * sqrt(1.0 - MIN_EXIT_COS * MIN_EXIT_COS) + ng * MIN_EXIT_COS;
    let half = normalize_or_zero(wo + kept);
    if all_zero(half) || !is_finite3(half) {
        return ng;
    }
    return half;
}

// whitted.rs `fresnel`.
fn fresnel(cos_in: f32, eta: f32) -> f32 {
    let cos_i = clamp(cos_in, 0.0, 1.0);
    let sin_t2 = eta * eta * (1.0 - cos_i * cos_i);
    if !(sin_t2 < 1.0) {
        return 1.0;
    }
    let cos_t = sqrt(1.0 - sin_t2);
    let rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let r = 0.5 * (rs * rs + rp * rp);
    if is_finite_f(r) {
        return clamp(r, 0.0, 1.0);
    }
    return 1.0;
}

// whitted.rs `refract`: the zero vector stands for None.
fn refract3(d: vec3<f32>, n: vec3<f32>, eta: f32) -> vec3<f32> {
    let cos_i = clamp(-dot3(d, n), 0.0, 1.0);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    if !(k >= 0.0) {
        return vec3<f32>(0.0);
    }
    return normalize_or_zero(d * eta + n * (eta * cos_i - sqrt(k)));
}

fn vertex(i: u32) -> vec3<f32> {
    return vec3<f32>(positions[3u * i], positions[3u * i + 1u], positions[3u * i + 2u]);
}

fn vertex_normal(i: u32) -> vec3<f32> {
    return vec3<f32>(normals[3u * i], normals[3u * i + 1u], normals[3u * i + 2u]);
}

// A hit ready for shading: TriangleGeometry::surface followed by Facing::new.
struct Surf {
    p: vec3<f32>,
    // Facing: geometric normal towards the ray, adapted shading normal, entering.
    ng: vec3<f32>,
    ns: vec3<f32>,
    entering: bool,
    // The unflipped shading normal (SurfaceHit::ns), which refraction reads.
    ns_raw: vec3<f32>,
    material: u32,
}

fn surface(dir: vec3<f32>, h: Hit) -> Surf {
    var s: Surf;
    let i0 = indices[3u * h.prim];
    let i1 = indices[3u * h.prim + 1u];
    let i2 = indices[3u * h.prim + 2u];
    let p0 = vertex(i0);
    let p1 = vertex(i1);
    let p2 = vertex(i2);
    let u = h.u;
    let v = h.v;
    let w = 1.0 - u - v;
    s.p = p0 * w + p1 * u + p2 * v;
    var ng = normalize_or_zero(cross3(p1 - p0, p2 - p0));
    if all_zero(ng) || !is_finite3(ng) {
        ng = -normalize_or_zero(dir);
    }
    var ns = ng;
    if scene.has_normals != 0u {
        let sn = vertex_normal(i0) * w + vertex_normal(i1) * u + vertex_normal(i2) * v;
        if is_finite3(sn) && dot3(sn, sn) > 1e-12 {
            ns = normalize_glam(sn);
        }
    }
    s.ns_raw = ns;
    s.material = min(material_ids[h.prim], scene.material_count - 1u);
    // Facing::new.
    let d = normalize_or_zero(dir);
    s.entering = dot3(ng, d) < 0.0;
    let fng = select(-ng, ng, s.entering);
    let fns = select(ns, -ns, dot3(ns, fng) < 0.0);
    s.ng = fng;
    s.ns = adapt(-d, fng, fns);
    return s;
}

// The smallest f32 above t (t >= 0).
fn next_up(t: f32) -> f32 {
    if is_nan_f(t) || t == inf_f() {
        return t;
    }
    if t == 0.0 {
        return bitcast<f32>(1u);
    }
    if t > 0.0 {
        return bitcast<f32>(bitcast<u32>(t) + 1u);
    }
    return bitcast<f32>(bitcast<u32>(t) - 1u);
}

const MAX_SHADOW_CROSSINGS: u32 = 64u;

struct Through {
    light: vec3<f32>,
    // Shadow-ray segments traced.
    rays: u32,
}

// shadow.rs `Shadows::light_through`.
fn light_through(o: vec3<f32>, d: vec3<f32>, tmax: f32) -> Through {
    if scene.any_transparent == 0u {
        let blocked = any_hit(prepare(o, d, 0.0, tmax));
        return Through(select(vec3<f32>(1.0), vec3<f32>(0.0), blocked), 1u);
    }
    var through = vec3<f32>(1.0);
    var tmin = 0.0;
    for (var crossing = 0u; crossing < MAX_SHADOW_CROSSINGS; crossing = crossing + 1u) {
        let h = closest_hit(prepare(o, d, tmin, tmax));
        if h.prim == NO_HIT {
            return Through(through, crossing + 1u);
        }
        through = through * materials[min(material_ids[h.prim], scene.material_count - 1u)].shadow_filter;
        if max_element(through) <= 0.0 || !is_finite3(through) {
            return Through(vec3<f32>(0.0), crossing + 1u);
        }
        tmin = next_up(h.t);
        if !(tmin <= tmax) {
            return Through(through, crossing + 1u);
        }
    }
    return Through(vec3<f32>(0.0), MAX_SHADOW_CROSSINGS);
}

fn eps_at(p: vec3<f32>) -> f32 {
    let a = abs(p);
    let m = max_element(a);
    return scene.eps_base + select(0.0, m * 1e-5, is_finite_f(m));
}

// What shading one hit gives: its own radiance (not yet times the ray's throughput) and
// up to two child rays (reflection first, then refraction, as the CPU traces them).
struct Shaded {
    color: vec3<f32>,
    children: u32,
    child0: RayRec,
    child1: RayRec,
    // The children's coefficients (the cumulative integrator's choice weighs them).
    coef0: vec3<f32>,
    coef1: vec3<f32>,
    shadow_rays: u32,
}

// Whitted::spawn's test and ray: false when the weight is too small.
fn spawn(r: RayRec, s: Surf, dir: vec3<f32>, coef: vec3<f32>, eps: f32, out: ptr<function, RayRec>) -> bool {
    let w = r.weight * max_element(coef);
    if !(w > scene.min_weight) {
        return false;
    }
    let side = select(-s.ng, s.ng, dot3(s.ng, dir) >= 0.0);
    (*out).org = s.p + side * eps;
    (*out).dir = dir;
    (*out).sample = r.sample;
    (*out).level = r.level + 1u;
    (*out).thr = r.thr * coef;
    (*out).weight = w;
    (*out).path = r.path;
    (*out).key = r.key;
    return true;
}

// Whitted::shade for ray r with closest hit h.
fn shade(r: RayRec, h: Hit) -> Shaded {
    var out: Shaded;
    out.children = 0u;
    out.shadow_rays = 0u;
    let s = surface(r.dir, h);
    let m = materials[s.material];
    let p = s.p;
    let d = normalize_or_zero(r.dir);
    let view = -d;
    let eps = eps_at(p);
    var c = m.ambient * scene.ambient;
    for (var li = 0u; li < scene.light_count; li = li + 1u) {
        let light = lights[li];
        var l: vec3<f32>;
        var tmax: f32;
        var att: f32;
        if light.kind == LIGHT_DIRECTIONAL {
            l = light.direction;
            tmax = inf_f();
            att = 1.0;
        } else {
            let to = light.position - p;
            let dist = sqrt(dot3(to, to));
            if !(dist > 0.0 && is_finite_f(dist)) {
                continue;
            }
            l = to / dist;
            tmax = dist - eps;
            att = attenuation(dist, light.falloff) * cone_factor(light, -l);
        }
        if att == 0.0 {
            continue;
        }
        let ndl = dot3(s.ns, l);
        if !(ndl > 0.0) || !is_finite_f(att) {
            continue;
        }
        let side = select(-s.ng, s.ng, dot3(s.ng, l) >= 0.0);
        let through = light_through(p + side * eps, l, tmax);
        out.shadow_rays = out.shadow_rays + through.rays;
        if all_zero(through.light) {
            continue;
        }
        let rl = s.ns * (2.0 * ndl) - l;
        var highlight = vec3<f32>(0.0);
        if m.has_spot != 0u {
            highlight = m.spot * powf(max(dot3(rl, view), 0.0), m.shine);
        }
        c = c + light.color * through.light * att * (m.diffuse * ndl + highlight);
    }
    out.color = c;
    if r.level >= scene.max_level {
        return out;
    }
    var mirror = m.specular;
    var transmitted = false;
    var tdir = vec3<f32>(0.0);
    var tcoef = vec3<f32>(0.0);
    if max_element(m.transparency) > 0.0 {
        let eta = select(m.ior / scene.env_ior, scene.env_ior / m.ior, s.entering);
        let smooth_n = select(s.ns_raw, -s.ns_raw, dot3(s.ns_raw, s.ng) < 0.0);
        var n = smooth_n;
        var t = refract3(d, smooth_n, eta);
        if all_zero(t) || !(dot3(t, s.ng) < 0.0) {
            n = s.ng;
            t = refract3(d, s.ng, eta);
        }
        if !all_zero(t) && dot3(t, s.ng) < 0.0 {
            let fr = fresnel(-dot3(d, n), eta);
            mirror = mirror + m.transparency * fr;
            transmitted = true;
            tdir = t;
            tcoef = m.transparency * (1.0 - fr);
        } else {
            mirror = mirror + m.transparency;
        }
    }
    var child: RayRec;
    if max_element(mirror) > 0.0 && spawn(r, s, reflect3(d, s.ns), mirror, eps, &child) {
        out.child0 = child;
        out.coef0 = mirror;
        out.children = 1u;
    }
    if transmitted && spawn(r, s, tdir, tcoef, eps, &child) {
        if out.children == 0u {
            out.child0 = child;
            out.coef0 = tcoef;
        } else {
            out.child1 = child;
            out.coef1 = tcoef;
        }
        out.children = out.children + 1u;
    }
    return out;
}

// The PCG hash of Jarzynski & Olano, "Hash Functions for GPU Rendering" (JCGT 2020):
// crates/render/src/sampler.rs `pcg_hash`, bit for bit (u32 arithmetic wraps in WGSL).
fn pcg_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// dynray_render::choice_random: the cumulative integrator's number in [0, 1) for the
// choice of path `path` at ray level `level` of the sample keyed `key`. The CPU's bits:
// a 24-bit integer times 2^-24 is exact in f32.
fn choice_random(key: u32, level: u32, path: u32) -> f32 {
    let h = pcg_hash(key ^ pcg_hash(level ^ pcg_hash(path)));
    return f32(h >> 8u) * (1.0 / 16777216.0);
}

// crates/render/src/cumulative/bounce.rs `reflect_probability`, in its operations: the
// reflected coefficient's share of the larger components, 0.5 where they give none,
// clamped to [EPSILON, 1 - EPSILON] where one share vanishes.
fn reflect_probability(cr: vec3<f32>, ct: vec3<f32>) -> f32 {
    let a = fmax(max_element(cr), 0.0);
    let b = fmax(max_element(ct), 0.0);
    let p = a / (a + b);
    if p > 0.0 && p < 1.0 {
        return p;
    }
    if !(a + b > 0.0) || !is_finite_f(p) {
        return 0.5;
    }
    // f32::EPSILON and 1 - f32::EPSILON, by their bits.
    return clamp(p, bitcast<f32>(0x34000000u), bitcast<f32>(0x3f7ffffeu));
}

// A contribution with NaN channels zeroed (Whitted::trace does so for each ray's colour).
fn no_nan(c: vec3<f32>) -> vec3<f32> {
    return select(c, vec3<f32>(0.0), vec3<bool>(is_nan_f(c.x), is_nan_f(c.y), is_nan_f(c.z)));
}

fn trace_ray(r: RayRec) -> Hit {
    return closest_hit(prepare(r.org, r.dir, 0.0, inf_f()));
}
