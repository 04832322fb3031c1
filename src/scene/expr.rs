//! Expressions a scene writes, such as `f = "-v/m"`: checked, located and compiled once.
//!
//! The `exmex` crate parses and evaluates. Its errors carry no position, so a small
//! lexer runs first and catches what people get wrong (an unknown variable, an unknown
//! character, unbalanced parentheses, two operators in a row, a missing operator) with
//! the byte range of the offending token inside the expression. Whatever exmex still
//! rejects is reported at the whole expression. [`file_span`] turns a range inside the
//! string into a range of the scene file, so the caret points inside the quotes.
//!
//! A compiled [`Expr`] reads its variables from a slice of *slots* that the caller
//! fills: the names given to [`compile`] in order, so `compile("-v/m", &["t", "v", "m"])`
//! reads `v` from slot 1 and `m` from slot 2. Evaluation never fails: an expression that
//! cannot be evaluated (a division by zero, `sqrt(-1)`) gives a non-finite number, which
//! the renderer skips.

use std::ops::Range;

use exmex::{Express, FlatEx};
use toml::Spanned;

/// Functions exmex knows, called as `name(argument)`.
pub const FUNCTIONS: &[&str] = &[
    "abs", "signum", "sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh", "asinh",
    "acosh", "atanh", "floor", "round", "ceil", "trunc", "fract", "exp", "sqrt", "cbrt", "ln",
    "log2", "log10", "log",
];

/// Functions of two arguments, called as `name(a, b)`.
pub const BINARY_FUNCTIONS: &[&str] = &["atan2", "min", "max"];

/// Named constants exmex substitutes.
pub const CONSTANTS: &[&str] = &["PI", "π", "E", "e", "TAU", "τ"];

/// The most variables one expression may read without a heap allocation per call.
const STACK_VARS: usize = 16;

/// A compiled expression that reads its variables from caller-filled slots.
#[derive(Clone, Debug)]
pub struct Expr {
    /// The expression as the scene wrote it.
    text: String,
    /// Boxed: exmex keeps its nodes inline, some 20 kB.
    flat: Box<FlatEx<f64>>,
    /// For each of exmex's variables (sorted by name), the slot it reads.
    slots: Vec<usize>,
}

impl PartialEq for Expr {
    /// Two expressions are equal when they were written the same and read the same slots.
    fn eq(&self, other: &Self) -> bool {
        self.text == other.text && self.slots == other.slots
    }
}

impl Expr {
    /// The expression as written.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// Returns true when the expression reads slot `slot`.
    pub fn reads(&self, slot: usize) -> bool {
        self.slots.contains(&slot)
    }

    /// Evaluates the expression with `values[i]` as the value of slot i. Returns NaN when
    /// exmex cannot evaluate it.
    pub fn eval(&self, values: &[f64]) -> f64 {
        let n = self.slots.len();
        let gather = |buffer: &mut [f64]| {
            for (b, &s) in buffer.iter_mut().zip(&self.slots) {
                *b = values.get(s).copied().unwrap_or(f64::NAN);
            }
        };
        let result = if n <= STACK_VARS {
            let mut buffer = [0.0; STACK_VARS];
            gather(&mut buffer[..n]);
            self.flat.eval(&buffer[..n])
        } else {
            let mut buffer = vec![0.0; n];
            gather(&mut buffer);
            self.flat.eval(&buffer)
        };
        result.unwrap_or(f64::NAN)
    }
}

/// Why an expression was rejected, with the bytes of the expression it is about.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExprError {
    /// What is wrong.
    pub message: String,
    /// The offending bytes of the expression, or `None` for the whole of it.
    pub range: Option<Range<usize>>,
    /// A short label for under the caret.
    pub label: String,
    /// What to change.
    pub hint: Option<String>,
}

impl ExprError {
    fn at(range: Range<usize>, message: impl Into<String>, label: impl Into<String>) -> Self {
        ExprError {
            message: message.into(),
            range: Some(range),
            label: label.into(),
            hint: None,
        }
    }

    fn hint(mut self, hint: impl Into<String>) -> Self {
        self.hint = Some(hint.into());
        self
    }
}

