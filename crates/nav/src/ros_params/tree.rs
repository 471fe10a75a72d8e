//! The parameter tree: YAML files layered under namespaces as roslaunch's
//! `<rosparam file=... ns=...>` loads them.
//!
//! roslaunch unrolls every map into its leaves, so a later file overrides single keys of an
//! earlier one (a deep merge), and `a: {b: 1}` is the same parameter as `a/b: 1`.
//! A key that starts with `/` is global: it ignores the file's namespace.
//! Setting a leaf replaces whatever was below it, and a value below a former leaf replaces it.

use super::error::ParamError;
use serde_yaml::Value;
use std::collections::BTreeMap;

/// One parameter file's text and the namespace its keys go under (roslaunch's `ns`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParamSource {
    /// How errors and warnings name the file (usually its path as the user gave it).
    pub name: String,
    /// The YAML text.
    pub text: String,
    /// Namespace the keys are placed under, `/`-separated (empty: move_base's own namespace).
    pub namespace: String,
}

/// One parameter: its value and the file that set it last.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Leaf {
    /// The YAML value (a scalar or a sequence; maps are unrolled into leaves).
    pub value: Value,
    /// Index of the file in [`ParamTree::files`].
    pub file: usize,
    /// Load order, for reporting in the order the user wrote things.
    pub seq: usize,
}

/// Every parameter of the layered files, by its full `/`-separated name.
#[derive(Debug, Clone, Default)]
pub(crate) struct ParamTree {
    /// The files' names, in load order.
    pub files: Vec<String>,
    /// Leaves by full name.
    pub leaves: BTreeMap<String, Leaf>,
    seq: usize,
}

/// Joins name components, dropping empty ones (`a//b/` is `a/b`).
pub(crate) fn join(parts: &[&str]) -> String {
    parts.iter().flat_map(|p| p.split('/')).filter(|c| !c.is_empty()).collect::<Vec<_>>().join("/")
}

impl ParamTree {
    /// Layers `sources` in order.
    pub fn build(sources: &[ParamSource]) -> Result<ParamTree, ParamError> {
        let mut tree = ParamTree::default();
        for s in sources {
            tree.add(s)?;
        }
        Ok(tree)
    }

    fn add(&mut self, s: &ParamSource) -> Result<(), ParamError> {
        let file = self.files.len();
        self.files.push(s.name.clone());
        let doc: Value = serde_yaml::from_str(&s.text).map_err(|e| ParamError::Yaml { file: s.name.clone(), message: e.to_string() })?;
        let ns = join(&[&s.namespace]);
        match doc {
            Value::Null => Ok(()),
            Value::Mapping(_) => self.insert(&ns, &doc, file, &s.name),
            // roslaunch sets a lone value at the namespace itself.
            other if !ns.is_empty() => self.insert(&ns, &other, file, &s.name),
            _ => Err(ParamError::Yaml { file: s.name.clone(), message: "expected a map of parameter names to values".into() }),
        }
    }

    fn insert(&mut self, name: &str, v: &Value, file: usize, file_name: &str) -> Result<(), ParamError> {
        match v {
            Value::Mapping(m) => {
                for (k, sub) in m {
                    let key = match k {
                        Value::String(s) => s.clone(),
                        Value::Number(n) => n.to_string(),
                        Value::Bool(b) => b.to_string(),
                        _ => return Err(ParamError::Yaml { file: file_name.into(), message: format!("{}: a key must be a name, got {}", if name.is_empty() { "/" } else { name }, super::value::show(k)) }),
                    };
                    let full = if key.starts_with('/') { join(&[&key]) } else { join(&[name, &key]) };
                    if full.is_empty() {
                        return Err(ParamError::Yaml { file: file_name.into(), message: format!("empty parameter name `{key}`") });
                    }
                    self.insert(&full, sub, file, file_name)?;
                }
                Ok(())
            }
            _ => {
                self.set(name, v.clone(), file);
                Ok(())
            }
        }
    }

    fn set(&mut self, name: &str, value: Value, file: usize) {
        let below = format!("{name}/");
        self.leaves.retain(|k, _| !k.starts_with(&below));
        let mut prefix = String::new();
        for c in name.split('/') {
            if !prefix.is_empty() {
                self.leaves.remove(&prefix);
                prefix.push('/');
            }
            prefix.push_str(c);
        }
        self.seq += 1;
        self.leaves.insert(name.to_string(), Leaf { value, file, seq: self.seq });
    }

    /// The leaf called `name`, if any.
    #[cfg(test)]
    pub fn get(&self, name: &str) -> Option<&Leaf> {
        self.leaves.get(name)
    }

    /// The file that set `leaf`.
    pub fn file_of(&self, leaf: &Leaf) -> &str {
        &self.files[leaf.file]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tree(files: &[(&str, &str)]) -> ParamTree {
        let sources: Vec<ParamSource> = files.iter().enumerate().map(|(i, (t, ns))| ParamSource { name: format!("f{i}.yaml"), text: t.to_string(), namespace: ns.to_string() }).collect();
        ParamTree::build(&sources).unwrap()
    }

    fn f(t: &ParamTree, k: &str) -> Option<f64> {
        t.get(k).and_then(|l| l.value.as_f64())
    }

    #[test]
    fn nested_and_slashed_keys_are_one_name_and_namespaces_prefix_them() {
        let t = tree(&[("a:\n  b: 1\n", ""), ("a/c: 2\n", ""), ("b: 3\n", "x/y"), ("/g: 4\n", "x")]);
        assert_eq!((f(&t, "a/b"), f(&t, "a/c"), f(&t, "x/y/b"), f(&t, "g")), (Some(1.0), Some(2.0), Some(3.0), Some(4.0)));
        assert_eq!(t.file_of(t.get("x/y/b").unwrap()), "f2.yaml");
    }

    #[test]
    fn later_files_override_single_keys_and_replace_subtrees() {
        let t = tree(&[("m: {a: 1, b: 2}\ns: 1\n", "ns"), ("m: {b: 5}\n", "ns"), ("s: {x: 1}\n", "ns"), ("m/a: 9\n", "ns")]);
        assert_eq!((f(&t, "ns/m/a"), f(&t, "ns/m/b")), (Some(9.0), Some(5.0)));
        assert_eq!((f(&t, "ns/s"), f(&t, "ns/s/x")), (None, Some(1.0)));
        let t = tree(&[("m: {a: 1}\n", ""), ("m: 3\n", "")]);
        assert_eq!((f(&t, "m"), f(&t, "m/a")), (Some(3.0), None));
    }

    #[test]
    fn empty_files_load_and_bad_ones_name_the_file() {
        assert!(tree(&[("", ""), ("# only a comment\n", "")]).leaves.is_empty());
        let bad = |text: &str| ParamTree::build(&[ParamSource { name: "bad.yaml".into(), text: text.into(), namespace: String::new() }]).unwrap_err().to_string();
        assert!(bad("a: [1, 2\n").starts_with("bad.yaml: "), "{}", bad("a: [1, 2\n"));
        assert!(bad("3\n").contains("expected a map"), "{}", bad("3\n"));
        assert!(bad("? [1]\n: 2\n").contains("a key must be a name"), "{}", bad("? [1]\n: 2\n"));
        // A lone value goes to the namespace itself.
        let t = ParamTree::build(&[ParamSource { name: "r.yaml".into(), text: "0.2\n".into(), namespace: "robot_radius".into() }]).unwrap();
        assert_eq!(f(&t, "robot_radius"), Some(0.2));
    }
}
