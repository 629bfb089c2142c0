//! The builders' WGSL modules (one per file of `shaders/`), compiled on first use and
//! kept for the device's lifetime; pipelines have layouts derived from their entry point.

use crate::{kernel, GpuContext, GpuError};
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

const BUILD_COMMON: &str = include_str!("../../shaders/build_common.wgsl");

/// A builder module: its sources (after `build_common.wgsl`) and entry points.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum Module {
    Scan,
    RadixSort,
    Morton,
    Karras,
    LbvhLayout,
    Refit,
    Sah,
}

impl Module {
    fn sources(self) -> &'static [&'static str] {
        match self {
            Module::Scan => &[crate::shader::WORKGROUP_SCAN, include_str!("../../shaders/scan.wgsl")],
            Module::RadixSort => &[include_str!("../../shaders/radix_sort.wgsl")],
            Module::Morton => &[include_str!("../../shaders/morton.wgsl")],
            Module::Karras => &[include_str!("../../shaders/karras.wgsl")],
            Module::LbvhLayout => &[include_str!("../../shaders/lbvh_layout.wgsl")],
            Module::Refit => &[include_str!("../../shaders/refit.wgsl")],
            Module::Sah => &[include_str!("../../shaders/sah_build.wgsl")],
        }
    }

    fn entries(self) -> &'static [&'static str] {
        match self {
            Module::Scan => &["scan_reduce", "scan_blocks", "scan_apply"],
            Module::RadixSort => &["sort_histogram", "sort_scatter"],
            Module::Morton => &["centroid_bounds", "morton_codes"],
            Module::Karras => &["hierarchy"],
            Module::LbvhLayout => &["layout_flags", "layout_emit"],
            Module::Refit => &["gather_triangles", "refit_level"],
            Module::Sah => &["sah_split", "sah_split_small", "sah_flags", "sah_emit", "sah_scatter"],
        }
    }

    /// The module's full source.
    pub(crate) fn source(self) -> String {
        let mut s = String::from(BUILD_COMMON);
        for part in self.sources() {
            s.push('\n');
            s.push_str(part);
        }
        s
    }

    #[cfg(test)]
    pub(crate) const ALL: [Module; 7] = [
        Module::Scan,
        Module::RadixSort,
        Module::Morton,
        Module::Karras,
        Module::LbvhLayout,
        Module::Refit,
        Module::Sah,
    ];
}

/// The compiled entry points of one module, by name.
pub(crate) struct Pipelines {
    by_entry: HashMap<&'static str, wgpu::ComputePipeline>,
}

impl Pipelines {
    pub(crate) fn get(&self, entry: &str) -> &wgpu::ComputePipeline {
        &self.by_entry[entry]
    }
}

/// Modules compiled so far on one device.
#[derive(Default)]
pub(crate) struct BuildKernels {
    modules: Mutex<HashMap<Module, Arc<Pipelines>>>,
}

impl BuildKernels {
    pub(crate) fn get(&self, ctx: &GpuContext, module: Module) -> Result<Arc<Pipelines>, GpuError> {
        let mut map = self.modules.lock().unwrap_or_else(|p| p.into_inner());
        if let Some(p) = map.get(&module) {
            return Ok(p.clone());
        }
        let entries = module.entries();
        let compiled = kernel::compile(ctx, "BVH builder", &module.source(), entries)?;
        let p = Arc::new(Pipelines { by_entry: entries.iter().copied().zip(compiled).collect() });
        map.insert(module, p.clone());
        Ok(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_builder_module_parses_and_validates() {
        for m in Module::ALL {
            let src = m.source();
            let module = naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&src)));
            naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
                .validate(&module)
                .unwrap_or_else(|e| panic!("{m:?}: {e:?}"));
            for e in m.entries() {
                assert!(module.entry_points.iter().any(|p| p.name == *e), "{m:?} lacks {e}");
            }
        }
    }
}