/// Checks and compiles `text`, whose variables may be the `names` (slot i is `names[i]`).
pub fn compile(text: &str, names: &[&str]) -> Result<Expr, ExprError> {
    let mut tokens = lex(text)?;
    check(text, &mut tokens, names)?;
    // Exmex reads a variable name in braces verbatim, which lets names hold dots, as
    // `puck.vx` does; every variable is handed over in that form.
    let mut rewritten = String::with_capacity(text.len() + 8);
    for token in &tokens {
        match token.kind {
            Kind::Variable => {
                let name = variable_name(&text[token.range.clone()]);
                rewritten.push('{');
                rewritten.push_str(name);
                rewritten.push('}');
            }
            // Exmex reads plain decimals only, so `1.5e-3` is handed over as `0.0015`;
            // Rust prints an f64 without an exponent and exactly.
            Kind::Number => match text[token.range.clone()].parse::<f64>() {
                Ok(v) => rewritten.push_str(&format!("{v}")),
                Err(_) => rewritten.push_str(&text[token.range.clone()]),
            },
            _ => rewritten.push_str(&text[token.range.clone()]),
        }
        rewritten.push(' ');
    }
    let flat = exmex::parse::<f64>(rewritten.trim_end()).map_err(|e| ExprError {
        message: format!("`{text}` is not an expression: {}", e.msg()),
        range: None,
        label: "cannot be parsed".into(),
        hint: Some(syntax_hint()),
    })?;
    let slots = flat
        .var_names()
        .iter()
        .map(|v| names.iter().position(|n| n == v))
        .collect::<Option<Vec<usize>>>()
        .ok_or_else(|| ExprError {
            message: format!("`{text}` reads a variable it may not"),
            range: None,
            label: String::new(),
            hint: Some(allowed_hint(names)),
        })?;
    Ok(Expr {
        text: text.to_string(),
        flat: Box::new(flat),
        slots,
    })
}

/// Returns the bytes of the scene file that `range` (bytes of the string's value) covers,
/// when the string is written plainly between quotes; otherwise the whole string, quotes
/// included, as escapes make the mapping uncertain.
pub fn file_span(file: &str, value: &Spanned<String>, range: Option<Range<usize>>) -> Range<usize> {
    let span = value.span();
    let plain = span.end >= span.start + 2
        && file.get(span.start + 1..span.end - 1) == Some(value.get_ref().as_str());
    match range {
        Some(r) if plain => span.start + 1 + r.start..span.start + 1 + r.end.max(r.start + 1),
        _ => span,
    }
}

/// Lists the variables an expression may read, for hints.
pub fn allowed_hint(names: &[&str]) -> String {
    if names.is_empty() {
        "this expression may read no variable; write a number".into()
    } else {
        format!(
            "the variables here are {}; functions such as sin, exp, sqrt, ln, abs, atan2(y, x), min(a, b); constants PI and E",
            names
                .iter()
                .map(|n| format!("`{n}`"))
                .collect::<Vec<_>>()
                .join(", ")
        )
    }
}

/// Returns true when `name` can be a variable: not a function or constant, and spelt
/// like an identifier.
pub fn is_valid_name(name: &str) -> bool {
    let mut chars = name.chars();
    chars.next().is_some_and(|c| c.is_alphabetic() || c == '_')
        && chars.all(|c| c.is_alphanumeric() || c == '_' || c == '.')
        && !FUNCTIONS.contains(&name)
        && !BINARY_FUNCTIONS.contains(&name)
        && !CONSTANTS.contains(&name)
}

fn syntax_hint() -> String {
    "write arithmetic with + - * / ^ and parentheses, e.g. \"-v/m\" or \"x^2 + C\"".into()
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Number,
    /// A variable, a function or a constant; told apart by [`check`].
    Name,
    /// A name that [`check`] found to be a variable.
    Variable,
    Operator,
    Comma,
    Open,
    Close,
}

#[derive(Clone, Debug)]
struct Token {
    kind: Kind,
    range: Range<usize>,
}

