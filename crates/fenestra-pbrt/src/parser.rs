//! Directives of the pbrt-v4 format from a token stream: the directive name, its positional
//! arguments (checked against the directive's signature) and its parameter list.

use crate::lexer::{Tok, Token};
use crate::params::{Param, ParamList, Values};
use crate::{Loc, PbrtError};

#[derive(Clone, Debug, PartialEq)]
pub enum Arg {
    Num(f64),
    Str(String),
}

#[derive(Debug)]
pub struct Directive {
    pub name: &'static str,
    pub loc: Loc,
    pub args: Vec<Arg>,
    pub params: ParamList,
}

impl Directive {
    pub fn num(&self, i: usize) -> f64 {
        match self.args.get(i) {
            Some(Arg::Num(v)) => *v,
            _ => 0.0,
        }
    }
    pub fn str(&self, i: usize) -> &str {
        match self.args.get(i) {
            Some(Arg::Str(s)) => s,
            _ => "",
        }
    }
}

/// Positional arguments: `s` a string, `w` a bare word, `nK` K numbers (optionally in brackets),
/// `m` one or two strings; `+` a parameter list follows.
const SIGNATURES: &[(&str, &str)] = &[
    ("Accelerator", "s+"),
    ("ActiveTransform", "w"),
    ("AreaLightSource", "s+"),
    ("Attribute", "s+"),
    ("AttributeBegin", ""),
    ("AttributeEnd", ""),
    ("Camera", "s+"),
    ("ColorSpace", "s"),
    ("ConcatTransform", "n16"),
    ("CoordinateSystem", "s"),
    ("CoordSysTransform", "s"),
    ("Film", "s+"),
    ("Identity", ""),
    ("Import", "s"),
    ("Include", "s"),
    ("Integrator", "s+"),
    ("LightSource", "s+"),
    ("LookAt", "n9"),
    ("MakeNamedMaterial", "s+"),
    ("MakeNamedMedium", "s+"),
    ("Material", "s+"),
    ("MediumInterface", "m"),
    ("NamedMaterial", "s"),
    ("ObjectBegin", "s"),
    ("ObjectEnd", ""),
    ("ObjectInstance", "s"),
    ("Option", "+"),
    ("PixelFilter", "s+"),
    ("ReverseOrientation", ""),
    ("Rotate", "n4"),
    ("Sampler", "s+"),
    ("Scale", "n3"),
    ("Shape", "s+"),
    ("Texture", "sss+"),
    ("Transform", "n16"),
    ("TransformBegin", ""),
    ("TransformEnd", ""),
    ("TransformTimes", "n2"),
    ("Translate", "n3"),
    ("WorldBegin", ""),
    ("WorldEnd", ""),
];

struct Cursor<'a> {
    tokens: &'a [Token],
    pos: usize,
    /// Where the file ends, for errors at end of input.
    end: Loc,
}

impl Cursor<'_> {
    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.pos)
    }
    fn next(&mut self) -> Option<&Token> {
        let t = self.tokens.get(self.pos);
        self.pos += 1;
        t
    }
    fn here(&self) -> Loc {
        self.peek()
            .map_or_else(|| self.end.clone(), |t| t.loc.clone())
    }
    fn found(&self) -> String {
        self.peek()
            .map_or_else(|| "end of file".into(), |t| t.tok.describe())
    }
    fn expected<T>(&self, what: &str, after: &str) -> Result<T, PbrtError> {
        Err(PbrtError::at(
            &self.here(),
            format!("expected {what} after {after}, found {}", self.found()),
        ))
    }
}

/// Parses a whole token stream into directives.
pub fn parse(tokens: &[Token], end: Loc) -> Result<Vec<Directive>, PbrtError> {
    let mut c = Cursor {
        tokens,
        pos: 0,
        end,
    };
    let mut out = Vec::new();
    while let Some(t) = c.next() {
        let loc = t.loc.clone();
        let Tok::Word(word) = &t.tok else {
            return Err(PbrtError::at(
                &loc,
                format!(
                    "expected a directive (such as Shape or LookAt), found {}",
                    t.tok.describe()
                ),
            ));
        };
        let Some(&(name, sig)) = SIGNATURES.iter().find(|s| s.0 == word) else {
            return Err(PbrtError::at(
                &loc,
                format!("unknown directive '{word}' (not part of the pbrt-v4 format)"),
            ));
        };
        let (args, has_params) = positional(&mut c, name, sig)?;
        let params = if has_params {
            param_list(&mut c, name)?
        } else {
            ParamList::default()
        };
        out.push(Directive {
            name,
            loc,
            args,
            params,
        });
    }
    Ok(out)
}

