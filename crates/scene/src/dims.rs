//! The sample-dimension layout: which dimension each domain consumes, in a fixed order, with no
//! dimension spent on a domain the scene does not call for.
//!
//! Order: pixel (2) · lens (2, if lens) · time (1, if time) · then per path vertex
//! `k = 0, 1, …`: light select (1) + light point (2) (if nee) · direction (2) · lobe (1, if lobe)
//! · roulette (1, if roulette).

use crate::Effects;

/// Where each domain's sample dimensions start, for a scene's [`Effects`]: both renderers and
/// the GPU kernel's specialization read the same layout, so the same sample index draws the same
/// numbers everywhere. An absent domain is `None`.
///
/// ```
/// use stratapt_scene::{DimLayout, Effects};
///
/// let all = DimLayout::new(&Effects::everything());
/// assert_eq!((all.pixel, all.lens, all.time), (0, Some(2), Some(4)));
/// assert_eq!(all.per_vertex, 7); // light select 1 + light point 2 + direction 2 + lobe + roulette
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct DimLayout {
    /// 2D: position in the pixel (filter).
    pub pixel: u32,
    /// 2D: point on the lens.
    pub lens: Option<u32>,
    /// 1D: instant in the shutter.
    pub time: Option<u32>,
    /// First dimension of vertex 0.
    pub first_vertex: u32,
    /// Dimensions consumed per vertex.
    pub per_vertex: u32,
    /// Offsets within a vertex's block.
    pub light_select: Option<u32>,
    pub light_point: Option<u32>,
    pub direction: u32,
    pub lobe: Option<u32>,
    pub roulette: Option<u32>,
}

impl DimLayout {
    /// The layout of a scene whose effects are `effects`, in the order of the module doc.
    pub fn new(effects: &Effects) -> Self {
        let mut next = 0;
        let mut take = |n: u32| {
            let d = next;
            next += n;
            d
        };
        let pixel = take(2);
        let lens = effects.lens.then(|| take(2));
        let time = effects.time.then(|| take(1));
        let first_vertex = next;
        let mut offset = 0;
        let mut take_v = |n: u32| {
            let d = offset;
            offset += n;
            d
        };
        let light_select = effects.nee.then(|| take_v(1));
        let light_point = effects.nee.then(|| take_v(2));
        let direction = take_v(2);
        let lobe = effects.lobe.then(|| take_v(1));
        let roulette = effects.roulette.then(|| take_v(1));
        Self {
            pixel,
            lens,
            time,
            first_vertex,
            per_vertex: offset,
            light_select,
            light_point,
            direction,
            lobe,
            roulette,
        }
    }

    /// First dimension of the block of path vertex `depth` (0 = first hit).
    pub fn vertex(&self, depth: u32) -> u32 {
        self.first_vertex + depth * self.per_vertex
    }

    /// Total dimensions a path of `max_depth` vertices can consume.
    pub fn total(&self, max_depth: u32) -> u32 {
        self.vertex(max_depth)
    }
}
