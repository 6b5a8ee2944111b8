//! The input policy's file side (INPUT_POLICY.md): every file a user hands tabula is read
//! through [`read_bytes`] or [`read_text`], which refuse what is not a regular file
//! (`/dev/zero`, a FIFO, a folder) and anything over the format's size limit *before*
//! reading it, so no parser ever sees more than a bounded number of bytes.

use std::io::Read;
use std::path::Path;

/// The kinds of file tabula reads, each with its own size limit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Point clouds: PCD and PLY frames and scans.
    Cloud,
    /// Triangle meshes: OBJ, STL, PLY with faces.
    Mesh,
    /// Robot descriptions: URDF, and the TOML description beside it.
    Robot,
    /// Scene files (TOML).
    Scene,
    /// PDDL domains, problems and plans.
    Pddl,
    /// Parameter files (TOML).
    Params,
}

impl Format {
    /// The name used in messages and in the `TABULA_MAX_<NAME>_MB` variable.
    pub fn name(self) -> &'static str {
        match self {
            Format::Cloud => "CLOUD",
            Format::Mesh => "MESH",
            Format::Robot => "ROBOT",
            Format::Scene => "SCENE",
            Format::Pddl => "PDDL",
            Format::Params => "PARAMS",
        }
    }

    /// Default limit in MiB: a 640×480 binary XYZRGB frame is 5 MB and a dense LiDAR
    /// sweep ~100 MB; real URDFs are under 1 MB (their meshes are separate files), and
    /// 8 MiB of XML already costs ~0.3 GB as a DOM; generated PDDL problems with a
    /// thousand objects are ~1 MB.
    fn default_mb(self) -> u64 {
        match self {
            Format::Cloud => 512,
            Format::Mesh => 256,
            Format::Robot => 8,
            Format::Scene => 8,
            Format::Pddl => 16,
            Format::Params => 1,
        }
    }

    /// The limit in bytes: `TABULA_MAX_<NAME>_MB` when set to a positive integer,
    /// else the default.
    pub fn max_bytes(self) -> u64 {
        let var = format!("TABULA_MAX_{}_MB", self.name());
        let mb = std::env::var(var)
            .ok()
            .and_then(|v| v.trim().parse::<u64>().ok())
            .filter(|&mb| mb > 0)
            .unwrap_or(self.default_mb());
        mb.saturating_mul(1 << 20)
    }
}

/// A file that was not read.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    #[error("cannot read {path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("{path} is not a regular file (a device, a pipe or a folder)")]
    NotAFile { path: String },
    #[error(
        "{path} is {size} bytes, over the {limit}-byte limit for {kind} files \
         (raise it with TABULA_MAX_{kind}_MB)"
    )]
    TooBig {
        path: String,
        size: u64,
        limit: u64,
        kind: &'static str,
    },
    #[error("{path} is not UTF-8 text (first bad byte at offset {offset})")]
    NotText { path: String, offset: usize },
    /// A parameter file that was read but is not valid (`origin` names it).
    #[error("{origin}: {message}")]
    Params { origin: String, message: String },
}

/// The deepest element nesting of XML text, counted before the XML reader (which
/// recurses) sees it: tags opened minus closed, skipping comments, declarations,
/// processing instructions and self-closing tags. Stops counting past `limit`.
pub fn xml_depth(text: &str, limit: usize) -> usize {
    let bytes = text.as_bytes();
    let (mut depth, mut deepest, mut i) = (0usize, 0usize, 0usize);
    while let Some(off) = bytes[i..].iter().position(|&b| b == b'<') {
        let start = i + off;
        let rest = &text[start..];
        let skip_to = |end: &str| {
            rest.find(end)
                .map_or(bytes.len(), |e| start + e + end.len())
        };
        if rest.starts_with("<!--") {
            i = skip_to("-->");
            continue;
        }
        if rest.starts_with("<![CDATA[") {
            i = skip_to("]]>");
            continue;
        }
        let close = rest.find('>').map_or(bytes.len(), |e| start + e);
        let tag = &text[start..close.min(bytes.len())];
        if tag.starts_with("</") {
            depth = depth.saturating_sub(1);
        } else if !(tag.starts_with("<?") || tag.starts_with("<!") || tag.ends_with('/')) {
            depth += 1;
            deepest = deepest.max(depth);
            if deepest > limit {
                return deepest;
            }
        }
        i = (close + 1).min(bytes.len());
    }
    deepest
}

/// A module's `Params` from a TOML file, or its defaults (SPEC's values) without one.
/// Every number is checked (finite, bounded) before deserializing, and the values'
/// ranges after (INPUT_POLICY.md).
pub fn load_params<T: serde::de::DeserializeOwned + Default + Validate>(
    path: Option<&Path>,
) -> Result<T, InputError> {
    match path {
        Some(p) => parse_params(&read_text(p, Format::Params)?, &p.display().to_string()),
        None => Ok(T::default()),
    }
}

