//! `wireflight effects`: every effect of the flight model's catalogue, or one, with what it
//! adds, the vehicles it applies to, whether it acts on the flight or on what the sensors read,
//! each parameter's unit, range, default and fit start, and two command lines that use it — the
//! twin of `wireflight keys`, read from the catalogue itself (as a table, or JSON with
//! `--json`).

use serde_json::{json, Value};

use super::keys::bound;
use crate::app::cli::{as_simulated, simulate_flies, EffectsArgs};
use crate::data::format::fmt_number;
use crate::data::VehicleKind;
use crate::flight::autopilot::Manoeuvre;
use crate::flight::effects::{Channel, EffectInfo, ParamSpec, CATALOGUE};
use crate::flight::spec::{EffectSpec, SpecError, AIRCRAFT};

/// Run `wireflight effects`.
///
/// # Errors
/// A name that is not in the catalogue.
pub fn run(args: &EffectsArgs) -> anyhow::Result<()> {
    let one = args.name.as_deref().map(lookup).transpose()?;
    let shown: Vec<Described> = match one {
        Some(info) => vec![Described::of(info)],
        None => CATALOGUE.iter().copied().map(Described::of).collect(),
    };
    if args.json {
        let v = match one {
            Some(_) => shown[0].to_json(),
            None => Value::Array(shown.iter().map(Described::to_json).collect()),
        };
        println!("{}", serde_json::to_string_pretty(&v)?);
    } else if one.is_some() {
        print!("{}", shown[0].text());
    } else {
        print!("{}", listing(&shown));
    }
    Ok(())
}

/// The catalogue entry of that name.
///
/// # Errors
/// A name that is not in the catalogue: the message gives the nearest name ("did you mean")
/// and the catalogue, and for `aircraft` the command that lists the aircraft's numbers.
fn lookup(name: &str) -> anyhow::Result<&'static EffectInfo> {
    if let Some(info) = CATALOGUE.iter().copied().find(|i| i.name == name) {
        return Ok(info);
    }
    if name.split(':').next() == Some(AIRCRAFT) {
        anyhow::bail!(
            "`{name}` is not an effect: the aircraft's own numbers (aircraft:KEY) are listed \
             by `wireflight keys`"
        );
    }
    Err(SpecError::NotInCatalogue(name.to_string()).into())
}

/// One catalogue effect as `effects` shows it: its static description, and what an instance
/// built as `simulate` builds it says.
struct Described {
    info: &'static EffectInfo,
    /// Each parameter's default value, in order (at `simulate`'s default origin).
    defaults: Vec<f64>,
    /// Whether it acts on what the sensors read rather than on the flight.
    measurement: bool,
    /// The channels a measurement effect changes.
    channels: &'static [Channel],
    /// Whether `simulate` can fly it.
    flies: bool,
    /// A channel only a recorded flight has, which it acts from (`simulate` cannot fly it).
    needs: Option<Channel>,
}

impl Described {
    fn of(info: &'static EffectInfo) -> Self {
        let effect = as_simulated(info);
        Self {
            info,
            defaults: effect.values().to_vec(),
            measurement: effect.is_measurement(),
            channels: effect.channels(),
            flies: simulate_flies(effect.as_ref()),
            needs: effect.lacks_channel(),
        }
    }

    /// The vehicle families it applies to.
    fn vehicles(&self) -> Vec<VehicleKind> {
        [VehicleKind::PointMass, VehicleKind::FixedWing]
            .into_iter()
            .filter(|v| self.info.applies.to(*v))
            .collect()
    }

