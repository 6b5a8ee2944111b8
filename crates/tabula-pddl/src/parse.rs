//! Domain and problem parsing with validation against the domain.

use crate::sexpr::{Sexpr, parse_all};
use crate::*;

const SUPPORTED: &[&str] = &[
    ":strips",
    ":typing",
    ":negative-preconditions",
    ":disjunctive-preconditions",
    ":equality",
    ":existential-preconditions",
    ":universal-preconditions",
    ":quantified-preconditions",
    ":conditional-effects",
    ":adl",
    ":action-costs",
];

type R<T> = Result<T, PddlError>;

fn err<T>(loc: Loc, kind: ErrorKind) -> R<T> {
    Err(PddlError::at(loc, kind))
}

fn expected<T>(node: &Sexpr, what: &str) -> R<T> {
    let found = match node {
        Sexpr::Atom(a, _) => format!("`{a}`"),
        Sexpr::List(items, _) => match items.first().and_then(Sexpr::atom) {
            Some(head) => format!("a `({head} …)` list"),
            None => "a list".into(),
        },
    };
    err(
        node.loc(),
        ErrorKind::Expected {
            expected: what.into(),
            found,
        },
    )
}

fn list<'a>(node: &'a Sexpr, what: &str) -> R<&'a [Sexpr]> {
    node.list().map_or_else(|| expected(node, what), Ok)
}

fn atom<'a>(node: &'a Sexpr, what: &str) -> R<&'a str> {
    node.atom().map_or_else(|| expected(node, what), Ok)
}

/// A `(:keyword …)` section: its keyword and all its items (keyword first).
fn section<'a>(node: &'a Sexpr, what: &str) -> R<(&'a str, &'a [Sexpr])> {
    let items = list(node, what)?;
    let head = items.first().map_or_else(
        || expected(node, "a section keyword"),
        |h| atom(h, "a section keyword"),
    )?;
    Ok((head, items))
}

/// The requirement keywords of a `(:requirements …)` section, all supported.
fn requirements(items: &[Sexpr]) -> R<Vec<String>> {
    items
        .iter()
        .map(|r| {
            let name = atom(r, "a requirement")?;
            if SUPPORTED.contains(&name) {
                Ok(name.to_string())
            } else {
                err(r.loc(), ErrorKind::UnsupportedRequirement(name.into()))
            }
        })
        .collect()
}

/// The single `(define …)` of a file and its sections.
fn define<'a>(top: &'a [Sexpr], kind: &str) -> R<(&'a str, &'a [Sexpr], Loc)> {
    let Some(first) = top.first() else {
        return err(
            Loc { line: 1, column: 1 },
            ErrorKind::Syntax(format!("empty input: expected (define ({kind} NAME) …)")),
        );
    };
    if let Some(extra) = top.get(1) {
        return expected(extra, "the end of the file after (define …)");
    }
    let items = list(first, "(define …)")?;
    if items.first().and_then(Sexpr::atom) != Some("define") {
        return expected(first, "(define …)");
    }
    let Some(header) = items.get(1) else {
        return expected(first, &format!("({kind} NAME) after define"));
    };
    let h = list(header, &format!("({kind} NAME)"))?;
    if h.len() != 2 || h[0].atom() != Some(kind) {
        return expected(header, &format!("({kind} NAME)"));
    }
    Ok((atom(&h[1], "a name")?, &items[2..], first.loc()))
}

