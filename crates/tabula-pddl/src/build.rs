//! Problems built in code: a caller that computes its facts (the clearing loop, every
//! frame) hands them over as atoms, checked against the domain as the parser checks
//! text, without writing PDDL and parsing it back.

use crate::ast::{Atom, Condition, Domain, GroundAtom, Problem, Term, TypedName};
use crate::{ErrorKind, Loc, PddlError};

/// Where an error in a built problem is: no file, no line.
const BUILT: Loc = Loc { line: 0, column: 0 };

fn error(kind: ErrorKind) -> PddlError {
    PddlError::at(BUILT, kind).in_file("<built problem>")
}

impl Problem {
    /// A problem of `domain` with `objects`, the facts `init` (sorted and deduplicated,
    /// as the parser leaves them) and the conjunction `goal`. Object types must be
    /// declared, names unique, and every atom's predicate declared with its arity over
    /// declared objects or constants.
    pub fn from_atoms(
        domain: &Domain,
        name: &str,
        objects: Vec<TypedName>,
        mut init: Vec<GroundAtom>,
        goal: &[GroundAtom],
    ) -> Result<Problem, PddlError> {
        for (i, o) in objects.iter().enumerate() {
            if !domain.types.iter().any(|(n, _)| *n == o.type_name) {
                return Err(error(ErrorKind::UndefinedType(o.type_name.clone())));
            }
            if objects[..i]
                .iter()
                .chain(&domain.constants)
                .any(|k| k.name == o.name)
            {
                return Err(error(ErrorKind::Duplicate(o.name.clone())));
            }
        }
        let declared = |a: &str| objects.iter().chain(&domain.constants).any(|k| k.name == a);
        for atom in init.iter().chain(goal) {
            let Some(sig) = domain.predicate(&atom.predicate) else {
                return Err(error(ErrorKind::UndefinedPredicate(atom.predicate.clone())));
            };
            if sig.params.len() != atom.args.len() {
                return Err(error(ErrorKind::Arity {
                    name: atom.predicate.clone(),
                    expected: sig.params.len(),
                    found: atom.args.len(),
                }));
            }
            if let Some(a) = atom.args.iter().find(|a| !declared(a)) {
                return Err(error(ErrorKind::UndefinedObject(a.clone())));
            }
        }
        init.sort();
        init.dedup();
        let goal = Condition::And(
            goal.iter()
                .map(|a| {
                    Condition::Atom(Atom {
                        predicate: a.predicate.clone(),
                        args: a.args.iter().map(|o| Term::Const(o.clone())).collect(),
                    })
                })
                .collect(),
        );
        Ok(Problem {
            name: name.into(),
            domain_name: domain.name.clone(),
            objects,
            init,
            init_numeric: Vec::new(),
            goal,
            minimize_total_cost: false,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Planner, SearchMode, parse_domain, parse_problem};

    const DOMAIN: &str = "(define (domain d) (:requirements :strips :typing) (:types obj)
        (:predicates (at ?o - obj) (done ?o - obj))
        (:action finish :parameters (?o - obj) :precondition (at ?o) :effect (done ?o)))";

    fn atom(p: &str, args: &[&str]) -> GroundAtom {
        GroundAtom {
            predicate: p.into(),
            args: args.iter().map(|a| a.to_string()).collect(),
        }
    }

    fn obj(name: &str, t: &str) -> TypedName {
        TypedName {
            name: name.into(),
            type_name: t.into(),
        }
    }

    #[test]
    fn a_built_problem_equals_the_parsed_one() {
        let d = parse_domain(DOMAIN).unwrap();
        let text = "(define (problem p) (:domain d) (:objects b a - obj)
            (:init (at b) (at a)) (:goal (and (done a) (done b))))";
        let parsed = parse_problem(text, &d).unwrap();
        let built = Problem::from_atoms(
            &d,
            "p",
            vec![obj("b", "obj"), obj("a", "obj")],
            vec![atom("at", &["b"]), atom("at", &["a"]), atom("at", &["a"])],
            &[atom("done", &["a"]), atom("done", &["b"])],
        )
        .unwrap();
        assert_eq!(built, parsed);
        let planner = Planner::new(d, built, Default::default()).unwrap();
        assert_eq!(
            planner.plan(SearchMode::Optimal, None).unwrap().steps.len(),
            2
        );
    }

    #[test]
    fn bad_atoms_and_objects_are_named() {
        let d = parse_domain(DOMAIN).unwrap();
        let build = |objects: Vec<TypedName>, init: Vec<GroundAtom>| {
            Problem::from_atoms(&d, "p", objects, init, &[])
                .unwrap_err()
                .kind
        };
        assert_eq!(
            build(vec![obj("a", "box")], vec![]),
            ErrorKind::UndefinedType("box".into())
        );
        assert_eq!(
            build(vec![obj("a", "obj"), obj("a", "obj")], vec![]),
            ErrorKind::Duplicate("a".into())
        );
        assert_eq!(
            build(vec![obj("a", "obj")], vec![atom("on", &["a"])]),
            ErrorKind::UndefinedPredicate("on".into())
        );
        assert!(matches!(
            build(vec![obj("a", "obj")], vec![atom("at", &["a", "a"])]),
            ErrorKind::Arity { .. }
        ));
        assert_eq!(
            build(vec![obj("a", "obj")], vec![atom("at", &["z"])]),
            ErrorKind::UndefinedObject("z".into())
        );
    }
}
