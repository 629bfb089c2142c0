//! Structure parameters on the command line: `key=value` pairs mapped onto each
//! structure's params struct (`BvhParams`, `BihParams`, …) by one function per structure.
//!
//! Every structure accepts `preset=NAME` (its named presets, applied first whatever the
//! order) and the fields of its params struct; unknown keys and bad values are errors that
//! name the structure, the key and what is accepted. The table of keys is in
//! docs/bench.md ("Structure parameters").

use anyhow::{anyhow, bail, Result};
use dynray_accel::apit::Observer;
use dynray_accel::{
    ABuffer, Accel, AccelKind, Apit, ApitParams, Bih, BihParams, Brute, Bvh, BvhParams, Grid, GridParams, KdTree,
    KdTreeParams, KdTreeRopes, Octree, OctreeDescent, OctreeParams,
};
use dynray_geom::{TriangleMesh, Vec3};

/// The `key=value` pairs of one structure, consumed key by key; whatever is left at the
/// end was not understood.
struct Pairs<'a> {
    kind: AccelKind,
    left: Vec<(&'a str, &'a str)>,
}

impl<'a> Pairs<'a> {
    fn new(kind: AccelKind, params: &'a [(String, String)]) -> Self {
        Self { kind, left: params.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect() }
    }

    /// Removes and returns the raw value of `key`.
    fn take(&mut self, key: &str) -> Option<&'a str> {
        let i = self.left.iter().position(|(k, _)| *k == key)?;
        Some(self.left.remove(i).1)
    }

    fn bad(&self, key: &str, value: &str, want: &str) -> anyhow::Error {
        anyhow!("{}: parameter `{key}={value}`: expected {want}", self.kind)
    }

    fn number<T: std::str::FromStr>(&mut self, key: &str, want: &str, slot: &mut T) -> Result<()> {
        if let Some(v) = self.take(key) {
            *slot = v.parse().map_err(|_| self.bad(key, v, want))?;
        }
        Ok(())
    }

    fn u32(&mut self, key: &str, slot: &mut u32) -> Result<()> {
        self.number(key, "a whole number", slot)
    }

    fn f32(&mut self, key: &str, slot: &mut f32) -> Result<()> {
        self.number(key, "a number", slot)
    }

    fn bool(&mut self, key: &str, slot: &mut bool) -> Result<()> {
        if let Some(v) = self.take(key) {
            *slot = match v {
                "on" | "true" | "yes" | "1" => true,
                "off" | "false" | "no" | "0" => false,
                _ => return Err(self.bad(key, v, "on or off")),
            };
        }
        Ok(())
    }

    /// An optional number: `off` (None) or a value.
    fn opt_f32(&mut self, key: &str, slot: &mut Option<f32>) -> Result<()> {
        if let Some(v) = self.take(key) {
            *slot = match v {
                "off" | "none" => None,
                _ => Some(v.parse().map_err(|_| self.bad(key, v, "a number or off"))?),
            };
        }
        Ok(())
    }

    /// `preset=NAME` looked up among `presets`.
    fn preset<P: Copy>(&mut self, presets: &[(&str, P)], slot: &mut P) -> Result<()> {
        if let Some(v) = self.take("preset") {
            let names: Vec<&str> = presets.iter().map(|(n, _)| *n).collect();
            *slot = presets
                .iter()
                .find(|(n, _)| *n == v)
                .map(|(_, p)| *p)
                .ok_or_else(|| anyhow!("{}: unknown preset `{v}` (known: {})", self.kind, names.join(", ")))?;
        }
        Ok(())
    }

    /// Fails on the first key nobody took, listing the structure's keys.
    fn finish(self, known: &[&str]) -> Result<()> {
        if let Some((k, _)) = self.left.first() {
            if known.is_empty() {
                bail!("{}: unknown parameter `{k}` ({} takes no parameters)", self.kind, self.kind);
            }
            bail!("{}: unknown parameter `{k}` (known: {})", self.kind, known.join(", "));
        }
        Ok(())
    }
}

