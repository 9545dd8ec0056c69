//! Named numbers of a scene: a `[parameters]` table of numbers, and
//! expressions that use them wherever a number stands, written as a string
//! that begins with `=`:
//!
//! ```toml
//! [parameters]
//! drum_radius = 100.0
//! thickness = 1.0
//!
//! [[body]]
//! mesh = { generator = "ring", r_inner = "= drum_radius", r_outer = "= drum_radius + thickness", ... }
//! ```
//!
//! Before the scene is read, each expression is evaluated and its string
//! replaced in the text by the number, on the same line, so that every
//! check of the number (range, type: an integer key takes only an integral
//! value) and every error's file:line is the one a number written there
//! would get; the error then also names the expression.
//!
//! The expressions are arithmetic on f64 (`+ - * / ^`, parentheses, the
//! constant `pi`, and `sqrt sin cos tan asin acos atan exp ln abs` of one
//! argument; angles in radians): a hand-written evaluator, because the
//! expression crates at hand treat `1/2` as integer division (0), a trap in
//! a geometry file.

use super::locate::{self, Source};
use super::{SceneError, SceneErrorKind};
use crate::problem::Parameter;
use std::ops::Range;
use toml::Spanned;
use toml::de::DeValue;

/// One expression replaced in the text: where (line), what was written, and
/// the number it gave.
pub(super) struct Substitution {
    pub line: usize,
    pub expression: String,
    pub value: f64,
}

/// The scene text with every `"= ..."` replaced by its value, the
/// parameters (with `overrides` applied: name, value), and what was
/// replaced.
pub(super) fn substitute(
    src: &Source,
    overrides: &[(String, f64)],
) -> Result<(String, Vec<Parameter>, Vec<Substitution>), SceneError> {
    let parameters = read_table(src, overrides)?;
    let mut found: Vec<(Range<usize>, String, f64)> = Vec::new();
    for (k, v) in src.doc.get_ref().iter() {
        if k.get_ref() != "parameters" {
            walk(src, &parameters, v, k.get_ref(), &mut found)?;
        }
    }
    let mut text = src.text.to_string();
    let mut subs = Vec::with_capacity(found.len());
    // Back to front, so that the spans before each replacement stay right.
    found.sort_by_key(|(span, ..)| std::cmp::Reverse(span.start));
    for (span, expression, value) in found {
        text.replace_range(span.clone(), &number_literal(value));
        subs.push(Substitution {
            line: locate::line_of(src.text, span.start),
            expression,
            value,
        });
    }
    Ok((text, parameters, subs))
}

/// Adds to a scene error the expressions on its line (the number it shows
/// came from them).
pub(super) fn annotate(mut e: SceneError, subs: &[Substitution]) -> SceneError {
    let here: Vec<String> = (subs.iter().rev())
        .filter(|s| s.line == e.line)
        .map(|s| format!("\"{}\" = {}", s.expression, s.value))
        .collect();
    if !here.is_empty() {
        e.message = format!("{} (from {})", e.message, here.join(", "));
    }
    e
}

/// A number as TOML writes it: an integer when the value is one (so that an
/// integer key such as `divisions` takes "= 2 * n"), else Rust's shortest
/// round-trip form.
fn number_literal(value: f64) -> String {
    if value.fract() == 0.0 && value.abs() < 9.0e15 {
        format!("{}", value as i64)
    } else {
        format!("{value:?}")
    }
}

fn read_table(src: &Source, overrides: &[(String, f64)]) -> Result<Vec<Parameter>, SceneError> {
    let mut out: Vec<Parameter> = Vec::new();
    if let Some(table) = src.doc.get_ref().get("parameters") {
        let Some(t) = table.get_ref().as_table() else {
            let msg = "[parameters] is a table of numbers: name = value";
            return Err(src.at(
                SceneErrorKind::InvalidValue,
                table.span(),
                "parameters",
                msg,
            ));
        };
        // In file order (the FMU's variables follow it).
        let mut entries: Vec<_> = t.iter().collect();
        entries.sort_by_key(|(k, _)| k.span().start);
        for (k, v) in entries {
            let name = k.get_ref().to_string();
            let key = format!("parameters.{name}");
            if !is_name(&name) || name == "pi" || FUNCTIONS.iter().any(|(f, _)| *f == name) {
                let msg = "a parameter's name is a letter followed by letters, digits or '_', and not pi or a function's name";
                return Err(src.at(SceneErrorKind::InvalidValue, k.span(), key, msg));
            }
            let value = match v.get_ref() {
                DeValue::Float(f) => f.as_str().parse::<f64>().ok(),
                DeValue::Integer(i) => i64::from_str_radix(i.as_str(), i.radix())
                    .ok()
                    .map(|i| i as f64),
                _ => None,
            };
            let Some(value) = value.filter(|x| x.is_finite()) else {
                let msg = "a parameter's value is a finite number (expressions may use parameters, not define them)";
                return Err(src.at(SceneErrorKind::InvalidValue, v.span(), key, msg));
            };
            out.push(Parameter {
                name,
                value,
                default: value,
            });
        }
    }
    // A value set from outside (the FMU, --set) is reported at the
    // [parameters] table.
    let table_at = src
        .doc
        .get_ref()
        .get("parameters")
        .map_or(0, |t| t.span().start);
    for (name, value) in overrides {
        let key = format!("parameters.{name}");
        let Some(p) = out.iter_mut().find(|p| &p.name == name) else {
            let known: Vec<&str> = out.iter().map(|p| p.name.as_str()).collect();
            let msg = format!(
                "no such parameter; the scene's [parameters]: {}",
                known.join(", ")
            );
            return Err(src.error(
                SceneErrorKind::UnknownReference,
                table_at,
                key,
                value.to_string(),
                msg,
            ));
        };
        if !value.is_finite() {
            let msg = "not a finite number".to_string();
            return Err(src.error(
                SceneErrorKind::InvalidValue,
                table_at,
                key,
                value.to_string(),
                msg,
            ));
        }
        p.value = *value;
    }
    Ok(out)
}

