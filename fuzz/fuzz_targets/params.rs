//! Any text as a parameter file of every module: the policy's number check, then
//! deserializing, then each module's own validation — an error or parameters, never a
//! panic. Run: `cargo +nightly fuzz run params`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fn load<T: serde::de::DeserializeOwned>(text: &str) -> Option<T> {
    tabula_geom::input::check_toml_numbers(text).ok()?;
    toml::from_str(text).ok()
}

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let _ = load::<tabula_perception::TabletopParams>(&text);
    let _ = load::<tabula_tasks::place::PlaceParams>(&text);
    let _ = load::<tabula_tasks::pick_place::PickPlaceParams>(&text);
    let _ = load::<tabula_tasks::stable::StableParams>(&text);
    if let Some(p) = load::<tabula_tasks::clear::ClearParams>(&text) {
        let _ = p.validate();
    }
    let _ = load::<tabula_robot::ik::NumericIkParams>(&text);
});
