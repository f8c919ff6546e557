"""A sample third-party plugin: a vendor standard with one item, a unit, a rate-table driver,
lifecycle listeners.

Used by tests/core/run/test_plugins.py; it implements every hook so each hook has a test.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from metro.core import hookimpl
from metro.core.uncertainty.budget import BudgetRow, UncertaintyBudget
from metro.core.model.results import Metric, Outcome, Result
from metro.core.model.procedure import Procedure, SegmentRequirement, Step
from metro.core.base.errors import DriverError
from metro.core.base.units import Q_, parse_quantity
from metro.instruments.drivers.base import Identity, RateTableDriver
from metro.instruments.equipment import RateTable

EVENTS: list[tuple[str, Any]] = []


class MeanOutput(Procedure):
    """Vendor item V.1: mean of the output, in °/h (for rate-output devices)."""

    standard = "vendorx"
    item = "V.1"
    title = "Mean output"
    clause = "V.1"
    metrics = (Metric("mean", "mean output", "ω̄", "deg/h", "V.1", "V-1"),)
    requires = (SegmentRequirement("static", "any static record", columns={"output": ("deg/h",)}),)

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return [Step("static", "static", "record", Q_(10, "min"), Q_(1, "s"),
                     {"orientation": "IRA up"})]

    def evaluate(self, campaign, ctx) -> Outcome:
        seg = campaign.find_segments("static")[0]
        s = seg.series("output", "deg/h")
        x = np.asarray(s.data.to("deg/h").magnitude)
        u = float(np.std(x, ddof=1) / np.sqrt(x.size))
        b = UncertaintyBudget("mean", "deg/h", [BudgetRow.type_a("scatter", "s/√n", Q_(u, "deg/h"),
                                                                 x.size - 1)])
        r = Result(self.metrics[0], Q_(float(np.mean(x)), "deg/h"), b.combined, b)
        return Outcome(self.standard, self.item, self.title, self.clause, [r], segments=[seg.id])


def _read_vendor(path, **kw):  # pragma: no cover - registration only
    raise NotImplementedError


@hookimpl
def metro_unit_definitions():
    return ["vendor_tick = 0.5 * arcsecond = vtick"]


@hookimpl
def metro_register_standards(registrar):
    registrar.add_standard("vendorx", "Vendor X internal procedures", designation="VX-001")
    registrar.add_procedure(MeanOutput)
    registrar.add_series("vendorx", "all-means", ["V.1", "V.2"], "V.1, and V.2 once it exists")


@hookimpl
def metro_register_readers(registrar):
    registrar.add_reader((".vxb",), _read_vendor, "Vendor X binary")


@hookimpl
def metro_register_stations(registrar):
    registrar.add_station("vendorx-bench", lambda **kw: None,
                          "Vendor X bench (not connected in tests)")


class AcmeRateTableDriver(RateTableDriver):
    """Vendor X's rate-table driver, as a vendor writes one (see docs/instruments.md).

    The controller here is simulated: an ``equipment.RateTable`` model turns at the set rate with
    its band's error and integrates the angle between calls.  A real driver sends the same
    requests over the vendor's protocol (serial, TCP, an SDK) and parses the replies.
    """

    def __init__(self, address: str = "sim://acme-rt", *, seed: int = 1):
        self.resource = address
        self.model = RateTable(id="ACME-RT-300", model="ACME RT-300", manufacturer="ACME",
                               serial="42",
                               certificate="ACME-CAL-2031", U=Q_(2e-5, ""), seed=seed)
        self._rate = 0.0
        self._angle = 0.0
        self._t = time.monotonic()
        self._open = True

    def _advance(self) -> None:
        now = time.monotonic()
        self._angle += self._actual() * (now - self._t)
        self._t = now

    def _actual(self) -> float:
        if self._rate == 0.0:
            return 0.0
        return self._rate * (1.0 + self.model.systematic_error(Q_(self._rate, "deg/s")))

    def _check(self, axis: int) -> None:
        if not self._open:
            raise DriverError(self.resource, None, "the connection is closed")
        if axis != 1:
            raise DriverError(self.resource, "axis", f"the RT-300 has one axis, not axis {axis}")

    def identify(self) -> Identity:
        return Identity("ACME", "RT-300", "42", "3.1")

    def set_rate(self, rate, *, axis=1):
        self._check(axis)
        self._advance()
        r = parse_quantity(rate, dimension="deg/s", field="rate")
        self.model.band(r)  # refuses a rate beyond the table's range
        self._rate = float(r.to("deg/s").magnitude)

    def move_to(self, angle, *, axis=1):
        self._check(axis)
        self._rate = 0.0
        self._angle = float(parse_quantity(angle, dimension="deg",
                                           field="angle").to("deg").magnitude)
        self._t = time.monotonic()

    def stop(self, *, axis=None):
        self._advance()
        self._rate = 0.0

    def rate(self, *, axis=1):
        self._check(axis)
        return Q_(self._actual(), "deg/s")

    def angle(self, *, axis=1):
        self._check(axis)
        self._advance()
        return Q_(self._angle % 360.0, "deg")

    def wait_stable(self, timeout, *, axis=1):
        self._check(axis)
        return True

    def equipment(self):
        return self.model.equipment()

    def close(self):
        self._open = False


@hookimpl
def metro_register_drivers(registrar):
    registrar.add_driver("acme-rt300", "rate-table", AcmeRateTableDriver,
                         "ACME RT-300 rate table (simulated)")


@hookimpl
def metro_register_templates(registrar):
    from importlib import resources

    p = Path(str(resources.files("metro.core.documents").joinpath("templates", "report.docx")))
    registrar.add_template("vendorx-report", p, standard="vendorx")


@hookimpl
def metro_item_applicability(procedure, device):
    if procedure.standard != "vendorx":
        return None
    from metro.core.model.procedure import Applicability

    EVENTS.append(("metro_item_applicability", procedure.qualified_id()))
    rate = device is None or device.output in ("", "rate")
    return Applicability(rate, "V.1 reads a rate output" if rate
                         else "V.1 needs a rate-output device")


@hookimpl
def metro_conformity_specifications(standard, campaign):
    if standard != "vendorx":
        return None
    from metro.core.uncertainty.conformity import parse_limit

    EVENTS.append(("metro_conformity_specifications", campaign.id))
    return [parse_limit("mean", "<= 2 deg/h", source="VX-001 limit table")]


@hookimpl
def metro_campaign_loaded(campaign):
    EVENTS.append(("metro_campaign_loaded", campaign.id))


@hookimpl
def metro_procedure_started(procedure, campaign, ctx):
    EVENTS.append(("metro_procedure_started", procedure.qualified_id()))


@hookimpl
def metro_procedure_finished(procedure, outcome):
    EVENTS.append(("metro_procedure_finished", outcome.id))


@hookimpl
def metro_extend_report_context(record, context):
    context["vendorx"] = {"note": "added by sample_vendor"}
    EVENTS.append(("metro_extend_report_context", sorted(context)[:3]))


@hookimpl
def metro_report_written(path, outcomes):
    EVENTS.append(("metro_report_written", str(path)))


@hookimpl
def metro_expected_values(campaign, ideal):
    """The vendor item's expected value from a station's noise-free offset (key ``vendorx:offset``,
    in °/h): what its evaluation gives on an ideal record; None for keys it does not know."""
    if "vendorx:offset" not in ideal:
        return None
    EVENTS.append(("metro_expected_values", campaign.id))
    from metro.api import Q_

    return {"X": Q_(float(ideal["vendorx:offset"]), "deg/h")}


def vendor_tick_in_arcsec() -> list[float]:
    """The vendor's tick (its unit definition) in arcseconds, and 7 ticks."""
    from metro.api import Q_

    return [float(Q_(1, "vtick").to("arcsec").magnitude), float(Q_(7, "vtick").to("arcsec")
                                                                .magnitude)]


@hookimpl
def metro_validation_cases():
    """The vendor's worked example: its tick is ½″ (VX-001 table 1)."""
    from metro.api import ValidationCase

    return [ValidationCase("vendorx:tick", "the vendor tick in arcseconds", "VX-001 table 1",
                           [0.5, 3.5], vendor_tick_in_arcsec, rtol=1e-12,
                           labels=("1 vtick", "7 vtick"), unit="″")]
