"""Shared helpers for flying JSBSim's c172p headless (used by c172p_params.py, fly.py, check.py).

Facts this module relies on (see docs/jsbsim.md):

* c172p, not c172x; dt = 1/400 s; rotational integrators = 3 (Adams-Bashforth 2).
* Surfaces: fcs/elevator-pos-rad, fcs/left-aileron-pos-rad, fcs/right-aileron-pos-rad (= -left)
  and fcs/rudder-pos-rad have Beard & McLain's signs: de = elevator, da = (left - right)/2, dr =
  rudder. The FCS maps a normalised command to a position asymmetrically (elevator -28..+23 deg,
  ailerons -20..+15 deg, rudder +-16 deg, all times a gain of 0.01745 rad/deg), so surfaces are
  commanded here in radians through the inverse of that map.
* A command set before run() acts one step late: fly.py sets each sample's command one step
  early.
* Trim in still air; wind is added by restarting with ground velocity = air velocity + wind.
* JSBSim's NED is local to the current position: outputs are rotated into the flat tangent
  frame at the origin (ECEF position from position/ecef-*-ft, attitude through Tec2b).
* inertia/ixz-slugs_ft2 is -integral(xz dm); Beard & McLain's Jxz is +integral(xz dm).
* moments/*-aero-lbsft are about the CG (JSBSim folds the aerodynamic reference point offset
  in); the alpha-dot terms (aero/coefficient/*adot*) are removed when linearising.

Needs only the `jsbsim` package (which itself depends on numpy; numpy is used here only because
JSBSim's matrix accessors return numpy arrays).
"""

from __future__ import annotations

import contextlib
import math
import os
import sys

import jsbsim

# Units (exact definitions).
FT = 0.3048  # m per ft
LBF = 4.4482216152605  # N per lbf
SLUG = LBF / FT  # kg per slug (14.5939...)
SLUG_FT2 = SLUG * FT * FT  # kg m^2 per slug ft^2 (1.35582...)
LBF_FT = LBF * FT  # N m per lbf ft
IN = 0.0254  # m per inch
SLUG_FT3 = SLUG / FT**3  # kg/m^3 per slug/ft^3
G0 = 9.80665

# FCS maps (c172p.xml, <flight_control>): position = norm * limit * GAIN.
GAIN = 0.01745
ELEV_LIM = (28.0, 23.0)  # (negative side, positive side), deg of "norm * limit"
AIL_LIM = (20.0, 15.0)  # left aileron; right = -left
RUD_LIM = (16.0, 16.0)

DT = 1.0 / 400.0
JSBSIM_VERSION = jsbsim.__version__


@contextlib.contextmanager
def quiet():
    """Silence JSBSim's C++ banner and trim chatter on stdout (fd 1)."""
    sys.stdout.flush()
    saved = os.dup(1)
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 1)
        yield
    finally:
        sys.stdout.flush()
        os.dup2(saved, 1)
        os.close(saved)
        os.close(devnull)


def _norm(rad: float, lim: tuple[float, float]) -> float:
    """Normalised command giving surface position `rad` through the asymmetric FCS map."""
    if rad >= 0.0:
        n = rad / (lim[1] * GAIN)
    else:
        n = rad / (lim[0] * GAIN)
    return max(-1.0, min(1.0, n))


def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def mat_vec(a, v):
    return [sum(a[i][k] * v[k] for k in range(3)) for i in range(3)]


def transpose(a):
    return [[a[j][i] for j in range(3)] for i in range(3)]


def euler_to_dcm(phi, theta, psi):
    """R_body->NED = Rz(psi) Ry(theta) Rx(phi)."""
    cf, sf = math.cos(phi), math.sin(phi)
    ct, st = math.cos(theta), math.sin(theta)
    cp, sp = math.cos(psi), math.sin(psi)
    return [
        [ct * cp, sf * st * cp - cf * sp, cf * st * cp + sf * sp],
        [ct * sp, sf * st * sp + cf * cp, cf * st * sp - sf * cp],
        [-st, sf * ct, cf * ct],
    ]


def dcm_to_euler(r):
    """(phi, theta, psi) of R_body->NED (z-y-x), psi and phi in (-pi, pi]."""
    theta = math.asin(max(-1.0, min(1.0, -r[2][0])))
    phi = math.atan2(r[2][1], r[2][2])
    psi = math.atan2(r[1][0], r[0][0])
    return phi, theta, psi


def as_list(m):
    """3x3 numpy array/matrix -> nested lists of floats."""
    rows = m.tolist()
    return [[float(x) for x in row] for row in rows]


def as_vec(m):
    """3-vector numpy array/matrix (any shape) -> list of floats."""
    out = []

    def walk(x):
        if isinstance(x, list):
            for y in x:
                walk(y)
        else:
            out.append(float(x))

    walk(m.tolist())
    return out