fn walk(
    src: &Source,
    parameters: &[Parameter],
    value: &Spanned<DeValue>,
    path: &str,
    found: &mut Vec<(Range<usize>, String, f64)>,
) -> Result<(), SceneError> {
    match value.get_ref() {
        DeValue::String(s) if s.trim_start().starts_with('=') => {
            let expression = s.trim_start()[1..].trim().to_string();
            let value_of = |name: &str| parameters.iter().find(|p| p.name == name).map(|p| p.value);
            let v = evaluate(&expression, &value_of)
                .map_err(|msg| src.at(SceneErrorKind::InvalidValue, value.span(), path, msg))?;
            found.push((value.span(), expression, v));
        }
        DeValue::Table(t) => {
            for (k, v) in t.iter() {
                walk(src, parameters, v, &locate::join(path, k.get_ref()), found)?;
            }
        }
        DeValue::Array(a) => {
            for (i, v) in a.iter().enumerate() {
                walk(src, parameters, v, &format!("{path}[{i}]"), found)?;
            }
        }
        _ => {}
    }
    Ok(())
}

fn is_name(s: &str) -> bool {
    let mut chars = s.chars();
    chars.next().is_some_and(|c| c.is_ascii_alphabetic())
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

type Function = fn(f64) -> f64;

const FUNCTIONS: [(&str, Function); 10] = [
    ("sqrt", f64::sqrt),
    ("sin", f64::sin),
    ("cos", f64::cos),
    ("tan", f64::tan),
    ("asin", f64::asin),
    ("acos", f64::acos),
    ("atan", f64::atan),
    ("exp", f64::exp),
    ("ln", f64::ln),
    ("abs", f64::abs),
];

/// The value of an arithmetic expression whose names are looked up in
/// `value_of` (and `pi`); an error says what is wrong, and where.
pub fn evaluate(text: &str, value_of: &dyn Fn(&str) -> Option<f64>) -> Result<f64, String> {
    let mut p = Parser {
        text,
        pos: 0,
        value_of,
    };
    let v = p.sum()?;
    p.skip_space();
    if p.pos < text.len() {
        return Err(p.fail("an operator or the end"));
    }
    if !v.is_finite() {
        return Err(format!(
            "expression \"{text}\" gives {v}, not a finite number"
        ));
    }
    Ok(v)
}

/// Recursive descent: sum = product {(+|-) product}; product = signed
/// {(*|/) signed}; signed = - signed | power; power = atom [^ signed];
/// atom = number | name | function ( sum ) | ( sum ).
struct Parser<'a> {
    text: &'a str,
    pos: usize,
    value_of: &'a dyn Fn(&str) -> Option<f64>,
}

