//! The layers hold: no library crate below the viewer depends on a GPU, window or plot crate,
//! the viewer (`draw`) takes wgpu only behind its feature and draws no plots, only the
//! presentation crate (`present`) depends on plotters, and no module of any crate imports a
//! sibling that imports it back (directly or through other siblings). Cargo refuses circles
//! between crates; these tests do the same for the modules inside each crate, and for the
//! dependency lists cargo would accept.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Crates that open windows, talk to the GPU or draw plots.
const HEAVY: [&str; 6] = [
    "wgpu",
    "winit",
    "egui",
    "egui-wgpu",
    "egui-winit",
    "plotters",
];

/// The library crates that must build without any of [`HEAVY`].
const LIGHT: [&str; 5] = [
    "wireflight-geometry",
    "wireflight-fsio",
    "wireflight-data",
    "wireflight-flight",
    "wireflight-analysis",
];

/// The workspace crates each library crate may depend on (`wireflight-` left out): the layers
/// below it only (`ARCHITECTURE.md`). Flight data sits below the flight model and reads files;
/// the analysis is pure and reads none; the viewer knows flight data but neither the flight
/// model nor the analysis; the presentation sits on all of them.
const BELOW: [(&str, &[&str]); 7] = [
    ("geometry", &[]),
    ("fsio", &[]),
    ("data", &["geometry", "fsio"]),
    ("flight", &["geometry", "fsio", "data"]),
    ("analysis", &["geometry", "data", "flight"]),
    ("draw", &["geometry", "fsio", "data"]),
    (
        "present",
        &["geometry", "fsio", "data", "flight", "analysis", "draw"],
    ),
];

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The crates of the workspace: package name → (directory, its `[dependencies]`, each with
/// whether it is optional).
type Crates = BTreeMap<String, (PathBuf, Vec<(String, bool)>)>;

/// The crates of the workspace (see [`Crates`]).
fn workspace_crates() -> Crates {
    let mut out = BTreeMap::new();
    for entry in std::fs::read_dir(repo().join("crates")).unwrap() {
        let dir = entry.unwrap().path();
        let text = std::fs::read_to_string(dir.join("Cargo.toml")).unwrap();
        let manifest: toml::Table = toml::from_str(&text).unwrap();
        let name = manifest["package"]["name"].as_str().unwrap().to_string();
        let deps = manifest
            .get("dependencies")
            .and_then(|d| d.as_table())
            .map(|table| {
                table
                    .iter()
                    .map(|(dep, spec)| {
                        let optional = spec
                            .get("optional")
                            .and_then(|o| o.as_bool())
                            .unwrap_or(false);
                        (dep.clone(), optional)
                    })
                    .collect()
            })
            .unwrap_or_default();
        out.insert(name, (dir, deps));
    }
    out
}

/// The crates of [`HEAVY`] that `name`'s dependency tree lists, each with the crate that lists
/// it: `name`'s own dependencies and those of the workspace crates it reaches through
/// non-optional ones (an optional dependency is listed, not followed).
fn heavy_listed(crates: &Crates, name: &str) -> Vec<(String, String)> {
    assert!(crates.contains_key(name), "no crate {name}");
    let mut found = BTreeSet::new();
    let mut seen = BTreeSet::new();
    let mut todo = vec![name.to_string()];
    while let Some(c) = todo.pop() {
        if !seen.insert(c.clone()) {
            continue;
        }
        if let Some((_, deps)) = crates.get(&c) {
            for (dep, optional) in deps {
                if HEAVY.contains(&dep.as_str()) {
                    found.insert((dep.clone(), c.clone()));
                }
                if !optional {
                    todo.push(dep.clone());
                }
            }
        }
    }
    found.into_iter().collect()
}

#[test]
fn light_crates_have_no_gpu_window_or_plot_dependency() {
    let crates = workspace_crates();
    let listed = |pairs: &[(&str, &str)]| -> Vec<(String, String)> {
        pairs
            .iter()
            .map(|(dep, by)| (dep.to_string(), by.to_string()))
            .collect()
    };
    for name in LIGHT {
        let heavy = heavy_listed(&crates, name);
        assert!(
            heavy.is_empty(),
            "{name} depends on {heavy:?} (crate, listed by)"
        );
    }
    // The viewer has wgpu only behind its feature, and nothing else of them: no plots.
    let (_, draw) = &crates["wireflight-draw"];
    for (dep, optional) in draw {
        if dep == "wgpu" {
            assert!(
                optional,
                "wireflight-draw must take wgpu only with its `gpu` feature"
            );
        }
    }
    assert_eq!(
        heavy_listed(&crates, "wireflight-draw"),
        listed(&[("wgpu", "wireflight-draw")]),
        "wireflight-draw's GPU, window and plot dependencies"
    );
    // The presentation draws the plots, and takes no GPU or window crate of its own.
    assert_eq!(
        heavy_listed(&crates, "wireflight-present"),
        listed(&[
            ("plotters", "wireflight-present"),
            ("wgpu", "wireflight-draw")
        ]),
        "wireflight-present's GPU, window and plot dependencies"
    );
}

#[test]
fn each_crate_depends_only_on_the_layers_below_it() {
    let crates = workspace_crates();
    let short = |name: &str| name.strip_prefix("wireflight-").unwrap_or(name).to_string();
    for (name, (_, deps)) in &crates {
        let Some((_, below)) = BELOW.iter().find(|(n, _)| *n == short(name)) else {
            panic!("{name} is not placed in the layers (BELOW in tests/it/layers.rs)");
        };
        for (dep, _) in deps {
            assert!(
                !crates.contains_key(dep) || below.contains(&short(dep).as_str()),
                "{name} depends on {dep}, which is not below it"
            );
        }
    }
}

/// A module of a crate: its path below the crate root (`["import", "ulog"]`).
type ModPath = Vec<String>;

/// Every `.rs` file of `src` as its module path.
fn modules(src: &Path) -> BTreeMap<ModPath, PathBuf> {
    let mut out = BTreeMap::new();
    let mut dirs = vec![src.to_path_buf()];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                dirs.push(path);
                continue;
            }
            if path.extension().is_none_or(|e| e != "rs") {
                continue;
            }
            let rel = path.strip_prefix(src).unwrap().with_extension("");
            let mut parts: ModPath = rel
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect();
            if matches!(
                parts.last().map(String::as_str),
                Some("mod" | "lib" | "main")
            ) {
                parts.pop();
            }
            out.insert(parts, path);
        }
    }
    out
}

