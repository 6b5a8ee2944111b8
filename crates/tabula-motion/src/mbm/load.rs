//! MotionBenchMaker problem sets from disk: a folder of set folders (or one set folder)
//! holding `sceneNNNN.yaml` / `requestNNNN.yaml` pairs, or the same as a `.tar.bz2` /
//! `.tar` archive — read in one pass, every entry bounded in size and number.

use super::MbmError;
use crate::moveit::{Limits, MotionRequest, PlanningScene};
use std::collections::BTreeMap;
use std::io::Read;
use std::path::Path;

/// One problem: a scene and a request, by set and number.
#[derive(Clone)]
pub struct MbmProblem {
    pub set: String,
    pub index: u32,
    pub scene: PlanningScene,
    pub request: MotionRequest,
}

/// Most files one problem folder or archive may hold (MBM's sets are 100 pairs each).
pub const MAX_FILES: usize = 100_000;
/// Most bytes decompressed from an archive in all.
pub const MAX_TOTAL_BYTES: u64 = 4 << 30;

#[derive(Default)]
struct Pair {
    scene: Option<(String, String)>,
    request: Option<(String, String)>,
}

/// Reads every problem under `path` (sorted by set, then number). A scene without its
/// request (or the reverse) is an error naming it, as is any file that does not parse.
pub fn load(path: &Path, limits: &Limits) -> Result<Vec<MbmProblem>, MbmError> {
    let mut pairs: BTreeMap<(String, u32), Pair> = BTreeMap::new();
    let meta =
        std::fs::metadata(path).map_err(|e| MbmError::Io(format!("{}: {e}", path.display())))?;
    if meta.is_dir() {
        read_folder(path, &mut pairs, limits)?;
    } else if meta.is_file() {
        read_archive(path, &mut pairs, limits)?;
    } else {
        return Err(MbmError::Io(format!(
            "{} is neither a folder nor a file",
            path.display()
        )));
    }
    if pairs.is_empty() {
        return Err(MbmError::Empty(path.display().to_string()));
    }
    pairs
        .into_iter()
        .map(|((set, index), pair)| {
            let (Some((scene_name, scene)), Some((request_name, request))) =
                (pair.scene, pair.request)
            else {
                return Err(MbmError::Unpaired(format!(
                    "{set}: problem {index:04} lacks its scene or its request"
                )));
            };
            let scene = PlanningScene::from_yaml(&scene, limits)
                .map_err(|e| MbmError::Parse(format!("{scene_name}: {e}")))?;
            let request = MotionRequest::from_yaml(&request, limits)
                .map_err(|e| MbmError::Parse(format!("{request_name}: {e}")))?;
            Ok(MbmProblem {
                set,
                index,
                scene,
                request,
            })
        })
        .collect()
}

/// `sceneNNNN.yaml` → (`scene`, NNNN); anything else → `None`.
fn problem_file(name: &str) -> Option<(&'static str, u32)> {
    let stem = name
        .strip_suffix(".yaml")
        .or_else(|| name.strip_suffix(".yml"))?;
    for kind in ["scene", "request"] {
        if let Some(n) = stem.strip_prefix(kind)
            && !n.is_empty()
            && n.len() <= 9
            && n.bytes().all(|b| b.is_ascii_digit())
        {
            return Some((kind, n.parse().ok()?));
        }
    }
    None
}

fn add(
    pairs: &mut BTreeMap<(String, u32), Pair>,
    set: &str,
    file: &str,
    origin: String,
    text: String,
) -> Result<(), MbmError> {
    let Some((kind, index)) = problem_file(file) else {
        return Ok(());
    };
    if pairs.len() >= MAX_FILES {
        return Err(MbmError::TooLarge(format!(
            "more than {MAX_FILES} problems"
        )));
    }
    let pair = pairs.entry((set.to_string(), index)).or_default();
    let slot = if kind == "scene" {
        &mut pair.scene
    } else {
        &mut pair.request
    };
    if slot.is_some() {
        return Err(MbmError::Unpaired(format!(
            "{origin}: a second {kind} {index:04} in set `{set}`"
        )));
    }
    *slot = Some((origin, text));
    Ok(())
}

