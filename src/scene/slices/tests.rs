//! The raw scene read in slices is the whole parse's: every value and every span (both of
//! which the `Debug` text of a [`RawScene`] shows); and whatever the slices cannot vouch
//! for is left to the whole-document path.

use std::path::{Path, PathBuf};

use super::*;

/// Whether a text was read in slices or left to the whole-document path.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Way {
    Sliced,
    Whole,
}

/// Returns the `Debug` text of the raw scene that the whole-document path reads, or
/// `None` when the text does not parse or does not fit the schema.
fn whole(text: &str) -> Option<String> {
    let root = DeTable::parse(text).ok()?;
    let raw = RawScene::deserialize(Deserializer::from(root)).ok()?;
    Some(format!("{raw:?}"))
}

/// Checks that a text read in slices of `slice_bytes`, if it is, gives the raw scene
/// of the whole text, and returns which way it went.
fn check(name: &str, text: &str, slice_bytes: usize) -> Way {
    let Some(sliced) = raw_scene_in_slices(text, slice_bytes, |_| true) else {
        return Way::Whole;
    };
    let sliced = format!("{sliced:?}");
    let Some(whole) = whole(text) else {
        panic!("{name}: read in slices of {slice_bytes} bytes, but the whole text is no scene");
    };
    if sliced != whole {
        let at = whole
            .bytes()
            .zip(sliced.bytes())
            .position(|(a, b)| a != b)
            .unwrap_or(whole.len().min(sliced.len()));
        let from = at.saturating_sub(300);
        panic!(
            "{name} in slices of {slice_bytes} bytes differs from the whole parse at byte \
             {at} of its dump:\nwhole:  …{}\nsliced: …{}",
            whole.get(from..(at + 300).min(whole.len())).unwrap_or(""),
            sliced.get(from..(at + 300).min(sliced.len())).unwrap_or(""),
        );
    }
    Way::Sliced
}

/// Every TOML file of the repository's scenes, documentation and tests, and every
/// TOML block of the documentation.
fn toml_texts() -> Vec<(String, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = vec![root.join("src/cli/template.toml")];
    for folder in ["scenes", "docs", "tests", "fuzz/seeds"] {
        collect(&root.join(folder), &mut files);
    }
    let mut texts: Vec<(String, String)> = files
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .map(|p| {
            let text = std::fs::read_to_string(p).expect("a TOML file of the repository reads");
            (p.display().to_string(), text)
        })
        .collect();
    let mut pages = vec![root.join("README.md")];
    collect(&root.join("docs"), &mut pages);
    for page in pages
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
    {
        let markdown = std::fs::read_to_string(page).expect("a page of the guide reads");
        let mut block: Option<String> = None;
        for line in markdown.lines() {
            let fence = line.trim_start().starts_with("```");
            match (&mut block, fence) {
                (None, true) if line.trim_start().starts_with("```toml") => {
                    block = Some(String::new());
                }
                (Some(text), false) => {
                    text.push_str(line);
                    text.push('\n');
                }
                (Some(_), true) => {
                    let text = block.take().unwrap_or_default();
                    texts.push((format!("a TOML block of {}", page.display()), text));
                }
                _ => {}
            }
        }
    }
    texts
}

/// Adds the files under a folder, its subfolders' too, in name order.
fn collect(folder: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(folder) else {
        return;
    };
    let mut paths: Vec<PathBuf> = entries.flatten().map(|e| e.path()).collect();
    paths.sort();
    for path in paths {
        if path.is_dir() {
            collect(&path, out);
        } else {
            out.push(path);
        }
    }
}

#[test]
fn every_toml_file_of_the_repository_reads_the_same_in_slices() {
    let texts = toml_texts();
    assert!(
        texts.len() >= 50,
        "the repository has its TOML: {}",
        texts.len()
    );
    let mut sliced = 0;
    for (name, text) in &texts {
        for slice_bytes in [1, 100, 2_000, SLICE_BYTES] {
            let way = check(name, text, slice_bytes);
            // The scenes of many bodies, which slices are for, must not be read whole.
            if name.contains("scenes/bench/") && text.matches("\n[[body]]").count() > 100 {
                assert_eq!(way, Way::Sliced, "{name} in slices of {slice_bytes} bytes");
            }
            sliced += usize::from(way == Way::Sliced);
        }
    }
    assert!(sliced > 100, "only {sliced} readings took slices");
}