/// `a b - t c - u d` → typed names (untyped ones are `object`).
fn typed_list(items: &[Sexpr], variables: bool) -> R<Vec<(TypedName, Loc)>> {
    let mut out = Vec::new();
    let mut pending: Vec<(String, Loc)> = Vec::new();
    let mut i = 0;
    while i < items.len() {
        let a = atom(&items[i], if variables { "a variable" } else { "a name" })?;
        if a == "-" {
            let Some(t) = items.get(i + 1) else {
                return expected(&items[i], "a type after `-`");
            };
            if let Sexpr::List(l, _) = t
                && l.first().and_then(Sexpr::atom) == Some("either")
            {
                return err(
                    t.loc(),
                    ErrorKind::Syntax("`(either …)` types are not supported".into()),
                );
            }
            let t = atom(t, "a type name")?;
            if pending.is_empty() {
                return expected(&items[i], "names before `-`");
            }
            out.extend(pending.drain(..).map(|(name, loc)| {
                (
                    TypedName {
                        name,
                        type_name: t.to_string(),
                    },
                    loc,
                )
            }));
            i += 2;
            continue;
        }
        let name = if variables {
            match a.strip_prefix('?') {
                Some(v) if !v.is_empty() => v.to_string(),
                _ => return expected(&items[i], "a variable `?name`"),
            }
        } else {
            if a.starts_with('?') {
                return expected(&items[i], "a name (not a variable)");
            }
            a.to_string()
        };
        pending.push((name, items[i].loc()));
        i += 1;
    }
    out.extend(pending.into_iter().map(|(name, loc)| {
        (
            TypedName {
                name,
                type_name: "object".into(),
            },
            loc,
        )
    }));
    Ok(out)
}

/// Parses and checks a domain.
pub fn parse_domain(text: &str) -> R<Domain> {
    let top = parse_all(text)?;
    let (name, sections, _) = define(&top, "domain")?;
    let mut d = Domain {
        name: name.to_string(),
        requirements: vec![":strips".into()],
        types: vec![("object".into(), None)],
        constants: Vec::new(),
        predicates: Vec::new(),
        functions: Vec::new(),
        actions: Vec::new(),
    };
    let mut actions = Vec::new();
    // Types used by declarations, checked once every section is read.
    let mut type_uses: Vec<(String, Loc)> = Vec::new();
    for s in sections {
        let (head, items) = section(s, "a domain section such as (:predicates …)")?;
        match head {
            ":requirements" => d.requirements.extend(requirements(&items[1..])?),
            ":types" => declare_types(&mut d, &items[1..], s.loc())?,
            ":constants" => {
                for (c, loc) in typed_list(&items[1..], false)? {
                    if d.constants.iter().any(|k| k.name == c.name) {
                        return err(loc, ErrorKind::Duplicate(c.name));
                    }
                    type_uses.push((c.type_name.clone(), loc));
                    d.constants.push(c);
                }
            }
            ":predicates" | ":functions" => {
                let functions = head == ":functions";
                declare_signatures(&mut d, (functions, &items[1..]), &mut type_uses)?;
            }
            ":action" => actions.push(s),
            other => {
                return err(
                    items[0].loc(),
                    ErrorKind::Syntax(format!("unknown domain section `{other}`")),
                );
            }
        }
    }
    // A parent named only after `-` is a type of its own, under `object` (as in
    // Fast Downward's translator).
    let parents: Vec<String> = d.types.iter().filter_map(|(_, p)| p.clone()).collect();
    for p in parents {
        if !d.types.iter().any(|(n, _)| *n == p) {
            d.types.push((p, Some("object".into())));
        }
    }
    for (t, loc) in type_uses {
        if !d.types.iter().any(|(n, _)| *n == t) {
            return err(loc, ErrorKind::UndefinedType(t));
        }
    }
    for s in actions {
        let a = parse_action(&d, s)?;
        if d.actions.iter().any(|x| x.name == a.name) {
            return err(s.loc(), ErrorKind::Duplicate(a.name));
        }
        d.actions.push(a);
    }
    Ok(d)
}

/// A `:types` section: each type once, none its own parent, and every chain of parents
/// reaching `object` (a cycle, a - b and b - a, makes every subtype question
/// unanswerable).
fn declare_types(d: &mut Domain, items: &[Sexpr], section: Loc) -> R<()> {
    for (t, loc) in typed_list(items, false)? {
        if t.name == "object" {
            continue;
        }
        if d.types.iter().any(|(n, _)| *n == t.name) {
            return err(loc, ErrorKind::Duplicate(t.name));
        }
        if t.name == t.type_name {
            let message = format!("type `{}` is declared a subtype of itself", t.name);
            return err(loc, ErrorKind::Syntax(message));
        }
        d.types.push((t.name, Some(t.type_name)));
    }
    for (name, _) in &d.types {
        let mut cur = name.as_str();
        for _ in 0..=d.types.len() {
            match d
                .types
                .iter()
                .find(|(n, _)| n == cur)
                .and_then(|(_, p)| p.as_deref())
            {
                Some(parent) => cur = parent,
                None => break,
            }
        }
        if d.types.iter().any(|(n, p)| n == cur && p.is_some()) {
            return err(
                section,
                ErrorKind::Syntax(format!(
                    "the :types form a cycle through `{name}`: every type must descend from `object`"
                )),
            );
        }
    }
    Ok(())
}