/// The code of a file without comments and without its test module (tests may use anything).
fn code_without_tests(text: &str) -> String {
    let code = text.split("#[cfg(test)]").next().unwrap_or("");
    code.lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

fn is_ident_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// The module paths a piece of code names: `crate::a::b`, `super::c`, `self::d`, and the
/// items of `prefix::{x, y::z}` groups (nested groups included), as written.
fn named_paths(code: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let bytes: Vec<char> = code.chars().collect();
    let mut i = 0;
    while i < bytes.len() {
        let starts_word = i == 0 || !is_ident_char(bytes[i - 1]);
        let rest: String = bytes[i..bytes.len().min(i + 5)].iter().collect();
        if !starts_word
            || !["crate", "super", "self"]
                .iter()
                .any(|r| rest.starts_with(r))
        {
            i += 1;
            continue;
        }
        let (paths, end) = parse_path(&bytes, i, vec![]);
        out.extend(paths);
        i = end.max(i + 1);
    }
    out
}

/// Parse a path (and a brace group after it) from `at`; returns the paths and where it ends.
fn parse_path(s: &[char], mut at: usize, prefix: Vec<String>) -> (Vec<Vec<String>>, usize) {
    let mut path = prefix;
    loop {
        let start = at;
        while at < s.len() && is_ident_char(s[at]) {
            at += 1;
        }
        if at > start {
            path.push(s[start..at].iter().collect());
        }
        if at + 2 < s.len() && s[at] == ':' && s[at + 1] == ':' {
            at += 2;
            if s[at] == '{' {
                // A group: each item continues the path.
                let mut out = Vec::new();
                at += 1;
                loop {
                    while at < s.len() && (s[at].is_whitespace() || s[at] == ',') {
                        at += 1;
                    }
                    if at >= s.len() || s[at] == '}' {
                        return (out, at + 1);
                    }
                    let (paths, end) = parse_path(s, at, path.clone());
                    out.extend(paths);
                    at = end;
                    // Skip `as name` and anything else up to the next item.
                    while at < s.len() && s[at] != ',' && s[at] != '}' {
                        at += 1;
                    }
                }
            }
            continue;
        }
        return (vec![path], at);
    }
}

/// The module a path names, from the module `here`: the longest prefix that is a module.
fn resolve(
    here: &[String],
    path: &[String],
    known: &BTreeMap<ModPath, PathBuf>,
) -> Option<ModPath> {
    let mut base: ModPath = Vec::new();
    let mut rest = path;
    match path.first().map(String::as_str) {
        Some("crate") => rest = &path[1..],
        Some("super" | "self") => {
            base = here.to_vec();
            while let Some(first) = rest.first() {
                match first.as_str() {
                    "super" => {
                        base.pop()?;
                    }
                    "self" => {}
                    _ => break,
                }
                rest = &rest[1..];
            }
        }
        _ => return None,
    }
    let full: ModPath = base.into_iter().chain(rest.iter().cloned()).collect();
    (1..=full.len())
        .rev()
        .map(|k| full[..k].to_vec())
        .find(|p| known.contains_key(p))
}

/// Circles among sibling modules of one crate: for each parent module, the groups of its
/// children that import each other in a ring.
fn circles(src: &Path) -> Vec<(String, Vec<String>)> {
    let known = modules(src);
    let mut edges: BTreeMap<ModPath, BTreeMap<String, BTreeSet<String>>> = BTreeMap::new();
    for (here, file) in &known {
        if here.last().is_some_and(|m| m == "tests") {
            continue;
        }
        let code = code_without_tests(&std::fs::read_to_string(file).unwrap());
        for path in named_paths(&code) {
            let Some(target) = resolve(here, &path, &known) else {
                continue;
            };
            let common = here.iter().zip(&target).take_while(|(a, b)| a == b).count();
            if common == here.len() || common == target.len() {
                continue; // a module and its own ancestor or descendant
            }
            edges
                .entry(here[..common].to_vec())
                .or_default()
                .entry(here[common].clone())
                .or_default()
                .insert(target[common].clone());
        }
    }
    let mut found = Vec::new();
    for (parent, graph) in &edges {
        for ring in strongly_connected(graph) {
            found.push((parent.join("::"), ring));
        }
    }
    found
}

/// The strongly connected components of more than one node (Tarjan's algorithm).
fn strongly_connected(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct Walk<'a> {
        graph: &'a BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        out: Vec<Vec<String>>,
    }
    fn visit<'a>(w: &mut Walk<'a>, v: &'a str) {
        let n = w.index.len();
        w.index.insert(v, n);
        w.low.insert(v, n);
        w.stack.push(v);
        for next in w.graph.get(v).into_iter().flatten() {
            if !w.index.contains_key(next.as_str()) {
                visit(w, next);
                let l = w.low[next.as_str()].min(w.low[v]);
                w.low.insert(v, l);
            } else if w.stack.contains(&next.as_str()) {
                let l = w.index[next.as_str()].min(w.low[v]);
                w.low.insert(v, l);
            }
        }
        if w.low[v] == w.index[v] {
            let at = w.stack.iter().rposition(|x| *x == v).unwrap();
            let ring: Vec<String> = w.stack.drain(at..).map(str::to_string).collect();
            if ring.len() > 1 {
                w.out.push(ring);
            }
        }
    }
    let mut w = Walk {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        out: Vec::new(),
    };
    for v in graph.keys() {
        if !w.index.contains_key(v.as_str()) {
            visit(&mut w, v);
        }
    }
    w.out
}