fn positional(c: &mut Cursor, name: &str, sig: &str) -> Result<(Vec<Arg>, bool), PbrtError> {
    let (sig, has_params) = match sig.strip_suffix('+') {
        Some(s) => (s, true),
        None => (sig, false),
    };
    let mut args = Vec::new();
    if let Some(n) = sig.strip_prefix('n') {
        let n: usize = n.parse().unwrap_or(0);
        let bracketed = matches!(c.peek().map(|t| &t.tok), Some(Tok::Open));
        if bracketed {
            c.next();
        }
        for _ in 0..n {
            match c.peek().map(|t| &t.tok) {
                Some(Tok::Number(v)) => {
                    args.push(Arg::Num(*v));
                    c.next();
                }
                _ => return c.expected(&format!("{n} numbers"), name),
            }
        }
        if bracketed {
            match c.peek().map(|t| &t.tok) {
                Some(Tok::Close) => {
                    c.next();
                }
                _ => return c.expected(&format!("']' closing the {n} numbers"), name),
            }
        }
        return Ok((args, has_params));
    }
    for (i, kind) in sig.chars().enumerate() {
        match (kind, c.peek().map(|t| &t.tok)) {
            ('s' | 'm', Some(Tok::Str(s))) => {
                args.push(Arg::Str(s.clone()));
                c.next();
                if kind == 'm' {
                    if let Some(Tok::Str(s)) = c.peek().map(|t| &t.tok) {
                        args.push(Arg::Str(s.clone()));
                        c.next();
                    }
                }
            }
            ('w', Some(Tok::Word(w))) => {
                args.push(Arg::Str(w.clone()));
                c.next();
            }
            _ => {
                let what = if kind == 'w' {
                    "a word".to_string()
                } else if sig.len() > 1 {
                    format!("quoted string {} of {}", i + 1, sig.len())
                } else {
                    "a quoted string".to_string()
                };
                return c.expected(&what, name);
            }
        }
    }
    Ok((args, has_params))
}

fn param_list(c: &mut Cursor, directive: &str) -> Result<ParamList, PbrtError> {
    let mut list = ParamList::default();
    while let Some(Tok::Str(decl)) = c.peek().map(|t| &t.tok) {
        let decl = decl.clone();
        let loc = c.here();
        c.next();
        let after = format!("parameter \"{decl}\" of {directive}");
        let values = match c.peek().map(|t| &t.tok) {
            Some(Tok::Open) => {
                c.next();
                let mut items = Vec::new();
                loop {
                    match c.peek().map(|t| t.tok.clone()) {
                        Some(Tok::Close) => {
                            c.next();
                            break;
                        }
                        Some(t @ (Tok::Number(_) | Tok::Str(_) | Tok::Word(_))) => {
                            items.push((t, c.here()));
                            c.next();
                        }
                        _ => return c.expected("a value or ']'", &after),
                    }
                }
                collect(items, &loc, &decl, &after)?
            }
            Some(t @ (Tok::Number(_) | Tok::Str(_) | Tok::Word(_))) => {
                let item = (t.clone(), c.here());
                c.next();
                collect(vec![item], &loc, &decl, &after)?
            }
            _ => return c.expected("a value or '['", &after),
        };
        list.params.push(Param::new(&decl, values, loc)?);
    }
    Ok(list)
}

