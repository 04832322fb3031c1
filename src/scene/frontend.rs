//! The front end of scene loading: text to a spanned document, `--set` overrides, the
//! serde schema and the rules, with every problem collected into one report.
//!
//! serde stops at the first unknown key or wrong type. To report them all, the file is
//! parsed once into a document in which every key and value keeps its span
//! ([`toml::de::DeTable`]); the schema is then tried on it repeatedly, and each value it
//! rejects is reported and taken out of the document before the next try. What is left
//! always fits the schema, so the rules in [`super::validate`] run on it too. A large
//! file that fits the schema is first read more quickly in slices ([`super::slices`]),
//! which give the same raw scene; any other file is read whole, as described here.
//!
//! A value taken out because of its type could make a rule report a problem that is
//! only a consequence (a body whose `mass` was a string "has no mass"), so the rules'
//! reports about that value, the tables holding it, and the values that depend on it
//! are left out. An unknown key changes nothing the rules read, so it hides nothing.

use std::ops::Range;
use std::path::Path;

use serde::Deserialize;
use sha2::{Digest, Sha256};
use toml::de::{DeTable, DeValue, Deserializer};

use super::raw::RawScene;
use super::{overrides, slices, validate, Diagnostic, Scene, SceneError, Sources};

/// Parses and validates the text of a scene file read from `path` (which only names it
/// in messages); [`Scene::load`] reads the file too.
///
/// ```
/// use std::path::Path;
/// use physframes::scene::parse;
///
/// let text = r#"
///     [render]
///     view = { min = [-1.0, -1.0], max = [1.0, 1.0] }
///     fps = 25
///     [[body]]
///     name = "puck"
///     mass = 2.0
///     velocity = [1.0, 0.0]
///     [[force]]
///     kind = "drag"
///     k = 0.5
/// "#;
/// let scene = parse(Path::new("puck.toml"), text).expect("a valid scene");
/// assert_eq!(scene.name, "puck");
/// assert_eq!(scene.bodies[0].mass, 2.0);
///
/// // Every problem is reported with its line and column.
/// let bad = text.replace("mass = 2.0", "mass = -2.0");
/// let error = parse(Path::new("puck.toml"), &bad).unwrap_err().to_string();
/// assert!(error.contains("`mass` must be > 0"));
/// assert!(error.contains("puck.toml:7:12"));
/// ```
pub fn parse(path: &Path, text: &str) -> Result<Scene, SceneError> {
    parse_with_overrides(path, text, &[])
}

/// Parses and validates the text of a scene file read from `path`, with the `--set`
/// overrides applied in order.
///
/// The scene's hash is the SHA-256 of the file's bytes when there is no override;
/// otherwise of the file's bytes followed, for each override in order, by a zero byte
/// and the argument's text, so that a render with overrides never passes for one
/// without.
pub fn parse_with_overrides(
    path: &Path,
    text: &str,
    overrides: &[String],
) -> Result<Scene, SceneError> {
    let error = |diagnostics| SceneError::new(path, text, diagnostics).with_overrides(overrides);
    let sources = Sources {
        file_len: text.len(),
        overrides,
    };
    let mut diagnostics = Vec::new();
    let mut pruned = Vec::new();
    // A large file is read in slices when it can be (see super::slices), with the
    // overrides that leave the bodies alone applied to the rest. That way vouches only
    // for a file that fits the schema and overrides that apply cleanly; any other file
    // is read whole, which finds and reports every problem.
    let sliced = if overrides.iter().any(|arg| overrides::may_touch_bodies(arg)) {
        None
    } else {
        slices::raw_scene(text, |root| {
            let mut problems = Vec::new();
            for (i, arg) in overrides.iter().enumerate() {
                overrides::apply(root, arg, sources.base(i), &mut problems);
            }
            problems.is_empty()
        })
    };
    let (root, raw) = match sliced {
        Some(raw) => (toml::Spanned::new(0..0, DeTable::default()), Some(raw)),
        None => match read_whole(text, &sources, &mut diagnostics, &mut pruned) {
            Ok(read) => read,
            // A syntax error stops parsing, so it is reported alone.
            Err(syntax) => return Err(error(vec![syntax])),
        },
    };
    if let Some(raw) = raw {
        let (scene, rules) = validate::check(path, text, raw);
        let poisoned = poisoned_spans(root.get_ref(), &pruned);
        let any_poison = pruned.iter().any(|p| !p.unknown_key);
        diagnostics.extend(rules.into_iter().filter(|d| match &d.span {
            Some(span) => !poisoned.iter().any(|p| overlaps(p, span)),
            // A problem of the whole file (no [render], too many frames) may follow from
            // a value taken out.
            None => !any_poison,
        }));
        if let (Some(mut scene), true) = (scene, diagnostics.is_empty()) {
            if !overrides.is_empty() {
                scene.source.hash = hash_with_overrides(text, overrides);
                scene.source.overrides = overrides.to_vec();
            }
            return Ok(scene);
        }
    }
    if diagnostics.is_empty() {
        // The schema failed without a place to point at; say so rather than nothing.
        diagnostics.push(Diagnostic::whole_file("the scene does not fit the schema"));
    }
    Err(error(diagnostics))
}

