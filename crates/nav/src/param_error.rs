//! [`ParamError`]: a parameter that does not parse or is out of range, named by its dotted
//! path as the user wrote it (`local_costmap.inflation_layer.inflation_radius`).

use std::fmt::Display;

/// A navigation parameter is invalid. Returned by the `validate()` of every parameter struct
/// and by the YAML loader; fix the named field (the message gives the allowed range).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ParamError {
    /// A value is outside its range or inconsistent with another field.
    #[error("{field}: {message}")]
    Invalid {
        /// Dotted path of the field, e.g. `DWAPlannerROS.sim_time`.
        field: String,
        /// What is wrong, e.g. `must be > 0, got -1`.
        message: String,
    },
    /// The YAML text does not parse into the parameters (wrong type, unknown field, bad syntax).
    #[error("{path}: {message}")]
    Parse {
        /// Dotted path where parsing failed (`.` for the document root).
        path: String,
        /// The parser's message.
        message: String,
    },
}

impl ParamError {
    /// An [`Invalid`](Self::Invalid) error for `field`.
    pub fn invalid(field: &str, message: impl Display) -> Self {
        Self::Invalid {
            field: field.to_string(),
            message: message.to_string(),
        }
    }

    /// The same error with `prefix.` put in front of its field path.
    pub fn within(self, prefix: &str) -> Self {
        let join = |p: String| {
            if p.is_empty() || p == "." {
                prefix.to_string()
            } else {
                format!("{prefix}.{p}")
            }
        };
        match self {
            Self::Invalid { field, message } => Self::Invalid {
                field: join(field),
                message,
            },
            Self::Parse { path, message } => Self::Parse {
                path: join(path),
                message,
            },
        }
    }
}

/// Checks `lo <= v <= hi` (either bound may be infinite); the error names `field`.
pub fn check_range(field: &str, v: f64, lo: f64, hi: f64) -> Result<(), ParamError> {
    if v.is_nan() || v < lo || v > hi {
        let range = match (lo.is_finite(), hi.is_finite()) {
            (true, true) => format!("in [{lo}, {hi}]"),
            (true, false) => format!(">= {lo}"),
            (false, true) => format!("<= {hi}"),
            (false, false) => "a number".to_string(),
        };
        return Err(ParamError::invalid(
            field,
            format!("must be {range}, got {v}"),
        ));
    }
    Ok(())
}

/// Checks `v > 0` and finite; the error names `field`.
pub fn check_positive(field: &str, v: f64) -> Result<(), ParamError> {
    if !(v > 0.0 && v.is_finite()) {
        return Err(ParamError::invalid(field, format!("must be > 0, got {v}")));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_the_dotted_field() {
        let e = check_range("inflation_radius", -0.2, 0.0, 50.0)
            .unwrap_err()
            .within("inflation_layer")
            .within("local_costmap");
        assert_eq!(
            e.to_string(),
            "local_costmap.inflation_layer.inflation_radius: must be in [0, 50], got -0.2"
        );
        assert_eq!(
            check_positive("sim_time", 0.0).unwrap_err().to_string(),
            "sim_time: must be > 0, got 0"
        );
    }
}