/// A `:predicates` or (`functions`) `:functions` section: each name once, its
/// parameters' types noted in `type_uses`.
fn declare_signatures(
    d: &mut Domain,
    (functions, items): (bool, &[Sexpr]),
    type_uses: &mut Vec<(String, Loc)>,
) -> R<()> {
    let mut i = 0;
    while i < items.len() {
        let decl = list(&items[i], "a declaration (name ?args…)")?;
        let Some(first) = decl.first() else {
            return expected(&items[i], "a name");
        };
        let pname = atom(first, "a name")?.to_string();
        let mut params = Vec::new();
        for (t, loc) in typed_list(&decl[1..], true)? {
            type_uses.push((t.type_name.clone(), loc));
            params.push(t);
        }
        let target = if functions {
            &mut d.functions
        } else {
            &mut d.predicates
        };
        if target.iter().any(|p| p.name == pname) {
            return err(items[i].loc(), ErrorKind::Duplicate(pname));
        }
        target.push(Signature {
            name: pname,
            params,
        });
        i += 1;
        // `:functions` may give a return type: `(f ?x) - number`.
        if functions && items.get(i).and_then(Sexpr::atom) == Some("-") {
            i += 2;
        }
    }
    Ok(())
}

struct Scope<'a> {
    domain: &'a Domain,
    vars: Vec<TypedName>,
    objects: &'a [TypedName],
    /// Where each object's name sits in `objects`: a problem of 100,000 objects looks
    /// one up per argument of every initial fact.
    object_index: std::collections::HashMap<&'a str, usize>,
}

impl<'a> Scope<'a> {
    fn new(domain: &'a Domain, objects: &'a [TypedName]) -> Self {
        Self {
            domain,
            vars: Vec::new(),
            objects,
            object_index: objects
                .iter()
                .enumerate()
                .map(|(i, o)| (o.name.as_str(), i))
                .collect(),
        }
    }
}

/// The largest action cost or numeric value (10⁹, Fast Downward's bound is 2³¹): a
/// plan's cost is a sum of them, and sums of larger ones overflow — a solvable problem
/// would come out "unsolvable" and a plan's printed cost would wrap.
pub const MAX_COST: i64 = 1_000_000_000;