#[test]
fn the_benchmark_of_ten_thousand_bodies_is_read_in_many_slices() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bench/bodies-10000.toml");
    let text = std::fs::read_to_string(path).expect("the benchmark scene reads");
    assert!(text.len() >= WHOLE_BELOW);
    let (starts, headers) = slice_starts(&text, SLICE_BYTES);
    assert_eq!(headers, 10_000);
    assert!(starts.len() >= 30, "{} slices", starts.len());
    let raw = raw_scene(&text, |_| true).expect("the benchmark is read in slices");
    assert_eq!(raw.body.len(), 10_000);
    assert_eq!(Some(format!("{raw:?}")), whole(&text));
}

/// A body with every key of the schema, sub-tables included.
const EVERY_KEY: &str = "[[body]]\nname = \"all\"\nmass = 2.0\nposition = [1.0, 2.0]\n\
    velocity = [0.5, -0.5]\n\
    shape = { polygon = { points = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]] } }\n\
    color = \"#ff8800\"\nshow_velocity = true\nshow_force = false\nangle = 0.25\n\
    angular_velocity = -1.0\ninertia = 3.0\nstatic = false\nrestitution = 0.5\n\
    friction = 0.25\n[[body.points]]\noffset = [0.1, 0.0]\nmass = 1.0\n\
    [[body.points]]\noffset = [-0.1, 0.0]\nmass = 1.5\n";

