//! Convex decompositions kept on disk, keyed by the mesh they came from: V-HACD takes
//! seconds on a real robot's concave links (the PR2's torso and fingers), and every
//! command that checks collisions needs them, so the second load of a robot reads the
//! parts instead of decomposing again. The cache is an optimisation only: anything
//! missing, unreadable or implausible in it is recomputed, never trusted.
//!
//! Folder: `$TABULA_CACHE_DIR`, else `$XDG_CACHE_HOME/tabula`, else `~/.cache/tabula`.

use crate::Vec3;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};

/// Most parts and points a cached decomposition may hold (V-HACD's defaults give at
/// most a few hundred parts of a few dozen points).
const MAX_PARTS: usize = 4096;
const MAX_POINTS: usize = 1 << 20;
const MAGIC: &[u8; 8] = b"TBLDCMP1";

/// The key of a mesh: its vertices and triangles, bit for bit.
pub fn key(points: &[Vec3], triangles: &[[u32; 3]]) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for p in points {
        p.to_array().map(f64::to_bits).hash(&mut h);
    }
    triangles.hash(&mut h);
    h.finish()
}

fn folder() -> Option<PathBuf> {
    let env = |k: &str| {
        std::env::var_os(k)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    env("TABULA_CACHE_DIR")
        .or_else(|| env("XDG_CACHE_HOME").map(|d| d.join("tabula")))
        .or_else(|| env("HOME").map(|d| d.join(".cache/tabula")))
        .map(|d| d.join("decompositions"))
}

fn file(dir: &Path, key: u64) -> PathBuf {
    dir.join(format!("{key:016x}.bin"))
}

/// The convex parts (their points) stored for `key`, if a plausible entry exists.
pub fn load(key: u64) -> Option<Vec<Vec<Vec3>>> {
    load_from(&folder()?, key)
}

/// Stores the parts for `key` (written whole, then renamed, so a reader never sees
/// half a file); failures are ignored — the cache is only a shortcut.
pub fn store(key: u64, parts: &[Vec<Vec3>]) {
    if let Some(dir) = folder() {
        store_in(&dir, key, parts);
    }
}

fn load_from(dir: &Path, key: u64) -> Option<Vec<Vec<Vec3>>> {
    let path = file(dir, key);
    let meta = std::fs::metadata(&path).ok()?;
    if !meta.is_file() || meta.len() > (MAX_POINTS as u64) * 24 + (MAX_PARTS as u64) * 4 + 16 {
        return None;
    }
    let bytes = std::fs::read(&path).ok()?;
    let mut at = bytes.strip_prefix(MAGIC.as_slice())?;
    let u32_next = |at: &mut &[u8]| -> Option<usize> {
        let (head, rest) = at.split_first_chunk::<4>()?;
        *at = rest;
        Some(u32::from_le_bytes(*head) as usize)
    };
    let parts = u32_next(&mut at)?;
    if parts == 0 || parts > MAX_PARTS {
        return None;
    }
    let mut out = Vec::with_capacity(parts);
    let mut total = 0;
    for _ in 0..parts {
        let n = u32_next(&mut at)?;
        total += n;
        if n < 4 || total > MAX_POINTS {
            return None;
        }
        let mut part = Vec::with_capacity(n);
        for _ in 0..n {
            let (xyz, rest) = at.split_first_chunk::<24>()?;
            at = rest;
            let f =
                |k: usize| f64::from_le_bytes(xyz[8 * k..8 * k + 8].try_into().unwrap_or_default());
            let p = Vec3::new(f(0), f(1), f(2));
            if !p.is_finite() || p.abs().max_element() > crate::input::MAX_MAGNITUDE {
                return None;
            }
            part.push(p);
        }
        out.push(part);
    }
    at.is_empty().then_some(out)
}

fn store_in(dir: &Path, key: u64, parts: &[Vec<Vec3>]) {
    let path = file(dir, key);
    if parts.is_empty() || parts.len() > MAX_PARTS {
        return;
    }
    let mut bytes = MAGIC.to_vec();
    bytes.extend((parts.len() as u32).to_le_bytes());
    for part in parts {
        bytes.extend((part.len() as u32).to_le_bytes());
        for p in part {
            for v in p.to_array() {
                bytes.extend(v.to_le_bytes());
            }
        }
    }
    let tmp = dir.join(format!("{key:016x}.{}.tmp", std::process::id()));
    if std::fs::create_dir_all(dir).is_ok() && std::fs::write(&tmp, &bytes).is_ok() {
        let _ = std::fs::rename(&tmp, &path);
    }
    let _ = std::fs::remove_file(&tmp);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_round_trip_and_damaged_entries_are_ignored() {
        let dir = std::env::temp_dir().join(format!("tabula-cache-{}", std::process::id()));
        let parts = vec![
            vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
            vec![Vec3::ONE; 5],
        ];
        let k = key(&parts[0], &[[0, 1, 2]]);
        assert_eq!(load_from(&dir, k), None);
        store_in(&dir, k, &parts);
        assert_eq!(load_from(&dir, k), Some(parts));
        let path = file(&dir, k);
        let mut bytes = std::fs::read(&path).unwrap();
        bytes.truncate(bytes.len() - 3);
        std::fs::write(&path, &bytes).unwrap();
        assert_eq!(load_from(&dir, k), None, "a truncated entry is recomputed");
        std::fs::remove_dir_all(&dir).ok();
    }
}