/// A module's `Params` from TOML text (`origin` names it in errors), checked as
/// [`load_params`] checks a file.
pub fn parse_params<T: serde::de::DeserializeOwned + Validate>(
    text: &str,
    origin: &str,
) -> Result<T, InputError> {
    let invalid = |message: String| InputError::Params {
        origin: origin.to_string(),
        message,
    };
    check_toml_numbers(text).map_err(invalid)?;
    let params: T = toml::from_str(text).map_err(|e| invalid(toml_error(text, &e)))?;
    params.validate().map_err(invalid)?;
    Ok(params)
}

/// A TOML error as one line: where it is and toml's message, which names the key and
/// lists the valid ones (its display puts that on a later line, after a source
/// excerpt, where a one-line error loses it).
pub fn toml_error(text: &str, e: &toml::de::Error) -> String {
    let line = e.span().map_or(1, |s| {
        text.as_bytes()[..s.start.min(text.len())]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            + 1
    });
    // toml quotes a wrong-typed float in full: 1e-300 as 302 characters.
    let message: Vec<String> = e
        .message()
        .trim()
        .split('`')
        .map(|part| match part.parse::<f64>() {
            Ok(v) if part.len() > 24 => shown(v),
            _ => part.to_string(),
        })
        .collect();
    // Type errors name no key: the line's own key is the one.
    let key = text
        .lines()
        .nth(line - 1)
        .and_then(|l| l.split_once('='))
        .map(|(k, _)| k.trim())
        .filter(|k| !k.is_empty() && !k.starts_with('[') && k.len() <= 80)
        .filter(|k| !e.message().contains(&format!("`{k}`")));
    match key {
        Some(k) => format!("line {line}, `{k}`: {}", message.join("`")),
        None => format!("line {line}: {}", message.join("`")),
    }
}

/// The whole file, after checking that it is a regular file within `format`'s limit.
pub fn read_bytes(path: &Path, format: Format) -> Result<Vec<u8>, InputError> {
    let shown = clip(&path.display().to_string(), 200);
    let io = |source| InputError::Io {
        path: shown.clone(),
        source,
    };
    let meta = std::fs::metadata(path).map_err(io)?;
    if !meta.is_file() {
        return Err(InputError::NotAFile { path: shown });
    }
    let limit = format.max_bytes();
    let too_big = |size| InputError::TooBig {
        path: shown.clone(),
        size,
        limit,
        kind: format.name(),
    };
    if meta.len() > limit {
        return Err(too_big(meta.len()));
    }
    // The length can change between the check and the read (a file being written, a
    // procfs file reporting 0): read at most one byte more than the limit.
    let file = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(limit + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(too_big(bytes.len() as u64));
    }
    Ok(bytes)
}

/// [`read_bytes`] as UTF-8 text.
pub fn read_text(path: &Path, format: Format) -> Result<String, InputError> {
    let bytes = read_bytes(path, format)?;
    String::from_utf8(bytes).map_err(|e| InputError::NotText {
        path: clip(&path.display().to_string(), 200),
        offset: e.utf8_error().valid_up_to(),
    })
}

/// At most `max` characters of `s` (an ellipsis marks the cut), so that an error
/// quoting its input stays one readable line whatever the input holds.
pub fn clip(s: &str, max: usize) -> String {
    let s = s.lines().next().unwrap_or("");
    match s.char_indices().nth(max) {
        Some((i, _)) => format!("{}…", &s[..i]),
        None => s.to_string(),
    }
}

/// A number as a message shows it: four decimals in the range people type, else
/// scientific (`1e300`, not the 301 digits `{}` prints; `1e-300`, not `0.0000`).
pub fn shown(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e6).contains(&v.abs()) {
        format!("{v:.4}")
    } else {
        let exact = format!("{v:e}");
        if exact.len() <= 10 {
            exact
        } else {
            format!("{v:.4e}")
        }
    }
}

/// `value` when it is finite, else an error naming what it is.
pub fn finite(what: &str, value: f64) -> Result<f64, String> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(format!("{what} must be a finite number, got {value}"))
    }
}

/// The largest magnitude of a number in a parameter or scene file: nothing in metres,
/// seconds, radians or kilograms is meaningful beyond it, and beyond it products of
/// two values overflow to infinity.
pub const MAX_MAGNITUDE: f64 = 1e6;

/// The largest whole number in a parameter or scene file (iterations, counts, samples):
/// more is hours of work, never a setting.
pub const MAX_COUNT: i64 = 10_000_000;