/// Layouts that slices must get right, each with the way it must go in slices of one
/// byte (so that every line `[[body]]` starts a slice), and whether the whole text is
/// a scene that fits the schema.
const CASES: &[(&str, Way, bool, &str)] = &[
    (
        "bodies, then [render] and [[force]]",
        Way::Sliced,
        true,
        "name = \"s\"\n[simulation]\ndt = 0.1\n[[body]]\nmass = 1.0\n[[body]]\nmass = 2.0\n\
         [render]\nfps = 30.0\n[[force]]\nkind = \"drag\"\n[[force]]\nkind = \"gravity\"\n",
    ),
    (
        "a body with every key, in a later slice",
        Way::Sliced,
        true,
        "[render]\nfps = 30.0\n[[body]]\nmass = 1.0\n\n# every key next\n[[body]]\nname = \"all\"\nmass = 2.0\nposition = [1.0, 2.0]\n\
         velocity = [0.5, -0.5]\n\
         shape = { polygon = { points = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]] } }\n\
         color = \"#ff8800\"\nshow_velocity = true\nshow_force = false\nangle = 0.25\n\
         angular_velocity = -1.0\ninertia = 3.0\nstatic = false\nrestitution = 0.5\n\
         friction = 0.25\n[[body.points]]\noffset = [0.1, 0.0]\nmass = 1.0\n\
         [[body.points]]\noffset = [-0.1, 0.0]\nmass = 1.5\n",
    ),
    (
        "circles and boxes as sub-tables and inline tables",
        Way::Sliced,
        true,
        "[[body]]\nshape = { circle = { radius = 0.5 } }\n[[body]]\n[body.shape.box]\n\
         width = 1.0\nheight = 2.0\n[[body]]\n[body.shape]\ncircle.radius = 0.25\n\
         [[body]]\nshape.box = { width = 3.0, height = 4.0 }\n",
    ),
    (
        "a file that starts with [[body]] and ends without a line break",
        Way::Sliced,
        true,
        "[[body]]\nmass = 1.0\n[[body]] # the second\nmass = 2.0\n[[body]]\t\nmass = 3.0",
    ),
    (
        "CRLF line endings",
        Way::Sliced,
        true,
        "[render]\r\nfps = 30.0\r\n[[body]]\r\nmass = 1.0\r\n[[body]] # two\r\nmass = 2.0\r\n\
         [[force]]\r\nkind = \"drag\"\r\n",
    ),
    (
        "[body.shape] after a [[force]], in the slice of its [[body]]",
        Way::Sliced,
        true,
        "[[body]]\nmass = 1.0\n[[force]]\nkind = \"drag\"\n[body.shape.circle]\nradius = 1.0\n\
         [[body]]\nmass = 2.0\n",
    ),
    (
        "[[force]] between bodies, twice",
        Way::Whole,
        true,
        "[[body]]\nmass = 1.0\n[[force]]\nkind = \"drag\"\n[[body]]\nmass = 2.0\n\
         [[force]]\nkind = \"gravity\"\n",
    ),
    (
        "a multi-line array holding a line [[body]] (not TOML, but no slice may say so)",
        Way::Whole,
        false,
        "[[body]]\nshape = { polygon = { points = [\n[0.0, 0.0], [1.0, 0.0],\n[[body]]\n] } }\n\
         [[body]]\nmass = 2.0\n",
    ),
    (
        "a multi-line basic string holding a line [[body]]",
        Way::Whole,
        true,
        "[[body]]\nname = \"\"\"\n[[body]]\n\"\"\"\n[[body]]\nmass = 2.0\n",
    ),
    (
        "a multi-line literal string holding a line [[body]]",
        Way::Whole,
        true,
        "[[body]]\nname = '''\n[[body]]\nmass = 3.0\n'''\n[[body]]\nmass = 2.0\n",
    ),
    (
        "body = [{...}] and then [[body]]",
        Way::Whole,
        false,
        "body = [{ mass = 1.0 }]\n[render]\nfps = 30.0\n[[body]]\nmass = 2.0\n",
    ),
    (
        "[[body]] and then [body]",
        Way::Whole,
        false,
        "[[body]]\nmass = 1.0\n[[force]]\nkind = \"drag\"\n[body]\nmass = 2.0\n",
    ),
    (
        "[render.view] in one slice and [render] in another",
        Way::Whole,
        true,
        "[[body]]\n[render.view]\nmin = [0.0, 0.0]\nmax = [1.0, 1.0]\n[[body]]\n[render]\n\
         fps = 30.0\n",
    ),
    (
        "[render] in two slices",
        Way::Whole,
        false,
        "[[body]]\n[render]\nfps = 30.0\n[[body]]\n[render]\nfps = 25.0\n",
    ),
    (
        "[render] before the bodies and [render.view] among them",
        Way::Whole,
        true,
        "[render]\nfps = 30.0\n[[body]]\n[render.view]\nmin = [0.0, 0.0]\nmax = [1.0, 1.0]\n\
         [[body]]\n",
    ),
    (
        "a syntax error in the last slice",
        Way::Whole,
        false,
        "[[body]]\nmass = 1.0\n[[body]]\nmass = = 2.0\n",
    ),
    (
        "a key the schema does not know, in a body of a later slice",
        Way::Whole,
        false,
        "[[body]]\nmass = 1.0\n[[body]]\nmas = 2.0\n",
    ),
    (
        "a value of the wrong type, in a body of a later slice",
        Way::Whole,
        false,
        "[[body]]\nmass = 1.0\n[[body]]\nmass = \"heavy\"\n",
    ),
    (
        "a key the schema does not know, after the bodies",
        Way::Whole,
        false,
        "[[body]]\nmass = 1.0\n[[body]]\nmass = 2.0\n[extra]\nx = 1\n",
    ),
    (
        "a byte-order mark, and headers that do not start a slice",
        Way::Sliced,
        true,
        "\u{feff}name = \"s\"\n[[body]]\nmass = 1.0\n  [[body]]\nmass = 2.0\n[[ body ]]\n\
         [[\"body\"]]\n[[body]]\n",
    ),
    (
        "[[body]] before the first line that starts a slice",
        Way::Whole,
        true,
        "[[ body ]]\nmass = 1.0\n[[body]]\nmass = 2.0\n",
    ),
    (
        "a line [[body]] followed by more than a comment",
        Way::Whole,
        false,
        "[[body]]\nmass = 1.0\n[[body]] x = 1\n",
    ),
    (
        "no line [[body]] at all",
        Way::Whole,
        true,
        "[render]\nfps = 30.0\n[[force]]\nkind = \"drag\"\n",
    ),
];

#[test]
fn tricky_layouts_read_as_the_whole_text_does() {
    for &(name, way, valid, text) in CASES {
        assert_eq!(whole(text).is_some(), valid, "{name}");
        assert_eq!(check(name, text, 1), way, "{name}");
        for slice_bytes in [2, 10, 30, 1000] {
            check(name, text, slice_bytes);
        }
    }
}