/// One parameter's values, which must all be of one kind; `decl` ("float fov") says which.
fn collect(
    items: Vec<(Tok, Loc)>,
    loc: &Loc,
    decl: &str,
    after: &str,
) -> Result<Values, PbrtError> {
    // A bare word is a bool; anywhere else the declared type says what was wanted (pbrt
    // numbers are finite decimals: nan and inf are words).
    let wanted = match decl.split_whitespace().next() {
        Some("bool") => "true or false",
        Some("string" | "texture") => "a quoted string",
        _ => "a number",
    };
    let bool_word = |t: &Tok| match t {
        Tok::Word(w) | Tok::Str(w) if w == "true" => Some(true),
        Tok::Word(w) | Tok::Str(w) if w == "false" => Some(false),
        _ => None,
    };
    match items.first().map(|i| &i.0) {
        None => Err(PbrtError::at(loc, format!("empty value list for {after}"))),
        Some(Tok::Number(_)) => items
            .iter()
            .map(|(t, l)| match t {
                Tok::Number(v) => Ok(*v),
                t => Err(PbrtError::at(
                    l,
                    format!("expected a number in {after}, found {}", t.describe()),
                )),
            })
            .collect::<Result<_, _>>()
            .map(Values::Nums),
        Some(Tok::Word(_)) => items
            .iter()
            .map(|(t, l)| {
                bool_word(t).ok_or_else(|| {
                    PbrtError::at(
                        l,
                        format!("expected {wanted} in {after}, found {}", t.describe()),
                    )
                })
            })
            .collect::<Result<_, _>>()
            .map(Values::Bools),
        Some(_) => {
            // Strings; a list of only "true"/"false" strings may also be a bool parameter,
            // which Param::new decides from the declared type.
            let strs: Result<Vec<String>, PbrtError> = items
                .iter()
                .map(|(t, l)| match t {
                    Tok::Str(s) => Ok(s.clone()),
                    t => Err(PbrtError::at(
                        l,
                        format!("expected a string in {after}, found {}", t.describe()),
                    )),
                })
                .collect();
            strs.map(Values::Strs)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lexer::tokenize;
    use std::sync::Arc;

    fn parse_str(s: &str) -> Result<Vec<Directive>, PbrtError> {
        let file = Arc::new(std::path::PathBuf::from("t.pbrt"));
        let toks = tokenize(s, &file)?;
        let end = Loc {
            file,
            line: 99,
            col: 1,
        };
        parse(&toks, end)
    }

    #[test]
    fn reads_signatures_and_parameters() {
        let d = parse_str(
            "LookAt 0 0 5  0 0 0  0 1 0\nTransform [1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1]\n\
             Shape \"sphere\" \"float radius\" 2 \"bool flag\" true\nTexture \"t\" \"spectrum\" \"imagemap\"",
        )
        .expect("parse");
        assert_eq!(d.len(), 4);
        assert_eq!(d[0].args.len(), 9);
        assert_eq!(d[1].args.len(), 16);
        assert_eq!(d[2].str(0), "sphere");
        assert_eq!(d[2].params.float("radius", 1.0).expect("r"), 2.0);
        assert!(d[2].params.bool("flag", false).expect("b"));
        assert_eq!(d[3].args.len(), 3);
    }

    #[test]
    fn malformed_directives_name_what_was_expected() {
        let e = parse_str("Translate 1 2").expect_err("short").to_string();
        assert!(
            e.starts_with("t.pbrt:99:1: expected 3 numbers after Translate, found end of file"),
            "{e}"
        );
        let e = parse_str("Shape 3").expect_err("no type").to_string();
        assert!(
            e.contains("1:7: expected a quoted string after Shape, found number 3"),
            "{e}"
        );
        let e = parse_str("Shapes \"sphere\"")
            .expect_err("unknown")
            .to_string();
        assert!(e.contains("unknown directive 'Shapes'"), "{e}");
        let e = parse_str("Shape \"sphere\" \"float radius\" [1 \"a\"]")
            .expect_err("mixed")
            .to_string();
        assert!(e.contains("expected a number"), "{e}");
        let e = parse_str("Shape \"sphere\" \"float radius\" [1")
            .expect_err("unclosed")
            .to_string();
        assert!(e.contains("expected a value or ']'"), "{e}");
        let e = parse_str("[ 1 ]").expect_err("stray").to_string();
        assert!(e.contains("expected a directive"), "{e}");
    }
}
