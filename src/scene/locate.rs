//! Where in the scene file a thing is: byte spans become `file:line`, the
//! dotted key and the value as written. Every `SceneError` is made here,
//! including the translation of toml/serde errors, which carry only a span.

use super::{SceneError, SceneErrorKind};
use std::ops::Range;
use std::path::Path;
use toml::Spanned;
use toml::de::{DeTable, DeValue};

/// The value shown for a key that is not there.
const MISSING: &str = "(missing)";
/// Longest value text quoted in a message.
const MAX_VALUE_CHARS: usize = 60;

/// The scene text and its parsed document, for locating spans.
pub(super) struct Source<'a> {
    pub file: &'a Path,
    pub text: &'a str,
    pub doc: &'a Spanned<DeTable<'a>>,
}

impl Source<'_> {
    /// An error about the value at `span`, shown as written in the file.
    pub fn at(
        &self,
        kind: SceneErrorKind,
        span: Range<usize>,
        key: impl Into<String>,
        message: impl Into<String>,
    ) -> SceneError {
        let value = value_text(self.text, span.clone());
        self.error(kind, span.start, key.into(), value, message.into())
    }

    /// A required key that is absent from the table at `table_span`.
    pub fn missing(
        &self,
        table_span: Range<usize>,
        key: impl Into<String>,
        message: impl Into<String>,
    ) -> SceneError {
        self.error(
            SceneErrorKind::MissingKey,
            table_span.start,
            key.into(),
            MISSING.into(),
            message.into(),
        )
    }

    pub(super) fn error(
        &self,
        kind: SceneErrorKind,
        offset: usize,
        key: String,
        value: String,
        message: String,
    ) -> SceneError {
        SceneError {
            kind,
            file: self.file.to_path_buf(),
            line: line_of(self.text, offset),
            key,
            value,
            message,
        }
    }

    /// A toml/serde error (unknown key, missing key, wrong type, unknown
    /// variant), located by its span in the parsed document.
    pub fn toml(&self, e: &toml::de::Error) -> SceneError {
        let span = e.span().unwrap_or(0..0);
        let (path, value_span) = locate(self.doc, span.clone()).unwrap_or_default();
        let msg = e.message();
        if let Some(field) = quoted(msg)
            .next()
            .filter(|_| msg.starts_with("missing field"))
        {
            return self.missing(span, join(&path, field), "required key is missing");
        }
        let (kind, message) = if msg.starts_with("unknown field") {
            let allowed: Vec<&str> = quoted(msg).skip(1).collect();
            let message = if allowed.is_empty() {
                "unknown key; this table takes no keys".to_string()
            } else {
                format!("unknown key; allowed keys: {}", allowed.join(", "))
            };
            (SceneErrorKind::UnknownKey, message)
        } else if msg.starts_with("unknown variant") {
            let allowed: Vec<&str> = quoted(msg).skip(1).collect();
            (
                SceneErrorKind::InvalidValue,
                format!("must be one of: {}", allowed.join(", ")),
            )
        } else if let Some((found, expected)) = wrong_type(msg) {
            (
                SceneErrorKind::WrongType,
                format!("expected {}, found {found}", readable(expected)),
            )
        } else if msg == "wanted string or table" {
            // toml's word for a value that cannot name an enum variant.
            (SceneErrorKind::WrongType, "expected a string".to_string())
        } else {
            (SceneErrorKind::InvalidValue, msg.to_string())
        };
        let value = value_text(self.text, value_span);
        self.error(kind, span.start, path, value, message)
    }
}

