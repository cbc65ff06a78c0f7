//! Where a value of a scene description was written: [`Spanned`] values whose span is a byte
//! range of the description's [`Sources`], the files it was read from one after another, so that
//! one number says which file, line and column a value came from, whichever reader made it.

use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::ops::Range;
use std::path::{Path, PathBuf};
use stratapt_scene::error::SourceLocation;

/// A value and the byte range of [`Sources`] it was read from.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Spanned<T> {
    span: Range<usize>,
    value: T,
}

impl<T> Spanned<T> {
    pub fn new(span: Range<usize>, value: T) -> Self {
        Self { span, value }
    }

    /// Where the value is: a byte range of the description's [`Sources`].
    pub fn span(&self) -> Range<usize> {
        self.span.clone()
    }

    pub fn get_ref(&self) -> &T {
        &self.value
    }

    pub fn get_mut(&mut self) -> &mut T {
        &mut self.value
    }

    pub fn into_inner(self) -> T {
        self.value
    }
}

/// Read from TOML with the span the TOML reader gives (an offset into the one file).
impl<'de, T: Deserialize<'de>> Deserialize<'de> for Spanned<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let s = toml::Spanned::<T>::deserialize(deserializer)?;
        Ok(Self::new(s.span(), s.into_inner()))
    }
}

/// Written as the value alone (a location is not part of the scene).
impl<T: Serialize> Serialize for Spanned<T> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.value.serialize(serializer)
    }
}

/// One file a description was read from, and its text (to turn offsets into lines).
#[derive(Clone, Debug)]
pub struct Source {
    pub path: PathBuf,
    pub text: String,
}

/// The files a description was read from, in reading order (the scene file first), laid one
/// after another in one byte space: file `i` starts where file `i − 1` ends, plus one.
#[derive(Clone, Debug, Default)]
pub struct Sources {
    files: Vec<Source>,
    /// Where each file starts in the joint byte space.
    starts: Vec<usize>,
}

impl Sources {
    /// The sources of one file.
    pub fn one(path: impl Into<PathBuf>, text: impl Into<String>) -> Self {
        let mut s = Self::default();
        s.push(path.into(), text.into());
        s
    }

    /// Add a file; its index.
    pub fn push(&mut self, path: PathBuf, text: String) -> usize {
        let start = match (self.files.last(), self.starts.last()) {
            (Some(f), Some(&s)) => s + f.text.len() + 1,
            _ => 0,
        };
        self.files.push(Source { path, text });
        self.starts.push(start);
        self.files.len() - 1
    }

    /// The files, in reading order.
    pub fn files(&self) -> &[Source] {
        &self.files
    }

    /// The scene file (the first one read); an empty path when there is none.
    pub fn main(&self) -> &Path {
        self.files.first().map_or(Path::new(""), |f| &f.path)
    }

    /// The joint span of byte offset `at` in file `file` (empty: where a value begins).
    pub fn span(&self, file: usize, at: usize) -> Range<usize> {
        let start = self.starts[file] + at;
        start..start
    }

    /// File, line and column of the joint byte offset `offset`.
    pub fn location(&self, offset: usize) -> SourceLocation {
        let i = self
            .starts
            .partition_point(|&s| s <= offset)
            .saturating_sub(1);
        match self.files.get(i) {
            Some(f) => SourceLocation::at_offset(&f.path, &f.text, offset - self.starts[i]),
            None => SourceLocation::file(""),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_name_the_file_line_and_column_they_fall_in() {
        let mut s = Sources::one("a.pbrt", "ab\ncd");
        let b = s.push("b.pbrt".into(), "x\n\nyz".into());
        assert_eq!(s.location(4).to_string(), "a.pbrt:2:2");
        let at = s.span(b, 4).start;
        assert_eq!(s.location(at).to_string(), "b.pbrt:3:2");
        assert_eq!(s.location(s.span(b, 0).start).to_string(), "b.pbrt:1:1");
        assert_eq!(s.main(), Path::new("a.pbrt"));
    }
}
