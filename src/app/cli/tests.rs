use super::*;

#[test]
fn size_parsing() {
    assert_eq!(parse_size("800x600"), Ok((800, 600)));
    assert_eq!(parse_size("1X1"), Ok((1, 1)));
    for bad in ["800", "0x600", "800x-1", "axb", "99999x10", ""] {
        assert!(parse_size(bad).is_err(), "{bad}");
    }
}

#[test]
fn angles_must_be_finite() {
    assert_eq!(finite_f64("-12.5"), Ok(-12.5));
    for bad in ["nan", "inf", "-inf", "NaN", "x"] {
        assert!(finite_f64(bad).is_err(), "{bad}");
    }
}

#[test]
fn negative_angles_parse() {
    let cli = Cli::try_parse_from([
        "wireflight",
        "render",
        "--pitch",
        "-15",
        "--yaw",
        "-90",
        "--out",
        "x.png",
    ])
    .unwrap();
    let Command::Render(r) = cli.command else {
        panic!()
    };
    assert_eq!((r.yaw, r.pitch), (-90.0, -15.0));
}

#[test]
fn view_takes_a_flight_model_with_any_flight_and_compares() {
    let parse = |args: &[&str]| Cli::try_parse_from(["wireflight", "view"].iter().chain(args));
    let view = |args: &[&str]| match parse(args).unwrap().command {
        Command::View(v) => v,
        _ => panic!(),
    };
    assert!(view(&["--flight", "a.csv", "--model", "m.toml"]).compares());
    assert!(view(&["--flight", "a.csv", "--add", "wind"]).compares());
    assert!(view(&["--flight", "a.csv", "--compare"]).compares());
    assert!(!view(&["--flight", "a.csv"]).compares());
    // Without a recorded flight the keys fly the aircraft: no flight model to choose.
    assert!(parse(&["--model", "m.toml"]).is_err());
}

#[test]
fn render_model_is_the_old_spelling_of_mesh_and_not_both() {
    let parse = |args: &[&str]| Cli::try_parse_from(["wireflight", "render"].iter().chain(args));
    let Command::Render(r) = parse(&["--model", "cube.obj", "--out", "x.png"])
        .unwrap()
        .command
    else {
        panic!()
    };
    assert_eq!(r.old_model.as_deref(), Some("cube.obj"));
    assert!(parse(&["--model", "a.obj", "--mesh", "b.obj", "--out", "x.png"]).is_err());
}