/// TOML text whose every number is finite and within [`MAX_MAGNITUDE`] (floats) or
/// `0..=MAX_COUNT` (integers; seeds, the one exception, are any `u64`), with the key
/// named on failure — checked before deserializing, so no `Params` struct ever holds
/// a NaN, an infinity or a count that never ends.
pub fn check_toml_numbers(text: &str) -> Result<(), String> {
    fn walk(key: &str, v: &toml::Value) -> Result<(), String> {
        match v {
            toml::Value::Float(x) if !x.is_finite() || x.abs() > MAX_MAGNITUDE => Err(format!(
                "`{key}` = {x:e}: numbers must be finite and at most {MAX_MAGNITUDE:e} in size"
            )),
            toml::Value::Integer(i)
                if !key.ends_with("seed") && !(-MAX_COUNT..=MAX_COUNT).contains(i) =>
            {
                Err(format!(
                    "`{key}` = {i}: whole numbers must be at most {MAX_COUNT} in size"
                ))
            }
            toml::Value::Array(items) => items
                .iter()
                .enumerate()
                .try_for_each(|(i, item)| walk(&format!("{key}[{i}]"), item)),
            toml::Value::Table(t) => t.iter().try_for_each(|(k, item)| {
                let key = if key.is_empty() {
                    k.clone()
                } else {
                    format!("{key}.{k}")
                };
                walk(&key, item)
            }),
            _ => Ok(()),
        }
    }
    let table: toml::Table = text
        .parse()
        .map_err(|e: toml::de::Error| clip(&toml_error(text, &e), 300))?;
    table.iter().try_for_each(|(k, v)| walk(k, v))
}

/// Range checks of a `Params` struct (INPUT_POLICY.md): a size that divides, a step
/// that advances a loop or a fraction outside [0, 1] is refused with its key named,
/// before any work starts. `at` is the table the struct sits in (`""` at the top).
pub trait Validate {
    fn check(&self, at: &str) -> Result<(), String>;

    fn validate(&self) -> Result<(), String> {
        self.check("")
    }
}

fn key(at: &str, name: &str) -> String {
    if at.is_empty() {
        name.to_string()
    } else {
        format!("{at}.{name}")
    }
}

/// `v` in `[lo, hi]`.
pub fn check_in(at: &str, name: &str, v: f64, lo: f64, hi: f64) -> Result<(), String> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err(format!(
            "`{}` = {}: must be in [{lo}, {hi}]",
            key(at, name),
            shown(v)
        ))
    }
}

/// `v` > 0 (a size, a step, a time): a zero divides or never advances.
pub fn check_positive(at: &str, name: &str, v: f64) -> Result<(), String> {
    if v.is_finite() && v > 0.0 && v <= MAX_MAGNITUDE {
        Ok(())
    } else {
        Err(format!(
            "`{}` = {}: must be > 0 and at most {MAX_MAGNITUDE:e}",
            key(at, name),
            shown(v)
        ))
    }
}

/// `v` ≥ 0 (a margin, a tolerance, a padding).
pub fn check_non_negative(at: &str, name: &str, v: f64) -> Result<(), String> {
    check_in(at, name, v, 0.0, MAX_MAGNITUDE)
}

/// `v` = 0 (the step is off) or in `[lo, hi]`: a voxel or leaf size, where a tiny one
/// overflows the grid's integer keys and a huge one merges everything.
pub fn check_off_or_in(at: &str, name: &str, v: f64, lo: f64, hi: f64) -> Result<(), String> {
    if v == 0.0 {
        Ok(())
    } else {
        check_in(at, name, v, lo, hi).map_err(|e| format!("{e} (or 0 to turn it off)"))
    }
}

/// A count of at least `min`.
pub fn check_count(at: &str, name: &str, v: usize, min: usize) -> Result<(), String> {
    if v >= min && v as i64 <= MAX_COUNT {
        Ok(())
    } else {
        Err(format!("`{}` = {v}: must be at least {min}", key(at, name)))
    }
}

/// The nested table `name` of a struct at `at`.
pub fn nested(at: &str, name: &str) -> String {
    key(at, name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_folders_and_missing_files_are_refused_before_reading() {
        assert!(matches!(
            read_bytes(Path::new("/dev/zero"), Format::Cloud),
            Err(InputError::NotAFile { .. })
        ));
        assert!(matches!(
            read_bytes(Path::new("/"), Format::Cloud),
            Err(InputError::NotAFile { .. })
        ));
        assert!(matches!(
            read_bytes(Path::new("/no/such/file"), Format::Cloud),
            Err(InputError::Io { .. })
        ));
    }

    #[test]
    fn toml_numbers_are_finite_and_bounded() {
        assert!(
            check_toml_numbers("a = 1.5\n[b]\nc = [1, 2]\nseed = 18446744073709551615").is_err()
        );
        assert!(check_toml_numbers("a = 1.5\n[b]\nc = [1, 2]\nrandom_seed = 9").is_ok());
        for bad in [
            "a = nan",
            "a = inf",
            "[t]\nx = -inf",
            "a = 1e300",
            "n = 99999999999",
            "v = [[1.0, nan]]",
        ] {
            let e = check_toml_numbers(bad).unwrap_err();
            assert!(e.contains('`'), "{bad}: {e}");
        }
    }

    #[test]
    fn clip_keeps_one_short_line() {
        assert_eq!(clip("abc", 5), "abc");
        assert_eq!(clip("abcdef", 3), "abc…");
        assert_eq!(clip("ab\ncd", 5), "ab");
        assert_eq!(clip("ééé", 2), "éé…");
    }
}