/// Builds `kind` over `mesh` with `params` applied on top of its defaults. `eye` is the
/// camera position: the A-PIT and the A-buffer centre their cube there unless
/// `observer=center` is given (seed 004 centres it on the observer).
pub fn build_with_params(
    kind: AccelKind,
    params: &[(String, String)],
    mesh: &TriangleMesh,
    eye: Option<Vec3>,
) -> Result<Box<dyn Accel>> {
    let mut p = Pairs::new(kind, params);
    Ok(match kind {
        AccelKind::Brute => {
            p.finish(&[])?;
            Box::new(Brute::build(mesh)?)
        }
        AccelKind::Bvh => {
            let bp = bvh(&mut p)?;
            Box::new(Bvh::build(mesh, &bp)?)
        }
        AccelKind::Bih => {
            let bp = bih(&mut p)?;
            Box::new(Bih::build(mesh, &bp)?)
        }
        AccelKind::KdTree | AccelKind::KdTreeRopes => {
            let kp = kdtree(&mut p)?;
            if kind == AccelKind::KdTree {
                Box::new(KdTree::build_with(mesh, &kp)?)
            } else {
                Box::new(KdTreeRopes::build_with(mesh, &kp)?)
            }
        }
        AccelKind::Octree | AccelKind::OctreeDescent => {
            let op = octree(&mut p)?;
            if kind == AccelKind::Octree {
                Box::new(Octree::build(mesh, &op)?)
            } else {
                Box::new(OctreeDescent::build(mesh, &op)?)
            }
        }
        AccelKind::Grid => {
            let gp = grid(&mut p)?;
            Box::new(Grid::build(mesh, &gp)?)
        }
        AccelKind::Apit | AccelKind::ABuffer => {
            let ap = apit(&mut p, eye)?;
            if kind == AccelKind::Apit {
                Box::new(Apit::build(mesh, &ap)?)
            } else {
                Box::new(ABuffer::build(mesh, &ap)?)
            }
        }
    })
}

/// Checks `params` for `kind` without building anything (for validating a command line
/// before a long run).
pub fn check_params(kind: AccelKind, params: &[(String, String)]) -> Result<()> {
    let mut p = Pairs::new(kind, params);
    match kind {
        AccelKind::Brute => p.finish(&[]),
        AccelKind::Bvh => bvh(&mut p).map(drop),
        AccelKind::Bih => bih(&mut p).map(drop),
        AccelKind::KdTree | AccelKind::KdTreeRopes => kdtree(&mut p).map(drop),
        AccelKind::Octree | AccelKind::OctreeDescent => octree(&mut p).map(drop),
        AccelKind::Grid => grid(&mut p).map(drop),
        AccelKind::Apit | AccelKind::ABuffer => apit(&mut p, None).map(drop),
    }
}

fn bvh(p: &mut Pairs) -> Result<BvhParams> {
    let mut bp = BvhParams::default();
    let presets = [("fast", BvhParams::fast()), ("default", bp), ("high_quality", BvhParams::high_quality())];
    p.preset(&presets, &mut bp)?;
    p.u32("bins", &mut bp.bins)?;
    p.u32("leaf_size", &mut bp.leaf_size)?;
    p.u32("max_leaf_size", &mut bp.max_leaf_size)?;
    p.f32("traversal_cost", &mut bp.traversal_cost)?;
    p.f32("intersection_cost", &mut bp.intersection_cost)?;
    finish(p, &["preset", "bins", "leaf_size", "max_leaf_size", "traversal_cost", "intersection_cost"])?;
    bp.validate()?;
    Ok(bp)
}

fn bih(p: &mut Pairs) -> Result<BihParams> {
    let mut bp = BihParams::default();
    p.preset(&BihParams::presets(), &mut bp)?;
    p.u32("max_prims", &mut bp.max_prims)?;
    p.u32("max_depth", &mut bp.max_depth)?;
    // `shrink=on` restores the seed's factor after a preset turned it off.
    if p.left.iter().any(|&(k, v)| k == "shrink" && v == "on") {
        p.take("shrink");
        bp.shrink = BihParams::default().shrink;
    }
    p.opt_f32("shrink", &mut bp.shrink)?;
    p.opt_f32("empty_cut", &mut bp.empty_cut)?;
    finish(p, &["preset", "max_prims", "max_depth", "shrink", "empty_cut"])?;
    bp.check()?;
    Ok(bp)
}

