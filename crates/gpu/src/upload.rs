//! Scene upload: the flattened scene's arrays as the storage buffers of group 0 in
//! `shaders/scene.wgsl`, checked against the device's limits first, and the uniform scene
//! when the kernel reads that ([`crate::specialize::SceneBinding`]).

use crate::cwbvh::Cwbvh;
use crate::params::UniformSceneOffsets;
use crate::shared::{
    binding, uniform_scene_words, MAX_BVH_DEPTH, MAX_UNIFORM_SCENE_WORDS, SURFACE_WORDS,
};
use crate::specialize::BvhLayout;
use crate::GpuError;
use stratapt_scene::environment::MAX_MAP_SIDE;
use stratapt_scene::records::{light_kind, texture_kind, BvhNode, Texture, TEXTURE_WORDS};
use stratapt_scene::FlatScene;
use wgpu::util::DeviceExt;

/// The scene's storage buffers with their bindings ([`binding::SCENE_ARRAYS`]), and the uniform
/// scene (zeros unless the kernel reads it).
pub struct SceneBuffers {
    buffers: Vec<(u32, wgpu::Buffer)>,
    uniform: wgpu::Buffer,
}

impl SceneBuffers {
    /// Upload `scene`, its BVH in layout `bvh`, and, with `uniform_scene`, the uniform scene
    /// of its arrays in the device's size ([`uniform_scene_fits`] must hold). An array larger
    /// than the device's storage-buffer binding limit is refused with its name and size (not
    /// left to a device error), and so is a BVH deeper than the traversal stack.
    pub fn new(
        device: &wgpu::Device,
        scene: &FlatScene,
        bvh: BvhLayout,
        uniform_scene: bool,
    ) -> Result<Self, GpuError> {
        let limit = device.limits().max_storage_buffer_binding_size;
        let words = uniform_scene_words(&device.limits());
        check_divisors(scene)?;
        let nodes = node_words(scene, bvh)?;
        let copy = match uniform_scene {
            true => uniform_words(scene, &nodes, words).ok_or_else(|| {
                GpuError::TooLarge(format!(
                    "its arrays with the {bvh} take more than the uniform scene's {}",
                    size(words as u64 * 16)
                ))
            })?,
            false => vec![[0; 4]; words as usize],
        };
        let vertex = vertex_words(scene);
        let buffers = arrays(scene, &nodes, &vertex, limit)
            .into_iter()
            .map(|(name, data)| {
                let buffer = storage(device, limit, binding::describe(name), data)?;
                Ok((binding::scene_array(name), buffer))
            })
            .collect::<Result<_, GpuError>>()?;
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("uniform scene"),
            contents: bytemuck::cast_slice(&copy),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        Ok(Self { buffers, uniform })
    }

    /// Bind-group entries of the scene's arrays and of the uniform scene.
    pub fn entries(&self) -> impl Iterator<Item = wgpu::BindGroupEntry<'_>> {
        self.buffers
            .iter()
            .map(|(b, buffer)| entry(*b, buffer))
            .chain([entry(binding::UNIFORM_SCENE, &self.uniform)])
    }
}

/// Whether a uniform scene of `words` words holds `scene`'s arrays and its BVH in layout `bvh`
/// (what [`crate::specialize::SceneBinding::Uniform`] reads them from).
pub fn uniform_scene_fits(scene: &FlatScene, bvh: BvhLayout, words: u32) -> bool {
    // Larger scenes are refused before their BVH is converted.
    UniformSceneOffsets::new(scene).nodes <= words
        && node_words(scene, bvh).is_ok_and(|nodes| uniform_words(scene, &nodes, words).is_some())
}

