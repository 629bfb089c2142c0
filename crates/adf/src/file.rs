//! The `.adf` file (docs/adf.md, "File format"): a fixed little-endian header, the three
//! tables as they upload (voxel texture, H, Φ), and an FNV-1a checksum of everything
//! before it. Loading checks the magic, the version, that the sizes the header gives add
//! up to the file's length (before reading any table), the checksum, and every table
//! entry the lookups index with, so a damaged file is an error naming it, never a panic.
//! Writing goes to a temporary file in the same folder, renamed over the target when
//! complete: no partial file is ever left under the target's name.

use crate::hash::{CellEntry, PerfectHash, PhiEntry};
use crate::{Adf, BuildInfo, Cube, FileError, View, ViewProjection, VoxelTexture, MAX_LEVEL};
use bytemuck::{Pod, Zeroable};
use dynray_geom::{Aabb, Vec3};
use std::io::Write;
use std::path::Path;

/// The first 8 bytes of every `.adf` file.
pub const MAGIC: [u8; 8] = *b"DYNRADF\0";
/// The format version this build reads and writes. Version 2 (trees to level 16: the
/// header's per-level counts to 16, H's second identifier words) replaced version 1,
/// which files written before it carry: rebuild those with `dynray adf build`.
pub const FORMAT_VERSION: u32 = 2;

// The tables are cast to bytes as they are in memory.
const _: () = assert!(cfg!(target_endian = "little"), "the .adf format is little-endian");

/// Levels the header has counts for.
const LEVEL_SLOTS: usize = MAX_LEVEL as usize + 1;

/// The header, 4-byte fields only (no padding).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Header {
    magic: [u8; 8],
    version: u32,
    header_bytes: u32,
    max_level: u32,
    internal_cells: u32,
    block_dims: [u32; 3],
    hash_m: u32,
    hash_r: u32,
    hash_attempts: u32,
    /// 1: H has a second identifier word per slot (trees deeper than 10 levels).
    wide_ids: u32,
    cube_origin: [f32; 3],
    cube_size: f32,
    source_min: [f32; 3],
    source_max: [f32; 3],
    epsilon: f32,
    lipschitz: f32,
    build_ms: f32,
    hash_ms: f32,
    triangles: [u32; 2],
    constrained_samples: [u32; 2],
    /// 0: no view; 1: perspective (`view_param` = fov_y degrees); 2: parallel (height).
    view_kind: u32,
    view_param: f32,
    view_position: [f32; 3],
    view_look_at: [f32; 3],
    view_up: [f32; 3],
    internal_per_level: [u32; LEVEL_SLOTS],
    leaves_per_level: [[u32; 2]; LEVEL_SLOTS],
}

// 93 four-byte fields; docs/adf.md gives this size.
const _: () = assert!(std::mem::size_of::<Header>() == 372);

fn split(x: u64) -> [u32; 2] {
    [x as u32, (x >> 32) as u32]
}

fn join(x: [u32; 2]) -> u64 {
    x[0] as u64 | (x[1] as u64) << 32
}

/// FNV-1a, 64 bits.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| (h ^ b as u64).wrapping_mul(0x0100_0000_01b3))
}

