"""A changed c172p: scaled aerodynamic coefficients and a payload at the CG (docs/jsbsim.md).

Used by fly.py and c172p_params.py (`--scale NAME=F`, `--payload-kg KG`). The package's
aircraft is never touched: the changed aircraft lives in a JSBSim root of its own (a temporary
folder) that holds a copy of `aircraft/c172p/` and links to the package's `engine/` and
`systems/`; load it with `C172P(root=...)`.

* `--scale NAME=F` wraps the body of `<function name="aero/coefficient/NAME">` in
  `<product><value>F</value> ... </product>`. NAME is matched without regard to case
  (`Clda` finds `ClDa`). After building, `check_scales` loads the changed and the unchanged
  aircraft, puts both into the same state, where every `<property>` input of each scaled
  function is non-zero (a table's lookup variable may be zero) and the coefficient itself is
  non-zero, and requires
  `aero/coefficient/NAME` to be F times the original (relative 1e-9) and every other
  `aero/coefficient/*` to be unchanged; anything else raises.
* `--payload-kg KG` adds `<pointmass name="Payload">` of KG (written in lb) at the CG of the
  loaded aircraft (`inertia/cg-{x,y,z}-in` after the IC): the mass grows by KG and the CG and
  the moments of inertia about the CG stay as they were (checked after loading; raises
  otherwise).
"""

from __future__ import annotations

import atexit
import math
import os
import re
import shutil
import tempfile

import jsbsim

from c172p_sim import C172P, LBF, G0, quiet  # noqa: F401

LB = LBF / G0  # kg per pound (mass): 0.45359237
AIRCRAFT = "c172p"


def package_root() -> str:
    return jsbsim.get_default_root_dir()


def xml_path(root: str | None = None) -> str:
    return os.path.join(root or package_root(), "aircraft", AIRCRAFT, AIRCRAFT + ".xml")


def parse_scale(text: str) -> tuple[str, float]:
    """'Clda=0.75' -> ('Clda', 0.75)."""
    if "=" not in text:
        raise ValueError(f"--scale wants NAME=FACTOR, got {text!r}")
    name, val = text.split("=", 1)
    name = name.strip()
    if name.startswith("aero/coefficient/"):
        name = name[len("aero/coefficient/"):]
    f = float(val)
    if not math.isfinite(f) or f == 1.0:
        raise ValueError(f"--scale {name}: factor must be finite and not 1 (got {val})")
    return name, f


def coefficient_names(xml_text: str) -> list[str]:
    return re.findall(r'<function\s+name="aero/coefficient/([^"]+)"', xml_text)


def resolve_name(xml_text: str, name: str) -> str:
    """The XML's exact spelling of a coefficient name (case-insensitive match)."""
    names = coefficient_names(xml_text)
    hits = [n for n in names if n.lower() == name.lower()]
    if len(hits) != 1:
        raise ValueError(f"no single aero/coefficient/{name} in {AIRCRAFT}.xml "
                         f"(have: {', '.join(names)})")
    return hits[0]


def function_span(xml_text: str, name: str) -> tuple[int, int, int]:
    """(start of the function tag, start of its body, start of </function>)."""
    m = re.search(r'<function\s+name="aero/coefficient/' + re.escape(name) + r'"\s*>', xml_text)
    if not m:
        raise ValueError(f"aero/coefficient/{name} not found")
    end = xml_text.index("</function>", m.end())
    if "<function" in xml_text[m.end():end]:
        raise ValueError(f"aero/coefficient/{name} has a nested <function>: not supported")
    body_start = m.end()
    d = re.match(r"\s*<description>.*?</description>", xml_text[body_start:end], re.S)
    if d:
        body_start += d.end()
    return m.start(), body_start, end


def function_inputs(xml_text: str, name: str, tables: bool = True) -> list[str]:
    """Properties the function reads: <property> and (tables=True) table <independentVar>."""
    _, b, e = function_span(xml_text, name)
    body = xml_text[b:e]
    props = re.findall(r"<property>\s*([^<\s]+)\s*</property>", body)
    if tables:
        props += re.findall(r"<independentVar[^>]*>\s*([^<\s]+)\s*</independentVar>", body)
    out = []
    for p in props:
        if p not in out:
            out.append(p)
    return out


