//! `wireflight effects` and `wireflight keys --json` end to end: every catalogue effect listed
//! with its parameters and units, the JSON, every command line the effects print run as
//! printed (so that the examples cannot rot), an unknown name refused with the nearest one,
//! and every key of the shipped parameter sets.

use std::path::Path;
use std::process::Output;

use serde_json::{json, Value};
use wireflight::flight::effects::CATALOGUE;
use wireflight::flight::params::keys::KEYS;
use wireflight::flight::spec::EffectSpec;

use crate::support::cli::{ok, refused, stderr, stdout, wireflight, wireflight_in};

/// What a run of `wireflight ARGS` printed, read as JSON (it must succeed).
fn json_of(args: &[&str]) -> Value {
    let text = ok(args);
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{args:?}: not JSON: {e}\n{text}"))
}

/// Run a command line as `effects` prints it (`wireflight ARGS`, words without quotes), with
/// `extra` arguments after it, in `dir`; paths into the repository (`tests/data/…`) are read
/// from it.
fn run_printed(line: &str, extra: &[&str], dir: &Path) -> Output {
    let mut words = line.split_whitespace();
    assert_eq!(words.next(), Some("wireflight"), "{line}");
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let args: Vec<String> = words
        .map(|w| match repo.join(w) {
            p if w.contains('/') && p.exists() => p.display().to_string(),
            _ => w.to_string(),
        })
        .chain(extra.iter().map(|a| a.to_string()))
        .collect();
    wireflight_in(dir, &args)
}

#[test]
fn every_effect_is_listed_with_its_parameters_and_units() {
    let text = ok(&["effects"]);
    let blocks: Vec<&str> = text.trim_end().split("\n\n").skip(1).collect();
    assert_eq!(blocks.len(), CATALOGUE.len(), "{text}");
    for (info, block) in CATALOGUE.iter().zip(&blocks) {
        assert!(
            block.starts_with(&format!("{}: {}\n", info.name, info.summary)),
            "{block}"
        );
        for p in info.params {
            let unit = if p.unit.is_empty() { "-" } else { p.unit };
            let line = block
                .lines()
                .find(|l| l.split_whitespace().next() == Some(p.name))
                .unwrap_or_else(|| panic!("{}.{} missing:\n{block}", info.name, p.name));
            assert!(line.contains(unit), "{line}");
        }
        assert_eq!(block.contains("no parameters"), info.params.is_empty());
        // `effects NAME` prints the effect's block of the list.
        let one = ok(&["effects", info.name]);
        assert_eq!(one.trim_end(), *block);
    }
}

