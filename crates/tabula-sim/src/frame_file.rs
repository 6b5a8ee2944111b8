//! A captured frame written as a sensor file: PCD in the camera's optical frame, or in
//! the world with the camera's pose as its `VIEWPOINT` (as PCL writes registered
//! clouds), or PLY; and its per-pixel labels as JSON.

use crate::camera::DepthFrame;
use std::io::Write;
use std::path::Path;
use tabula_geom::{PcdEncoding, PlyEncoding};

/// How a frame is written.
#[derive(Debug, Clone, Copy, Default)]
pub struct FrameFile {
    /// Binary instead of ASCII.
    pub binary: bool,
    /// Points in the world frame with the camera as `VIEWPOINT` (PCD only).
    pub world: bool,
}

/// Why a frame was not written.
#[derive(Debug, thiserror::Error)]
pub enum FrameFileError {
    #[error("a frame in the world frame needs a PCD (PLY has no VIEWPOINT for the camera's pose)")]
    WorldNeedsPcd,
    #[error("cannot write {path}: {error}")]
    Io { path: String, error: std::io::Error },
}

impl DepthFrame {
    /// Writes the cloud to `path`: PLY when it ends in `.ply`, else PCD.
    pub fn write_file(&self, path: &Path, how: FrameFile) -> Result<(), FrameFileError> {
        let ply = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("ply"));
        if ply && how.world {
            return Err(FrameFileError::WorldNeedsPcd);
        }
        let io = |error| FrameFileError::Io {
            path: path.display().to_string(),
            error,
        };
        let mut out = std::io::BufWriter::new(std::fs::File::create(path).map_err(io)?);
        if ply {
            let encoding = match how.binary {
                true => PlyEncoding::BinaryLittleEndian,
                false => PlyEncoding::Ascii,
            };
            tabula_geom::write_ply(&self.cloud, &mut out, encoding).map_err(io)?;
        } else {
            let encoding = match how.binary {
                true => PcdEncoding::Binary,
                false => PcdEncoding::Ascii,
            };
            if how.world {
                let viewpoint = &self.world_from_camera;
                self.cloud
                    .transformed(viewpoint)
                    .write_pcd_with(
                        &mut out,
                        encoding,
                        &tabula_geom::PcdExtras {
                            viewpoint: *viewpoint,
                            ..Default::default()
                        },
                    )
                    .map_err(io)?;
            } else {
                self.cloud.write_pcd(&mut out, encoding).map_err(io)?;
            }
        }
        // Dropping a BufWriter swallows the last write's error (a full disk).
        out.flush().map_err(io)
    }

    /// Writes the per-pixel ground-truth labels and their names as JSON to `path`.
    pub fn write_labels(&self, path: &Path) -> Result<(), FrameFileError> {
        let v = serde_json::json!({"width": self.width, "height": self.height, "names": self.label_names, "labels": self.labels});
        std::fs::write(path, v.to_string()).map_err(|error| FrameFileError::Io {
            path: path.display().to_string(),
            error,
        })
    }
}
