//! Parameter types and ranges, and reading YAML values as them.
//!
//! Types follow ROS's XmlRpc rules: a real parameter takes an integer, an integer parameter
//! refuses a real, and strings are never numbers. Booleans also take YAML 1.1's `yes`/`no`/`on`/
//! `off` (rosparam reads YAML 1.1), and reals take rosparam's `!degrees` and `!radians` tags.

use serde_yaml::Value;

/// Allowed values of a number (every number must also be finite).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Range {
    /// Any finite number.
    Any,
    /// `>= 0`.
    NonNeg,
    /// `> 0`.
    Pos,
    /// `>= lo`.
    AtLeast(f64),
    /// `lo <= x <= hi`.
    Within(f64, f64),
    /// `lo < x < hi`.
    Open(f64, f64),
}

impl Range {
    /// `Err("must be ...")` when `x` is outside.
    pub fn check(self, x: f64) -> Result<(), String> {
        let (ok, rule) = match self {
            _ if !x.is_finite() => (false, "must be a finite number".to_string()),
            Range::Any => (true, String::new()),
            Range::NonNeg => (x >= 0.0, "must be >= 0".into()),
            Range::Pos => (x > 0.0, "must be > 0".into()),
            Range::AtLeast(lo) => (x >= lo, format!("must be >= {lo}")),
            Range::Within(lo, hi) => (x >= lo && x <= hi, format!("must be in [{lo}, {hi}]")),
            Range::Open(lo, hi) => (x > lo && x < hi, format!("must be in ({lo}, {hi})")),
        };
        if ok {
            Ok(())
        } else {
            Err(rule)
        }
    }
}

/// A parameter's type.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Ty {
    /// true/false.
    Bool,
    /// An integer within the range.
    Int(Range),
    /// A real within the range.
    Float(Range),
    /// A string.
    Str,
    /// A polygon: a list of `[x, y]` pairs, or that list written as a string.
    Footprint,
    /// A list (of anything).
    List,
    /// Anything (checked by the code that uses it).
    Any,
}

/// A short rendering of `v` for messages: numbers and words as written, strings quoted.
pub(crate) fn show(v: &Value) -> String {
    match v {
        Value::Null => "nothing".into(),
        Value::Bool(b) => b.to_string(),
        Value::Number(n) => n.to_string(),
        Value::String(s) => format!("{s:?}"),
        Value::Sequence(_) => "a list".into(),
        Value::Mapping(_) => "a map".into(),
        Value::Tagged(t) => format!("{} {}", t.tag, show(&t.value)),
    }
}

/// `v` as a real (integers and `!degrees`/`!radians` numbers too).
pub(crate) fn as_f64(v: &Value) -> Result<f64, String> {
    match v {
        Value::Number(n) => n.as_f64().ok_or_else(|| format!("expected a number, got {n}")),
        Value::Tagged(t) if t.tag == "degrees" || t.tag == "radians" => {
            let x = as_f64(&t.value)?;
            Ok(if t.tag == "degrees" { x.to_radians() } else { x })
        }
        other => Err(format!("expected a number, got {}", show(other))),
    }
}

/// `v` as an integer.
pub(crate) fn as_i64(v: &Value) -> Result<i64, String> {
    match v {
        Value::Number(n) => n.as_i64().ok_or_else(|| format!("expected an integer, got {n}")),
        other => Err(format!("expected an integer, got {}", show(other))),
    }
}

/// `v` as a boolean.
pub(crate) fn as_bool(v: &Value) -> Result<bool, String> {
    match v {
        Value::Bool(b) => Ok(*b),
        Value::String(s) => match s.to_ascii_lowercase().as_str() {
            "true" | "yes" | "on" => Ok(true),
            "false" | "no" | "off" => Ok(false),
            _ => Err(format!("expected true or false, got {}", show(v))),
        },
        other => Err(format!("expected true or false, got {}", show(other))),
    }
}

/// `v` as a string.
pub(crate) fn as_str(v: &Value) -> Result<&str, String> {
    match v {
        Value::String(s) => Ok(s),
        other => Err(format!("expected a string, got {}", show(other))),
    }
}