/// The uniform scene (`uniform_scene` in `shaders/scene.wgsl`): each of the scene's arrays from its
/// [`UniformSceneOffsets`] offset, word for word as in its storage buffer except that a point, a shading
/// normal and a surface start a word each; the BVH's `nodes` last; zeros after, to `size` words.
/// `None` when they do not fit.
fn uniform_words(scene: &FlatScene, nodes: &[[u32; 4]], size: u32) -> Option<Vec<[u32; 4]>> {
    use bytemuck::cast_slice as words;
    let layout = UniformSceneOffsets::new(scene);
    let size = size as usize;
    if layout.nodes as usize + nodes.len() > size {
        return None;
    }
    let g = &scene.geometry;
    let mut out = Vec::with_capacity(size);
    out.extend_from_slice(&g.prims);
    out.extend(g.points.iter().map(|p| p.map(f32::to_bits)));
    out.extend(g.normals.iter().map(|n| {
        let [x, y, z] = n.map(f32::to_bits);
        [x, y, z, 0]
    }));
    for surface in &g.surfaces {
        let [a, b, c, d, e, f]: [u32; 6] = bytemuck::cast(*surface);
        let padded: [[u32; 4]; SURFACE_WORDS] = [[a, b, c, d], [e, f, 0, 0]];
        out.extend(padded);
    }
    out.extend_from_slice(words(&scene.materials));
    out.extend_from_slice(words(&scene.lights));
    out.extend_from_slice(words(&scene.light_table));
    out.extend_from_slice(words(&scene.unhittable_table));
    out.extend_from_slice(words(&scene.motions));
    debug_assert_eq!(out.len(), layout.nodes as usize);
    out.extend_from_slice(nodes);
    out.resize(size, [0; 4]);
    Some(out)
}

/// The scene's arrays by the names the kernel binds them under ([`binding::SCENE_ARRAYS`]), with
/// the BVH's `nodes` and the `normals` binding's words (shading normals, then texture
/// coordinates: [`vertex_words`]). The primitives and the tables take two bindings each: as
/// many as one binding of `limit` bytes holds, and the rest.
fn arrays<'a>(
    scene: &'a FlatScene,
    nodes: &'a [[u32; 4]],
    vertex: &'a [f32],
    limit: u64,
) -> [(&'static str, &'a [u8]); binding::SCENE_ARRAYS.len()] {
    use bytemuck::cast_slice as bytes;
    let g = &scene.geometry;
    let (prims, more) = match prims_split(g.len(), limit) {
        0 => (&g.prims[..], &[][..]),
        split => g.prims.split_at(split as usize),
    };
    let (tables, tables_more) = match tables_split(scene.tables.len(), limit) {
        0 => (&scene.tables[..], &[][..]),
        split => scene.tables.split_at(split as usize),
    };
    [
        ("prims", bytes(prims)),
        ("prims_more", bytes(more)),
        ("surfaces", bytes(&g.surfaces)),
        ("points", bytes(&g.points)),
        ("normals", bytes(vertex)),
        ("materials", bytes(&scene.materials)),
        ("lights", bytes(&scene.lights)),
        ("light_table", bytes(&scene.light_table)),
        ("unhittable_table", bytes(&scene.unhittable_table)),
        ("motions", bytes(&scene.motions)),
        ("nodes", bytes(nodes)),
        ("tables", bytes(tables)),
        ("tables_more", bytes(tables_more)),
    ]
}

/// The `normals` binding's words: each point's shading normal (`xyz`) when some surface has
/// them, then each point's texture coordinates (`uv`, from
/// [`crate::params::uv_base`]) when some has them.
fn vertex_words(scene: &FlatScene) -> Vec<f32> {
    let g = &scene.geometry;
    let mut out = Vec::with_capacity(3 * g.normals.len() + 2 * g.uvs.len());
    out.extend(g.normals.iter().flatten());
    out.extend(g.uvs.iter().flatten());
    out
}

/// The first word of the tables that the second tables binding holds on a device that binds
/// `limit` bytes, or 0 when one binding holds them all (the kernel's `TABLES_SPLIT`).
pub fn tables_split(words: usize, limit: u64) -> u32 {
    let per_binding = limit / 4;
    match words as u64 <= per_binding {
        true => 0,
        false => per_binding.min(u32::MAX as u64) as u32,
    }
}

