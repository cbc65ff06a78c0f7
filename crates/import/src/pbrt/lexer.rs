//! pbrt-v4's tokens (its `Tokenizer`): `#` comments to the end of the line, quoted strings with
//! C escapes, `[` and `]`, and bare words (numbers, directive names, `true` / `false`), each with
//! its byte offset for errors that name the line and column.

use std::path::Path;
use stratapt_scene::error::{SceneError, SourceLocation};

/// One token.
#[derive(Clone, Debug, PartialEq)]
pub enum Token<'a> {
    /// A bare word: a directive's name, a number, `true` or `false`.
    Word(&'a str),
    /// A quoted string, its escapes resolved.
    Str(String),
    Open,
    Close,
}

/// A token and the byte offset it starts at.
#[derive(Clone, Debug, PartialEq)]
pub struct At<'a> {
    pub token: Token<'a>,
    pub at: usize,
}

/// The tokens of `text` (the contents of `file`, named in errors).
pub fn tokens<'a>(text: &'a str, file: &Path) -> Result<Vec<At<'a>>, SceneError> {
    let bytes = text.as_bytes();
    let err = |at: usize, reason: String| {
        SceneError::new(SourceLocation::at_offset(file, text, at), reason)
    };
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        match c {
            b' ' | b'\t' | b'\n' | b'\r' => i += 1,
            b'#' => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
            }
            b'[' | b']' => {
                let token = if c == b'[' { Token::Open } else { Token::Close };
                out.push(At { token, at: i });
                i += 1;
            }
            b'"' => {
                let start = i;
                i += 1;
                let mut s = String::new();
                loop {
                    let Some(ch) = text[i..].chars().next() else {
                        return Err(err(start, "a string that is never closed".into()));
                    };
                    match ch {
                        '"' => {
                            i += 1;
                            break;
                        }
                        '\n' => return Err(err(start, "a newline inside a string".into())),
                        '\\' => {
                            let Some(e) = text[i + 1..].chars().next() else {
                                return Err(err(start, "a string that is never closed".into()));
                            };
                            s.push(match e {
                                'b' => '\u{8}',
                                'f' => '\u{c}',
                                'n' => '\n',
                                'r' => '\r',
                                't' => '\t',
                                '\\' | '\'' | '"' => e,
                                other => return Err(err(i, format!("unknown escape `\\{other}`"))),
                            });
                            i += 1 + e.len_utf8();
                        }
                        _ => {
                            s.push(ch);
                            i += ch.len_utf8();
                        }
                    }
                }
                out.push(At {
                    token: Token::Str(s),
                    at: start,
                });
            }
            _ => {
                let start = i;
                while i < bytes.len()
                    && !matches!(
                        bytes[i],
                        b' ' | b'\t' | b'\n' | b'\r' | b'"' | b'[' | b']' | b'#'
                    )
                {
                    i += 1;
                }
                out.push(At {
                    token: Token::Word(&text[start..i]),
                    at: start,
                });
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(text: &str) -> Vec<Token<'_>> {
        tokens(text, Path::new("t.pbrt"))
            .unwrap()
            .into_iter()
            .map(|t| t.token)
            .collect()
    }

    #[test]
    fn comments_strings_brackets_and_words() {
        assert_eq!(
            words("Shape \"sphere\" # a comment \"not a string\"\n  \"float radius\" [2.5]"),
            vec![
                Token::Word("Shape"),
                Token::Str("sphere".into()),
                Token::Str("float radius".into()),
                Token::Open,
                Token::Word("2.5"),
                Token::Close,
            ]
        );
        assert_eq!(
            words(r#""a\"b\\c\td" [1-2]"#),
            vec![
                Token::Str("a\"b\\c\td".into()),
                Token::Open,
                Token::Word("1-2"),
                Token::Close,
            ]
        );
        assert_eq!(words("Translate 1 -2e3 .5#x"), words("Translate 1 -2e3 .5"));
    }

    #[test]
    fn offsets_name_the_line_and_column() {
        let t = tokens("A\n  \"b\" [", Path::new("t.pbrt")).unwrap();
        assert_eq!(t.iter().map(|t| t.at).collect::<Vec<_>>(), vec![0, 4, 8]);
        for (text, at, reason) in [
            ("Shape \"sphere", "1:7", "never closed"),
            ("Shape\n \"sph\nere\"", "2:2", "newline inside a string"),
            ("A \"x\\q\"", "1:5", "unknown escape `\\q`"),
        ] {
            let e = tokens(text, Path::new("t.pbrt")).unwrap_err().to_string();
            assert!(
                e.contains(&format!("t.pbrt:{at}")) && e.contains(reason),
                "{e}"
            );
        }
    }
}