/// Splits an expression into tokens with their byte ranges.
fn lex(text: &str) -> Result<Vec<Token>, ExprError> {
    let mut tokens = Vec::new();
    let mut chars = text.char_indices().peekable();
    while let Some(&(i, c)) = chars.peek() {
        let single = |kind| Token {
            kind,
            range: i..i + c.len_utf8(),
        };
        match c {
            c if c.is_whitespace() => {
                chars.next();
            }
            '+' | '-' | '*' | '/' | '^' => {
                tokens.push(single(Kind::Operator));
                chars.next();
            }
            ',' => {
                tokens.push(single(Kind::Comma));
                chars.next();
            }
            '(' => {
                tokens.push(single(Kind::Open));
                chars.next();
            }
            ')' => {
                tokens.push(single(Kind::Close));
                chars.next();
            }
            '{' => {
                let Some(close) = text[i..].find('}') else {
                    return Err(ExprError::at(
                        i..text.len(),
                        "`{` opens a variable name that is never closed",
                        "no `}` after this",
                    ));
                };
                tokens.push(Token {
                    kind: Kind::Name,
                    range: i..i + close + 1,
                });
                while chars.next_if(|&(j, _)| j <= i + close).is_some() {}
            }
            c if c.is_ascii_digit() || c == '.' => {
                let end = number_end(text, i);
                let literal = &text[i..end];
                if literal.parse::<f64>().is_err() {
                    return Err(ExprError::at(
                        i..end,
                        format!("`{literal}` is not a number"),
                        "not a number",
                    )
                    .hint("write numbers like 2, 0.5, 1.5e-3"));
                }
                tokens.push(Token {
                    kind: Kind::Number,
                    range: i..end,
                });
                while chars.next_if(|&(j, _)| j < end).is_some() {}
            }
            c if c.is_alphabetic() || c == '_' => {
                let mut end = i;
                let bytes = text.as_bytes();
                for (j, d) in text[i..].char_indices() {
                    let j = i + j;
                    // A dot continues a name when a letter follows it: `puck.vx`.
                    let dotted = d == '.'
                        && text[j + 1..]
                            .chars()
                            .next()
                            .is_some_and(|n| n.is_alphabetic() || n == '_');
                    if d.is_alphanumeric() || d == '_' || dotted {
                        end = j + d.len_utf8();
                    } else {
                        break;
                    }
                }
                debug_assert!(end <= bytes.len());
                tokens.push(Token {
                    kind: Kind::Name,
                    range: i..end,
                });
                while chars.next_if(|&(j, _)| j < end).is_some() {}
            }
            _ => {
                return Err(ExprError::at(
                    i..i + c.len_utf8(),
                    format!("unexpected character `{c}` in an expression"),
                    "not part of an expression",
                )
                .hint(syntax_hint()));
            }
        }
    }
    Ok(tokens)
}

/// Returns the end of the number starting at byte `start`: digits, one dot, and an
/// exponent `e`/`E` with an optional sign.
fn number_end(text: &str, start: usize) -> usize {
    let bytes = text.as_bytes();
    let mut i = start;
    while i < bytes.len() && (bytes[i].is_ascii_digit() || bytes[i] == b'.') {
        i += 1;
    }
    if i < bytes.len() && (bytes[i] == b'e' || bytes[i] == b'E') {
        let mut j = i + 1;
        if j < bytes.len() && (bytes[j] == b'+' || bytes[j] == b'-') {
            j += 1;
        }
        if j < bytes.len() && bytes[j].is_ascii_digit() {
            while j < bytes.len() && bytes[j].is_ascii_digit() {
                j += 1;
            }
            i = j;
        }
    }
    i
}

/// The variable name a name token stands for: braces removed.
fn variable_name(token: &str) -> &str {
    token
        .strip_prefix('{')
        .and_then(|t| t.strip_suffix('}'))
        .unwrap_or(token)
}