fn kdtree(p: &mut Pairs) -> Result<KdTreeParams> {
    let mut kp = KdTreeParams::default();
    p.preset(&KdTreeParams::presets(), &mut kp)?;
    p.f32("traversal_cost", &mut kp.traversal_cost)?;
    p.f32("intersection_cost", &mut kp.intersection_cost)?;
    p.f32("empty_bonus", &mut kp.empty_bonus)?;
    if let Some(v) = p.take("max_depth") {
        kp.max_depth = match v {
            "auto" => None,
            _ => Some(v.parse().map_err(|_| p.bad("max_depth", v, "a whole number or auto"))?),
        };
    }
    p.f32("depth_factor", &mut kp.depth_factor)?;
    p.u32("min_prims", &mut kp.min_prims)?;
    p.f32("max_refs_per_triangle", &mut kp.max_refs_per_triangle)?;
    let known = [
        "preset",
        "traversal_cost",
        "intersection_cost",
        "empty_bonus",
        "max_depth",
        "depth_factor",
        "min_prims",
        "max_refs_per_triangle",
    ];
    finish(p, &known)?;
    kp.validate()?;
    Ok(kp)
}

fn octree(p: &mut Pairs) -> Result<OctreeParams> {
    let mut op = OctreeParams::default();
    p.preset(&OctreeParams::presets(), &mut op)?;
    p.u32("max_depth", &mut op.max_depth)?;
    p.u32("leaf_threshold", &mut op.leaf_threshold)?;
    p.bool("balance", &mut op.balance)?;
    finish(p, &["preset", "max_depth", "leaf_threshold", "balance"])?;
    op.check()?;
    Ok(op)
}

fn grid(p: &mut Pairs) -> Result<GridParams> {
    let mut gp = GridParams::default();
    p.preset(&GridParams::presets(), &mut gp)?;
    p.f32("density", &mut gp.density)?;
    p.u32("max_cells", &mut gp.max_cells)?;
    p.u32("max_refs_per_triangle", &mut gp.max_refs_per_triangle)?;
    p.bool("exact_overlap", &mut gp.exact_overlap)?;
    finish(p, &["preset", "density", "max_cells", "max_refs_per_triangle", "exact_overlap"])?;
    gp.check()?;
    Ok(gp)
}

fn apit(p: &mut Pairs, eye: Option<Vec3>) -> Result<ApitParams> {
    let mut ap = ApitParams::default();
    let presets = [("fast", ApitParams::fast()), ("default", ap), ("high_quality", ApitParams::high_quality())];
    p.preset(&presets, &mut ap)?;
    p.u32("resolution", &mut ap.resolution)?;
    p.u32("fragment_budget", &mut ap.fragment_budget)?;
    let observer = p.take("observer").unwrap_or("eye");
    ap.observer = match (observer, eye) {
        ("eye", Some(e)) => Observer::Point(e),
        ("eye", None) | ("center", _) => Observer::BoundsCenter,
        (v, _) => return Err(p.bad("observer", v, "eye or center")),
    };
    finish(p, &["preset", "resolution", "fragment_budget", "observer"])?;
    if !(1..=ApitParams::MAX_RESOLUTION).contains(&ap.resolution) {
        bail!("{}: resolution {} is outside 1..={}", p.kind, ap.resolution, ApitParams::MAX_RESOLUTION);
    }
    Ok(ap)
}