#[test]
fn every_key_of_a_body_moves_with_its_slice() {
    // The body with every key is read from slices that start at every offset its text
    // can be given, and each of its spans must still point at its own text.
    let mut text = String::from("[render]\nfps = 30.0\n");
    for i in 0..40 {
        text.push_str(&format!("[[body]]\nmass = {i}.5\n"));
        text.push_str(EVERY_KEY);
    }
    for slice_bytes in [1, 7, 100, 1_000] {
        assert_eq!(
            check("bodies with every key", &text, slice_bytes),
            Way::Sliced
        );
    }
    let raw = raw_scene_in_slices(&text, 1, |_| true).expect("read in slices");
    let last = raw.body.last().expect("80 bodies").get_ref();
    let name = last.name.as_ref().expect("a name");
    assert_eq!(&text[name.span()], "\"all\"");
    let points = last.points.as_ref().expect("point masses");
    let point = points.get_ref().last().expect("two points").get_ref();
    assert_eq!(&text[point.mass.span()], "1.5");
    let friction = last.friction.as_ref().expect("friction");
    assert_eq!(&text[friction.span()], "0.25");
    assert!(friction.span().start > text.len() - EVERY_KEY.len());
}

/// Returns a scene of `count` bodies, one `[[body]]` table each, and a force.
fn many_bodies(count: usize) -> String {
    let mut text = String::from("[simulation]\nduration = 1.0\n\n[render]\nfps = 30\n");
    text.push_str("view = { min = [0.0, 0.0], max = [16.0, 9.0] }\n\n");
    for i in 0..count {
        text.push_str(&format!(
            "[[body]]\nmass = 1.0\nposition = [{}.5, 4.0]\nvelocity = [-0.1130, -0.2729]\n\
             shape = {{ circle = {{ radius = 0.03 }} }}\n",
            i % 16
        ));
    }
    text.push_str("\n[[force]]\nkind = \"drag\"\nk = 0.05\n");
    text
}

/// Returns `text` with the `n`th body's mass (counted from 0) written as `mass`, and
/// the line of that mass, counted from 1.
fn with_mass(text: &str, n: usize, mass: &str) -> (String, usize) {
    let at = text
        .match_indices("[[body]]")
        .nth(n)
        .expect("enough bodies")
        .0;
    let line = text[..at].matches('\n').count() + 2;
    let mut changed = text.to_string();
    let old = "[[body]]\nmass = 1.0";
    changed.replace_range(at..at + old.len(), &format!("[[body]]\nmass = {mass}"));
    (changed, line)
}

#[test]
fn problems_late_in_a_large_file_are_reported_at_their_place() {
    let valid = many_bodies(2_000);
    assert!(valid.len() > 2 * WHOLE_BELOW);
    assert_eq!(check("2000 bodies", &valid, SLICE_BYTES), Way::Sliced);
    let path = Path::new("big.toml");
    let scene = crate::scene::parse(path, &valid).expect("a valid scene");
    assert_eq!(scene.bodies.len(), 2_000);

    // A rule broken in a body that fits the schema: found in the sliced raw scene, so
    // its place comes from the slice's spans, moved.
    let (text, line) = with_mass(&valid, 1_799, "-1.0");
    assert_eq!(check("a negative mass", &text, SLICE_BYTES), Way::Sliced);
    let reported = crate::scene::parse(path, &text).expect_err("a mass is negative");
    let reported = reported.to_string();
    assert!(reported.contains("`mass` must be > 0"), "{reported}");
    assert!(
        reported.contains(&format!("big.toml:{line}:8")),
        "the error is on line {line}, column 8:\n{reported}"
    );

    // A syntax error and a wrong type: read whole, as every file with either always was.
    for (bad, message) in [("= 1.0", "expected"), ("\"heavy\"", "invalid type")] {
        let (text, line) = with_mass(&valid, 1_799, bad);
        assert_eq!(check(bad, &text, SLICE_BYTES), Way::Whole);
        let reported = crate::scene::parse(path, &text)
            .expect_err("a mass is bad")
            .to_string();
        assert!(reported.contains(message), "{reported}");
        assert!(
            reported.contains(&format!("big.toml:{line}:8")),
            "the error is on line {line}, column 8:\n{reported}"
        );
    }
}

/// SplitMix64: a small seeded generator, so that the random layouts are the same in
/// every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    fn pick<'a>(&mut self, items: &[&'a str]) -> &'a str {
        items[self.below(items.len())]
    }
}

/// Lines that may stand before the first table.
const PREAMBLE: &[&str] = &[
    "name = \"random\"",
    "# a comment",
    "simulation.dt = 0.01",
    "body = [{ mass = 1.0 }]",
    "force = []",
    "",
];

