//! An independent reader of what the animation tests need from a `.gltf` file: the JSON
//! through serde_json, accessors read by hand, node TRS sampled with this file's own
//! lerp and slerp in f64. It shares no code with the loader it checks.

use glam::{DMat4, DQuat, DVec3};
use serde_json::Value;
use std::path::Path;

pub struct Doc {
    pub json: Value,
    buffers: Vec<Vec<u8>>,
}

impl Doc {
    pub fn open(path: &Path) -> Doc {
        let json: Value = serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap();
        let buffers = json["buffers"]
            .as_array()
            .unwrap()
            .iter()
            .map(|b| std::fs::read(path.parent().unwrap().join(b["uri"].as_str().unwrap())).unwrap())
            .collect();
        Doc { json, buffers }
    }

    pub fn usize(v: &Value) -> usize {
        v.as_u64().unwrap() as usize
    }

    /// Accessor `i` as numbers, components in order (floats and unsigned integers).
    pub fn read(&self, i: usize) -> Vec<f64> {
        let acc = &self.json["accessors"][i];
        let view = &self.json["bufferViews"][Self::usize(&acc["bufferView"])];
        let data = &self.buffers[Self::usize(&view["buffer"])];
        let n = match acc["type"].as_str().unwrap() {
            "SCALAR" => 1,
            "VEC2" => 2,
            "VEC3" => 3,
            "VEC4" => 4,
            "MAT4" => 16,
            t => panic!("type {t}"),
        };
        let ct = Self::usize(&acc["componentType"]);
        let csize = match ct {
            5121 => 1,
            5123 => 2,
            5125 | 5126 => 4,
            _ => panic!("component type {ct}"),
        };
        let stride = view.get("byteStride").map_or(n * csize, Self::usize);
        let base = view.get("byteOffset").map_or(0, Self::usize) + acc.get("byteOffset").map_or(0, Self::usize);
        let mut out = Vec::new();
        for e in 0..Self::usize(&acc["count"]) {
            for c in 0..n {
                let o = base + e * stride + c * csize;
                let b = &data[o..o + csize];
                out.push(match ct {
                    5121 => b[0] as f64,
                    5123 => u16::from_le_bytes([b[0], b[1]]) as f64,
                    5125 => u32::from_le_bytes(b.try_into().unwrap()) as f64,
                    _ => f32::from_le_bytes(b.try_into().unwrap()) as f64,
                });
            }
        }
        out
    }

    /// Every node's local matrix at time `t`: the file's TRS with the first animation's
    /// LINEAR channels applied (all these models use).
    pub fn locals(&self, t: f64) -> Vec<DMat4> {
        let nodes = self.json["nodes"].as_array().unwrap();
        let mut trs: Vec<(DVec3, DQuat, DVec3)> = nodes
            .iter()
            .map(|n| {
                let v = |k: &str, d: &[f64]| -> Vec<f64> {
                    n.get(k).map_or(d.to_vec(), |a| a.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect())
                };
                let (t, r, s) =
                    (v("translation", &[0.0; 3]), v("rotation", &[0.0, 0.0, 0.0, 1.0]), v("scale", &[1.0; 3]));
                (DVec3::from_slice(&t), DQuat::from_xyzw(r[0], r[1], r[2], r[3]), DVec3::from_slice(&s))
            })
            .collect();
        if let Some(anim) = self.json.get("animations").and_then(|a| a.get(0)) {
            for ch in anim["channels"].as_array().unwrap() {
                let sampler = &anim["samplers"][Self::usize(&ch["sampler"])];
                assert_eq!(sampler["interpolation"].as_str().unwrap_or("LINEAR"), "LINEAR");
                let path = ch["target"]["path"].as_str().unwrap();
                if path == "weights" {
                    continue;
                }
                let times = self.read(Self::usize(&sampler["input"]));
                let values = self.read(Self::usize(&sampler["output"]));
                let w = values.len() / times.len();
                let v = sample_linear(&times, &values, w, t, path == "rotation");
                let node = &mut trs[Self::usize(&ch["target"]["node"])];
                match path {
                    "translation" => node.0 = DVec3::from_slice(&v),
                    "rotation" => node.1 = DQuat::from_xyzw(v[0], v[1], v[2], v[3]),
                    _ => node.2 = DVec3::from_slice(&v),
                }
            }
        }
        nodes
            .iter()
            .zip(trs)
            .map(|(n, (t, r, s))| match n.get("matrix") {
                Some(m) => {
                    let m: Vec<f64> = m.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
                    DMat4::from_cols_slice(&m)
                }
                None => DMat4::from_translation(t) * DMat4::from_quat(r.normalize()) * DMat4::from_scale(s),
            })
            .collect()
    }

    /// World matrices at `t`, from the parent links of `children`.
    pub fn worlds(&self, t: f64) -> Vec<DMat4> {
        let locals = self.locals(t);
        let nodes = self.json["nodes"].as_array().unwrap();
        let mut parent = vec![None; nodes.len()];
        for (i, n) in nodes.iter().enumerate() {
            for c in n.get("children").and_then(Value::as_array).into_iter().flatten() {
                parent[Self::usize(c)] = Some(i);
            }
        }
        (0..nodes.len())
            .map(|mut i| {
                let mut m = locals[i];
                while let Some(p) = parent[i] {
                    m = locals[p] * m;
                    i = p;
                }
                m
            })
            .collect()
    }
}

/// Linear (slerp for rotations) sample of `w`-wide keys at `t`, held outside the keys.
pub fn sample_linear(times: &[f64], values: &[f64], w: usize, t: f64, rotation: bool) -> Vec<f64> {
    let key = |k: usize| &values[k * w..(k + 1) * w];
    if t <= times[0] {
        return key(0).to_vec();
    }
    let Some(k1) = times.iter().position(|&x| x > t) else { return key(times.len() - 1).to_vec() };
    let k0 = k1 - 1;
    let s = (t - times[k0]) / (times[k1] - times[k0]);
    if !rotation {
        return key(k0).iter().zip(key(k1)).map(|(a, b)| a + (b - a) * s).collect();
    }
    // Slerp written out: shorter arc, sin-weighted blend.
    let (a, mut b) = (key(k0).to_vec(), key(k1).to_vec());
    let mut dot: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
    if dot < 0.0 {
        b.iter_mut().for_each(|x| *x = -*x);
        dot = -dot;
    }
    let (wa, wb) = if dot > 0.999_999 {
        (1.0 - s, s)
    } else {
        let theta = dot.acos();
        (((1.0 - s) * theta).sin() / theta.sin(), (s * theta).sin() / theta.sin())
    };
    let q: Vec<f64> = a.iter().zip(&b).map(|(x, y)| wa * x + wb * y).collect();
    let len = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    q.iter().map(|x| x / len).collect()
}
