"""The live bench station: metro drives a rate table and records a gyro's output.

A bench is composed from registered drivers (``metro_register_drivers``):

* a **rate table** (driver kind ``rate-table``, e.g. a vendor's), commanded per step with
  ``set_rate`` / ``stop`` and ``wait_stable``; it states its own accuracy and calibration with
  ``equipment()``;
* an **output** driver: a ``dmm`` reading an analog gyro's voltage at the step's interval (time
  stamps from the clock), or a ``gyro-output`` reading a digital frame stream (frames averaged,
  or summed, into samples at the step's interval; time from the frame counter).

Its configuration is a TOML *bench file* (``metro acquire … --station bench --station-option
config=bench.toml``, format in docs/instruments.md): the driver and its constructor arguments for
each role, the device under test (the ``[device]`` keys of a campaign manifest), environment and
site, and the lab's calibration data of each piece of equipment.  :func:`load_bench` checks all
of it and names file, field and reason on any problem.

What the bench cannot do by itself — re-mount the device, set a chamber temperature or a field,
power-cycle the device, apply a shock — goes through an *operator* callback (by default: print the
instruction and wait for Enter on a terminal).  Step kinds that need instruments the bench does
not have are refused before anything moves (:meth:`BenchStation.check`).  The table is stopped
and every driver closed on any error and on Ctrl-C; ``metro acquire`` then writes nothing.
"""

from __future__ import annotations

import datetime as dt
import hashlib
import math
import sys
import time
from types import TracebackType
from typing import Any, Callable, Mapping, Protocol, Sequence

import attrs
import numpy as np
import pint

from metro.core.base.errors import DataError, DriverError, MetroError
from metro.core.model.campaign import Campaign, DeviceUnderTest, Equipment, Segment
from metro.core.model.procedure import Step
from metro.core.base.units import parse_quantity

from .bench_file import BENCH_FORMAT, BenchConfig, DriverSpec, OutputSpec, flag_value, load_bench

__all__ = [
    "BENCH_FORMAT",
    "Clock",
    "SystemClock",
    "Operator",
    "terminal_operator",
    "DriverSpec",
    "OutputSpec",
    "BenchConfig",
    "StepPlan",
    "load_bench",
    "BenchStation",
    "bench_station_factory",
    "SUPPORTED_KINDS",
    "UNSUPPORTED_KINDS",
]

Progress = Callable[[str, float, float], None]

# ------------------------------------------------------------------------------ time


class Clock(Protocol):
    """Where the bench gets its time: seconds from a monotonic clock, and a way to wait."""

    def monotonic(self) -> float: ...

    def sleep(self, seconds: float) -> None: ...


@attrs.frozen
class SystemClock:
    """The real clock: :func:`time.monotonic` and :func:`time.sleep`."""

    def monotonic(self) -> float:
        return time.monotonic()

    def sleep(self, seconds: float) -> None:
        if seconds > 0:
            time.sleep(seconds)


# ------------------------------------------------------------------------------ the operator

#: ``operator(instruction, step)`` returns once the operator has done what ``instruction`` says
#: for ``step``; it raises (``KeyboardInterrupt``, a :class:`MetroError`) to abort the run.
Operator = Callable[[str, Step], None]


def terminal_operator(instruction: str, step: Step) -> None:
    """Print the instruction and wait for Enter on the terminal (Ctrl-C aborts the run)."""
    if not _interactive():
        raise MetroError(
            f"step {step.segment!r} ({step.kind}) needs the operator: {instruction}; "
            "metro is not running on a terminal, so nobody can confirm it",
            hint=_ASSUME_READY_HINT,
        )
    print(f"\n[bench] step {step.segment} ({step.kind}): {instruction}", file=sys.stderr)
    input("[bench] press Enter when done (Ctrl-C aborts the run) ")


def _interactive() -> bool:
    try:
        return bool(sys.stdin is not None and sys.stdin.isatty())
    except (AttributeError, ValueError):  # a closed or replaced stdin
        return False