impl Parser<'_> {
    fn skip_space(&mut self) {
        while self.text[self.pos..].starts_with(' ') || self.text[self.pos..].starts_with('\t') {
            self.pos += 1;
        }
    }

    fn peek(&mut self) -> Option<char> {
        self.skip_space();
        self.text[self.pos..].chars().next()
    }

    fn fail(&self, wanted: &str) -> String {
        let rest = &self.text[self.pos..];
        let at = if rest.is_empty() {
            "the end".to_string()
        } else {
            format!("\"{rest}\"")
        };
        format!("expression \"{}\": {wanted} expected at {at}", self.text)
    }

    fn sum(&mut self) -> Result<f64, String> {
        let mut v = self.product()?;
        while let Some(op @ ('+' | '-')) = self.peek() {
            self.pos += 1;
            let rhs = self.product()?;
            v = if op == '+' { v + rhs } else { v - rhs };
        }
        Ok(v)
    }

    fn product(&mut self) -> Result<f64, String> {
        let mut v = self.signed()?;
        while let Some(op @ ('*' | '/')) = self.peek() {
            self.pos += 1;
            let rhs = self.signed()?;
            v = if op == '*' { v * rhs } else { v / rhs };
        }
        Ok(v)
    }

    fn signed(&mut self) -> Result<f64, String> {
        if self.peek() == Some('-') {
            self.pos += 1;
            return Ok(-self.signed()?);
        }
        self.power()
    }

    fn power(&mut self) -> Result<f64, String> {
        let base = self.atom()?;
        if self.peek() == Some('^') {
            self.pos += 1;
            return Ok(base.powf(self.signed()?));
        }
        Ok(base)
    }

    fn atom(&mut self) -> Result<f64, String> {
        match self.peek() {
            Some('(') => {
                self.pos += 1;
                let v = self.sum()?;
                if self.peek() != Some(')') {
                    return Err(self.fail("\")\""));
                }
                self.pos += 1;
                Ok(v)
            }
            Some(c) if c.is_ascii_digit() || c == '.' => self.number(),
            Some(c) if c.is_ascii_alphabetic() => self.name(),
            _ => Err(self.fail("a number, a name or \"(\"")),
        }
    }

    fn number(&mut self) -> Result<f64, String> {
        let rest = &self.text[self.pos..];
        let mut end = rest
            .find(|c: char| !(c.is_ascii_digit() || c == '.'))
            .unwrap_or(rest.len());
        // An exponent: e or E, an optional sign, digits.
        let tail = &rest[end..];
        if tail.starts_with(['e', 'E']) {
            let sign = usize::from(tail[1..].starts_with(['+', '-']));
            let digits = tail[1 + sign..]
                .find(|c: char| !c.is_ascii_digit())
                .unwrap_or(tail.len() - 1 - sign);
            if digits > 0 {
                end += 1 + sign + digits;
            }
        }
        let v = rest[..end]
            .parse::<f64>()
            .map_err(|_| self.fail("a number"))?;
        self.pos += end;
        Ok(v)
    }

    fn name(&mut self) -> Result<f64, String> {
        let rest = &self.text[self.pos..];
        let end = rest
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(rest.len());
        let name = &rest[..end];
        let start = self.pos;
        self.pos += end;
        if let Some((_, f)) = FUNCTIONS.iter().find(|(n, _)| *n == name) {
            if self.peek() != Some('(') {
                return Err(self.fail(&format!("\"(\" after {name}")));
            }
            return self.atom().map(f);
        }
        if name == "pi" {
            return Ok(std::f64::consts::PI);
        }
        (self.value_of)(name).ok_or_else(|| {
            format!(
                "expression \"{}\": no parameter named \"{name}\" (at \"{}\"); [parameters] defines the names",
                self.text,
                &self.text[start..]
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eval(text: &str) -> Result<f64, String> {
        let names = |n: &str| match n {
            "r" => Some(100.0),
            "t" => Some(1.5),
            "n" => Some(4.0),
            _ => None,
        };
        evaluate(text, &names)
    }

    #[test]
    fn arithmetic_in_f64_with_the_usual_precedence() {
        assert_eq!(eval("1/2").unwrap(), 0.5);
        assert_eq!(eval("r + t").unwrap(), 101.5);
        assert_eq!(eval("2 * r + t * 2").unwrap(), 203.0);
        assert_eq!(eval("(r + t) * 2").unwrap(), 203.0);
        assert_eq!(eval("r - t - 1").unwrap(), 97.5);
        assert_eq!(eval("r / n / 5").unwrap(), 5.0);
        assert_eq!(eval("-2^2").unwrap(), -4.0);
        assert_eq!(eval("2^-1").unwrap(), 0.5);
        assert_eq!(eval("2^3^2").unwrap(), 512.0);
        assert_eq!(eval("-(r)").unwrap(), -100.0);
        assert_eq!(eval("1.5e2 + 2E-1 + .5").unwrap(), 150.7);
        assert_eq!(eval("sqrt(n) * cos(0) + abs(-t)").unwrap(), 3.5);
        assert_eq!(eval("180 * atan(1) / pi").unwrap(), 45.0);
    }

    #[test]
    fn errors_say_what_and_where() {
        let e = eval("r + ").unwrap_err();
        assert!(
            e.contains("a number, a name or \"(\" expected at the end"),
            "{e}"
        );
        let e = eval("r + radius").unwrap_err();
        assert!(e.contains("no parameter named \"radius\""), "{e}");
        let e = eval("(r + t").unwrap_err();
        assert!(e.contains("\")\" expected"), "{e}");
        let e = eval("r t").unwrap_err();
        assert!(
            e.contains("an operator or the end expected at \"t\""),
            "{e}"
        );
        let e = eval("r / 0").unwrap_err();
        assert!(e.contains("gives inf, not a finite number"), "{e}");
        let e = eval("sqrt r").unwrap_err();
        assert!(e.contains("\"(\" after sqrt"), "{e}");
        assert!(eval("ln(0 - 1)").unwrap_err().contains("NaN"));
    }

    #[test]
    fn integral_values_are_written_as_integers() {
        assert_eq!(number_literal(64.0), "64");
        assert_eq!(number_literal(-3.0), "-3");
        assert_eq!(number_literal(0.5), "0.5");
        assert_eq!(number_literal(1e-8), "1e-8");
        assert_eq!(number_literal(1e20), "1e20");
    }
}
