//! Twin pixels: the sparse set of pixels that a render also samples with an independent
//! randomization (replica 1, [`stratapt_sampling::replica`]), to calibrate the error estimate.
//!
//! The film is cut into `block × block` blocks; each block's twin is one pixel at a hashed
//! position inside it (so the subset does not alias with the scene). `block` is 4 (1 pixel in
//! 16 has a twin: 6 % more samples) unless that leaves fewer than [`MIN_TWINS`] twins, then 2,
//! then 1 (every pixel of a tiny film has one). Twin `k` is block `(k % blocks_x, k / blocks_x)`.
//! On the GPU the twins are extra rows after the film (twin `k` at virtual row
//! `height + k / width`, column `k % width`). Mirrored in `shaders/twin.wgsl`.

use stratapt_sampling::hash::hash_combine;

/// Fewest twins a film gets (while it has that many pixels): enough pairs for the image-wide
/// calibration to be within a few percent.
pub const MIN_TWINS: u32 = 256;
/// Key of the hash that places each twin inside its block.
pub const TWIN_KEY: u32 = 0x7e1a_b10c;

/// Where a film's twins are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TwinLayout {
    pub width: u32,
    pub height: u32,
    /// Side of the blocks that hold one twin each, in pixels.
    pub block: u32,
    /// Blocks per film row.
    pub blocks_x: u32,
    /// Number of twins (blocks).
    pub count: u32,
}

impl TwinLayout {
    pub fn new(width: u32, height: u32) -> Self {
        let blocks = |b: u32| (width.div_ceil(b), height.div_ceil(b));
        let block = [4, 2]
            .into_iter()
            .find(|&b| {
                let (x, y) = blocks(b);
                x as u64 * y as u64 >= MIN_TWINS as u64
            })
            .unwrap_or(1);
        let (blocks_x, blocks_y) = blocks(block);
        Self {
            width,
            height,
            block,
            blocks_x,
            count: blocks_x * blocks_y,
        }
    }

    /// The film pixel twin `k` samples again.
    #[inline]
    pub fn pixel(&self, k: u32) -> [u32; 2] {
        let (bx, by) = (k % self.blocks_x, k / self.blocks_x);
        let h = hash_combine(hash_combine(TWIN_KEY, bx), by);
        let (ox, oy) = (h % self.block, (h / self.block) % self.block);
        [
            (bx * self.block + ox).min(self.width - 1),
            (by * self.block + oy).min(self.height - 1),
        ]
    }

    /// Rows the twins take after the film on the GPU (`width` twins per row).
    pub fn rows(&self) -> u32 {
        self.count.div_ceil(self.width.max(1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_twin_per_block_inside_it() {
        for (w, h) in [
            (1, 1),
            (4, 4),
            (16, 16),
            (33, 17),
            (64, 64),
            (100, 37),
            (512, 384),
        ] {
            let t = TwinLayout::new(w, h);
            assert!(
                t.count >= MIN_TWINS.min(w * h),
                "{w}x{h}: {} twins",
                t.count
            );
            for k in 0..t.count {
                let [x, y] = t.pixel(k);
                assert!(x < w && y < h);
                let (bx, by) = (k % t.blocks_x, k / t.blocks_x);
                assert_eq!((x / t.block, y / t.block), (bx, by), "{w}x{h} twin {k}");
            }
        }
        assert_eq!(TwinLayout::new(512, 512).block, 4);
        assert_eq!(TwinLayout::new(32, 32).block, 2);
        assert_eq!(TwinLayout::new(16, 16).block, 1);
    }
}
