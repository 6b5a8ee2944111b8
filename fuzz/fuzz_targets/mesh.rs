//! Any bytes as an OBJ, an STL, a PLY or a COLLADA mesh: the reader gives triangles or an error,
//! and what it gives yields a collision shape and stable poses or an error — never a
//! panic. Run: `cargo +nightly fuzz run mesh`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tabula_tasks::stable::{StableParams, of_mesh};

fuzz_target!(|data: &[u8]| {
    for ext in ["obj", "stl", "ply", "dae"] {
        if let Ok((points, triangles)) = tabula_geom::mesh::parse_mesh(data, ext, [1.0; 3]) {
            // Large meshes are the reader's business; the shape and the stable poses
            // are fuzzed on small ones so that each input runs in milliseconds.
            if points.len() <= 64 {
                let _ = tabula_geom::mesh::mesh_shape(&points, &triangles, false);
                let _ = of_mesh(&points, &triangles, &StableParams::default());
            }
        }
    }
});
