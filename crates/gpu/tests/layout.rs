//! Every struct the host uploads has, in the kernel, the member offsets and size of its Rust
//! `#[repr(C)]` mirror: naga's layout of `shaders/scene.wgsl` against `offset_of!` and
//! `size_of`. A member added on one side only, reordered or resized fails here rather than as
//! garbage on a device. No device needed.

use std::mem::{offset_of, size_of};
use stratapt_gpu::cwbvh::CwbvhNode;
use stratapt_gpu::testing::{
    binding, compose_modules, kernel_modules, validate, KernelParams, Params, UniformSceneOffsets,
};
use stratapt_gpu::Specialization;
use stratapt_scene::records::{AliasEntry, BvhNode, Camera, Light, Material, Motion};
use stratapt_scene::records::{Pose, Surface, Texture};

/// `(member, offset)` of every member of WGSL struct `name` not named `_pad*`, and its size.
fn wgsl(module: &naga::Module, name: &str) -> (Vec<(String, u32)>, u32) {
    let (_, ty) = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("no WGSL struct {name}"));
    let naga::TypeInner::Struct { members, span } = &ty.inner else {
        panic!("{name} is not a struct");
    };
    let named = members
        .iter()
        .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
        .filter(|(n, _)| !n.starts_with("_pad"))
        .collect();
    (named, *span)
}

/// Compare WGSL struct `$wgsl` with Rust type `$rust`: `$member => $field` pairs name every
/// non-pad WGSL member and the Rust field it mirrors (`$member` alone: the same name).
macro_rules! same_layout {
    ($module:expr, $wgsl:literal, $rust:ty, [$($member:ident $(=> $field:ident)?),* $(,)?]) => {{
        let (members, size) = wgsl($module, $wgsl);
        let rust: Vec<(String, u32)> = vec![
            $((stringify!($member).to_string(), same_layout!(@offset $rust, $member $($field)?))),*
        ];
        assert_eq!(members, rust, "{}: WGSL member offsets vs {}", $wgsl, stringify!($rust));
        assert_eq!(size as usize, size_of::<$rust>(), "{}: size", $wgsl);
    }};
    (@offset $rust:ty, $member:ident $field:ident) => { offset_of!($rust, $field) as u32 };
    (@offset $rust:ty, $member:ident) => { offset_of!($rust, $member) as u32 };
}

#[test]
fn wgsl_structs_match_their_rust_mirrors() {
    let source = compose_modules(&kernel_modules(), "").unwrap_or_else(|e| panic!("{e}"));
    let module = validate(&source).unwrap_or_else(|e| panic!("{e}"));
    let m = &module;
    same_layout!(
        m,
        "Surface",
        Surface,
        [kind, material, light, motion, flags, alpha]
    );
    same_layout!(
        m,
        "Texture",
        Texture,
        [tag, texels, width, height, uv_u, decode, uv_v, value, other]
    );
    same_layout!(
        m,
        "Material",
        Material,
        [color, tag, emission, ior, eta, alpha_u, k, alpha_v]
    );
    same_layout!(
        m,
        "Light",
        Light,
        [
            p0,
            kind,
            p1,
            motion,
            p2,
            select_pdf,
            radiance,
            unhittable_select_pdf,
            flags
        ]
    );
    same_layout!(m, "AliasEntry", AliasEntry, [threshold, alias_index => alias, pdf]);
    same_layout!(m, "Pose", Pose, [translation, rotation, scale]);
    same_layout!(m, "Motion", Motion, [open, close]);
    same_layout!(m, "BvhNode", BvhNode, [min, prim_count, max, first_index]);
    same_layout!(
        m,
        "CwbvhNode",
        CwbvhNode,
        [
            p,
            e_imask => e,
            child_base,
            prim_base,
            child_meta,
            child_min_x,
            child_max_x,
            child_min_y,
            child_max_y,
            child_min_z,
            child_max_z,
        ]
    );
    same_layout!(
        m,
        "Camera",
        Camera,
        [
            eye0,
            tan_half_fov,
            target0,
            lens_radius,
            up0,
            focus_distance,
            eye1,
            shutter_open,
            target1,
            shutter_close,
            up1,
            filter_kind => filter,
            width,
            height,
            filter_param,
        ]
    );
    same_layout!(
        m,
        "Params",
        Params,
        [
            camera,
            sampler,
            spp,
            seed,
            strategy,
            sample_base,
            batch_spp,
            max_depth,
            light_count,
            env_first,
            light_table_len,
            unhittable_table_len,
            node_count,
            tile_origin,
            tile_size,
            film_rows,
            twin_block,
            twin_blocks_x,
            twin_count,
            twin_key,
            uv_base,
            split,
            kernel,
            uniform_scene,
        ]
    );
    same_layout!(
        m,
        "UniformSceneOffsets",
        UniformSceneOffsets,
        [
            points,
            normals,
            surfaces,
            materials,
            lights,
            light_table,
            unhittable_table,
            motions,
            nodes,
        ]
    );
    same_layout!(
        m,
        "KernelParams",
        KernelParams,
        [
            effects,
            light_kinds,
            material_kinds,
            dim_pixel,
            dim_lens,
            dim_time,
            dim_first_vertex,
            dim_per_vertex,
            dim_light_select,
            dim_light_point,
            dim_direction,
            dim_lobe,
            dim_roulette,
        ]
    );
}

