//! The parsed (lifted) PDDL task. Names are lower-case.

use crate::Loc;

/// `name - type` (type `object` when untyped).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TypedName {
    pub name: String,
    pub type_name: String,
}

/// A predicate or function declaration.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Signature {
    pub name: String,
    pub params: Vec<TypedName>,
}

/// An argument: a variable (`?x`, stored without `?`) or an object/constant.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Term {
    Var(String),
    Const(String),
}

/// `(predicate args…)`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Atom {
    pub predicate: String,
    pub args: Vec<Term>,
}

/// A goal description.
#[derive(Debug, Clone, PartialEq)]
pub enum Condition {
    True,
    Atom(Atom),
    Equal(Term, Term),
    Not(Box<Condition>),
    And(Vec<Condition>),
    Or(Vec<Condition>),
    Imply(Box<Condition>, Box<Condition>),
    Exists(Vec<TypedName>, Box<Condition>),
    Forall(Vec<TypedName>, Box<Condition>),
}

/// The amount added to `total-cost` by an action.
#[derive(Debug, Clone, PartialEq)]
pub enum CostExpr {
    Constant(i64),
    /// A numeric fluent whose values the problem's `:init` gives.
    Function(String, Vec<Term>),
}

/// An effect.
#[derive(Debug, Clone, PartialEq)]
pub enum Effect {
    And(Vec<Effect>),
    Add(Atom),
    Delete(Atom),
    Forall(Vec<TypedName>, Box<Effect>),
    When(Condition, Box<Effect>),
    IncreaseCost(CostExpr),
}

/// An action schema.
#[derive(Debug, Clone, PartialEq)]
pub struct Action {
    pub name: String,
    pub params: Vec<TypedName>,
    pub precondition: Condition,
    pub effect: Effect,
    pub loc: Loc,
}

/// A domain.
#[derive(Debug, Clone, PartialEq)]
pub struct Domain {
    pub name: String,
    pub requirements: Vec<String>,
    /// Every declared type with its parent (`object` has none).
    pub types: Vec<(String, Option<String>)>,
    pub constants: Vec<TypedName>,
    pub predicates: Vec<Signature>,
    pub functions: Vec<Signature>,
    pub actions: Vec<Action>,
}

impl Domain {
    /// True when `t` is `ancestor` or a subtype of it.
    pub fn is_subtype(&self, t: &str, ancestor: &str) -> bool {
        let mut cur = Some(t.to_string());
        let mut steps = 0;
        while let Some(c) = cur {
            if c == ancestor {
                return true;
            }
            steps += 1;
            if steps > self.types.len() + 1 {
                return false;
            }
            cur = self
                .types
                .iter()
                .find(|(n, _)| *n == c)
                .and_then(|(_, p)| p.clone());
        }
        false
    }

    pub fn predicate(&self, name: &str) -> Option<&Signature> {
        self.predicates.iter().find(|p| p.name == name)
    }

    /// True when the domain charges action costs (`:action-costs`).
    pub fn uses_action_costs(&self) -> bool {
        self.requirements.iter().any(|r| r == ":action-costs")
    }
}

/// A ground fact `(predicate objects…)`.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct GroundAtom {
    pub predicate: String,
    pub args: Vec<String>,
}

/// A problem.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    pub name: String,
    pub domain_name: String,
    pub objects: Vec<TypedName>,
    pub init: Vec<GroundAtom>,
    /// `(= (f objects…) value)` entries of `:init`.
    pub init_numeric: Vec<(GroundAtom, i64)>,
    pub goal: Condition,
    /// True for `(:metric minimize (total-cost))`.
    pub minimize_total_cost: bool,
}
