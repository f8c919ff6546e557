"""A misbehaving plugin: registers gbt45570:D.5.6 a second time."""

from metro.core import hookimpl
from metro.plugins.gbt45570.procedures import AngleRandomWalkD56


class MyARW(AngleRandomWalkD56):
    pass


@hookimpl
def metro_register_standards(registrar):
    registrar.add_procedure(MyARW)
