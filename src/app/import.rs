//! `wireflight import`: read a PX4 log or a column-mapped CSV, say what was found, and keep
//! the result as the project's CSV.

use crate::app::cli::ImportArgs;
use crate::data::report::{sampled_channels, sampling_lines};
use crate::data::{load, Loaded};

/// Run `wireflight import`.
///
/// # Errors
/// The reader's error (naming the file and where in it), write errors.
pub fn run(args: &ImportArgs) -> anyhow::Result<()> {
    if let Some(out) = &args.out {
        crate::app::outputs::check_outputs(&[("--flight", &args.flight)], &[("--out", out)], &[])?;
    }
    let Loaded { data, report } = load(&args.flight, &args.data.options())?;
    if let Some(out) = &args.out {
        crate::data::write(out, &data)?;
    }
    if args.json {
        let mut v = match &report {
            Some(r) => r.to_json(),
            None => serde_json::json!({
                "file": args.flight.display().to_string(),
                "format": crate::data::CSV_FORMAT,
                "samples": data.len(),
                "duration_s": data.duration(),
                "sampled": crate::data::report::sampled_json(&sampled_channels(&data)),
            }),
        };
        v["derived"] = serde_json::json!(data.derived);
        v["out"] = serde_json::json!(args.out.as_ref().map(|p| p.display().to_string()));
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    // The report of what the file held goes where every command's does: stderr, unless
    // --quiet (as `compare`); text from the file has its control characters escaped.
    if !crate::draw::progress::is_quiet() {
        let text = match &report {
            Some(r) => r.to_string(),
            None => format!(
                "{} (flight-data CSV): {} {} over {:.1} s\n{}",
                args.flight.display(),
                data.len(),
                if data.sampling.is_all() {
                    "samples"
                } else {
                    "rows"
                },
                data.duration(),
                sampling_lines(&sampled_channels(&data))
            ),
        };
        eprint!("{}", crate::fsio::printable(&text));
    }
    if let Some(out) = &args.out {
        let rows = if data.sampling.is_all() {
            "samples"
        } else {
            "rows"
        };
        println!("wrote {} ({} {rows})", crate::app::shown(out), data.len());
    }
    Ok(())
}
