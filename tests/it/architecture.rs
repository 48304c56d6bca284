//! The modules point one way: no import cycle between two root modules or
//! folders of `src/` (cycles inside one folder may stay).
//!
//! Every `crate::NAME` path in a file of root module `A` (comments left
//! out) is an edge `A -> NAME`, the crate root's re-exports (`crate::Error`,
//! `crate::Settings`, ...) counted as the module that defines them. The
//! graph must have no cycle: a depth-first search finds none.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::Path;

/// Items the crate root re-exports, and the module that defines each.
const ROOT_REEXPORTS: [(&str, &str); 15] = [
    ("Body", "body"),
    ("BodyDesc", "body"),
    ("BodyError", "body"),
    ("MassSpec", "body"),
    ("Shape", "body"),
    ("ShapePart", "body"),
    ("Error", "error"),
    ("Scene", "scene"),
    ("SceneError", "scene"),
    ("FrictionModel", "settings"),
    ("Method", "settings"),
    ("Settings", "settings"),
    ("SettingsError", "settings"),
    ("Report", "stabilizer"),
    ("Stabilizer", "stabilizer"),
];

/// The root module of a file under `src/` (`None` for the crate root and
/// the command-line tool).
fn root_module(relative: &Path) -> Option<String> {
    let first = relative.components().next()?.as_os_str().to_str()?;
    let name = first.trim_end_matches(".rs");
    (name != "lib" && name != "bin").then(|| name.to_string())
}

/// The text of `source` without its `//` comments.
fn without_comments(source: &str) -> String {
    source
        .lines()
        .map(|line| line.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The modules that `text` names as `crate::NAME`.
fn imports(text: &str) -> BTreeSet<String> {
    let reexports: BTreeMap<&str, &str> = ROOT_REEXPORTS.into_iter().collect();
    text.match_indices("crate::")
        .map(|(at, prefix)| {
            let rest = &text[at + prefix.len()..];
            let end = rest
                .find(|c: char| !(c.is_alphanumeric() || c == '_'))
                .unwrap_or(rest.len());
            let name = &rest[..end];
            reexports.get(name).copied().unwrap_or(name).to_string()
        })
        .filter(|name| !name.is_empty() && name != "internals")
        .collect()
}

fn visit(dir: &Path, src: &Path, edges: &mut BTreeMap<String, BTreeSet<String>>) {
    for entry in fs::read_dir(dir).expect("src/ is readable") {
        let path = entry.expect("a directory entry").path();
        if path.is_dir() {
            visit(&path, src, edges);
            continue;
        }
        if path.extension().and_then(|e| e.to_str()) != Some("rs") {
            continue;
        }
        let relative = path.strip_prefix(src).expect("under src/");
        let Some(module) = root_module(relative) else {
            continue;
        };
        let text = without_comments(&fs::read_to_string(&path).expect("a source file"));
        let targets: Vec<String> = imports(&text)
            .into_iter()
            .filter(|t| *t != module)
            .collect();
        edges.entry(module).or_default().extend(targets);
    }
}

/// A cycle through `node`, if the search from it finds one.
fn find_cycle(
    node: &str,
    edges: &BTreeMap<String, BTreeSet<String>>,
    path: &mut Vec<String>,
    done: &mut BTreeSet<String>,
) -> Option<Vec<String>> {
    if let Some(start) = path.iter().position(|n| n == node) {
        return Some(path[start..].to_vec());
    }
    if done.contains(node) {
        return None;
    }
    path.push(node.to_string());
    for next in edges.get(node).into_iter().flatten() {
        if let Some(cycle) = find_cycle(next, edges, path, done) {
            return Some(cycle);
        }
    }
    path.pop();
    done.insert(node.to_string());
    None
}

#[test]
fn no_import_cycle_between_root_modules() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut edges = BTreeMap::new();
    visit(&src, &src, &mut edges);
    assert!(
        edges.len() >= 10,
        "too few modules found: {:?}",
        edges.keys()
    );
    // The model imports no algorithm.
    for model in ["geometry", "body", "scene"] {
        let algorithms = ["contact", "projector", "solver", "stabilizer", "rows"];
        let bad: Vec<_> = edges[model]
            .iter()
            .filter(|t| algorithms.contains(&t.as_str()))
            .collect();
        assert!(bad.is_empty(), "{model} imports {bad:?}");
    }
    let mut done = BTreeSet::new();
    for node in edges.keys() {
        let cycle = find_cycle(node, &edges, &mut Vec::new(), &mut done);
        assert!(cycle.is_none(), "import cycle: {cycle:?}");
    }
}

#[test]
fn the_cycle_search_finds_a_planted_cycle() {
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    edges.entry("a".into()).or_default().insert("b".into());
    edges.entry("b".into()).or_default().insert("c".into());
    edges.entry("c".into()).or_default().insert("a".into());
    let cycle = find_cycle("a", &edges, &mut Vec::new(), &mut BTreeSet::new());
    assert_eq!(cycle, Some(vec!["a".into(), "b".into(), "c".into()]));
    assert_eq!(
        imports("use crate::Settings; x = crate::contact::detect();"),
        ["contact".to_string(), "settings".to_string()].into()
    );
}
