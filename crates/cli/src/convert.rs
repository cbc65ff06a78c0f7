//! `strata convert`: a scene written in another format, by the output's extension.
//!
//! - `.toml`: a pbrt-v4 scene as strata's own, to read and edit: the scene's description
//!   serialized as a TOML file, and its meshes as binary PLY files in `NAME-meshes/` beside it.
//!   Rendering the converted scene gives the imported scene's image bit for bit (the file reads
//!   back into the description `strata render scene.pbrt` validates, and the meshes as the same
//!   floats).
//! - `.xml`: any scene strata reads, as a Mitsuba 3 scene of what strata renders
//!   ([`stratapt_import::export::mitsuba`]): the XML file, and its PLY meshes and PFM images in
//!   `NAME-mitsuba/` beside it. What Mitsuba cannot express is a warning.
//!
//! Nothing is written unless the whole scene converts and loads: the folder's files go to a
//! temporary folder renamed into place (an earlier conversion's set aside until the end, and put
//! back if anything fails), then the scene file is written to a temporary sibling and renamed.

use crate::scene::{check_strict, show_warnings, warning_lines, ImportArgs};
use anyhow::Context;
use clap::Args;
use std::path::{Path, PathBuf};
use stratapt_import::pbrt;

#[derive(Args)]
pub struct ConvertArgs {
    /// Scene file: a pbrt-v4 scene (.pbrt, .pbrt.gz) for a .toml output; any scene strata
    /// reads for a .xml output.
    scene: PathBuf,
    /// File to write: strata's TOML (.toml; its meshes go to NAME-meshes/ beside it) or
    /// Mitsuba 3's XML (.xml; its meshes and images go to NAME-mitsuba/ beside it).
    #[arg(short, long)]
    output: PathBuf,
    #[command(flatten)]
    import: ImportArgs,
}

pub fn run(args: ConvertArgs) -> anyhow::Result<()> {
    match args.output.extension().and_then(|e| e.to_str()) {
        Some("toml") => to_toml(args),
        Some("xml") => to_mitsuba(args),
        _ => anyhow::bail!(
            "{}: the output is a .toml file (strata's format) or a .xml file (Mitsuba 3's)",
            args.output.display()
        ),
    }
}

/// The folder the output file is written in.
fn output_dir(output: &Path) -> PathBuf {
    match output.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// A pbrt-v4 scene as strata's TOML and PLY meshes.
fn to_toml(args: ConvertArgs) -> anyhow::Result<()> {
    if !pbrt::is_pbrt(&args.scene) {
        anyhow::bail!(
            "{}: a .toml output is converted from a pbrt-v4 scene (.pbrt, .pbrt.gz)",
            args.scene.display()
        );
    }
    let dir = output_dir(&args.output);
    let mesh_dir = pbrt::mesh_dir(&args.output);
    let started = std::time::Instant::now();
    let imported = pbrt::import::import(&args.scene, &mesh_dir)?;
    let report = imported.import.clone().unwrap_or_default();
    let lines = warning_lines(Some(&report));
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
    let final_dir = dir.join(&mesh_dir);
    place(&args.output, &final_dir, toml.as_bytes(), |tmp| {
        imported.meshes.iter().try_for_each(|(name, mesh)| {
            let file = name.strip_prefix(&format!("{mesh_dir}/")).unwrap_or(name);
            let path = tmp.join(file);
            stratapt_import::load::write_ply(&path, mesh)
                .with_context(|| format!("cannot write {}", path.display()))
        })
    })?;
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

/// Any scene as Mitsuba 3's XML, with its meshes and images.
fn to_mitsuba(args: ConvertArgs) -> anyhow::Result<()> {
    let started = std::time::Instant::now();
    let scene = stratapt_import::load(&args.scene)?;
    let lines = warning_lines(scene.import.as_ref());
    check_strict(&args.scene, &lines, args.import)?;
    show_warnings(&lines);
    let stem = args
        .output
        .file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    let folder = format!("{stem}-mitsuba");
    let export = stratapt_import::export::mitsuba::export(&scene, &folder);
    for w in &export.warnings {
        eprintln!("warning: Mitsuba: {w}");
    }
    let dir = output_dir(&args.output);
    place(
        &args.output,
        &dir.join(&folder),
        export.xml.as_bytes(),
        |tmp| {
            export.files.iter().try_for_each(|(name, bytes)| {
                let file = name.strip_prefix(&format!("{folder}/")).unwrap_or(name);
                let path = tmp.join(file);
                std::fs::write(&path, bytes)
                    .with_context(|| format!("cannot write {}", path.display()))
            })
        },
    )?;
    println!(
        "wrote {} ({} files in {}/) in {:.2} s; {} things Mitsuba draws differently",
        args.output.display(),
        export.files.len(),
        dir.join(&folder).display(),
        started.elapsed().as_secs_f64(),
        export.warnings.len()
    );
    Ok(())
}

/// Writes folder `final_dir` (its files by `fill`, into a temporary folder renamed into place)
/// and then `output` (through a temporary sibling). An earlier conversion's folder is set
/// aside, not deleted, until the new file is in place; if anything fails on the way it is put
/// back and nothing new remains.
fn place(
    output: &Path,
    final_dir: &Path,
    text: &[u8],
    fill: impl FnOnce(&Path) -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    let name = final_dir
        .file_name()
        .map_or("files".into(), |n| n.to_string_lossy().into_owned());
    let parent = final_dir.parent().unwrap_or(Path::new("."));
    let pid = std::process::id();
    let tmp = parent.join(format!(".{name}.tmp-{pid}"));
    let old = parent.join(format!(".{name}.old-{pid}"));
    let _ = std::fs::remove_dir_all(&tmp);
    std::fs::create_dir_all(&tmp).with_context(|| format!("{}", tmp.display()))?;
    if let Err(e) = fill(&tmp) {
        let _ = std::fs::remove_dir_all(&tmp);
        return Err(e);
    }
    let empty = std::fs::read_dir(&tmp).map_or(true, |mut d| d.next().is_none());
    let had_old = final_dir.exists();
    if had_old {
        // (A crashed run of a process with this id may have left its own.)
        let _ = std::fs::remove_dir_all(&old);
        if let Err(e) = std::fs::rename(final_dir, &old) {
            let _ = std::fs::remove_dir_all(&tmp);
            let e = anyhow::Error::from(e);
            return Err(e.context(format!("cannot move {} aside", final_dir.display())));
        }
    }
    let placed = match empty {
        true => std::fs::remove_dir(&tmp).map_err(anyhow::Error::from),
        false => std::fs::rename(&tmp, final_dir)
            .with_context(|| format!("cannot rename into {}", final_dir.display())),
    }
    .and_then(|()| crate::study::write_atomically(output, text));
    if let Err(e) = placed {
        let _ = std::fs::remove_dir_all(&tmp);
        if had_old {
            let _ = std::fs::remove_dir_all(final_dir);
            let _ = std::fs::rename(&old, final_dir);
        }
        return Err(e);
    }
    if had_old {
        let _ = std::fs::remove_dir_all(&old);
    }
    Ok(())
}
