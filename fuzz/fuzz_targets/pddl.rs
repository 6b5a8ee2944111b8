//! Any bytes as a PDDL domain, as a problem of the seed's domain and as a plan: a parse or a
//! located error, never a panic. Run: `cargo +nightly fuzz run pddl`.
#![no_main]

use libfuzzer_sys::fuzz_target;

const DOMAIN: &str = include_str!("../../pddl/tablewclear-domain.pddl");

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let _ = tabula_pddl::parse_domain(&text);
    if let Ok(domain) = tabula_pddl::parse_domain(DOMAIN) {
        let _ = tabula_pddl::parse_problem(&text, &domain);
    }
    let _ = tabula_pddl::parse_plan(&text);
});
