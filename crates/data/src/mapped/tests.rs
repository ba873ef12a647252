use std::f64::consts::{FRAC_PI_2, PI};

use glam::DVec3;

use super::*;
use crate::Channel;

#[test]
fn inline_maps_with_units_numbers_and_offsets() {
    let m = ColumnMap::parse(
        "time=t_us:us:-2, north=x, east=y, height=h:ft, roll=phi:deg,pitch=th:deg,\
         yaw=psi:0.5, airspeed=tas:kt",
    )
    .unwrap();
    let t = m.get("time").unwrap();
    assert_eq!((t.column.as_str(), t.scale, t.offset), ("t_us", 1e-6, -2.0));
    assert_eq!(m.get("height").unwrap().scale, METRES_PER_FOOT);
    assert_eq!(m.get("yaw").unwrap().scale, 0.5);
    let m = ColumnMap::parse("time=t,lat=la:1e-7*deg,lon=lo:1e-7*deg,alt=a:mm").unwrap();
    assert!((m.get("lat").unwrap().scale - 1e-7 * PI / 180.0).abs() < 1e-20);
}

#[test]
fn bad_maps_say_what_is_wrong() {
    let cases = [
        ("north=x", "no `time`"),
        ("time=t", "no position"),
        ("time=t,north=x,east=y", "needs down (or height) too"),
        (
            "time=t,north=x,east=y,down=z,roll=r",
            "attitude comes as a set",
        ),
        (
            "time=t,north=x,east=y,down=z,roll=r:ft",
            "`ft` is a length but roll is an angle",
        ),
        (
            "time=t,north=x,east=y,down=z,roll=r:degs",
            "unknown unit `degs`",
        ),
        ("time=t:0", "other than 0"),
        ("time=t,time=u", "time is mapped twice"),
        ("time=t,speed=s", "unknown quantity `speed`"),
        ("time", "not QUANTITY=COLUMN"),
        ("time=t:s:x", "offset `x`"),
        ("time=t,north=x,east=y,down=z,lat=a", "give one"),
    ];
    for (spec, want) in cases {
        let e = ColumnMap::parse(spec).unwrap_err().to_string();
        assert!(e.contains(want), "{spec}: {e}");
    }
}

#[test]
fn toml_maps() {
    let m = ColumnMap::from_toml(
        r#"
        delimiter = ";"
        [columns]
        time = { column = "t, µs", unit = "us", offset = 1.5 }
        north = "x"
        east = "y"
        down = { column = "z", scale = -1 }
        "#,
    )
    .unwrap();
    assert_eq!(m.delimiter, Some(';'));
    assert_eq!(m.get("time").unwrap().column, "t, µs");
    assert_eq!(m.get("down").unwrap().scale, -1.0);
    let e =
        ColumnMap::from_toml("[columns]\ntime = { column = \"t\", units = \"s\" }").unwrap_err();
    assert!(e.to_string().contains("column map"), "{e}");
}

#[test]
fn reads_mapped_rows() {
    let map =
        ColumnMap::parse("time=ms:ms:-1,north=n,east=e,height=h,roll=r:deg,pitch=p:deg,yaw=y:deg")
            .unwrap();
    let text = "# vehicle: point-mass\nms,n,e,h,r,p,y,junk\n1000,0,0,10,0,0,90,x\n1100,1,0,10,0,0,90,y\n1200,2,0,11,0,0,90,z\n";
    let (d, report) = parse(text, "m.csv", &map).unwrap();
    assert!(
        (d.time[1] - 0.1).abs() < 1e-12 && d.time[0] == 0.0,
        "{:?}",
        d.time
    );
    assert_eq!(d.pos_ned[2], DVec3::new(2.0, 0.0, -11.0));
    assert!((d.attitude.as_ref().unwrap()[0].yaw - FRAC_PI_2).abs() < 1e-12);
    assert!(d.vel_ned.is_some() && d.is_derived(super::super::DERIVED_VEL_NED));
    let text = report.to_string();
    assert!(text.contains("time      ms [ms] -1"), "{text}");
    assert!(text.contains("1 column not mapped"), "{text}");
}

