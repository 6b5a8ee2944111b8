//! PDDL domains and problems.

use super::*;

pub(super) fn pddl(c: &mut Corpus) {
    costs(c);
    let domain = read_repo("pddl/tablewclear-domain.pddl");
    let problem = read_repo("pddl/thesis6-a.pddl");
    let d = c.file("pddl/domain.pddl", &domain);
    let plan = |c: &mut Corpus, name: &str, class, expect, dom: Option<String>, prob: String| {
        let df = match dom {
            Some(t) => c.file(&format!("pddl/{name}-domain.pddl"), t),
            None => d.clone(),
        };
        let pf = c.file(&format!("pddl/{name}-problem.pddl"), prob);
        c.case(
            &format!("pddl-{name}"),
            class,
            expect,
            &["plan", &df, &pf, "--timeout", "15"],
        );
    };
    plan(c, "valid", "garbage", Ok, None, problem.clone());
    c.needs("cost = 9");
    plan(
        c,
        "unsolvable",
        "garbage",
        NoSolution,
        None,
        read_repo("pddl/thesis6-unsolvable.pddl"),
    );
    c.needs("unsolvable");
    for cut in [0, 1, 30, 200, 500] {
        plan(
            c,
            &format!("problem-cut-{cut}"),
            "malformed",
            Error,
            None,
            problem[..cut].to_string(),
        );
        plan(
            c,
            &format!("domain-cut-{cut}"),
            "malformed",
            Error,
            Some(domain[..cut * 8].to_string()),
            problem.clone(),
        );
    }
    for (name, text, class) in [
        ("unbalanced", problem.replacen(")", "", 3), "malformed"),
        ("extra-close", format!("{problem}))"), "malformed"),
        (
            "undeclared-object",
            problem.replacen("(on o1 o2)", "(on o1 o99)", 1),
            "garbage",
        ),
        (
            "unknown-predicate",
            problem.replacen("(on o1 o2)", "(under o1 o2)", 1),
            "garbage",
        ),
        (
            "wrong-arity",
            problem.replacen("(on o1 o2)", "(on o1)", 1),
            "garbage",
        ),
        (
            "wrong-domain",
            problem.replacen("(:domain tablewclear)", "(:domain other)", 1),
            "garbage",
        ),
        (
            "goal-missing",
            problem.replacen("(:goal", "(:gaol", 1),
            "malformed",
        ),
        (
            "duplicate-object",
            problem.replacen("o6 - obj", "o6 o6 - obj", 1),
            "garbage",
        ),
        ("nul-bytes", problem.replacen("o1", "o\0", 1), "malformed"),
        (
            "string-literal",
            problem.replacen("o1 o2 o3", "\"o1\" o2 o3", 1),
            "malformed",
        ),
    ] {
        plan(c, name, class, Error, None, text);
    }
    // Deep nesting: 100,000 parentheses, in a goal and bare.
    plan(
        c,
        "nested-goal-100k",
        "recursion",
        Error,
        None,
        problem.replacen(
            "(:goal (and",
            &format!("(:goal {}(and", "(and ".repeat(100_000)),
            1,
        ),
    );
    plan(
        c,
        "nested-bare-100k",
        "recursion",
        Error,
        None,
        format!("{}{}", "(".repeat(100_000), ")".repeat(100_000)),
    );
    plan(
        c,
        "nested-domain-100k",
        "recursion",
        Error,
        Some(format!("{}{}", "(".repeat(100_000), ")".repeat(100_000))),
        problem.clone(),
    );
    // A type cycle and an undefined parent type.
    let typed = "(define (domain t) (:requirements :typing) (:types a - b b - a) (:predicates (p ?x - a)) (:action go :parameters (?x - a) :precondition (p ?x) :effect (not (p ?x))))";
    plan(
        c,
        "type-cycle",
        "garbage",
        Error,
        Some(typed.into()),
        "(define (problem q) (:domain t) (:objects x - a) (:init (p x)) (:goal (not (p x))))"
            .into(),
    );
    let self_typed = "(define (domain t) (:requirements :typing) (:types a - a) (:predicates (p ?x - a)) (:action go :parameters (?x - a) :precondition (p ?x) :effect (not (p ?x))))";
    plan(
        c,
        "type-self",
        "garbage",
        Error,
        Some(self_typed.into()),
        "(define (problem q) (:domain t) (:objects x - a) (:init (p x)) (:goal (not (p x))))"
            .into(),
    );
    // Grounding blow-ups: quantifiers over many variables, many-parameter actions.
    let objects: String = (0..66).map(|i| format!(" o{i}")).collect();
    let quant = "(define (domain q) (:requirements :adl) (:predicates (p ?a ?b ?c ?d ?e ?f) (done)) (:action go :parameters () :precondition (forall (?a ?b ?c ?d ?e ?f) (not (p ?a ?b ?c ?d ?e ?f))) :effect (done)))";
    // Quantifiers over 5 and 6 variables (1.25e9 and 8.3e10 bindings): grounding counts
    // them and stops at the deadline (0.3 s here: on a fast machine the 5e7-binding work
    // limit — a clean error too, but another status — was reached within 2 s).
    let exists = "(define (domain q) (:requirements :adl) (:predicates (p ?a ?b ?c ?d ?e) (done)) (:action go :parameters () :precondition (exists (?a ?b ?c ?d ?e) (p ?a ?b ?c ?d ?e)) :effect (done)))";
    for (name, domain, init) in [
        ("forall-6-vars", quant, ""),
        ("exists-5-vars", exists, "(p o1 o2 o3 o4 o5)"),
    ] {
        let df = c.file(&format!("pddl/{name}-domain.pddl"), domain);
        let pf = c.file(
            &format!("pddl/{name}-problem.pddl"),
            format!("(define (problem q1) (:domain q) (:objects{objects}) (:init {init}) (:goal (done)))"),
        );
        c.case(
            &format!("pddl-{name}"),
            "unbounded",
            NoSolution,
            &["plan", &df, &pf, "--timeout", "0.3"],
        );
        c.needs("time limit");
    }
    let four = "(define (domain f) (:predicates (p ?a ?b ?c ?d) (q ?a)) (:action go :parameters (?a ?b ?c ?d) :precondition (q ?a) :effect (p ?a ?b ?c ?d)))";
    plan(
        c,
        "four-params-66-objects",
        "unbounded",
        Ok,
        Some(four.into()),
        format!(
            "(define (problem f1) (:domain f) (:objects{objects}) (:init (q o1)) (:goal (p o1 o1 o1 o2)))"
        ),
    );
    let many: String = (0..60).map(|i| format!(" ?v{i}")).collect();
    let wide = format!(
        "(define (domain w) (:predicates (p{many}) (d)) (:action go :parameters ({many}) :precondition (d) :effect (p{many})))"
    );
    plan(
        c,
        "sixty-params",
        "unbounded",
        Error,
        Some(wide),
        format!("(define (problem w1) (:domain w) (:objects{objects}) (:init (d)) (:goal (d)))"),
    );
    // An unsolvable search space too big to exhaust: ends at --timeout with exit 2.
    let counter = "(define (domain c) (:predicates (at ?x) (next ?x ?y) (goal-reached)) (:action step :parameters (?x ?y) :precondition (and (at ?x) (next ?x ?y)) :effect (and (not (at ?x)) (at ?y))))";
    let n = 60;
    let objs: String = (0..n).map(|i| format!(" c{i}")).collect();
    let mut init = String::new();
    for i in 0..n {
        for j in 0..n {
            if i != j {
                let _ = write!(init, " (next c{i} c{j})");
            }
        }
    }
    let f = c.file("pddl/no-goal-reachable-domain.pddl", counter);
    let p = c.file("pddl/no-goal-reachable-problem.pddl", format!("(define (problem c1) (:domain c) (:objects{objs}) (:init (at c0){init}) (:goal (goal-reached)))"));
    c.case(
        "pddl-goal-unreachable",
        "unbounded",
        NoSolution,
        &["plan", &f, &p, "--timeout", "5"],
    );
    // A budget of expanded states ends the search where it binds, on any machine.
    c.case(
        "pddl-expansion-budget",
        "unbounded",
        NoSolution,
        &[
            "plan",
            &d,
            "@pddl/valid-problem.pddl",
            "--max-expanded",
            "1",
        ],
    );
    c.needs("--max-expanded");
    // A plan to validate that is malformed.
    let good_plan = c.file("pddl/plan-ok.txt", "(grasp o6)\n");
    c.case(
        "pddl-validate-wrong-plan",
        "garbage",
        Error,
        &[
            "plan",
            "--validate",
            &d,
            "@pddl/valid-problem.pddl",
            &good_plan,
        ],
    );
    for (name, text) in [
        ("unknown-action", "(fly o1)\n"),
        ("unbalanced", "(grasp o1\n"),
        ("unknown-object", "(grasp o99)\n"),
        ("huge", &"(grasp o1)\n".repeat(100_000)),
    ] {
        let f = c.file(&format!("pddl/plan-{name}.txt"), text);
        c.case(
            &format!("pddl-validate-{name}"),
            "malformed",
            Error,
            &["plan", "--validate", &d, "@pddl/valid-problem.pddl", &f],
        );
    }
}

