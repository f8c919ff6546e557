"""metro's built-in instruments as a plugin: the sample-file formats (read and write), the simulated
optical-gyro stations, the live bench station and the drivers.

Loaded through the ``metro`` entry-point group like any third-party plugin.
"""

from __future__ import annotations

from metro.core import hookimpl


@hookimpl
def metro_register_readers(registrar) -> None:
    from . import readers

    text = "samples with `name [unit]` headers"
    registrar.add_reader(
        (".csv",), readers.read_samples, f"comma-separated {text}", write=readers.write_samples_csv
    )
    registrar.add_reader((".tsv", ".txt"), readers.read_samples, f"tab-separated {text}")
    registrar.add_reader(
        (".npy",), readers.read_samples, "NumPy .npy samples", write=readers.write_samples_npy
    )
    registrar.add_reader((".parquet", ".pq"), readers.read_samples, "Apache Parquet samples")


@hookimpl
def metro_register_stations(registrar) -> None:
    from .simulated import station_factory

    registrar.add_station(
        "simulated", station_factory, "built-in simulated test station (virtual optical gyro)"
    )

    from .sim_gbt_rate import digital_station_factory

    registrar.add_station(
        "simulated-digital",
        digital_station_factory,
        "the simulated station with a digital (LSB) output gyro, for the GB/T 45570 rate method",
    )

    # the standards' own simulated stations (a standard's plugin never imports instruments)
    from .angle_instrument import station_factory as ogam_station
    from .mimu import station_factory as mimu_station
    from .vibratory import station_factory as vibratory_station

    registrar.add_station(
        "simulated-jjf2014",
        vibratory_station,
        "simulated JJF 2014 station (virtual analog vibratory rate gyro on "
        "rate/vibration tables)",
    )
    registrar.add_station(
        "simulated-mimu",
        mimu_station,
        "simulated MIMU (JJF 2003 eq. (1), (2)) on a three-axis position/rate table",
    )
    registrar.add_station(
        "simulated-ogam",
        ogam_station,
        "simulated optical-gyro angle measuring instrument on a low-speed turntable",
    )

    from functools import partial

    from .bench import bench_station_factory

    # the registry is complete (drivers included) by the time a station is made
    registrar.add_station(
        "bench",
        partial(bench_station_factory, registrar.registry),
        "live bench: a registered rate-table driver and a DMM or gyro-output "
        "driver, configured by a bench file "
        "(--station-option config=bench.toml)",
    )


@hookimpl
def metro_register_drivers(registrar) -> None:
    # the modules import PyVISA / pyserial only when a driver is opened
    from .drivers.scpi_dmm import ScpiDmm
    from .drivers.serial_gyro import SerialGyro

    registrar.add_driver(
        "scpi-dmm", "dmm", ScpiDmm, "SCPI 6½-digit DMM over PyVISA (GPIB, USB-TMC, LAN)"
    )
    registrar.add_driver(
        "serial-gyro",
        "gyro-output",
        SerialGyro,
        "gyro digital output over RS-422/RS-485: binary frames with a declared layout",
    )