#[test]
fn effects_json_parses_with_every_effect_and_the_wind_s_parameters() {
    let wind = json_of(&["effects", "wind", "--json"]);
    assert_eq!(wind["name"], "wind");
    assert_eq!(wind["applies_to"], json!(["point-mass", "fixed-wing"]));
    assert_eq!(wind["acts_on"], "flight");
    let params = wind["params"].as_array().unwrap();
    let names: Vec<&str> = params.iter().map(|p| p["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["north_mps", "east_mps", "down_mps"]);
    for p in params {
        assert_eq!(p["unit"], "m/s");
        assert_eq!(p["range"], json!([-200.0, 200.0]));
        assert_eq!((&p["default"], &p["fit_start"]), (&json!(0.0), &json!(0.0)));
    }
    let all = json_of(&["effects", "--json"]);
    let all = all.as_array().unwrap();
    assert_eq!(all.len(), CATALOGUE.len());
    for (info, e) in CATALOGUE.iter().zip(all) {
        assert_eq!(
            (&e["name"], &e["summary"]),
            (&json!(info.name), &json!(info.summary))
        );
        let params = e["params"].as_array().unwrap();
        assert_eq!(params.len(), info.params.len(), "{e}");
        for (p, j) in info.params.iter().zip(params) {
            assert_eq!((&j["name"], &j["unit"]), (&json!(p.name), &json!(p.unit)));
            assert_eq!(j["range"], json!([p.range.0, p.range.1]));
            for value in ["default", "fit_start"] {
                let v = j[value].as_f64().unwrap_or_else(|| panic!("{value}: {j}"));
                assert!(p.check(v).is_ok(), "{}.{}: {value} {v}", info.name, p.name);
            }
        }
    }
}

/// Every command line the effects print runs as printed: the flight simulated with the effect
/// hidden (shortened to 20 s), then compared with the model, the effect added, whose fit
/// recovers the hidden values (the flight has no noise).
#[test]
fn every_printed_example_runs_and_the_fit_recovers_what_was_hidden() {
    let dir = tempfile::tempdir().unwrap();
    let all = json_of(&["effects", "--json"]);
    for e in all.as_array().unwrap() {
        let name = e["name"].as_str().unwrap();
        let text = stdout(&wireflight(&["effects", name]));
        let hidden = e["examples"]["hidden"].as_str();
        let add = e["examples"]["add"].as_str().unwrap();
        for line in hidden.iter().chain([&add]) {
            assert!(
                text.contains(*line),
                "{name}: `{line}` not printed:\n{text}"
            );
        }
        let mut truth = Vec::new();
        if let Some(line) = hidden {
            let o = run_printed(line, &["--duration", "20"], dir.path());
            assert!(o.status.success(), "{line}: {}", stderr(&o));
            assert!(
                stdout(&o).contains("(+1 hidden, not in the file)"),
                "{}",
                stdout(&o)
            );
            let spec = line
                .split_whitespace()
                .skip_while(|w| *w != "--hidden")
                .nth(1);
            truth = EffectSpec::parse(spec.unwrap()).unwrap().params;
        }
        let o = run_printed(add, &["--json"], dir.path());
        assert!(o.status.success(), "{add}: {}", stderr(&o));
        let v: Value = serde_json::from_str(&stdout(&o)).unwrap();
        let added = &v["added"][0];
        assert_eq!(added["effect"], name, "{add}: {v}");
        for (key, value) in &truth {
            let fitted = added["params"][key].as_f64().unwrap();
            assert!(
                (fitted - value).abs() <= 0.05 * value.abs(),
                "{add}: {key} = {fitted}, hidden {value}"
            );
        }
    }
}

#[test]
fn help_has_examples_and_the_global_options() {
    let text = stdout(&wireflight(&["effects", "--help"]));
    assert!(text.contains("Examples:") && text.contains("wireflight effects wind"));
    assert!(text.contains("Global options (every command):"), "{text}");
    let top = stdout(&wireflight(&["--help"]));
    assert!(top.contains("effects") && top.contains("keys"), "{top}");
}

#[test]
fn an_unknown_effect_is_refused_with_the_nearest_name() {
    let o = wireflight(&["effects", "gyro_bais"]);
    assert_eq!(o.status.code(), Some(2), "{}", stdout(&o));
    let err = stderr(&o);
    assert!(
        err.contains("unknown effect `gyro_bais`: did you mean `gyro_bias`?"),
        "{err}"
    );
    assert!(
        err.contains("attitude_offset") && stdout(&o).is_empty(),
        "{err}"
    );
    let err = refused(&["effects", "aircraft", "--json"]);
    assert!(err.contains("wireflight keys"), "{err}");
}

#[test]
fn keys_json_lists_every_key_with_a_finite_value_in_each_shipped_set() {
    let aircraft = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/aircraft");
    let mut sets = vec![("aerosonde".to_string(), "aerosonde".to_string())];
    for entry in std::fs::read_dir(&aircraft).unwrap() {
        let path = entry.unwrap().path();
        let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
        sets.push((path.display().to_string(), stem));
    }
    assert!(sets.len() >= 3, "{sets:?}");
    for (set, name) in &sets {
        let v = json_of(&["keys", "--aircraft", set.as_str(), "--json"]);
        assert_eq!(v["aircraft"], json!(name), "{set}");
        let keys = v["keys"].as_array().unwrap();
        assert_eq!(keys.len(), KEYS.len());
        for (k, j) in KEYS.iter().zip(keys) {
            assert_eq!((&j["key"], &j["table"]), (&json!(k.name), &json!(k.table)));
            assert_eq!(
                (&j["unit"], &j["meaning"]),
                (&json!(k.unit), &json!(k.term))
            );
            assert_eq!(j["range"], json!([k.range.0, k.range.1]));
            let value = j["value"].as_f64().unwrap_or_else(|| panic!("{set}: {j}"));
            assert!(value.is_finite() && (k.range.0..=k.range.1).contains(&value));
        }
    }
    assert_eq!(json_of(&["keys", "--json"])["aircraft"], "aerosonde");
}
