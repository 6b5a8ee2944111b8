//! S-expressions with source positions: the layer under the PDDL parser.
//!
//! PDDL is case-insensitive; atoms are lower-cased here once, and every node keeps the
//! line and column it started at so every later error can name its place.

use crate::{ErrorKind, Loc, PddlError};

/// One node: an atom (symbol, variable, number) or a parenthesised list.
#[derive(Debug, Clone, PartialEq)]
pub enum Sexpr {
    Atom(String, Loc),
    List(Vec<Sexpr>, Loc),
}

impl Sexpr {
    pub fn loc(&self) -> Loc {
        match self {
            Sexpr::Atom(_, l) | Sexpr::List(_, l) => *l,
        }
    }

    pub fn atom(&self) -> Option<&str> {
        match self {
            Sexpr::Atom(a, _) => Some(a),
            Sexpr::List(..) => None,
        }
    }

    pub fn list(&self) -> Option<&[Sexpr]> {
        match self {
            Sexpr::List(items, _) => Some(items),
            Sexpr::Atom(..) => None,
        }
    }
}

/// Deepest nesting accepted: the grounder and validator recurse over formulas, and no
/// real domain comes near this.
pub const MAX_DEPTH: usize = 256;

/// Reads every top-level expression of `text`; `;` starts a comment to end of line.
pub fn parse_all(text: &str) -> Result<Vec<Sexpr>, PddlError> {
    let mut stack: Vec<(Vec<Sexpr>, Loc)> = Vec::new();
    let mut top = Vec::new();
    let (mut line, mut col) = (1usize, 1usize);
    let mut chars = text.chars().peekable();
    while let Some(&c) = chars.peek() {
        let here = Loc { line, column: col };
        match c {
            '\n' => {
                chars.next();
                line += 1;
                col = 1;
            }
            c if c.is_whitespace() => {
                chars.next();
                col += 1;
            }
            ';' => {
                while let Some(&c) = chars.peek() {
                    if c == '\n' {
                        break;
                    }
                    chars.next();
                }
            }
            '(' => {
                chars.next();
                col += 1;
                if stack.len() >= MAX_DEPTH {
                    return Err(PddlError::at(
                        here,
                        ErrorKind::Syntax(format!("nesting deeper than {MAX_DEPTH} levels")),
                    ));
                }
                stack.push((Vec::new(), here));
            }
            ')' => {
                chars.next();
                col += 1;
                let (items, start) = stack.pop().ok_or_else(|| {
                    PddlError::at(here, ErrorKind::Syntax("unexpected `)`".into()))
                })?;
                let node = Sexpr::List(items, start);
                match stack.last_mut() {
                    Some((parent, _)) => parent.push(node),
                    None => top.push(node),
                }
            }
            _ => {
                let mut atom = String::new();
                while let Some(&c) = chars.peek() {
                    if c.is_whitespace() || c == '(' || c == ')' || c == ';' {
                        break;
                    }
                    atom.extend(c.to_lowercase());
                    chars.next();
                    col += 1;
                }
                let node = Sexpr::Atom(atom, here);
                match stack.last_mut() {
                    Some((parent, _)) => parent.push(node),
                    None => top.push(node),
                }
            }
        }
    }
    if let Some((_, start)) = stack.pop() {
        return Err(PddlError::at(
            start,
            ErrorKind::Syntax("this `(` is never closed".into()),
        ));
    }
    Ok(top)
}
