//! Names: the bodies and swarms a force selects, resolved to body indices, with the
//! closest name suggested for one that resolves to nothing.

use std::collections::HashMap;

use toml::Spanned;

use super::Validator;
use crate::scene::swarm::split_member_name;
use crate::scene::Diagnostic;
use crate::sim::Selection;

impl Validator {
    pub(super) fn selection(
        &mut self,
        raw: Option<&Spanned<Vec<Spanned<String>>>>,
        names: &Names,
    ) -> Option<Selection> {
        let Some(raw) = raw else {
            return Some(Selection::All);
        };
        if raw.get_ref().is_empty() {
            self.error(
                Diagnostic::at(
                    raw.span(),
                    "`bodies` is empty, so the force acts on nothing",
                )
                .hint("leave `bodies` out to act on every body"),
            );
            return None;
        }
        // Each name selects one body or a whole swarm; the indices are gathered, then
        // sorted, so that a body named twice (itself, or through its swarm) is found.
        let mut picked: Vec<(u32, usize)> = Vec::new();
        let mut ok = true;
        for (k, name) in raw.get_ref().iter().enumerate() {
            match names.resolve(name.get_ref()) {
                Some(Target::Body(i)) => picked.push((i, k)),
                Some(Target::Swarm(range)) => picked.extend(range.map(|i| (i, k))),
                None => {
                    self.unknown_body(name, names);
                    ok = false;
                }
            }
        }
        picked.sort_unstable();
        for pair in picked.windows(2) {
            if pair[0].0 == pair[1].0 {
                let name = &raw.get_ref()[pair[1].1.max(pair[0].1)];
                self.error(
                    Diagnostic::at(
                        name.span(),
                        format!(
                            "`{}` selects body `{}` a second time",
                            name.get_ref(),
                            names.name_of(pair[0].0)
                        ),
                    )
                    .hint("a force acts once on each body it names (a swarm's name selects all its members)"),
                );
                ok = false;
                break;
            }
        }
        let list: Vec<u32> = picked.into_iter().map(|(i, _)| i).collect();
        ok.then(|| Selection::from_sorted(list, names.len()))
    }

    pub(super) fn body_index(&mut self, name: &Spanned<String>, names: &Names) -> Option<u32> {
        match names.resolve(name.get_ref()) {
            Some(Target::Body(i)) => Some(i),
            Some(Target::Swarm(range)) => {
                self.error(
                    Diagnostic::at(
                        name.span(),
                        format!(
                            "`{}` is a swarm of {} bodies, not one body",
                            name.get_ref(),
                            range.len()
                        ),
                    )
                    .label("a swarm")
                    .hint(format!("name one member, e.g. `{}0`", name.get_ref())),
                );
                None
            }
            None => {
                self.unknown_body(name, names);
                None
            }
        }
    }

    pub(super) fn unknown_body(&mut self, name: &Spanned<String>, names: &Names) {
        let mut known: Vec<String> = names.bodies.keys().map(|k| k.to_string()).collect();
        known.sort_unstable();
        for s in names.swarms {
            known.push(format!(
                "{} (a swarm: {}0 to {}{})",
                s.name,
                s.name,
                s.name,
                s.count - 1
            ));
        }
        let hint = if known.is_empty() {
            "the scene declares no body".to_string()
        } else {
            format!("bodies in this scene: {}", known.join(", "))
        };
        self.error(
            Diagnostic::at(
                name.span(),
                format!("no body is named `{}`", name.get_ref()),
            )
            .label("unknown body")
            .hint(hint),
        );
    }
}

/// A swarm's name and the indices of its members: first ..first + count.
pub(super) struct SwarmName {
    pub(super) name: String,
    pub(super) first: u32,
    pub(super) count: u32,
}

/// What a name in a force selects.
pub(super) enum Target {
    Body(u32),
    Swarm(std::ops::Range<u32>),
}

/// Resolves the names forces use: a body's, a swarm's, or a swarm member's
/// (`dust17`). Members are found by parsing their number, so a swarm of a million
/// bodies costs no table of a million names.
pub(super) struct Names<'a> {
    bodies: HashMap<&'a str, u32>,
    swarms: &'a [SwarmName],
    len: usize,
}

impl<'a> Names<'a> {
    pub(super) fn new(body_names: &'a [String], swarms: &'a [SwarmName]) -> Self {
        let bodies = body_names
            .iter()
            .enumerate()
            .map(|(i, name)| (name.as_str(), i as u32))
            .collect();
        let len = body_names.len() + swarms.iter().map(|s| s.count as usize).sum::<usize>();
        Names {
            bodies,
            swarms,
            len,
        }
    }

    /// Returns the number of bodies, swarm members included.
    pub(super) fn len(&self) -> usize {
        self.len
    }

    pub(super) fn resolve(&self, name: &str) -> Option<Target> {
        if let Some(i) = self.bodies.get(name) {
            return Some(Target::Body(*i));
        }
        if let Some(s) = self.swarms.iter().find(|s| s.name == name) {
            return Some(Target::Swarm(s.first..s.first + s.count));
        }
        let (prefix, k) = split_member_name(name)?;
        let s = self.swarms.iter().find(|s| s.name == prefix)?;
        (k < u64::from(s.count)).then(|| Target::Body(s.first + k as u32))
    }

    /// Returns the name of body `i`, for messages.
    pub(super) fn name_of(&self, i: u32) -> String {
        if let Some((name, _)) = self.bodies.iter().find(|(_, j)| **j == i) {
            return name.to_string();
        }
        self.swarms
            .iter()
            .find(|s| (s.first..s.first + s.count).contains(&i))
            .map_or_else(|| format!("#{i}"), |s| format!("{}{}", s.name, i - s.first))
    }
}
