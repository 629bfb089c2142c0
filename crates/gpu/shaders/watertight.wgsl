// The engine's ray-triangle test (crates/geom/src/triangle.rs, Woop, Benthin and Wald,
// JCGT 2013) and the per-ray constants it needs (crates/geom/src/ray.rs). `real` is f64
// where the adapter has 64-bit floats (then every operation below is the CPU's, in the
// CPU's order, and hits are bit-identical) and f32 elsewhere. The prelude defines it.

struct PRay {
    org: vec3<f32>,
    dir: vec3<f32>,
    inv: vec3<f32>,
    tmin: f32,
    tmax: f32,
    // Axis permutation: z is the dominant axis of dir.
    k: vec3<u32>,
    // dir[kx]/dir[kz], dir[ky]/dir[kz], 1/dir[kz].
    shear: vec3<real>,
    // The origin permuted to (kx, ky, kz).
    o64: vec3<real>,
    // A zero direction: the CPU's test never hits it (its shear is NaN or infinite).
    degenerate: bool,
}

struct TriHit {
    hit: bool,
    t: f32,
    u: f32,
    v: f32,
}

// +inf or -inf with the sign of x (-0 gives -inf, as 1/-0 does on the CPU).
fn signed_inf(x: f32) -> f32 {
    return bitcast<f32>((bitcast<u32>(x) & 0x80000000u) | 0x7f800000u);
}

fn prepare(o: vec3<f32>, d: vec3<f32>, tmin: f32, tmax: f32) -> PRay {
    var r: PRay;
    r.org = o;
    r.dir = d;
    r.tmin = tmin;
    r.tmax = tmax;
    let a = abs(d);
    // Dominant axis; ties to the lower axis, as the CPU.
    var kz = 2u;
    if a.x >= a.y && a.x >= a.z {
        kz = 0u;
    } else if a.y >= a.z {
        kz = 1u;
    }
    var kx = (kz + 1u) % 3u;
    var ky = (kx + 1u) % 3u;
    if d[kz] < 0.0 {
        let s = kx;
        kx = ky;
        ky = s;
    }
    r.k = vec3<u32>(kx, ky, kz);
    r.degenerate = d[kz] == 0.0;
    let dz = real(d[kz]);
    r.shear = vec3<real>(real(d[kx]) / dz, real(d[ky]) / dz, real(1.0) / dz);
    r.o64 = vec3<real>(real(o[kx]), real(o[ky]), real(o[kz]));
    r.inv = vec3<f32>(reciprocal(d.x), reciprocal(d.y), reciprocal(d.z));
    return r;
}

// 1/x as the CPU's f32 division gives it: through f64 where `real` is f64 (53 bits ≥ 2·24+2,
// so the double rounding is exact), an explicit signed infinity for zero.
fn reciprocal(x: f32) -> f32 {
    if x == 0.0 {
        return signed_inf(x);
    }
    return f32(real(1.0) / real(x));
}

fn rel(p: vec3<f32>, r: PRay) -> vec3<real> {
    return vec3<real>(real(p[r.k.x]) - r.o64.x, real(p[r.k.y]) - r.o64.y, real(p[r.k.z]) - r.o64.z);
}

// Two-sided, accepting r.tmin <= t <= tmax; (t, u, v) with the hit point
// (1-u-v)·p0 + u·p1 + v·p2.
fn intersect_triangle(p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>, r: PRay, tmax: f32) -> TriHit {
    var out = TriHit(false, 0.0, 0.0, 0.0);
    let a = rel(p0, r);
    let b = rel(p1, r);
    let c = rel(p2, r);
    let sx = r.shear.x;
    let sy = r.shear.y;
    let ax = a.x - sx * a.z;
    let ay = a.y - sy * a.z;
    let bx = b.x - sx * b.z;
    let by = b.y - sy * b.z;
    let cx = c.x - sx * c.z;
    let cy = c.y - sy * c.z;
    let eu = cx * by - cy * bx;
    let ev = ax * cy - ay * cx;
    let ew = bx * ay - by * ax;
    let zero = real(0.0);
    if (eu < zero || ev < zero || ew < zero) && (eu > zero || ev > zero || ew > zero) {
        return out;
    }
    let det = eu + ev + ew;
    if det == zero {
        return out;
    }
    let tt = (eu * a.z + ev * b.z + ew * c.z) * r.shear.z;
    let rcp = real(1.0) / det;
    let t = f32(tt * rcp);
    if t >= r.tmin && t <= tmax {
        out = TriHit(true, t, f32(ev * rcp), f32(ew * rcp));
    }
    return out;
}