_ASSUME_READY_HINT = (
    "run `metro acquire` from a terminal and confirm each instruction, or, if the bench is set "
    "up for every such step already (or they are automated), pre-confirm them all with "
    "--station-option assume_ready=true"
)

# ------------------------------------------------------------------------------ step kinds

#: step kinds the bench runs: the table turns at the step's ``rate`` (or rests without one)
#: while the output is recorded; other conditions are set up by the operator
SUPPORTED_KINDS: frozenset[str] = frozenset(
    {
        "static",
        "static-zero",
        "rate",
        "rate-output",
        "rate-static",
        "threshold",
        "rate-repeat",
        "static-repeat",
        "rate-temperature",
        "static-temperature",
        "high-temperature",
        "low-temperature",
        "rate-accel",
        "static-accel",
        "static-field",
        "rate-shock",
        "rate-vibration",
        "static-shock",
        "static-vibration",
        "misalignment",
        "rate-mounting",
        "polarity",
    }
)

#: step kinds the bench cannot run at all, and why
UNSUPPORTED_KINDS: Mapping[str, str] = {
    "rate-revolutions": "it counts the output over whole table revolutions timed by the table's "
    "revolution "
    "pulse; the bench has no pulse-counter input",
    "revolutions-mounting": "it counts the output over whole revolutions (revolution pulse, "
    "counter)",
    "revolutions-repeat": "it counts the output over whole revolutions (revolution pulse, counter)",
    "revolutions-temperature": "it counts the output over whole revolutions (revolution pulse, "
    "counter)",
    "angular-vibration": "it needs an angular vibration table and its reference sensor",
    "shock": "it records during a shock pulse (shock machine, fast acquisition)",
    "vibration": "it records during vibration (shaker, fast acquisition)",
    "startup": "it records from the moment of power-on; the bench does not switch the device's "
    "power",
    "power-on": "it records from the moment of power-on; the bench does not switch the device's "
    "power",
    "power": "it needs a voltmeter and an ammeter on the supply",
    "tilt": "it needs a tilt table",
    "position": "it needs a position table and all outputs of a multi-axis IMU; the bench records "
    "one output",
    "positioning": "it reads an angle instrument's output at turntable stops",
    "scale-factor": "it reads an angle instrument's output at turntable stops",
    "zero": "it reads an angle instrument's output at turntable stops",
    "resolution": "it steps the input by small increments around a base rate, which the bench does "
    "not sequence",
}

#: conditions the bench sets itself
_AUTOMATIC = frozenset({"rate"})
#: conditions that only label a step
_LABELS = frozenset({"when"})
#: conditions that say how the device is mounted (a change is an operator step)
_MOUNTING = ("orientation", "axis", "position", "axis_up", "turn")
_SHOCK_KINDS = {
    "rate-shock": "shock",
    "static-shock": "shock",
    "rate-vibration": "vibration",
    "static-vibration": "vibration",
}
_OPERATOR = frozenset(_MOUNTING) | {"temperature", "field", "field_axis", "run", "phase"}


def _norm(v: Any) -> str:
    return " ".join(str(v).split()).casefold()


# ------------------------------------------------------------------------------ planning


@attrs.frozen
class StepPlan:
    """One step as the bench will run it: the table's rate (``None``: at rest), the samples to
    record, and what the operator must do first."""

    step: Step
    rate: pint.Quantity | None
    n: int
    instructions: tuple[str, ...]
    power_cycle: bool = False


def _n_samples(step: Step) -> int:
    n = float((step.duration / step.interval).to("").magnitude)
    return max(1, int(round(n)))


# ------------------------------------------------------------------------------ the station