#[test]
fn empty_cells_are_channels_not_sampled_then() {
    let map = ColumnMap::parse(
        "time=t,north=n,east=e,height=h,roll=r:deg,pitch=p:deg,yaw=y:deg,\
         throttle=th,elevator=el,aileron=ai,rudder=ru",
    )
    .unwrap();
    // A logger's export: position at its own rate, attitude at another, commands as set.
    let head = "t;n;e;h;r;p;y;th;el;ai;ru\n";
    let text = format!(
        "{head}0;0;0;10;0;0;170;0.5;0;0;0\n0.1;;;;;;;;;;\n\
         0.2;2;0;10;0;0;-170;0.6;;;\n0.3;;;;0;0;-150;;;;\n"
    );
    let (d, report) = parse(&text, "m.csv", &map).unwrap();
    assert_eq!(d.sampling.count(Channel::Position, 4), 2);
    assert_eq!(d.sampling.count(Channel::Attitude, 4), 3);
    assert_eq!(d.pos_ned[1], DVec3::new(1.0, 0.0, -10.0));
    // Heading filled the short way through ±180°, throttle held.
    assert!(d.attitude.as_ref().unwrap()[1].yaw.to_degrees().abs() > 179.9);
    let c = d.controls.as_ref().unwrap();
    assert_eq!([c[1].throttle, c[3].throttle], [0.5, 0.6]);
    assert!(
        report.to_string().contains("each channel at its own times"),
        "{report}"
    );
    // A set partly empty, the time empty, a column never given: the file, line and column.
    for (rows, want) in [
        (
            "0;0;;10;0;0;0;0;0;0;0\n",
            "m.csv: line 2, column `e`: empty while `n` has a value",
        ),
        (
            ";0;0;10;0;0;0;0;0;0;0\n",
            "m.csv: line 2, column `t`: empty",
        ),
        (
            "0;0;0;10;0;0;0;;0;0;0\n1;0;0;10;0;0;0;;0;0;0\n",
            "m.csv: line 1, column `th`: no samples",
        ),
    ] {
        let e = parse(&format!("{head}{rows}"), "m.csv", &map)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with(want), "{e}");
    }
}

#[test]
fn every_mapped_quantity_has_a_range() {
    for (name, _, _) in QUANTITIES {
        assert!(
            crate::columns::Quantity::of_mapped(name).is_some(),
            "{name} has no range"
        );
    }
}

#[test]
fn values_out_of_range_are_refused_where_they_enter() {
    // The ranges of the project's CSV, in SI after the scale and offset, naming the line,
    // the column and the range.
    let base = "time=t:us,north=n,east=e,down=d";
    let cases = [
        (
            base,
            "t,n,e,d\n0,0,0,0\n1,1e300,0,0\n",
            "line 3",
            "`n`",
            "±1e8 m",
        ),
        (
            base,
            "t,n,e,d\n0,0,0,0\n1e18,0,0,0\n",
            "line 3",
            "`t`",
            "±1e9 s",
        ),
        (
            "time=t,north=n,east=e,down=d:km",
            "t,n,e,d\n0,0,0,0\n1,0,0,2e5\n",
            "line 3",
            "`d`",
            "±1e8 m",
        ),
        (
            "time=t,north=n,east=e,down=d:1:1e9",
            "t,n,e,d\n0,0,0,0\n",
            "line 2",
            "`d`",
            "±1e8 m",
        ),
        (
            "time=t,lat=la:deg,lon=lo:deg,alt=a",
            "t,la,lo,a\n0,10,1e6,0\n",
            "line 2",
            "`lo`",
            "-180°..360°",
        ),
        (
            "time=t,north=n,east=e,down=d,vn=a,ve=b,vd=c",
            "t,n,e,d,a,b,c\n0,0,0,0,1e6,0,0\n",
            "line 2",
            "`a`",
            "±1e5 m/s",
        ),
        (
            "time=t,north=n,east=e,down=d,throttle=x,elevator=y,aileron=z:deg,rudder=w",
            "t,n,e,d,x,y,z,w\n0,0,0,0,0.5,0,91,0\n",
            "line 2",
            "`z`",
            "±90°",
        ),
        (
            "time=t,north=n,east=e,down=d,throttle=x:%,elevator=y:deg,aileron=z:deg,rudder=w:deg",
            "t,n,e,d,x,y,z,w\n0,0,0,0,150,0,0,0\n",
            "line 2",
            "`x`",
            "0..1",
        ),
    ];
    for (spec, text, line, column, range) in cases {
        let map = ColumnMap::parse(spec).unwrap();
        let e = parse(text, "m.csv", &map).unwrap_err().to_string();
        for want in [
            "m.csv",
            line,
            column,
            range,
            "outside the range of a flight",
        ] {
            assert!(e.contains(want), "{spec}: `{want}` not in: {e}");
        }
    }
    // The unit is shown with the cell, so that 1e18 µs is seen to be 1e12 s.
    let map = ColumnMap::parse(base).unwrap();
    let e = parse("t,n,e,d\n0,0,0,0\n1e18,0,0,0\n", "m.csv", &map).unwrap_err();
    assert!(e.to_string().contains("`1e18 us`"), "{e}");
}

