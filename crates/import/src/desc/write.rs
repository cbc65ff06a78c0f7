//! A scene description written as strata's TOML (`strata convert`): each table as the format
//! documents it (`docs/reference/scene-format.md`), numbers as the shortest text that reads back
//! the same `f64`, so that the file loads into the description it was written from, value for
//! value. File names are rewritten relative to the folder the file is written to; a mesh held in
//! memory keeps its name (the caller writes it there as a PLY file).

use super::Textured;
use super::{Description, Geometry, LightDesc, MaterialDesc, Numbers, ShapeDesc, TextureDesc};
use serde::Serialize;
use std::fmt::Write;
use std::path::{Component, Path, PathBuf};

/// `desc` as the text of a TOML file to be written in folder `out_dir`; the error is what
/// could not be written.
pub fn to_toml(desc: &Description, out_dir: &Path) -> Result<String, String> {
    let w = Writer { desc, out_dir };
    let mut out = format!(
        "# Written by strata from {}.\n",
        desc.sources.main().display()
    );
    let scene = &desc.scene;
    section(&mut out, "[camera]", None, table(scene.camera.get_ref())?);
    if let Some(film) = &scene.film {
        section(&mut out, "[film]", None, table(film.get_ref())?);
    }
    if let Some(render) = &scene.render {
        section(&mut out, "[render]", None, table(render.get_ref())?);
    }
    if let Some(sky) = &scene.sky {
        let mut sky = sky.get_ref().clone();
        if let Some(map) = &mut sky.map {
            *map.get_mut() = w.file(map.get_ref());
        }
        section(&mut out, "[sky]", None, table(&sky)?);
    }
    for (name, texture) in &desc.textures {
        let header = format!("[textures.{}]", quoted(name.get_ref()));
        let t = match texture {
            TextureDesc::Image(d) => {
                let mut d = d.clone();
                *d.file.get_mut() = w.file(d.file.get_ref());
                table(&d)?
            }
            TextureDesc::Checkerboard(d) => table(d)?,
        };
        section(&mut out, &header, Some(texture.type_name()), t);
    }
    for (name, material) in &desc.materials {
        let header = format!("[materials.{}]", quoted(name.get_ref()));
        let t = match material {
            MaterialDesc::Diffuse(d) => table(d)?,
            MaterialDesc::Conductor(d) => table(d)?,
            MaterialDesc::Dielectric(d) => table(d)?,
            MaterialDesc::Plastic(d) => table(d)?,
            MaterialDesc::Mix(d) => table(d)?,
            MaterialDesc::Coated(d) => table(d)?,
        };
        section(&mut out, &header, Some(material.type_name()), t);
    }
    for shape in &desc.shapes {
        section(
            &mut out,
            "[[shapes]]",
            Some(shape.geometry.type_name()),
            w.shape(shape)?,
        );
    }
    for light in &desc.lights {
        let t = match light.get_ref() {
            LightDesc::Point(d) => table(d)?,
            LightDesc::Line(d) => table(d)?,
            LightDesc::Distant(d) => table(d)?,
            LightDesc::Spot(d) => table(d)?,
        };
        section(&mut out, "[[lights]]", Some(light.get_ref().type_name()), t);
    }
    Ok(out)
}

struct Writer<'a> {
    desc: &'a Description,
    out_dir: &'a Path,
}

impl Writer<'_> {
    /// A file name of the description as the written file gives it.
    fn file(&self, name: &str) -> String {
        if self.desc.meshes.contains_key(name) || Path::new(name).is_absolute() {
            return name.to_string();
        }
        relative(&self.desc.base_dir.join(name), self.out_dir)
            .to_string_lossy()
            .replace('\\', "/")
    }

    /// One shape's keys: its geometry's, then the common ones.
    fn shape(&self, shape: &ShapeDesc) -> Result<toml::Table, String> {
        let mut t = match &shape.geometry {
            Geometry::Rectangle(d) => table(d)?,
            Geometry::Triangle(d) => table(d)?,
            Geometry::Quad(d) => table(d)?,
            Geometry::Disk(d) => table(d)?,
            Geometry::Sphere(d) => table(d)?,
            Geometry::Box(d) => table(d)?,
            Geometry::Mesh(d) => {
                let mut d = d.clone();
                *d.file.get_mut() = self.file(d.file.get_ref());
                table(&d)?
            }
        };
        let common = &shape.common;
        if let Some(m) = &common.material {
            t.insert("material".into(), m.get_ref().clone().into());
        }
        if let Some(two_sided) = &common.two_sided {
            t.insert("two_sided".into(), (*two_sided.get_ref()).into());
        }
        if let Some(alpha) = &common.alpha {
            let value = match alpha.get_ref() {
                Textured::Value(Numbers([a])) => (*a).into(),
                Textured::Texture(name) => name.clone().into(),
            };
            t.insert("alpha".into(), value);
        }
        for (key, transform) in [
            ("transform", &common.transform),
            ("transform_close", &common.transform_close),
        ] {
            if let Some(x) = transform {
                t.insert(key.into(), toml::Value::Table(table(x.get_ref())?));
            }
        }
        Ok(t)
    }
}

/// A value's keys.
fn table<T: Serialize>(value: &T) -> Result<toml::Table, String> {
    toml::Table::try_from(value).map_err(|e| e.to_string())
}

/// `name` as a TOML key (quoted).
fn quoted(name: &str) -> String {
    toml::Value::String(name.to_string()).to_string()
}

/// One table under `header`: its `type` first, then its keys, each value on one line.
fn section(out: &mut String, header: &str, kind: Option<&str>, t: toml::Table) {
    writeln!(out, "\n{header}").ok();
    if let Some(kind) = kind {
        writeln!(out, "type = {}", quoted(kind)).ok();
    }
    for (key, value) in t {
        writeln!(out, "{key} = {value}").ok();
    }
}

/// `path` relative to `base`, through `..` where `base` is not above it (absolute where they
/// share no root).
pub fn relative(path: &Path, base: &Path) -> PathBuf {
    // Absolute, with `.` and `..` resolved by the names alone (the output's folder may not
    // exist yet, so nothing is asked of the file system).
    let absolute = |p: &Path| {
        // An empty path (the folder of a file named without one) is the current folder.
        let p = if p.as_os_str().is_empty() {
            Path::new(".")
        } else {
            p
        };
        let p = std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
        let mut out = PathBuf::new();
        for c in p.components() {
            match c {
                Component::CurDir => {}
                Component::ParentDir => {
                    out.pop();
                }
                c => out.push(c),
            }
        }
        out
    };
    let (path, base) = (absolute(path), absolute(base));
    let (a, b): (Vec<_>, Vec<_>) = (path.components().collect(), base.components().collect());
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    if common == 0 {
        return path;
    }
    let mut out = PathBuf::new();
    for _ in common..b.len() {
        out.push("..");
    }
    for c in &a[common..] {
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_paths_resolve_dots_by_name() {
        let cwd = std::env::current_dir().unwrap();
        let cases = [
            ("scenes/tex/a.png", "out", "../scenes/tex/a.png"),
            ("scenes/tex/a.png", "x/../out", "../scenes/tex/a.png"),
            ("scenes/./tex/a.png", "scenes", "tex/a.png"),
            ("a.png", ".", "a.png"),
            ("a.png", "", "a.png"),
        ];
        for (path, base, expected) in cases {
            let got = relative(&cwd.join(path), Path::new(base));
            assert_eq!(got, PathBuf::from(expected), "{path} from {base}");
        }
    }
}
