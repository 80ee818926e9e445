//! Typed parameter lists ("float fov" [ 45 ]) with type checks at parse time and tracking of
//! which parameters a directive used, so the rest can be reported as unsupported.

use crate::spectra::SpectrumParam;
use crate::{Loc, PbrtError};
use fenestra_core::{Rgb, Vec2, Vec3};
use std::cell::Cell;

#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    Nums(Vec<f64>),
    Strs(Vec<String>),
    Bools(Vec<bool>),
}

/// The parameter types of pbrt-v4 and the kind of value each holds.
const TYPES: &[(&str, Kind, usize)] = &[
    ("integer", Kind::Num, 1),
    ("float", Kind::Num, 1),
    ("point2", Kind::Num, 2),
    ("vector2", Kind::Num, 2),
    ("point3", Kind::Num, 3),
    ("vector3", Kind::Num, 3),
    ("normal3", Kind::Num, 3),
    ("point", Kind::Num, 3),
    ("vector", Kind::Num, 3),
    ("normal", Kind::Num, 3),
    ("rgb", Kind::Num, 3),
    ("color", Kind::Num, 3),
    ("blackbody", Kind::Num, 1),
    ("spectrum", Kind::NumOrStr, 2),
    ("bool", Kind::Bool, 1),
    ("string", Kind::Str, 1),
    ("texture", Kind::Str, 1),
];

#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Num,
    Str,
    NumOrStr,
    Bool,
}

#[derive(Debug)]
pub struct Param {
    pub ty: String,
    pub name: String,
    pub values: Values,
    pub loc: Loc,
    used: Cell<bool>,
}

impl Param {
    /// Checks the declared type against the values and builds the parameter.
    pub fn new(decl: &str, values: Values, loc: Loc) -> Result<Param, PbrtError> {
        let mut words = decl.split_whitespace();
        let (Some(ty), Some(name), None) = (words.next(), words.next(), words.next()) else {
            return Err(PbrtError::at(
                &loc,
                format!("parameter declaration \"{decl}\" must be \"type name\""),
            ));
        };
        let Some(&(_, kind, arity)) = TYPES.iter().find(|t| t.0 == ty) else {
            let names: Vec<&str> = TYPES.iter().map(|t| t.0).collect();
            return Err(PbrtError::at(
                &loc,
                format!(
                    "unknown parameter type '{ty}' (expected one of {})",
                    names.join(", ")
                ),
            ));
        };
        // pbrt-v4 also writes booleans as quoted strings: "bool twosided" "true".
        let values = match values {
            Values::Strs(s)
                if kind == Kind::Bool && s.iter().all(|w| w == "true" || w == "false") =>
            {
                Values::Bools(s.iter().map(|w| w == "true").collect())
            }
            v => v,
        };
        let (found, n) = match &values {
            Values::Nums(v) => ("numbers", v.len()),
            Values::Strs(v) => ("strings", v.len()),
            Values::Bools(v) => ("booleans", v.len()),
        };
        let kind_ok = match kind {
            Kind::Num => matches!(values, Values::Nums(_)),
            Kind::Str => matches!(values, Values::Strs(_)),
            Kind::Bool => matches!(values, Values::Bools(_)),
            Kind::NumOrStr => !matches!(values, Values::Bools(_)),
        };
        if !kind_ok {
            let want = match kind {
                Kind::Num => "numbers",
                Kind::Str => "strings",
                Kind::Bool => "true or false",
                Kind::NumOrStr => "numbers or a string",
            };
            return Err(PbrtError::at(
                &loc,
                format!("parameter \"{name}\" of type {ty} expects {want}, found {found}"),
            ));
        }
        if n == 0 {
            return Err(PbrtError::at(
                &loc,
                format!("parameter \"{name}\" has no values"),
            ));
        }
        if matches!(values, Values::Nums(_)) && n % arity != 0 {
            return Err(PbrtError::at(
                &loc,
                format!("parameter \"{name}\" of type {ty} needs a multiple of {arity} numbers, found {n}"),
            ));
        }
        if ty == "integer" {
            if let Values::Nums(v) = &values {
                if let Some(x) = v
                    .iter()
                    .find(|x| x.fract() != 0.0 || x.abs() > 2f64.powi(31))
                {
                    return Err(PbrtError::at(
                        &loc,
                        format!("parameter \"{name}\" of type integer has the value {x}, which is not a 32-bit integer"),
                    ));
                }
            }
        }
        Ok(Param {
            ty: ty.into(),
            name: name.into(),
            values,
            loc,
            used: Cell::new(false),
        })
    }
}

#[derive(Debug, Default)]
pub struct ParamList {
    pub params: Vec<Param>,
}

