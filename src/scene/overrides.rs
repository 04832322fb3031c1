//! `--set KEY=VALUE`: scene values overridden from the command line.
//!
//! An override is applied to the parsed document before the schema and the rules see
//! it, so an overridden value is checked exactly like one written in the file. Its
//! spans point into the argument itself (see [`super::Sources`]), so a problem is
//! shown in the `--set` argument that caused it, with a caret under the bad part.
//!
//! Keys are TOML dotted keys. `body.NAME.key` addresses the `[[body]]` named NAME
//! (an unnamed body is `body0`, `body1`, … as in the scene), `force.N.key` the N-th
//! `[[force]]` counted from 0 (and likewise `NAME.N.key` for any array of tables, whose
//! tables may also be addressed by their `name`, as in `swarm.discs.seed`), and
//! any other path a plain table path such as `simulation.dt` or `render.view.min`;
//! missing tables are created. The value is a
//! TOML value; text that is not one (a bare word such as `--set name=demo`) is taken
//! as a string.

use std::borrow::Cow;
use std::ops::Range;

use toml::de::{DeTable, DeValue};
use toml::Spanned;

use super::Diagnostic;

/// One segment of an override's key path, with its span.
struct Segment {
    name: String,
    span: Range<usize>,
}

/// Applies the override `arg`, whose text starts at offset `base`, to the document
/// `root`. A problem with the argument itself (no `=`, an unknown body, …) is pushed to
/// `diagnostics` and the document is left unchanged.
pub(super) fn apply<'i>(
    root: &mut DeTable<'i>,
    arg: &'i str,
    base: usize,
    diagnostics: &mut Vec<Diagnostic>,
) {
    match parse(arg, base).and_then(|(path, value)| insert(root, &path, value)) {
        Ok(()) => {}
        Err(d) => diagnostics.push(d),
    }
}

/// Returns true when the override `arg` may change the bodies' tables: its key path
/// starts with `body`, or it cannot be read at all (the whole-document path then
/// reports why).
pub(super) fn may_touch_bodies(arg: &str) -> bool {
    let Some(eq) = equals_sign(arg) else {
        return true;
    };
    key_path(&arg[..eq], 0).map_or(true, |path| path.first().is_none_or(|s| s.name == "body"))
}

/// Splits `KEY=VALUE` into the key's segments and the value, with spans offset by
/// `base`.
fn parse(arg: &str, base: usize) -> Result<(Vec<Segment>, Spanned<DeValue<'_>>), Diagnostic> {
    let whole = base..base + arg.len();
    let Some(eq) = equals_sign(arg) else {
        return Err(Diagnostic::at(whole, "`--set` expects KEY=VALUE")
            .label("no `=` here")
            .hint("e.g. --set simulation.dt=0.001 or --set body.puck.mass=2"));
    };
    let path = key_path(&arg[..eq], base)?;
    let value_text = &arg[eq + 1..];
    let value_start = eq + 1;
    if value_text.trim().is_empty() {
        return Err(
            Diagnostic::at(base + eq..base + eq + 1, "`--set` has no value after `=`")
                .hint("give a TOML value, e.g. 2, 0.5, [0, 1], true or \"text\""),
        );
    }
    let value = match DeValue::parse(value_text) {
        Ok(value) => shift(value, base + value_start),
        Err(_) => {
            // Not a TOML value: take the text, trimmed, as a string, so that
            // `--set name=demo` works without shell-escaped quotes.
            let leading = value_text.len() - value_text.trim_start().len();
            let text = value_text.trim();
            let start = base + value_start + leading;
            Spanned::new(
                start..start + text.len(),
                DeValue::String(Cow::Owned(text.to_string())),
            )
        }
    };
    Ok((path, value))
}

/// Returns the byte index of the first `=` outside quotes.
fn equals_sign(arg: &str) -> Option<usize> {
    let mut quote: Option<char> = None;
    for (i, c) in arg.char_indices() {
        match (quote, c) {
            (None, '"' | '\'') => quote = Some(c),
            (Some(q), c) if c == q => quote = None,
            (None, '=') => return Some(i),
            _ => {}
        }
    }
    None
}

