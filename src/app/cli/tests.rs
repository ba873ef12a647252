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
