"""metro's own validation cases on published reference data: the NIST StRD regression sets
(least squares), the NBS14 Allan statistics, and unit conversions and round trips.

The reference data ship in ``metro/core/validation/data/`` (:func:`data_path`), each file with
its source named: the NIST files as published (``Norris.dat``; ``Pontius.dat`` with its certified
values in a ``#`` header), ``allan_nbs14.json`` with the NBS Monograph 140 values.
"""

from __future__ import annotations

import functools
import json
import re
from importlib import resources
from typing import Any

import numpy as np

from .case import ValidationCase

__all__ = ["allan_cases", "data_path", "nbs14_long_series", "nist_cases", "read_allan_reference",
           "read_norris", "read_pontius", "unit_cases"]

NIST_SOURCE = "NIST/ITL Statistical Reference Datasets (StRD), linear regression, dataset {name}"
_NUM = r"([-+]?\d*\.\d+(?:[EeDd][-+]?\d+)?)"


def data_path(name: str) -> Any:
    """The shipped reference data file ``name`` (an importlib resource, readable as a path)."""
    return resources.files(__package__).joinpath("data", name)


def _num(s: str) -> float:
    return float(s.replace("D", "E"))


@functools.cache
def read_norris() -> tuple[dict[str, float], np.ndarray, np.ndarray]:
    """Norris.dat as NIST publishes it: (certified values, x, y); data from line 61 (y x)."""
    lines = data_path("Norris.dat").read_text().splitlines()
    text = "\n".join(lines[:60])
    b0 = re.search(rf"^\s*B0\s+{_NUM}\s+{_NUM}", text, re.MULTILINE)
    b1 = re.search(rf"^\s*B1\s+{_NUM}\s+{_NUM}", text, re.MULTILINE)
    rsd = re.search(rf"Residual\s*\n\s*Standard Deviation\s+{_NUM}", text)
    r2 = re.search(rf"R-Squared\s+{_NUM}", text)
    if not (b0 and b1 and rsd and r2):
        raise ValueError("Norris.dat: the certified values are not where NIST prints them")
    cert = {"B0": _num(b0.group(1)), "sdB0": _num(b0.group(2)), "B1": _num(b1.group(1)),
            "sdB1": _num(b1.group(2)), "rsd": _num(rsd.group(1)), "r2": _num(r2.group(1))}
    data = np.array([[float(v) for v in ln.split()] for ln in lines[60:] if ln.strip()])
    return cert, data[:, 1], data[:, 0]


@functools.cache
def read_pontius() -> tuple[dict[str, float], np.ndarray, np.ndarray]:
    """Pontius.dat (the certified values in a ``#`` header): (certified values, x, y)."""
    text = data_path("Pontius.dat").read_text()
    cert = {}
    for k, est, sd in re.findall(r"^#\s*B(\d)\s+(\S+)\s+(\S+)", text, re.MULTILINE):
        cert[f"B{k}"] = _num(est)
        cert[f"sdB{k}"] = _num(sd)
    cert["rss"] = _num(re.search(r"residual sum of squares\s+(\S+)", text).group(1))
    rows = [ln.split() for ln in text.splitlines() if ln.strip() and not ln.startswith("#")]
    data = np.array(rows, dtype=float)
    return cert, data[:, 1], data[:, 0]


def _norris() -> list[float]:
    from ..stats.lsq import fit_line

    _, x, y = read_norris()
    fit = fit_line(x, y)
    return [*fit.coef, *fit.stderr, fit.residual_sd, fit.r2]


def _pontius() -> list[float]:
    from ..stats.lsq import fit_polynomial

    _, x, y = read_pontius()
    fit = fit_polynomial(x, y, 2)
    return [*fit.coef, *fit.stderr, fit.ssr]


def nist_cases() -> list[ValidationCase]:
    """NIST StRD Norris (straight line, certified to 15 digits; 1e-12 relative) and Pontius
    (quadratic, badly scaled; 1e-9 relative) through :mod:`metro.core.stats.lsq`."""
    cn, _, _ = read_norris()
    cp, _, _ = read_pontius()
    return [
        ValidationCase(
            "nist:norris", "least squares straight line (fit_line), 36 points",
            NIST_SOURCE.format(name="Norris") + ", certified values (Norris.dat)",
            [cn["B0"], cn["B1"], cn["sdB0"], cn["sdB1"], cn["rsd"], cn["r2"]], _norris,
            rtol=1e-12, labels=("B0", "B1", "s(B0)", "s(B1)", "residual SD", "R²")),
        ValidationCase(
            "nist:pontius", "least squares quadratic (fit_polynomial), 40 points, x up to 3×10⁶",
            NIST_SOURCE.format(name="Pontius") + ", certified values (Pontius.dat)",
            [cp["B0"], cp["B1"], cp["B2"], cp["sdB0"], cp["sdB1"], cp["sdB2"], cp["rss"]],
            _pontius, rtol=1e-9,
            labels=("B0", "B1", "B2", "s(B0)", "s(B1)", "s(B2)", "residual SS")),
    ]