/// Parses a dotted TOML key, as TOML itself does, into segments with spans.
fn key_path(key: &str, base: usize) -> Result<Vec<Segment>, Diagnostic> {
    let bad = || {
        Diagnostic::at(
            base..base + key.len(),
            format!("`{}` is not a key", key.trim()),
        )
        .label("expected a dotted key")
        .hint("write a dotted key such as simulation.dt, render.view.min or body.puck.mass")
    };
    if key.trim().is_empty() {
        return Err(bad());
    }
    // `KEY = 0` is a TOML document whose only entry is the key path; parsing it gives
    // the segments, quoted or bare, with spans that are offsets into `key`.
    let probe = format!("{key}= 0");
    let document = DeTable::parse(&probe).map_err(|_| bad())?;
    let mut segments = Vec::new();
    let mut table = document.get_ref();
    loop {
        let mut entries = table.iter();
        let (Some((k, v)), None) = (entries.next(), entries.next()) else {
            return Err(bad());
        };
        let span = k.span();
        segments.push(Segment {
            name: k.get_ref().to_string(),
            span: base + span.start..base + span.end,
        });
        match v.get_ref() {
            DeValue::Table(inner) => table = inner,
            _ => return Ok(segments),
        }
    }
}

/// Inserts `value` at `path` in the document.
fn insert<'i>(
    root: &mut DeTable<'i>,
    path: &[Segment],
    value: Spanned<DeValue<'i>>,
) -> Result<(), Diagnostic> {
    let (table, rest) = match path[0].name.as_str() {
        "body" if path.len() > 1 => (find_body(root, &path[1])?, &path[2..]),
        "force" if path.len() > 1 => (find_force(root, &path[1])?, &path[2..]),
        _ => (root, path),
    };
    let Some((last, parents)) = rest.split_last() else {
        let whole = path[0].span.start..path[1].span.end;
        return Err(Diagnostic::at(
            whole,
            format!("`{}.{}` names a whole table", path[0].name, path[1].name),
        )
        .label("set one of its keys")
        .hint(format!(
            "e.g. --set {}.{}.mass=2",
            path[0].name, path[1].name
        )));
    };
    let mut table = table;
    let mut depth = 0;
    while depth < parents.len() {
        let segment = &parents[depth];
        let key = Spanned::new(segment.span.clone(), Cow::Owned(segment.name.clone()));
        let span = segment.span.clone();
        let entry = table
            .entry(key)
            .or_insert_with(|| Spanned::new(span, DeValue::Table(DeTable::new())));
        let so_far = |end: usize| {
            parents[..=end]
                .iter()
                .map(|s| s.name.as_str())
                .collect::<Vec<_>>()
                .join(".")
        };
        match entry.get_mut() {
            DeValue::Table(inner) => {
                table = inner;
                depth += 1;
            }
            // `NAME.N.key` addresses the N-th table of an array of tables, such as
            // `force.N` or any other `[[NAME]]`.
            DeValue::Array(_) if depth + 1 == parents.len() => {
                return Err(Diagnostic::at(
                    segment.span.clone(),
                    format!(
                        "`{}` is an array, not a table, so it has no key `{}`",
                        so_far(depth),
                        last.name
                    ),
                )
                .label("not a table")
                .hint(format!(
                    "a table in an array of tables is addressed by its index: {}.0.{}",
                    so_far(depth),
                    last.name
                )));
            }
            DeValue::Array(items) => {
                let index = &parents[depth + 1];
                let count = items.len();
                // By its index, or by its `name` (a swarm's, say: swarm.discs.seed).
                let at = index.name.parse::<usize>().ok().or_else(|| {
                    items.iter().position(|item| {
                        item.get_ref()
                            .as_table()
                            .and_then(|t| t.get("name"))
                            .and_then(|n| n.get_ref().as_str())
                            == Some(index.name.as_str())
                    })
                });
                // The names, for the hint when neither finds a table.
                let names: Vec<String> = items
                    .iter()
                    .filter_map(|item| item.get_ref().as_table())
                    .filter_map(|t| t.get("name").and_then(|n| n.get_ref().as_str()))
                    .map(str::to_string)
                    .collect();
                match at.and_then(|i| items.get_mut(i)).map(|item| item.get_mut()) {
                    Some(DeValue::Table(inner)) => {
                        table = inner;
                        depth += 2;
                    }
                    _ => {
                        let named = if names.is_empty() {
                            String::new()
                        } else {
                            format!(", named {}", names.join(", "))
                        };
                        return Err(Diagnostic::at(
                            index.span.clone(),
                            format!("`{}` has no table `{}`", so_far(depth), index.name),
                        )
                        .label("an index counted from 0 in file order, or a `name`")
                        .hint(format!(
                            "`{}` holds {count} item{}{named}",
                            so_far(depth),
                            if count == 1 { "" } else { "s" }
                        )));
                    }
                }
            }
            other => {
                return Err(Diagnostic::at(
                    segment.span.clone(),
                    format!(
                        "`{}` is {}, not a table, so it has no key `{}`",
                        so_far(depth),
                        with_article(other.type_str()),
                        rest[depth + 1].name
                    ),
                )
                .label("not a table"));
            }
        }
    }
    let key = Spanned::new(last.span.clone(), Cow::Owned(last.name.clone()));
    // A key already in the table keeps its place in the file, but the value and its
    // spans are the override's. Removing first makes the key's span the override's too,
    // so that a problem with the key points at the argument.
    table.remove(last.name.as_str());
    table.insert(key, value);
    Ok(())
}

