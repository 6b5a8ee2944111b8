//! The parser on the seed's domain and problems, classic constructs, and bad input.

use proptest::prelude::*;
use tabula_pddl::*;

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../pddl/");

fn read(name: &str) -> String {
    std::fs::read_to_string(format!("{DATA}{name}")).unwrap()
}

#[test]
fn seed_domain_and_problems_parse() {
    let d = parse_domain(&read("tablewclear-domain.pddl")).unwrap();
    assert_eq!(d.name, "tablewclear");
    assert_eq!(d.actions.len(), 5);
    assert_eq!(d.predicates.len(), 12);
    for p in [
        "thesis6-a",
        "thesis6-b",
        "thesis6-c",
        "thesis6-d-dropped",
        "thesis6-unsolvable",
    ] {
        let prob =
            parse_problem(&read(&format!("{p}.pddl")), &d).unwrap_or_else(|e| panic!("{p}: {e}"));
        assert_eq!(prob.domain_name, "tablewclear");
        assert!(!prob.init.is_empty());
        assert!(matches!(prob.goal, Condition::And(_)));
    }
    let a = parse_problem(&read("thesis6-a.pddl"), &d).unwrap();
    assert_eq!(a.objects.len(), 6);
    assert!(a.init.contains(&GroundAtom {
        predicate: "on".into(),
        args: vec!["o1".into(), "o2".into()]
    }));
}

const TYPED: &str = r#"
(define (domain Logistics-Like)
  (:requirements :typing :action-costs :equality :disjunctive-preconditions)
  (:types truck plane - vehicle  vehicle package - thing  place)
  (:constants depot - place)
  (:predicates (at ?t - thing ?p - place) (in ?p - package ?v - vehicle))
  (:functions (total-cost) - number (distance ?a ?b - place) - number)
  (:action drive
    :parameters (?t - truck ?from ?to - place)
    :precondition (and (at ?t ?from) (not (= ?from ?to)) (or (at ?t depot) (not (at ?t depot))))
    :effect (and (not (at ?t ?from)) (at ?t ?to) (increase (total-cost) (distance ?from ?to))))
  (:action load
    :parameters (?p - package ?v - vehicle ?l - place)
    :precondition (and (at ?p ?l) (at ?v ?l))
    :effect (and (not (at ?p ?l)) (in ?p ?v) (increase (total-cost) 1))))
"#;

#[test]
fn typing_costs_and_case_insensitivity() {
    let d = parse_domain(TYPED).unwrap();
    assert_eq!(d.name, "logistics-like");
    assert!(
        d.is_subtype("truck", "thing")
            && d.is_subtype("truck", "object")
            && !d.is_subtype("place", "thing")
    );
    assert!(d.uses_action_costs());
    let p = parse_problem(
        "(define (problem p1) (:domain logistics-like) (:objects t1 - truck a b - place pk - package)
           (:init (at t1 a) (at pk a) (= (distance a b) 7) (= (total-cost) 0))
           (:goal (and (in pk t1) (at t1 b))) (:metric minimize (total-cost)))",
        &d,
    )
    .unwrap();
    assert!(p.minimize_total_cost);
    assert_eq!(p.init_numeric.len(), 2);
}

fn domain_error(text: &str) -> PddlError {
    parse_domain(text).expect_err("must be rejected")
}

