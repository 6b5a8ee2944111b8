//! Perception for tabula (PCL's role): point-cloud files, RANSAC planes, and seed 002's
//! tabletop pipeline — table plane, hull, prism, objects — on organized depth frames.
//! Work in progress: filters, normals, convexity-based segmentation, free-space maps and
//! the self-filter of issue 4 come next.

pub mod eval;
pub mod filters;
pub mod freespace;
mod kd;
pub mod plane;
pub mod selffilter;
pub mod surfaces;
pub mod tabletop;

pub use plane::{Plane, RansacParams, ransac_plane};
pub use surfaces::{Surface, SurfaceParams, find_surfaces};
pub use tabletop::{Tabletop, TabletopError, TabletopParams, extract, to_world};
pub use tabula_geom::{PcdError, PlyError, read_pcd, read_ply};
