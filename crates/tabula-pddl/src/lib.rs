//! PDDL for tabula's task planner (SPEC §3.4–3.6), in process: parse, ground, search
//! (optimal A* + LM-cut + strong stubborn sets, or greedy h^FF), validate, replan.
//!
//! The parser reads domains and problems
//! with `:strips`, `:typing`, `:negative-preconditions`, `:disjunctive-preconditions`,
//! `:equality`, `:existential-preconditions`, `:universal-preconditions`,
//! `:conditional-effects` (`:adl` is their union) and `:action-costs`.
//!
//! Written here rather than taken from the `pddl` crate, which is EUPL (copyleft) while
//! tabula is MIT OR Apache-2.0 (DESIGN.md). Every error names `file:line:column`.

mod ast;
mod build;
pub mod generator;
pub mod ground;
pub mod heuristic;
mod parse;
pub mod planner;
pub mod search;
pub mod sexpr;
mod task;
pub mod validate;

pub use ast::*;
pub use ground::{GroundError, GroundOptions, GroundTask};
pub use parse::{parse_domain, parse_problem};
pub use planner::{NoPlan, Plan, Planner, SearchMode};
pub use search::Budget;
pub use validate::{PlanError, PlanStep, parse_plan, validate};

/// A place in a PDDL file (1-based).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Loc {
    pub line: usize,
    pub column: usize,
}

/// What went wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ErrorKind {
    #[error("{0}")]
    Syntax(String),
    #[error("expected {expected}, found {found}")]
    Expected { expected: String, found: String },
    #[error(
        "requirement `{0}` is not supported (supported: :strips :typing :negative-preconditions :disjunctive-preconditions :equality :existential-preconditions :universal-preconditions :quantified-preconditions :conditional-effects :adl :action-costs)"
    )]
    UnsupportedRequirement(String),
    #[error("predicate `{0}` is not declared in the domain")]
    UndefinedPredicate(String),
    #[error("type `{0}` is not declared in the domain")]
    UndefinedType(String),
    #[error("object or constant `{0}` is not declared")]
    UndefinedObject(String),
    #[error("variable `{0}` is not bound by the action's parameters or a quantifier")]
    UndefinedVariable(String),
    #[error("function `{0}` is not declared in the domain")]
    UndefinedFunction(String),
    #[error("`{name}` takes {expected} argument(s), given {found}")]
    Arity {
        name: String,
        expected: usize,
        found: usize,
    },
    #[error("`{0}` is declared twice")]
    Duplicate(String),
    #[error("`{found}` has type `{found_type}`, which is not a `{expected_type}`")]
    TypeMismatch {
        found: String,
        found_type: String,
        expected_type: String,
    },
    #[error("problem is for domain `{problem_domain}`, but the domain is `{domain}`")]
    DomainMismatch {
        domain: String,
        problem_domain: String,
    },
}

/// A parse or validation error with its place.
#[derive(Debug, Clone, PartialEq)]
pub struct PddlError {
    pub file: Option<String>,
    pub loc: Loc,
    pub kind: ErrorKind,
}

impl PddlError {
    pub(crate) fn at(loc: Loc, kind: ErrorKind) -> Self {
        Self {
            file: None,
            loc,
            kind,
        }
    }

    /// Names the file the error came from.
    pub fn in_file(mut self, file: impl Into<String>) -> Self {
        self.file = Some(file.into());
        self
    }
}

impl std::fmt::Display for PddlError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let file = self.file.as_deref().unwrap_or("<input>");
        write!(
            f,
            "{file}:{}:{}: {}",
            self.loc.line, self.loc.column, self.kind
        )
    }
}

impl std::error::Error for PddlError {}
