"""The bench file of the live bench station (``metro-bench/1``, format in docs/instruments.md):
the driver and its constructor arguments for each role, the device under test, environment and
site, and the lab's calibration data of each piece of equipment.  :func:`load_bench` checks all of
it and names file, field and reason on any problem; nothing is opened or moved here.
"""

from __future__ import annotations

import inspect
import math
from pathlib import Path
from typing import Any, Mapping, Sequence

import attrs
import pint

from metro.core.base.errors import DataError, DriverError, MetroError
from metro.core.model.campaign import Calibration, DeviceUnderTest, Equipment
from metro.core.base.units import parse_quantity, unit

__all__ = ["BENCH_FORMAT", "DriverSpec", "OutputSpec", "BenchConfig", "flag_value", "load_bench"]

BENCH_FORMAT = "metro-bench/1"


@attrs.frozen
class DriverSpec:
    """One driver of the bench: the registered ``name``, its ``kind`` and class, and the
    constructor arguments from the bench file (``where`` names the table, e.g. ``rate_table``)."""

    where: str
    name: str
    kind: str
    cls: type
    args: Mapping[str, Any]

    def open(self) -> Any:
        """Construct (connect) the driver; a failure that is not a DriverError is wrapped into
        one."""
        try:
            return self.cls(**dict(self.args))
        except MetroError:
            raise
        except Exception as exc:  # a driver's own error type: name the role and the driver
            raise DriverError(
                str(self.args.get("resource") or self.args.get("port") or self.name),
                "open",
                f"driver {self.name!r} ({self.where}) failed to open: {type(exc).__name__}: {exc}",
            ) from exc


@attrs.frozen
class OutputSpec:
    """How the output is recorded into each segment: the column and its unit; for a DMM its
    range and integration time; for a frame stream the field, how frames become samples and
    the frame period."""

    driver: DriverSpec
    column: str
    unit: str | None
    range: pint.Quantity | None = None
    nplc: float = 10.0
    field: str | None = None
    aggregate: str = "mean"
    frame_interval: pint.Quantity | None = None
    allow_unclean: bool = False
    equipment: Equipment | None = None


@attrs.frozen
class BenchConfig:
    """A checked bench file."""

    source: str
    id: str
    device: DeviceUnderTest
    environment: Mapping[str, Any]
    site: Mapping[str, Any]
    table: DriverSpec
    table_axis: int
    table_role: str | None
    table_calibration: Calibration | None
    output: OutputSpec
    orientation: str
    settle_timeout: pint.Quantity
    equipment: tuple[Equipment, ...]


_TOP = {"format", "bench", "device", "environment", "site", "rate_table", "output", "equipment"}
_BENCH_KEYS = {"id", "orientation", "settle_timeout"}
_TABLE_KEYS = {"driver", "args", "axis", "role", "calibration"}
#: the keys of every [output]: its driver, the instrument it is, and the column it writes
_OUTPUT_KEYS = {"driver", "args", "id", "role", "model", "manufacturer", "serial", "column", "unit",
                "calibration", "properties"}
_DMM_KEYS = _OUTPUT_KEYS | {"range", "nplc"}
_GYRO_KEYS = _OUTPUT_KEYS | {"field", "aggregate", "allow_unclean"}


def _sub(doc: Mapping[str, Any], key: str, src: str, *, required: bool = True) -> Mapping[str, Any]:
    v = doc.get(key)
    if v is None:
        if required:
            raise DataError(
                src,
                f"[{key}]",
                "missing table",
                hint=f"add a [{key}] table (docs/instruments.md, Bench station)",
            )
        return {}
    if not isinstance(v, dict):
        raise DataError(src, key, f"must be a table, got {type(v).__name__}")
    return v


def _unknown(t: Mapping[str, Any], allowed: set[str], src: str, where: str) -> None:
    bad = sorted(set(t) - allowed)
    if bad:
        raise DataError(
            src,
            f"{where}.{bad[0]}",
            f"unknown key{'s' if len(bad) > 1 else ''} "
            f"{', '.join(bad)}; [{where}] takes {', '.join(sorted(allowed))}",
        )


def _text(t: Mapping[str, Any], key: str, src: str, where: str, default: str | None = None) -> str:
    v = t.get(key, default)
    if v is None:
        raise DataError(src, f"{where}.{key}", "missing", hint=f'add {key} = "…" to [{where}]')
    if not isinstance(v, str) or not v.strip():
        raise DataError(src, f"{where}.{key}", f"must be non-empty text, got {v!r}")
    return v.strip()