/// The first primitive of `prims` that the second primitives binding holds on a device that
/// binds `limit` bytes, or 0 when one binding holds them all (the kernel's `PRIMS_SPLIT`).
pub fn prims_split(prims: usize, limit: u64) -> u32 {
    let per_binding = limit / std::mem::size_of::<[u32; 4]>() as u64;
    match prims as u64 <= per_binding {
        true => 0,
        false => per_binding.min(u32::MAX as u64) as u32,
    }
}

/// Bytes of each buffer `SceneBuffers::new` uploads for `scene` with its BVH in layout `bvh`,
/// by name (an empty array still takes its binding's minimum; the uniform scene is bound, zeros,
/// even where the kernel does not read it, and counted at its largest,
/// [`MAX_UNIFORM_SCENE_WORDS`]); no device needed.
pub fn scene_bytes(
    scene: &FlatScene,
    bvh: BvhLayout,
) -> Result<Vec<(&'static str, u64)>, GpuError> {
    let nodes = node_words(scene, bvh)?;
    let vertex = vertex_words(scene);
    Ok(arrays(scene, &nodes, &vertex, u64::MAX)
        .into_iter()
        .map(|(name, data)| (binding::describe(name), data.len().max(EMPTY_BYTES) as u64))
        .chain([("uniform scene", MAX_UNIFORM_SCENE_WORDS as u64 * 16)])
        .collect())
}

/// A bind-group entry binding all of `buffer`.
pub fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}

/// The host's half of the kernel's audit (`docs/design/kernel-checks.md`): the kernel, compiled
/// without integer-division guards, divides by an environment map's sides and wraps texel
/// indices by an image texture's, so those must be in the range the loader gives them (2 to
/// 2²⁴ texels a side for a map, 1 to 2³⁰ − 1 for an image) in any scene, built by the loader or
/// by hand.
fn check_divisors(scene: &FlatScene) -> Result<(), GpuError> {
    let side = |s: f32| s.fract() == 0.0 && (2.0..=MAX_MAP_SIDE as f32).contains(&s);
    for (i, light) in scene.lights.iter().enumerate() {
        let [w, h, _] = light.p2;
        let map = light.kind == light_kind::ENVIRONMENT || light.kind == light_kind::OCTAHEDRAL;
        if map && !(side(w) && side(h)) {
            return Err(GpuError::Unsupported(format!(
                "light {i} is an environment map of {w}×{h} texels; the kernel takes 2 to \
                 {MAX_MAP_SIDE} a side"
            )));
        }
    }
    let words = TEXTURE_WORDS;
    for i in 0..scene.textures as usize {
        let record = scene
            .tables
            .get(i * words..(i + 1) * words)
            .ok_or_else(|| GpuError::Unsupported(format!("texture {i} is past the tables")))?;
        let texture: Texture = bytemuck::pod_read_unaligned(bytemuck::cast_slice(record));
        let image = texture.tag & 0xff == texture_kind::IMAGE;
        let fits = |n: u32| (1..=u32::MAX / 4).contains(&n);
        if image && !(fits(texture.width) && fits(texture.height)) {
            return Err(GpuError::Unsupported(format!(
                "texture {i} is an image of {}×{} texels; the kernel takes 1 to {} a side",
                texture.width,
                texture.height,
                u32::MAX / 4
            )));
        }
    }
    Ok(())
}

/// The `nodes` binding (`array<vec4u>`): the BVH2's nodes, or the CWBVH's nodes and primitive
/// slots. Refused when the traversal stack could overflow.
fn node_words(scene: &FlatScene, bvh: BvhLayout) -> Result<Vec<[u32; 4]>, GpuError> {
    // Both layouts come from the BVH2, which must be a tree for either traversal to end.
    let bvh2 = &scene.bvh.nodes;
    let bvh2_depth = bvh_depth(bvh2.len(), |i| (bvh2[i].prim_count, bvh2[i].first_index))
        .map_err(|e| GpuError::Unsupported(format!("its BVH cannot be traversed: {e}")))?;
    let (words, depth) = match bvh {
        BvhLayout::Bvh2 => {
            let nodes: Vec<BvhNode> = bvh2.iter().map(BvhNode::from_obvhs).collect();
            (bytemuck::cast_slice(&nodes).to_vec(), bvh2_depth)
        }
        BvhLayout::Cwbvh => {
            let cwbvh = Cwbvh::build(&scene.bvh);
            (bytemuck::cast_slice(&cwbvh.words()).to_vec(), cwbvh.depth)
        }
    };
    if depth > MAX_BVH_DEPTH {
        return Err(GpuError::TooLarge(format!(
            "its {bvh} is {depth} levels deep; the traversal stack holds {MAX_BVH_DEPTH}"
        )));
    }
    Ok(words)
}

