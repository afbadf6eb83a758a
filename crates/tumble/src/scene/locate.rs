//! Finding a field path in the source text, so that errors found after
//! deserialization (a negative mass, a mesh that is not closed) point at the
//! line and column of the offending value. TOML is re-parsed with `toml`'s
//! spanned document tree, JSON with `jsonc-parser`'s AST (both keep byte
//! ranges). A path that does not exist in the text (a default was used) is
//! located at its deepest existing ancestor.

use super::error::{FieldPath, PathSeg};
use super::Format;

/// 1-based line and column (in characters) of byte `offset` in `text`.
pub fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = before[line_start..].chars().count() + 1;
    (line, column)
}

/// Byte offset of the value at `path` (or of its deepest existing ancestor).
pub fn locate(text: &str, format: Format, path: &FieldPath) -> usize {
    match format {
        Format::Toml => locate_toml(text, path),
        Format::Json => locate_json(text, path),
    }
}

fn locate_toml(text: &str, path: &FieldPath) -> usize {
    use toml::de::{DeTable, DeValue};
    let Ok(root) = DeTable::parse(text) else {
        return 0;
    };
    let span = root.span();
    let root = toml::Spanned::new(span, DeValue::Table(root.into_inner()));
    let mut found = root.span().start;
    let mut value = &root;
    for seg in &path.0 {
        let next = match (seg, value.get_ref()) {
            (PathSeg::Key(k), DeValue::Table(t)) => {
                t.iter().find(|(key, _)| key.get_ref() == k).map(|(_, v)| v)
            }
            (PathSeg::Index(i), DeValue::Array(a)) => a.get(*i),
            _ => None,
        };
        match next {
            Some(v) => {
                found = v.span().start;
                value = v;
            }
            None => break,
        }
    }
    found
}

fn locate_json(text: &str, path: &FieldPath) -> usize {
    use jsonc_parser::ast::Value;
    use jsonc_parser::common::Ranged;
    let parsed = jsonc_parser::parse_to_ast(text, &Default::default(), &Default::default());
    let Ok(Some(root)) = parsed.map(|p| p.value) else {
        return 0;
    };
    let mut found = root.start();
    let mut value = &root;
    for seg in &path.0 {
        let next = match (seg, value) {
            (PathSeg::Key(k), Value::Object(o)) => o.get(k).map(|p| &p.value),
            (PathSeg::Index(i), Value::Array(a)) => a.elements.get(*i),
            _ => None,
        };
        match next {
            Some(v) => {
                found = v.start();
                value = v;
            }
            None => break,
        }
    }
    found
}
