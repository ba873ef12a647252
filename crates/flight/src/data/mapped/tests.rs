use std::f64::consts::{FRAC_PI_2, PI};

use glam::DVec3;

use super::*;

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
