"""Live-instrument drivers: the SCPI DMM against a pyvisa-sim instrument, the serial gyro over a
pseudo-terminal pair, and the frame parser's reporting of every bad frame."""

from __future__ import annotations

import os
import struct
import threading
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pint.errors import UndefinedUnitError

from metro.core.base.errors import DriverError, UnitError
from metro.core.base.units import Q_
from metro.core.model import drivers as base
from metro.instruments.drivers.serial_gyro import (FrameField, FrameLayout, FrameParser, SerialGyro,
                                                   checksum)

DMM_YAML = Path(__file__).parents[1] / "data" / "drivers" / "scpi_dmm.yaml"
DMM_ADDR = "TCPIP::dmm.metro.test::INSTR"


# ------------------------------------------------------------------------------ SCPI DMM


@pytest.fixture
def dmm():
    from metro.instruments.drivers.scpi_dmm import ScpiDmm

    _fresh_sim()
    d = ScpiDmm(DMM_ADDR, visa_library=f"{DMM_YAML}@sim")
    yield d
    d.close()
    _fresh_sim()


def _fresh_sim() -> None:
    """pyvisa caches one library (and pyvisa-sim its devices) per path: drop it between tests."""
    from pyvisa.highlevel import VisaLibraryBase
    from pyvisa_sim.highlevel import SimVisaLibrary

    for key in [k for k in VisaLibraryBase._registry if k[0] is SimVisaLibrary]:
        VisaLibraryBase._registry.pop(key)


def test_dmm_identifies_configures_and_reads_quantities(dmm):
    idn = dmm.identify()
    assert (idn.manufacturer, idn.model, idn.serial,
            idn.firmware) == ("METRO-SIM", "DMM-6.5", "SN000123", "1.2.3")
    dmm.reset()
    dmm.configure_dc_voltage(Q_(1, "V"), nplc=1)
    assert dmm.range() == Q_(1.0, "V")
    dmm.configure_dc_voltage(Q_(100, "mV"))  # units converted at the boundary
    assert dmm.range() == Q_(0.1, "V")
    dmm.configure_dc_voltage(None)
    r = dmm.read()
    assert r.units == Q_(1, "V").units and r.magnitude == pytest.approx(0.0123456)
    dmm._inst.write(f"SIM:INPUT {-2.5e-3:E}")  # the voltage at the simulated instrument's input
    many = dmm.read_many(4)
    assert many.to("mV").magnitude.tolist() == pytest.approx([-2.5] * 4)


def test_dmm_instrument_errors_and_overload_are_loud(dmm):
    with pytest.raises(DriverError, match=r"CONF:VOLT:DC 3.000000E\+00.*-113"):
        dmm.configure_dc_voltage(Q_(3, "V"))  # not a range of this DMM
    with pytest.raises(UnitError, match="not compatible"):
        dmm.configure_dc_voltage(Q_(3, "A"))
    with pytest.raises(DriverError, match="nplc"):
        dmm.configure_dc_voltage(Q_(1, "V"), nplc=0)
    dmm._inst.write("SIM:INPUT 9.9E37")
    with pytest.raises(DriverError, match="overload"):
        dmm.read()
    dmm.close()
    with pytest.raises(DriverError, match="closed"):
        dmm.read()


def test_dmm_connection_dropped_mid_read_fails_loudly(dmm, monkeypatch):
    """A connection lost between readings (cable pulled, instrument switched off) is a DriverError
    naming the address and the command — never a reading, never an empty value."""
    from pyvisa import constants, errors
    from pyvisa_sim.highlevel import SimVisaLibrary

    dmm._inst.write(f"SIM:INPUT {1.25e-3:E}")
    assert dmm.read().to("mV").magnitude == pytest.approx(1.25)
    real = SimVisaLibrary.read
    state = {"lost": False}

    def read(self, session, count):
        if state["lost"]:
            raise errors.VisaIOError(constants.VI_ERROR_CONN_LOST)
        return real(self, session, count)

    monkeypatch.setattr(SimVisaLibrary, "read", read)
    state["lost"] = True
    with pytest.raises(DriverError, match="no valid reply.*VI_ERROR_CONN_LOST") as ei:
        dmm.read()
    assert (ei.value.file, ei.value.field) == (DMM_ADDR, "READ?")
    with pytest.raises(DriverError) as ei:
        dmm.read_many(5)
    assert ei.value.file == DMM_ADDR


@pytest.mark.filterwarnings("ignore:read string doesn't end with termination characters")
def test_dmm_unknown_resource_is_a_clear_error():
    from metro.instruments.drivers.scpi_dmm import ScpiDmm

    with pytest.raises(DriverError, match="empty reply") as ei:
        ScpiDmm("TCPIP::nowhere.metro.test::INSTR", visa_library=f"{DMM_YAML}@sim", timeout="0.2 s")
    assert ei.value.file == "TCPIP::nowhere.metro.test::INSTR" and ei.value.field == "*IDN?"
    with pytest.raises(DriverError) as ei:  # not a message-based instrument: no SCPI at all
        ScpiDmm("NOT-A-VISA-ADDRESS", visa_library=f"{DMM_YAML}@sim")
    assert ei.value.file == "NOT-A-VISA-ADDRESS"


