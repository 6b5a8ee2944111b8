//! Any bytes as a PDDL domain, as a problem of the seed's domain and as a plan: a parse
//! or a located error, never a panic; a problem that parses is grounded and searched
//! under a 50 ms deadline. Run: `cargo +nightly fuzz run pddl`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::time::{Duration, Instant};
use tabula_pddl::{GroundOptions, Planner, SearchMode};

const DOMAIN: &str = include_str!("../../pddl/tablewclear-domain.pddl");

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let _ = tabula_pddl::parse_domain(&text);
    if let Ok(domain) = tabula_pddl::parse_domain(DOMAIN)
        && let Ok(problem) = tabula_pddl::parse_problem(&text, &domain)
    {
        let options = GroundOptions {
            deadline: Some(Instant::now() + Duration::from_millis(50)),
            ..GroundOptions::default()
        };
        if let Ok(planner) = Planner::new(domain, problem, options) {
            let _ = planner.plan(SearchMode::Fast, Some(Duration::from_millis(50)));
        }
    }
    let _ = tabula_pddl::parse_plan(&text);
});