def scale_function(xml_text: str, name: str, factor: float) -> str:
    _, b, e = function_span(xml_text, name)
    body = xml_text[b:e].rstrip()
    wrapped = (f"\n                <product>\n                <value>{factor!r}</value>"
               f"{body}\n                </product>\n            ")
    return xml_text[:b] + wrapped + xml_text[e:]


def cg_in(root: str | None = None) -> tuple[float, float, float]:
    """CG of the loaded aircraft (structural frame, inches) after an IC."""
    sim = C172P(root=root)
    with quiet():
        sim.fdm.run_ic()
    return (sim["inertia/cg-x-in"], sim["inertia/cg-y-in"], sim["inertia/cg-z-in"])


def add_payload(xml_text: str, kg: float, cg: tuple[float, float, float]) -> str:
    lb = kg / LB
    pm = (f'    <pointmass name="Payload">\n'
          f'            <weight unit="LBS"> {lb!r} </weight>\n'
          f'            <location unit="IN">\n'
          f'                <x> {cg[0]!r} </x>\n'
          f'                <y> {cg[1]!r} </y>\n'
          f'                <z> {cg[2]!r} </z>\n'
          f'            </location>\n'
          f'        </pointmass>\n    ')
    i = xml_text.index("</mass_balance>")
    return xml_text[:i] + pm + xml_text[i:]


class Variant:
    """A changed c172p: scales {name: factor} (names as the XML spells them), payload kg."""

    def __init__(self, scales=None, payload_kg: float = 0.0):
        self.scales = dict(scales or {})
        self.payload_kg = float(payload_kg)
        self.root = None
        self.payload_root = None
        self.cg = None

    @property
    def changed(self) -> bool:
        return bool(self.scales) or self.payload_kg != 0.0

    def labels(self) -> list[str]:
        """One line per change, e.g. 'ClDa*0.75', 'payload +80 kg at the CG'."""
        out = [f"{n}*{f:g}" for n, f in self.scales.items()]
        if self.payload_kg:
            out.append(f"payload {self.payload_kg:+g} kg at the CG")
        return out

    def describe(self) -> str:
        return ", ".join(self.labels()) if self.changed else "none"

    def build(self) -> str | None:
        """Make the JSBSim root (None when nothing is changed) and check it."""
        if not self.changed:
            return None
        if self.root:
            return self.root
        pkg = package_root()
        with open(xml_path(pkg)) as f:
            text = f.read()
        self.scales = {resolve_name(text, n): v for n, v in self.scales.items()}
        if self.payload_kg:
            self.cg = cg_in(None)
            text = add_payload(text, self.payload_kg, self.cg)
            if self.scales:
                # The reference for the scale check: the same payload, nothing scaled.
                self.payload_root = make_root(text)
        for n, v in self.scales.items():
            text = scale_function(text, n, v)
        root = make_root(text)
        self.root = root
        self.check()
        return root

    # ------------------------------------------------------------------ checks
    def check(self) -> None:
        if self.scales:
            check_scales(self.root, self.scales, self.payload_root)
        if self.payload_kg:
            check_payload(self.payload_root or self.root, self.payload_kg)


def make_root(xml_text: str) -> str:
    """A temporary JSBSim root with aircraft/c172p/c172p.xml = xml_text (removed at exit)."""
    pkg = package_root()
    root = tempfile.mkdtemp(prefix="jsbsim-c172p-variant-")
    atexit.register(shutil.rmtree, root, True)
    shutil.copytree(os.path.join(pkg, "aircraft", AIRCRAFT),
                    os.path.join(root, "aircraft", AIRCRAFT))
    for d in ("engine", "systems", "scripts"):
        if os.path.isdir(os.path.join(pkg, d)):
            os.symlink(os.path.join(pkg, d), os.path.join(root, d))
    with open(xml_path(root), "w") as f:
        f.write(xml_text)
    return root