fn read_folder(
    root: &Path,
    pairs: &mut BTreeMap<(String, u32), Pair>,
    limits: &Limits,
) -> Result<(), MbmError> {
    let list = |dir: &Path| -> Result<Vec<std::fs::DirEntry>, MbmError> {
        let mut v: Vec<_> = std::fs::read_dir(dir)
            .map_err(|e| MbmError::Io(format!("{}: {e}", dir.display())))?
            .filter_map(Result::ok)
            .take(MAX_FILES + 1)
            .collect();
        if v.len() > MAX_FILES {
            return Err(MbmError::TooLarge(format!(
                "{}: more than {MAX_FILES} entries",
                dir.display()
            )));
        }
        v.sort_by_key(|e| e.file_name());
        Ok(v)
    };
    let set_of_root = root
        .file_name()
        .map_or("problems".into(), |n| n.to_string_lossy().to_string());
    let mut folders = vec![(set_of_root, root.to_path_buf())];
    for e in list(root)? {
        if e.file_type().is_ok_and(|t| t.is_dir())
            && !e.file_name().to_string_lossy().starts_with('.')
        {
            folders.push((e.file_name().to_string_lossy().to_string(), e.path()));
        }
    }
    for (set, dir) in folders {
        for e in list(&dir)? {
            let name = e.file_name().to_string_lossy().to_string();
            if problem_file(&name).is_none() {
                continue;
            }
            let text = tabula_geom::input::read_text(&e.path(), tabula_geom::input::Format::Scene)
                .map_err(|err| MbmError::Io(err.to_string()))?;
            if text.len() > limits.bytes {
                return Err(MbmError::TooLarge(format!(
                    "{}: over {} bytes",
                    e.path().display(),
                    limits.bytes
                )));
            }
            add(pairs, &set, &name, e.path().display().to_string(), text)?;
        }
    }
    Ok(())
}

fn read_archive(
    path: &Path,
    pairs: &mut BTreeMap<(String, u32), Pair>,
    limits: &Limits,
) -> Result<(), MbmError> {
    let file =
        std::fs::File::open(path).map_err(|e| MbmError::Io(format!("{}: {e}", path.display())))?;
    let name = path.to_string_lossy();
    let reader: Box<dyn Read> =
        if name.ends_with(".tar.bz2") || name.ends_with(".tbz2") || name.ends_with(".tbz") {
            Box::new(bzip2::read::BzDecoder::new(std::io::BufReader::new(file)))
        } else if name.ends_with(".tar") {
            Box::new(std::io::BufReader::new(file))
        } else {
            return Err(MbmError::Io(format!(
                "{}: expected a folder, a .tar.bz2 or a .tar",
                path.display()
            )));
        };
    let archive_error = |e: std::io::Error| MbmError::Io(format!("{}: {e}", path.display()));
    let mut archive = tar::Archive::new(reader);
    let mut total = 0u64;
    for (count, entry) in archive.entries().map_err(archive_error)?.enumerate() {
        if count > 4 * MAX_FILES {
            return Err(MbmError::TooLarge(format!(
                "{}: more than {} entries",
                path.display(),
                4 * MAX_FILES
            )));
        }
        let mut entry = entry.map_err(archive_error)?;
        if !entry.header().entry_type().is_file() {
            continue;
        }
        let entry_path = entry.path().map_err(archive_error)?.to_path_buf();
        let Some(file) = entry_path
            .file_name()
            .map(|f| f.to_string_lossy().to_string())
        else {
            continue;
        };
        if problem_file(&file).is_none() {
            continue;
        }
        let set = entry_path
            .parent()
            .and_then(Path::file_name)
            .map_or("problems".into(), |s| s.to_string_lossy().to_string());
        let size = entry.header().size().map_err(archive_error)?;
        total = total.saturating_add(size);
        if size > limits.bytes as u64 || total > MAX_TOTAL_BYTES {
            return Err(MbmError::TooLarge(format!(
                "{}: {} is {size} bytes (limit {} per file, {MAX_TOTAL_BYTES} in all)",
                path.display(),
                entry_path.display(),
                limits.bytes
            )));
        }
        let mut text = String::with_capacity(size as usize);
        entry
            .by_ref()
            .take(limits.bytes as u64 + 1)
            .read_to_string(&mut text)
            .map_err(|e| {
                MbmError::Io(format!("{}: {}: {e}", path.display(), entry_path.display()))
            })?;
        add(
            pairs,
            &set,
            &file,
            format!("{}:{}", path.display(), entry_path.display()),
            text,
        )?;
    }
    Ok(())
}