/// Reads the whole text into a document, applies the overrides and tries the schema on
/// it, taking out and reporting each value it rejects (see [`fit_schema`]). Returns the
/// document as far as the rules need it (empty when the schema took it whole) and the
/// raw scene, or the syntax error that stopped parsing.
fn read_whole<'i>(
    text: &'i str,
    sources: &Sources<'i>,
    diagnostics: &mut Vec<Diagnostic>,
    pruned: &mut Vec<Pruned>,
) -> Result<(toml::Spanned<DeTable<'i>>, Option<RawScene>), Diagnostic> {
    let overrides = sources.overrides;
    let mut root = DeTable::parse(text).map_err(|e| {
        let message = e.message().trim().to_string();
        match e.span() {
            Some(span) => Diagnostic::at(span, message),
            None => Diagnostic::whole_file(message),
        }
    })?;
    for (i, arg) in overrides.iter().enumerate() {
        overrides::apply(root.get_mut(), arg, sources.base(i), diagnostics);
    }
    // The schema is first tried on the document itself, which a scene that fits (the
    // usual case) then spends without a copy: copying 10,000 bodies' tables took a
    // quarter of parsing them. Only a rejected document is parsed again, with the same
    // overrides, for fit_schema to take apart.
    if let Ok(raw) = RawScene::deserialize(Deserializer::from(root)) {
        return Ok((toml::Spanned::new(0..0, DeTable::default()), Some(raw)));
    }
    let mut root = DeTable::parse(text).expect("the text parsed a moment ago");
    for (i, arg) in overrides.iter().enumerate() {
        // Their problems were reported the first time.
        overrides::apply(root.get_mut(), arg, sources.base(i), &mut Vec::new());
    }
    let raw = fit_schema(&mut root, diagnostics, pruned);
    Ok((root, raw))
}