    /// Each parameter with its default and the value a fit starts from.
    fn params(&self) -> impl Iterator<Item = (&'static ParamSpec, f64, f64)> + '_ {
        self.info
            .params
            .iter()
            .zip(&self.defaults)
            .map(|(p, &default)| (p, default, p.start.unwrap_or(default)))
    }

    /// The effect's block of text: name and summary, vehicles and kind, parameters, examples.
    fn text(&self) -> String {
        let vehicles: Vec<&str> = self.vehicles().iter().map(|v| v.name()).collect();
        let mut out = format!(
            "{}: {}\n  applies to {}; {}\n",
            self.info.name,
            self.info.summary,
            vehicles.join(" and "),
            self.acts_on()
        );
        out += &self.param_table();
        let examples = self.examples();
        for (k, line) in examples.hidden.iter().chain([&examples.add]).enumerate() {
            out += &format!("  {:<9}{line}\n", if k == 0 { "example:" } else { "" });
        }
        out
    }

    /// What it acts on, in words.
    fn acts_on(&self) -> String {
        let channels: Vec<String> = self.channels.iter().map(ToString::to_string).collect();
        match self.needs {
            _ if self.measurement => {
                format!("acts on what the sensors read: {}", channels.join(", "))
            }
            Some(c) => {
                format!("acts on the flight from the {c} a flight recorded; simulate has none")
            }
            None => "acts on the flight".into(),
        }
    }

    /// The parameters' table: name, unit, range, default, fit start (`origin` for a property
    /// of the place, explained under the table).
    fn param_table(&self) -> String {
        if self.info.params.is_empty() {
            return "  no parameters\n".into();
        }
        let shown = |p: &ParamSpec, x: f64| {
            if p.from_origin {
                "origin".to_string()
            } else {
                fmt_number(x)
            }
        };
        let rows: Vec<[String; 5]> = self
            .params()
            .map(|(p, default, start)| {
                [
                    p.name.to_string(),
                    if p.unit.is_empty() { "-" } else { p.unit }.to_string(),
                    format!("{}..{}", bound(p.range.0), bound(p.range.1)),
                    shown(p, default),
                    shown(p, start),
                ]
            })
            .collect();
        let header = ["param", "unit", "range", "default", "fit from"].map(String::from);
        let width = |i: usize| {
            std::iter::once(&header)
                .chain(&rows)
                .map(|r| r[i].chars().count())
                .max()
                .unwrap_or(0)
        };
        let (w0, w1, w2, w3, w4) = (width(0), width(1), width(2), width(3), width(4));
        let mut out = String::new();
        for r in std::iter::once(&header).chain(&rows) {
            out += &format!(
                "  {:<w0$}  {:<w1$}  {:<w2$}  {:>w3$}  {:>w4$}\n",
                r[0], r[1], r[2], r[3], r[4]
            );
        }
        if self.info.params.iter().any(|p| p.from_origin) {
            out += "  origin: a property of the place, from the flight's metadata (then held, not \
                    fitted)\n";
        }
        out
    }

    /// The effect as JSON: `examples.hidden` is `null` where `simulate` cannot fly it, and a
    /// number that is not finite is `null` (serde_json writes any so).
    fn to_json(&self) -> Value {
        let params: Vec<Value> = self
            .params()
            .map(|(p, default, start)| {
                json!({
                    "name": p.name,
                    "unit": p.unit,
                    "range": [p.range.0, p.range.1],
                    "default": default,
                    "fit_start": start,
                    "from_origin": p.from_origin,
                })
            })
            .collect();
        let examples = self.examples();
        json!({
            "name": self.info.name,
            "summary": self.info.summary,
            "applies_to": self.vehicles().iter().map(|v| v.name()).collect::<Vec<_>>(),
            "acts_on": if self.measurement { "sensors" } else { "flight" },
            "channels": self.channels.iter().map(|c| channel_key(*c)).collect::<Vec<_>>(),
            "needs_recorded": self.needs.map(channel_key),
            "params": params,
            "examples": { "hidden": examples.hidden, "add": examples.add },
        })
    }
}

/// Two command lines that use an effect.
struct Examples {
    /// A flight simulated with the effect in the truth alone (`--hidden`), its parameters a
    /// typical size away from their defaults, which the comparison recovers; `None` where
    /// `simulate` cannot fly it.
    hidden: Option<String>,
    /// That flight (or a recorded one) compared with the model, the effect added (`--add`)
    /// and its parameters fitted.
    add: String,
}

impl Described {
    fn examples(&self) -> Examples {
        let name = self.info.name;
        // `simulate`'s default vehicle where the effect applies to it.
        let vehicle = if self.info.applies.to(VehicleKind::FixedWing) {
            VehicleKind::FixedWing
        } else {
            VehicleKind::PointMass
        };
        if !self.flies {
            return Examples {
                hidden: None,
                add: format!(
                    "wireflight compare --flight {} --add {name}",
                    recorded_flight(vehicle)
                ),
            };
        }
        // A fixed wing flies the flight test, which moves every surface, the throttle, the
        // attitude and the airspeed, so that the comparison recovers every parameter; a point
        // mass its one manoeuvre, the default.
        let mut simulate = String::from("wireflight simulate");
        if vehicle == VehicleKind::FixedWing {
            simulate += &format!(" --manoeuvre {}", Manoeuvre::FlightTest);
        } else {
            simulate += &format!(" --vehicle {vehicle}");
        }
        for option in self.channels.iter().filter_map(|c| recording_option(*c)) {
            simulate += &format!(" {option}");
        }
        let spec = EffectSpec {
            name: name.to_string(),
            params: self
                .params()
                .filter(|(p, ..)| !p.from_origin)
                .map(|(p, default, _)| (p.name.to_string(), example_value(p, default)))
                .collect(),
            fit: Vec::new(),
        };
        Examples {
            hidden: Some(format!(
                "{simulate} --hidden {} --out {name}.csv",
                spec.to_arg()
            )),
            add: format!("wireflight compare --flight {name}.csv --add {name}"),
        }
    }
}

/// A value to fly a parameter at in an example: its default moved by its typical size (down
/// where up leaves its range), to four significant digits.
fn example_value(p: &ParamSpec, default: f64) -> f64 {
    let step = p.scale_at(default);
    let v = if p.check(default + step).is_ok() {
        default + step
    } else {
        (default - step).clamp(p.range.0, p.range.1)
    };
    fmt_number(v).parse().unwrap_or(v)
}

/// The option that makes `simulate` record a channel it leaves out by default.
fn recording_option(c: Channel) -> Option<&'static str> {
    (c == Channel::Accelerometer).then_some("--noise-acc 0")
}

