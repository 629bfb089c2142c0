// Seed 001's distance field on the device: the voxel texture of 3×3×3 sibling blocks, the
// cell table H and the offset table Φ as storage buffers, located without a stack and
// sphere traced. Each function is crates/adf's of the same name, in its operation order
// (locate.rs, reconstruct.rs, crack.rs, trace.rs), so the device and the CPU agree to
// the rounding of the adapter's f32 arithmetic (docs/adf.md, "On the GPU").

struct AdfParams {
    origin: vec3<f32>,
    size: f32,
    max_level: u32,
    // Edges of H (m̄) and Φ (r̄).
    m: u32,
    r: u32,
    lipschitz: f32,
    // Block slots per axis (x, y) and texels per axis (x, y) of the voxel texture.
    bx: u32,
    by: u32,
    sx: u32,
    sy: u32,
    // Rays or points in the batch, the level search (0 linear, 1 binary, 2 coherent
    // linear), entries of the per-cell bound table, points per invocation (locate).
    count: u32,
    search: u32,
    cells: u32,
    run: u32,
    texel_count: u32,
    // 1: the march also writes the field's gradient at the hit.
    normals: u32,
    // 1: H has a second identifier word per slot (`high_ids`: trees deeper than 10).
    wide: u32,
    _pad1: u32,
}

// The deepest internal cell containing a point (locate.rs `Located`).
struct Located {
    level: u32,
    block: u32,
    probes: u32,
}

// One ray's answer: t (+inf on a miss), field samples, hash probes of point location,
// and the gradient at the hit when asked.
struct MarchAnswer {
    grad: vec3<f32>,
    t: f32,
    samples: u32,
    probes: u32,
    found: u32,
    _pad: u32,
}

@group(0) @binding(0) var<storage, read> texels: array<f32>;
// H: (key identifier, block); Φ: (x | y << 16, z | w << 16).
@group(0) @binding(1) var<storage, read> table: array<vec2<u32>>;
@group(0) @binding(2) var<storage, read> phi: array<vec2<u32>>;
@group(0) @binding(3) var<storage, read> cell_bound: array<f32>;
@group(0) @binding(4) var<uniform> P: AdfParams;
// march: two vec4 per ray (origin xyz, dir x; dir yz, tmin, tmax); locate: fine
// coordinates (xyz) per point.
@group(0) @binding(5) var<storage, read> rays: array<vec4<f32>>;
@group(0) @binding(6) var<storage, read_write> answers: array<MarchAnswer>;
@group(0) @binding(7) var<storage, read> points: array<vec4<u32>>;
@group(0) @binding(8) var<storage, read_write> located: array<vec4<u32>>;
// H's second identifier words (one zero word when the tree has none).
@group(0) @binding(9) var<storage, read> high_ids: array<u32>;

const MAX_MARCH_STEPS: u32 = 4096u;
const MIN_STEP: f32 = 0.1;
const REFINE_STEPS: u32 = 24u;

fn pos_inf() -> f32 {
    return bitcast<f32>(0x7f800000u);
}

fn nan_bits(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7fffffffu) > 0x7f800000u;
}

// f32::min / f32::max: the other operand when one is NaN.
fn fmin_(a: f32, b: f32) -> f32 {
    if nan_bits(a) {
        return b;
    }
    if nan_bits(b) {
        return a;
    }
    return min(a, b);
}

fn fmax_(a: f32, b: f32) -> f32 {
    if nan_bits(a) {
        return b;
    }
    if nan_bits(b) {
        return a;
    }
    return max(a, b);
}

fn key_id(k: vec3<u32>) -> u32 {
    let low = k & vec3<u32>(1023u);
    return low.x | (low.y << 10u) | (low.z << 20u);
}

fn key_high_id(k: vec3<u32>) -> u32 {
    let high = k >> vec3<u32>(10u);
    return high.x | (high.y << 10u) | (high.z << 20u);
}

// PerfectHash::find: the block of the cell with key k, or 0xffffffff.
fn find(k: vec3<u32>) -> u32 {
    let r = P.r;
    let pi = (k.x % r) + r * ((k.y % r) + r * (k.z % r));
    let e = phi[pi];
    let t = vec3<u32>(e.x & 0xffffu, e.x >> 16u, e.y & 0xffffu);
    let w = max(e.y >> 16u, 1u);
    let m = P.m;
    let s = ((k % vec3<u32>(w)) + t) % vec3<u32>(m);
    let slot = s.x + m * (s.y + m * s.z);
    let h = table[slot];
    var high = 0u;
    if P.wide == 1u {
        high = high_ids[slot];
    }
    return select(0xffffffffu, h.y, h.x == key_id(k) && high == key_high_id(k));
}