/// Returns the hash of a scene file with overrides: SHA-256 over the file's bytes, then
/// a zero byte and each override's text, in order.
pub fn hash_with_overrides(text: &str, overrides: &[String]) -> String {
    let mut hasher = Sha256::new();
    hasher.update(text.as_bytes());
    for o in overrides {
        hasher.update([0u8]);
        hasher.update(o.as_bytes());
    }
    hasher
        .finalize()
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// A value taken out of the document because the schema rejected it.
#[derive(Debug)]
struct Pruned {
    /// Its key path: table keys and array indices, from the root.
    path: Vec<String>,
    /// The spans of its key (when it had one) and its value.
    spans: Vec<Range<usize>>,
    /// The spans of the tables that held it, innermost last.
    ancestors: Vec<Range<usize>>,
    /// True when it was taken out only because its key is unknown.
    unknown_key: bool,
}

/// Tries the schema on the document until it fits, reporting and taking out each value
/// it rejects. Returns the raw scene, or `None` when a rejection cannot be located.
fn fit_schema(
    root: &mut toml::Spanned<DeTable<'_>>,
    diagnostics: &mut Vec<Diagnostic>,
    pruned: &mut Vec<Pruned>,
) -> Option<RawScene> {
    // Every round takes out at least one value, so this ends; the cap is a guard.
    for _ in 0..10_000 {
        let e = match RawScene::deserialize(Deserializer::from(root.clone())) {
            Ok(raw) => return Some(raw),
            Err(e) => e,
        };
        let message = e.message().trim().to_string();
        let Some(span) = e.span() else {
            diagnostics.push(Diagnostic::whole_file(message));
            return None;
        };
        let consequence = is_consequence(&message, &span, pruned);
        let Some(mut p) = prune(root.get_mut(), &span) else {
            if !consequence {
                diagnostics.push(Diagnostic::at(span, message));
            }
            return None;
        };
        p.unknown_key = message.starts_with("unknown field");
        if !consequence {
            diagnostics.push(schema_diagnostic(span, &message, &p.path));
        }
        pruned.push(p);
    }
    None
}

/// Returns true when a rejection follows from an earlier one: it is about a value
/// already taken out, or says a table misses the very key taken out of it.
fn is_consequence(message: &str, span: &Range<usize>, pruned: &[Pruned]) -> bool {
    let missing = message
        .strip_prefix("missing field `")
        .and_then(|m| m.split('`').next());
    pruned.iter().any(|p| {
        p.spans.iter().any(|s| overlaps(s, span))
            || (missing.is_some()
                && p.ancestors.last() == Some(span)
                && p.path.last().map(String::as_str) == missing)
    })
}

/// Turns serde's message into a diagnostic: the key path as the label, and for an
/// unknown key the nearest known key and the list of known ones.
fn schema_diagnostic(span: Range<usize>, message: &str, path: &[String]) -> Diagnostic {
    // The list of known keys goes to the hint, not the headline.
    let headline = match message.split_once(", expected") {
        Some((head, _)) if message.starts_with("unknown field") => head,
        _ => message,
    };
    let d = Diagnostic::at(span, headline).label(format!("in `{}`", dotted(path)));
    match unknown_field_hint(message) {
        Some(hint) => d.hint(hint),
        None => d,
    }
}

/// Writes a key path as `body[0].mass`.
fn dotted(path: &[String]) -> String {
    let mut out = String::new();
    for segment in path {
        if segment.bytes().all(|b| b.is_ascii_digit()) && !out.is_empty() {
            out.push_str(&format!("[{segment}]"));
        } else {
            if !out.is_empty() {
                out.push('.');
            }
            out.push_str(segment);
        }
    }
    out
}

/// For serde's "unknown field `x`, expected one of `a`, `b`": suggests the nearest
/// known key and lists them all.
fn unknown_field_hint(message: &str) -> Option<String> {
    let rest = message.strip_prefix("unknown field `")?;
    let mut parts = rest.split('`');
    let unknown = parts.next()?;
    // After the unknown name, backquoted names alternate with the text between them.
    let known: Vec<&str> = parts.skip(1).step_by(2).collect();
    if known.is_empty() {
        return Some("this table takes no keys".to_string());
    }
    let nearest = known
        .iter()
        .map(|k| (edit_distance(unknown, k), *k))
        .min()
        .filter(|(d, k)| *d <= 2.max(k.len() / 3));
    let list = known.join(", ");
    Some(match nearest {
        Some((_, k)) => format!("did you mean `{k}`? this table takes: {list}"),
        None => format!("this table takes: {list}"),
    })
}

/// Returns the Levenshtein distance between two strings, counted in characters.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let substitute = diagonal + usize::from(ca != *cb);
            diagonal = row[j + 1];
            row[j + 1] = substitute.min(row[j] + 1).min(row[j + 1] + 1);
        }
    }
    row[b.len()]
}

/// Takes out of `table` the deepest value or key at `span`, and says what it was.
fn prune(table: &mut DeTable<'_>, span: &Range<usize>) -> Option<Pruned> {
    prune_table(table, span, &mut Vec::new(), &mut Vec::new())
}

fn prune_table(
    table: &mut DeTable<'_>,
    span: &Range<usize>,
    path: &mut Vec<String>,
    ancestors: &mut Vec<Range<usize>>,
) -> Option<Pruned> {
    let keys: Vec<String> = table.keys().map(|k| k.get_ref().to_string()).collect();
    for name in keys {
        let (key_span, value_span) = match table.get_key_value(name.as_str()) {
            Some((k, v)) => (k.span(), v.span()),
            None => continue,
        };
        path.push(name.clone());
        let found = if key_span == *span {
            None
        } else {
            table.get_mut(name.as_str()).and_then(|v| {
                let value_span = v.span();
                prune_value(v.get_mut(), value_span, span, path, ancestors)
            })
        };
        if found.is_some() {
            return found;
        }
        if key_span == *span || contains(&value_span, span) {
            table.remove(name.as_str());
            return Some(Pruned {
                path: path.clone(),
                spans: vec![key_span, value_span],
                ancestors: ancestors.clone(),
                unknown_key: false,
            });
        }
        path.pop();
    }
    None
}