/// Returns "an integer", "a string": a type's name with its article.
fn with_article(name: &str) -> String {
    let vowel = name.starts_with(['a', 'e', 'i', 'o', 'u']);
    format!("{} {name}", if vowel { "an" } else { "a" })
}

/// Returns the table of the `[[body]]` named by `segment`.
fn find_body<'a, 'i>(
    root: &'a mut DeTable<'i>,
    segment: &Segment,
) -> Result<&'a mut DeTable<'i>, Diagnostic> {
    let mut names = Vec::new();
    if let Some(DeValue::Array(bodies)) = root.get_mut("body").map(|b| b.get_mut()) {
        // A body without `name` is called body0, body1, … by its position, as in the
        // scene.
        let index = bodies.iter().enumerate().position(|(i, b)| {
            let name = body_name(b.get_ref(), i);
            let found = name == segment.name;
            names.push(name);
            found
        });
        if let Some(DeValue::Table(table)) =
            index.and_then(|i| bodies.get_mut(i)).map(|b| b.get_mut())
        {
            return Ok(table);
        }
    }
    let hint = if names.is_empty() {
        "the scene declares no [[body]]".to_string()
    } else {
        format!("bodies in this scene: {}", names.join(", "))
    };
    Err(Diagnostic::at(
        segment.span.clone(),
        format!("no body is named `{}`", segment.name),
    )
    .label("body.NAME.key addresses a [[body]] by its name")
    .hint(hint))
}

/// Returns the name a body goes by: its `name`, or `body{i}`.
fn body_name(body: &DeValue<'_>, i: usize) -> String {
    body.as_table()
        .and_then(|t| t.get("name"))
        .and_then(|n| n.get_ref().as_str())
        .map_or_else(|| format!("body{i}"), str::to_string)
}

/// Returns the table of the `[[force]]` whose index `segment` gives.
fn find_force<'a, 'i>(
    root: &'a mut DeTable<'i>,
    segment: &Segment,
) -> Result<&'a mut DeTable<'i>, Diagnostic> {
    let count = match root.get("force").map(|f| f.get_ref()) {
        Some(DeValue::Array(forces)) => forces.len(),
        _ => 0,
    };
    let range = if count == 0 {
        "the scene declares no [[force]]".to_string()
    } else {
        format!(
            "this scene has {count} force{}: force.0 to force.{}",
            if count == 1 { "" } else { "s" },
            count - 1
        )
    };
    let index = match segment.name.parse::<usize>() {
        Ok(i) if i < count => i,
        Ok(_) => {
            return Err(Diagnostic::at(
                segment.span.clone(),
                format!("there is no force {}", segment.name),
            )
            .label("forces are counted from 0 in file order")
            .hint(range))
        }
        Err(_) => {
            return Err(Diagnostic::at(
                segment.span.clone(),
                format!("`{}` is not a force's index", segment.name),
            )
            .label("force.N.key addresses the N-th [[force]], counted from 0")
            .hint(range))
        }
    };
    match root.get_mut("force").map(|f| f.get_mut()) {
        Some(DeValue::Array(forces)) => match forces.get_mut(index).map(|f| f.get_mut()) {
            Some(DeValue::Table(table)) => Ok(table),
            _ => Err(Diagnostic::at(
                segment.span.clone(),
                format!("force {index} is not a table"),
            )),
        },
        _ => Err(Diagnostic::at(segment.span.clone(), range)),
    }
}

