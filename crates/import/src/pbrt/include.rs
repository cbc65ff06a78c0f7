//! A pbrt-v4 scene with its `Include`d and `Import`ed files spliced in where they are named, as
//! pbrt-v4 reads them: a relative path resolves against the directory of the scene file named
//! on the command line (pbrt's one search directory, whichever file names it), and a name ending
//! in `.gz` is decompressed. `Import` is read as `Include` (pbrt-v4 parses it on another thread
//! and lets it add only shapes, lights, materials and textures: the same scene). A file that
//! includes itself, directly or not, is refused at the directive that closes the cycle.

use super::parse::{parse, Arg, Directive};
use crate::desc::Sources;
use std::io::Read;
use std::ops::Range;
use std::path::{Path, PathBuf};
use stratapt_scene::error::{SceneError, SourceLocation};

/// The scene's directives in reading order, each with the index of its file in [`Sources`]
/// (which the scene's description keeps, so that its spans name these files); the `Include`
/// and `Import` directives themselves are replaced by what they read.
#[derive(Clone, Debug, Default)]
pub struct Parsed {
    pub sources: Sources,
    pub directives: Vec<(usize, Directive)>,
}

impl Parsed {
    /// One file's text, without reading what it includes (for tests and for text that is not in
    /// a file); `path` names it in errors.
    pub fn from_text(text: &str, path: &Path) -> Result<Self, SceneError> {
        Ok(Self {
            sources: Sources::one(path, text),
            directives: parse(text, path)?.into_iter().map(|d| (0, d)).collect(),
        })
    }

    /// Where byte offset `at` of source `source` is (file, line, column).
    pub fn location(&self, source: usize, at: usize) -> SourceLocation {
        self.sources.location(self.span(source, at).start)
    }

    /// The span of byte offset `at` of source `source` in the description's [`Sources`].
    pub fn span(&self, source: usize, at: usize) -> Range<usize> {
        self.sources.span(source, at)
    }

    /// The error `reason` at byte offset `at` of source `source`.
    pub fn err(&self, source: usize, at: usize, reason: impl Into<String>) -> SceneError {
        SceneError::new(self.location(source, at), reason)
    }

    /// The last directive named `name` (pbrt-v4 keeps the last `Film`, `Camera`, …), with the
    /// index of its source.
    pub fn last(&self, name: &str) -> Option<(usize, &Directive)> {
        self.directives
            .iter()
            .rfind(|(_, d)| d.name == name)
            .map(|(s, d)| (*s, d))
    }
}

/// The text of `path`, gunzipped when its name ends in `.gz`.
fn read(path: &Path) -> Result<String, String> {
    let bytes = std::fs::read(path).map_err(|e| e.to_string())?;
    let bytes = if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gz"))
    {
        let mut out = Vec::new();
        flate2::read::GzDecoder::new(&bytes[..])
            .read_to_end(&mut out)
            .map_err(|e| format!("not a gzip file: {e}"))?;
        out
    } else {
        bytes
    };
    String::from_utf8(bytes).map_err(|e| format!("not UTF-8 text: {e}"))
}

/// The scene file at `path` with everything it includes.
pub fn parse_scene(path: &Path) -> Result<Parsed, SceneError> {
    let text = read(path).map_err(|e| SceneError::new(SourceLocation::file(path), e))?;
    let base = path.parent().unwrap_or(Path::new("")).to_path_buf();
    let mut parsed = Parsed::default();
    splice(
        &mut parsed,
        path.to_path_buf(),
        text,
        &base,
        &mut Vec::new(),
    )?;
    Ok(parsed)
}