# ------------------------------------------------------------------------------ frames

# AA 55 | counter u8 | rate i32 (1 µ°/s) | temperature i16 (0.01 °C) | status u8 | sum8
LAYOUT = FrameLayout()


def _frames(n, start=0, layout=LAYOUT, *, corrupt=(), skip=(), status=None):
    out, raw = bytearray(), []
    for k in range(n):
        if k in skip:
            continue
        rate = int(1_000_000 * np.sin(k / 10.0))
        vals = (rate, 2000 + k % 7, 0 if status is None or k not in status else 0x04)
        out += layout.encode(start + k, vals, corrupt=k in corrupt)
        if k not in corrupt:
            raw.append((start + k, vals))
    return bytes(out), raw


def test_checksums():
    assert checksum("sum8", b"\x01\x02\xff") == 0x02
    assert checksum("xor8", b"\x0f\xf0\x01") == 0xFE
    assert checksum("crc16", b"123456789") == 0x29B1  # the CRC-16/CCITT-FALSE check value
    with pytest.raises(ValueError):
        checksum("md5", b"")


def test_layout_is_declared_and_checked():
    assert LAYOUT.size == 2 + 1 + 4 + 2 + 1 + 1
    big = FrameLayout(header=b"\x7e", counter=FrameField("n", "H"), byte_order=">",
                      checksum="crc16",
                      fields=(FrameField("rate", "f", 1.0, "deg/h"),))
    assert big.size == 1 + 2 + 4 + 2 and big.counter_modulus == 65536
    with pytest.raises(ValueError):
        FrameLayout(counter=FrameField("n", "h"))  # a signed counter
    with pytest.raises(ValueError):
        FrameField("rate", "x")
    with pytest.raises(UndefinedUnitError):
        FrameField("rate", "i", 1.0, "furlongs per fortnight per wibble")


@settings(max_examples=40, deadline=None)
@given(cuts=st.lists(st.integers(min_value=0, max_value=11 * 60), max_size=30))
def test_parser_gives_the_same_frames_and_issues_for_any_chunking(cuts):
    stream, _ = _frames(60, start=250, corrupt={7}, skip={20, 21})
    stream = stream[:300] + b"\x00\x13\x37" + stream[300:]
    whole = FrameParser(LAYOUT)
    ref = whole.feed(stream)
    p = FrameParser(LAYOUT)
    got = []
    bounds = sorted({0, len(stream), *[c for c in cuts if c < len(stream)]})
    for a, b in zip(bounds[:-1], bounds[1:]):
        got += p.feed(stream[a:b])
    assert got == ref and p.issues == whole.issues


def test_parser_reports_bad_checksum_gaps_and_junk_with_positions():
    stream, raw = _frames(50, start=250, corrupt={10}, skip={30, 31, 32})  # counter wraps at 256
    junk_at = 40 * LAYOUT.size - 3 * LAYOUT.size  # frame 40 of the stream (3 skipped before)
    stream = stream[:junk_at] + b"\x01\x02\x03\x04\x05" + stream[junk_at:]
    p = FrameParser(LAYOUT)
    frames = p.feed(stream)
    p.finish()
    # every good frame, none invented
    assert [f.counter for f in frames] == [c % 256 for c, _ in raw]
    kinds = [(i.kind, i.position, i.count) for i in p.issues]
    size = LAYOUT.size
    assert ("checksum", 10 * size, 0) in kinds
    assert ("counter-gap", 11 * size, 1) in kinds  # the frame with the bad checksum is missing
    assert ("counter-gap", 30 * size, 3) in kinds
    assert ("junk", junk_at, 5) in kinds
    assert len(p.issues) == 4
    np.testing.assert_allclose([f.values[0] for f in frames], [v[0] * 1e-6 for _, v in raw])


def test_parser_fails_loudly_on_a_stream_that_is_not_frames_or_ends_mid_frame():
    p = FrameParser(LAYOUT)
    with pytest.raises(DriverError, match="without a valid frame"):
        p.feed(bytes(range(1, 200)))
    p = FrameParser(LAYOUT)
    stream, _ = _frames(3)
    p.feed(stream[:-4])
    with pytest.raises(DriverError, match="ended inside a frame"):
        p.finish()


# ------------------------------------------------------------------------------ serial over a pty


@pytest.fixture
def pty_pair():
    master, slave = os.openpty()
    name = os.ttyname(slave)
    state = {"master": master}
    yield name, state
    for fd in (state.get("master"), slave):
        if fd is not None:
            try:
                os.close(fd)
            except OSError:
                pass


def _writer(fd, data, *, chunk=97, close_after=False, state=None):
    def run():
        for a in range(0, len(data), chunk):
            try:
                os.write(fd, data[a:a + chunk])
            except OSError:  # the reading side has gone (the test is over)
                return
            time.sleep(0.0005)
        if close_after:
            os.close(fd)
            state["master"] = None

    t = threading.Thread(target=run, daemon=True)
    t.start()
    return t