// Adf::probe: the block of the level-`level` cell holding fine coordinates q.
fn probe(level: u32, q: vec3<u32>) -> u32 {
    let shift = P.max_level - level;
    return find((vec3<u32>(1u) << vec3<u32>(level)) + (q >> vec3<u32>(shift)));
}

const NONE: u32 = 0xffffffffu;

// Adf::locate_fine; `hint` is the coherent search's starting level and receives the answer's.
fn locate_fine(q: vec3<u32>, search: u32, hint: ptr<function, u32>) -> Located {
    let deepest = P.max_level - 1u;
    var root = probe(0u, q);
    if root == NONE {
        root = 0u;
    }
    var found: Located;
    if search == 0u {
        found = Located(0u, root, 0u);
        for (var l = 1u; l <= deepest; l++) {
            found.probes += 1u;
            let b = probe(l, q);
            if b == NONE {
                break;
            }
            found.level = l;
            found.block = b;
        }
    } else if search == 1u {
        var lo = 1i;
        var hi = i32(deepest);
        found = Located(0u, root, 0u);
        while lo <= hi {
            let mid = (lo + hi) / 2i;
            found.probes += 1u;
            let b = probe(u32(mid), q);
            if b != NONE {
                found.level = u32(mid);
                found.block = b;
                lo = mid + 1i;
            } else {
                hi = mid - 1i;
            }
        }
    } else {
        var l = min(*hint, deepest);
        var probes = 1u;
        var b = root;
        if l != 0u {
            b = probe(l, q);
        }
        if b != NONE {
            while l < deepest {
                probes += 1u;
                let nb = probe(l + 1u, q);
                if nb == NONE {
                    break;
                }
                l += 1u;
                b = nb;
            }
            found = Located(l, b, probes);
        } else {
            loop {
                l -= 1u;
                if l == 0u {
                    found = Located(0u, root, probes);
                    break;
                }
                probes += 1u;
                let pb = probe(l, q);
                if pb != NONE {
                    found = Located(l, pb, probes);
                    break;
                }
            }
        }
    }
    *hint = found.level;
    return found;
}

// Adf::fine_coords.
fn fine_coords(u: vec3<f32>) -> vec3<u32> {
    let n = f32(1u << P.max_level);
    let top = (1u << P.max_level) - 1u;
    return min(vec3<u32>(max(u * n, vec3<f32>(0.0))), vec3<u32>(top));
}

fn unit(p: vec3<f32>) -> vec3<f32> {
    return (p - P.origin) / P.size;
}

// VoxelTexture::texel (0 outside, as the CPU).
fn texel(x: u32, y: u32, z: u32) -> f32 {
    let i = x + P.sx * (y + P.sy * z);
    if i >= P.texel_count {
        return 0.0;
    }
    return texels[i];
}

// The 8 samples of the leaf holding q, child of `cell` (Adf::leaf_corners), index
// x + 2y + 4z.
fn leaf_corners(cell: Located, q: vec3<u32>) -> array<f32, 8> {
    let idx = q >> vec3<u32>(P.max_level - cell.level - 1u);
    let b = cell.block;
    let o = vec3<u32>(3u * (b % P.bx), 3u * ((b / P.bx) % P.by), 3u * (b / (P.bx * P.by))) + (idx & vec3<u32>(1u));
    var c: array<f32, 8>;
    for (var i = 0u; i < 8u; i++) {
        c[i] = texel(o.x + (i & 1u), o.y + ((i >> 1u) & 1u), o.z + (i >> 2u));
    }
    return c;
}

fn lerp_(a: f32, b: f32, s: f32) -> f32 {
    return a + (b - a) * s;
}

// build.rs `trilinear`, in its order.
fn trilinear(c: array<f32, 8>, t: vec3<f32>) -> f32 {
    let x00 = lerp_(c[0], c[1], t.x);
    let x10 = lerp_(c[2], c[3], t.x);
    let x01 = lerp_(c[4], c[5], t.x);
    let x11 = lerp_(c[6], c[7], t.x);
    return lerp_(lerp_(x00, x10, t.y), lerp_(x01, x11, t.y), t.z);
}