@attrs.define
class BenchStation:
    """A live bench (registered as station ``bench``).

    :param config: the checked bench file.
    :param clock: where time comes from (default: the system's monotonic clock and sleep).
    :param operator: the operator callback (default: :func:`terminal_operator`).
    :param assume_ready: every operator step is taken as done without asking.
    :param allow_unclean: keep frame records with issues (recorded in the segment's conditions).
    :param warmed_up: the device has warmed up already; steps' warm-up times are not waited.
    """

    config: BenchConfig
    clock: Clock = attrs.field(factory=SystemClock)
    operator: Operator | None = None
    assume_ready: bool = False
    allow_unclean: bool = False
    warmed_up: bool = False

    name = "bench"

    def device(self) -> DeviceUnderTest:
        return self.config.device

    # -- planning -----------------------------------------------------------------------
    def check(
        self, steps: Sequence[Step], *, items: Mapping[str, Sequence[str]] | None = None
    ) -> list[StepPlan]:
        """Check every step before anything is opened or moved and return the plan.

        ``items`` maps segment ids to the items that asked for them (for the error messages).
        Refused: a step kind the bench cannot run, a condition it does not know how to set up, a
        rate that is not a rate, a step interval that is not a whole number of frame periods, and
        operator steps when no operator can answer (no terminal and not ``assume_ready``).
        """
        items = items or {}

        def who(step: Step) -> str:
            its = items.get(step.segment)
            return f" (item {', '.join(its)})" if its else ""

        for step in steps:
            if step.kind in UNSUPPORTED_KINDS or step.kind not in SUPPORTED_KINDS:
                same = [s for s in steps if s.kind == step.kind]
                segs = ", ".join(s.segment for s in same[:4]) + (" …" if len(same) > 4 else "")
                its = sorted({i for s in same for i in items.get(s.segment, ())})
                reason = UNSUPPORTED_KINDS.get(
                    step.kind, "the bench does not know this kind of step"
                )
                raise MetroError(
                    f"the bench cannot run steps of kind {step.kind!r}"
                    f"{' for item ' + ', '.join(its) if its else ''} (segment {segs}): {reason}; "
                    "nothing was commanded",
                    hint=f"the bench runs the kinds {', '.join(sorted(SUPPORTED_KINDS))}; acquire "
                    "the other items on a station that can, or record them and use `metro run "
                    "--data`",
                )
            unknown = sorted(set(step.conditions) - _AUTOMATIC - _OPERATOR - _LABELS)
            if unknown:
                raise MetroError(
                    f"step {step.segment!r} ({step.kind}){who(step)} has condition(s) "
                    f"{', '.join(unknown)} the bench does not know how to set up; nothing was "
                    f"commanded"
                )
            if not (step.interval.magnitude > 0 and step.duration.magnitude > 0):
                raise MetroError(
                    f"step {step.segment!r}{who(step)}: duration and interval must be positive"
                )
        plans: list[StepPlan] = []
        state: dict[str, str | None] = {k: None for k in _OPERATOR}
        state["orientation"] = _norm(self.config.orientation)
        for step in steps:
            rate = None
            if "rate" in step.conditions:
                rate = parse_quantity(
                    step.conditions["rate"],
                    dimension="deg/s",
                    field=f"segments.{step.segment}.conditions.rate",
                )
            self._check_frames(step, who(step))
            instr, cycle = _instructions(step, state)
            plans.append(StepPlan(step, rate, _n_samples(step), tuple(instr), cycle))
        need = [p for p in plans if p.instructions]
        if need and not self.assume_ready and self.operator is None and not _interactive():
            first = need[0]
            more = f" ({len(need) - 1} more step(s) need the operator too)" if len(need) > 1 else ""
            raise MetroError(
                f"step {first.step.segment!r} ({first.step.kind}){who(first.step)} needs the "
                f"operator: {'; '.join(first.instructions)}{more}; "
                "metro is not running on a terminal, so nobody can confirm it; nothing was "
                "commanded",
                hint=_ASSUME_READY_HINT,
            )
        return plans

    def _check_frames(self, step: Step, who: str) -> None:
        fi = self.config.output.frame_interval
        if self.config.output.driver.kind != "gyro-output" or fi is None:
            return
        m = float((step.interval / fi).to("").magnitude)
        if m < 0.999999 or abs(m - round(m)) > 1e-6 * max(1.0, m):
            raise MetroError(
                f"step {step.segment!r}{who} samples every {step.interval:~P}, which is not a "
                f"whole "
                f"number of the gyro's frame periods ({fi:~P}); nothing was commanded",
                hint="set the gyro's output rate so the step interval is a multiple of its frame "
                "period",
            )

    # -- running --------------------------------------------------------------------------
    def acquire(self, steps: list[Step], *, progress: Progress | None = None) -> Campaign:
        """Run ``steps`` on the bench and return the campaign (samples in memory)."""
        plans = self.check(steps)
        cfg = self.config
        clock = self.clock
        operator = self.operator or terminal_operator
        segments: list[Segment] = []
        prompts = 0
        with _Drivers(cfg) as d:
            table, out = d.table, d.output
            if out.kind == "dmm":
                out.driver.configure_dc_voltage(cfg.output.range, nplc=cfg.output.nplc)
            powered_at = -math.inf if self.warmed_up else clock.monotonic()
            for i, plan in enumerate(plans):
                step = plan.step
                if progress is not None:
                    progress(f"bench: {step.segment}", i, len(plans))
                if plan.instructions:
                    # the table rests while the operator works on the bench
                    table.stop(axis=cfg.table_axis)
                    self._settle(table, step, None)
                    if not self.assume_ready:
                        operator("; ".join(plan.instructions), step)
                    prompts += 1
                    if plan.power_cycle:
                        powered_at = clock.monotonic()
                if plan.rate is not None:
                    table.set_rate(plan.rate, axis=cfg.table_axis)
                else:
                    table.stop(axis=cfg.table_axis)
                self._settle(table, step, plan.rate)
                if step.warmup is not None:
                    self._warm_up(step, powered_at, progress)
                if out.kind == "dmm":
                    segments.append(self._record_dmm(out, plan, progress))
                else:
                    segments.append(self._record_frames(out, plan, progress))
            table.stop(axis=cfg.table_axis)
            meta = {
                "bench": cfg.source,
                "bench_id": cfg.id,
                "rate_table": f"{d.table_identity} at {table.resource or cfg.table.name}",
                "output": f"{d.output_identity} at {out.driver.resource or cfg.output.driver.name}",
                "operator_steps": prompts,
            }
            equipment = d.equipment()
        stamp = dt.datetime.now(dt.timezone.utc).strftime("%Y%m%dT%H%M%SZ")
        return Campaign(
            id=f"{cfg.id}-{stamp}",
            device=cfg.device,
            equipment=equipment,
            environment=cfg.environment,
            site=cfg.site,
            segments=segments,
            source=cfg.source,
            simulated=False,
            meta=meta,
        )

    def _settle(self, table: Any, step: Step, rate: pint.Quantity | None) -> None:
        cfg = self.config
        if not table.wait_stable(cfg.settle_timeout, axis=cfg.table_axis):
            what = f"at {rate:~P}" if rate is not None else "at rest"
            raise DriverError(
                table.resource or cfg.table.name,
                f"wait_stable (step {step.segment})",
                f"the table did not settle {what} within {cfg.settle_timeout:~P}; nothing was "
                "recorded",
                hint="check the table (drive enabled, load, limits) or raise [bench] "
                "settle_timeout",
            )

    def _warm_up(self, step: Step, powered_at: float, progress: Progress | None) -> None:
        need = float(step.warmup.to("s").magnitude)
        start = self.clock.monotonic()
        while True:
            left = need - (self.clock.monotonic() - powered_at)
            if left <= 0:
                return
            if progress is not None:
                progress(
                    f"bench: {step.segment} warm-up",
                    self.clock.monotonic() - start,
                    self.clock.monotonic() - start + left,
                )
            self.clock.sleep(min(left, 1.0))

    def _record_dmm(self, out: "_Opened", plan: StepPlan, progress: Progress | None) -> Segment:
        step, n = plan.step, plan.n
        clock, dmm = self.clock, out.driver
        unit_text = self.config.output.unit or "V"
        dt_s = float(step.interval.to("s").magnitude)
        values = np.empty(n, dtype=np.float64)
        stamps = np.empty(n, dtype=np.float64)
        t0 = clock.monotonic()
        for k in range(n):
            slot = t0 + k * dt_s
            now = clock.monotonic()
            if now < slot:
                clock.sleep(slot - now)
                now = clock.monotonic()
            elif now - slot > 0.5 * dt_s:
                raise DriverError(
                    dmm.resource,
                    f"READ? (step {step.segment}, sample {k})",
                    f"the reading is {now - slot:.3g} s late for its slot: the DMM cannot keep up "
                    f"with "
                    f"the step's {dt_s:g} s interval; nothing was written",
                    hint="lower nplc in the bench file's [output] table",
                )
            stamps[k] = now - t0
            reading = dmm.read()
            values[k] = float(
                parse_quantity(reading, dimension="V", field="reading").to(unit_text).magnitude
            )
            if progress is not None:
                progress(f"recording {step.segment}", k + 1, n)
        cols = {
            "time": (np.arange(n, dtype=np.float64) * dt_s, "s"),
            self.config.output.column: (values, unit_text),
            "read_time": (stamps, "s"),
        }
        return _segment(step, dict(step.conditions), cols)

    def _record_frames(self, out: "_Opened", plan: StepPlan, progress: Progress | None) -> Segment:
        step, n = plan.step, plan.n
        spec = self.config.output
        gyro = out.driver
        fi = getattr(gyro, "interval", None) or spec.frame_interval
        if fi is None:
            raise DataError(
                self.config.source,
                "output.args.interval",
                f'driver {spec.driver.name!r} does not say its frame period; give interval = "…"',
            )
        m = int(round(float((step.interval / fi).to("").magnitude)))
        if m < 1 or abs(float((step.interval / fi).to("").magnitude) - m) > 1e-6 * m:
            raise MetroError(
                f"step {step.segment!r} samples every {step.interval:~P}, not a whole number of "
                f"the "
                f"gyro's frame periods ({fi:~P})"
            )
        if progress is not None:
            progress(f"recording {step.segment}", 0, n)
        gyro.restart()
        rec = gyro.read(n * m)
        if spec.field not in rec.columns:
            raise DataError(
                self.config.source,
                "output.field",
                f"the frames have no field {spec.field!r}; fields: {', '.join(rec.columns)}",
            )
        clean = not rec.issues
        if not clean and not (spec.allow_unclean or self.allow_unclean):
            raise DriverError(
                gyro.resource,
                f"frames (step {step.segment})",
                "the record is not clean: " + "; ".join(rec.warnings) + "; nothing was written",
                hint="re-acquire (check cable, termination, baud rate), or keep such records with "
                "their issues written into the segment: allow_unclean = true in [output] or "
                "--station-option allow_unclean=true",
            )
        q = rec.columns[spec.field]
        unit_text = spec.unit or f"{q.units:D}" or "1"
        try:
            x = np.asarray(q.to(unit_text).magnitude, dtype=np.float64)
        except pint.DimensionalityError as exc:
            raise DataError(
                self.config.source,
                "output.unit",
                f"the field {spec.field!r} is in {q.units:~P}, which cannot be given in "
                f"{unit_text}",
            ) from exc
        window = np.asarray(rec.counter, dtype=np.int64) // m
        keep = window < n
        counts = np.bincount(window[keep], minlength=n)[:n]
        if np.any(counts == 0):
            k = int(np.flatnonzero(counts == 0)[0])
            raise DriverError(
                gyro.resource,
                f"frames (step {step.segment}, sample {k})",
                f"every frame of sample {k} is missing: a sample cannot be made from nothing; "
                + "; ".join(rec.warnings),
                hint="re-acquire",
            )
        if spec.aggregate == "sum" and np.any(counts < m):
            raise DriverError(
                gyro.resource,
                f"frames (step {step.segment})",
                "frames are missing and the output is summed (increments): a sample with missing "
                "frames would be short by what they held; " + "; ".join(rec.warnings),
                hint="re-acquire",
            )
        sums = np.bincount(window[keep], weights=x[keep], minlength=n)[:n]
        values = sums if spec.aggregate == "sum" else sums / counts
        cols: dict[str, tuple[np.ndarray, str]] = {
            "time": (np.arange(n, dtype=np.float64) * float(step.interval.to("s").magnitude), "s"),
            spec.column: (values, unit_text),
        }
        conditions = dict(step.conditions)
        if not clean:
            cols["frames"] = (counts.astype(np.int64), "1")
            conditions["frame_issues"] = " | ".join(rec.warnings)
            conditions["missing_frames"] = int(rec.missing_frames)
        if progress is not None:
            progress(f"recording {step.segment}", n, n)
        return _segment(step, conditions, cols)


