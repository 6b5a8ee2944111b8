use tabula_pddl::*;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let d = parse_domain(&std::fs::read_to_string(&args[1]).unwrap()).unwrap();
    let p = parse_problem(&std::fs::read_to_string(&args[2]).unwrap(), &d).unwrap();
    let t0 = std::time::Instant::now();
    for _ in 0..20 {
        let t = GroundTask::new(&d, &p, &GroundOptions::default()).unwrap();
        std::hint::black_box(t);
    }
    println!("{:?} per grounding", t0.elapsed() / 20);
}
