"""What plugins register, and the registrars they register it with: part of the plugin contract.

The registration hooks (:mod:`.hookspec`) receive a registrar bound to the registering plugin,
which validates what it is given and records it, with the plugin's name, in the
:class:`Registry`; a duplicate is reported with both plugins' names.  The plugin manager
(:mod:`metro.core.run.plugin_manager`) makes the registrars and reads the registry.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Callable, Sequence

import attrs

from ..base.errors import PluginError
from .procedure import Procedure

__all__ = [
    "StandardInfo",
    "ProcedureInfo",
    "SeriesInfo",
    "ReaderInfo",
    "StationInfo",
    "DriverInfo",
    "TemplateInfo",
    "PluginInfo",
    "Registry",
    "Registrar",
    "StandardRegistrar",
    "ReaderRegistrar",
    "StationRegistrar",
    "TemplateRegistrar",
    "DriverRegistrar",
]


# --------------------------------------------------------------------------------------
# Registered things
# --------------------------------------------------------------------------------------


@attrs.frozen
class StandardInfo:
    id: str
    title: str
    designation: str
    plugin: str
    description: str = ""


@attrs.frozen
class ProcedureInfo:
    cls: type[Procedure]
    plugin: str

    @property
    def id(self) -> str:
        return self.cls.qualified_id()


@attrs.frozen
class SeriesInfo:
    """A named group of items of one standard (e.g. GB/T 45570 ``scale-factor``): running
    the series runs those of its members that apply to the device."""

    standard: str
    name: str
    members: tuple[str, ...]
    description: str
    plugin: str


@attrs.frozen
class ReaderInfo:
    """A samples-file format: how files with these suffixes are read and, optionally, written.

    ``read(path, **kw)`` returns a table of columns with units; ``write(path, columns, units)``
    (``None``: the format is read-only) writes ``{name: array}`` with ``{name: unit text}`` so
    that ``read`` gives them back, and returns the path written (a text format also takes
    ``comments=[…]``, lines written as ``# `` comments)."""

    suffixes: tuple[str, ...]
    read: Callable[..., Any]
    description: str
    plugin: str
    write: Callable[..., Any] | None = None


@attrs.frozen
class StationInfo:
    name: str
    factory: Callable[..., Any]
    description: str
    plugin: str


@attrs.frozen
class DriverInfo:
    name: str
    kind: str
    cls: type
    description: str
    plugin: str


@attrs.frozen
class TemplateInfo:
    """A registered document: a docxtpl template (``path``) or a layout for
    :class:`metro.core.documents.document.DocumentBuilder` (``layout``: ``"module:function"`` or a
    callable)."""

    name: str
    path: Path | None
    standard: str | None
    kind: str
    plugin: str
    layout: Any = None


@attrs.frozen
class PluginInfo:
    name: str
    module: str
    distribution: str | None
    version: str | None
    builtin: bool


@attrs.define
class Registry:
    """What all plugins registered."""

    standards: dict[str, StandardInfo] = attrs.field(factory=dict)
    procedures: dict[str, ProcedureInfo] = attrs.field(factory=dict)
    series: dict[str, SeriesInfo] = attrs.field(factory=dict)
    readers: dict[str, ReaderInfo] = attrs.field(factory=dict)
    stations: dict[str, StationInfo] = attrs.field(factory=dict)
    templates: dict[str, TemplateInfo] = attrs.field(factory=dict)
    drivers: dict[str, DriverInfo] = attrs.field(factory=dict)


# --------------------------------------------------------------------------------------
# Registrars (one per plugin per hook call)
# --------------------------------------------------------------------------------------


@attrs.define
class Registrar:
    """What every registrar shares: the registry it records into and the plugin registering."""

    registry: Registry
    plugin: str

    def _dup(self, what: str, key: str, other: str) -> PluginError:
        return PluginError(
            f"{what} {key!r} is registered twice: by plugin {other!r} and by plugin "
            f"{self.plugin!r}",
            hint=f"block one of them (METRO_BLOCK_PLUGINS={self.plugin}) or rename the {what}",
        )


class StandardRegistrar(Registrar):
    """Validates and records standards and procedures for one plugin."""

    def add_standard(
        self, id: str, title: str, designation: str = "", description: str = ""
    ) -> None:
        if not id or not id.replace("_", "").isalnum() or id != id.lower():
            raise PluginError(
                f"plugin {self.plugin!r}: standard id {id!r} must be lower-case letters/digits"
            )
        if id in self.registry.standards:
            raise self._dup("standard", id, self.registry.standards[id].plugin)
        self.registry.standards[id] = StandardInfo(id, title, designation, self.plugin, description)

    def add_procedure(self, cls: type[Procedure]) -> None:
        if not (isinstance(cls, type) and issubclass(cls, Procedure)):
            raise PluginError(f"plugin {self.plugin!r}: {cls!r} is not a metro Procedure subclass")
        for attr in ("standard", "item", "title", "clause"):
            if not getattr(cls, attr, None):
                raise PluginError(
                    f"plugin {self.plugin!r}: procedure {cls.__name__} has no {attr!r}"
                )
        if getattr(cls, "__abstractmethods__", None):
            raise PluginError(
                f"plugin {self.plugin!r}: procedure {cls.__name__} does not implement "
                f"{', '.join(sorted(cls.__abstractmethods__))}"
            )
        pid = cls.qualified_id()
        if pid in self.registry.procedures:
            raise self._dup("item", pid, self.registry.procedures[pid].plugin)
        self.registry.procedures[pid] = ProcedureInfo(cls, self.plugin)

    def add_series(
        self, standard: str, name: str, members: Sequence[str], description: str = ""
    ) -> None:
        """A series alias: ``metro run -s standard -i name`` runs those ``members`` (item ids) that
        are registered and apply to the device (``metro_item_applicability``), and says which
        it chose and why.  A name may not be an item id; members need not all be registered yet."""
        if not name or not members:
            raise PluginError(
                f"plugin {self.plugin!r}: series needs a name and at least one member item"
            )
        key = f"{standard}:{name}"
        if key in self.registry.series:
            raise self._dup("series", key, self.registry.series[key].plugin)
        self.registry.series[key] = SeriesInfo(
            standard, name, tuple(members), description, self.plugin
        )


class ReaderRegistrar(Registrar):
    """Validates and records the samples-file formats of one plugin."""

    def add_reader(
        self,
        suffixes: Sequence[str],
        read: Callable[..., Any],
        description: str = "",
        *,
        write: Callable[..., Any] | None = None,
    ) -> None:
        """Register a file format by suffix: ``read`` and, when the format can be written (a
        campaign that ``metro acquire`` writes), ``write`` (see :class:`ReaderInfo`)."""
        if not callable(read):
            raise PluginError(f"plugin {self.plugin!r}: reader for {suffixes} is not callable")
        if write is not None and not callable(write):
            raise PluginError(f"plugin {self.plugin!r}: writer for {suffixes} is not callable")
        sfx = tuple(s.lower() if s.startswith(".") else "." + s.lower() for s in suffixes)
        for s in sfx:
            if s in self.registry.readers:
                raise self._dup("reader for suffix", s, self.registry.readers[s].plugin)
        info = ReaderInfo(sfx, read, description, self.plugin, write)
        for s in sfx:
            self.registry.readers[s] = info


class StationRegistrar(Registrar):
    def add_station(self, name: str, factory: Callable[..., Any], description: str = "") -> None:
        if name in self.registry.stations:
            raise self._dup("station", name, self.registry.stations[name].plugin)
        self.registry.stations[name] = StationInfo(name, factory, description, self.plugin)


class TemplateRegistrar(Registrar):
    def add_template(
        self,
        name: str,
        path: Path | str | None = None,
        *,
        standard: str | None = None,
        kind: str = "report",
        layout: Any = None,
    ) -> None:
        """A docxtpl template file (``path``), or a document layout (``layout``: a function
        ``layout(doc, ctx)`` or its ``"module:function"`` name) built by
        metro.core.documents.document."""
        if (path is None) == (layout is None):
            raise PluginError(
                f"plugin {self.plugin!r}: template {name!r} needs a path or a layout (one of them)"
            )
        p = None if path is None else Path(path)
        if p is not None and not p.is_file():
            raise PluginError(f"plugin {self.plugin!r}: template {name!r} not found at {p}")
        if name in self.registry.templates:
            raise self._dup("template", name, self.registry.templates[name].plugin)
        self.registry.templates[name] = TemplateInfo(name, p, standard, kind, self.plugin, layout)


class DriverRegistrar(Registrar):
    """Validates and records live-instrument drivers for one plugin."""

    def add_driver(self, name: str, kind: str, cls: type, description: str = "") -> None:
        from .drivers import DRIVER_KINDS

        if (
            not isinstance(name, str)
            or not name
            or name != name.strip()
            or any(c.isspace() for c in name)
        ):
            raise PluginError(
                f"plugin {self.plugin!r}: driver name {name!r} must be a non-empty word"
            )
        if kind not in DRIVER_KINDS:
            raise PluginError(
                f"plugin {self.plugin!r}: driver {name!r} has unknown kind {kind!r}; "
                f"kinds: {', '.join(sorted(DRIVER_KINDS))}"
            )
        iface = DRIVER_KINDS[kind]
        if not (isinstance(cls, type) and issubclass(cls, iface)):
            raise PluginError(
                f"plugin {self.plugin!r}: driver {name!r} ({cls!r}) does not subclass "
                f"{iface.__module__}.{iface.__name__}",
                hint=f"derive the driver class from {iface.__name__} and implement its methods",
            )
        missing = sorted(getattr(cls, "__abstractmethods__", ()) or ())
        if missing:
            raise PluginError(
                f"plugin {self.plugin!r}: driver {name!r} ({cls.__name__}) does not implement "
                f"{', '.join(missing)}"
            )
        if name in self.registry.drivers:
            raise self._dup("driver", name, self.registry.drivers[name].plugin)
        self.registry.drivers[name] = DriverInfo(name, kind, cls, description, self.plugin)