def test_serial_gyro_reads_frames_and_reports_what_went_wrong(pty_pair):
    name, state = pty_pair
    stream, raw = _frames(600, corrupt={100}, skip={300}, status={450})
    with SerialGyro(name, LAYOUT, interval=Q_(1, "ms"), timeout=Q_(2, "s")) as gyro:
        t = _writer(state["master"], stream)
        rec = gyro.read(400)
        rec2 = gyro.read(len(raw) - 400)
        t.join(5)
    assert rec.n_frames == 400 and rec2.n_frames == len(raw) - 400
    assert rec.columns["rate"].units == Q_(1, "deg/s").units
    np.testing.assert_allclose(rec.columns["rate"].magnitude, [v[0] * 1e-6 for _, v in raw[:400]])
    assert rec.columns["temperature"].to("degC").magnitude[0] == pytest.approx(20.0)
    # the corrupted frame and the skipped one: counted, located, and visible as gaps in time
    assert rec.count("checksum") == 1 and rec.count("counter-gap") == 2 and rec.missing_frames == 2
    assert any("checksum" in w and f"byte {100 * LAYOUT.size}" in w for w in rec.warnings)
    cols = rec.as_columns()
    steps = np.diff(cols["time"][0])
    assert sorted(set(np.round(steps, 9))) == [0.001, 0.002] and (np.round(steps, 9)
                                                                  == 0.002).sum() == 2
    with pytest.raises(DriverError, match="checksum"):
        rec.require_clean()
    # the second read carries the status flag, and only its own issues
    assert rec2.count("status") == 1 and rec2.count("checksum") == 0 and "0x4" in rec2.issues[
        0].detail


def test_serial_gyro_dropped_connection_fails_loudly(pty_pair):
    name, state = pty_pair
    stream, _ = _frames(20)
    with SerialGyro(name, LAYOUT, timeout=Q_(0.5, "s")) as gyro:
        _writer(state["master"], stream[:-5], close_after=True, state=state).join(5)
        with pytest.raises(DriverError) as ei:
            gyro.read(100)
    assert ei.value.file == name
    assert "connection" in ei.value.reason or "no data" in ei.value.reason


def test_serial_gyro_wrong_layout_fails_loudly(pty_pair):
    name, state = pty_pair
    other = FrameLayout(header=b"\x7e\x81", checksum="crc16")
    stream, _ = _frames(40, layout=other)
    with SerialGyro(name, LAYOUT, timeout=Q_(1, "s")) as gyro:
        t = _writer(state["master"], stream)
        with pytest.raises(DriverError, match="does not match the declared layout"):
            gyro.read(10)
    os.close(state.pop("master"))  # a writer blocked on a full buffer gets an error and stops
    t.join(5)
    assert not t.is_alive()


def test_serial_gyro_bad_port_is_a_clear_error(tmp_path):
    with pytest.raises(DriverError, match="cannot open the serial port"):
        SerialGyro(str(tmp_path / "no-such-tty"), LAYOUT)


# ------------------------------------------------------------------------------ interfaces


def test_interfaces_are_abstract_and_cover_the_kinds():
    assert set(base.DRIVER_KINDS) == {"dmm", "gyro-output", "rate-table"}
    with pytest.raises(TypeError):
        base.RateTableDriver()  # abstract
    assert base.Identity.from_idn("ACME,RT-300,42,2.1\n") == base.Identity(
        "ACME", "RT-300", "42", "2.1")
    with pytest.raises(ValueError):
        base.Identity.from_idn("garbage")


def test_binary_layout_matches_struct():
    f = LAYOUT.encode(5, (123456, -150, 0))
    assert f[:2] == b"\xaa\x55"
    n, rate, temp, status, cs = struct.unpack("<BihBB", f[2:])
    assert (n, rate, temp, status) == (5, 123456, -150, 0) and cs == sum(f[2:-1]) & 0xFF


def test_dmm_device_clear_on_opening(monkeypatch):
    """Opening sends a VISA device clear, so a reply left in the output buffer by an interrupted
    session is not read as the answer to the first query; a backend without it (pyvisa-sim) is
    noted, not an error."""
    import pyvisa.resources

    from metro.instruments.drivers.scpi_dmm import ScpiDmm

    _fresh_sim()
    d = ScpiDmm(DMM_ADDR, visa_library=f"{DMM_YAML}@sim")
    assert d.device_cleared is False and d.identity.model  # pyvisa-sim has no viClear
    d.close()
    calls = []
    monkeypatch.setattr(pyvisa.resources.Resource, "clear",
                        lambda self: calls.append(self.resource_name))
    _fresh_sim()
    d = ScpiDmm(DMM_ADDR, visa_library=f"{DMM_YAML}@sim")
    try:
        assert d.device_cleared is True and len(calls) == 1
    finally:
        d.close()
        _fresh_sim()