/// Levels below the root of the deepest leaf (a lone root is depth 0). Fails unless the inner
/// nodes' children are nodes of the array and every node is reached once: the kernel's
/// traversal ends because it walks a tree (`docs/design/kernel-checks.md`), so a BVH that is
/// not one never reaches it. An empty BVH (a scene without geometry) is depth 0. `node(i)` is
/// node `i`'s primitive count (0 for an inner node) and first child or primitive.
fn bvh_depth(len: usize, node: impl Fn(usize) -> (u32, u32)) -> Result<usize, String> {
    if len == 0 {
        return Ok(0);
    }
    let mut deepest = 0;
    let mut reached = vec![false; len];
    let mut stack = vec![(0usize, 0usize)];
    while let Some((index, depth)) = stack.pop() {
        if index >= len {
            return Err(format!("a child index {index} is past its {len} nodes"));
        }
        if std::mem::replace(&mut reached[index], true) {
            return Err(format!("node {index} is reached twice (not a tree)"));
        }
        deepest = deepest.max(depth);
        let (prim_count, first_index) = node(index);
        if prim_count == 0 {
            let first = first_index as usize;
            stack.push((first, depth + 1));
            stack.push((first + 1, depth + 1));
        }
    }
    Ok(deepest)
}

/// `bytes` in MiB, or KiB below one MiB (a limit of 0 MiB says nothing).
fn size(bytes: u64) -> String {
    if bytes >= 1 << 20 {
        format!("{} MiB", bytes >> 20)
    } else {
        format!("{:.1} KiB", bytes as f64 / 1024.0)
    }
}

/// What an empty array is bound with: zeros as large as the largest element any array has
/// (bindings cannot be empty, and a binding must hold at least one element of its type; the
/// shaders never index an empty array).
const EMPTY_BYTES: usize = 96;

/// A read-only storage buffer holding `data` ([`EMPTY_BYTES`] of zeros when empty).
fn storage(
    device: &wgpu::Device,
    limit: u64,
    name: &str,
    data: &[u8],
) -> Result<wgpu::Buffer, GpuError> {
    let zero = [0u8; EMPTY_BYTES];
    let data = if data.is_empty() { &zero[..] } else { data };
    if data.len() as u64 > limit {
        return Err(GpuError::TooLarge(format!(
            "{name} take {}, more than this device's storage-buffer limit of {}",
            size(data.len() as u64),
            size(limit)
        )));
    }
    Ok(
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(name),
            contents: data,
            usage: wgpu::BufferUsages::STORAGE,
        }),
    )
}