/// Tables, and what follows their headers (`\n` standing for a line break), that fit
/// the schema and may stand anywhere and many times.
const COMMON: &[&str] = &[
    "[[body]]\nmass = 1.0\nposition = [0.5, 4.0]",
    "[[body]]\nshape = { circle = { radius = 0.03 } }",
    "[[body]] # a body\nname = \"b\"",
    "[[body]]",
    "[[body]]\nname = \"\"\"\n[[body]]\n\"\"\"",
    "[[body]]\ncolor = '''\n[[force]]\nkind = 1\n'''",
    "[[body]]\nshape.box = { width = 1.0, height = 2.0 }\nangle = 0.5",
    "[[body]]\nmass = 2.0\n\n# the next body\n",
    "[[body]]\nshape = { polygon = { points = [\n  [0.0, 1.0],\n  [1.0, 0.0],\n  [0.0, 0.0],\n] } }",
    "[[body]]\n[[body.points]]\noffset = [1.0, 0.0]\nmass = 1.0",
    "[[body]]\n[body.shape.circle]\nradius = 0.5",
    EVERY_KEY,
    "[[force]]\nkind = \"drag\"\nk = 0.5",
    "[[swarm]]\nname = \"s\"\ncount = 3\nmass = 1.0\n\
     position = { min = [0.0, 0.0], max = [1.0, 1.0] }",
];

/// Tables that may clash with others, keys the schema does not know, and errors.
const RARE: &[&str] = &[
    "[[ body ]]\nmass = 2.0",
    "[body.shape]\ncircle = { radius = 1.0 }",
    "[[body.points]]\noffset = [0.0, 0.0]\nmass = 1.0",
    "[render]\nfps = 30.0",
    "[render.view]\nmin = [0.0, 0.0]\nmax = [1.0, 1.0]",
    "[simulation]\nduration = 1.0",
    "[contacts]\nrestitution = 0.5",
    "[[body]]\nmas = 1.0",
    "[[body]]\nmass = = 1.0",
    "[[body]]\nmass = \"heavy\"",
    "[[body]]\nname = \"unterminated",
];

/// Returns a random scene-like document.
fn random_document(rng: &mut Rng) -> String {
    let mut lines = Vec::new();
    for _ in 0..rng.below(3) {
        lines.push(rng.pick(PREAMBLE));
    }
    for _ in 0..rng.below(25) {
        let table = if rng.below(10) == 0 {
            rng.pick(RARE)
        } else {
            rng.pick(COMMON)
        };
        lines.push(table);
    }
    let newline = if rng.below(4) == 0 { "\r\n" } else { "\n" };
    let mut text = lines.join("\n").replace('\n', newline);
    if rng.below(3) != 0 {
        text.push_str(newline);
    }
    text
}

#[test]
fn random_layouts_read_as_the_whole_text_does() {
    let mut rng = Rng(16);
    let (mut sliced, mut whole_scene, mut no_scene) = (0, 0, 0);
    for i in 0..3_000 {
        let text = random_document(&mut rng);
        let slice_bytes = [1, 1, 20, 60, 200][rng.below(5)];
        let way = check(
            &format!("random document {i}:\n{text}\n"),
            &text,
            slice_bytes,
        );
        match (way, whole(&text).is_some()) {
            (Way::Sliced, _) => sliced += 1,
            (Way::Whole, true) => whole_scene += 1,
            (Way::Whole, false) => no_scene += 1,
        }
    }
    // Each way is taken often, so that the comparison tests each.
    assert!(
        sliced > 400 && whole_scene > 400 && no_scene > 400,
        "{sliced} sliced, {whole_scene} scenes read whole, {no_scene} not scenes"
    );
}