impl Scope<'_> {
    fn term(&self, node: &Sexpr) -> R<(Term, String)> {
        let a = atom(node, "a variable or object")?;
        if let Some(v) = a.strip_prefix('?') {
            let t = self.vars.iter().rev().find(|x| x.name == v);
            return t.map_or_else(
                || err(node.loc(), ErrorKind::UndefinedVariable(a.into())),
                |t| Ok((Term::Var(v.into()), t.type_name.clone())),
            );
        }
        let o = self
            .domain
            .constants
            .iter()
            .find(|o| o.name == a)
            .or_else(|| self.object_index.get(a).map(|&i| &self.objects[i]));
        o.map_or_else(
            || err(node.loc(), ErrorKind::UndefinedObject(a.into())),
            |o| Ok((Term::Const(a.into()), o.type_name.clone())),
        )
    }

    fn atom(&self, items: &[Sexpr], loc: Loc) -> R<Atom> {
        let name = atom(&items[0], "a predicate")?;
        let Some(sig) = self.domain.predicate(name) else {
            return err(items[0].loc(), ErrorKind::UndefinedPredicate(name.into()));
        };
        self.args(name, &sig.params, &items[1..], loc)
            .map(|args| Atom {
                predicate: name.into(),
                args,
            })
    }

    fn args(&self, name: &str, params: &[TypedName], items: &[Sexpr], loc: Loc) -> R<Vec<Term>> {
        if params.len() != items.len() {
            return err(
                loc,
                ErrorKind::Arity {
                    name: name.into(),
                    expected: params.len(),
                    found: items.len(),
                },
            );
        }
        let mut args = Vec::with_capacity(items.len());
        for (node, p) in items.iter().zip(params) {
            let (term, t) = self.term(node)?;
            // A variable of a supertype may still be bound to a fitting object; only
            // reject what can never fit.
            if !self.domain.is_subtype(&t, &p.type_name)
                && !self.domain.is_subtype(&p.type_name, &t)
            {
                return err(
                    node.loc(),
                    ErrorKind::TypeMismatch {
                        found: node.atom().unwrap_or_default().into(),
                        found_type: t,
                        expected_type: p.type_name.clone(),
                    },
                );
            }
            args.push(term);
        }
        Ok(args)
    }

    fn quantified(&mut self, items: &[Sexpr], node: &Sexpr) -> R<Vec<TypedName>> {
        if items.len() != 3 {
            return expected(node, "(quantifier (?vars…) body)");
        }
        let vars: Vec<TypedName> = typed_list(list(&items[1], "a variable list")?, true)?
            .into_iter()
            .map(|(t, _)| t)
            .collect();
        for v in &vars {
            if !self.domain.types.iter().any(|(n, _)| *n == v.type_name) {
                return err(
                    items[1].loc(),
                    ErrorKind::UndefinedType(v.type_name.clone()),
                );
            }
        }
        Ok(vars)
    }

    fn condition(&mut self, node: &Sexpr) -> R<Condition> {
        let items = list(node, "a condition in parentheses")?;
        let Some(head) = items.first() else {
            return Ok(Condition::True);
        };
        let head = atom(head, "a predicate or connective")?;
        let sub = |s: &mut Self, i: usize| -> R<Box<Condition>> {
            match items.get(i) {
                Some(n) => Ok(Box::new(s.condition(n)?)),
                None => expected(node, "a sub-condition"),
            }
        };
        Ok(match head {
            "and" => Condition::And(
                items[1..]
                    .iter()
                    .map(|c| self.condition(c))
                    .collect::<R<_>>()?,
            ),
            "or" => Condition::Or(
                items[1..]
                    .iter()
                    .map(|c| self.condition(c))
                    .collect::<R<_>>()?,
            ),
            "not" if items.len() == 2 => Condition::Not(sub(self, 1)?),
            "imply" if items.len() == 3 => Condition::Imply(sub(self, 1)?, sub(self, 2)?),
            "exists" | "forall" => {
                let vars = self.quantified(items, node)?;
                let n = vars.len();
                self.vars.extend(vars.iter().cloned());
                let body = self.condition(&items[2]);
                self.vars.truncate(self.vars.len() - n);
                if head == "exists" {
                    Condition::Exists(vars, Box::new(body?))
                } else {
                    Condition::Forall(vars, Box::new(body?))
                }
            }
            "=" if items.len() == 3 => {
                Condition::Equal(self.term(&items[1])?.0, self.term(&items[2])?.0)
            }
            "not" | "imply" | "=" => {
                return expected(
                    node,
                    &format!("`{head}` with the right number of arguments"),
                );
            }
            _ => Condition::Atom(self.atom(items, node.loc())?),
        })
    }

    fn effect(&mut self, node: &Sexpr) -> R<Effect> {
        let items = list(node, "an effect in parentheses")?;
        let Some(head) = items.first() else {
            return Ok(Effect::And(Vec::new()));
        };
        let head = atom(head, "a predicate or effect keyword")?;
        Ok(match head {
            "and" => Effect::And(
                items[1..]
                    .iter()
                    .map(|e| self.effect(e))
                    .collect::<R<_>>()?,
            ),
            "not" if items.len() == 2 => {
                let inner = list(&items[1], "an atom")?;
                if inner.is_empty() {
                    return expected(&items[1], "an atom");
                }
                Effect::Delete(self.atom(inner, items[1].loc())?)
            }
            "forall" => {
                let vars = self.quantified(items, node)?;
                let n = vars.len();
                self.vars.extend(vars.iter().cloned());
                let body = self.effect(&items[2]);
                self.vars.truncate(self.vars.len() - n);
                Effect::Forall(vars, Box::new(body?))
            }
            "when" if items.len() == 3 => Effect::When(
                self.condition(&items[1])?,
                Box::new(self.effect(&items[2])?),
            ),
            "increase" if items.len() == 3 => {
                let target = list(&items[1], "(total-cost)")?;
                if target.len() != 1 || target[0].atom() != Some("total-cost") {
                    return expected(&items[1], "(total-cost)");
                }
                Effect::IncreaseCost(match &items[2] {
                    Sexpr::Atom(a, loc) => match a.parse::<i64>() {
                        Ok(v) if (0..=MAX_COST).contains(&v) => CostExpr::Constant(v),
                        _ => {
                            return err(
                                *loc,
                                ErrorKind::Expected {
                                    expected: format!(
                                        "a non-negative integer cost of at most {MAX_COST}"
                                    ),
                                    found: format!("`{}`", a.chars().take(40).collect::<String>()),
                                },
                            );
                        }
                    },
                    Sexpr::List(f, loc) => {
                        let Some(fname) = f.first() else {
                            return expected(&items[2], "a cost function");
                        };
                        let fname = atom(fname, "a function name")?;
                        let Some(sig) = self.domain.functions.iter().find(|s| s.name == fname)
                        else {
                            return err(*loc, ErrorKind::UndefinedFunction(fname.into()));
                        };
                        CostExpr::Function(
                            fname.into(),
                            self.args(fname, &sig.params, &f[1..], *loc)?,
                        )
                    }
                })
            }
            "not" | "when" | "increase" => {
                return expected(
                    node,
                    &format!("`{head}` with the right number of arguments"),
                );
            }
            _ => Effect::Add(self.atom(items, node.loc())?),
        })
    }
}

