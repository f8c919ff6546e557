"""A gyro's digital output over RS-422/RS-485: binary frames with a declared layout.

A frame is ``header | counter | fields … | checksum``, laid out with :mod:`struct`::

    layout = FrameLayout(
        header=b"\\xAA\\x55",
        counter=FrameField("counter", "B"),
        fields=(FrameField("rate", "i", scale=1e-6, unit="deg/s"),   # 32-bit, 1 µ°/s per LSB
                FrameField("temperature", "h", scale=0.01, unit="degC"),
                FrameField("status", "B")),
        checksum="sum8",                      # or "xor8", "crc16"
    )

:class:`FrameParser` turns a byte stream into frames and *reports* everything that is not a
clean frame: a bad checksum (the frame is left out of the data and its byte position recorded),
a skipped counter (how many frames are missing, and where), bytes that are not a frame, a status
word that is not 0.  Nothing is dropped silently: :class:`GyroRecord` carries the issues next to
the data, its ``warnings`` say what happened, and its ``time`` column is built from the frame
counter, so a gap stays a gap (metro's readers refuse a time column with a gap).  Streams that
cannot be frames at all — no header within a few frame lengths (wrong layout or baud rate), a
stream that ends mid-frame, a port that goes away — raise
:class:`~metro.core.base.errors.DriverError`.

:class:`SerialGyro` reads frames from a serial port with pyserial (imported when it opens).
"""

from __future__ import annotations

import struct
from typing import Any, Iterable, Iterator, Mapping

import attrs
import numpy as np
import pint

from metro.core.base.errors import DriverError
from metro.core.base.units import Q_, parse_quantity, unit

from metro.core.model.drivers import GyroOutputDriver, Identity

from .base import import_for_driver

__all__ = [
    "FrameField",
    "FrameLayout",
    "FrameIssue",
    "Frame",
    "FrameParser",
    "GyroRecord",
    "SerialGyro",
    "checksum",
]

_INT_CODES = set("bBhHiIqQ")
_CODES = _INT_CODES | set("fd")


def _valid_code(inst: Any, attribute: attrs.Attribute, value: str) -> None:
    if value not in _CODES:
        raise ValueError(
            f"{attribute.name}: struct code {value!r} is not one of {''.join(sorted(_CODES))}"
        )


def _valid_unit(inst: Any, attribute: attrs.Attribute, value: str) -> None:
    unit(value)  # raises on a unit pint cannot read


@attrs.frozen
class FrameField:
    """One field of a frame: its ``struct`` code, and value = raw × ``scale`` in ``unit``."""

    name: str
    code: str = attrs.field(validator=_valid_code)
    scale: float = 1.0
    unit: str = attrs.field(default="1", validator=_valid_unit)

    @property
    def size(self) -> int:
        return struct.calcsize("<" + self.code)


def _crc16_ccitt(data: bytes) -> int:
    """CRC-16/CCITT-FALSE: polynomial 0x1021, initial value 0xFFFF, no reflection, no final XOR."""
    crc = 0xFFFF
    for byte in data:
        crc ^= byte << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


def checksum(kind: str, data: bytes) -> int:
    """The checksum of ``data``: ``sum8`` (sum of bytes mod 256), ``xor8`` or ``crc16``
    (CCITT-FALSE)."""
    if kind == "sum8":
        return sum(data) & 0xFF
    if kind == "xor8":
        x = 0
        for b in data:
            x ^= b
        return x
    if kind == "crc16":
        return _crc16_ccitt(data)
    raise ValueError(f"unknown checksum {kind!r}; use sum8, xor8 or crc16")


_CHECK_CODES = {"sum8": "B", "xor8": "B", "crc16": "H"}