/// A flight of the repository's test data, for an effect that acts from what only a recorded
/// flight has: a point mass with its attitude (JSBSim's Mk-82), a fixed wing (JSBSim's
/// Cessna 172P).
fn recorded_flight(vehicle: VehicleKind) -> &'static str {
    match vehicle {
        VehicleKind::PointMass => "tests/data/jsbsim-mk82.csv",
        VehicleKind::FixedWing => "tests/data/jsbsim-c172p-doublets.csv",
    }
}

/// A channel's name in JSON.
fn channel_key(c: Channel) -> &'static str {
    match c {
        Channel::Position => "position",
        Channel::Velocity => "velocity",
        Channel::Attitude => "attitude",
        Channel::Rates => "rates",
        Channel::Airspeed => "airspeed",
        Channel::Accelerometer => "accelerometer",
    }
}

/// Every effect: a line on how effects are named and used, then each effect's block.
fn listing(shown: &[Described]) -> String {
    let sensors = shown.iter().filter(|d| d.measurement).count();
    let mut out = format!(
        "NAME[:K=V,...]: the {} effects of the catalogue, {} acting on the flight and {sensors} \
         on what the sensors read; --effects A,B adds them at their defaults, --add NAME fits \
         one's parameters, --add/--hidden NAME:K=V sets them; wireflight effects NAME shows one\n",
        shown.len(),
        shown.len() - sensors,
    );
    for d in shown {
        out += "\n";
        out += &d.text();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all() -> Vec<Described> {
        CATALOGUE.iter().copied().map(Described::of).collect()
    }

    #[test]
    fn every_effect_is_listed_with_its_parameters_units_and_examples() {
        let text = listing(&all());
        assert!(text.starts_with(&format!("NAME[:K=V,...]: the {} effects", CATALOGUE.len())));
        for info in CATALOGUE {
            let head = format!("{}: {}\n", info.name, info.summary);
            let start = text
                .find(&head)
                .unwrap_or_else(|| panic!("{head}:\n{text}"));
            let block = &text[start..];
            let block = &block[..block.find("\n\n").unwrap_or(block.len())];
            for p in info.params {
                let unit = if p.unit.is_empty() { "-" } else { p.unit };
                let line = block
                    .lines()
                    .find(|l| l.split_whitespace().next() == Some(p.name))
                    .unwrap_or_else(|| panic!("{}.{}:\n{block}", info.name, p.name));
                assert!(line.contains(unit), "{line}");
                assert!(line.contains(&format!("{}..{}", bound(p.range.0), bound(p.range.1))));
            }
            assert!(block.contains(&format!("--add {}", info.name)), "{block}");
            assert_eq!(
                block.contains("no parameters"),
                info.params.is_empty(),
                "{block}"
            );
        }
    }

    #[test]
    fn examples_parse_with_values_in_range_and_simulate_what_it_can() {
        for d in all() {
            let name = d.info.name;
            let examples = d.examples();
            assert!(
                examples.add.ends_with(&format!(" --add {name}")),
                "{}",
                examples.add
            );
            let Some(hidden) = examples.hidden else {
                assert_eq!(
                    name, "incidence_lift",
                    "only it acts from a recorded attitude"
                );
                assert!(examples.add.contains("tests/data/jsbsim-mk82.csv"));
                continue;
            };
            let words: Vec<&str> = hidden.split_whitespace().collect();
            let at = words.iter().position(|w| *w == "--hidden").unwrap();
            let spec = EffectSpec::parse(words[at + 1]).unwrap();
            assert_eq!(spec.name, name);
            let mut effect = as_simulated(d.info);
            for (k, v) in &spec.params {
                effect.set_param(k, *v).unwrap();
                let i = d
                    .info
                    .params
                    .iter()
                    .position(|p| p.name == k.as_str())
                    .unwrap();
                assert_ne!(*v, d.defaults[i], "{name}.{k}: the example changes nothing");
            }
            let settable = d.info.params.iter().filter(|p| !p.from_origin).count();
            assert_eq!(spec.params.len(), settable, "{hidden}");
            let fixed_wing = d.info.applies.to(VehicleKind::FixedWing);
            assert_eq!(
                hidden.contains("--vehicle point-mass"),
                !fixed_wing,
                "{hidden}"
            );
            assert_eq!(
                hidden.contains("--manoeuvre flight-test"),
                fixed_wing,
                "{hidden}"
            );
            let writes = format!("--out {name}.csv");
            assert!(hidden.ends_with(&writes) && examples.add.contains(&format!("{name}.csv")));
        }
        let accel = Described::of(crate::flight::effects::find("accel_bias").unwrap());
        assert!(accel.examples().hidden.unwrap().contains("--noise-acc 0"));
    }

    #[test]
    fn example_values_move_by_the_typical_size_and_stay_in_range() {
        let p = ParamSpec::new("x", "m", (-1.0, 1.0), 0.25);
        assert_eq!(example_value(&p, 0.0), 0.25);
        assert_eq!(example_value(&p, 1.0), 0.75);
        let tiny = ParamSpec {
            scale_relative: true,
            ..ParamSpec::new("k", "1/m", (0.0, 1.0), 1e-4)
        };
        assert_eq!(example_value(&tiny, 1e-3), 0.002);
        let nav = ParamSpec::new("delay_s", "s", (0.0, 1.0), 0.02);
        assert_eq!(example_value(&nav, 0.1), 0.12, "no 0.12000000000000001");
    }

    #[test]
    fn json_has_the_text_content_and_parses() {
        let v: Value = serde_json::from_str(
            &serde_json::to_string(&Described::of(CATALOGUE[0]).to_json()).unwrap(),
        )
        .unwrap();
        let wind = CATALOGUE[0];
        assert_eq!(v["name"], wind.name);
        assert_eq!(v["summary"], wind.summary);
        assert_eq!(v["applies_to"], json!(["point-mass", "fixed-wing"]));
        assert_eq!(v["acts_on"], "flight");
        let params = v["params"].as_array().unwrap();
        assert_eq!(params.len(), wind.params.len());
        for (j, p) in params.iter().zip(wind.params) {
            assert_eq!(j["name"], p.name);
            assert_eq!(j["unit"], p.unit);
            assert_eq!(j["range"], json!([p.range.0, p.range.1]));
            assert_eq!(j["default"], 0.0);
        }
        assert!(v["examples"]["hidden"]
            .as_str()
            .unwrap()
            .contains("--hidden wind:"));
        for d in all() {
            let v = d.to_json();
            assert_eq!(v["acts_on"] == "sensors", d.measurement, "{v}");
            assert_eq!(v["channels"].as_array().unwrap().len(), d.channels.len());
            if d.info.params.iter().any(|p| p.from_origin) {
                assert!(d.text().contains("origin: a property of the place"));
            }
        }
    }

    #[test]
    fn an_unknown_name_gets_the_nearest_and_aircraft_gets_keys() {
        assert_eq!(lookup("gyro_bias").unwrap().name, "gyro_bias");
        let e = lookup("wnd").unwrap_err().to_string();
        assert!(
            e.contains("unknown effect `wnd`: did you mean `wind`?"),
            "{e}"
        );
        assert!(e.contains("attitude_offset"), "the catalogue: {e}");
        let e = lookup("aircraft:c_m_alpha").unwrap_err().to_string();
        assert!(e.contains("wireflight keys"), "{e}");
    }
}