/// The check is not vacuous: a WGSL struct with one member moved is caught.
#[test]
#[should_panic(expected = "WGSL member offsets")]
fn a_moved_member_is_caught() {
    let source = compose_modules(&kernel_modules(), "").unwrap().replace(
        "    kind: u32,\n    material: u32,\n    light: u32,",
        "    kind: u32,\n    light: u32,\n    material: u32,",
    );
    assert!(source.contains("    light: u32,\n    material: u32,"));
    let module = validate(&source).unwrap_or_else(|e| panic!("{e}"));
    same_layout!(
        &module,
        "Surface",
        Surface,
        [kind, material, light, motion, flags, alpha]
    );
}

/// `(name, binding)` of every resource the kernel `source` declares, sorted; all in group 0.
fn wgsl_bindings(source: &str) -> Vec<(String, u32)> {
    let module = validate(source).unwrap_or_else(|e| panic!("{e}"));
    let mut out: Vec<(String, u32)> = module
        .global_variables
        .iter()
        .filter_map(|(_, g)| {
            let b = g.binding.as_ref()?;
            assert_eq!(b.group, 0, "{:?}", g.name);
            Some((g.name.clone().unwrap_or_default(), b.binding))
        })
        .collect();
    out.sort();
    out
}

/// The host's bindings by name (`binding::all`), sorted.
fn host_bindings() -> Vec<(String, u32)> {
    let mut out: Vec<(String, u32)> = binding::all()
        .into_iter()
        .map(|(name, b)| (name.to_string(), b))
        .collect();
    out.sort();
    out
}

/// The host binds every buffer at the number the kernel declares it under, matched by name: an
/// array moved or added on one side only fails here.
#[test]
fn bindings_match_by_name() {
    let source = compose_modules(&kernel_modules(), "").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(wgsl_bindings(&source), host_bindings());
    // Not vacuous: two arrays swapped in the kernel are caught.
    let swapped = source
        .replace(
            "@binding(3) var<storage, read> surfaces",
            "@binding(99) var<storage, read> surfaces",
        )
        .replace(
            "@binding(4) var<storage, read> points",
            "@binding(3) var<storage, read> points",
        )
        .replace(
            "@binding(99) var<storage, read> surfaces",
            "@binding(4) var<storage, read> surfaces",
        );
    assert_ne!(swapped, source);
    assert_ne!(wgsl_bindings(&swapped), host_bindings());
}

/// `(name, default)` of every `override` constant of the kernel `source`, sorted; a bool as 0/1.
fn override_defaults(source: &str) -> Vec<(String, f64)> {
    let module = validate(source).unwrap_or_else(|e| panic!("{e}"));
    let mut out: Vec<(String, f64)> = module
        .overrides
        .iter()
        .map(|(_, o)| {
            let name = o.name.clone().unwrap_or_default();
            let init = o.init.unwrap_or_else(|| panic!("{name} has no default"));
            let value = match module.global_expressions[init] {
                naga::Expression::Literal(naga::Literal::Bool(b)) => b as u32 as f64,
                naga::Expression::Literal(naga::Literal::U32(u)) => u as f64,
                ref other => panic!("{name} defaults to {other:?}"),
            };
            (name, value)
        })
        .collect();
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

/// The host's override constants for [`Specialization::everything`], sorted.
fn everything() -> Vec<(String, f64)> {
    let mut out: Vec<(String, f64)> = Specialization::everything()
        .constants()
        .into_iter()
        .map(|(name, v)| (name.to_string(), v))
        .collect();
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

/// The kernel declares exactly the override constants the host sets, by name, and each
/// defaults to its value for a scene with every effect (what probes and tests composed without
/// a specialization get), so a default is never a second, stale definition.
#[test]
fn overrides_default_to_every_effect() {
    let source = compose_modules(&kernel_modules(), "").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(override_defaults(&source), everything());
    // Not vacuous: a stale default is caught.
    let stale = source.replace(
        "override DIM_PER_VERTEX: u32 = 7u;",
        "override DIM_PER_VERTEX: u32 = 8u;",
    );
    assert_ne!(stale, source);
    assert_ne!(override_defaults(&stale), everything());
}
