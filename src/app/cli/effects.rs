//! `wireflight effects` options, and what `simulate --help` says of the effects: both read the
//! catalogue itself (`flight::effects::CATALOGUE`), so that no list of effects is written
//! twice.

use clap::Args;

use crate::flight::effects::{Effect, EffectContext, EffectInfo, CATALOGUE};

const EFFECTS_EXAMPLES: &str = "\
Examples:
  wireflight effects                    # every effect of the catalogue
  wireflight effects wind               # one
  wireflight effects gyro_bias --json   # machine-readable
  wireflight keys                       # the aircraft's own numbers (aircraft:KEY)

For each effect: what it adds, the vehicles it applies to, whether it acts on the flight or on
what the sensors read, each parameter's unit, range, default (what --effects flies, and a
--hidden or --add that does not give it) and where a fit starts, and two command lines: a
flight simulated with the effect hidden in the truth, then compared with the model, the
effect added and its parameters fitted.";

/// `wireflight effects` options.
#[derive(Debug, Args)]
#[command(after_help = EFFECTS_EXAMPLES)]
pub struct EffectsArgs {
    /// One effect of the catalogue [default: every one].
    #[arg(value_name = "NAME")]
    pub name: Option<String>,
    /// Machine-readable output (JSON) on stdout: an array of the effects, or with NAME the
    /// one.
    #[arg(long)]
    pub json: bool,
}

/// A catalogue effect as `simulate` builds it: its defaults at `simulate`'s default origin
/// (latitude 45°), with no recorded flight.
pub fn as_simulated(info: &'static EffectInfo) -> Box<dyn Effect> {
    info.build(&EffectContext::default())
}

/// Whether `simulate` can fly an effect built by [`as_simulated`]: it acts from nothing that
/// only a recorded flight has (a point mass's recorded attitude).
pub fn simulate_flies(effect: &dyn Effect) -> bool {
    effect.lacks_channel().is_none()
}

/// The closing paragraph of `simulate --help`: the effects of the catalogue that `simulate`
/// flies, those acting on the flight first, then those acting on what the sensors read.
pub(super) fn simulate_effects_help() -> String {
    let (mut flight, mut sensors) = (Vec::new(), Vec::new());
    for info in CATALOGUE {
        let effect = as_simulated(info);
        if !simulate_flies(effect.as_ref()) {
            continue;
        }
        if effect.is_measurement() {
            sensors.push(info.name);
        } else {
            flight.push(info.name);
        }
    }
    wrap(
        &format!(
            "Effects: {}; and what the sensors read: {} (`wireflight effects` lists each with \
             its parameters; docs/flight-model.md). --hidden effects fly in the truth (the \
             sensors' change what the file records) but nothing about them is written to the \
             file.",
            flight.join(", "),
            sensors.join(", ")
        ),
        HELP_WIDTH,
    )
}

/// Widest line of the help texts.
const HELP_WIDTH: usize = 95;

/// `text` broken into lines of at most `width` characters at spaces (a longer word stands on
/// its own line).
fn wrap(text: &str, width: usize) -> String {
    let mut out = String::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        if !line.is_empty() && line.chars().count() + 1 + word.chars().count() > width {
            out += &line;
            out.push('\n');
            line.clear();
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line += word;
    }
    out + &line
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simulate_help_names_every_effect_simulate_flies_and_no_other() {
        let help = simulate_effects_help();
        let words: Vec<&str> = help
            .split(|c: char| c.is_whitespace() || c == ',' || c == ';')
            .collect();
        for info in CATALOGUE {
            let flies = simulate_flies(as_simulated(info).as_ref());
            assert_eq!(words.contains(&info.name), flies, "{}:\n{help}", info.name);
        }
        assert!(!words.contains(&"incidence_lift"), "{help}");
        assert!(
            help.lines().all(|l| l.chars().count() <= HELP_WIDTH),
            "{help}"
        );
        let sensors = help.find("what the sensors read").unwrap();
        assert!(help.find("gyro_bias").unwrap() > sensors, "{help}");
        assert!(help.find("wind").unwrap() < sensors, "{help}");
    }

    #[test]
    fn wrap_breaks_at_spaces_within_the_width() {
        assert_eq!(wrap("a bb ccc dddd", 6), "a bb\nccc\ndddd");
        assert_eq!(wrap("toolongword x", 4), "toolongword\nx");
        assert_eq!(wrap("", 10), "");
    }
}