def _instructions(step: Step, state: dict[str, str | None]) -> tuple[list[str], bool]:
    """What the operator must do before ``step``, given the bench's ``state`` (updated)."""
    c = {k: _norm(v) for k, v in step.conditions.items()}
    raw = dict(step.conditions)
    out: list[str] = []
    cycle = False
    shock = _SHOCK_KINDS.get(step.kind)
    mount_keys = [k for k in _MOUNTING if k in c and not (shock and k == "axis")]
    changed = [k for k in mount_keys if state.get(k) != c[k]]
    if changed:
        out.append(
            "mount the device: " + ", ".join(f"{k.replace('_', ' ')} {raw[k]}" for k in mount_keys)
        )
    for k in mount_keys:
        state[k] = c[k]
    if "temperature" in c and state["temperature"] != c["temperature"]:
        out.append(f"set the chamber to {raw['temperature']} and let the device soak")
        state["temperature"] = c["temperature"]
    if "field" in c or "field_axis" in c:
        f = f"{c.get('field', '')}|{c.get('field_axis', '')}"
        if state["field"] != f:
            where = f" along {raw['field_axis']}" if "field_axis" in raw else ""
            out.append(f"set the field generator to {raw.get('field', '0')}{where}")
            state["field"] = f
    if "run" in c:
        if state["run"] is not None and state["run"] != c["run"]:
            out.append(f"power the device off and on again (run {raw['run']})")
            cycle = True
        state["run"] = c["run"]
    if shock and "phase" in c:
        if c["phase"] == "after" and state["phase"] != "after":
            axis = f" along axis {raw['axis']}" if "axis" in raw else ""
            out.append(f"apply the {shock}{axis} as the standard asks ({step.description})")
        state["phase"] = c["phase"]
    return out, cycle


