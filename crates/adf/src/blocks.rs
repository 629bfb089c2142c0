//! The voxel texture (seed 001 §3.1): one single-channel 3-D texture holding, for every
//! internal cell, the 3×3×3 samples its 8 children share (27 texels instead of the
//! 8 × 8 = 64 a pointer ADF keeps for them). Child `o ∈ {0,1}^3` reads the 2×2×2
//! sub-block at `origin + o`, so a lookup never leaves its block and no gutter is needed.
//!
//! Blocks sit on a regular grid of `dims` block slots (x fastest), filled in the tree's
//! breadth-first order: block `i` has its first texel at
//! `3 · (i mod bx, (i / bx) mod by, i / (bx · by))`. Texels are stored x fastest, then y,
//! then z, as a 3-D texture upload wants them; unused slots hold 0.

/// The packed voxel texture.
#[derive(Clone, Debug, PartialEq)]
pub struct VoxelTexture {
    /// Block slots per axis.
    pub(crate) dims: [u32; 3],
    /// `27 · dims[0] · dims[1] · dims[2]` texels, x fastest.
    pub(crate) texels: Vec<f32>,
}

impl VoxelTexture {
    /// Block slots for `n` blocks: `bx = by = ⌈∛n⌉`, `bz` as few as hold the rest.
    pub(crate) fn dims_for(n: usize) -> [u32; 3] {
        let n = n.max(1);
        let mut b = (n as f64).cbrt().ceil() as u32;
        while (b as usize).pow(3) < n {
            b += 1;
        }
        while b > 1 && ((b - 1) as usize).pow(3) >= n {
            b -= 1;
        }
        let bz = n.div_ceil(b as usize * b as usize) as u32;
        [b, b, bz.max(1)]
    }

    /// Packs the child-grid samples of each internal cell, block `i` from `blocks[i]`.
    pub(crate) fn pack(blocks: &[[f32; 27]]) -> Self {
        let dims = Self::dims_for(blocks.len());
        let mut tex = Self { dims, texels: vec![0.0; 27 * dims.iter().map(|&d| d as usize).product::<usize>()] };
        for (i, b) in blocks.iter().enumerate() {
            let o = tex.origin(i as u32);
            for (k, v) in b.iter().enumerate() {
                let k = k as u32;
                let at = tex.index(o[0] + k % 3, o[1] + (k / 3) % 3, o[2] + k / 9);
                tex.texels[at] = *v;
            }
        }
        tex
    }

    /// Texture size in texels per axis.
    pub fn size(&self) -> [u32; 3] {
        self.dims.map(|d| 3 * d)
    }

    /// Block slots per axis (block `i` sits at slot `(i mod bx, (i / bx) mod by, i / (bx · by))`).
    pub fn block_dims(&self) -> [u32; 3] {
        self.dims
    }

    /// Every texel, x fastest (what a device uploads).
    pub fn texels(&self) -> &[f32] {
        &self.texels
    }

    /// Number of block slots.
    pub fn slots(&self) -> usize {
        self.dims.iter().map(|&d| d as usize).product()
    }

    /// The first texel of block `i`.
    #[inline]
    pub(crate) fn origin(&self, i: u32) -> [u32; 3] {
        let (bx, by) = (self.dims[0], self.dims[1]);
        [3 * (i % bx), 3 * ((i / bx) % by), 3 * (i / (bx * by))]
    }

    #[inline]
    fn index(&self, x: u32, y: u32, z: u32) -> usize {
        let [sx, sy, _] = self.size();
        x as usize + sx as usize * (y as usize + sy as usize * z as usize)
    }

    /// The texel at `(x, y, z)`; 0 outside (never for blocks the hash names, which load
    /// checks against the slot count).
    #[inline]
    pub(crate) fn texel(&self, x: u32, y: u32, z: u32) -> f32 {
        self.texels.get(self.index(x, y, z)).copied().unwrap_or(0.0)
    }

    /// Bytes of the texture.
    pub fn memory_bytes(&self) -> usize {
        self.texels.len() * 4
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dims_hold_every_block_and_packing_round_trips() {
        for n in [1usize, 2, 7, 8, 9, 26, 27, 28, 1000, 1001] {
            let d = VoxelTexture::dims_for(n);
            let slots = d.iter().map(|&x| x as usize).product::<usize>();
            assert!(slots >= n && slots < n + (d[0] * d[1]) as usize, "{n}: {d:?}");
        }
        let blocks: Vec<[f32; 27]> = (0..30).map(|i| std::array::from_fn(|k| (i * 27 + k) as f32)).collect();
        let t = VoxelTexture::pack(&blocks);
        for (i, b) in blocks.iter().enumerate() {
            let o = t.origin(i as u32);
            for (k, v) in b.iter().enumerate() {
                let k = k as u32;
                assert_eq!(t.texel(o[0] + k % 3, o[1] + (k / 3) % 3, o[2] + k / 9), *v);
            }
        }
    }
}