def _probe_state(sim: C172P) -> None:
    """A state where the usual aerodynamic inputs are all non-zero (still air, 50 m/s,
    alpha 4 deg, beta 3 deg, p q r 0.1/0.05/0.08 rad/s, surfaces 2/3/2 deg, flaps commanded
    10 deg, throttle 0.7); alpha-dot made non-zero by re-running the models twice with
    integration suspended (the state does not move, so both aircraft see the same state)."""
    f = sim.fdm
    va = 50.0 / 0.3048
    a, b = math.radians(4.0), math.radians(3.0)
    f["ic/h-sl-ft"] = 1000.0 / 0.3048
    f["ic/lat-geod-deg"] = 47.4
    f["ic/long-gc-deg"] = 8.5
    f["ic/psi-true-deg"] = 0.0
    f["ic/theta-deg"] = 2.0
    f["ic/phi-deg"] = 5.0
    f["ic/u-fps"] = va * math.cos(a) * math.cos(b)
    f["ic/v-fps"] = va * math.sin(b)
    f["ic/w-fps"] = va * math.sin(a) * math.cos(b)
    f["ic/p-rad_sec"], f["ic/q-rad_sec"], f["ic/r-rad_sec"] = 0.1, 0.05, 0.08
    f["fcs/mixture-cmd-norm"] = 1.0
    sim.command(math.radians(2.0), math.radians(3.0), math.radians(2.0), 0.7)
    f["fcs/flap-cmd-norm"] = 0.33
    with quiet():
        f.run_ic()
        f["propulsion/set-running"] = -1
        f.run_ic()
        f["fcs/flap-pos-deg"] = 10.0
        f.suspend_integration()
        for _ in range(2):
            f.run()
        f.resume_integration()


def _coefficients(sim: C172P, names) -> dict:
    return {n: sim["aero/coefficient/" + n] for n in names}


def check_scales(root: str, scales: dict, ref_root: str | None = None) -> dict:
    """Raise unless aero/coefficient/NAME == F x the original (every input non-zero) and
    every other coefficient is unchanged (except those reading alpha-dot, which follows the
    accelerations and so any scaled force). The original is the package's aircraft, or
    ref_root (the same payload, nothing scaled). Returns {name: (original, changed)}."""
    with open(xml_path(root)) as f:
        text = f.read()
    names = coefficient_names(text)
    base, var = C172P(root=ref_root), C172P(root=root)
    _probe_state(base)
    _probe_state(var)
    out = {}
    for n, fac in scales.items():
        # Every factor of the product must be non-zero (else F x 0 = 0 proves nothing); a
        # table's lookup variable may be 0 (the table's value is then checked to be non-zero).
        for p in function_inputs(text, n, tables=False):
            v = var[p]
            if v == 0.0 or not math.isfinite(v):
                raise RuntimeError(f"cannot check --scale {n}: its input {p} is {v} in the "
                                   "probe state")
        o, c = base["aero/coefficient/" + n], var["aero/coefficient/" + n]
        if o == 0.0 or not math.isclose(c, fac * o, rel_tol=1e-9, abs_tol=0.0):
            raise RuntimeError(f"--scale {n}={fac}: aero/coefficient/{n} is {c!r}, "
                               f"expected {fac} x {o!r} = {fac * o!r}")
        out[n] = (o, c)
    cb, cv = _coefficients(base, names), _coefficients(var, names)
    for n in names:
        if n in scales or any("alphadot" in p for p in function_inputs(text, n)):
            continue
        if not math.isclose(cb[n], cv[n], rel_tol=1e-12, abs_tol=1e-12):
            raise RuntimeError(f"unscaled aero/coefficient/{n} changed: {cb[n]!r} -> {cv[n]!r}")
    return out


def check_payload(root: str, kg: float) -> None:
    base, var = C172P(), C172P(root=root)
    with quiet():
        base.fdm.run_ic()
        var.fdm.run_ic()
    mb, mv = base.mass_props(), var.mass_props()
    # JSBSim converts lb to slug with its own 32.174049 ft/s^2: agreement to ~1e-8.
    if not math.isclose(mv["mass_kg"] - mb["mass_kg"], kg, rel_tol=1e-6, abs_tol=1e-9):
        raise RuntimeError(f"payload: mass {mb['mass_kg']} -> {mv['mass_kg']}, not +{kg} kg")
    for i in range(3):
        if abs(mv["cg_in"][i] - mb["cg_in"][i]) > 1e-9:
            raise RuntimeError(f"payload moved the CG: {mb['cg_in']} -> {mv['cg_in']}")
    for k in ("jx", "jy", "jz", "jxz", "jxy", "jyz"):
        if abs(mv[k] - mb[k]) > 1e-9 * max(1.0, abs(mb[k])):
            raise RuntimeError(f"payload changed {k} about the CG: {mb[k]} -> {mv[k]}")