struct Sample {
    d: f32,
    cell: Located,
    q: vec3<u32>,
}

// Adf::sample_unit.
fn sample_unit(u_in: vec3<f32>, search: u32, hint: ptr<function, u32>) -> Sample {
    let u = clamp(u_in, vec3<f32>(0.0), vec3<f32>(1.0));
    let q = fine_coords(u);
    let cell = locate_fine(q, search, hint);
    let leaf = cell.level + 1u;
    let idx = q >> vec3<u32>(P.max_level - leaf);
    let scale = f32(1u << leaf);
    let t = clamp(u * scale - vec3<f32>(idx), vec3<f32>(0.0), vec3<f32>(1.0));
    return Sample(trilinear(leaf_corners(cell, q), t), cell, q);
}

// Adf::gradient at world point p (central differences half a finest cell wide).
fn gradient(p: vec3<f32>, hint: ptr<function, u32>) -> vec3<f32> {
    let h = 0.5 / f32(1u << P.max_level);
    let u = clamp(unit(p), vec3<f32>(h), vec3<f32>(1.0 - h));
    var g: vec3<f32>;
    for (var k = 0u; k < 3u; k++) {
        var e = vec3<f32>(0.0);
        e[k] = h;
        let hi = sample_unit(u + e, 2u, hint).d;
        let lo = sample_unit(u - e, 2u, hint).d;
        g[k] = (hi - lo) / (2.0 * h * P.size);
    }
    return g;
}

// crack.rs `leaf_gradient_bound` over the leaf's corners, edge h.
fn leaf_gradient_bound(c: array<f32, 8>, h: f32) -> f32 {
    var g2 = 0.0;
    for (var axis = 0u; axis < 3u; axis++) {
        var m = 0.0;
        for (var j = 0u; j < 4u; j++) {
            let a = j & 1u;
            let w = j >> 1u;
            var lo: f32;
            var hi: f32;
            if axis == 0u {
                lo = c[2u * a + 4u * w];
                hi = c[1u + 2u * a + 4u * w];
            } else if axis == 1u {
                lo = c[a + 4u * w];
                hi = c[a + 2u + 4u * w];
            } else {
                lo = c[a + 2u * w];
                hi = c[a + 2u * w + 4u];
            }
            m = fmax_(m, abs(hi - lo));
        }
        g2 += (m / h) * (m / h);
    }
    return sqrt(g2);
}

// How far a ray at unit point u moving du per unit t may go without crossing the
// surface, where the field is `reach` (trace.rs `safe_step`).
fn exit_of(level: u32, u: vec3<f32>, du: vec3<f32>, q: vec3<u32>) -> f32 {
    let h = 1.0 / f32(1u << level);
    let idx = vec3<f32>(q >> vec3<u32>(P.max_level - level));
    var e = pos_inf();
    for (var k = 0u; k < 3u; k++) {
        var x = pos_inf();
        if du[k] > 0.0 {
            x = ((idx[k] + 1.0) * h - u[k]) / du[k];
        } else if du[k] < 0.0 {
            x = (idx[k] * h - u[k]) / du[k];
        }
        e = fmin_(e, x);
    }
    return fmax_(e, 0.0);
}

fn safe_step(u: vec3<f32>, du: vec3<f32>, reach: f32, cell: Located, q: vec3<u32>) -> f32 {
    var best = 0.0;
    let leaf_edge = P.size / f32(1u << (cell.level + 1u));
    let lb = leaf_gradient_bound(leaf_corners(cell, q), leaf_edge);
    var free = select(pos_inf(), reach / lb, lb > 0.0);
    var e = exit_of(cell.level + 1u, u, du, q);
    best = fmax_(best, fmin_(free, e));
    if free <= e {
        return best;
    }
    var level = cell.level;
    loop {
        var b = cell.block;
        if level != cell.level {
            b = probe(level, q);
        }
        var bound = P.lipschitz;
        if b != NONE && b < P.cells {
            bound = cell_bound[b];
        }
        free = select(pos_inf(), reach / bound, bound > 0.0);
        e = exit_of(level, u, du, q);
        best = fmax_(best, fmin_(free, e));
        if free <= e || level == 0u {
            break;
        }
        level -= 1u;
    }
    return best;
}

fn is_nan3_(x: vec3<f32>) -> vec3<bool> {
    return (bitcast<vec3<u32>>(x) & vec3<u32>(0x7fffffffu)) > vec3<u32>(0x7f800000u);
}