@attrs.frozen
class FrameLayout:
    """The binary layout of one frame.

    ``byte_order`` is ``"<"`` (little-endian) or ``">"``; the checksum covers the bytes after
    the header up to the checksum and is stored in the same byte order.  The counter is an
    unsigned integer field that increases by one per frame and wraps at 2^bits.
    """

    header: bytes = attrs.field(default=b"\xaa\x55")
    counter: FrameField = attrs.field(factory=lambda: FrameField("counter", "B"))
    fields: tuple[FrameField, ...] = attrs.field(
        factory=lambda: (
            FrameField("rate", "i", 1e-6, "deg/s"),
            FrameField("temperature", "h", 0.01, "degC"),
            FrameField("status", "B"),
        ),
        converter=tuple,
    )
    checksum: str = attrs.field(default="sum8", validator=attrs.validators.in_(tuple(_CHECK_CODES)))
    byte_order: str = attrs.field(default="<", validator=attrs.validators.in_(("<", ">")))

    def __attrs_post_init__(self) -> None:
        if not self.header:
            raise ValueError("a frame needs header bytes to synchronise on")
        if self.counter.code not in set("BHIQ"):
            raise ValueError(
                f"the counter must be an unsigned integer field (B, H, I, Q), not "
                f"{self.counter.code!r}"
            )
        names = [self.counter.name] + [f.name for f in self.fields]
        if len(set(names)) != len(names) or "time" in names:
            raise ValueError(f"field names must be distinct and not 'time': {names}")

    @classmethod
    def from_mapping(cls, m: Mapping[str, Any], *, where: str = "layout") -> "FrameLayout":
        """A layout from plain data (a bench file's table)::

            {"header": "AA55", "counter": {"name": "counter", "code": "B"},
             "fields": [{"name": "rate", "code": "i", "scale": 1e-6, "unit": "deg/s"}, …],
             "checksum": "sum8", "byte_order": "<"}

        ``header`` is hexadecimal text; a missing key takes the default layout's value.  A bad
        entry is a ``ValueError`` naming the key (``where.fields[1].code``)."""
        if not isinstance(m, Mapping):
            raise ValueError(f"{where}: must be a table, got {type(m).__name__}")
        unknown = sorted(set(m) - {"header", "counter", "fields", "checksum", "byte_order"})
        if unknown:
            raise ValueError(
                f"{where}: unknown key(s) {', '.join(unknown)}; "
                "use header, counter, fields, checksum, byte_order"
            )

        def field(d: Any, w: str) -> FrameField:
            if not isinstance(d, Mapping) or "name" not in d or "code" not in d:
                raise ValueError(f"{w}: give a table with at least name and code, got {d!r}")
            bad = sorted(set(d) - {"name", "code", "scale", "unit"})
            if bad:
                raise ValueError(
                    f"{w}: unknown key(s) {', '.join(bad)}; use name, code, scale, unit"
                )
            try:
                return FrameField(
                    str(d["name"]),
                    str(d["code"]),
                    float(d.get("scale", 1.0)),
                    str(d.get("unit", "1")),
                )
            except (ValueError, TypeError, pint.errors.UndefinedUnitError) as exc:
                raise ValueError(f"{w}: {exc}") from exc

        kw: dict[str, Any] = {}
        if "header" in m:
            try:
                kw["header"] = bytes.fromhex(str(m["header"]))
            except ValueError as exc:
                raise ValueError(
                    f"{where}.header: not hexadecimal bytes ({m['header']!r})"
                ) from exc
        if "counter" in m:
            kw["counter"] = field(m["counter"], f"{where}.counter")
        if "fields" in m:
            fl = m["fields"]
            if not isinstance(fl, (list, tuple)) or not fl:
                raise ValueError(f"{where}.fields: give a non-empty list of field tables")
            kw["fields"] = tuple(field(d, f"{where}.fields[{i}]") for i, d in enumerate(fl))
        for key in ("checksum", "byte_order"):
            if key in m:
                kw[key] = str(m[key])
        try:
            return cls(**kw)
        except (ValueError, TypeError) as exc:
            raise ValueError(f"{where}: {exc}") from exc

    @property
    def body_format(self) -> str:
        return self.byte_order + self.counter.code + "".join(f.code for f in self.fields)

    @property
    def body_size(self) -> int:
        return struct.calcsize(self.body_format)

    @property
    def size(self) -> int:
        return len(self.header) + self.body_size + struct.calcsize(_CHECK_CODES[self.checksum])

    @property
    def counter_modulus(self) -> int:
        return 1 << (8 * self.counter.size)

    def encode(self, counter: int, values: Iterable[float], *, corrupt: bool = False) -> bytes:
        """One frame with these raw field values (integers for integer codes); ``corrupt`` flips
        the checksum (for tests and simulators)."""
        body = struct.pack(self.body_format, counter % self.counter_modulus, *values)
        c = checksum(self.checksum, body) ^ (1 if corrupt else 0)
        return self.header + body + struct.pack(self.byte_order + _CHECK_CODES[self.checksum], c)


