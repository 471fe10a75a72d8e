//! The edge that reads parameter files: `FILE[@NAMESPACE]` arguments, as
//! `<rosparam file="FILE" ns="NAMESPACE">`.

use super::error::ParamError;
use super::load::{nav_params_from_sources, LoadedParams};
use super::tree::ParamSource;
use std::path::PathBuf;
use std::str::FromStr;

/// A parameter file and the namespace its keys are loaded under, written `FILE[@NAMESPACE]`
/// (`costmap_common_params.yaml@global_costmap`); no namespace is move_base's own.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParamFile {
    /// The YAML file.
    pub path: PathBuf,
    /// `/`-separated namespace (empty: move_base's own).
    pub namespace: String,
}

impl FromStr for ParamFile {
    type Err = ParamError;

    /// Splits at the last `@`; the namespace must be a ROS name (letters, digits, `_`, `/`,
    /// each part starting with a letter).
    fn from_str(arg: &str) -> Result<Self, Self::Err> {
        let bad = |message: &str| ParamError::Argument { arg: arg.to_string(), message: message.to_string() };
        let (path, namespace) = match arg.rsplit_once('@') {
            Some((path, ns)) => (path, ns.trim_matches('/')),
            None => (arg, ""),
        };
        if path.is_empty() {
            return Err(bad("no file before `@`"));
        }
        if arg.contains('@') && namespace.is_empty() {
            return Err(bad("no namespace after `@`"));
        }
        let valid = |part: &str| part.chars().next().is_some_and(|c| c.is_ascii_alphabetic()) && part.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
        if !namespace.is_empty() && !namespace.split('/').all(valid) {
            return Err(bad("the namespace must be a ROS name: letters, digits, `_` and `/`, each part starting with a letter"));
        }
        Ok(ParamFile { path: PathBuf::from(path), namespace: namespace.to_string() })
    }
}

impl std::fmt::Display for ParamFile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.path.display())?;
        if !self.namespace.is_empty() {
            write!(f, "@{}", self.namespace)?;
        }
        Ok(())
    }
}

/// Reads `files` and layers them in order (see [`nav_params_from_sources`]); no files: the
/// defaults. Errors name the file as given.
pub fn load_nav_params(files: &[ParamFile]) -> Result<LoadedParams, ParamError> {
    let sources = files
        .iter()
        .map(|f| {
            let name = f.path.display().to_string();
            let bytes = std::fs::read(&f.path).map_err(|source| ParamError::Read { file: name.clone(), source })?;
            let text = String::from_utf8(bytes).map_err(|e| ParamError::Yaml { file: name.clone(), message: format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to()) })?;
            Ok(ParamSource { name, text, namespace: f.namespace.clone() })
        })
        .collect::<Result<Vec<_>, ParamError>>()?;
    nav_params_from_sources(&sources)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_arguments_split_at_the_last_at_sign() {
        let f: ParamFile = "a/b@c.yaml@global_costmap".parse().unwrap();
        assert_eq!((f.path, f.namespace.as_str()), (PathBuf::from("a/b@c.yaml"), "global_costmap"));
        assert_eq!("x.yaml".parse::<ParamFile>().unwrap().namespace, "");
        assert_eq!("x.yaml@/move_base/local_costmap/".parse::<ParamFile>().unwrap().to_string(), "x.yaml@move_base/local_costmap");
        for bad in ["x.yaml@", "@ns", "x.yaml@1ns", "x.yaml@a b"] {
            assert!(bad.parse::<ParamFile>().is_err(), "{bad}");
        }
        let e = load_nav_params(&["/nonexistent/nav.yaml".parse().unwrap()]).unwrap_err().to_string();
        assert!(e.starts_with("/nonexistent/nav.yaml: "), "{e}");
    }
}