def _segment(
    step: Step, conditions: dict[str, Any], cols: dict[str, tuple[np.ndarray, str]]
) -> Segment:
    h = hashlib.sha256()
    for name, (a, u) in cols.items():
        h.update(f"{name} [{u}]".encode())
        h.update(np.ascontiguousarray(a).tobytes())
    return Segment(
        id=step.segment,
        kind=step.kind,
        conditions=conditions,
        interval=step.interval,
        file=None,
        sha256=h.hexdigest(),
        loader=lambda c=cols: c,
    )


@attrs.define
class _Opened:
    """An open driver of the bench."""

    spec: DriverSpec
    driver: Any

    @property
    def kind(self) -> str:
        return self.spec.kind


class _Drivers:
    """Opens the bench's drivers; on leaving — normally, on an error or on Ctrl-C — stops the
    table and closes every driver.  A failure while cleaning up after an error is added to that
    error as a note rather than hiding it."""

    def __init__(self, config: BenchConfig) -> None:
        self.config = config
        self._table: _Opened | None = None
        self._output: _Opened | None = None
        self.table_identity = ""
        self.output_identity = ""
        self._table_eq: Equipment | None = None

    @property
    def table(self) -> Any:
        assert self._table is not None
        return self._table.driver

    @property
    def output(self) -> _Opened:
        assert self._output is not None
        return self._output

    def __enter__(self) -> "_Drivers":
        try:
            self._table = _Opened(self.config.table, self.config.table.open())
            ident = self.table.identify()
            self.table_identity = _describe(ident)
            eq = self.table.equipment()
            if not isinstance(eq, Equipment):
                raise DriverError(
                    self.table.resource or self.config.table.name,
                    "equipment()",
                    f"driver {self.config.table.name!r} returned {eq!r}, not an Equipment",
                )
            self._table_eq = attrs.evolve(
                eq,
                manufacturer=ident.manufacturer or eq.manufacturer,
                model=ident.model or eq.model,
                serial=ident.serial or eq.serial,
                role=self.config.table_role or eq.role,
                calibration=self.config.table_calibration or eq.calibration,
            )
            self._output = _Opened(self.config.output.driver, self.config.output.driver.open())
            oid = self._output.driver.identify()
            self.output_identity = _describe(oid)
            self._output_ident = oid
        except BaseException as exc:
            self.__exit__(type(exc), exc, exc.__traceback__)
            raise
        return self

    def equipment(self) -> list[Equipment]:
        out = [self._table_eq] if self._table_eq is not None else []
        e = self.config.output.equipment
        if e is not None:
            oid = self._output_ident
            out.append(
                attrs.evolve(
                    e,
                    manufacturer=e.manufacturer or oid.manufacturer,
                    model=e.model or oid.model,
                    serial=e.serial or oid.serial,
                )
            )
        return out + list(self.config.equipment)

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        problems: list[BaseException] = []
        if self._table is not None:
            try:
                self._table.driver.stop(axis=None)
            except Exception as e:  # noqa: BLE001 - reported below
                problems.append(e)
        for opened in (self._output, self._table):
            if opened is None:
                continue
            try:
                opened.driver.close()
            except Exception as e:  # noqa: BLE001
                problems.append(e)
        self._output = None
        self._table = None
        if problems:
            if exc is not None:
                for p in problems:
                    exc.add_note(f"while stopping the bench: {type(p).__name__}: {p}")
            else:
                raise problems[0]


