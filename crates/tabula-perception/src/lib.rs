//! Perception for tabula (PCL's role): point-cloud files, RANSAC planes, and seed 002's
//! tabletop pipeline — table plane, hull, prism, objects — on organized depth frames.
//! Work in progress: filters, normals, convexity-based segmentation, free-space maps and
//! the self-filter of issue 4 come next.

pub mod pcd;
pub mod plane;
pub mod tabletop;

pub use pcd::{PcdError, read_pcd};
pub use plane::{Plane, RansacParams, ransac_plane};
pub use tabletop::{Tabletop, TabletopError, TabletopParams, extract, to_world};
