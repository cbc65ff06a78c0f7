//! What `strata bench`'s flags choose to time: the renderers, and on the GPU the kernels, BVH
//! layouts and scene bindings, each expanded into the list a scene is timed with.

use clap::ValueEnum;
use stratapt_gpu::{BvhLayout, Kernel, Renderer, Runtime, SceneBinding, Specialization, Traversal};

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(super) enum KernelsChoice {
    /// The kernel compiled for each scene.
    Specialized,
    /// The one kernel with every effect, chosen at run time.
    Generic,
    /// Specialized, then generic, a row each.
    Both,
    /// Specialized, each unused effect carried alone, generic.
    Effects,
}

impl KernelsChoice {
    /// The kernels to time on a scene whose specialization is `spec`.
    pub(super) fn kernels(self, spec: &Specialization) -> Vec<Kernel> {
        match self {
            KernelsChoice::Specialized => vec![Kernel::Specialized],
            KernelsChoice::Generic => vec![Kernel::Generic],
            KernelsChoice::Both => vec![Kernel::Specialized, Kernel::Generic],
            KernelsChoice::Effects => {
                // Each effect, light kind and material kind the scene does not use, alone.
                let unused = |all: u32, used: u32| {
                    (0..32)
                        .map(|k| 1u32 << k)
                        .filter(move |bit| all & bit != 0 && used & bit == 0)
                };
                let (all, none) = (Runtime::ALL, Runtime::NONE);
                let e = &spec.effects;
                let carried = unused(all.effects, spec.effect_bits())
                    .map(|effects| Runtime { effects, ..none })
                    .chain(
                        unused(all.light_kinds, e.light_kinds).map(|light_kinds| Runtime {
                            light_kinds,
                            ..none
                        }),
                    )
                    .chain(
                        unused(all.material_kinds, e.material_kinds).map(|material_kinds| {
                            Runtime {
                                material_kinds,
                                ..none
                            }
                        }),
                    )
                    .chain([Runtime { dims: true, ..none }]);
                std::iter::once(Kernel::Specialized)
                    .chain(carried.map(Kernel::Carrying))
                    .chain([Kernel::Generic])
                    .collect()
            }
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(super) enum BvhChoice {
    /// The layout the renderer picks for the adapter.
    Auto,
    /// The binary BVH (obvhs BVH2).
    Bvh2,
    /// The compressed 8-wide BVH.
    Cwbvh,
    /// Each layout in turn, a row each.
    Both,
}

impl BvhChoice {
    /// The layouts to time on `renderer` (none without a GPU).
    pub(super) fn layouts(self, renderer: Option<&Renderer>) -> Vec<BvhLayout> {
        match (self, renderer) {
            (_, None) => Vec::new(),
            (BvhChoice::Auto, Some(renderer)) => vec![renderer.bvh_layout()],
            (BvhChoice::Bvh2, _) => vec![BvhLayout::Bvh2],
            (BvhChoice::Cwbvh, _) => vec![BvhLayout::Cwbvh],
            (BvhChoice::Both, _) => BvhLayout::ALL.to_vec(),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(super) enum TraversalChoice {
    /// The traversal the renderer picks for the adapter.
    Auto,
    /// The kernel's own BVH traversal.
    Bvh,
    /// The adapter's ray queries (scenes of static triangles, devices that have them).
    RayQuery,
    /// The BVH, then ray queries, rows each.
    Both,
}

impl TraversalChoice {
    /// The traversals to time on `renderer` (none without a GPU).
    pub(super) fn traversals(self, renderer: Option<&Renderer>) -> Vec<Traversal> {
        match (self, renderer) {
            (_, None) => Vec::new(),
            (TraversalChoice::Auto, Some(renderer)) => vec![renderer.traversal()],
            (TraversalChoice::Bvh, _) => vec![Traversal::Bvh],
            (TraversalChoice::RayQuery, _) => vec![Traversal::RayQuery],
            (TraversalChoice::Both, _) => vec![Traversal::Bvh, Traversal::RayQuery],
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(super) enum BindingChoice {
    /// The binding the renderer picks for the adapter.
    Auto,
    /// The storage buffers.
    Storage,
    /// The uniform copy, where the scene fits it.
    Uniform,
    /// Storage, then uniform, a row each.
    Both,
}

impl BindingChoice {
    /// The bindings to time on `renderer`, each with its label in the rows (none without a
    /// GPU).
    pub(super) fn bindings(self, renderer: Option<&Renderer>) -> Vec<(SceneBinding, &'static str)> {
        match (self, renderer) {
            (_, None) => Vec::new(),
            (BindingChoice::Auto, Some(renderer)) => vec![(renderer.scene_binding(), "")],
            (BindingChoice::Storage, _) => vec![(SceneBinding::Storage, "/storage")],
            (BindingChoice::Uniform, _) => vec![(SceneBinding::Uniform, "/uniform")],
            (BindingChoice::Both, _) => vec![
                (SceneBinding::Storage, "/storage"),
                (SceneBinding::Uniform, "/uniform"),
            ],
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(super) enum Renderers {
    /// The GPU renderer and the CPU reference.
    Both,
    /// The GPU renderer only.
    Gpu,
    /// The CPU reference only.
    Cpu,
    /// The CPU reference, then the eight-lane CPU prototype on the scenes it covers, with its
    /// speed against the reference.
    Cpu8,
}
