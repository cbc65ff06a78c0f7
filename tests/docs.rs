//! Links in the documentation resolve: every relative link in `README.md` and `docs/**/*.md`
//! names a file or folder that exists, and its `#anchor` (also one within the same file) is the
//! slug of a heading in the target, as GitHub makes them (lowercase; letters, digits, `-` and
//! `_` kept, spaces turned into `-`, everything else dropped; a repeated heading gets `-1`,
//! `-2`, …). Links to `http(s)://` and `mailto:` and anything inside code (fenced blocks and
//! inline code spans) are not checked.
//!
//! Std only, so it also runs on its own:
//! `CARGO_MANIFEST_DIR=$PWD rustc --edition 2021 --test tests/docs.rs -o /tmp/docs-test && /tmp/docs-test`.

use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};

#[path = "support/markdown.rs"]
mod markdown;
use markdown::documentation;

/// What a link's path names.
enum Target {
    Missing,
    Folder,
    File(String),
}

/// One link that does not resolve: where it is and why.
#[derive(Debug)]
struct Broken {
    file: PathBuf,
    line: usize,
    link: String,
    reason: String,
}

impl std::fmt::Display for Broken {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}:{}: ({}) {}",
            self.file.display(),
            self.line,
            self.link,
            self.reason
        )
    }
}

/// Lines outside fenced code blocks, numbered from 1.
fn prose_lines(text: &str) -> Vec<(usize, &str)> {
    let mut fence: Option<(char, usize)> = None;
    let mut lines = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let trimmed = line.trim_start();
        let marker = trimmed.chars().next().filter(|c| *c == '`' || *c == '~');
        let run = marker.map_or(0, |c| trimmed.chars().take_while(|x| *x == c).count());
        match (fence, marker) {
            (None, Some(c)) if run >= 3 => fence = Some((c, run)),
            (Some((c, n)), Some(m)) if m == c && run >= n && trimmed[run..].trim().is_empty() => {
                fence = None
            }
            (None, _) => lines.push((i + 1, line)),
            _ => {}
        }
    }
    lines
}

/// The line with inline code spans blanked out (a link inside backticks is not a link).
fn without_code_spans(line: &str) -> String {
    let mut out = String::with_capacity(line.len());
    let mut rest = line;
    while let Some(start) = rest.find('`') {
        let ticks = rest[start..].chars().take_while(|c| *c == '`').count();
        let delimiter = "`".repeat(ticks);
        match rest[start + ticks..].find(&delimiter) {
            Some(len) => {
                out.push_str(&rest[..start]);
                out.push_str(&" ".repeat(ticks * 2 + len));
                rest = &rest[start + ticks * 2 + len..];
            }
            None => break,
        }
    }
    out.push_str(rest);
    out
}

/// The targets of the inline links and images on one line: what stands between `](` and its
/// matching `)`, without a title.
fn link_targets(line: &str) -> Vec<String> {
    let line = without_code_spans(line);
    let mut targets = Vec::new();
    let mut rest = line.as_str();
    while let Some(at) = rest.find("](") {
        let after = &rest[at + 2..];
        let mut depth = 0usize;
        let mut end = None;
        for (i, c) in after.char_indices() {
            match c {
                '(' => depth += 1,
                ')' if depth == 0 => {
                    end = Some(i);
                    break;
                }
                ')' => depth -= 1,
                _ => {}
            }
        }
        let Some(end) = end else { break };
        let inside = after[..end].trim();
        let inside = inside
            .strip_prefix('<')
            .and_then(|s| s.strip_suffix('>'))
            .unwrap_or(inside);
        let target = inside.split_whitespace().next().unwrap_or("");
        targets.push(target.to_string());
        rest = &after[end..];
    }
    targets
}

/// GitHub's anchor for a heading's text.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || *c == '-' || *c == '_' || *c == ' ')
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The anchors of a markdown file's ATX headings, repeated slugs numbered as GitHub does.
fn anchors(text: &str) -> Vec<String> {
    let mut seen: HashMap<String, usize> = HashMap::new();
    let mut out = Vec::new();
    for (_, line) in prose_lines(text) {
        let hashes = line.chars().take_while(|c| *c == '#').count();
        if !(1..=6).contains(&hashes) || !line[hashes..].starts_with(' ') {
            continue;
        }
        let text = line[hashes..].trim().trim_end_matches('#').trim();
        let base = slug(text);
        let count = seen.entry(base.clone()).or_insert(0);
        out.push(match *count {
            0 => base,
            n => format!("{base}-{n}"),
        });
        *count += 1;
    }
    out
}