fn prune_value(
    value: &mut DeValue<'_>,
    value_span: Range<usize>,
    span: &Range<usize>,
    path: &mut Vec<String>,
    ancestors: &mut Vec<Range<usize>>,
) -> Option<Pruned> {
    match value {
        DeValue::Table(table) => {
            ancestors.push(value_span);
            let found = prune_table(table, span, path, ancestors);
            ancestors.pop();
            found
        }
        DeValue::Array(items) => {
            for i in 0..items.len() {
                let item_span = items[i].span();
                path.push(i.to_string());
                let found = items.get_mut(i).and_then(|item| {
                    prune_value(item.get_mut(), item_span.clone(), span, path, ancestors)
                });
                if found.is_some() {
                    return found;
                }
                if contains(&item_span, span) {
                    let all = std::mem::replace(items, toml::de::DeArray::new());
                    *items = all
                        .into_iter()
                        .enumerate()
                        .filter_map(|(j, item)| (j != i).then_some(item))
                        .collect();
                    return Some(Pruned {
                        path: path.clone(),
                        spans: vec![item_span],
                        ancestors: ancestors.clone(),
                        unknown_key: false,
                    });
                }
                path.pop();
            }
            None
        }
        _ => None,
    }
}

/// Returns the spans about which the rules' reports may be mere consequences of values
/// taken out: those values, the tables that held them, and the values that depend on
/// them across tables (dt on fps; forces on the bodies' names).
fn poisoned_spans(root: &DeTable<'_>, pruned: &[Pruned]) -> Vec<Range<usize>> {
    let mut spans = Vec::new();
    for p in pruned.iter().filter(|p| !p.unknown_key) {
        spans.extend(p.spans.iter().cloned());
        spans.extend(p.ancestors.iter().cloned());
        let path: Vec<&str> = p.path.iter().map(String::as_str).collect();
        match path.as_slice() {
            // Whether frames fall on steps depends on fps.
            ["render"] | ["render", "fps"] => {
                if let Some(dt) = root
                    .get("simulation")
                    .and_then(|s| s.get_ref().as_table())
                    .and_then(|s| s.get("dt"))
                {
                    spans.push(dt.span());
                }
            }
            // Forces name bodies.
            ["body"] | ["body", _] | ["body", _, "name"] => {
                if let Some(forces) = root.get("force") {
                    collect_spans(forces, &mut spans);
                }
            }
            _ => {}
        }
    }
    spans.retain(|s| !s.is_empty());
    spans
}

/// Collects the span of a value and of everything inside it.
fn collect_spans(value: &toml::Spanned<DeValue<'_>>, spans: &mut Vec<Range<usize>>) {
    spans.push(value.span());
    match value.get_ref() {
        DeValue::Table(t) => {
            for (k, v) in t.iter() {
                spans.push(k.span());
                collect_spans(v, spans);
            }
        }
        DeValue::Array(items) => {
            for item in items {
                collect_spans(item, spans);
            }
        }
        _ => {}
    }
}

/// Returns true when `outer` holds all of `inner`; an empty `outer` holds nothing.
fn contains(outer: &Range<usize>, inner: &Range<usize>) -> bool {
    !outer.is_empty() && outer.start <= inner.start && inner.end <= outer.end
}

/// Returns true when two spans share a byte, or are the same empty span.
fn overlaps(a: &Range<usize>, b: &Range<usize>) -> bool {
    (a.start < b.end && b.start < a.end) || a == b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_keys_get_the_nearest_known_key() {
        let hint =
            unknown_field_hint("unknown field `mas`, expected one of `name`, `mass`, `position`");
        assert_eq!(
            hint.as_deref(),
            Some("did you mean `mass`? this table takes: name, mass, position")
        );
        let hint = unknown_field_hint("unknown field `zzz`, expected `x`");
        assert_eq!(hint.as_deref(), Some("this table takes: x"));
    }

    #[test]
    fn edit_distance_counts_insertions_deletions_and_substitutions() {
        assert_eq!(edit_distance("mas", "mass"), 1);
        assert_eq!(edit_distance("fsp", "fps"), 2);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
    }

    #[test]
    fn key_paths_read_like_toml() {
        let path: Vec<String> = ["body", "1", "mass"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        assert_eq!(dotted(&path), "body[1].mass");
    }
}
