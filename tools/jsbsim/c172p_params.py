#!/usr/bin/env python3
"""Build a Beard & McLain parameter set (flight-model.md) for JSBSim's c172p.

    python3 tools/jsbsim/c172p_params.py                      # writes assets/aircraft/c172p.toml
    python3 tools/jsbsim/c172p_params.py --out /tmp/x.toml --airspeed 50 --altitude 1000
    python3 tools/jsbsim/c172p_params.py --compare --scale Clda=0.75   # true change of the set
    python3 tools/jsbsim/c172p_params.py --compare --payload-kg 80 --out /tmp/heavy.toml

Sources, in order:
* mass, inertia about the CG: JSBSim's mass balance after loading (empty weight + pilot + fuel
  as the aircraft file has them), slug ft^2 -> kg m^2, Jxz = -inertia/ixz-slugs_ft2 (JSBSim
  stores -integral(xz dm); Beard & McLain use +integral(xz dm));
* S, b, c: the <metrics> of aircraft/c172p/c172p.xml inside the installed package;
* aerodynamic derivatives: JSBSim trimmed at --airspeed/--altitude (still air), then central
  finite differences of JSBSim's own aerodynamic force (forces/fb*-aero-lbs) and moment about
  the CG (moments/*-aero-lbsft, which already contain the aero-reference-point offset) with
  respect to alpha, beta, p, q, r, de, da, dr; each perturbed state is set with run_ic (still
  air, same attitude), and JSBSim's alpha-dot terms (CLadot, Cmadot) are subtracted because
  Beard & McLain have none. Lift/drag are taken in Beard & McLain's stability axes
  (L = fx sin a - fz cos a, D = -fx cos a - fz sin a), rates non-dimensionalised with b/2Va and
  c/2Va, moments with qbar S b / qbar S c;
* c_d_p and the Oswald e: least-squares fit of C_Dp + (C_L0 + C_La a)^2/(pi e AR) to JSBSim's
  drag over alpha in [-3, 9] deg, constrained to pass through the trim point;
* the offsets c_*_0: chosen so that the linear model equals JSBSim at trim. c_m_0 and c_n_0
  also fold in the propulsion moments at trim (thrust line below the CG, thrust at the lateral
  CG offset, P-factor), which Beard & McLain's thrust model lacks, so that the baseline trims
  with JSBSim's elevator and rudder. The engine torque (rolling) is NOT folded by default: it
  is the catalogue effect `prop_torque` (k_torque is fitted and reported); --fold-torque folds
  its trim value into c_ell_0 instead;
* stall blend M, alpha0: fitted to JSBSim's lift table over alpha in [-5, 20] deg;
* propulsion: thrust = 1/2 rho S_prop C_prop ((k_motor dt)^2 - Va^2) fitted to JSBSim's steady
  engine+propeller thrust over dt in [0.45, 0.95], Va in [40, 60] m/s at the trim altitude,
  constrained through the trim point; S_prop is the propeller disc (75 in diameter);
* rho: JSBSim's density at the trim altitude.

Prints a report of every coefficient with its source and writes the TOML atomically.
Needs only the `jsbsim` package.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import tempfile
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import jsbsim  # noqa: E402

from c172p_sim import (  # noqa: E402
    C172P, FT, IN, JSBSIM_VERSION, LBF, air_state_ic,
)
from c172p_variant import Variant, parse_scale, xml_path  # noqa: E402

REPO = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


# ------------------------------------------------------------------------------ XML
def aircraft_xml_path() -> str:
    return os.path.join(jsbsim.get_default_root_dir(), "aircraft", "c172p", "c172p.xml")


def read_metrics(path: str) -> dict:
    """S (m^2), b (m), c (m), prop diameter (m) from the aircraft/engine XML."""
    to_m = {"FT": FT, "IN": IN, "M": 1.0}
    root = ET.parse(path).getroot()
    met = root.find("metrics")

    def length(tag):
        el = met.find(tag)
        return float(el.text) * to_m[el.get("unit", "FT").upper()]

    wa = met.find("wingarea")
    s = float(wa.text) * {"FT2": FT * FT, "M2": 1.0}[wa.get("unit", "FT2").upper()]
    thr = root.find("propulsion/engine/thruster")
    prop_file = os.path.join(jsbsim.get_default_root_dir(), "engine", thr.get("file") + ".xml")
    prop = ET.parse(prop_file).getroot()
    d = prop.find("diameter")
    diam = float(d.text) * to_m[d.get("unit", "IN").upper()]
    ixx_prop = float(prop.find("ixx").text) * LBF / FT * FT * FT  # slug ft^2 -> kg m^2
    return dict(s=s, b=length("wingspan"), c=length("chord"), prop_diameter=diam,
                prop_file=os.path.basename(prop_file), ixx_prop=ixx_prop)


# ------------------------------------------------------------------------------ coefficients
def coefficients(sim: C172P, geo: dict) -> dict:
    """Non-dimensional aero coefficients of the current JSBSim state (alpha-dot removed)."""
    F, M = sim.aero_fm(remove_alphadot=True)
    qbar = sim["aero/qbar-psf"] * LBF / (FT * FT)
    a = sim["aero/alpha-rad"]
    qs = qbar * geo["s"]
    return dict(
        CL=(F[0] * math.sin(a) - F[2] * math.cos(a)) / qs,
        CD=(-F[0] * math.cos(a) - F[2] * math.sin(a)) / qs,
        CY=F[1] / qs,
        Cl=M[0] / (qs * geo["b"]),
        Cm=M[1] / (qs * geo["c"]),
        Cn=M[2] / (qs * geo["b"]),
    )


AXES = ("CL", "CD", "CY", "Cl", "Cm", "Cn")


def derivatives(sim: C172P, base: dict, geo: dict) -> dict:
    """Central finite differences around `base` (trim): d(coefficient)/d(variable) per rad
    (rates: per non-dimensional rate)."""
    va = base["va"]
    bn, cn = geo["b"] / (2 * va), geo["c"] / (2 * va)
    out = {}

    def state_pair(name, h):
        res = []
        for sgn in (1, -1):
            kw = {name: base[name] + sgn * h}
            sim.command(base["de"], base["da"], base["dr"], base["throttle"])
            air_state_ic(sim, base, **kw)
            res.append(coefficients(sim, geo))
        return res

    for name, h, scale in (("alpha", math.radians(0.5), 1.0), ("beta", math.radians(1.0), 1.0),
                           ("p", 0.05, bn), ("q", 0.05, cn), ("r", 0.05, bn)):
        cp, cm = state_pair(name, h)
        out[name] = {k: (cp[k] - cm[k]) / (2 * h * scale) for k in AXES}

    for name, idx, h in (("de", 0, math.radians(1.0)), ("da", 1, math.radians(1.0)),
                         ("dr", 2, math.radians(1.0))):
        res, pos = [], []
        for sgn in (1, -1):
            d = [base["de"], base["da"], base["dr"]]
            d[idx] += sgn * h
            sim.command(d[0], d[1], d[2], base["throttle"])
            air_state_ic(sim, base)
            pos.append(sim.surfaces()[idx])
            res.append(coefficients(sim, geo))
        dd = pos[0] - pos[1]
        out[name] = {k: (res[0][k] - res[1][k]) / dd for k in AXES}
    sim.command(base["de"], base["da"], base["dr"], base["throttle"])
    air_state_ic(sim, base)
    return out


def alpha_sweep(sim: C172P, base: dict, geo: dict, alphas_deg) -> list:
    rows = []
    sim.command(base["de"], base["da"], base["dr"], base["throttle"])
    for ad in alphas_deg:
        air_state_ic(sim, base, alpha=math.radians(ad))
        c = coefficients(sim, geo)
        rows.append((math.radians(ad), c["CL"], c["CD"], sim["aero/stall-hyst-norm"]))
    air_state_ic(sim, base)
    return rows


def sigma(alpha, m, a0):
    e1 = math.exp(-m * (alpha - a0))
    e2 = math.exp(m * (alpha + a0))
    return (1 + e1 + e2) / ((1 + e1) * (1 + e2))


def cl_bm(alpha, cl0, cla, m, a0):
    s = sigma(alpha, m, a0)
    sgn = 1.0 if alpha >= 0 else -1.0
    return (1 - s) * (cl0 + cla * alpha) + s * 2 * sgn * math.sin(alpha) ** 2 * math.cos(alpha)


# ------------------------------------------------------------------------------ propulsion
def thrust_grid(base: dict, throttles, speeds, settle_s=6.0, root=None):
    """Steady JSBSim thrust (N) and propulsion moments (N m) at (throttle, Va): the airframe
    is frozen (integrators 0) while the engine and propeller run to a steady state."""
    sim = C172P(root=root)
    sim.trim(base["va"], base["alt_m"], base["lat"], base["lon"])
    sim["propulsion/fuel_freeze"] = 1
    for k in ("rate/rotational", "rate/translational", "position/rotational",
              "position/translational"):
        sim["simulation/integrator/" + k] = 0
    n = int(round(settle_s / sim.dt))
    rows = []
    for dt in throttles:
        for va in speeds:
            sim.command(base["de"], base["da"], base["dr"], dt)
            air_state_ic(sim, base, va=va)
            last = None
            for i in range(n):
                sim.fdm.run()
                if i == n - int(1.0 / sim.dt):
                    last = sim["propulsion/engine/thrust-lbs"]
            T = sim["propulsion/engine/thrust-lbs"] * LBF
            drift = abs(T - last * LBF)
            _, Mp = sim.prop_fm()
            rows.append(dict(dt=dt, va=va, T=T, drift=drift, l=Mp[0], m=Mp[1], n=Mp[2],
                             rpm=sim["propulsion/engine/engine-rpm"]))
    return rows


def fit_thrust(rows, dt0, va0, t0):
    """T = A dt^2 - B Va^2 through (dt0, va0, t0): one-parameter least squares for B."""
    sxy = sxx = 0.0
    for r in rows:
        x = va0 ** 2 * r["dt"] ** 2 / dt0 ** 2 - r["va"] ** 2
        y = r["T"] - t0 * r["dt"] ** 2 / dt0 ** 2
        sxy += x * y
        sxx += x * x
    b = sxy / sxx
    a = (t0 + b * va0 ** 2) / dt0 ** 2
    return a, b


def fit_thrust_free(rows):
    """Unconstrained least squares T = A dt^2 - B Va^2 (for comparison)."""
    s11 = s12 = s22 = y1 = y2 = 0.0
    for r in rows:
        x1, x2 = r["dt"] ** 2, -r["va"] ** 2
        s11 += x1 * x1
        s12 += x1 * x2
        s22 += x2 * x2
        y1 += x1 * r["T"]
        y2 += x2 * r["T"]
    det = s11 * s22 - s12 * s12
    return (y1 * s22 - y2 * s12) / det, (s11 * y2 - s12 * y1) / det


def thrust_errors(rows, a, b):
    errs = [r["T"] - (a * r["dt"] ** 2 - b * r["va"] ** 2) for r in rows]
    rms = math.sqrt(sum(e * e for e in errs) / len(errs))
    return rms, max(abs(e) for e in errs)


# ------------------------------------------------------------------------------ output
def fmt(v: float, sig: int = 4) -> str:
    """Round to `sig` significant digits; always a TOML float. |v| < 1e-7 is written as 0
    (finite-difference noise of terms JSBSim does not have)."""
    if abs(v) < 1e-7:
        return "0.0"
    s = f"{v:.{sig}g}"
    if "e" in s:
        mant, exp = s.split("e")
        if "." not in mant:
            mant += ".0"
        s = f"{mant}e{int(exp)}"
    elif "." not in s:
        s += ".0"
    return s


def write_atomic(path: str, text: str) -> None:
    d = os.path.dirname(os.path.abspath(path))
    os.makedirs(d, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=".tmp-", dir=d)
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes 0600; give the file normal permissions
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def build(args, root=None) -> tuple[dict, dict, str]:
    """The parameter set of the c172p in the JSBSim root `root` (default: the package's;
    c172p_variant.Variant.build() makes a changed one)."""
    xml = aircraft_xml_path() if root is None else xml_path(root)
    geo = read_metrics(xml)
    ar = geo["b"] ** 2 / geo["s"]

    sim = C172P(root=root)
    base = sim.trim(args.airspeed, args.altitude, args.latitude, args.longitude)
    base.update(alt_m=args.altitude)
    mp = sim.mass_props()
    f = sim.fdm
    # JSBSim's own view of the geometry must agree with the XML.
    for k, prop, unit in (("s", "metrics/Sw-sqft", FT * FT), ("b", "metrics/bw-ft", FT),
                          ("c", "metrics/cbarw-ft", FT)):
        if abs(f[prop] * unit - geo[k]) > 1e-9 * geo[k]:
            raise RuntimeError(f"{k}: XML {geo[k]} vs JSBSim {f[prop] * unit}")

    va, a_t, b_t = base["va"], base["alpha"], base["beta"]
    de_t, da_t, dr_t, dt_t = base["de"], base["da"], base["dr"], base["throttle"]
    rho = base["rho"]
    qbar = 0.5 * rho * va * va
    qbar_jsb = f["aero/qbar-psf"] * LBF / (FT * FT)
    c_t = coefficients(sim, geo)
    Fa, Ma = sim.aero_fm(remove_alphadot=False)
    Fp, Mp = sim.prop_fm()
    trim_info = dict(
        alpha=a_t, beta=b_t, theta=base["theta"], phi=base["phi"], de=de_t, da=da_t, dr=dr_t,
        throttle=dt_t, va=va, rho=rho, qbar=qbar, qbar_jsb=qbar_jsb, thrust=Fp[0],
        prop_moments=Mp, aero_moments=Ma, coeffs=c_t,
        qbar_induced_ratio=f["aero/function/qbar-induced-psf"] / f["aero/qbar-psf"],
        rpm=f["propulsion/engine/engine-rpm"], lat=base["lat"], lon=base["lon"],
        h_m=f["position/geod-alt-ft"] * FT,
    )

    d = derivatives(sim, base, geo)

    # Drag polar through the trim point.
    cla = d["alpha"]["CL"]
    cl0 = c_t["CL"] - cla * a_t - d["de"]["CL"] * de_t
    cdde = d["de"]["CD"]
    sweep = alpha_sweep(sim, base, geo, [x * 0.5 for x in range(-6, 19)])  # -3..9 deg
    cd_t = c_t["CD"] - cdde * de_t
    sxy = sxx = 0.0
    for a, _cl, cd, _h in sweep:
        x = (cl0 + cla * a) ** 2 - (cl0 + cla * a_t) ** 2
        y = (cd - cdde * de_t) - cd_t
        sxy += x * y
        sxx += x * x
    k_ind = sxy / sxx
    cdp = cd_t - k_ind * (cl0 + cla * a_t) ** 2
    e_osw = 1.0 / (math.pi * ar * k_ind)
    polar_err = [cd - (cdp + k_ind * (cl0 + cla * a) ** 2 + cdde * de_t) for a, _c, cd, _h in sweep]
    polar_rms = math.sqrt(sum(x * x for x in polar_err) / len(polar_err))
    polar_max = max(abs(x) for x in polar_err)

    # Stall blend fitted to JSBSim's lift over -5..20 deg (static part, elevator at trim).
    lift = alpha_sweep(sim, base, geo, list(range(-5, 21)))
    cl_de = d["de"]["CL"] * de_t
    best = None
    for m in range(10, 201, 5):
        for a0i in range(200, 401, 2):
            a0 = a0i / 1000.0
            err = sum((cl - cl_de - cl_bm(a, cl0, cla, m, a0)) ** 2 for a, cl, _cd, _h in lift)
            if best is None or err < best[0]:
                best = (err, float(m), a0)
    _, m_blend, alpha0 = best
    stall_rms = math.sqrt(best[0] / len(lift))
    jsb_peak = max(lift, key=lambda r: r[1])
    bm_curve = [(a / 1000.0, cl_bm(a / 1000.0, cl0, cla, m_blend, alpha0)) for a in range(0, 400)]
    bm_peak = max(bm_curve, key=lambda r: r[1])

    # Offsets: the linear model equals JSBSim (aero, + folded propulsion moments) at trim.
    qsb, qsc = qbar_jsb * geo["s"] * geo["b"], qbar_jsb * geo["s"] * geo["c"]
    cm_prop = Mp[1] / qsc
    cn_prop = Mp[2] / qsb
    cl_prop = Mp[0] / qsb
    cy0 = c_t["CY"] + Fp[1] / (qbar_jsb * geo["s"]) - d["beta"]["CY"] * b_t \
        - d["da"]["CY"] * da_t - d["dr"]["CY"] * dr_t
    cm0_aero = c_t["Cm"] - d["alpha"]["Cm"] * a_t - d["de"]["Cm"] * de_t
    cl0_aero = c_t["Cl"] - d["beta"]["Cl"] * b_t - d["da"]["Cl"] * da_t - d["dr"]["Cl"] * dr_t
    cn0_aero = c_t["Cn"] - d["beta"]["Cn"] * b_t - d["da"]["Cn"] * da_t - d["dr"]["Cn"] * dr_t

    # Propulsion.
    prop_rows = thrust_grid(base, [0.45 + 0.05 * i for i in range(11)],
                            [40.0 + 2.5 * i for i in range(9)], root=root)
    wide_rows = thrust_grid(base, [0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0],
                            [35.0, 40.0, 45.0, 50.0, 55.0, 60.0, 65.0], root=root)
    A, B = fit_thrust(prop_rows, dt_t, va, trim_info["thrust"])
    Af, Bf = fit_thrust_free(prop_rows)
    s_prop = math.pi * (geo["prop_diameter"] / 2) ** 2
    c_prop = 2 * B / (rho * s_prop)
    k_motor = math.sqrt(A / B)
    ktq_num = sum(-r["l"] * r["dt"] ** 2 for r in prop_rows)
    ktq_den = sum(r["dt"] ** 4 for r in prop_rows)
    k_torque = ktq_num / ktq_den
    tq_rms = math.sqrt(sum((r["l"] + k_torque * r["dt"] ** 2) ** 2 for r in prop_rows)
                       / len(prop_rows))
    omega_t = trim_info["rpm"] * 2 * math.pi / 60
    k_gyro = geo["ixx_prop"] * omega_t / dt_t

    p = {
        "mass": dict(mass_kg=mp["mass_kg"], jx=mp["jx"], jy=mp["jy"], jz=mp["jz"],
                     jxz=mp["jxz"]),
        "geometry": dict(s_wing=geo["s"], b=geo["b"], c=geo["c"], e=e_osw, rho=rho),
        "longitudinal": dict(
            c_l_0=cl0, c_l_alpha=cla, c_l_q=d["q"]["CL"], c_l_delta_e=d["de"]["CL"],
            c_d_p=cdp, c_d_q=d["q"]["CD"], c_d_delta_e=cdde,
            c_m_0=cm0_aero + cm_prop, c_m_alpha=d["alpha"]["Cm"], c_m_q=d["q"]["Cm"],
            c_m_delta_e=d["de"]["Cm"], m_blend=m_blend, alpha0=alpha0),
        "lateral": dict(
            c_y_0=cy0, c_y_beta=d["beta"]["CY"], c_y_p=d["p"]["CY"], c_y_r=d["r"]["CY"],
            c_y_delta_a=d["da"]["CY"], c_y_delta_r=d["dr"]["CY"],
            c_ell_0=cl0_aero + (cl_prop if args.fold_torque else 0.0),
            c_ell_beta=d["beta"]["Cl"], c_ell_p=d["p"]["Cl"], c_ell_r=d["r"]["Cl"],
            c_ell_delta_a=d["da"]["Cl"], c_ell_delta_r=d["dr"]["Cl"],
            c_n_0=cn0_aero + cn_prop, c_n_beta=d["beta"]["Cn"], c_n_p=d["p"]["Cn"],
            c_n_r=d["r"]["Cn"], c_n_delta_a=d["da"]["Cn"], c_n_delta_r=d["dr"]["Cn"]),
        "propulsion": dict(s_prop=s_prop, c_prop=c_prop, k_motor=k_motor),
    }
    info = dict(
        geo=geo, ar=ar, mp=mp, trim=trim_info, d=d, cl0=cl0, polar_rms=polar_rms,
        polar_max=polar_max, k_ind=k_ind, stall_rms=stall_rms, jsb_peak=jsb_peak,
        bm_peak=bm_peak, lift=lift, cm0_aero=cm0_aero, cm_prop=cm_prop, cl0_aero=cl0_aero,
        cl_prop=cl_prop, cn0_aero=cn0_aero, cn_prop=cn_prop, A=A, B=B, Af=Af, Bf=Bf,
        thrust_fit=thrust_errors(prop_rows, A, B), thrust_fit_free=thrust_errors(prop_rows, Af, Bf),
        thrust_wide=thrust_errors(wide_rows, A, B), prop_rows=prop_rows, wide_rows=wide_rows,
        k_torque=k_torque, tq_rms=tq_rms, k_gyro=k_gyro, omega_t=omega_t,
        drift=max(r["drift"] for r in prop_rows + wide_rows), xml=xml,
        rp_offset=sim.cg_to_rp_body(),
    )
    return p, info, xml


# Where each key comes from (for the report).
SOURCE = {
    "mass_kg": "JSBSim inertia/mass-slugs (empty 1500 lb + pilot 180 lb + fuel 200 lb)",
    "jx": "JSBSim inertia/ixx-slugs_ft2 (about the CG, incl. point masses and fuel)",
    "jy": "JSBSim inertia/iyy-slugs_ft2", "jz": "JSBSim inertia/izz-slugs_ft2",
    "jxz": "-JSBSim inertia/ixz-slugs_ft2 (JSBSim stores -integral xz dm)",
    "s_wing": "c172p.xml <wingarea>", "b": "c172p.xml <wingspan>", "c": "c172p.xml <chord>",
    "e": "fit of the drag polar (through trim), alpha -3..9 deg",
    "rho": "JSBSim atmosphere/rho-slugs_ft3 at the trim altitude",
    "c_l_0": "C_L at trim minus the linear terms", "c_l_alpha": "FD dC_L/dalpha",
    "c_l_q": "FD dC_L/d(q c/2Va)", "c_l_delta_e": "FD dC_L/d(de)",
    "c_d_p": "fit of the drag polar (through trim)", "c_d_q": "FD dC_D/d(q c/2Va)",
    "c_d_delta_e": "FD dC_D/d(de) (JSBSim: 0.06|de|, de > 0 here)",
    "c_m_0": "C_m at trim minus linear terms, + propulsion pitching moment at trim",
    "c_m_alpha": "FD dC_m/dalpha (about the CG)", "c_m_q": "FD dC_m/d(q c/2Va)",
    "c_m_delta_e": "FD dC_m/d(de) (incl. slipstream factor at trim)",
    "m_blend": "LS fit of the blend to JSBSim's C_L(alpha), -5..20 deg",
    "alpha0": "LS fit of the blend to JSBSim's C_L(alpha), -5..20 deg",
    "c_y_0": "C_Y at trim minus linear terms", "c_y_beta": "FD dC_Y/dbeta",
    "c_y_p": "FD dC_Y/d(p b/2Va)", "c_y_r": "FD dC_Y/d(r b/2Va)",
    "c_y_delta_a": "FD dC_Y/d(da)", "c_y_delta_r": "FD dC_Y/d(dr)",
    "c_ell_0": "C_l at trim minus linear terms (engine torque not folded)",
    "c_ell_beta": "FD dC_l/dbeta (about the CG)", "c_ell_p": "FD dC_l/d(p b/2Va)",
    "c_ell_r": "FD dC_l/d(r b/2Va)", "c_ell_delta_a": "FD dC_l/d(da)",
    "c_ell_delta_r": "FD dC_l/d(dr)",
    "c_n_0": "C_n at trim minus linear terms, + propulsion yawing moment at trim",
    "c_n_beta": "FD dC_n/dbeta (about the CG)", "c_n_p": "FD dC_n/d(p b/2Va)",
    "c_n_r": "FD dC_n/d(r b/2Va)", "c_n_delta_a": "FD dC_n/d(da)",
    "c_n_delta_r": "FD dC_n/d(dr) (incl. slipstream factor at trim)",
    "s_prop": "propeller disc, 75 in diameter (prop_75in2f.xml)",
    "c_prop": "thrust fit: 2B/(rho S_prop)", "k_motor": "thrust fit: sqrt(A/B)",
}

# The XML's own number for each derivative, for cross-checking the finite differences (about
# the aero reference point, before the CG offset; None where the XML has no single number).
XML_VALUE = {
    "c_l_alpha": "0.48/0.09 = 5.333 (CLwbh table, |alpha| < 0.09)", "c_l_q": "3.9 (CLq)",
    "c_l_delta_e": "0.43 (CLDe)", "c_d_delta_e": "0.06 (CDDe, |de|)",
    "c_m_alpha": "-1.8 (Cmalpha, about the ARP)", "c_m_q": "-12.4 (Cmq)",
    "c_m_delta_e": "-1.122 x qbar_induced/qbar (Cmde)",
    "c_y_beta": "-0.137/0.349 = -0.3926 (CYb)", "c_y_p": "CYp(alpha) table",
    "c_y_r": "CYr(alpha) table", "c_y_delta_a": "0 (CYda)", "c_y_delta_r": "0.187 (CYdr)",
    "c_ell_beta": "-0.0322/0.349 = -0.0923 (Clb, about the ARP)", "c_ell_p": "-0.484 (Clp)",
    "c_ell_r": "Clr(alpha) table", "c_ell_delta_a": "0.229 (ClDa)",
    "c_ell_delta_r": "0.0147 (Cldr)", "c_n_beta": "0.0205/0.349 = 0.0587 (Cnb)",
    "c_n_p": "-0.0278 (Cnp)", "c_n_r": "-0.0937 (Cnr)", "c_n_delta_a": "-0.0053 (Cnda)",
    "c_n_delta_r": "-0.043 x qbar_induced/qbar (Cndr)",
}


def toml_text(p: dict, info: dict, args) -> str:
    t = info["trim"]
    lines = [
        "# Cessna 172P parameter set for the fixed-wing model of flight-model.md, made from",
        f"# JSBSim {JSBSIM_VERSION}'s c172p (aircraft/c172p/c172p.xml of the Python package) by",
        "# tools/jsbsim/c172p_params.py (see tools/jsbsim/README.md):",
        f"#   trim in still air at Va = {t['va']:.1f} m/s, {args.altitude:.0f} m altitude, flaps up,"
        f" {p['mass']['mass_kg']:.1f} kg;",
        f"#   trim: alpha = {math.degrees(t['alpha']):.3f} deg, de = {math.degrees(t['de']):.3f}"
        f" deg, da = {math.degrees(t['da']):.3f} deg,",
        f"#   dr = {math.degrees(t['dr']):.3f} deg, throttle = {t['throttle']:.4f}.",
        "# Mass and inertia from JSBSim's mass balance (about the CG; Jxz = -JSBSim ixz);",
        "# S, b, c from the XML; derivatives by central finite differences of JSBSim's aero",
        "# forces and moments about the CG (aero reference point offset included, alpha-dot",
        "# terms removed); c_d_p and e from a drag-polar fit; stall blend fitted to the lift",
        "# table; thrust model fitted to the engine+propeller over throttle 0.45..0.95 and",
        "# 40..60 m/s. c_m_0 and c_n_0 include the propulsion moments at trim (thrust line,",
        "# P-factor, thrust at the lateral CG offset); "
        + ("the engine torque at trim is folded into c_ell_0."
           if args.fold_torque else
           "the engine torque is not folded (it is the"),
    ]
    if not args.fold_torque:
        lines.append(f"# `prop_torque` effect: k_torque ~ {info['k_torque']:.0f} N m).")
    lines += [
        "# Not representable here: alpha-dot terms, slipstream (elevator/rudder power vary with",
        "# throttle), drag from |beta|, thrust-line moment changes with throttle, fuel burn.",
        f'name = "c172p"',
        "",
    ]
    units = {"jx": "kg m^2", "s_wing": "m^2", "b": "span, m", "c": "mean chord, m",
             "e": "Oswald efficiency", "rho": "constant air density of the baseline, kg/m^3",
             "mass_kg": None, "m_blend": "M of the stall blend", "alpha0": "rad",
             "s_prop": "propeller disc, m^2", "k_motor": "m/s per unit throttle"}
    sig = {"mass_kg": 5, "jx": 5, "jy": 5, "jz": 5, "jxz": 3, "s_wing": 5, "b": 5, "c": 5,
           "rho": 5, "m_blend": 3, "alpha0": 3, "s_prop": 4}
    for table in ("mass", "geometry", "longitudinal", "lateral", "propulsion"):
        lines.append(f"[{table}]")
        for k, v in p[table].items():
            s = f"{k} = {fmt(v, sig.get(k, 4))}"
            if units.get(k):
                s = f"{s:<24}# {units[k]}"
            lines.append(s)
        lines.append("")
    return "\n".join(lines).rstrip("\n") + "\n"


def report(p: dict, info: dict) -> None:
    t = info["trim"]
    g = info["geo"]
    print(f"JSBSim {JSBSIM_VERSION}, c172p from {info['xml']}")
    print(f"Trim (still air): Va {t['va']:.3f} m/s, h {t['h_m']:.2f} m, alpha "
          f"{math.degrees(t['alpha']):.4f} deg, beta {math.degrees(t['beta']):.4f} deg, theta "
          f"{math.degrees(t['theta']):.4f} deg, phi {math.degrees(t['phi']):.4f} deg")
    print(f"  de {math.degrees(t['de']):.4f} deg, da {math.degrees(t['da']):.4f} deg, dr "
          f"{math.degrees(t['dr']):.4f} deg, throttle {t['throttle']:.5f}, thrust "
          f"{t['thrust']:.1f} N, {t['rpm']:.0f} rpm, qbar {t['qbar_jsb']:.2f} Pa "
          f"(1/2 rho Va^2 = {t['qbar']:.2f}), slipstream qbar ratio {t['qbar_induced_ratio']:.4f}")
    print(f"  propulsion moments at trim (N m): l {t['prop_moments'][0]:.1f}, m "
          f"{t['prop_moments'][1]:.1f}, n {t['prop_moments'][2]:.1f}")
    mp = info["mp"]
    print(f"  CG (structural, in): {mp['cg_in']}, CG->aero ref. point (body FRD, m): "
          f"{[round(x, 4) for x in info['rp_offset']]}")
    print(f"  products of inertia B&M has no key for: Jxy {mp['jxy']:.2f}, Jyz {mp['jyz']:.2f}"
          " kg m^2 (ignored)")
    print()
    print(f"{'key':<15}{'value':>12}  source  [XML value]")
    for table in ("mass", "geometry", "longitudinal", "lateral", "propulsion"):
        print(f"[{table}]")
        for k, v in p[table].items():
            xmlv = XML_VALUE.get(k)
            print(f"  {k:<13}{fmt(v, 5):>12}  {SOURCE[k]}" + (f"  [{xmlv}]" if xmlv else ""))
    print()
    print(f"Offsets: c_m_0 aero {info['cm0_aero']:.5f} + propulsion {info['cm_prop']:.5f}; "
          f"c_n_0 aero {info['cn0_aero']:.5f} + propulsion {info['cn_prop']:.5f}; "
          f"c_ell_0 aero {info['cl0_aero']:.5f} (engine torque at trim would add "
          f"{info['cl_prop']:.5f})")
    print(f"Drag polar: k = 1/(pi e AR) = {info['k_ind']:.5f} (AR {info['ar']:.3f}), fit RMS "
          f"{info['polar_rms']:.5f}, max {info['polar_max']:.5f} over alpha -3..9 deg")
    print(f"Stall blend: RMS C_L error {info['stall_rms']:.4f} over -5..20 deg; JSBSim peak "
          f"C_L {info['jsb_peak'][1]:.3f} at {math.degrees(info['jsb_peak'][0]):.1f} deg, B&M "
          f"peak {info['bm_peak'][1]:.3f} at {math.degrees(info['bm_peak'][0]):.1f} deg")
    print("  alpha  JSBSim C_L  B&M C_L   (elevator at trim)")
    cl_de = info["d"]["de"]["CL"] * t["de"]
    L = p["longitudinal"]
    for a, cl, _cd, _h in info["lift"]:
        if round(math.degrees(a)) % 2 == 0:
            print(f"  {math.degrees(a):5.1f}  {cl:9.4f}  "
                  f"{cl_bm(a, L['c_l_0'], L['c_l_alpha'], L['m_blend'], L['alpha0']) + cl_de:9.4f}")
    print("Cross derivatives Beard & McLain cannot hold (per rad / per non-dim. rate):")
    d = info["d"]
    for var, axis in (("alpha", "Cl"), ("alpha", "Cn"), ("alpha", "CY"), ("beta", "CL"),
                      ("beta", "Cm"), ("beta", "CD"), ("p", "Cm"), ("q", "Cl"), ("de", "Cl"),
                      ("da", "CL"), ("dr", "CD")):
        print(f"  d{axis}/d{var} = {d[var][axis]:+.5f}")
    A, B = info["A"], info["B"]
    rms, mx = info["thrust_fit"]
    print(f"Thrust fit T = A dt^2 - B Va^2, through trim: A {A:.1f} N, B {B:.5f} N s^2/m^2; "
          f"RMS {rms:.1f} N, max {mx:.1f} N over dt 0.45..0.95 x Va 40..60 m/s "
          f"(trim thrust {t['thrust']:.1f} N; {100 * rms / t['thrust']:.1f}% RMS)")
    rf, mf = info["thrust_fit_free"]
    print(f"  unconstrained LS: A {info['Af']:.1f}, B {info['Bf']:.5f}: RMS {rf:.1f} N, max "
          f"{mf:.1f} N")
    rw, mw = info["thrust_wide"]
    print(f"  same fit over dt 0.3..1.0 x Va 35..65 m/s: RMS {rw:.1f} N, max {mw:.1f} N")
    print(f"  engine settle: max thrust change over the last second {info['drift']:.2f} N")
    print("  JSBSim thrust (N) vs fit, rows dt, columns Va 35..65:")
    for dt in sorted({r["dt"] for r in info["wide_rows"]}):
        row = [r for r in info["wide_rows"] if r["dt"] == dt]
        print(f"   {dt:.1f} " + " ".join(f"{r['T']:6.0f}/{A * dt * dt - B * r['va'] ** 2:6.0f}"
                                       for r in row))
    print(f"Engine torque: l_prop = -k_torque dt^2 with k_torque {info['k_torque']:.1f} N m "
          f"(RMS {info['tq_rms']:.1f} N m)  -> catalogue effect prop_torque")
    print(f"Propeller angular momentum at trim: I_prop {g['ixx_prop']:.3f} kg m^2 x "
          f"{info['omega_t']:.1f} rad/s; k_gyro = h/dt ~ {info['k_gyro']:.0f} kg m^2/s "
          "-> catalogue effect gyroscopic")


# Which keys of the set a change of the XML is meant to move (the headline of --compare).
TARGET_KEYS = {
    "ClDa": ["c_ell_delta_a"], "Cnr": ["c_n_r"], "Cmalpha": ["c_m_alpha"], "Clp": ["c_ell_p"],
    "Cmq": ["c_m_q"], "Cmde": ["c_m_delta_e"], "Cnb": ["c_n_beta"], "Clb": ["c_ell_beta"],
    "Cndr": ["c_n_delta_r"], "Cnda": ["c_n_delta_a"], "Cldr": ["c_ell_delta_r"],
    "CLDe": ["c_l_delta_e"], "CLq": ["c_l_q"], "CLwbh": ["c_l_alpha", "c_l_0"],
    "CYb": ["c_y_beta"], "Cnp": ["c_n_p"], "Clr": ["c_ell_r"], "CYdr": ["c_y_delta_r"],
}


def compare(p0: dict, p1: dict, variant: Variant, threshold: float = 0.005) -> list:
    """Print the true change of the set (every key that moves by more than `threshold`
    relative, the target keys always) and return [(key, before, after)]."""
    targets = [k for n in variant.scales for k in TARGET_KEYS.get(n, [])]
    if variant.payload_kg:
        targets.append("mass_kg")
    print(f"True change of the parameter set for: {variant.describe()}")
    print(f"  {'key':<15}{'unchanged':>12}{'changed':>12}{'change':>12}{'ratio':>9}")
    out = []
    for table in p0:
        for k, v0 in p0[table].items():
            v1 = p1[table][k]
            rel = abs(v1 - v0) / abs(v0) if v0 != 0 else (0.0 if v1 == 0 else math.inf)
            tiny = max(abs(v0), abs(v1)) < 1e-7  # written as 0 in the TOML (fmt)
            if k in targets or (rel > threshold and not tiny):
                ratio = f"{v1 / v0:9.4f}" if v0 != 0 else f"{'-':>9}"
                mark = "  <- target" if k in targets else ""
                print(f"  {k:<15}{fmt(v0, 5):>12}{fmt(v1, 5):>12}{v1 - v0:>+12.4g}{ratio}{mark}")
                out.append((k, v0, v1))
    print(f"  (others change by less than {100 * threshold:g} %)")
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=None,
                    help="TOML to write (default: assets/aircraft/c172p.toml for the unchanged "
                         "aircraft; nothing for a changed one)")
    ap.add_argument("--airspeed", type=float, default=50.0, help="trim true airspeed, m/s")
    ap.add_argument("--altitude", type=float, default=1000.0, help="trim altitude, m")
    ap.add_argument("--latitude", type=float, default=47.4)
    ap.add_argument("--longitude", type=float, default=8.5)
    ap.add_argument("--fold-torque", action="store_true",
                    help="fold the engine torque at trim into c_ell_0")
    ap.add_argument("--scale", action="append", default=[], metavar="NAME=F",
                    help="derive the set of a changed c172p: aero/coefficient/NAME times F "
                         "(repeatable; as fly.py --scale)")
    ap.add_argument("--payload-kg", type=float, default=0.0,
                    help="derive the set of a c172p with this payload at the CG, kg")
    ap.add_argument("--compare", action="store_true",
                    help="with --scale/--payload-kg: print only the true change of the set "
                         "(changed vs unchanged aircraft), not the full report")
    ap.add_argument("--dry-run", action="store_true", help="report only, write nothing")
    args = ap.parse_args(argv)
    try:
        scales = dict(parse_scale(x) for x in args.scale)
    except ValueError as e:
        ap.error(str(e))
    variant = Variant(scales, args.payload_kg)
    if not variant.changed:
        if args.compare:
            ap.error("--compare needs --scale or --payload-kg")
        p, info, _ = build(args)
        report(p, info)
        out = args.out or os.path.join(REPO, "assets", "aircraft", "c172p.toml")
        if not args.dry_run:
            write_atomic(out, toml_text(p, info, args))
            print(f"\nwrote {out}")
        return 0
    root = variant.build()
    print(f"changed c172p: {variant.describe()} (checked in JSBSim)")
    p, info, _ = build(args, root)
    if args.compare:
        p0, _, _ = build(args)
        compare(p0, p, variant)
    else:
        report(p, info)
    if args.out and not args.dry_run:
        text = toml_text(p, info, args).replace(
            '# Cessna 172P parameter set', f'# Changed ({variant.describe()}) Cessna 172P '
            'parameter set', 1)
        write_atomic(args.out, text)
        print(f"\nwrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
