//! The input policy's command-line side (INPUT_POLICY.md): every number a user types
//! is parsed here, so a NaN, an infinity or a count that would exhaust memory is a
//! usage error naming the flag, before any work starts.

/// A command line clap accepted that is still incomplete (a subcommand or an argument
/// it cannot require because `--print-params` stands in for it): exit 64, as clap's.
#[derive(Debug)]
pub struct Usage(pub String);

impl std::fmt::Display for Usage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} (see --help)", self.0)
    }
}

impl std::error::Error for Usage {}

/// The value of an optional argument clap requires unless `--print-params` is given.
pub fn given<'a>(
    v: &'a Option<std::path::PathBuf>,
    flag: &str,
) -> Result<&'a std::path::Path, Usage> {
    v.as_deref().ok_or_else(|| {
        Usage(format!(
            "the following required argument was not provided: {flag}"
        ))
    })
}

/// A finite number (coordinates, joint values, margins).
pub fn finite(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{}` is not a number", tabula_geom::input::clip(s, 40)))?;
    tabula_geom::input::finite("the value", v)
}

/// The longest time limit accepted: beyond 11.6 days a limit means "none", and larger
/// values overflow deadlines.
pub const MAX_SECONDS: f64 = 1e6;

/// A time limit in seconds: finite, positive, at most [`MAX_SECONDS`].
pub fn seconds(s: &str) -> Result<f64, String> {
    let v = finite(s)?;
    if v > 0.0 && v <= MAX_SECONDS {
        Ok(v)
    } else {
        Err(format!(
            "a time limit must be in (0, {MAX_SECONDS}] s, got {v}"
        ))
    }
}

/// A publishing rate in Hz: 0 (off) to 1 kHz.
#[cfg(feature = "ros")]
pub fn rate(s: &str) -> Result<f64, String> {
    let v = finite(s)?;
    if (0.0..=1000.0).contains(&v) {
        Ok(v)
    } else {
        Err(format!("a rate must be in [0, 1000] Hz, got {v}"))
    }
}

/// The largest seed accepted: 2^53 − 1, exact in JSON and far from where seed + trial
/// would wrap (a run of seeds counts up from the one given).
pub const MAX_SEED: u64 = (1 << 53) - 1;

/// A random seed: a whole number from 0 to [`MAX_SEED`].
pub fn seed(s: &str) -> Result<u64, String> {
    s.trim()
        .parse::<u64>()
        .ok()
        .filter(|v| *v <= MAX_SEED)
        .ok_or_else(|| {
            format!(
                "`{}` is not a seed: a whole number from 0 to {MAX_SEED}",
                tabula_geom::input::clip(s, 40)
            )
        })
}

/// A count of runs, poses, scenes or repetitions: 1 to 1,000,000 (each unit of work is
/// at least microseconds, so the cap is days of work; beyond it a typo, never a wish).
pub fn count(s: &str) -> Result<usize, String> {
    bounded(s, 1, 1_000_000)
}

/// [`count`] for the seeds-and-runs counters kept as `u64`.
pub fn count_u64(s: &str) -> Result<u64, String> {
    count(s).map(|v| v as u64)
}

/// A count of objects in a generated problem or scene: 1 to 10,000 (grounding grows
/// with the square of it; 10,000 is already minutes).
pub fn objects(s: &str) -> Result<usize, String> {
    bounded(s, 1, 10_000)
}

/// An image side in pixels: 1 to 16,384.
pub fn pixels(s: &str) -> Result<usize, String> {
    bounded(s, 1, 16_384)
}

fn bounded(s: &str, lo: usize, hi: usize) -> Result<usize, String> {
    let v: u64 = s.trim().parse().map_err(|_| {
        format!(
            "`{}` is not a whole number from {lo} to {hi}",
            tabula_geom::input::clip(s, 40)
        )
    })?;
    usize::try_from(v)
        .ok()
        .filter(|v| (lo..=hi).contains(v))
        .ok_or_else(|| format!("{v} is out of range: from {lo} to {hi}"))
}

/// How robot files given to any command load (global flags): xacro arguments, package
/// folders and the SRDF, as `xacro`, `ROS_PACKAGE_PATH` and MoveIt take them.
#[derive(clap::Args, Debug, Default)]
pub struct RobotFileArgs {
    /// A xacro argument for every `--robot` that is a .xacro file, as on xacro's
    /// command line (`ur_type:=ur5e`, `hand:=true`); repeatable.
    #[arg(long = "xacro-arg", value_name = "NAME:=VALUE", value_parser = xacro_arg, global = true)]
    pub xacro_args: Vec<(String, String)>,
    /// A folder of ROS packages (or a package folder) searched for `$(find pkg)` and
    /// `package://pkg/…` before `ROS_PACKAGE_PATH`; repeatable.
    #[arg(long = "package-path", value_name = "DIR", global = true)]
    pub package_paths: Vec<std::path::PathBuf>,
    /// The robot's MoveIt SRDF (groups, named states, allowed collisions); by default
    /// the `.srdf` beside the URDF, if there is one.
    #[arg(long, value_name = "FILE", global = true)]
    pub srdf: Option<std::path::PathBuf>,
}