@attrs.frozen
class FrameIssue:
    """A problem in the stream: ``kind`` is ``checksum``, ``counter-gap``, ``junk`` or ``status``;
    ``position`` the byte offset in the stream where it starts; ``frame`` the index of the next
    good frame in the data (where the problem sits)."""

    kind: str
    position: int
    frame: int
    detail: str
    #: for ``counter-gap``: how many frames are missing; for ``junk``: how many bytes
    count: int = 0


@attrs.frozen
class Frame:
    position: int
    counter: int
    values: tuple[float, ...]


class FrameParser:
    """Incremental frame parser: :meth:`feed` bytes, get complete good frames; issues accumulate
    in :attr:`issues`.  ``max_junk`` bytes without a valid frame is an error (a wrong layout or
    baud rate), as is ending mid-frame (:meth:`finish`)."""

    def __init__(
        self,
        layout: FrameLayout,
        *,
        max_junk: int | None = None,
        source: str = "stream",
        lead_in: bool = False,
    ) -> None:
        self.layout = layout
        #: bytes skipped before the first good frame when the parser starts mid-stream (``lead_in``)
        self.lead_in = 0
        self._lead_in_open = lead_in
        self.source = source
        self.max_junk = max_junk if max_junk is not None else 4 * layout.size
        self.issues: list[FrameIssue] = []
        self._buf = bytearray()
        self._offset = 0  # stream position of _buf[0]
        self._junk_start: int | None = None
        self._junk = 0
        self._last_counter: int | None = None
        self._bad_until = 0  # bytes before this stream offset belong to a frame already reported
        self._n_good = 0
        self._check = struct.Struct(layout.byte_order + _CHECK_CODES[layout.checksum])
        self._body = struct.Struct(layout.body_format)

    def _flush_junk(self) -> None:
        if self._junk:
            self.issues.append(
                FrameIssue(
                    "junk",
                    self._junk_start or 0,
                    self._n_good,
                    f"{self._junk} byte(s) that are not a frame were skipped",
                    self._junk,
                )
            )
            self._junk, self._junk_start = 0, None

    def _skip(self, n: int) -> None:
        if self._lead_in_open and self._offset + n <= self.layout.size:
            # started mid-stream: the tail of a frame sent before the record began
            self.lead_in += n
            del self._buf[:n]
            self._offset += n
            return
        counted = max(0, self._offset + n - max(self._offset, self._bad_until))
        if counted and self._junk_start is None:
            self._junk_start = max(self._offset, self._bad_until)
        self._junk += counted
        del self._buf[:n]
        self._offset += n
        if self._junk > self.max_junk:
            raise DriverError(
                self.source,
                f"byte {self._junk_start}",
                f"{self._junk} bytes without a valid frame: the stream does not match the "
                f"declared layout ({self.layout.size}-byte frames, header "
                f"{self.layout.header.hex()})",
                hint="check the frame layout, the baud rate and the wiring (RS-422 polarity)",
            )

    def feed(self, data: bytes) -> list[Frame]:
        L = self.layout
        self._buf += data
        out: list[Frame] = []
        hlen, size = len(L.header), L.size
        while True:
            i = self._buf.find(L.header)
            if i < 0:
                keep = hlen - 1  # a header may be split across reads
                if len(self._buf) > keep:
                    self._skip(len(self._buf) - keep)
                break
            if i > 0:
                self._skip(i)
            if len(self._buf) < size:
                break
            frame = bytes(self._buf[:size])
            body = frame[hlen : hlen + L.body_size]
            (stored,) = self._check.unpack(frame[hlen + L.body_size :])
            if checksum(L.checksum, body) != stored:
                if self._lead_in_open and self._offset < size:
                    self._skip(1)  # a header pattern inside the tail of an earlier frame
                    continue
                self._flush_junk()
                self.issues.append(
                    FrameIssue(
                        "checksum",
                        self._offset,
                        self._n_good,
                        f"checksum {stored:#x} does not match the frame "
                        f"({checksum(L.checksum, body):#x}); frame left out",
                    )
                )
                # the frame's bytes are reported with it; resynchronise on the next header
                self._bad_until = self._offset + size
                self._skip(1)
                continue
            self._flush_junk()
            self._lead_in_open = False
            raw = self._body.unpack(body)
            cnt = int(raw[0])
            if self._last_counter is not None:
                step = (cnt - self._last_counter) % L.counter_modulus
                if step != 1:
                    missing = (step - 1) if step else L.counter_modulus - 1
                    self.issues.append(
                        FrameIssue(
                            "counter-gap",
                            self._offset,
                            self._n_good,
                            f"counter went {self._last_counter} → {cnt}: "
                            f"{missing} frame(s) missing",
                            missing,
                        )
                    )
            self._last_counter = cnt
            values = tuple(float(v) * f.scale for v, f in zip(raw[1:], L.fields))
            out.append(Frame(self._offset, cnt, values))
            self._n_good += 1
            del self._buf[:size]
            self._offset += size
        return out

    def finish(self) -> None:
        """The stream has ended: leftover bytes of a partial frame are an error."""
        if self._buf:
            raise DriverError(
                self.source,
                f"byte {self._offset}",
                f"the stream ended inside a frame ({len(self._buf)} of {self.layout.size} bytes)",
                hint="the connection dropped or the device stopped mid-frame",
            )