fn is_finite_(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

// Aabb::clip of the cube: (entered, near, far).
fn clip_cube(o: vec3<f32>, d: vec3<f32>, tmin: f32, tmax: f32) -> vec3<f32> {
    let inv = vec3<f32>(1.0) / d;
    let t0 = (P.origin - o) * inv;
    let t1 = (P.origin + vec3<f32>(P.size) - o) * inv;
    let ninf = vec3<f32>(bitcast<f32>(0xff800000u));
    let pinf = vec3<f32>(pos_inf());
    let nan = is_nan3_(t0) | is_nan3_(t1);
    let lo = select(min(t0, t1), ninf, nan);
    let hi = select(max(t0, t1), pinf, nan);
    var near = max(lo.x, max(lo.y, lo.z));
    var far = min(hi.x, min(hi.y, hi.z));
    near = fmax_(near * select(SLAB_GROW, SLAB_SHRINK, near > 0.0), tmin);
    far = fmin_(far * select(SLAB_SHRINK, SLAB_GROW, far > 0.0), tmax);
    return vec3<f32>(select(0.0, 1.0, near <= far), near, far);
}

fn crossed(outside: bool, d: f32) -> bool {
    return select(d >= 0.0, d <= 0.0, outside);
}

// Adf::march_counted: the first crossing of the surface along the ray.
fn march(o: vec3<f32>, d: vec3<f32>, tmin: f32, tmax: f32, search: u32) -> MarchAnswer {
    var a = MarchAnswer(vec3<f32>(0.0), pos_inf(), 0u, 0u, 0u, 0u);
    let c = clip_cube(o, d, tmin, tmax);
    if c.x == 0.0 {
        return a;
    }
    let dl = sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    if !(dl > 0.0 && is_finite_(dl)) {
        return a;
    }
    let t1 = c.z;
    let finest = P.size / f32(1u << P.max_level);
    let min_step = MIN_STEP * finest / dl;
    let du = d / P.size;
    var hint = 0u;
    a.samples = 1u;
    var t = fmax_(c.y, tmin);
    var s = sample_unit(unit(o + d * t), search, &hint);
    a.probes = s.cell.probes;
    var outside = s.d > 0.0;
    if abs(s.d) <= 1e-3 * finest {
        var h = 0u;
        let g = gradient(o + d * t, &h);
        outside = g.x * d.x + g.y * d.y + g.z * d.z >= 0.0;
    }
    for (var step_i = 0u; step_i < MAX_MARCH_STEPS; step_i++) {
        let u = unit(o + d * t);
        let step = fmax_(safe_step(u, du, abs(s.d) / dl, s.cell, s.q), min_step);
        let tn = fmin_(t + step, t1);
        let n = sample_unit(unit(o + d * tn), search, &hint);
        a.samples += 1u;
        a.probes += n.cell.probes;
        if crossed(outside, n.d) {
            var lo = t;
            var hi = tn;
            for (var i = 0u; i < REFINE_STEPS; i++) {
                let mid = 0.5 * (lo + hi);
                a.samples += 1u;
                let m = sample_unit(unit(o + d * mid), search, &hint);
                a.probes += m.cell.probes;
                if crossed(outside, m.d) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            a.t = hi;
            a.found = 1u;
            return a;
        }
        if tn >= t1 {
            return a;
        }
        t = tn;
        s = n;
    }
    return a;
}

@compute @workgroup_size(64)
fn adf_march(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= P.count {
        return;
    }
    let ra = rays[2u * i];
    let rb = rays[2u * i + 1u];
    let o = ra.xyz;
    let d = vec3<f32>(ra.w, rb.x, rb.y);
    var a = march(o, d, rb.z, rb.w, P.search);
    if a.found == 1u && P.normals == 1u {
        var h = 0u;
        a.grad = gradient(o + d * a.t, &h);
    }
    answers[i] = a;
}

// Point location of P.run consecutive points per invocation, the coherent search's
// hint carried from one to the next (as a CPU loop over the same run).
@compute @workgroup_size(64)
fn adf_locate(@builtin(global_invocation_id) gid: vec3<u32>) {
    let first = gid.x * P.run;
    if first >= P.count {
        return;
    }
    var hint = 0u;
    let last = min(first + P.run, P.count);
    for (var i = first; i < last; i++) {
        let c = locate_fine(points[i].xyz, P.search, &hint);
        located[i] = vec4<u32>(c.level, c.block, c.probes, 0u);
    }
}
