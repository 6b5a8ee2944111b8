//! Any text as a parameter file of every module: the policy's number check, then
//! deserializing, then each module's range checks (`Validate`) — an error or parameters,
//! never a panic. Run: `cargo +nightly fuzz run params`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tabula_geom::input::Validate;

fn load<T: serde::de::DeserializeOwned + Validate>(text: &str) {
    if tabula_geom::input::check_toml_numbers(text).is_ok()
        && let Ok(params) = toml::from_str::<T>(text)
    {
        let _ = params.validate();
    }
}

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    load::<tabula_perception::TabletopParams>(&text);
    load::<tabula_tasks::place::PlaceParams>(&text);
    load::<tabula_tasks::pick_place::PickPlaceParams>(&text);
    load::<tabula_tasks::stable::StableParams>(&text);
    load::<tabula_tasks::clear::ClearParams>(&text);
    load::<tabula_robot::ik::NumericIkParams>(&text);
});