/// Checks names and the order of tokens, and marks variables.
fn check(text: &str, tokens: &mut [Token], names: &[&str]) -> Result<(), ExprError> {
    if tokens.is_empty() {
        return Err(ExprError {
            message: "the expression is empty".into(),
            range: None,
            label: "nothing to evaluate".into(),
            hint: Some(syntax_hint()),
        });
    }
    // Names: functions, constants or allowed variables.
    let mut functions = vec![false; tokens.len()];
    for (k, token) in tokens.iter_mut().enumerate() {
        if token.kind != Kind::Name {
            continue;
        }
        let word = &text[token.range.clone()];
        let braced = word.starts_with('{');
        let name = variable_name(word);
        if !braced && (FUNCTIONS.contains(&name) || BINARY_FUNCTIONS.contains(&name)) {
            functions[k] = true;
        } else if !braced && CONSTANTS.contains(&name) {
            token.kind = Kind::Number;
        } else if names.contains(&name) {
            token.kind = Kind::Variable;
        } else {
            return Err(ExprError::at(
                token.range.clone(),
                format!("unknown variable `{name}` in `{text}`"),
                "not a variable here",
            )
            .hint(allowed_hint(names)));
        }
    }
    let is_operand_end = |k: Kind| matches!(k, Kind::Number | Kind::Variable | Kind::Close);
    let is_operand_start = |k: Kind| matches!(k, Kind::Number | Kind::Variable | Kind::Open);
    let mut open: Vec<Range<usize>> = Vec::new();
    for (k, token) in tokens.iter().enumerate() {
        let previous = k.checked_sub(1).map(|p| (&tokens[p], functions[p]));
        let op = &text[token.range.clone()];
        match token.kind {
            Kind::Open => open.push(token.range.clone()),
            Kind::Close => {
                if open.pop().is_none() {
                    return Err(ExprError::at(
                        token.range.clone(),
                        format!("`)` closes nothing in `{text}`"),
                        "no `(` before it",
                    ));
                }
                if let Some((p, _)) = previous {
                    if matches!(p.kind, Kind::Open | Kind::Operator | Kind::Comma) {
                        return Err(ExprError::at(
                            token.range.clone(),
                            format!("a value is missing before `)` in `{text}`"),
                            "expected a value before this",
                        ));
                    }
                }
            }
            Kind::Operator => {
                let binary_only = matches!(op, "*" | "/" | "^");
                let after_operand = previous.is_some_and(|(p, f)| !f && is_operand_end(p.kind));
                if binary_only && !after_operand {
                    return Err(ExprError::at(
                        token.range.clone(),
                        format!("`{op}` needs a value on its left in `{text}`"),
                        "nothing to apply it to",
                    ));
                }
                if k + 1 == tokens.len() {
                    return Err(ExprError::at(
                        token.range.clone(),
                        format!("`{op}` needs a value on its right in `{text}`"),
                        "the expression ends here",
                    ));
                }
            }
            Kind::Comma => {
                if previous.is_none_or(|(p, _)| !is_operand_end(p.kind)) {
                    return Err(ExprError::at(
                        token.range.clone(),
                        format!("a value is missing before `,` in `{text}`"),
                        "expected a value before this",
                    ));
                }
            }
            Kind::Number | Kind::Variable | Kind::Name => {}
        }
        // A function name must be followed by its parenthesised argument.
        if functions[k] && tokens.get(k + 1).is_none_or(|n| n.kind != Kind::Open) {
            return Err(ExprError::at(
                token.range.clone(),
                format!("the function `{op}` needs its argument in parentheses"),
                "expected `(` after this",
            )
            .hint(format!("e.g. {op}(x)")));
        }
        // Two values side by side need an operator between them.
        if let Some((p, p_function)) = previous {
            let juxtaposed = is_operand_end(p.kind)
                && (is_operand_start(token.kind) || functions[k])
                && !p_function;
            if juxtaposed {
                let what = if token.kind == Kind::Open && p.kind == Kind::Variable {
                    format!("`{}` is a variable, not a function", &text[p.range.clone()])
                } else {
                    format!(
                        "an operator is missing between `{}` and `{op}` in `{text}`",
                        &text[p.range.clone()]
                    )
                };
                return Err(ExprError::at(
                    token.range.clone(),
                    what,
                    "expected an operator before this",
                )
                .hint("write multiplication explicitly, e.g. 2*x"));
            }
        }
    }
    if let Some(unclosed) = open.pop() {
        return Err(ExprError::at(
            unclosed,
            format!("`(` is never closed in `{text}`"),
            "no matching `)`",
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn error(text: &str, names: &[&str]) -> ExprError {
        match compile(text, names) {
            Ok(_) => panic!("`{text}` should be rejected"),
            Err(e) => e,
        }
    }

    /// Returns the text the error points at.
    fn pointed<'a>(text: &'a str, e: &ExprError) -> &'a str {
        e.range.clone().map_or(text, |r| &text[r])
    }

    #[test]
    fn expressions_read_their_slots_by_name() {
        let e = compile("-v/m", &["t", "v", "m"]).expect("valid");
        assert_eq!(e.eval(&[9.0, 3.0, 2.0]), -1.5);
        assert!(e.reads(1) && e.reads(2) && !e.reads(0));
        let p = compile("x^2 + C", &["x", "y", "t", "C"]).expect("valid");
        assert_eq!(p.eval(&[3.0, 0.0, 0.0, -1.0]), 8.0);
        let f = compile("2*exp(-t) + sin(PI*x) + max(x, t)", &["x", "t"]).expect("valid");
        let want = 2.0 * (-1.0f64).exp() + (std::f64::consts::PI * 0.5).sin() + 1.0;
        assert!((f.eval(&[0.5, 1.0]) - want).abs() < 1e-12);
        let dotted = compile("puck.vx * 2 + {my puck.x}", &["puck.vx", "my puck.x"]).expect("ok");
        assert_eq!(dotted.eval(&[1.5, 1.0]), 4.0);
        let scientific = compile("1.5e-3*x + 2E2", &["x"]).expect("valid");
        assert_eq!(scientific.eval(&[1000.0]), 201.5);
    }

    #[test]
    fn errors_point_at_the_offending_token() {
        let cases: &[(&str, &str, &str)] = &[
            ("-z/m", "z", "unknown variable `z`"),
            ("2*x + $", "$", "unexpected character"),
            ("(x + 1", "(", "never closed"),
            ("x + 1)", ")", "closes nothing"),
            ("x * * 2", "*", "needs a value on its left"),
            ("x +", "+", "needs a value on its right"),
            ("2 x", "x", "operator is missing"),
            ("x(2)", "(", "is a variable, not a function"),
            ("sin x", "sin", "in parentheses"),
            ("1.2.3", "1.2.3", "not a number"),
            ("max(x, )", ")", "missing before `)`"),
        ];
        for (text, at, message) in cases {
            let e = error(text, &["x", "y", "m"]);
            assert_eq!(pointed(text, &e), *at, "{text}: {e:?}");
            assert!(e.message.contains(message), "{text}: {}", e.message);
        }
    }

    #[test]
    fn unknown_variables_name_the_allowed_ones() {
        let e = error("-q", &["t", "v", "m"]);
        let hint = e.hint.unwrap_or_default();
        assert!(hint.contains("`t`, `v`, `m`"), "{hint}");
    }

    #[test]
    fn empty_expressions_are_errors_about_the_whole_string() {
        let e = error("  ", &["x"]);
        assert_eq!(e.range, None);
    }

    #[test]
    fn file_spans_point_inside_plain_strings_only() {
        let file = "f = \"-z/m\"\ng = \"a\\u0062\"\n";
        let plain = Spanned::new(4..10, "-z/m".to_string());
        assert_eq!(&file[file_span(file, &plain, Some(1..2))], "z");
        let escaped = Spanned::new(15..24, "ab".to_string());
        assert_eq!(file_span(file, &escaped, Some(1..2)), 15..24);
    }

    #[test]
    fn names_that_clash_with_functions_or_constants_are_invalid() {
        assert!(is_valid_name("m") && is_valid_name("v0") && is_valid_name("C"));
        assert!(!is_valid_name("e") && !is_valid_name("sin") && !is_valid_name("2x"));
    }
}