impl ParamList {
    fn find(&self, name: &str, types: &[&str]) -> Result<Option<&Param>, PbrtError> {
        let Some(p) = self.params.iter().rev().find(|p| p.name == name) else {
            return Ok(None);
        };
        if !types.contains(&p.ty.as_str()) {
            return Err(PbrtError::at(
                &p.loc,
                format!(
                    "parameter \"{name}\" has type {} but {} is expected",
                    p.ty,
                    types.join(" or ")
                ),
            ));
        }
        p.used.set(true);
        Ok(Some(p))
    }

    fn nums(&self, name: &str, types: &[&str]) -> Result<Option<(&[f64], &Loc)>, PbrtError> {
        Ok(self.find(name, types)?.and_then(|p| match &p.values {
            Values::Nums(v) => Some((v.as_slice(), &p.loc)),
            _ => None,
        }))
    }

    fn single<T>(
        &self,
        name: &str,
        types: &[&str],
        get: impl Fn(&Values) -> Option<T>,
    ) -> Result<Option<T>, PbrtError> {
        let Some(p) = self.find(name, types)? else {
            return Ok(None);
        };
        let n = match &p.values {
            Values::Nums(v) => v.len(),
            Values::Strs(v) => v.len(),
            Values::Bools(v) => v.len(),
        };
        if n != 1 {
            return Err(PbrtError::at(
                &p.loc,
                format!("parameter \"{name}\" takes one value, found {n}"),
            ));
        }
        Ok(get(&p.values))
    }

    pub fn float(&self, name: &str, default: f32) -> Result<f32, PbrtError> {
        Ok(self
            .single(name, &["float"], |v| match v {
                Values::Nums(n) => Some(n[0] as f32),
                _ => None,
            })?
            .unwrap_or(default))
    }

    pub fn opt_float(&self, name: &str) -> Result<Option<f32>, PbrtError> {
        self.single(name, &["float"], |v| match v {
            Values::Nums(n) => Some(n[0] as f32),
            _ => None,
        })
    }

    pub fn int(&self, name: &str, default: i64) -> Result<i64, PbrtError> {
        Ok(self
            .single(name, &["integer"], |v| match v {
                Values::Nums(n) => Some(n[0] as i64),
                _ => None,
            })?
            .unwrap_or(default))
    }

    pub fn bool(&self, name: &str, default: bool) -> Result<bool, PbrtError> {
        Ok(self
            .single(name, &["bool"], |v| match v {
                Values::Bools(b) => Some(b[0]),
                _ => None,
            })?
            .unwrap_or(default))
    }

    pub fn string(&self, name: &str) -> Result<Option<String>, PbrtError> {
        self.single(name, &["string"], |v| match v {
            Values::Strs(s) => Some(s[0].clone()),
            _ => None,
        })
    }

    /// A string array with its location.
    pub fn strings(&self, name: &str) -> Result<Option<(Vec<String>, Loc)>, PbrtError> {
        Ok(self.find(name, &["string"])?.and_then(|p| match &p.values {
            Values::Strs(s) => Some((s.clone(), p.loc.clone())),
            _ => None,
        }))
    }

    pub fn texture(&self, name: &str) -> Result<Option<String>, PbrtError> {
        self.single(name, &["texture"], |v| match v {
            Values::Strs(s) => Some(s[0].clone()),
            _ => None,
        })
    }

    pub fn floats(&self, name: &str) -> Result<Option<Vec<f32>>, PbrtError> {
        Ok(self
            .nums(name, &["float"])?
            .map(|(v, _)| v.iter().map(|&x| x as f32).collect()))
    }

    /// Integer array with its location (for index range errors).
    pub fn ints(&self, name: &str) -> Result<Option<(Vec<i64>, Loc)>, PbrtError> {
        Ok(self
            .nums(name, &["integer"])?
            .map(|(v, loc)| (v.iter().map(|&x| x as i64).collect(), loc.clone())))
    }

    pub fn point3s(&self, name: &str) -> Result<Option<Vec<Vec3>>, PbrtError> {
        self.vec3s(name, &["point3", "point"])
    }

    pub fn normals(&self, name: &str) -> Result<Option<Vec<Vec3>>, PbrtError> {
        self.vec3s(name, &["normal3", "normal"])
    }