/// Layout of group 0: the params uniform, the scene's read-only storage arrays, the
/// accumulator, the uniform scene.
pub fn bind_group_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty,
        count: None,
    };
    let storage = |read_only| wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Storage { read_only },
        has_dynamic_offset: false,
        min_binding_size: None,
    };
    let uniform = wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Uniform,
        has_dynamic_offset: false,
        min_binding_size: None,
    };
    let mut entries = vec![entry(binding::PARAMS, uniform)];
    entries.extend(
        binding::SCENE_ARRAYS
            .iter()
            .map(|(name, _)| entry(binding::scene_array(name), storage(true))),
    );
    entries.push(entry(binding::ACCUM, storage(false)));
    entries.push(entry(binding::UNIFORM_SCENE, uniform));
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("strata scene"),
        entries: &entries,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shared::MIN_UNIFORM_SCENE_WORDS;
    use std::path::Path;

    /// Every bundled scene fits the smallest uniform scene in either BVH layout (the docs and
    /// `SceneBinding::Uniform` say so); each array sits at its `UniformSceneOffsets` offset, the nodes
    /// last, zeros after.
    #[test]
    fn every_bundled_scene_fits_the_uniform_copy() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
        let mut checked = 0;
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_none_or(|e| e != "toml") {
                continue;
            }
            let scene = stratapt_import::scene_file::load(&path).unwrap_or_else(|e| panic!("{e}"));
            let layout = UniformSceneOffsets::new(&scene);
            for bvh in BvhLayout::ALL {
                let nodes = node_words(&scene, bvh).unwrap();
                let words = uniform_words(&scene, &nodes, MIN_UNIFORM_SCENE_WORDS)
                    .unwrap_or_else(|| panic!("{} ({bvh}) does not fit", path.display()));
                let used = layout.nodes as usize + nodes.len();
                println!("{} ({bvh}): {used} words", path.display());
                assert_eq!(words.len(), MIN_UNIFORM_SCENE_WORDS as usize);
                assert!(uniform_scene_fits(&scene, bvh, MIN_UNIFORM_SCENE_WORDS));
                let g = &scene.geometry;
                assert_eq!(&words[..g.prims.len()], &g.prims[..]);
                let point = |i: usize| words[layout.points as usize + i];
                assert_eq!(point(0), g.points[0].map(f32::to_bits));
                let at = layout.nodes as usize;
                assert_eq!(&words[at..at + nodes.len()], &nodes[..]);
                assert!(words[used..].iter().all(|w| *w == [0; 4]));
            }
            checked += 1;
        }
        assert!(checked >= 10, "{checked} scenes");
    }

    /// A scene whose environment map or image texture has a side the kernel cannot divide by
    /// is refused at upload, however it was built; the bundled scenes pass.
    #[test]
    fn a_zero_or_huge_divisor_is_refused_at_upload() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
        let load = |name: &str| {
            stratapt_import::scene_file::load(&dir.join(name)).unwrap_or_else(|e| panic!("{e}"))
        };
        let mut environment = load("environment.toml");
        assert!(check_divisors(&environment).is_ok());
        let map = environment
            .lights
            .iter()
            .position(|l| l.kind == light_kind::ENVIRONMENT)
            .expect("an environment map");
        environment.lights[map].p2[0] = 0.0;
        let e = check_divisors(&environment).unwrap_err().to_string();
        assert!(e.contains("environment map of 0×"), "{e}");
        environment.lights[map].p2[0] = (MAX_MAP_SIDE * 2) as f32;
        assert!(check_divisors(&environment).is_err());
        let mut textures = load("textures.toml");
        assert!(check_divisors(&textures).is_ok());
        let words = TEXTURE_WORDS;
        let image = (0..textures.textures as usize)
            .find(|&i| textures.tables[i * words].to_bits() & 0xff == texture_kind::IMAGE)
            .expect("an image texture");
        // The record's width, the third word, set to 0.
        textures.tables[image * words + 2] = f32::from_bits(0);
        let e = check_divisors(&textures).unwrap_err().to_string();
        assert!(
            e.contains(&format!("texture {image} is an image of 0×")),
            "{e}"
        );
    }

    /// A BVH2 the kernel's traversal could not end on (a child past the nodes, a node reached
    /// twice) is refused; a tree passes with its depth.
    #[test]
    fn a_bvh2_that_is_not_a_tree_is_refused() {
        // Nodes as (primitive count, first child or primitive).
        let depth = |nodes: &[(u32, u32)]| bvh_depth(nodes.len(), |i| nodes[i]);
        assert_eq!(depth(&[(0, 1), (1, 0), (1, 1)]), Ok(1));
        assert_eq!(depth(&[(2, 0)]), Ok(0));
        assert_eq!(depth(&[]), Ok(0));
        let past = depth(&[(0, 1), (1, 0)]).unwrap_err();
        assert!(past.contains("child index 2 is past its 2 nodes"), "{past}");
        // Node 1 is inner with children 0 and 1 again: a cycle back to the root.
        let cycle = depth(&[(0, 1), (0, 0), (1, 0)]).unwrap_err();
        assert!(cycle.contains("reached twice"), "{cycle}");
    }
}
