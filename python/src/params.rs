//! Parameters from Python: a dict (sent as JSON) or a TOML file, checked exactly as the
//! CLI checks a `--params` file (every number bounded, every range validated).

use crate::value_error;
use pyo3::PyResult;
use tabula_geom::input::{Validate, load_params, parse_params};

/// `text` of `kind` (`"json"`: a dict's JSON; `"file"`: a TOML file's path) as a
/// module's parameters; keys left out keep their defaults (SPEC's values).
pub fn parse<T: serde::de::DeserializeOwned + Default + Validate>(
    kind: &str,
    text: &str,
) -> PyResult<T> {
    let toml_text = match kind {
        "file" => return load_params(Some(std::path::Path::new(text))).map_err(value_error),
        "json" => {
            let value: toml::Value =
                serde_json::from_str(text).map_err(|e| value_error(format!("params: {e}")))?;
            toml::to_string(&value).map_err(|e| value_error(format!("params: {e}")))?
        }
        other => return Err(value_error(format!("params: unknown kind `{other}`"))),
    };
    parse_params(&toml_text, "params").map_err(value_error)
}
