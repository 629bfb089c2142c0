//! One descriptor per structure kind: its name, what it is, its parameters type (keys,
//! presets, check, build), whether it refits, whether it depends on the eye, whether the
//! GPU backend traces it. The registry ([`AccelKind`]), [`AccelSpec`], `dynray info`,
//! the bench and the Python package all read this one table, so adding a structure is
//! one row here (and its folder).

use crate::structure_params::ParamKey;
use crate::{
    ABuffer, Accel, AccelKind, AccelSpec, Apit, ApitParams, Bih, BihParams, Brute, BruteParams, BuildError, Bvh,
    BvhParams, Grid, GridParams, KdTree, KdTreeParams, KdTreeRopes, Octree, OctreeDescent, OctreeParams,
    StructureParams, Wbvh, WbvhParams,
};
use dynray_geom::{TriangleMesh, Vec3};

/// A structure's build function: the spec (its parameters), the mesh, the eye.
pub type BuildFn = fn(&AccelSpec, &TriangleMesh, Option<Vec3>) -> Result<Box<dyn Accel>, BuildError>;

/// What the engine knows of one structure kind.
#[derive(Clone, Copy)]
pub struct AccelDescriptor {
    /// The kind.
    pub kind: AccelKind,
    /// The `--accel` spelling.
    pub name: &'static str,
    /// One line on what it is, for listings.
    pub summary: &'static str,
    /// The keys of its parameters type (without `preset`).
    pub keys: &'static [ParamKey],
    /// Its parameters type's preset names, `default` among them.
    pub presets: fn() -> Vec<&'static str>,
    /// Reads and validates a spec's parameters without building.
    pub check: fn(&AccelSpec) -> Result<(), BuildError>,
    /// Builds it over a mesh (the eye for view-dependent kinds).
    pub build: BuildFn,
    /// True when its update refits the bounds over the same tree (else an update
    /// rebuilds, whatever the policy).
    pub refits: bool,
    /// True when it is built around the observer, so a moving camera means an update.
    pub view_dependent: bool,
    /// True when the GPU backend traces it (`--backend gpu`).
    pub gpu: bool,
}

impl std::fmt::Debug for AccelDescriptor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AccelDescriptor").field("name", &self.name).finish_non_exhaustive()
    }
}

fn presets<P: StructureParams>() -> Vec<&'static str> {
    P::presets().into_iter().map(|(n, _)| n).collect()
}

fn check<P: StructureParams>(spec: &AccelSpec) -> Result<(), BuildError> {
    spec.read::<P>().map(drop)
}

/// The A-PIT's and the A-buffer's parameters, centred on the eye when they ask for it.
fn apit_params(spec: &AccelSpec, eye: Option<Vec3>) -> Result<ApitParams, BuildError> {
    let p: ApitParams = spec.read()?;
    Ok(match (p.observer, eye) {
        (crate::apit::Observer::Eye, Some(e)) => p.with_observer(e),
        _ => p,
    })
}