fn parse_action(d: &Domain, node: &Sexpr) -> R<Action> {
    let items = list(node, "(:action …)")?;
    let Some(name) = items.get(1) else {
        return expected(node, "an action name");
    };
    let name = atom(name, "an action name")?.to_string();
    let mut scope = Scope::new(d, &[]);
    let (mut precondition, mut effect) = (Condition::True, Effect::And(Vec::new()));
    let mut i = 2;
    while i < items.len() {
        let key = atom(&items[i], "`:parameters`, `:precondition` or `:effect`")?;
        let Some(value) = items.get(i + 1) else {
            return expected(&items[i], "a value after the keyword");
        };
        match key {
            ":parameters" => {
                for (p, loc) in typed_list(list(value, "a parameter list")?, true)? {
                    if !d.types.iter().any(|(n, _)| *n == p.type_name) {
                        return err(loc, ErrorKind::UndefinedType(p.type_name));
                    }
                    if scope.vars.iter().any(|v| v.name == p.name) {
                        return err(loc, ErrorKind::Duplicate(format!("?{}", p.name)));
                    }
                    scope.vars.push(p);
                }
            }
            ":precondition" => precondition = scope.condition(value)?,
            ":effect" => effect = scope.effect(value)?,
            other => {
                return err(
                    items[i].loc(),
                    ErrorKind::Syntax(format!("unknown action keyword `{other}`")),
                );
            }
        }
        i += 2;
    }
    Ok(Action {
        name,
        params: scope.vars,
        precondition,
        effect,
        loc: node.loc(),
    })
}