/// Moves every span in a parsed value by `offset`.
fn shift(value: Spanned<DeValue<'_>>, offset: usize) -> Spanned<DeValue<'_>> {
    let span = value.span();
    let moved = span.start + offset..span.end + offset;
    let inner = match value.into_inner() {
        DeValue::Array(items) => {
            DeValue::Array(items.into_iter().map(|v| shift(v, offset)).collect())
        }
        DeValue::Table(table) => DeValue::Table(shift_table(table, offset)),
        other => other,
    };
    Spanned::new(moved, inner)
}

fn shift_table(table: DeTable<'_>, offset: usize) -> DeTable<'_> {
    let mut out = DeTable::new();
    for (k, v) in table {
        let span = k.span();
        out.insert(
            Spanned::new(span.start + offset..span.end + offset, k.into_inner()),
            shift(v, offset),
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn segments(key: &str) -> Vec<(String, Range<usize>)> {
        match key_path(key, 100) {
            Ok(s) => s.into_iter().map(|s| (s.name, s.span)).collect(),
            Err(d) => panic!("`{key}`: {}", d.message),
        }
    }

    #[test]
    fn keys_are_split_like_toml_dotted_keys() {
        assert_eq!(
            segments("simulation.dt"),
            vec![("simulation".into(), 100..110), ("dt".into(), 111..113)]
        );
        assert_eq!(
            segments("body.\"my puck\".mass"),
            vec![
                ("body".into(), 100..104),
                ("my puck".into(), 105..114),
                ("mass".into(), 115..119)
            ]
        );
        assert!(key_path("", 0).is_err());
        assert!(key_path("a..b", 0).is_err());
    }

    #[test]
    fn the_first_equals_sign_outside_quotes_splits_key_and_value() {
        assert_eq!(equals_sign("a.b=1"), Some(3));
        assert_eq!(equals_sign("body.\"x=y\".mass=2"), Some(15));
        assert_eq!(equals_sign("name"), None);
    }

    /// Applies one override to a document and returns it, or the problem's message.
    fn applied(text: &str, arg: &str) -> Result<String, String> {
        let mut root = DeTable::parse(text).expect("valid TOML");
        let mut diagnostics = Vec::new();
        apply(root.get_mut(), arg, text.len() + 1, &mut diagnostics);
        match diagnostics.pop() {
            Some(d) => Err(d.message),
            None => Ok(format!("{:?}", root.get_ref())),
        }
    }

    #[test]
    fn any_array_of_tables_is_addressed_by_index() {
        let text = "[[swarm]]\ncount = 1\n[[swarm]]\ncount = 2\n";
        let doc = applied(text, "swarm.1.count=7").expect("applies");
        assert!(doc.contains("\"7\""), "{doc}");
        assert_eq!(
            applied(text, "swarm.2.count=7").err().as_deref(),
            Some("`swarm` has no table `2`")
        );
        assert_eq!(
            applied("a = 1\n", "a.b=2").err().as_deref(),
            Some("`a` is an integer, not a table, so it has no key `b`")
        );
    }

    #[test]
    fn a_value_that_is_not_toml_becomes_a_string() {
        let (_, v) = parse("name=demo run", 10).expect("parses");
        assert_eq!(v.get_ref().as_str(), Some("demo run"));
        assert_eq!(v.span(), 15..23);
        let (_, v) = parse("render.view.min=[0, 1]", 0).expect("parses");
        assert!(v.get_ref().is_array());
        assert_eq!(v.span(), 16..22);
    }
}