impl Adf {
    /// The file's bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        let i = &self.info;
        let mut internal_per_level = [0u32; LEVEL_SLOTS];
        let mut leaves_per_level = [[0u32; 2]; LEVEL_SLOTS];
        for (l, (&n, &m)) in i.internal_per_level.iter().zip(&i.leaves_per_level).enumerate().take(LEVEL_SLOTS) {
            internal_per_level[l] = n as u32;
            leaves_per_level[l] = split(m);
        }
        let (view_kind, view_param, v) = match i.view {
            None => (
                0,
                0.0,
                View {
                    position: Vec3::ZERO,
                    look_at: Vec3::ZERO,
                    up: Vec3::ZERO,
                    projection: ViewProjection::Parallel(0.0),
                },
            ),
            Some(v) => match v.projection {
                ViewProjection::Perspective(f) => (1, f, v),
                ViewProjection::Parallel(h) => (2, h, v),
            },
        };
        let h = Header {
            magic: MAGIC,
            version: FORMAT_VERSION,
            header_bytes: std::mem::size_of::<Header>() as u32,
            max_level: self.max_level,
            internal_cells: self.internal_cells() as u32,
            block_dims: self.voxels.dims,
            hash_m: self.hash.m,
            hash_r: self.hash.r,
            hash_attempts: self.hash.attempts,
            wide_ids: !self.hash.high.is_empty() as u32,
            cube_origin: self.cube.origin.to_array(),
            cube_size: self.cube.size,
            source_min: self.source_bounds.min.to_array(),
            source_max: self.source_bounds.max.to_array(),
            epsilon: self.epsilon,
            lipschitz: self.lipschitz,
            build_ms: i.build_ms,
            hash_ms: i.hash_ms,
            triangles: split(i.triangles),
            constrained_samples: split(i.constrained_samples),
            view_kind,
            view_param,
            view_position: v.position.to_array(),
            view_look_at: v.look_at.to_array(),
            view_up: v.up.to_array(),
            internal_per_level,
            leaves_per_level,
        };
        let mut out = Vec::with_capacity(std::mem::size_of::<Header>() + self.voxels.memory_bytes() + 8);
        out.extend_from_slice(bytemuck::bytes_of(&h));
        out.extend_from_slice(bytemuck::cast_slice(&self.voxels.texels));
        out.extend_from_slice(bytemuck::cast_slice(&self.hash.table));
        out.extend_from_slice(bytemuck::cast_slice(&self.hash.high));
        out.extend_from_slice(bytemuck::cast_slice(&self.hash.phi));
        out.extend_from_slice(bytemuck::cast_slice(&self.cell_lipschitz));
        let sum = fnv1a(&out);
        out.extend_from_slice(&sum.to_le_bytes());
        out
    }

    /// Writes the file atomically ([`dynray_geom::file::atomic`]: a temporary file beside
    /// it, renamed when complete, never over an input).
    pub fn save(&self, path: &Path) -> Result<(), FileError> {
        let io = |source| FileError::Io { path: path.to_path_buf(), source };
        dynray_geom::file::write_atomic(path, |f| f.write_all(&self.to_bytes()).map_err(io), io)
    }

    /// Reads and checks a file (module docs).
    pub fn load(path: &Path) -> Result<Self, FileError> {
        let bytes =
            dynray_geom::file::read(path).map_err(|source| FileError::Io { path: path.to_path_buf(), source })?;
        Self::from_bytes(&bytes, path)
    }

    /// Parses and checks a file's bytes; `path` names it in errors.
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Self, FileError> {
        let corrupt = |what: String| FileError::Corrupt { path: path.to_path_buf(), what };
        if bytes.len() < 12 || bytes[..8] != MAGIC {
            return Err(FileError::NotAdf { path: path.to_path_buf() });
        }
        let version = u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]);
        if version != FORMAT_VERSION {
            return Err(FileError::Version { path: path.to_path_buf(), found: version, supported: FORMAT_VERSION });
        }
        let hsize = std::mem::size_of::<Header>();
        let length =
            |expected: u64| FileError::Length { path: path.to_path_buf(), expected, found: bytes.len() as u64 };
        if bytes.len() < hsize {
            return Err(length(hsize as u64 + 8));
        }
        let h: Header = bytemuck::pod_read_unaligned(&bytes[..hsize]);
        if h.header_bytes as usize != hsize {
            return Err(corrupt(format!("header of {} bytes, expected {hsize}", h.header_bytes)));
        }
        if !(1..=MAX_LEVEL).contains(&h.max_level) {
            return Err(corrupt(format!("max level {} outside 1..={MAX_LEVEL}", h.max_level)));
        }
        // Sizes in u128: three u32 dimensions or a u32 cubed reach 2^96, past u64 (a
        // header whose product wrapped in u64 loaded and drew wrong pixels). Nothing here
        // overflows, and a header claiming huge tables is caught by the length check
        // before anything is allocated; after it, every size fits the file, and usize.
        let slots: u128 = h.block_dims.iter().map(|&d| d as u128).product();
        let (voxels, table, phi) = (27 * slots, (h.hash_m as u128).pow(3), (h.hash_r as u128).pow(3));
        if h.wide_ids > 1 {
            return Err(corrupt(format!("identifier width flag {}", h.wide_ids)));
        }
        let high = if h.wide_ids == 1 { table } else { 0 };
        let expected = hsize as u128 + 4 * voxels + 8 * table + 4 * high + 8 * phi + 4 * h.internal_cells as u128 + 8;
        if bytes.len() as u128 != expected {
            return Err(length(u64::try_from(expected).unwrap_or(u64::MAX)));
        }
        let body = bytes.len() - 8;
        let mut sum = [0u8; 8];
        sum.copy_from_slice(&bytes[body..]);
        if fnv1a(&bytes[..body]) != u64::from_le_bytes(sum) {
            return Err(corrupt("checksum mismatch".into()));
        }
        let n = h.internal_cells as u64;
        if n == 0 || slots < n as u128 || table < n as u128 || h.hash_r == 0 || h.block_dims.contains(&0) {
            return Err(corrupt(format!(
                "{n} internal cells do not fit {slots} blocks or a {}^3 cell table",
                h.hash_m
            )));
        }
        let floats = [h.cube_size, h.epsilon, h.lipschitz]
            .into_iter()
            .chain(h.cube_origin)
            .chain(h.source_min)
            .chain(h.source_max);
        if floats.into_iter().any(|x| !x.is_finite()) || h.cube_size <= 0.0 {
            return Err(corrupt("non-finite or non-positive cube, bounds, epsilon or Lipschitz bound".into()));
        }
        let (v0, t0) = (hsize, hsize + 4 * voxels as usize);
        let w0 = t0 + 8 * table as usize;
        let p0 = w0 + 4 * high as usize;
        let l0 = p0 + 8 * phi as usize;
        let texels: Vec<f32> = bytemuck::pod_collect_to_vec(&bytes[v0..t0]);
        let table: Vec<CellEntry> = bytemuck::pod_collect_to_vec(&bytes[t0..w0]);
        let high: Vec<u32> = bytemuck::pod_collect_to_vec(&bytes[w0..p0]);
        let phi: Vec<PhiEntry> = bytemuck::pod_collect_to_vec(&bytes[p0..l0]);
        let cell_lipschitz: Vec<f32> = bytemuck::pod_collect_to_vec(&bytes[l0..body]);
        if cell_lipschitz.iter().any(|x| !(x.is_finite() && *x >= 0.0)) {
            return Err(corrupt("negative or non-finite Lipschitz bound of a cell".into()));
        }
        if texels.iter().any(|x| !x.is_finite()) {
            return Err(corrupt("non-finite voxel".into()));
        }
        if let Some(e) =
            phi.iter().find(|e| e.w == 0 || e.w as u32 > h.hash_m || e.t.iter().any(|&t| t as u32 >= h.hash_m))
        {
            return Err(corrupt(format!("offset entry {e:?} outside the {}^3 cell table", h.hash_m)));
        }
        let hash = PerfectHash { m: h.hash_m, r: h.hash_r, phi, table, high, attempts: h.hash_attempts };
        // Every stored cell must be where its key hashes, inside the tree, and name a block.
        let mut stored = 0u64;
        let mut stored_per_level = [0u64; LEVEL_SLOTS];
        for (s, k) in (0..hash.table.len()).filter_map(|s| Some((s, hash.key_at(s)?))) {
            let e = hash.table[s];
            let level = 31 - k[0].max(1).leading_zeros();
            let same_level = k.iter().all(|&c| c >= 1 && 31 - c.leading_zeros() == level);
            if !same_level || level >= h.max_level || hash.slot(k) != s || e.block as u64 >= n {
                return Err(corrupt(format!("cell table slot {s} holds an invalid entry {e:?}")));
            }
            stored += 1;
            stored_per_level[level as usize] += 1;
        }
        if stored != n || hash.find([1, 1, 1]).is_none() {
            return Err(corrupt(format!("{stored} cells in the table, header says {n} (root included)")));
        }
        let view = match h.view_kind {
            0 => None,
            k @ (1 | 2) => {
                let v = [h.view_position, h.view_look_at, h.view_up].map(Vec3::from_array);
                if v.iter().any(|x| !x.is_finite()) || !h.view_param.is_finite() {
                    return Err(corrupt("non-finite view".into()));
                }
                let projection = if k == 1 {
                    ViewProjection::Perspective(h.view_param)
                } else {
                    ViewProjection::Parallel(h.view_param)
                };
                Some(View { position: v[0], look_at: v[1], up: v[2], projection })
            }
            k => return Err(corrupt(format!("unknown view kind {k}"))),
        };
        let levels = h.max_level as usize + 1;
        let info = BuildInfo {
            internal_per_level: h.internal_per_level[..levels].iter().map(|&x| x as u64).collect(),
            leaves_per_level: h.leaves_per_level[..levels].iter().map(|&x| join(x)).collect(),
            build_ms: h.build_ms,
            hash_ms: h.hash_ms,
            constrained_samples: join(h.constrained_samples),
            triangles: join(h.triangles),
            view,
        };
        // The counts `info` prints and `cells()` adds up: each level's internal cells are
        // the ones the table holds, and the tree is complete (the root splits, and every
        // internal cell's 8 children are internal cells or leaves of the next level). A
        // header's leaf counts are otherwise any 64-bit numbers, whose sum overflowed
        // (found by fuzzing, docs/fuzzing.md).
        if info.internal_per_level[..] != stored_per_level[..levels] {
            return Err(corrupt(format!(
                "per-level internal cell counts {:?} are not the table's {:?}",
                info.internal_per_level,
                &stored_per_level[..levels]
            )));
        }
        let mut children = 1u64;
        for (level, (&internal, &leaves)) in info.internal_per_level.iter().zip(&info.leaves_per_level).enumerate() {
            if internal.checked_add(leaves) != Some(children) || (level == levels - 1 && internal != 0) {
                return Err(corrupt(format!(
                    "level {level} has {internal} internal cells and {leaves} leaves; the level above splits into {children} cells"
                )));
            }
            children = 8 * internal;
        }
        Ok(Adf {
            max_level: h.max_level,
            cube: Cube { origin: Vec3::from_array(h.cube_origin), size: h.cube_size },
            source_bounds: Aabb::new(Vec3::from_array(h.source_min), Vec3::from_array(h.source_max)),
            epsilon: h.epsilon,
            lipschitz: h.lipschitz,
            cell_lipschitz,
            voxels: VoxelTexture { dims: h.block_dims, texels },
            hash,
            info,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{BuildParams, SphereSource};
    use std::mem::offset_of;

    /// `bytes` with its checksum written again over the body, as a damaged file made by
    /// a tool (or an attacker) that knows the format would have it.
    fn resummed(mut bytes: Vec<u8>) -> Vec<u8> {
        let body = bytes.len() - 8;
        let sum = fnv1a(&bytes[..body]);
        bytes[body..].copy_from_slice(&sum.to_le_bytes());
        bytes
    }

    /// Regression (found by fuzzing, docs/fuzzing.md): the header's leaf counts were
    /// taken as written, so a file with a valid checksum and a leaf count near 2^64 loaded,
    /// and `cells()` (`dynray info`'s cell count) overflowed adding them up: a panic with
    /// overflow checks, a wrapped count without. The per-level counts must now describe
    /// the tree the cell table holds.
    #[test]
    fn per_level_counts_must_describe_the_stored_tree() {
        let src = SphereSource { centre: Vec3::new(0.1, -0.2, 0.05), radius: 1.0 };
        let b = Aabb::new(Vec3::splat(-2.0), Vec3::splat(2.0));
        let adf = Adf::build(&src, b, &BuildParams { max_level: 4, epsilon: 1e-3 }, &|_, _| {}).unwrap();
        let bytes = adf.to_bytes();
        let p = Path::new("x.adf");
        let loaded = Adf::from_bytes(&bytes, p).unwrap();
        assert_eq!(loaded.cells(), 1 + 8 * loaded.internal_cells());

        let leaves = offset_of!(Header, leaves_per_level);
        let internal = offset_of!(Header, internal_per_level);
        let mut huge = bytes.clone();
        huge[leaves + 8 * 2..leaves + 8 * 3].copy_from_slice(&u64::MAX.to_le_bytes());
        let e = Adf::from_bytes(&resummed(huge), p).unwrap_err().to_string();
        assert!(e.starts_with("x.adf: ") && e.contains("level 2 has"), "{e}");

        // One leaf too many at the deepest level, and the root counted as a leaf.
        let mut extra = bytes.clone();
        let at = leaves + 8 * 4;
        let n = u64::from_le_bytes(extra[at..at + 8].try_into().unwrap());
        extra[at..at + 8].copy_from_slice(&(n + 1).to_le_bytes());
        assert!(matches!(Adf::from_bytes(&resummed(extra), p), Err(FileError::Corrupt { .. })));
        let mut root = bytes.clone();
        root[leaves..leaves + 4].copy_from_slice(&1u32.to_le_bytes());
        assert!(matches!(Adf::from_bytes(&resummed(root), p), Err(FileError::Corrupt { .. })));

        // Internal counts moved between levels keep their sum but not the table's levels.
        let mut moved = bytes;
        let count =
            |b: &[u8], l: usize| u32::from_le_bytes(b[internal + 4 * l..internal + 4 * l + 4].try_into().unwrap());
        let (one, two) = (count(&moved, 1), count(&moved, 2));
        moved[internal + 4..internal + 8].copy_from_slice(&(one + 1).to_le_bytes());
        moved[internal + 8..internal + 12].copy_from_slice(&(two - 1).to_le_bytes());
        let e = Adf::from_bytes(&resummed(moved), p).unwrap_err().to_string();
        assert!(e.contains("are not the table's"), "{e}");
    }
}