/// Parses a problem and checks it against `domain`.
pub fn parse_problem(text: &str, domain: &Domain) -> R<Problem> {
    let top = parse_all(text)?;
    let (name, sections, loc) = define(&top, "problem")?;
    let mut p = Problem {
        name: name.to_string(),
        domain_name: String::new(),
        objects: Vec::new(),
        init: Vec::new(),
        init_numeric: Vec::new(),
        goal: Condition::True,
        minimize_total_cost: false,
    };
    let mut init_nodes: &[Sexpr] = &[];
    let mut goal_node = None;
    for s in sections {
        let (head, items) = section(s, "a problem section such as (:init …)")?;
        match head {
            ":domain" => p.domain_name = problem_domain(s, items, domain)?,
            ":requirements" => {
                requirements(&items[1..])?;
            }
            ":objects" => declare_objects(&mut p, &items[1..], domain)?,
            ":init" => init_nodes = &items[1..],
            ":goal" => {
                let Some(g) = items.get(1) else {
                    return expected(s, "a goal condition");
                };
                goal_node = Some(g);
            }
            ":metric" => {
                let ok = items.len() == 3
                    && items[1].atom() == Some("minimize")
                    && items[2]
                        .list()
                        .is_some_and(|l| l.len() == 1 && l[0].atom() == Some("total-cost"));
                if !ok {
                    return expected(s, "(:metric minimize (total-cost))");
                }
                p.minimize_total_cost = true;
            }
            other => {
                return err(
                    items[0].loc(),
                    ErrorKind::Syntax(format!("unknown problem section `{other}`")),
                );
            }
        }
    }
    if p.domain_name.is_empty() {
        return err(
            loc,
            ErrorKind::Syntax("the problem names no (:domain …)".into()),
        );
    }
    let mut scope = Scope::new(domain, &p.objects);
    let mut init = Vec::new();
    let mut init_numeric = Vec::new();
    for node in init_nodes {
        let items = list(node, "an initial fact in parentheses")?;
        if items.is_empty() {
            return expected(node, "an initial fact");
        }
        if items[0].atom() == Some("=") {
            init_numeric.push(scope.numeric_fact(node, items)?);
            continue;
        }
        let a = scope.atom(items, node.loc())?;
        init.push(ground(&a.predicate, a.args));
    }
    init.sort();
    init.dedup();
    let goal = goal_node.map(|g| scope.condition(g)).transpose()?;
    p.init = init;
    p.init_numeric = init_numeric;
    if let Some(goal) = goal {
        p.goal = goal;
    }
    Ok(p)
}

/// The `:domain` section's name, which must be `domain`'s.
fn problem_domain(s: &Sexpr, items: &[Sexpr], domain: &Domain) -> R<String> {
    let Some(dn) = items.get(1) else {
        return expected(s, "a domain name");
    };
    let name = atom(dn, "a domain name")?.to_string();
    if name != domain.name {
        return err(
            dn.loc(),
            ErrorKind::DomainMismatch {
                domain: domain.name.clone(),
                problem_domain: name,
            },
        );
    }
    Ok(name)
}

/// An `:objects` section: each of a declared type, none named twice or as a constant.
fn declare_objects(p: &mut Problem, items: &[Sexpr], domain: &Domain) -> R<()> {
    let mut taken: std::collections::HashSet<String> = p
        .objects
        .iter()
        .chain(&domain.constants)
        .map(|k| k.name.clone())
        .collect();
    for (o, oloc) in typed_list(items, false)? {
        if !domain.types.iter().any(|(n, _)| *n == o.type_name) {
            return err(oloc, ErrorKind::UndefinedType(o.type_name));
        }
        if !taken.insert(o.name.clone()) {
            return err(oloc, ErrorKind::Duplicate(o.name));
        }
        p.objects.push(o);
    }
    Ok(())
}

impl Scope<'_> {
    /// An initial numeric fact `(= (function objects…) value)`.
    fn numeric_fact(&self, node: &Sexpr, items: &[Sexpr]) -> R<(GroundAtom, i64)> {
        if items.len() != 3 {
            return expected(node, "(= (function objects…) value)");
        }
        let f = list(&items[1], "(function objects…)")?;
        let Some(fname) = f.first() else {
            return expected(&items[1], "a function");
        };
        let fname = atom(fname, "a function name")?;
        let Some(sig) = self.domain.functions.iter().find(|s| s.name == fname) else {
            return err(items[1].loc(), ErrorKind::UndefinedFunction(fname.into()));
        };
        let args = self.args(fname, &sig.params, &f[1..], items[1].loc())?;
        let value = atom(&items[2], "a number")?;
        let Ok(value) = value.parse::<i64>() else {
            return expected(&items[2], "an integer value");
        };
        if !(-MAX_COST..=MAX_COST).contains(&value) {
            return expected(
                &items[2],
                &format!("an integer of at most {MAX_COST} in size"),
            );
        }
        Ok((ground(fname, args), value))
    }
}

fn ground(name: &str, args: Vec<Term>) -> GroundAtom {
    GroundAtom {
        predicate: name.into(),
        args: args
            .into_iter()
            .map(|t| match t {
                Term::Const(c) | Term::Var(c) => c,
            })
            .collect(),
    }
}
