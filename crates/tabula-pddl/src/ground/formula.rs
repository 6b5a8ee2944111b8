//! Ground formulas in negation normal form and their DNF.

/// A grounded formula in negation normal form.
#[derive(Debug, Clone)]
pub(super) enum Gf {
    True,
    False,
    Lit(u32, bool),
    And(Vec<Gf>),
    Or(Vec<Gf>),
}

pub(super) fn and(items: Vec<Gf>) -> Gf {
    let mut out = Vec::with_capacity(items.len());
    for g in items {
        match g {
            Gf::True => {}
            Gf::False => return Gf::False,
            Gf::And(inner) => out.extend(inner),
            other => out.push(other),
        }
    }
    match out.len() {
        0 => Gf::True,
        1 => out.pop().unwrap_or(Gf::True),
        _ => Gf::And(out),
    }
}

pub(super) fn or(items: Vec<Gf>) -> Gf {
    let mut out = Vec::with_capacity(items.len());
    for g in items {
        match g {
            Gf::False => {}
            Gf::True => return Gf::True,
            Gf::Or(inner) => out.extend(inner),
            other => out.push(other),
        }
    }
    match out.len() {
        0 => Gf::False,
        1 => out.pop().unwrap_or(Gf::False),
        _ => Gf::Or(out),
    }
}

pub(super) const DNF_LIMIT: usize = 100_000;

/// Clauses of a DNF as sorted literal lists; contradictory clauses are dropped.
pub(super) fn dnf(g: &Gf) -> Option<Vec<Vec<(u32, bool)>>> {
    Some(match g {
        Gf::True => vec![Vec::new()],
        Gf::False => Vec::new(),
        Gf::Lit(a, p) => vec![vec![(*a, *p)]],
        Gf::Or(items) => {
            let mut out = Vec::new();
            for i in items {
                out.extend(dnf(i)?);
                if out.len() > DNF_LIMIT {
                    return None;
                }
            }
            out
        }
        Gf::And(items) => {
            let mut acc: Vec<Vec<(u32, bool)>> = vec![Vec::new()];
            for i in items {
                let part = dnf(i)?;
                let mut next = Vec::with_capacity(acc.len() * part.len());
                for a in &acc {
                    for p in &part {
                        let mut c = a.clone();
                        c.extend_from_slice(p);
                        c.sort_unstable();
                        c.dedup();
                        if c.windows(2).all(|w| w[0].0 != w[1].0) {
                            next.push(c);
                        }
                    }
                }
                if next.len() > DNF_LIMIT {
                    return None;
                }
                acc = next;
            }
            acc
        }
    })
}