/// Parse `text` (of `path`) into `parsed`, reading its includes in place; `open` is the chain
/// of files being read (for cycles).
fn splice(
    parsed: &mut Parsed,
    path: PathBuf,
    text: String,
    base: &Path,
    open: &mut Vec<PathBuf>,
) -> Result<(), SceneError> {
    let directives = parse(&text, &path)?;
    let canonical = std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone());
    let source = parsed.sources.push(path, text);
    open.push(canonical);
    for d in directives {
        if d.name != "Include" && d.name != "Import" {
            parsed.directives.push((source, d));
            continue;
        }
        let Some(Arg::Str(name)) = d.args.first() else {
            unreachable!("the parser gives Include and Import one string");
        };
        let file = base.join(name);
        let canonical = std::fs::canonicalize(&file).unwrap_or_else(|_| file.clone());
        if open.contains(&canonical) {
            return Err(parsed.err(
                source,
                d.at,
                format!("{} `{name}` includes a file that is including it", d.name),
            ));
        }
        let text = read(&file).map_err(|e| {
            parsed.err(
                source,
                d.at,
                format!("{} `{name}` ({}): {e}", d.name, file.display()),
            )
        })?;
        splice(parsed, file, text, base, open)?;
    }
    open.pop();
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn gzip(text: &str) -> Vec<u8> {
        let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        e.write_all(text.as_bytes()).unwrap();
        e.finish().unwrap()
    }

    /// Includes are spliced in order, relative to the main file's directory even from a file in
    /// a subdirectory; `.gz` files are decompressed; every directive keeps its own file.
    #[test]
    fn includes_are_spliced_where_they_are_named() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::create_dir(d.join("geometry")).unwrap();
        std::fs::write(
            d.join("main.pbrt"),
            "WorldBegin\nInclude \"geometry/a.pbrt\"\nShape \"disk\"\nImport \"geometry/b.pbrt.gz\"\n",
        )
        .unwrap();
        // b.pbrt.gz is named relative to main.pbrt's directory, though a.pbrt names nothing.
        std::fs::write(
            d.join("geometry/a.pbrt"),
            "Shape \"sphere\"\nTranslate 1 2 3\n",
        )
        .unwrap();
        std::fs::write(
            d.join("geometry/b.pbrt.gz"),
            gzip("Shape \"trianglemesh\"\nInclude \"geometry/c.pbrt\"\n"),
        )
        .unwrap();
        std::fs::write(d.join("geometry/c.pbrt"), "AttributeBegin\n").unwrap();
        let p = parse_scene(&d.join("main.pbrt")).unwrap_or_else(|e| panic!("{e}"));
        let names: Vec<(&str, usize)> = p
            .directives
            .iter()
            .map(|(s, d)| (d.name.as_str(), *s))
            .collect();
        assert_eq!(
            names,
            vec![
                ("WorldBegin", 0),
                ("Shape", 1),
                ("Translate", 1),
                ("Shape", 0),
                ("Shape", 2),
                ("AttributeBegin", 3),
            ]
        );
        assert!(p.sources.files()[2].path.ends_with("geometry/b.pbrt.gz"));
        // An error in an included file names that file.
        let (s, d) = &p.directives[4];
        let e = p.err(*s, d.at, "here").to_string();
        assert!(e.contains("b.pbrt.gz:1:1: here"), "{e}");
    }

    #[test]
    fn missing_cyclic_and_broken_includes_are_refused_where_named() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let check = |main: &str, words: &[&str]| {
            std::fs::write(d.join("main.pbrt"), main).unwrap();
            let e = parse_scene(&d.join("main.pbrt")).unwrap_err().to_string();
            for w in words {
                assert!(e.contains(w), "`{w}` not in: {e}");
            }
        };
        check(
            "WorldBegin\n  Include \"nope.pbrt\"",
            &["main.pbrt:2:3:", "Include `nope.pbrt`", "nope.pbrt)"],
        );
        std::fs::write(d.join("loop.pbrt"), "Include \"main.pbrt\"\n").unwrap();
        check("Include \"loop.pbrt\"", &["loop.pbrt:1:1:", "including it"]);
        std::fs::write(d.join("bad.pbrt"), "Shape \"sphere\"\n\"float radius\" x\n").unwrap();
        check("Include \"bad.pbrt\"", &["bad.pbrt:2:16:", "takes numbers"]);
        std::fs::write(d.join("fake.pbrt.gz"), "Shape \"sphere\"").unwrap();
        check(
            "Import \"fake.pbrt.gz\"",
            &["main.pbrt:1:1:", "not a gzip file"],
        );
        let e = parse_scene(&d.join("absent.pbrt")).unwrap_err().to_string();
        assert!(e.contains("absent.pbrt"), "{e}");
    }
}