/// `v` as a footprint polygon (m); `None` for costmap_2d's "no footprint" (`""`, `"[]"`, `[]`).
pub(crate) fn as_footprint(v: &Value) -> Result<Option<Vec<[f64; 2]>>, String> {
    let parsed;
    let list = match v {
        Value::String(s) if s.trim().is_empty() => return Ok(None),
        Value::String(s) => {
            parsed = serde_yaml::from_str::<Value>(s).map_err(|_| format!("expected a list of [x, y] points, got {}", show(v)))?;
            &parsed
        }
        other => other,
    };
    let Value::Sequence(points) = list else { return Err(format!("expected a list of [x, y] points, got {}", show(v))) };
    if points.is_empty() {
        return Ok(None);
    }
    if points.len() < 3 {
        return Err(format!("a footprint needs at least 3 points, got {}", points.len()));
    }
    points
        .iter()
        .map(|p| match p {
            Value::Sequence(xy) if xy.len() == 2 => {
                let x = as_f64(&xy[0])?;
                let y = as_f64(&xy[1])?;
                if x.is_finite() && y.is_finite() {
                    Ok([x, y])
                } else {
                    Err(format!("footprint points must be finite, got [{x}, {y}]"))
                }
            }
            other => Err(format!("each footprint point must be a pair [x, y], got {}", show(other))),
        })
        .collect::<Result<Vec<_>, _>>()
        .map(Some)
}

/// Checks `v` against `ty`; the error says what was expected and what was found.
pub(crate) fn check(v: &Value, ty: Ty) -> Result<(), String> {
    let in_range = |x: f64, r: Range| r.check(x).map_err(|rule| format!("{rule}, got {}", show(v)));
    match ty {
        Ty::Bool => as_bool(v).map(|_| ()),
        Ty::Int(r) => in_range(as_i64(v)? as f64, r),
        Ty::Float(r) => in_range(as_f64(v)?, r),
        Ty::Str => as_str(v).map(|_| ()),
        Ty::Footprint => as_footprint(v).map(|_| ()),
        Ty::List => match v {
            Value::Sequence(_) => Ok(()),
            other => Err(format!("expected a list, got {}", show(other))),
        },
        Ty::Any => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn y(s: &str) -> Value {
        serde_yaml::from_str(s).unwrap()
    }

    #[test]
    fn numbers_follow_xmlrpc_and_ranges_quote_the_value() {
        assert_eq!(check(&y("3"), Ty::Float(Range::Pos)), Ok(()));
        assert_eq!(check(&y("0"), Ty::Float(Range::Pos)), Err("must be > 0, got 0".into()));
        assert_eq!(check(&y("-0.5"), Ty::Float(Range::NonNeg)), Err("must be >= 0, got -0.5".into()));
        assert_eq!(check(&y(".nan"), Ty::Float(Range::Any)), Err("must be a finite number, got .nan".into()));
        assert_eq!(check(&y("2.5"), Ty::Int(Range::Pos)), Err("expected an integer, got 2.5".into()));
        assert_eq!(check(&y("fast"), Ty::Float(Range::Any)), Err("expected a number, got \"fast\"".into()));
        assert_eq!(check(&y("1.5"), Ty::Float(Range::Within(0.0, 1.0))), Err("must be in [0, 1], got 1.5".into()));
        assert!((as_f64(&y("!degrees 90")).unwrap() - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        assert_eq!(as_bool(&y("yes")), Ok(true));
        assert!(as_bool(&y("1")).is_err());
    }

    #[test]
    fn footprints_parse_from_lists_and_strings() {
        let sq = Some(vec![[-0.1, -0.1], [-0.1, 0.1], [0.1, 0.1], [0.1, -0.1]]);
        assert_eq!(as_footprint(&y("[[-0.1, -0.1], [-0.1, 0.1], [0.1, 0.1], [0.1, -0.1]]")), Ok(sq.clone()));
        assert_eq!(as_footprint(&y("'[[-0.1, -0.1], [-0.1, 0.1], [0.1, 0.1], [0.1, -0.1]]'")), Ok(sq));
        assert_eq!(as_footprint(&y("'[]'")), Ok(None));
        assert_eq!(as_footprint(&y("[[0, 0], [1, 0]]")), Err("a footprint needs at least 3 points, got 2".into()));
        assert!(as_footprint(&y("[[0, 0], [1, 0], [1]]")).unwrap_err().contains("pair"));
        assert!(as_footprint(&y("'[[0, 0], [1'")).is_err());
    }
}