def flag_value(v: Any, src: str, field: str) -> bool:
    """A yes/no setting: a TOML boolean or one of true/yes/1/on, false/no/0/off (else a
    DataError)."""
    if isinstance(v, bool):
        return v
    if isinstance(v, str) and v.strip().lower() in (
        "true",
        "yes",
        "1",
        "on",
        "false",
        "no",
        "0",
        "off",
    ):
        return v.strip().lower() in ("true", "yes", "1", "on")
    if isinstance(v, int) and v in (0, 1):
        return bool(v)
    raise DataError(src, field, f"must be true or false, got {v!r}")


def _driver(
    t: Mapping[str, Any], where: str, kinds: Sequence[str], drivers: Mapping[str, Any], src: str
) -> DriverSpec:
    name = _text(t, "driver", src, where)
    if name not in drivers:
        avail = ", ".join(f"{n} ({d.kind})" for n, d in sorted(drivers.items())) or "none"
        raise DataError(
            src,
            f"{where}.driver",
            f"no driver {name!r} is registered; registered drivers: {avail}",
            hint="`metro plugins` lists the drivers and their plugins; "
            "a vendor's driver comes with "
            "its plugin",
        )
    info = drivers[name]
    if info.kind not in kinds:
        raise DataError(
            src,
            f"{where}.driver",
            f"driver {name!r} is a {info.kind!r} driver; [{where}] needs "
            f"{' or '.join(repr(k) for k in kinds)}",
        )
    args = t.get("args", {})
    if not isinstance(args, dict):
        raise DataError(
            src, f"{where}.args", f"must be a table of the driver's arguments, got {args!r}"
        )
    try:
        inspect.signature(info.cls).bind(**args)
    except TypeError as exc:
        try:
            sig = str(inspect.signature(info.cls))
        except (TypeError, ValueError):  # pragma: no cover - builtins without a signature
            sig = "(…)"
        raise DataError(
            src,
            f"{where}.args",
            f"driver {name!r} ({info.cls.__name__}{sig}) cannot take these arguments: {exc}",
        ) from exc
    return DriverSpec(where, name, info.kind, info.cls, dict(args))


def _equipment_of(
    t: Mapping[str, Any], where: str, default_role: str, src: str, *, required: bool
) -> Equipment | None:
    from metro.core.run.manifest import calibration_from_table

    if "id" not in t:
        if required:
            raise DataError(
                src,
                f"{where}.id",
                "missing: the lab's id of this instrument (asset number)",
                hint=f'add id = "DMM-07" to [{where}]',
            )
        return None
    eid = _text(t, "id", src, where)
    cal_t = t.get("calibration")
    if cal_t is None and required:
        raise DataError(
            src,
            f"{where}.calibration",
            "missing: the instrument's calibration data",
            hint=f"add [{where}.calibration] with certificate, U, k and due (the budgets use U)",
        )
    if cal_t is not None and not isinstance(cal_t, dict):
        raise DataError(
            src, f"{where}.calibration", "must be a table (certificate, U, k, due, lab)"
        )
    cal = calibration_from_table(cal_t, src, f"{where}.calibration") if cal_t is not None else None
    props_t = t.get("properties", {})
    if not isinstance(props_t, dict):
        raise DataError(src, f"{where}.properties", 'must be a table of name = "value unit"')
    from metro.core.run.manifest import maybe_quantity

    props = {k: maybe_quantity(v, src, f"{where}.properties.{k}") for k, v in props_t.items()}
    return Equipment(
        id=eid,
        role=_text(t, "role", src, where, default_role),
        model=str(t.get("model", "")),
        manufacturer=str(t.get("manufacturer", "")),
        serial=str(t.get("serial", "")),
        properties=props,
        calibration=cal,
    )


