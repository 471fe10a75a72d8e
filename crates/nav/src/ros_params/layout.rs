//! The shape of one costmap's parameters: its layers (from `plugins`, or the pre-Hydro
//! static/obstacle/inflation trio) and its obstacle layers' observation sources.
//!
//! costmap_2d without `plugins` moves the top-level names into `static_layer`,
//! `obstacle_layer` and `inflation_layer` (`loadOldParameters`); with `plugins` it copies the
//! top-level names over each layer's (`copyParentParameters`). Either way a name at the
//! costmap's top wins over the same name inside a layer, which is the order [`super::load`]
//! reads them in.

use super::error::ParamError;
use super::value::{as_str, show};
use serde_yaml::Value;

/// Which costmap_2d plugin a layer is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum LayerKind {
    /// costmap_2d::StaticLayer.
    Static,
    /// costmap_2d::ObstacleLayer.
    Obstacle,
    /// costmap_2d::VoxelLayer (read as an obstacle layer: xhab's costmaps are 2D).
    Voxel,
    /// costmap_2d::InflationLayer.
    Inflation,
    /// Any other plugin type (not run by xhab).
    Other(String),
}

/// One layer: its name (its namespace inside the costmap's) and kind.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Layer {
    /// Namespace inside the costmap's.
    pub name: String,
    /// Plugin kind.
    pub kind: LayerKind,
}

/// One observation source of an obstacle layer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Source {
    /// Its name, as listed in `observation_sources`.
    pub name: String,
    /// Namespaces (inside the costmap's) its parameters may sit under, the first found wins.
    pub prefixes: Vec<String>,
}

/// A costmap's layers and sources.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct Layout {
    /// `plugins` was given.
    pub plugins: bool,
    /// Layers in order.
    pub layers: Vec<Layer>,
    /// Observation sources of the obstacle layers, in order.
    pub sources: Vec<Source>,
}

impl Layout {
    /// The first layer of `kind`'s name.
    pub fn layer(&self, pick: impl Fn(&LayerKind) -> bool) -> Option<&str> {
        self.layers.iter().find(|l| pick(&l.kind)).map(|l| l.name.as_str())
    }

    /// The kind of the layer called `name`.
    pub fn kind_of(&self, name: &str) -> Option<&LayerKind> {
        self.layers.iter().find(|l| l.name == name).map(|l| &l.kind)
    }

    /// The source whose parameters sit under `prefix` (inside the costmap's namespace).
    pub fn source_at(&self, prefix: &str) -> Option<&Source> {
        self.sources.iter().find(|s| s.prefixes.iter().any(|p| p == prefix))
    }
}

/// Reads `plugins` (a list of `{name, type}` maps); `key` and `file` name it in errors.
pub(crate) fn parse_plugins(v: &Value, file: &str, key: &str) -> Result<Vec<Layer>, ParamError> {
    let err = |message: String| ParamError::Value { file: file.into(), key: key.into(), message };
    let Value::Sequence(items) = v else { return Err(err(format!("expected a list of {{name, type}} maps, got {}", show(v)))) };
    items
        .iter()
        .map(|item| {
            let field = |f: &str| -> Result<String, ParamError> {
                let got = item.get(f).ok_or_else(|| err(format!("each plugin needs a `{f}`, got {}", show(item))))?;
                as_str(got).map(str::to_string).map_err(|m| err(format!("plugin `{f}`: {m}")))
            };
            let (name, ty) = (field("name")?, field("type")?);
            let kind = match ty.as_str() {
                "costmap_2d::StaticLayer" => LayerKind::Static,
                "costmap_2d::ObstacleLayer" => LayerKind::Obstacle,
                "costmap_2d::VoxelLayer" => LayerKind::Voxel,
                "costmap_2d::InflationLayer" => LayerKind::Inflation,
                _ => LayerKind::Other(ty),
            };
            Ok(Layer { name, kind })
        })
        .collect()
}

/// The source names of an `observation_sources` value (space-separated, as costmap_2d splits it).
pub(crate) fn parse_sources(v: &Value, file: &str, key: &str) -> Result<Vec<String>, ParamError> {
    let s = as_str(v).map_err(|m| ParamError::Value { file: file.into(), key: key.into(), message: format!("{m} (source names separated by spaces)") })?;
    Ok(s.split_whitespace().map(str::to_string).collect())
}

/// The pre-Hydro layers: costmap_2d's `loadOldParameters` (a voxel obstacle layer when
/// `map_type: voxel`; the static layer is listed whatever `static_map` says, since xhab's
/// global costmap always starts from the map).
pub(crate) fn old_layers(voxel: bool) -> Vec<Layer> {
    vec![
        Layer { name: "static_layer".into(), kind: LayerKind::Static },
        Layer { name: "obstacle_layer".into(), kind: if voxel { LayerKind::Voxel } else { LayerKind::Obstacle } },
        Layer { name: "inflation_layer".into(), kind: LayerKind::Inflation },
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plugins_and_sources_parse_and_bad_ones_name_the_key() {
        let v: Value = serde_yaml::from_str("[{name: static, type: 'costmap_2d::StaticLayer'}, {name: people, type: 'social_navigation_layers::ProxemicLayer'}]").unwrap();
        let layers = parse_plugins(&v, "c.yaml", "global_costmap/plugins").unwrap();
        assert_eq!(layers[0], Layer { name: "static".into(), kind: LayerKind::Static });
        assert_eq!(layers[1].kind, LayerKind::Other("social_navigation_layers::ProxemicLayer".into()));
        let e = parse_plugins(&serde_yaml::from_str("[{name: a}]").unwrap(), "c.yaml", "global_costmap/plugins").unwrap_err().to_string();
        assert!(e.starts_with("c.yaml: global_costmap/plugins: each plugin needs a `type`"), "{e}");
        assert_eq!(parse_sources(&Value::String(" scan  bump ".into()), "c.yaml", "k").unwrap(), ["scan", "bump"]);
        assert!(parse_sources(&serde_yaml::from_str("[scan]").unwrap(), "c.yaml", "k").is_err());
    }
}