#[test]
fn overrides_that_leave_the_bodies_alone_are_applied_to_the_rest() {
    use crate::scene::{overrides, Sources};

    let text = many_bodies(1_000);
    assert!(text.len() >= WHOLE_BELOW);
    let sets: Vec<String> = [
        "simulation.duration=2.0",
        "force.0.k=0.25",
        "render.view.max=[20.0, 10.0]",
        "name=renamed",
        "render.fps=25",
    ]
    .map(String::from)
    .to_vec();
    let sources = Sources {
        file_len: text.len(),
        overrides: &sets,
    };
    fn apply<'i>(root: &mut DeTable<'i>, sets: &'i [String], sources: &Sources<'_>) -> bool {
        let mut problems = Vec::new();
        for (i, arg) in sets.iter().enumerate() {
            overrides::apply(root, arg, sources.base(i), &mut problems);
        }
        problems.is_empty()
    }
    let sliced = raw_scene(&text, |root| apply(root, &sets, &sources)).expect("read in slices");
    let mut root = DeTable::parse(&text).expect("valid TOML");
    assert!(
        apply(root.get_mut(), &sets, &sources),
        "the overrides apply"
    );
    let whole = RawScene::deserialize(Deserializer::from(root)).expect("fits the schema");
    assert_eq!(format!("{sliced:?}"), format!("{whole:?}"));

    // Through the front end: the scene is the overridden one, with its hash.
    let path = Path::new("many.toml");
    let scene = crate::scene::parse_with_overrides(path, &text, &sets)
        .map_err(|e| e.to_string())
        .expect("valid");
    assert_eq!(scene.simulation.duration, 2.0);
    assert_eq!(scene.name, "renamed");
    assert_eq!(scene.render.fps, 25.0);
    assert_eq!(scene.bodies.len(), 1_000);
    assert_eq!(
        scene.source.hash,
        crate::scene::hash_with_overrides(&text, &sets)
    );

    // Whether an override may touch the bodies is read from its key path.
    for (arg, touches) in [
        ("body.body3.mass=2", true),
        ("body=1", true),
        ("\"body\".x=1", true),
        ("no equals sign", true),
        ("simulation.dt=0.01", false),
        ("force.0.k=1", false),
    ] {
        assert_eq!(overrides::may_touch_bodies(arg), touches, "{arg}");
    }

    // An override that does not apply is reported by the whole-document path, at its
    // place in the argument.
    let bad = vec!["force.7.k=1".to_string()];
    let message = crate::scene::parse_with_overrides(path, &text, &bad)
        .expect_err("there is one force")
        .to_string();
    assert!(message.contains("there is no force 7"), "{message}");
}

#[test]
fn mutated_benchmark_files_read_as_the_whole_text_does() {
    // Lines of the benchmark of 1,000 bodies cut, doubled, swapped with one another
    // or replaced with awkward ones, at random: wherever the slices still read the
    // file, the raw scene is the whole parse's. PHYSFRAMES_SLICE_CASES sets how many
    // (3,000 passed when this was written).
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bench/bodies-1000.toml");
    let text = std::fs::read_to_string(path).expect("the benchmark scene reads");
    let lines: Vec<&str> = text.lines().collect();
    const AWKWARD: &[&str] = &[
        "[[body]]",
        "[body.shape]",
        "[[force]]\nkind = \"drag\"",
        "[render]",
        "name = \"\"\"",
        "\"\"\"",
        "color = '''",
        "'''",
        "[[body.points]]\noffset = [0.0, 0.0]\nmass = 1.0",
        "static = true",
        "mass = [",
        "]",
        "# [[body]]",
        "  [[body]]",
        "",
    ];
    let cases: usize = std::env::var("PHYSFRAMES_SLICE_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(200);
    let mut rng = Rng(2026);
    let (mut sliced, mut whole) = (0, 0);
    for case in 0..cases {
        let mut mutated: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
        for _ in 0..1 + rng.below(4) {
            let at = rng.below(mutated.len());
            match rng.below(4) {
                0 => {
                    mutated.remove(at);
                }
                1 => {
                    let line = mutated[rng.below(mutated.len())].clone();
                    mutated.insert(at, line);
                }
                2 => {
                    let other = rng.below(mutated.len());
                    mutated.swap(at, other);
                }
                _ => mutated[at] = rng.pick(AWKWARD).to_string(),
            }
        }
        let mutated = mutated.join("\n");
        let slice_bytes = [100, 2_000, SLICE_BYTES][rng.below(3)];
        match check(&format!("mutation {case}"), &mutated, slice_bytes) {
            Way::Sliced => sliced += 1,
            Way::Whole => whole += 1,
        }
    }
    // Most mutations break the schema (a key twice, a value gone), so are read whole;
    // about one in seven still reads in slices (415 of 3,000 with this generator).
    assert!(
        sliced > cases / 12 && whole > cases / 2,
        "{sliced} sliced, {whole} whole"
    );
}