def _describe(ident: Any) -> str:
    parts = [p for p in (getattr(ident, "manufacturer", ""), getattr(ident, "model", "")) if p]
    text = " ".join(parts) or str(ident)
    if getattr(ident, "serial", ""):
        text += f" s/n {ident.serial}"
    if getattr(ident, "firmware", ""):
        text += f" firmware {ident.firmware}"
    return text


_OPTIONS = {"config", "assume_ready", "allow_unclean", "warmed_up", "clock", "operator"}


def bench_station_factory(registry: Any, **options: Any) -> BenchStation:
    """The ``bench`` station: ``config`` (the bench file, required), ``assume_ready``,
    ``allow_unclean``, ``warmed_up`` (true/false); from Python also ``clock`` and ``operator``.

    ``registry`` is the plugin registry (its ``drivers``); the bench file is read and checked
    here, so a bad file fails before any instrument is opened."""
    unknown = sorted(set(options) - _OPTIONS)
    if unknown:
        extra = " (--seed is for simulated stations)" if "seed" in unknown else ""
        raise DataError(
            None,
            f"station option {unknown[0]}",
            f"the bench station does not take {', '.join(unknown)}{extra}; it takes config, "
            "assume_ready, allow_unclean, warmed_up",
        )
    if "config" not in options:
        raise DataError(
            None,
            "station option config",
            "missing: the bench file",
            hint="--station-option config=bench.toml (format: docs/instruments.md, Bench station)",
        )
    cfg = load_bench(str(options["config"]), registry.drivers)
    flags = {
        k: flag_value(options[k], cfg.source, f"station option {k}")
        for k in ("assume_ready", "allow_unclean", "warmed_up")
        if k in options
    }
    clock = options.get("clock") or SystemClock()
    if not (
        callable(getattr(clock, "monotonic", None)) and callable(getattr(clock, "sleep", None))
    ):
        raise DataError(
            None,
            "station option clock",
            f"{clock!r} is not a clock (monotonic() and sleep(s))",
            hint="the clock and the operator are given from Python, not on the command line",
        )
    operator = options.get("operator")
    if operator is not None and not callable(operator):
        raise DataError(
            None,
            "station option operator",
            f"{operator!r} is not a callable operator(instruction, step)",
            hint="the clock and the operator are given from Python, not on the command line",
        )
    return BenchStation(cfg, clock=clock, operator=operator, **flags)