#[test]
fn a_lone_cr_ends_a_line() {
    let map = ColumnMap::parse("time=t,north=n,east=e,down=d").unwrap();
    for end in ["\r", "\r\n", "\n"] {
        let text = ["# source: x", "t,n,e,d", "0,0,0,0", "1,1,0,0", "2,2,0,x"].join(end);
        let e = parse(&text, "m.csv", &map).unwrap_err().to_string();
        assert!(
            e.contains("line 5") && e.contains("not a number: `x`"),
            "{end:?}: {e}"
        );
        let text = ["t,n,e,d", "0,0,0,0", "1,1,0,0", ""].join(end);
        let (d, _) = parse(&text, "m.csv", &map).unwrap();
        assert_eq!(d.len(), 2, "{end:?}");
    }
}

#[test]
fn accelerometer_in_m_s2_g_and_ft_s2() {
    let map = ColumnMap::parse("time=t,north=n,east=e,down=d,ax=fx:g,ay=fy:ft/s2,az=fz").unwrap();
    assert_eq!(map.get("ax").unwrap().scale, crate::G0);
    assert_eq!(map.get("ay").unwrap().scale, METRES_PER_FOOT);
    let text = "t,n,e,d,fx,fy,fz\n0,0,0,0,0.1,1,-9.8\n1,1,0,0,-0.1,-1,-9.7\n";
    let (d, report) = parse(text, "acc.csv", &map).unwrap();
    let a = d.accel_body.as_ref().unwrap();
    assert!((a[0].x - 0.1 * crate::G0).abs() < 1e-12, "{}", a[0]);
    assert!((a[1].y + METRES_PER_FOOT).abs() < 1e-12, "{}", a[1]);
    assert_eq!(a[1].z, -9.7);
    let line = report.to_string();
    assert!(
        line.contains("accelerometer  fx [g], fy [ft/s2], fz"),
        "{line}"
    );
    // A set comes whole; a unit of another kind is refused.
    let e = ColumnMap::parse("time=t,north=n,east=e,down=d,ax=fx").unwrap_err();
    assert!(
        e.to_string()
            .contains("accelerometer comes as a set: `ax` is mapped, so map ay, az too"),
        "{e}"
    );
    let e = ColumnMap::parse("time=t,north=n,east=e,down=d,ax=a:m/s,ay=b,az=c").unwrap_err();
    assert!(
        e.to_string()
            .contains("`m/s` is a speed but ax is an acceleration"),
        "{e}"
    );
    // 60 g read as g: beyond the 50 g of every reader, naming the line and column.
    let map = ColumnMap::parse("time=t,north=n,east=e,down=d,ax=fx:g,ay=fy,az=fz").unwrap();
    let text = "t,n,e,d,fx,fy,fz\n0,0,0,0,0,0,-9.8\n1,0,0,0,60,0,-9.8\n";
    let e = parse(text, "acc.csv", &map).unwrap_err().to_string();
    assert_eq!(
        e,
        "acc.csv: line 3, column `fx`: `60 g` is outside the range of a flight: ±490.3 m/s² (50 g)"
    );
}