#[test]
fn no_module_imports_a_sibling_that_imports_it_back() {
    let mut sources = vec![repo().join("src")];
    sources.extend(workspace_crates().values().map(|(dir, _)| dir.join("src")));
    let mut all = Vec::new();
    for src in &sources {
        for (parent, ring) in circles(src) {
            all.push(format!(
                "{}: in `{parent}`: {}",
                src.display(),
                ring.join(" ↔ ")
            ));
        }
    }
    assert!(all.is_empty(), "import circles:\n{}", all.join("\n"));
}

#[test]
fn the_circle_finder_sees_a_circle() {
    // Two siblings naming each other through `super::`, one of them inside a group.
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path();
    std::fs::write(src.join("lib.rs"), "mod a;\nmod b;\nmod c;\n").unwrap();
    std::fs::write(src.join("a.rs"), "use super::{b::Thing, c};\n").unwrap();
    std::fs::write(src.join("b.rs"), "use crate::c::Other;\n").unwrap();
    std::fs::write(
        src.join("c.rs"),
        "// use super::b;  (a comment names nothing)\nfn f() { super::a::g() }\n\
         #[cfg(test)]\nmod tests { use super::super::b; }\n",
    )
    .unwrap();
    let found = circles(src);
    assert_eq!(found.len(), 1, "{found:?}");
    let (parent, mut ring) = found[0].clone();
    ring.sort();
    assert_eq!(parent, "");
    assert_eq!(ring, ["a", "b", "c"]);
    // Without c → a the ring is gone.
    std::fs::write(src.join("c.rs"), "fn f() {}\n").unwrap();
    assert!(circles(src).is_empty());
}

#[test]
fn pure_crates_name_no_file_api() {
    for name in ["geometry", "analysis"] {
        let src = repo().join("crates").join(name).join("src");
        for (module, file) in modules(&src) {
            let code = code_without_tests(&std::fs::read_to_string(&file).unwrap());
            for api in [
                "std::fs",
                "File::",
                "wireflight_fsio",
                "read_to_string",
                "std::io::stdout",
            ] {
                assert!(
                    !code.contains(api),
                    "{}: the pure crate `{name}` names `{api}` (module {})",
                    file.display(),
                    module.join("::")
                );
            }
        }
    }
}