#[test]
fn errors_name_the_place_and_the_problem() {
    let bad_pred = TYPED.replace(
        "(in ?p ?v) (increase (total-cost) 1)",
        "(inside ?p ?v) (increase (total-cost) 1)",
    );
    let e = domain_error(&bad_pred);
    assert!(
        matches!(e.kind, ErrorKind::UndefinedPredicate(ref p) if p == "inside"),
        "{e}"
    );
    assert_eq!((e.loc.line, e.loc.column), (15, 36), "{e}");
    let e = domain_error(&TYPED.replace("(at ?p ?l) (at ?v ?l))", "(at ?p) (at ?v ?l))"));
    assert!(
        matches!(
            e.kind,
            ErrorKind::Arity {
                expected: 2,
                found: 1,
                ..
            }
        ),
        "{e}"
    );
    let e = domain_error(&TYPED.replace(":parameters (?t - truck", ":parameters (?t - lorry"));
    assert!(matches!(e.kind, ErrorKind::UndefinedType(_)), "{e}");
    let e = domain_error(&TYPED.replace("(at ?t ?to)", "(at ?x ?to)"));
    assert!(matches!(e.kind, ErrorKind::UndefinedVariable(_)), "{e}");
    let e = domain_error(&TYPED.replace(":equality", ":fluents"));
    assert!(
        matches!(e.kind, ErrorKind::UnsupportedRequirement(_)),
        "{e}"
    );
    assert!(e.to_string().starts_with("<input>:3:"), "{e}");
    let e = domain_error(&TYPED.replace("(at ?t depot)", "(at ?t nowhere)"));
    assert!(matches!(e.kind, ErrorKind::UndefinedObject(_)), "{e}");
    let e = domain_error("(define (domain x) (:predicates (p)) ");
    assert!(
        matches!(e.kind, ErrorKind::Syntax(_)) && e.loc == Loc { line: 1, column: 1 },
        "{e}"
    );
    let e = domain_error(&TYPED.replace("(in ?p ?v) (increase", "(in ?v ?p) (increase"));
    assert!(matches!(e.kind, ErrorKind::TypeMismatch { .. }), "{e}");
    let d = parse_domain(TYPED).unwrap();
    let e = parse_problem(
        "(define (problem p) (:domain other) (:objects a - place))",
        &d,
    )
    .unwrap_err();
    assert!(matches!(e.kind, ErrorKind::DomainMismatch { .. }), "{e}");
    let e = parse_problem(
        "(define (problem p) (:domain logistics-like) (:objects a - place) (:init (at b a)))",
        &d,
    )
    .unwrap_err();
    assert!(
        matches!(e.kind, ErrorKind::UndefinedObject(ref o) if o == "b"),
        "{e}"
    );
    assert_eq!(
        e.clone().in_file("p.pddl").to_string().split(':').next(),
        Some("p.pddl")
    );
}

#[test]
fn absurd_nesting_is_an_error_not_a_stack_overflow() {
    let deep = format!(
        "(define (domain d) (:predicates (p)) (:action a :parameters () :precondition {}(p){} :effect (p)))",
        "(not ".repeat(100_000),
        ")".repeat(100_000)
    );
    let e = parse_domain(&deep).unwrap_err();
    assert!(
        matches!(e.kind, ErrorKind::Syntax(ref m) if m.contains("nesting")),
        "{e}"
    );
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    /// Mutated domains and problems: a parse or an error, never a panic.
    #[test]
    fn mutated_pddl_never_panics(
        which in 0usize..2,
        edits in proptest::collection::vec((any::<prop::sample::Index>(), 0u8..3, prop::sample::select(vec!['(', ')', '-', '?', ' ', 'a', ';', '\n', '='])), 1..6),
    ) {
        let domain_text = std::fs::read_to_string(format!("{DATA}tablewclear-domain.pddl")).unwrap();
        let problem_text = std::fs::read_to_string(format!("{DATA}thesis6-a.pddl")).unwrap();
        let mut chars: Vec<char> = if which == 0 { domain_text.chars().collect() } else { problem_text.chars().collect() };
        for (at, op, c) in edits {
            if chars.is_empty() { break; }
            let i = at.index(chars.len());
            match op {
                0 => { chars.remove(i); }
                1 => chars.insert(i, c),
                _ => chars[i] = c,
            }
        }
        let text: String = chars.into_iter().collect();
        if which == 0 {
            let _ = parse_domain(&text);
        } else {
            let d = parse_domain(&domain_text).unwrap();
            let _ = parse_problem(&text, &d);
        }
    }
}

#[test]
fn type_cycles_are_errors() {
    for types in [
        "(:types a - b b - a)",
        "(:types a - a)",
        "(:types a - b b - c c - a)",
    ] {
        let text = format!(
            "(define (domain t) (:requirements :typing) {types} (:predicates (p ?x - a)) \
             (:action go :parameters (?x - a) :precondition (p ?x) :effect (not (p ?x))))"
        );
        let e = parse_domain(&text).unwrap_err().to_string();
        assert!(e.contains("cycle") || e.contains("itself"), "{types}: {e}");
    }
    assert!(
        parse_domain("(define (domain t) (:types a - b b - object) (:predicates (p ?x - a)))")
            .is_ok()
    );
}