/// [`Pairs::finish`] on a borrowed reader: moves the leftovers out.
fn finish(p: &mut Pairs, known: &[&str]) -> Result<()> {
    Pairs { kind: p.kind, left: std::mem::take(&mut p.left) }.finish(known)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kv(pairs: &[(&str, &str)]) -> Vec<(String, String)> {
        pairs.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect()
    }

    #[test]
    fn every_structure_takes_its_fields_and_presets() {
        let mut p = Pairs::new(AccelKind::Bih, &[]);
        assert_eq!(bih(&mut p).unwrap(), BihParams::default());
        let params = kv(&[("max_prims", "5"), ("preset", "wachter_keller"), ("shrink", "on")]);
        let b = bih(&mut Pairs::new(AccelKind::Bih, &params)).unwrap();
        assert_eq!(b, BihParams { max_prims: 5, shrink: BihParams::default().shrink, ..BihParams::wachter_keller() });
        let params = kv(&[("shrink", "off"), ("empty_cut", "0.5")]);
        let b = bih(&mut Pairs::new(AccelKind::Bih, &params)).unwrap();
        assert_eq!((b.shrink, b.empty_cut), (None, Some(0.5)));
        let params = kv(&[("balance", "off"), ("max_depth", "6")]);
        let o = octree(&mut Pairs::new(AccelKind::Octree, &params)).unwrap();
        assert_eq!(o, OctreeParams { balance: false, max_depth: 6, ..OctreeParams::default() });
        let params = kv(&[("preset", "fast"), ("bins", "32")]);
        let b = bvh(&mut Pairs::new(AccelKind::Bvh, &params)).unwrap();
        assert_eq!(b, BvhParams { bins: 32, ..BvhParams::fast() });
        let params = kv(&[("max_depth", "auto"), ("min_prims", "4")]);
        let k = kdtree(&mut Pairs::new(AccelKind::KdTree, &params)).unwrap();
        assert_eq!(k, KdTreeParams { min_prims: 4, ..KdTreeParams::default() });
        let params = kv(&[("density", "3"), ("exact_overlap", "no")]);
        let g = grid(&mut Pairs::new(AccelKind::Grid, &params)).unwrap();
        assert_eq!(g, GridParams { density: 3.0, exact_overlap: false, ..GridParams::default() });
        let eye = Vec3::new(1.0, 2.0, 3.0);
        let params = kv(&[("resolution", "32")]);
        let a = apit(&mut Pairs::new(AccelKind::Apit, &params), Some(eye)).unwrap();
        assert_eq!((a.resolution, a.observer), (32, Observer::Point(eye)));
        let params = kv(&[("observer", "center")]);
        let a = apit(&mut Pairs::new(AccelKind::Apit, &params), Some(eye)).unwrap();
        assert_eq!(a.observer, Observer::BoundsCenter);
    }

    #[test]
    fn bad_parameters_name_the_structure_key_and_choices() {
        for (kind, pairs, needle) in [
            (AccelKind::Bih, vec![("max_prims", "x")], "`max_prims=x`: expected a whole number"),
            (AccelKind::Bih, vec![("max_prims", "0")], "max_prims"),
            (AccelKind::Bih, vec![("leaf", "4")], "unknown parameter `leaf` (known: preset, max_prims"),
            (AccelKind::Bih, vec![("preset", "turbo")], "unknown preset `turbo` (known: default, fast"),
            (AccelKind::Octree, vec![("balance", "maybe")], "expected on or off"),
            (AccelKind::Octree, vec![("max_depth", "20")], "max_depth"),
            (AccelKind::Bvh, vec![("bins", "1")], "bins"),
            (AccelKind::Grid, vec![("density", "-1")], "density"),
            (AccelKind::KdTree, vec![("empty_bonus", "2")], "empty_bonus"),
            (AccelKind::Apit, vec![("observer", "left")], "eye or center"),
            (AccelKind::ABuffer, vec![("resolution", "0")], "resolution 0"),
            (AccelKind::Brute, vec![("x", "1")], "brute takes no parameters"),
        ] {
            let e = check_params(kind, &kv(&pairs)).unwrap_err().to_string();
            assert!(e.contains(needle), "{kind} {pairs:?}: {e}");
        }
    }

    #[test]
    fn parameters_reach_the_built_structure() {
        let mesh = dynray_scene::shapes::icosphere(Vec3::ZERO, 1.0, 2);
        let small = build_with_params(AccelKind::Bih, &kv(&[("max_prims", "1")]), &mesh, None).unwrap();
        let large = build_with_params(AccelKind::Bih, &kv(&[("max_prims", "30")]), &mesh, None).unwrap();
        assert!(small.stats().leaves > large.stats().leaves);
        let bal = build_with_params(AccelKind::Octree, &[], &mesh, None).unwrap();
        let unbal = build_with_params(AccelKind::Octree, &kv(&[("balance", "off")]), &mesh, None).unwrap();
        assert!(bal.stats().leaves >= unbal.stats().leaves);
    }
}
