//! Tokens of the pbrt-v4 scene format: bare words, numbers, quoted strings and brackets, with
//! `#` comments to the end of the line. Every token carries its line and column.

use crate::{Loc, PbrtError};
use std::sync::Arc;

#[derive(Clone, Debug, PartialEq)]
pub enum Tok {
    /// A bare word: a directive name, `true`/`false`, or anything else unquoted.
    Word(String),
    Number(f64),
    Str(String),
    Open,
    Close,
}

impl Tok {
    /// How the token reads in an error message.
    pub fn describe(&self) -> String {
        match self {
            Tok::Word(w) => format!("'{w}'"),
            Tok::Number(n) => format!("number {n}"),
            Tok::Str(s) => format!("string \"{s}\""),
            Tok::Open => "'['".into(),
            Tok::Close => "']'".into(),
        }
    }
}

#[derive(Clone, Debug)]
pub struct Token {
    pub tok: Tok,
    pub loc: Loc,
}

/// Splits `text` (the contents of `file`) into tokens.
pub fn tokenize(text: &str, file: &Arc<std::path::PathBuf>) -> Result<Vec<Token>, PbrtError> {
    let mut tokens = Vec::new();
    let mut chars = text.char_indices().peekable();
    let (mut line, mut line_start) = (1u32, 0usize);
    let loc_at = |line: u32, line_start: usize, at: usize| Loc {
        file: file.clone(),
        line,
        col: (text[line_start..at].chars().count() + 1) as u32,
    };
    while let Some(&(at, c)) = chars.peek() {
        let loc = loc_at(line, line_start, at);
        match c {
            '\n' => {
                chars.next();
                line += 1;
                line_start = at + 1;
            }
            c if c.is_whitespace() => {
                chars.next();
            }
            '#' => while chars.next_if(|&(_, c)| c != '\n').is_some() {},
            '[' | ']' => {
                chars.next();
                let tok = if c == '[' { Tok::Open } else { Tok::Close };
                tokens.push(Token { tok, loc });
            }
            '"' => {
                chars.next();
                let mut s = String::new();
                loop {
                    match chars.next() {
                        None | Some((_, '\n')) => {
                            return Err(PbrtError::at(
                                &loc,
                                "unterminated string: expected a closing '\"' on the same line",
                            ))
                        }
                        Some((_, '"')) => break,
                        Some((_, '\\')) => match chars.next() {
                            Some((_, 'n')) => s.push('\n'),
                            Some((_, 't')) => s.push('\t'),
                            Some((_, 'b')) => s.push('\u{8}'),
                            Some((_, 'f')) => s.push('\u{c}'),
                            Some((_, 'r')) => s.push('\r'),
                            Some((_, e @ ('\\' | '"' | '\''))) => s.push(e),
                            Some((at, e)) => {
                                return Err(PbrtError::at(
                                    &loc_at(line, line_start, at),
                                    format!("unknown escape '\\{e}' in string"),
                                ))
                            }
                            None => {
                                return Err(PbrtError::at(
                                    &loc,
                                    "unterminated string at end of file",
                                ))
                            }
                        },
                        Some((_, c)) => s.push(c),
                    }
                }
                tokens.push(Token {
                    tok: Tok::Str(s),
                    loc,
                });
            }
            _ => {
                let mut end = at;
                while let Some((i, c)) = chars
                    .next_if(|&(_, c)| !(c.is_whitespace() || matches!(c, '"' | '[' | ']' | '#')))
                {
                    end = i + c.len_utf8();
                }
                let word = &text[at..end];
                let starts_numeric = word
                    .chars()
                    .next()
                    .is_some_and(|c| c.is_ascii_digit() || matches!(c, '-' | '+' | '.'));
                let tok = if starts_numeric {
                    match word.parse::<f64>() {
                        // Scene values end up in f32: larger magnitudes would become infinite.
                        Ok(v) if v.abs() <= f32::MAX as f64 => Tok::Number(v),
                        _ => {
                            return Err(PbrtError::at(
                                &loc,
                                format!("'{word}' is not a finite number"),
                            ))
                        }
                    }
                } else {
                    Tok::Word(word.to_string())
                };
                tokens.push(Token { tok, loc });
            }
        }
    }
    Ok(tokens)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn toks(s: &str) -> Result<Vec<Tok>, PbrtError> {
        tokenize(s, &Arc::new("t.pbrt".into())).map(|v| v.into_iter().map(|t| t.tok).collect())
    }

    #[test]
    fn splits_words_numbers_strings_and_brackets() {
        let t = toks("Shape \"sphere\" \"float radius\" [2.5e-1] # comment\nWorldBegin -3 .5")
            .expect("tokens");
        assert_eq!(
            t,
            vec![
                Tok::Word("Shape".into()),
                Tok::Str("sphere".into()),
                Tok::Str("float radius".into()),
                Tok::Open,
                Tok::Number(0.25),
                Tok::Close,
                Tok::Word("WorldBegin".into()),
                Tok::Number(-3.0),
                Tok::Number(0.5),
            ]
        );
        assert_eq!(
            toks(r#""a\"b\\c""#).expect("escapes"),
            vec![Tok::Str("a\"b\\c".into())]
        );
    }

    #[test]
    fn errors_name_line_and_column() {
        let e = toks("Shape\n  \"sphere")
            .expect_err("unterminated")
            .to_string();
        assert!(e.starts_with("t.pbrt:2:3: unterminated string"), "{e}");
        let e = toks("Translate 1 2x 3")
            .expect_err("bad number")
            .to_string();
        assert!(
            e.starts_with("t.pbrt:1:13: '2x' is not a finite number"),
            "{e}"
        );
        let e = toks("é \"\\q\"").expect_err("bad escape").to_string();
        assert!(e.starts_with("t.pbrt:1:5: unknown escape"), "{e}");
    }
}