@attrs.frozen(eq=False)
class GyroRecord:
    """What :class:`SerialGyro` read: one column per field (quantities), the counter, a ``time``
    column from the unwrapped counter × interval, and every issue found."""

    columns: dict[str, pint.Quantity]
    #: the frame counter unwrapped (0 at the first frame; a gap of k frames jumps by k + 1)
    counter: np.ndarray
    interval: pint.Quantity
    issues: tuple[FrameIssue, ...]
    positions: np.ndarray
    source: str = ""

    @property
    def n_frames(self) -> int:
        return int(self.counter.size)

    @property
    def missing_frames(self) -> int:
        return sum(i.count for i in self.issues if i.kind == "counter-gap")

    def count(self, kind: str) -> int:
        return sum(1 for i in self.issues if i.kind == kind)

    @property
    def warnings(self) -> list[str]:
        """One line per kind of problem, with the first positions."""
        out = []
        for kind in ("checksum", "counter-gap", "junk", "status"):
            found = [i for i in self.issues if i.kind == kind]
            if not found:
                continue
            where = ", ".join(f"byte {i.position} (before frame {i.frame})" for i in found[:5])
            more = f" and {len(found) - 5} more" if len(found) > 5 else ""
            out.append(f"{self.source}: {len(found)} {kind} issue(s) at {where}{more}")
        if self.missing_frames:
            out.append(
                f"{self.source}: {self.missing_frames} frame(s) missing in total; the time column "
                f"has gaps"
            )
        return out

    @property
    def clean(self) -> bool:
        return not self.issues

    def require_clean(self) -> "GyroRecord":
        """The record itself if nothing went wrong, else a :class:`DriverError` listing the
        issues."""
        if self.issues:
            raise DriverError(
                self.source,
                "frames",
                "; ".join(self.warnings),
                hint="re-acquire, or keep the record and its gaps explicitly",
            )
        return self

    def as_columns(self) -> dict[str, tuple[np.ndarray, str]]:
        """``{name: (array, unit text)}`` (what a segment loader returns), ``time`` first."""
        t = self.interval.to("s").magnitude * (
            self.counter - self.counter[0] if self.counter.size else self.counter
        )
        out = {"time": (np.asarray(t, dtype=float), "s")}
        for name, q in self.columns.items():
            out[name] = (
                np.asarray(q.magnitude, dtype=float),
                f"{q.units:D}" if str(q.units) else "1",
            )
        return out


