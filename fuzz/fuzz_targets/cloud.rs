//! Point-cloud files: any bytes give a cloud or an error, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = tabula_geom::read_pcd(data);
    let _ = tabula_geom::read_ply(data);
});
