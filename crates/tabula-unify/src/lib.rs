//! Build-only (the workspace-hack pattern): depending on this crate turns on, in the
//! demo's and the Python package's own builds, the dependency features the workspace's
//! test build turns on, so both reuse its compiled crates. See `Cargo.toml`.
