//! Perception for tabula (PCL's role): filters and normals on organized or unorganized
//! clouds, RANSAC planes, seed 000's surface search, seed 002's tabletop pipeline with a
//! segmentation that separates touching and stacked objects, free-space maps that
//! answer where a footprint fits, the robot self-filter, and scoring against the
//! simulator's labels. Point-cloud files (PCD, PLY) live in `tabula-geom`.

pub mod eval;
pub mod filters;
pub mod frame;
pub mod freespace;
mod kd;
pub mod params;
pub mod plane;
pub mod score;
pub mod segment;
pub mod selffilter;
pub mod stray;
pub mod support;
pub mod surfaces;
pub mod tabletop;

pub use plane::{Plane, RansacParams, ransac_plane};
pub use surfaces::{Surface, SurfaceParams, find_surfaces};
pub use tabletop::{Tabletop, TabletopError, TabletopParams, extract, to_world};
pub use tabula_geom::{PcdError, PlyError, read_pcd, read_ply};