/// Every structure, in the order listings show them ([`AccelKind::ALL`]).
pub const DESCRIPTORS: &[AccelDescriptor] = &[
    AccelDescriptor {
        kind: AccelKind::Brute,
        name: "brute",
        summary: "every triangle for every ray: the oracle",
        keys: BruteParams::KEYS,
        presets: presets::<BruteParams>,
        check: check::<BruteParams>,
        build: |s, m, _| {
            s.read::<BruteParams>()?;
            Ok(Box::new(Brute::build(m)?))
        },
        refits: false,
        view_dependent: false,
        gpu: false,
    },
    AccelDescriptor {
        kind: AccelKind::Bvh,
        name: "bvh",
        summary: "binned-SAH BVH collapsed to 4/8-wide SIMD nodes with 4-triangle leaf blocks (the default)",
        keys: WbvhParams::KEYS,
        presets: presets::<WbvhParams>,
        check: check::<WbvhParams>,
        build: |s, m, _| Ok(Box::new(Wbvh::build(m, &s.read()?)?)),
        refits: true,
        view_dependent: false,
        // Traced on the GPU as its binary tree, `bvh2` (AccelSpec::binary_bvh).
        gpu: true,
    },
    AccelDescriptor {
        kind: AccelKind::Bvh2,
        name: "bvh2",
        summary: "seed 003's binary binned-SAH BVH: what the GPU uploads and the wide BVH collapses",
        keys: BvhParams::KEYS,
        presets: presets::<BvhParams>,
        check: check::<BvhParams>,
        build: |s, m, _| Ok(Box::new(Bvh::build(m, &s.read()?)?)),
        refits: true,
        view_dependent: false,
        gpu: true,
    },
    AccelDescriptor {
        kind: AccelKind::Bih,
        name: "bih",
        summary: "Bounding Interval Hierarchy (seed 000), built for per-frame rebuilds",
        keys: BihParams::KEYS,
        presets: presets::<BihParams>,
        check: check::<BihParams>,
        build: |s, m, _| Ok(Box::new(Bih::build(m, &s.read()?)?)),
        refits: true,
        view_dependent: false,
        gpu: false,
    },
    AccelDescriptor {
        kind: AccelKind::KdTree,
        name: "kdtree",
        summary: "SAH kd-tree, stack traversal (seed 000's baseline)",
        keys: KdTreeParams::KEYS,
        presets: presets::<KdTreeParams>,
        check: check::<KdTreeParams>,
        build: |s, m, _| Ok(Box::new(KdTree::build_with(m, &s.read()?)?)),
        refits: false,
        view_dependent: false,
        gpu: false,
    },
    AccelDescriptor {
        kind: AccelKind::KdTreeRopes,
        name: "kdtree-ropes",
        summary: "SAH kd-tree, stackless Ropes++ traversal (seed 000's baseline)",
        keys: KdTreeParams::KEYS,
        presets: presets::<KdTreeParams>,
        check: check::<KdTreeParams>,
        build: |s, m, _| Ok(Box::new(KdTreeRopes::build_with(m, &s.read()?)?)),
        refits: false,
        view_dependent: false,
        gpu: false,
    },
    AccelDescriptor {
        kind: AccelKind::Octree,
        name: "octree",
        summary: "2:1-balanced octree walked leaf to leaf through neighbour links (seed 002)",
        keys: OctreeParams::KEYS,
        presets: presets::<OctreeParams>,
        check: check::<OctreeParams>,
        build: |s, m, _| Ok(Box::new(Octree::build(m, &s.read()?)?)),
        refits: false,
        view_dependent: false,
        gpu: false,
    },
    AccelDescriptor {
        kind: AccelKind::OctreeDescent,
        name: "octree-descent",
        summary: "the same octree, top-down parametric descent (Revelles 2000)",
        keys: OctreeParams::KEYS,
        presets: presets::<OctreeParams>,
        check: check::<OctreeParams>,
        build: |s, m, _| Ok(Box::new(OctreeDescent::build(m, &s.read()?)?)),
        refits: false,
        view_dependent: false,
        gpu: false,
    },
    AccelDescriptor {
        kind: AccelKind::Grid,
        name: "grid",
        summary: "uniform grid (seed 002's baseline)",
        keys: GridParams::KEYS,
        presets: presets::<GridParams>,
        check: check::<GridParams>,
        build: |s, m, _| Ok(Box::new(Grid::build(m, &s.read()?)?)),
        refits: false,
        view_dependent: false,
        gpu: false,
    },
    AccelDescriptor {
        kind: AccelKind::Apit,
        name: "apit",
        summary: "A-buffers on a cube around the observer with pseudo-interval trees (seed 004)",
        keys: ApitParams::KEYS,
        presets: presets::<ApitParams>,
        check: check::<ApitParams>,
        build: |s, m, eye| Ok(Box::new(Apit::build(m, &apit_params(s, eye)?)?)),
        refits: false,
        view_dependent: true,
        gpu: false,
    },
    AccelDescriptor {
        kind: AccelKind::ABuffer,
        name: "abuffer",
        summary: "the same A-buffers with plain per-pixel lists (seed 004's baseline)",
        keys: ApitParams::KEYS,
        presets: presets::<ApitParams>,
        check: check::<ApitParams>,
        build: |s, m, eye| Ok(Box::new(ABuffer::build(m, &apit_params(s, eye)?)?)),
        refits: false,
        view_dependent: true,
        gpu: false,
    },
];

impl AccelKind {
    /// This kind's row of [`DESCRIPTORS`].
    pub fn descriptor(self) -> &'static AccelDescriptor {
        DESCRIPTORS.iter().find(|d| d.kind == self).expect("every kind has a descriptor (tested)")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_has_one_descriptor_in_listing_order() {
        let kinds: Vec<AccelKind> = DESCRIPTORS.iter().map(|d| d.kind).collect();
        assert_eq!(kinds, AccelKind::ALL);
        for d in DESCRIPTORS {
            assert_eq!(d.kind.descriptor().name, d.name);
            assert!((d.presets)().contains(&"default"), "{}", d.name);
        }
    }

    #[test]
    fn refits_match_what_the_structures_do() {
        let mesh = TriangleMesh::new(vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], vec![[0, 1, 2]]);
        for d in DESCRIPTORS {
            let built = (d.build)(&AccelSpec::new(d.kind), &mesh, None).unwrap();
            assert_eq!(built.update_refits(), d.refits, "{}", d.name);
        }
    }
}
