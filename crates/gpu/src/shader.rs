//! The WGSL kernels: the modules of `shaders/`, composed into one source and validated by naga.
//!
//! WGSL has no imports, so the host concatenates the modules (`scene.wgsl`, the structs and
//! bindings every module uses, first). Each module prefixes its names with its stem.

use crate::GpuError;

/// Every module of `shaders/`, by stem, in composition order.
pub const MODULES: &[(&str, &str)] = &[
    ("scene", include_str!("../../../shaders/scene.wgsl")),
    ("sampler", include_str!("../../../shaders/sampler.wgsl")),
    ("filter", include_str!("../../../shaders/filter.wgsl")),
    ("frame", include_str!("../../../shaders/frame.wgsl")),
    ("warp", include_str!("../../../shaders/warp.wgsl")),
    ("mis", include_str!("../../../shaders/mis.wgsl")),
    ("twin", include_str!("../../../shaders/twin.wgsl")),
    ("camera", include_str!("../../../shaders/camera.wgsl")),
    ("motion", include_str!("../../../shaders/motion.wgsl")),
    ("offset", include_str!("../../../shaders/offset.wgsl")),
    ("intersect", include_str!("../../../shaders/intersect.wgsl")),
    ("bvh", include_str!("../../../shaders/bvh.wgsl")),
    ("cwbvh", include_str!("../../../shaders/cwbvh.wgsl")),
    ("bsdf", include_str!("../../../shaders/bsdf.wgsl")),
    ("light", include_str!("../../../shaders/light.wgsl")),
    (
        "integrator",
        include_str!("../../../shaders/integrator.wgsl"),
    ),
];

/// The modules the path-tracing kernel is built from (all of them).
pub fn kernel_modules() -> Vec<&'static str> {
    MODULES.iter().map(|(stem, _)| *stem).collect()
}

/// `scene.wgsl`, then the named modules in [`MODULES`] order, then `extra`, validated by naga.
pub fn compose(modules: &[&str], extra: &str) -> Result<String, GpuError> {
    if let Some(unknown) = modules
        .iter()
        .find(|m| !MODULES.iter().any(|(stem, _)| stem == *m))
    {
        return Err(GpuError::Shader(format!(
            "no shader module `{unknown}` in shaders/"
        )));
    }
    let mut source = String::new();
    for (stem, text) in MODULES {
        if *stem == "scene" || modules.contains(stem) {
            source.push_str(&format!("// ==== shaders/{stem}.wgsl ====\n"));
            source.push_str(text);
            source.push('\n');
        }
    }
    source.push_str(extra);
    validate(&source)?;
    Ok(source)
}

/// Parse and validate a WGSL source with naga; the error names the module and line.
pub fn validate(source: &str) -> Result<naga::Module, GpuError> {
    let module = naga::front::wgsl::parse_str(source)
        .map_err(|e| GpuError::Shader(locate(source, &e.emit_to_string(source))))?;
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| GpuError::Shader(locate(source, &e.emit_to_string(source))))?;
    Ok(module)
}

/// Append to a naga message which module of `shaders/` each `wgsl:LINE` it cites falls in.
fn locate(source: &str, message: &str) -> String {
    let starts: Vec<(usize, &str)> = source
        .lines()
        .enumerate()
        .filter_map(|(i, l)| {
            l.strip_prefix("// ==== ")
                .and_then(|r| r.strip_suffix(" ===="))
                .map(|name| (i + 1, name))
        })
        .collect();
    let mut out = message.to_string();
    for cited in message
        .split("wgsl:")
        .skip(1)
        .filter_map(|r| r.split(':').next()?.parse::<usize>().ok())
    {
        if let Some((start, name)) = starts.iter().rev().find(|(s, _)| *s < cited) {
            out.push_str(&format!("\n(line {cited} is {name}:{})", cited - start));
        }
    }
    out
}