def _output(t: Mapping[str, Any], drivers: Mapping[str, Any], src: str) -> OutputSpec:
    spec = _driver(t, "output", ("dmm", "gyro-output"), drivers, src)
    column = _text(t, "column", src, "output", "output")
    if spec.kind == "dmm":
        _unknown(t, _DMM_KEYS, src, "output")
        unit_text = _text(t, "unit", src, "output", "V")
        try:
            parse_quantity(f"1 {unit_text}", dimension="V", file=src, field="output.unit")
        except DataError as exc:
            raise DataError(
                src, "output.unit", f"a DMM reads volts: {unit_text!r} is not a voltage unit"
            ) from exc
        rng = None
        if "range" in t:
            rng = parse_quantity(t["range"], dimension="V", file=src, field="output.range")
            if not rng.magnitude > 0:
                raise DataError(src, "output.range", f"must be positive, got {t['range']!r}")
        nplc = t.get("nplc", 10.0)
        if (
            isinstance(nplc, bool)
            or not isinstance(nplc, (int, float))
            or not (nplc > 0 and math.isfinite(nplc))
        ):
            raise DataError(
                src, "output.nplc", f"must be a positive number of power-line cycles, got {nplc!r}"
            )
        eq = _equipment_of(t, "output", "dmm", src, required=True)
        return OutputSpec(spec, column, unit_text, range=rng, nplc=float(nplc), equipment=eq)
    _unknown(t, _GYRO_KEYS, src, "output")
    field = _text(t, "field", src, "output")
    unit_text = t.get("unit")
    if unit_text is not None:
        unit_text = _text(t, "unit", src, "output")
        try:
            unit(unit_text)
        except Exception as exc:  # pint raises several types
            raise DataError(
                src, "output.unit", f"not a unit metro can read: {unit_text!r} ({exc})"
            ) from exc
    agg = _text(t, "aggregate", src, "output", "mean")
    if agg not in ("mean", "sum"):
        raise DataError(
            src,
            "output.aggregate",
            f'must be "mean" (a rate output) or "sum" (increments, pulses), got {agg!r}',
        )
    interval = None
    if "interval" in spec.args:
        interval = parse_quantity(
            spec.args["interval"], dimension="s", file=src, field="output.args.interval"
        )
        if not interval.magnitude > 0:
            raise DataError(src, "output.args.interval", "the frame period must be positive")
    allow = flag_value(t.get("allow_unclean", False), src, "output.allow_unclean")
    eq = _equipment_of(t, "output", "acquisition", src, required=False)
    return OutputSpec(
        spec,
        column,
        unit_text,
        field=field,
        aggregate=agg,
        frame_interval=interval,
        allow_unclean=allow,
        equipment=eq,
    )


def load_bench(path: str | Path, drivers: Mapping[str, Any]) -> BenchConfig:
    """Read and check a bench file; ``drivers`` maps registered driver names to their
    :class:`~metro.core.run.plugin_manager.DriverInfo`.  Every problem is a :class:`DataError`
    naming the
    file, the field and the reason; nothing is opened or moved here."""
    from metro.core.run.manifest import (calibration_from_table, device_from_table,
                                         environment_from_table, equipment_from_table, read_toml,
                                         site_from_table)

    p = Path(path)
    src, doc = read_toml(
        p,
        BENCH_FORMAT,
        what="bench file",
        hint="give its path with --station-option config=bench.toml (docs/instruments.md)",
    )
    _unknown(doc, _TOP, src, "bench file")

    b = _sub(doc, "bench", src, required=False)
    _unknown(b, _BENCH_KEYS, src, "bench")
    bench_id = _text(b, "id", src, "bench", p.stem)
    orientation = _text(b, "orientation", src, "bench", "IRA up")
    settle = parse_quantity(
        b.get("settle_timeout", "120 s"), dimension="s", file=src, field="bench.settle_timeout"
    )
    if not settle.magnitude > 0:
        raise DataError(
            src, "bench.settle_timeout", f"must be positive, got {b.get('settle_timeout')!r}"
        )

    device = device_from_table(_sub(doc, "device", src), src)
    environment = environment_from_table(_sub(doc, "environment", src), src)
    site = site_from_table(_sub(doc, "site", src), src)

    rt = _sub(doc, "rate_table", src)
    _unknown(rt, _TABLE_KEYS, src, "rate_table")
    table = _driver(rt, "rate_table", ("rate-table",), drivers, src)
    axis = rt.get("axis", 1)
    if isinstance(axis, bool) or not isinstance(axis, int) or axis < 1:
        raise DataError(src, "rate_table.axis", f"must be a whole number from 1, got {axis!r}")
    role = _text(rt, "role", src, "rate_table") if "role" in rt else None
    cal_t = rt.get("calibration")
    if cal_t is not None and not isinstance(cal_t, dict):
        raise DataError(
            src, "rate_table.calibration", "must be a table (certificate, U, k, due, lab)"
        )
    table_cal = (
        calibration_from_table(cal_t, src, "rate_table.calibration") if cal_t is not None else None
    )

    output = _output(_sub(doc, "output", src), drivers, src)

    eq_list = doc.get("equipment", [])
    if not isinstance(eq_list, list):
        raise DataError(src, "equipment", "must be an array of tables ([[equipment]])")
    equipment = tuple(
        equipment_from_table(e, src, f"equipment[{i}]") for i, e in enumerate(eq_list)
    )
    ids = [e.id for e in equipment] + ([output.equipment.id] if output.equipment else [])
    dup = sorted({i for i in ids if ids.count(i) > 1})
    if dup:
        raise DataError(src, "equipment", f"duplicate equipment id(s) {', '.join(dup)}")
    return BenchConfig(
        src,
        bench_id,
        device,
        environment,
        site,
        table,
        axis,
        role,
        table_cal,
        output,
        orientation,
        settle,
        equipment,
    )