class C172P:
    """One JSBSim c172p instance with the project's conventions."""

    def __init__(self, dt: float = DT, root: str | None = None):
        """root: a JSBSim root folder (default: the package's; c172p_variant.py makes one
        with a changed aircraft)."""
        with quiet():
            self.fdm = jsbsim.FGFDMExec(root or jsbsim.get_default_root_dir())
            self.fdm.set_debug_level(0)
            if not self.fdm.load_model("c172p"):
                raise RuntimeError("JSBSim could not load c172p")
        self.fdm.set_dt(dt)
        self.dt = dt
        for k in ("rate/rotational", "position/rotational"):
            self.fdm["simulation/integrator/" + k] = 3
        self.frame0 = None

    def __getitem__(self, k):
        return self.fdm[k]

    def __setitem__(self, k, v):
        self.fdm[k] = v

    # ---------------------------------------------------------------- controls
    def command(self, de: float, da: float, dr: float, throttle: float) -> None:
        """Command surfaces (rad, Beard & McLain signs) and throttle (0..1).

        The trim commands are zeroed: the whole deflection goes through *-cmd-norm."""
        f = self.fdm
        f["fcs/pitch-trim-cmd-norm"] = 0.0
        f["fcs/roll-trim-cmd-norm"] = 0.0
        f["fcs/yaw-trim-cmd-norm"] = 0.0
        f["fcs/elevator-cmd-norm"] = _norm(de, ELEV_LIM)
        f["fcs/aileron-cmd-norm"] = _norm(da, AIL_LIM)
        f["fcs/rudder-cmd-norm"] = _norm(dr, RUD_LIM)
        f["fcs/throttle-cmd-norm"] = max(0.0, min(1.0, throttle))

    def surfaces(self) -> tuple[float, float, float]:
        """Actual surface positions in Beard & McLain's convention, rad: (de, da, dr)."""
        f = self.fdm
        da = 0.5 * (f["fcs/left-aileron-pos-rad"] - f["fcs/right-aileron-pos-rad"])
        return f["fcs/elevator-pos-rad"], da, f["fcs/rudder-pos-rad"]

    # ---------------------------------------------------------------- trim
    def trim(self, va: float, alt_m: float, lat_deg: float, lon_deg: float,
             heading_deg: float = 0.0, gamma_deg: float = 0.0) -> dict:
        """Full trim in still air at true airspeed va (m/s) and geodetic altitude alt_m."""
        f = self.fdm
        f["ic/lat-geod-deg"] = lat_deg
        f["ic/long-gc-deg"] = lon_deg
        f["ic/h-sl-ft"] = alt_m / FT
        f["ic/psi-true-deg"] = heading_deg
        f["ic/vt-fps"] = va / FT
        f["ic/gamma-deg"] = gamma_deg
        f["ic/phi-deg"] = 0.0
        f["ic/beta-deg"] = 0.0
        f["ic/p-rad_sec"] = f["ic/q-rad_sec"] = f["ic/r-rad_sec"] = 0.0
        f["fcs/mixture-cmd-norm"] = 1.0
        f["fcs/throttle-cmd-norm"] = 0.7
        with quiet():
            f.run_ic()
            f["propulsion/set-running"] = -1
            f.run_ic()
            f.do_trim(1)  # full trim; raises jsbsim.TrimFailureError on failure
        de, da, dr = self.surfaces()
        st = self.state()
        st.update(de=de, da=da, dr=dr, throttle=f["fcs/throttle-cmd-norm"])
        # Re-express the trim through our own command path (total deflection in *-cmd-norm).
        self.command(de, da, dr, st["throttle"])
        return st

    def state(self) -> dict:
        """Kinematic state needed to restart (local NED, still-air quantities)."""
        f = self.fdm
        return dict(
            lat=f["position/lat-geod-deg"], lon=f["position/long-gc-deg"],
            h_sl_ft=f["position/h-sl-ft"],
            phi=f["attitude/phi-rad"], theta=f["attitude/theta-rad"], psi=f["attitude/psi-rad"],
            u=f["velocities/u-fps"] * FT, v=f["velocities/v-fps"] * FT,
            w=f["velocities/w-fps"] * FT,
            p=f["velocities/p-rad_sec"], q=f["velocities/q-rad_sec"], r=f["velocities/r-rad_sec"],
            alpha=f["aero/alpha-rad"], beta=f["aero/beta-rad"], va=f["velocities/vt-fps"] * FT,
            rho=f["atmosphere/rho-slugs_ft3"] * SLUG_FT3,
        )

    def restart(self, st: dict, wind_ned=(0.0, 0.0, 0.0)) -> None:
        """Restart from a still-air state `st` (from trim()/state()) with a steady wind:
        same position, attitude, rates and air-relative velocity; ground velocity = air + wind.
        The engine keeps its state (run_ic does not reset it)."""
        f = self.fdm
        wn, we, wd = wind_ned
        f["ic/lat-geod-deg"] = st["lat"]
        f["ic/long-gc-deg"] = st["lon"]
        f["ic/h-sl-ft"] = st["h_sl_ft"]
        f["ic/phi-rad"] = st["phi"]
        f["ic/theta-rad"] = st["theta"]
        f["ic/psi-true-rad"] = st["psi"]
        R = euler_to_dcm(st["phi"], st["theta"], st["psi"])
        vair = mat_vec(R, [st["u"], st["v"], st["w"]])
        mag = math.hypot(wn, we)
        f["ic/vw-mag-fps"] = mag / FT
        f["ic/vw-dir-deg"] = math.degrees(math.atan2(we, wn)) if mag > 0 else 0.0
        f["ic/vn-fps"] = (vair[0] + wn) / FT
        f["ic/ve-fps"] = (vair[1] + we) / FT
        f["ic/vd-fps"] = (vair[2] + wd) / FT
        f["ic/p-rad_sec"] = st["p"]
        f["ic/q-rad_sec"] = st["q"]
        f["ic/r-rad_sec"] = st["r"]
        with quiet():
            f.run_ic()
        if wd != 0.0:
            # The IC has no vertical wind: set it in the atmosphere and recompute the
            # derivatives without advancing time (a few passes: JSBSim's alpha-dot sees the
            # jump in alpha between run_ic and the first pass and settles after the next).
            f["atmosphere/wind-north-fps"] = wn / FT
            f["atmosphere/wind-east-fps"] = we / FT
            f["atmosphere/wind-down-fps"] = wd / FT
            f.suspend_integration()
            for _ in range(4):
                f.run()
            f.resume_integration()
        got = (f["velocities/vt-fps"] * FT, f["aero/alpha-rad"], f["aero/beta-rad"])
        want = (st["va"], st["alpha"], st["beta"])
        if abs(got[0] - want[0]) > 1e-6 * want[0] + 1e-6 or max(
                abs(got[1] - want[1]), abs(got[2] - want[2])) > 1e-7:
            raise RuntimeError(f"restart did not reproduce the air data: {got} vs {want}")

    # ---------------------------------------------------------------- forces
    def cg_to_rp_body(self):
        """Vector from CG to the aero reference point in body FRD axes, m.

        Structural frame: x aft, y right, z up (inches)."""
        f = self.fdm
        rp = as_vec(self.fdm.get_aircraft().get_xyz_rp())
        cg = [f["inertia/cg-x-in"], f["inertia/cg-y-in"], f["inertia/cg-z-in"]]
        return [-(rp[0] - cg[0]) * IN, (rp[1] - cg[1]) * IN, -(rp[2] - cg[2]) * IN]

    def aero_fm(self, remove_alphadot: bool = True):
        """Aerodynamic force (N, body) and moment about the CG (N m, body).

        With remove_alphadot, the alpha-dot terms (CLadot: lift at the aero reference point;
        Cmadot: pitching moment) are subtracted, so that finite differences of states set by
        run_ic (which come with the alpha-dot of the new state's accelerations) see only the
        static and rate derivatives."""
        f = self.fdm
        F = [f["forces/fbx-aero-lbs"] * LBF, f["forces/fby-aero-lbs"] * LBF,
             f["forces/fbz-aero-lbs"] * LBF]
        M = [f["moments/l-aero-lbsft"] * LBF_FT, f["moments/m-aero-lbsft"] * LBF_FT,
             f["moments/n-aero-lbsft"] * LBF_FT]
        if remove_alphadot:
            lift_ad = f["aero/coefficient/CLadot"] * LBF
            m_ad = f["aero/coefficient/Cmadot"] * LBF_FT
            tw2b = as_list(self.fdm.get_auxiliary().get_Tw2b())
            Fad = mat_vec(tw2b, [0.0, 0.0, -lift_ad])
            r = self.cg_to_rp_body()
            Mad = [r[1] * Fad[2] - r[2] * Fad[1], r[2] * Fad[0] - r[0] * Fad[2] + m_ad,
                   r[0] * Fad[1] - r[1] * Fad[0]]
            F = [F[i] - Fad[i] for i in range(3)]
            M = [M[i] - Mad[i] for i in range(3)]
        return F, M

    def prop_fm(self):
        f = self.fdm
        F = [f["forces/fbx-prop-lbs"] * LBF, f["forces/fby-prop-lbs"] * LBF,
             f["forces/fbz-prop-lbs"] * LBF]
        M = [f["moments/l-prop-lbsft"] * LBF_FT, f["moments/m-prop-lbsft"] * LBF_FT,
             f["moments/n-prop-lbsft"] * LBF_FT]
        return F, M

    def mass_props(self) -> dict:
        """Mass (kg) and inertia about the CG in Beard & McLain's convention (kg m^2)."""
        f = self.fdm
        return dict(
            mass_kg=f["inertia/mass-slugs"] * SLUG,
            jx=f["inertia/ixx-slugs_ft2"] * SLUG_FT2,
            jy=f["inertia/iyy-slugs_ft2"] * SLUG_FT2,
            jz=f["inertia/izz-slugs_ft2"] * SLUG_FT2,
            # JSBSim: ixz = -integral(xz dm) in the structural frame (x aft, z up), which
            # equals -integral(xz dm) in body FRD (both axes flip). B&M: Jxz = +integral(xz dm).
            jxz=-f["inertia/ixz-slugs_ft2"] * SLUG_FT2,
            # Not representable in Beard & McLain (reported only): +integral(xy dm) and
            # +integral(yz dm) in body axes (one axis flips: the sign of -ixy/-iyz flips back).
            jxy=f["inertia/ixy-slugs_ft2"] * SLUG_FT2,
            jyz=f["inertia/iyz-slugs_ft2"] * SLUG_FT2,
            cg_in=(f["inertia/cg-x-in"], f["inertia/cg-y-in"], f["inertia/cg-z-in"]),
        )

    # ---------------------------------------------------------------- flat frame output
    def set_origin(self) -> dict:
        """Make the current position the origin of the flat NED tangent frame."""
        f = self.fdm
        prop = f.get_propagate()
        tec2b = as_list(prop.get_Tec2b())
        tl2b = as_list(prop.get_Tl2b())
        self.frame0 = dict(
            r_ec2n0=mat_mul(transpose(tl2b), tec2b),  # ECEF -> local NED at the origin
            p0=[f["position/ecef-x-ft"] * FT, f["position/ecef-y-ft"] * FT,
                f["position/ecef-z-ft"] * FT],
            lat=f["position/lat-geod-deg"], lon=f["position/long-gc-deg"],
            alt=f["position/geod-alt-ft"] * FT,
        )
        return self.frame0

    def sample(self) -> dict:
        """Current state in the flat tangent frame at the origin (SI units, radians)."""
        f = self.fdm
        fr = self.frame0
        prop = f.get_propagate()
        tec2b = as_list(prop.get_Tec2b())
        r_b2n0 = mat_mul(fr["r_ec2n0"], transpose(tec2b))
        p = [f["position/ecef-x-ft"] * FT, f["position/ecef-y-ft"] * FT,
             f["position/ecef-z-ft"] * FT]
        ned = mat_vec(fr["r_ec2n0"], [p[i] - fr["p0"][i] for i in range(3)])
        uvw = [f["velocities/u-fps"] * FT, f["velocities/v-fps"] * FT,
               f["velocities/w-fps"] * FT]  # ECEF-relative velocity, body axes
        vned = mat_vec(r_b2n0, uvw)
        phi, theta, psi = dcm_to_euler(r_b2n0)
        de, da, dr = self.surfaces()
        return dict(
            t=f.get_sim_time(), north=ned[0], east=ned[1], down=ned[2],
            phi=phi, theta=theta, psi=psi, vn=vned[0], ve=vned[1], vd=vned[2],
            p=f["velocities/p-rad_sec"], q=f["velocities/q-rad_sec"],
            r=f["velocities/r-rad_sec"], va=f["velocities/vt-fps"] * FT,
            alpha=f["aero/alpha-rad"], beta=f["aero/beta-rad"],
            throttle=f["fcs/throttle-cmd-norm"], de=de, da=da, dr=dr,
        )


def air_state_ic(sim: C172P, base: dict, va=None, alpha=None, beta=None, p=None, q=None,
                 r=None) -> None:
    """Put the aircraft (still air) into an air-relative state for a finite difference:
    attitude and position of `base`, body velocity from (va, alpha, beta), rates (p, q, r)."""
    va = base["va"] if va is None else va
    alpha = base["alpha"] if alpha is None else alpha
    beta = base["beta"] if beta is None else beta
    st = dict(base)
    st.update(
        u=va * math.cos(alpha) * math.cos(beta), v=va * math.sin(beta),
        w=va * math.sin(alpha) * math.cos(beta), va=va, alpha=alpha, beta=beta,
        p=base["p"] if p is None else p, q=base["q"] if q is None else q,
        r=base["r"] if r is None else r,
    )
    sim.restart(st)