@functools.cache
def read_allan_reference() -> dict[str, Any]:
    """allan_nbs14.json: the NBS14 data and their published deviations."""
    return json.loads(data_path("allan_nbs14.json").read_text(encoding="utf-8"))


def nbs14_long_series(spec: dict[str, Any] | None = None) -> np.ndarray:
    """The 1000-point NBS14 series: n₀ = seed, n_{i+1} = a·n_i mod m, values n_i/m."""
    spec = spec or read_allan_reference()["long"]
    n, a, m = spec["seed"], spec["multiplier"], spec["modulus"]
    out = np.empty(spec["count"])
    for i in range(out.size):
        out[i] = n / m
        n = (a * n) % m
    return out


def _allan(which: str, stat: str) -> list[float]:
    from ..stats import allan

    spec = read_allan_reference()[which]
    y = np.asarray(spec["data"], float) if which == "short" else nbs14_long_series(spec)
    fn = {"adev": allan.adev, "oadev": allan.oadev, "mdev": allan.mdev}[stat]
    return list(fn(y, spec["tau0"], spec["m"], engine="numpy").deviation)


def allan_cases() -> list[ValidationCase]:
    """ADEV, OADEV and MDEV of the NBS14 short (9-point) and long (1000-point) series."""
    ref = read_allan_reference()
    out = []
    for which in ("short", "long"):
        spec = ref[which]
        for stat in ("adev", "oadev", "mdev"):
            out.append(ValidationCase(
                f"allan:{stat}-nbs14-{which}", f"{stat.upper()} of the NBS14 {spec['description']}",
                ref["source"], spec[stat], functools.partial(_allan, which, stat),
                rtol=ref["tolerance_rtol"], labels=tuple(f"τ = {m:g} s" for m in spec["m"])))
    return out


#: (value, unit, other unit, the value in the other unit by the definitions named)
CONVERSIONS = (
    (1.0, "deg/h", "deg/s", 1 / 3600, "1 h = 3600 s (SI Brochure table 8)"),
    (1.0, "arcsec", "deg", 1 / 3600, "1″ = (1/60)′ = (1/3600)° (SI Brochure table 8)"),
    (1.0, "deg", "rad", np.pi / 180, "1° = (π/180) rad (SI Brochure table 8)"),
    (1.0, "gn", "m/s^2", 9.80665, "standard gravity 9.80665 m/s² (3rd CGPM, 1901)"),
    (1.0, "deg/h/g", "deg/h/gn", 1.0, "g with other units is standard gravity (metro units.txt)"),
    (1.0, "ppm", "", 1e-6, "1 ppm = 10⁻⁶"),
    (1.0, "deg/h^0.5", "deg/s^0.5", 1 / 60, "√(1 h) = 60 √s"),
    (1.0, "degC", "K", 274.15, "0 °C = 273.15 K (SI Brochure 2.3.1)"),
)


def _convert(value: float, a: str, b: str) -> list[float]:
    from ..base.units import Q_, fmt_unit, unit

    there = Q_(value, unit(a)).to(unit(b))
    back = there.to(unit(a))
    # the unit as metro prints it reads back to the same unit
    if a != "degC" and unit(fmt_unit(unit(a))) != unit(a):
        raise ValueError(f"{fmt_unit(unit(a))!r} does not read back as {a!r}")
    return [float(there.magnitude), float(back.magnitude)]


def unit_cases() -> list[ValidationCase]:
    """Conversions to the defined value and back (:mod:`metro.core.base.units`), and the unit
    text metro prints reading back to the same unit."""
    return [
        ValidationCase(
            f"units:{a}->{b or '1'}", f"{value:g} {a} in {b or 'a plain number'} and back", source,
            [expected, value], functools.partial(_convert, value, a, b), rtol=1e-12,
            labels=(f"in {b or '1'}", f"back in {a}"))
        for value, a, b, expected, source in CONVERSIONS
    ]