/// A TOML syntax error. There is no document to locate it in, so the key is
/// read from the text: the last table header before the line, and the key
/// written on it; the value is the rest of the line.
pub(super) fn syntax_error(file: &Path, text: &str, e: &toml::de::Error) -> SceneError {
    let offset = e.span().map_or(0, |s| s.start).min(text.len());
    let line = line_of(text, offset);
    let lines: Vec<&str> = text.lines().collect();
    let line_text = lines.get(line - 1).map_or("", |l| l.trim());
    let table = lines[..(line - 1).min(lines.len())]
        .iter()
        .rev()
        .find_map(|l| header(l))
        .map(|h| {
            // The index of an array-of-tables entry is the number of its headers so far.
            let count = lines[..line - 1]
                .iter()
                .filter(|l| header(l) == Some(h))
                .count();
            match h.strip_prefix("[[") {
                Some(name) => format!("{}[{}]", name.trim_end_matches(']').trim(), count - 1),
                None => h.trim_matches(|c| c == '[' || c == ']').trim().to_string(),
            }
        });
    let (key, value) = match (header(line_text), line_text.split_once('=')) {
        (Some(h), _) => (
            h.trim_matches(|c| c == '[' || c == ']').trim().to_string(),
            line_text,
        ),
        (None, Some((k, v))) => (join(table.as_deref().unwrap_or(""), k.trim()), v.trim()),
        (None, None) => match line_text.split_once(char::is_whitespace) {
            Some((k, v)) => (join(table.as_deref().unwrap_or(""), k), v.trim()),
            None => (table.unwrap_or_else(|| "(document)".into()), line_text),
        },
    };
    SceneError {
        kind: SceneErrorKind::Syntax,
        file: file.to_path_buf(),
        line,
        key,
        value: value.to_string(),
        message: format!(
            "TOML syntax: {}",
            e.message().trim().trim_end_matches(", expected nothing")
        ),
    }
}

/// The header of a table line (`[name]` or `[[name]]`) without its comment.
fn header(line: &str) -> Option<&str> {
    let line = line.split('#').next().unwrap_or("").trim();
    let name = line
        .strip_prefix('[')?
        .strip_suffix(']')?
        .trim_matches(|c| c == '[' || c == ']');
    let bare = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "_-. ".contains(c));
    bare.then_some(line)
}

/// Non-finite numbers (nan, inf, or overflow) are refused wherever they are.
pub(super) fn check_finite(src: &Source) -> Result<(), SceneError> {
    fn walk(src: &Source, value: &Spanned<DeValue>, path: &str) -> Result<(), SceneError> {
        match value.get_ref() {
            DeValue::Float(f) if !f.as_str().parse::<f64>().is_ok_and(f64::is_finite) => {
                let message = "numbers must be finite";
                return Err(src.at(SceneErrorKind::InvalidValue, value.span(), path, message));
            }
            DeValue::Table(t) => {
                for (k, v) in t.iter() {
                    walk(src, v, &join(path, k.get_ref()))?;
                }
            }
            DeValue::Array(a) => {
                for (i, v) in a.iter().enumerate() {
                    walk(src, v, &format!("{path}[{i}]"))?;
                }
            }
            _ => {}
        }
        Ok(())
    }
    for (k, v) in src.doc.get_ref().iter() {
        walk(src, v, &join("", k.get_ref()))?;
    }
    Ok(())
}

/// The value at a dotted path of the document (`["body", "0", "mesh"]`:
/// numeric parts index arrays).
pub(super) fn lookup<'d, 'i>(
    doc: &'d Spanned<DeTable<'i>>,
    path: &[&str],
) -> Option<&'d Spanned<DeValue<'i>>> {
    let (first, rest) = path.split_first()?;
    let mut value = doc.get_ref().get(*first)?;
    for part in rest {
        value = match part.parse::<usize>() {
            Ok(i) => value.get_ref().get(i)?,
            Err(_) => value.get_ref().get(*part)?,
        };
    }
    Some(value)
}

/// 1-based line of a byte offset.
pub(super) fn line_of(text: &str, offset: usize) -> usize {
    1 + text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
}

/// The value as written: its first line, shortened if long.
fn value_text(text: &str, span: Range<usize>) -> String {
    let raw = text.get(span).unwrap_or("").trim();
    let first = raw.lines().next().unwrap_or("");
    if first.chars().count() > MAX_VALUE_CHARS {
        let cut: String = first.chars().take(MAX_VALUE_CHARS).collect();
        format!("{cut} ...")
    } else if first.len() < raw.len() {
        format!("{first} ...")
    } else {
        first.to_string()
    }
}

