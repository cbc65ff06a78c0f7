//! `strata convert`: a pbrt-v4 scene written as strata's own, to read and edit: the scene's
//! description serialized as a TOML file, and its meshes as binary PLY files in `NAME-meshes/`
//! beside it. Rendering the converted scene gives the imported scene's image bit for bit (the
//! file reads back into the description `strata render scene.pbrt` validates, and the meshes as
//! the same floats).
//!
//! Nothing is written unless the whole scene converts and loads: the meshes go to a temporary
//! folder renamed into place (an earlier conversion's set aside until the end, and put back if
//! anything fails), then the TOML file is written to a temporary sibling and renamed.

use crate::scene::{check_strict, show_warnings, ImportArgs};
use anyhow::Context;
use clap::Args;
use std::path::PathBuf;
use stratapt_import::pbrt;

#[derive(Args)]
pub struct ConvertArgs {
    /// pbrt-v4 scene file (.pbrt or .pbrt.gz).
    scene: PathBuf,
    /// strata scene file to write (.toml); its meshes go to NAME-meshes/ beside it.
    #[arg(short, long)]
    output: PathBuf,
    #[command(flatten)]
    import: ImportArgs,
}

pub fn run(args: ConvertArgs) -> anyhow::Result<()> {
    if !pbrt::is_pbrt(&args.scene) {
        anyhow::bail!(
            "{}: convert reads pbrt-v4 scenes (.pbrt, .pbrt.gz)",
            args.scene.display()
        );
    }
    if args.output.extension().is_none_or(|e| e != "toml") {
        anyhow::bail!("{}: the output is a .toml file", args.output.display());
    }
    let dir = match args.output.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let mesh_dir = pbrt::mesh_dir(&args.output);
    let started = std::time::Instant::now();
    let imported = pbrt::import::import(&args.scene, &mesh_dir)?;
    let report = imported.import.clone().unwrap_or_default();
    let lines: Vec<String> = report
        .warnings
        .iter()
        .map(|w| format!("{}: {}", w.at, w.message))
        .collect();
    check_strict(&args.scene, &lines, args.import)?;
    show_warnings(&lines);
    // Validate what will be written, so that nothing is written for a scene that does not load
    // (errors name the pbrt file's lines).
    stratapt_import::load::build(imported.clone())?;
    let toml = stratapt_import::desc::write::to_toml(&imported, &dir)
        .map_err(|e| anyhow::anyhow!("{}: cannot be written as TOML: {e}", args.scene.display()))?;
    // And the text reads back (a writer's mistake is caught here, not in the user's next render).
    stratapt_import::load::parse(&toml, &args.output).map_err(|e| {
        anyhow::anyhow!(
            "{}: strata wrote TOML it cannot read back (a bug): {e}",
            args.scene.display()
        )
    })?;

    // The meshes: into a temporary folder, renamed over the old one.
    let final_dir = dir.join(&mesh_dir);
    let pid = std::process::id();
    let tmp = dir.join(format!(".{mesh_dir}.tmp-{pid}"));
    let old = dir.join(format!(".{mesh_dir}.old-{pid}"));
    if !imported.meshes.is_empty() {
        let _ = std::fs::remove_dir_all(&tmp);
        std::fs::create_dir_all(&tmp).with_context(|| format!("{}", tmp.display()))?;
        let written = imported.meshes.iter().try_for_each(|(name, mesh)| {
            let file = name.strip_prefix(&format!("{mesh_dir}/")).unwrap_or(name);
            let path = tmp.join(file);
            stratapt_import::load::write_ply(&path, mesh)
                .with_context(|| format!("cannot write {}", path.display()))
        });
        if let Err(e) = written {
            let _ = std::fs::remove_dir_all(&tmp);
            return Err(e);
        }
    }
    // An earlier conversion's meshes are set aside, not deleted, until the new TOML is in
    // place; if anything fails on the way they are put back.
    let had_old = final_dir.exists();
    if had_old {
        std::fs::rename(&final_dir, &old)
            .with_context(|| format!("cannot move {} aside", final_dir.display()))?;
    }
    let placed = match imported.meshes.is_empty() {
        true => Ok(()),
        false => std::fs::rename(&tmp, &final_dir)
            .with_context(|| format!("cannot rename into {}", final_dir.display())),
    }
    .and_then(|()| crate::study::write_atomically(&args.output, toml.as_bytes()));
    if let Err(e) = placed {
        let _ = std::fs::remove_dir_all(&tmp);
        if had_old {
            let _ = std::fs::remove_dir_all(&final_dir);
            let _ = std::fs::rename(&old, &final_dir);
        }
        return Err(e);
    }
    if had_old {
        let _ = std::fs::remove_dir_all(&old);
    }
    let r = &report;
    println!(
        "wrote {} ({} shapes, {} meshes with {} triangles in {}/) in {:.2} s; {} warnings",
        args.output.display(),
        r.shapes + r.instanced_shapes,
        imported.meshes.len(),
        r.triangles,
        final_dir.display(),
        started.elapsed().as_secs_f64(),
        lines.len()
    );
    Ok(())
}