    fn vec3s(&self, name: &str, types: &[&str]) -> Result<Option<Vec<Vec3>>, PbrtError> {
        Ok(self.nums(name, types)?.map(|(v, _)| {
            v.chunks_exact(3)
                .map(|c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32))
                .collect()
        }))
    }

    pub fn point2s(&self, name: &str) -> Result<Option<Vec<Vec2>>, PbrtError> {
        Ok(self.nums(name, &["point2", "vector2"])?.map(|(v, _)| {
            v.chunks_exact(2)
                .map(|c| Vec2::new(c[0] as f32, c[1] as f32))
                .collect()
        }))
    }

    pub fn point3(&self, name: &str, default: Vec3) -> Result<Vec3, PbrtError> {
        match self.nums(name, &["point3", "point"])? {
            None => Ok(default),
            Some((v, _)) if v.len() == 3 => Ok(Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32)),
            Some((v, loc)) => Err(PbrtError::at(
                loc,
                format!(
                    "parameter \"{name}\" takes one 3-vector, found {} numbers",
                    v.len()
                ),
            )),
        }
    }

    /// A spectrum parameter: `rgb`/`color`, `blackbody`, `spectrum` (pairs, a name, or a
    /// file of pairs relative to the scene file).
    pub fn spectrum(&self, name: &str) -> Result<Option<(SpectrumParam, Loc)>, PbrtError> {
        let Some(p) = self.find(name, &["rgb", "color", "blackbody", "spectrum", "float"])? else {
            return Ok(None);
        };
        let bad = |what: String| Err(PbrtError::at(&p.loc, what));
        let s = match (&p.values, p.ty.as_str()) {
            (Values::Nums(v), "rgb" | "color") if v.len() == 3 => {
                SpectrumParam::Rgb(Rgb::new(v[0] as f32, v[1] as f32, v[2] as f32))
            }
            (Values::Nums(v), "float") if v.len() == 1 => {
                SpectrumParam::Rgb(Rgb::splat(v[0] as f32))
            }
            (Values::Nums(v), "blackbody") if v.len() == 1 => SpectrumParam::Blackbody(v[0] as f32),
            (Values::Nums(v), "spectrum") => SpectrumParam::Sampled(
                v.chunks_exact(2)
                    .map(|c| (c[0] as f32, c[1] as f32))
                    .collect(),
            ),
            (Values::Strs(s), "spectrum") if s.len() == 1 => {
                if crate::spectra::names_file(&s[0]) {
                    let dir = p.loc.file.parent().unwrap_or(std::path::Path::new("."));
                    match crate::spectra::read_file(&dir.join(&s[0])) {
                        Ok(pairs) => SpectrumParam::Sampled(pairs),
                        Err(e) => return bad(format!("parameter \"{name}\": {e}")),
                    }
                } else {
                    SpectrumParam::Named(s[0].clone())
                }
            }
            _ => {
                return bad(format!(
                    "parameter \"{name}\" ({}) must hold one value",
                    p.ty
                ))
            }
        };
        Ok(Some((s, p.loc.clone())))
    }

    /// The declared type of parameter `name`, if present.
    pub fn type_of(&self, name: &str) -> Option<&str> {
        self.params
            .iter()
            .rev()
            .find(|p| p.name == name)
            .map(|p| p.ty.as_str())
    }

    /// Whether a parameter called `name` is present (of any type).
    pub fn has(&self, name: &str) -> bool {
        self.params.iter().any(|p| p.name == name)
    }

    /// Marks every parameter as used (for directives reported as unsupported as a whole).
    pub fn use_all(&self) {
        for p in &self.params {
            p.used.set(true);
        }
    }

    /// Parameters no reader looked at.
    pub fn unused(&self) -> impl Iterator<Item = &Param> {
        self.params.iter().filter(|p| !p.used.get())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    fn loc() -> Loc {
        Loc {
            file: Arc::new("t.pbrt".into()),
            line: 1,
            col: 1,
        }
    }

    #[test]
    fn declarations_are_type_checked() {
        assert!(Param::new("float fov", Values::Nums(vec![45.0]), loc()).is_ok());
        let e = Param::new("float fov", Values::Strs(vec!["abc".into()]), loc()).expect_err("type");
        assert!(
            e.to_string().contains("expects numbers, found strings"),
            "{e}"
        );
        let e = Param::new("rgb L", Values::Nums(vec![1.0, 2.0]), loc()).expect_err("arity");
        assert!(e.to_string().contains("multiple of 3"), "{e}");
        let e = Param::new("integer n", Values::Nums(vec![1.5]), loc()).expect_err("int");
        assert!(e.to_string().contains("not a 32-bit integer"), "{e}");
        let e = Param::new("quaternion q", Values::Nums(vec![1.0]), loc()).expect_err("ty");
        assert!(e.to_string().contains("unknown parameter type"), "{e}");
        assert!(Param::new("fov", Values::Nums(vec![1.0]), loc()).is_err());
    }

    #[test]
    fn lookups_check_types_and_track_use() {
        let list = ParamList {
            params: vec![
                Param::new("float fov", Values::Nums(vec![30.0]), loc()).expect("p"),
                Param::new("float zmin", Values::Nums(vec![0.0]), loc()).expect("p"),
            ],
        };
        assert_eq!(list.float("fov", 90.0).expect("fov"), 30.0);
        assert_eq!(list.float("radius", 1.0).expect("default"), 1.0);
        assert!(list.int("fov", 0).is_err());
        let unused: Vec<&str> = list.unused().map(|p| p.name.as_str()).collect();
        assert_eq!(unused, vec!["zmin"]);
    }
}