/// `path.key`, quoting keys that are not bare TOML keys.
pub(super) fn join(path: &str, key: &str) -> String {
    let bare = !key.is_empty()
        && key
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    let key = if bare {
        key.to_string()
    } else {
        format!("{key:?}")
    };
    if path.is_empty() {
        key
    } else {
        format!("{path}.{key}")
    }
}

/// The dotted path of the node whose key or value has exactly this span
/// (the deepest one), else of the deepest value containing it; with the span
/// of its value.
fn locate(doc: &Spanned<DeTable>, span: Range<usize>) -> Option<(String, Range<usize>)> {
    fn exact(
        value: &Spanned<DeValue>,
        path: &str,
        span: &Range<usize>,
    ) -> Option<(String, Range<usize>)> {
        match value.get_ref() {
            DeValue::Table(t) => {
                for (k, v) in t.iter() {
                    let child = join(path, k.get_ref());
                    if let Some(found) = exact(v, &child, span) {
                        return Some(found);
                    }
                    if k.span() == *span {
                        return Some((child, v.span()));
                    }
                }
            }
            DeValue::Array(a) => {
                for (i, v) in a.iter().enumerate() {
                    if let Some(found) = exact(v, &format!("{path}[{i}]"), span) {
                        return Some(found);
                    }
                }
            }
            _ => {}
        }
        (value.span() == *span).then(|| (path.to_string(), value.span()))
    }
    fn containing(
        value: &Spanned<DeValue>,
        path: &str,
        span: &Range<usize>,
    ) -> Option<(String, Range<usize>)> {
        let children: Vec<(String, &Spanned<DeValue>)> = match value.get_ref() {
            DeValue::Table(t) => t
                .iter()
                .map(|(k, v)| (join(path, k.get_ref()), v))
                .collect(),
            DeValue::Array(a) => a
                .iter()
                .enumerate()
                .map(|(i, v)| (format!("{path}[{i}]"), v))
                .collect(),
            _ => Vec::new(),
        };
        for (child, v) in children {
            if let Some(found) = containing(v, &child, span) {
                return Some(found);
            }
        }
        let s = value.span();
        (s.start <= span.start && span.end <= s.end).then(|| (path.to_string(), s))
    }
    let root = Spanned::new(doc.span(), DeValue::Table(doc.get_ref().clone()));
    if let Some(found) = exact(&root, "", &span) {
        return Some(found);
    }
    // serde reports a key missing from the document itself with an empty span.
    if span.is_empty() {
        return Some((String::new(), span));
    }
    containing(&root, "", &span)
}

/// The backtick-quoted words of a serde message, in order.
fn quoted(msg: &str) -> impl Iterator<Item = &str> {
    msg.split('`').skip(1).step_by(2)
}

/// `(found, expected)` of serde's "invalid type/value/length" messages.
fn wrong_type(msg: &str) -> Option<(String, &str)> {
    if let Some(rest) = msg.strip_prefix("invalid length ") {
        let (count, expected) = rest.split_once(", expected ")?;
        let found = if count == "1" {
            "1 value".to_string()
        } else {
            format!("{count} values")
        };
        return Some((found, expected));
    }
    let rest = msg
        .strip_prefix("invalid type: ")
        .or_else(|| msg.strip_prefix("invalid value: "))?;
    let (found, expected) = rest.split_once(", expected ")?;
    Some((readable(found), expected))
}

/// serde's names for types, in the scene's words.
fn readable(serde_name: &str) -> String {
    match serde_name {
        "f64" | "f32" => "a number".into(),
        "usize" | "u64" | "u32" => "a non-negative integer".into(),
        "a sequence" | "sequence" => "an array".into(),
        "a map" | "map" => "a table".into(),
        e if e.starts_with("struct ") => "a table".into(),
        e => e.into(),
    }
}
