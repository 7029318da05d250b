//! The little XML the VTK writers and readers need: attribute escaping and a
//! tag scanner for files we wrote ourselves.
//!
//! A full XML parser would be a dependency for no gain: VTK headers are flat,
//! attribute-only elements, and the readers here only ever see our own
//! output (plus hand edits, which get a clear error rather than a panic).

use std::io;

/// Escapes text for use inside a double-quoted attribute value.
pub(crate) fn escape_attr(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\n' => out.push_str("&#10;"),
            '\r' => out.push_str("&#13;"),
            '\t' => out.push_str("&#9;"),
            c => out.push(c),
        }
    }
    out
}

/// Reverses [`escape_attr`] (and the numeric character references any XML
/// writer may produce).
pub(crate) fn unescape(s: &str) -> io::Result<String> {
    let mut out = String::with_capacity(s.len());
    let mut rest = s;
    while let Some(i) = rest.find('&') {
        out.push_str(&rest[..i]);
        let after = &rest[i + 1..];
        let end = after
            .find(';')
            .ok_or_else(|| invalid(format!("unterminated entity in {s:?}")))?;
        let entity = &after[..end];
        let c = match entity {
            "amp" => '&',
            "lt" => '<',
            "gt" => '>',
            "quot" => '"',
            "apos" => '\'',
            _ => {
                let code = if let Some(hex) = entity.strip_prefix("#x") {
                    u32::from_str_radix(hex, 16).ok()
                } else if let Some(dec) = entity.strip_prefix('#') {
                    dec.parse().ok()
                } else {
                    None
                };
                code.and_then(char::from_u32)
                    .ok_or_else(|| invalid(format!("unknown entity &{entity}; in {s:?}")))?
            }
        };
        out.push(c);
        rest = &after[end + 1..];
    }
    out.push_str(rest);
    Ok(out)
}

pub(crate) fn invalid(msg: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidData, msg)
}

/// One markup item of the scanned text.
#[derive(Debug, PartialEq)]
pub(crate) enum Tag {
    /// `<name a="b">` or, with `self_closing`, `<name a="b"/>`.
    Open {
        name: String,
        attrs: Vec<(String, String)>,
        self_closing: bool,
        /// Byte offset just past the closing `>`.
        end: usize,
    },
    /// `</name>`.
    Close { name: String },
}

/// Scans the tags of `text`, skipping declarations (`<?...?>`), comments and
/// character data.
pub(crate) fn tags(text: &str) -> io::Result<Vec<Tag>> {
    let mut out = Vec::new();
    let mut pos = 0;
    while let Some(rel) = text[pos..].find('<') {
        let start = pos + rel;
        let rest = &text[start..];
        if rest.starts_with("<!--") {
            let close = rest
                .find("-->")
                .ok_or_else(|| invalid("unterminated XML comment".into()))?;
            pos = start + close + 3;
            continue;
        }
        let close = find_tag_end(rest)
            .ok_or_else(|| invalid(format!("unterminated XML tag at byte {start}")))?;
        let inner = &rest[1..close];
        pos = start + close + 1;
        if inner.starts_with('?') || inner.starts_with('!') {
            continue;
        }
        if let Some(name) = inner.strip_prefix('/') {
            out.push(Tag::Close {
                name: name.trim().to_string(),
            });
            continue;
        }
        let (body, self_closing) = match inner.strip_suffix('/') {
            Some(b) => (b, true),
            None => (inner, false),
        };
        let body = body.trim();
        let name_end = body.find(char::is_whitespace).unwrap_or(body.len());
        let name = body[..name_end].to_string();
        if name.is_empty() {
            return Err(invalid(format!("empty XML tag name at byte {start}")));
        }
        let attrs = parse_attrs(&body[name_end..])?;
        out.push(Tag::Open {
            name,
            attrs,
            self_closing,
            end: pos,
        });
    }
    Ok(out)
}

/// Position of the `>` that ends the tag starting at `s[0] == '<'`, ignoring
/// any `>` inside quoted attribute values.
fn find_tag_end(s: &str) -> Option<usize> {
    let mut quote: Option<char> = None;
    for (i, c) in s.char_indices() {
        match (quote, c) {
            (None, '"' | '\'') => quote = Some(c),
            (Some(q), c) if c == q => quote = None,
            (None, '>') => return Some(i),
            _ => {}
        }
    }
    None
}

fn parse_attrs(mut s: &str) -> io::Result<Vec<(String, String)>> {
    let mut out = Vec::new();
    loop {
        s = s.trim_start();
        if s.is_empty() {
            return Ok(out);
        }
        let eq = s
            .find('=')
            .ok_or_else(|| invalid(format!("attribute without value: {s:?}")))?;
        let key = s[..eq].trim().to_string();
        let after = s[eq + 1..].trim_start();
        let q = after
            .chars()
            .next()
            .filter(|c| *c == '"' || *c == '\'')
            .ok_or_else(|| invalid(format!("unquoted value for attribute {key:?}")))?;
        let val_end = after[1..]
            .find(q)
            .ok_or_else(|| invalid(format!("unterminated value for attribute {key:?}")))?;
        out.push((key, unescape(&after[1..1 + val_end])?));
        s = &after[val_end + 2..];
    }
}

/// Value of attribute `key`, if present.
pub(crate) fn attr<'a>(attrs: &'a [(String, String)], key: &str) -> Option<&'a str> {
    attrs
        .iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.as_str())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escape_round_trips() {
        let s = "a<b>&\"c' d\n\te";
        assert_eq!(unescape(&escape_attr(s)).unwrap(), s);
        assert_eq!(unescape("x&#65;&#x42;").unwrap(), "xAB");
        assert!(unescape("&bogus;").is_err());
        assert!(unescape("a & b").is_err());
    }

    #[test]
    fn scans_tags_and_attributes() {
        let text = r#"<?xml version="1.0"?><!-- c > d --><A x="1" y='a>b'><B z="&quot;"/></A>"#;
        let t = tags(text).unwrap();
        assert_eq!(t.len(), 3);
        match &t[0] {
            Tag::Open {
                name,
                attrs,
                self_closing,
                ..
            } => {
                assert_eq!(name, "A");
                assert!(!self_closing);
                assert_eq!(attr(attrs, "y"), Some("a>b"));
                assert_eq!(attr(attrs, "x"), Some("1"));
            }
            other => panic!("{other:?}"),
        }
        match &t[1] {
            Tag::Open {
                attrs,
                self_closing,
                ..
            } => {
                assert!(self_closing);
                assert_eq!(attr(attrs, "z"), Some("\""));
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(t[2], Tag::Close { name: "A".into() });
    }

    #[test]
    fn malformed_markup_is_an_error_not_a_panic() {
        for bad in ["<A", "<A x>", "<A x=1>", "<A x=\"1>", "<>", "<!-- x"] {
            assert!(tags(bad).is_err(), "{bad}");
        }
    }
}