/// Action costs that once wrapped or overflowed: a solvable problem called
/// "unsolvable", a validated plan's cost printed modulo 2⁶⁴. Costs over 10⁹ are refused
/// naming the bound; at the bound the sums are exact.
fn costs(c: &mut Corpus) {
    let domain = |cost: &str| {
        format!(
            "(define (domain costly) (:requirements :strips :action-costs)\n\
             (:predicates (at ?x) (link ?x ?y)) (:functions (total-cost) (length ?a ?b) - number)\n\
             (:action hop :parameters (?a ?b) :precondition (and (at ?a) (link ?a ?b))\n\
             :effect (and (not (at ?a)) (at ?b) (increase (total-cost) {cost}))))\n"
        )
    };
    let problem = |length: &str| {
        format!(
            "(define (problem p) (:domain costly) (:objects a b c d)\n\
             (:init (at a) (link a b) (link b c) (link c d) (= (total-cost) 0)\n\
             (= (length a b) {length}) (= (length b c) 1) (= (length c d) 1))\n\
             (:goal (at d)) (:metric minimize (total-cost)))\n"
        )
    };
    let steps = c.file("pddl/costly-plan.txt", "(hop a b)\n(hop b c)\n(hop c d)\n");
    for (name, cost, length, expect, needle) in [
        (
            "cost-5e18",
            "5000000000000000000",
            "1",
            Error,
            "at most 1000000000",
        ),
        (
            "cost-i64-max",
            "9223372036854775807",
            "1",
            Error,
            "at most 1000000000",
        ),
        (
            "cost-u64-over",
            "18446744073709551617",
            "1",
            Error,
            "at most 1000000000",
        ),
        (
            "cost-bound-plus-one",
            "1000000001",
            "1",
            Error,
            "at most 1000000000",
        ),
        ("cost-at-bound", "1000000000", "1", Ok, "cost = 3000000000"),
        (
            "cost-function",
            "(length ?a ?b)",
            "1000000000",
            Ok,
            "cost = 1000000002",
        ),
        (
            "cost-function-huge",
            "(length ?a ?b)",
            "9223372036854775807",
            Error,
            "at most 1000000000",
        ),
        (
            "cost-function-negative-huge",
            "(length ?a ?b)",
            "-5000000000000",
            Error,
            "at most 1000000000",
        ),
    ] {
        let d = c.file(&format!("pddl/{name}-domain.pddl"), domain(cost));
        let p = c.file(&format!("pddl/{name}-problem.pddl"), problem(length));
        c.case(
            &format!("pddl-{name}"),
            "overflow",
            expect,
            &["plan", &d, &p],
        );
        c.needs(needle);
        if matches!(expect, Ok) {
            c.case(
                &format!("pddl-{name}-validate"),
                "overflow",
                Ok,
                &["plan", &d, &p, &steps, "--validate"],
            );
            c.needs(&needle.replace(" = ", " "));
        }
    }
}