/// `base/relative` with `.` and `..` taken out, without touching the file system.
fn join(base: &Path, relative: &str) -> PathBuf {
    let mut out = PathBuf::new();
    for part in base.join(relative).components() {
        match part {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// Every broken relative link of one markdown file, whose text is `text`; `lookup` says what a
/// path names (the file system in the real test, a table in the self-test).
fn broken_links(file: &Path, text: &str, lookup: &dyn Fn(&Path) -> Target) -> Vec<Broken> {
    let mut broken = Vec::new();
    let folder = file.parent().unwrap_or(Path::new(""));
    for (number, line) in prose_lines(text) {
        for link in link_targets(line) {
            let lower = link.to_ascii_lowercase();
            if lower.starts_with("http://")
                || lower.starts_with("https://")
                || lower.starts_with("mailto:")
            {
                continue;
            }
            let mut report = |reason: String| {
                broken.push(Broken {
                    file: file.to_path_buf(),
                    line: number,
                    link: link.clone(),
                    reason,
                })
            };
            let (path, anchor) = match link.split_once('#') {
                Some((path, anchor)) => (path, Some(anchor)),
                None => (link.as_str(), None),
            };
            let target_text = if path.is_empty() {
                Some(text.to_string())
            } else {
                match lookup(&join(folder, path)) {
                    Target::Missing => {
                        report(format!("no such file: {}", join(folder, path).display()));
                        continue;
                    }
                    Target::Folder => None,
                    Target::File(content) => Some(content),
                }
            };
            let Some(anchor) = anchor else { continue };
            let markdown = path.is_empty() || path.to_ascii_lowercase().ends_with(".md");
            match target_text {
                Some(content) if markdown => {
                    if !anchors(&content).iter().any(|a| a == anchor) {
                        report(format!("no heading with the anchor #{anchor}"));
                    }
                }
                _ => report(format!("#{anchor} on a target that is not a markdown file")),
            }
        }
    }
    broken
}

#[test]
fn every_relative_link_in_the_documentation_resolves() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let lookup = |path: &Path| {
        let full = root.join(path);
        if full.is_dir() {
            Target::Folder
        } else if !full.is_file() {
            Target::Missing
        } else if full.extension().is_some_and(|e| e == "md") {
            Target::File(std::fs::read_to_string(&full).unwrap())
        } else {
            Target::File(String::new()) // an image or a patch: only its existence is checked
        }
    };
    let files = documentation(root);
    assert!(files.len() > 1, "found no markdown under docs/");
    let mut broken = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(root.join(file)).unwrap();
        broken.extend(broken_links(file, &text, &lookup));
    }
    let list: Vec<String> = broken.iter().map(|b| b.to_string()).collect();
    assert!(
        list.is_empty(),
        "{} broken links:\n{}",
        list.len(),
        list.join("\n")
    );
}

#[test]
fn the_checker_reports_a_missing_file_and_a_missing_anchor() {
    let files: HashMap<PathBuf, &str> = [
        (
            PathBuf::from("docs/guide/a.md"),
            "# A\n\n## Parts and merge\n",
        ),
        (
            PathBuf::from("docs/reference/b.md"),
            "# B: the `[camera]` table\n",
        ),
    ]
    .into_iter()
    .collect();
    let lookup = |path: &Path| match files.get(path) {
        Some(text) => Target::File(text.to_string()),
        None if path == Path::new("docs") => Target::Folder,
        None => Target::Missing,
    };
    let text = "\
# Index

A good link: [parts](guide/a.md#parts-and-merge), [B](./reference/b.md#b-the-camera-table),
[self](#index), [web](https://example.com/missing.md), [folder](../docs).
A missing file: [gone](guide/gone.md).
```sh
[not a link](inside/a/fence.md)
```
A missing anchor: [parts](guide/a.md#parts), and `[code](nowhere.md)`, and [here](#nowhere).
";
    let broken = broken_links(Path::new("docs/README.md"), text, &lookup);
    let found: Vec<(usize, &str)> = broken.iter().map(|b| (b.line, b.link.as_str())).collect();
    assert_eq!(
        found,
        [
            (5, "guide/gone.md"),
            (9, "guide/a.md#parts"),
            (9, "#nowhere")
        ],
        "{broken:#?}"
    );
    assert!(broken[0]
        .to_string()
        .starts_with("docs/README.md:5: (guide/gone.md) no such file"));
}

#[test]
fn slugs_follow_github() {
    assert_eq!(
        slug("Specialization: what it saves and what it costs"),
        "specialization-what-it-saves-and-what-it-costs"
    );
    assert_eq!(
        slug("`[[lights]]`: lights that are not surfaces"),
        "lights-lights-that-are-not-surfaces"
    );
    assert_eq!(
        slug("What limits lavapipe on Mesa 22.3"),
        "what-limits-lavapipe-on-mesa-223"
    );
    assert_eq!(
        anchors("# A\n## A\n```\n# not a heading\n```\n## A\n"),
        ["a", "a-1", "a-2"]
    );
}
