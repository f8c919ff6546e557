"""GB/T 45570—2025 光学陀螺仪通用技术要求 (optical gyroscopes) as a metro plugin.

Registered through the ``metro`` entry-point group, like any third-party plugin.
Items implemented so far: D.1.1–D.1.3 (angle method) and D.5.1–D.5.6 (bias series, ARW).
"""

from __future__ import annotations

from metro.core import hookimpl

STANDARD_ID = "gbt45570"


@hookimpl
def metro_register_standards(registrar) -> None:
    from . import angle_method
    from .procedures import PROCEDURES

    registrar.add_standard(
        STANDARD_ID,
        "光学陀螺仪通用技术要求 (Optical gyroscopes — general technical requirements)",
        designation="GB/T 45570—2025",
        description="test methods of normative appendix D",
    )
    for cls in angle_method.PROCEDURES + PROCEDURES:
        registrar.add_procedure(cls)