class SerialGyro(GyroOutputDriver):
    """Frames from a gyro's serial output (RS-422/RS-485 through a USB adapter, or a pty in tests).

    :param port: the serial device (``/dev/ttyUSB0``, ``COM3``).
    :param layout: the frame layout.
    :param interval: the frame period (the gyro's output rate), a quantity.
    :param timeout: how long a read may wait for bytes before the connection counts as dropped.
    """

    def __init__(
        self,
        port: str,
        layout: FrameLayout | Mapping[str, Any],
        *,
        interval: Any = "1 ms",
        baudrate: int = 921600,
        timeout: Any = "1 s",
        parity: str = "N",
        stopbits: float = 1,
    ) -> None:
        self.resource = port
        if isinstance(layout, Mapping):
            try:
                layout = FrameLayout.from_mapping(layout)
            except ValueError as exc:
                raise DriverError(port, "layout", str(exc)) from exc
        self.layout = layout
        self.interval = parse_quantity(interval, dimension="s", field="interval")
        self._timeout_s = float(
            parse_quantity(timeout, dimension="s", field="timeout").to("s").magnitude
        )
        serial = import_for_driver("serial", port, package="pyserial")
        self._serial_mod = serial
        try:
            self._port = serial.Serial(
                port,
                baudrate=baudrate,
                timeout=self._timeout_s,
                parity=parity,
                stopbits=stopbits,
                bytesize=8,
            )
        except (serial.SerialException, OSError, ValueError) as exc:
            raise DriverError(
                port,
                None,
                f"cannot open the serial port: {exc}",
                hint="check the port name and that no other program holds it",
            ) from exc
        self.parser = FrameParser(layout, source=port)
        self._pending: list[Frame] = []
        self._issues_read = 0
        self._status_index = next(
            (i for i, f in enumerate(layout.fields) if f.name == "status"), None
        )

    def identify(self) -> Identity:
        """A streaming gyro does not answer queries: the identity is the port and the layout."""
        return Identity(
            "serial gyro", f"{self.layout.size}-byte frames, {self.layout.checksum}", self.resource
        )

    def _chunks(self) -> Iterator[bytes]:
        while True:
            try:
                data = self._port.read(max(1, min(self._port.in_waiting or 1, 1 << 16)))
            except (self._serial_mod.SerialException, OSError) as exc:
                raise DriverError(
                    self.resource,
                    f"byte {self.parser._offset + len(self.parser._buf)}",
                    f"the connection was lost: {exc}",
                    hint="check the cable and the adapter; nothing after this point was read",
                ) from exc
            if not data:
                raise DriverError(
                    self.resource,
                    f"byte {self.parser._offset + len(self.parser._buf)}",
                    f"no data for {self._timeout_s:g} s: the connection dropped or the gyro "
                    "stopped sending",
                    hint="check power, cable and baud rate",
                )
            yield data

    def read(self, n_frames: int) -> GyroRecord:
        """Read until ``n_frames`` good frames have arrived (issues are collected on the way)."""
        if n_frames < 1:
            raise DriverError(self.resource, "n_frames", f"need at least one frame, got {n_frames}")
        frames: list[Frame] = list(self._pending)
        start_issues = self._issues_read
        if len(frames) < n_frames:
            for data in self._chunks():
                frames += self.parser.feed(data)
                if len(frames) >= n_frames:
                    break
        frames, self._pending = frames[:n_frames], frames[n_frames:]
        # issues up to the last frame returned belong to this read; later ones to the next
        last = frames[-1].position
        issues = [i for i in self.parser.issues[start_issues:] if i.position <= last]
        self._issues_read = start_issues + len(issues)
        L = self.layout
        vals = np.array([f.values for f in frames], dtype=float).reshape(len(frames), len(L.fields))
        counter = np.array([f.counter for f in frames], dtype=np.int64)
        unwrapped = (
            np.concatenate([[0], np.cumsum(np.diff(counter) % L.counter_modulus)])
            if frames
            else counter
        )
        if self._status_index is not None:
            bad = np.flatnonzero(vals[:, self._status_index] != 0)
            status_scale = L.fields[self._status_index].scale
            for j in bad:
                issues.append(
                    FrameIssue(
                        "status",
                        frames[j].position,
                        int(j),
                        f"status word {int(vals[j, self._status_index] / status_scale):#x}",
                    )
                )
        cols = {L.counter.name: Q_(counter.astype(float), "")}
        for k, f in enumerate(L.fields):
            cols[f.name] = Q_(vals[:, k], f.unit)
        return GyroRecord(
            cols,
            unwrapped,
            self.interval,
            tuple(issues),
            np.array([f.position for f in frames], dtype=np.int64),
            self.resource,
        )

    def restart(self) -> None:
        """Start a new record: discard the bytes received so far (frames sent while the table was
        still settling) and resynchronise.  The bytes before the first whole frame after this
        point are the tail of a frame sent before it, not a fault: they are counted in
        :attr:`FrameParser.lead_in` rather than reported as junk."""
        try:
            self._port.reset_input_buffer()
        except (self._serial_mod.SerialException, OSError) as exc:
            raise DriverError(
                self.resource, "reset_input_buffer", f"the connection was lost: {exc}"
            ) from exc
        self.parser = FrameParser(self.layout, source=self.resource, lead_in=True)
        self._pending = []
        self._issues_read = 0

    def close(self) -> None:
        port = getattr(self, "_port", None)
        if port is not None and port.is_open:
            port.close()