impl RobotFileArgs {
    /// Makes these the options every robot file loads with.
    pub fn install(&self) -> Result<(), String> {
        if let Some(bad) = self.package_paths.iter().find(|p| !p.is_dir()) {
            return Err(format!("--package-path {}: not a folder", bad.display()));
        }
        if let Some(s) = &self.srdf
            && !s.is_file()
        {
            let what = if s.exists() {
                "not a regular file"
            } else {
                "no such file"
            };
            return Err(format!("--srdf {}: {what}", s.display()));
        }
        tabula_robot::robots::set_default_options(tabula_robot::robots::LoadOptions {
            xacro_args: self.xacro_args.clone(),
            packages: tabula_robot::packages::PackagePaths::new(self.package_paths.clone()),
            srdf: self.srdf.clone(),
        });
        Ok(())
    }
}

/// `NAME:=VALUE` (xacro's form; `NAME=VALUE` is taken too).
fn xacro_arg(s: &str) -> Result<(String, String), String> {
    let (name, value) = s
        .split_once(":=")
        .or_else(|| s.split_once('='))
        .ok_or_else(|| format!("`{}` is not NAME:=VALUE", tabula_geom::input::clip(s, 40)))?;
    let name = name.trim();
    if name.is_empty() || !name.chars().all(|c| c.is_alphanumeric() || c == '_') {
        return Err(format!(
            "`{}` is not a xacro argument name",
            tabula_geom::input::clip(name, 40)
        ));
    }
    Ok((name.to_string(), value.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn non_finite_and_out_of_range_values_are_refused() {
        for bad in ["nan", "inf", "-inf", "1e999", "x", ""] {
            assert!(finite(bad).is_err(), "{bad}");
        }
        assert_eq!(finite(" -0.5 "), Ok(-0.5));
        for bad in ["0", "-1", "1e300", "nan", "inf"] {
            assert!(seconds(bad).is_err(), "{bad}");
        }
        for bad in ["0", "-1", "18446744073709551615", "1e3", "1000001"] {
            assert!(count(bad).is_err(), "{bad}");
        }
        assert_eq!(count("1000000"), Ok(1_000_000));
        assert!(pixels("4294967295").is_err());
        assert!(seed("18446744073709551615").is_err() && seed("-1").is_err());
        assert_eq!(seed("9007199254740991"), Ok(MAX_SEED));
        assert_eq!(
            xacro_arg("ur_type:=ur5e"),
            Ok(("ur_type".into(), "ur5e".into()))
        );
        assert!(xacro_arg("nothing").is_err() && xacro_arg(":=x").is_err());
    }
}

/// The command line with negative numbers in exponent form (`-5e-3`, `-1E+2`) written
/// out in plain decimals (`-0.005`, the same `f64`): clap takes a leading `-` for a
/// flag unless the rest looks like a number, and its test knows no signed exponent.
pub fn negative_exponents(
    args: impl IntoIterator<Item = std::ffi::OsString>,
) -> Vec<std::ffi::OsString> {
    args.into_iter()
        .map(|a| {
            let Some(s) = a.to_str() else { return a };
            let digit_after_sign = s
                .strip_prefix('-')
                .and_then(|r| r.chars().next())
                .is_some_and(|c| c.is_ascii_digit() || c == '.');
            match s.parse::<f64>() {
                Ok(v) if digit_after_sign && s.contains(['e', 'E']) && v.is_finite() => {
                    format!("{v}").into()
                }
                _ => a,
            }
        })
        .collect()
}

#[cfg(test)]
mod exponent_tests {
    use super::negative_exponents;

    #[test]
    fn negative_exponents_become_plain_decimals_of_the_same_value() {
        let args = [
            "tabula", "-5e-3", "-1E+2", "-v", "--x", "-", "5e-3", "-1e-300",
        ];
        let out = negative_exponents(args.iter().map(Into::into));
        let out: Vec<&str> = out.iter().map(|a| a.to_str().unwrap()).collect();
        assert_eq!(
            &out[..7],
            ["tabula", "-0.005", "-100", "-v", "--x", "-", "5e-3"]
        );
        assert_eq!(out[7].parse::<f64>().unwrap(), -1e-300);
    }
}
