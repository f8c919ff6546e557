"""A typed wrapper around pluggy's plugin manager; the registrars plugins talk to are in
:mod:`metro.core.model.registry` (re-exported here).

The core never calls ``pm.hook.…`` directly: it calls the typed methods of
:class:`MetroPluginManager`.  Registration hooks are called once per plugin with a
registrar bound to that plugin's name, so every registered thing knows where it came from
and duplicates are reported with both names.

Loading: plugins come from the ``metro`` entry-point group — metro's own built-ins
included.  ``METRO_DISABLE_PLUGIN_AUTOLOAD=1`` (or ``--no-plugin-autoload``) loads only the
built-ins of the ``metro`` distribution, plus any named in ``METRO_PLUGINS``;
``METRO_BLOCK_PLUGINS=a,b`` (or ``--block-plugin a``) blocks plugins by name.
"""

from __future__ import annotations

import functools
import importlib
import os
import sys
import types
from importlib import resources
from importlib import metadata
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Iterable, Mapping, Sequence

import pluggy

from ..model import hookspec
from ..model.registry import (DriverInfo, DriverRegistrar, PluginInfo, ProcedureInfo, ReaderInfo,
                              ReaderRegistrar, Registrar, Registry, SeriesInfo, StandardInfo,
                              StandardRegistrar, StationInfo, StationRegistrar, TemplateInfo,
                              TemplateRegistrar)
from ..base.errors import PluginError
from ..base.locale import add_catalogs
from ..base.extras import DISTRIBUTION
from ..model.campaign import Campaign
from ..model.results import Outcome
from ..model.procedure import Procedure, RunContext
from ..base.units import add_definitions

if TYPE_CHECKING:  # pragma: no cover
    from ..uncertainty.conformity import Specification
    from ..model.procedure import Applicability

__all__ = [
    "ENTRY_POINT_GROUP", "MetroPluginManager", "get_plugin_manager", "builtin_plugin_manager",
    "item_sort_key", "StandardInfo", "ProcedureInfo", "SeriesInfo", "ReaderInfo", "StationInfo",
    "DriverInfo", "TemplateInfo", "PluginInfo", "Registry", "Registrar", "StandardRegistrar",
    "ReaderRegistrar", "StationRegistrar", "TemplateRegistrar", "DriverRegistrar",
]

ENTRY_POINT_GROUP = "metro"
BUILTIN_DIST = DISTRIBUTION  # metro's own plugins come from metro's distribution

# --------------------------------------------------------------------------------------
# The manager
# --------------------------------------------------------------------------------------


def item_sort_key(item: str) -> tuple:
    """Order item ids as the standards number them: 7.2.2 before 7.2.10, D.1.6 before D.2.1."""
    import re

    return tuple((0, int(t), "") if t.isdigit() else (1, 0, t) for t
                 in re.findall(r"\d+|[^\d.:]+", item))


def _env_list(name: str) -> list[str]:
    return [x.strip() for x in os.environ.get(name, "").split(",") if x.strip()]


class MetroPluginManager:
    """metro's plugin manager: loads plugins, runs registration, exposes typed hook calls."""

    def __init__(self) -> None:
        self.pm = pluggy.PluginManager(hookspec.PROJECT)
        self.pm.add_hookspecs(hookspec)
        self.registry = Registry()
        self.plugins: dict[str, PluginInfo] = {}
        self._registered = False

    # -- loading ------------------------------------------------------------------------
    def load(
        self,
        *,
        autoload: bool | None = None,
        block: Iterable[str] = (),
        extra: Iterable[str] = (),
    ) -> "MetroPluginManager":
        """Load plugins from the entry-point group, honouring autoload/block settings."""
        if autoload is None:
            autoload = os.environ.get("METRO_DISABLE_PLUGIN_AUTOLOAD", "") in ("", "0")
        blocked = set(block) | set(_env_list("METRO_BLOCK_PLUGINS"))
        wanted = set(extra) | set(_env_list("METRO_PLUGINS"))
        for name in blocked:
            self.pm.set_blocked(name)
        for ep in metadata.entry_points(group=ENTRY_POINT_GROUP):
            dist = ep.dist.metadata["Name"] if ep.dist is not None else None
            builtin = dist is not None and dist.lower().replace("_", "-") == BUILTIN_DIST
            if ep.name in blocked or self.pm.is_blocked(ep.name) or ep.name in self.plugins:
                continue
            if not (autoload or builtin or ep.name in wanted):
                continue
            try:
                obj = ep.load()
            except Exception as exc:  # a broken third-party plugin must say who it is
                raise PluginError(
                    f"plugin {ep.name!r} (entry point {ep.value}, distribution {dist}) failed to "
                    f"load: {exc}",
                    hint=f"block it with METRO_BLOCK_PLUGINS={ep.name} or fix/uninstall {dist}",
                ) from exc
            version = ep.dist.version if ep.dist is not None else None
            self.add_plugin(obj, ep.name, distribution=dist, version=version, builtin=builtin)
        for name in wanted - set(self.plugins):
            if name in blocked:
                continue
            # METRO_PLUGINS may also name an importable module directly
            try:
                mod = importlib.import_module(name)
            except ImportError as exc:
                raise PluginError(f"plugin {name!r} named in METRO_PLUGINS cannot be imported: "
                                  f"{exc}") from exc
            # an installed plugin named by its module: loaded already
            if self.pm.is_registered(mod):
                continue
            self.add_plugin(mod, name)
        return self

    def add_plugin(self, obj: Any, name: str, *, distribution: str | None = None,
                   version: str | None = None, builtin: bool = False) -> None:
        """Register a plugin object (module or instance) under ``name``."""
        if self._registered:
            raise PluginError(f"plugin {name!r} added after registration ran; add plugins first")
        if name in self.plugins:
            raise PluginError(f"two plugins are called {name!r}")
        if self.pm.is_blocked(name):
            return
        self.pm.register(obj, name=name)
        self.plugins[name] = PluginInfo(name, getattr(obj, "__name__", type(obj).__name__),
                                        distribution, version, builtin)

    # -- registration ---------------------------------------------------------------------
    def _call_each(self, hook_name: str, registrar_cls: type[Registrar]) -> None:
        caller = getattr(self.pm.hook, hook_name)
        # call each implementation separately so the registrar knows who is registering;
        # sorted by plugin name so the outcome never depends on registration order
        for impl in sorted(caller.get_hookimpls(), key=lambda i: i.plugin_name):
            reg = registrar_cls(self.registry, impl.plugin_name)
            impl.function(registrar=reg)

    def register_all(self) -> Registry:
        """Run the set-up and registration phases once; return the registry."""
        if self._registered:
            return self.registry
        for impl in sorted(self.pm.hook.metro_unit_definitions.get_hookimpls(),
                           key=lambda i: i.plugin_name):
            lines = impl.function() or ()
            add_definitions(lines, source=f"plugin {impl.plugin_name}")
        self._call_each("metro_register_standards", StandardRegistrar)
        self._call_each("metro_register_readers", ReaderRegistrar)
        self._call_each("metro_register_stations", StationRegistrar)
        self._call_each("metro_register_templates", TemplateRegistrar)
        self._call_each("metro_register_drivers", DriverRegistrar)
        for key, ser in self.registry.series.items():
            if key in self.registry.procedures:
                raise PluginError(f"plugin {ser.plugin!r}: series {key!r} has the id of an item")
        for pid, info in self.registry.procedures.items():
            if info.cls.standard not in self.registry.standards:
                raise PluginError(
                    f"plugin {info.plugin!r} registered item {pid!r} of standard "
                    f"{info.cls.standard!r}, which no loaded plugin registers"
                )
        self._registered = True
        for folder in self.catalog_folders().values():  # plugins' own translations
            add_catalogs(folder)
        return self.registry

    # -- typed lookups ----------------------------------------------------------------------
    def procedure(self, standard: str, item: str) -> type[Procedure]:
        reg = self.register_all()
        if standard not in reg.standards:
            raise PluginError(
                f"unknown standard {standard!r}; loaded: "
                f"{', '.join(sorted(reg.standards)) or 'none'}",
                hint="`metro plugins` lists loaded plugins; `metro items` lists every item",
            )
        pid = f"{standard}:{item}"
        if pid not in reg.procedures:
            items = sorted((p.cls.item for p in reg.procedures.values() if p.cls.standard
                            == standard),
                           key=item_sort_key)
            raise PluginError(f"standard {standard!r} has no item {item!r}; its items: "
                              f"{', '.join(items)}")
        return reg.procedures[pid].cls

    def procedures_of(self, standard: str) -> list[type[Procedure]]:
        reg = self.register_all()
        return [p.cls for p in reg.procedures.values() if p.cls.standard == standard]

    def series(self, standard: str, name: str) -> SeriesInfo | None:
        """The series ``name`` of ``standard``, or ``None`` if there is none by that name."""
        return self.register_all().series.get(f"{standard}:{name}")

    def item_applicability(self, procedure: type[Procedure], device: Any) -> "Applicability":
        """Whether ``procedure`` applies to ``device``: the first plugin that answers
        ``metro_item_applicability``, else the procedure's own ``applies_to``."""
        from ..model.procedure import Applicability

        ans = self.pm.hook.metro_item_applicability(procedure=procedure, device=device)
        if ans is None:
            ans = procedure.applies_to(device)
        if not isinstance(ans, Applicability):
            raise PluginError(f"applicability of {procedure.qualified_id()} is {ans!r}, not an "
                              "Applicability")
        return ans

    def conformity_specifications(self, standard: str, campaign: Campaign) -> list["Specification"]:
        """Every plugin's specifications for ``standard`` (checked, in plugin-name order)."""
        from ..uncertainty.conformity import Specification

        out: list[Specification] = []
        caller = self.pm.hook.metro_conformity_specifications
        for impl in sorted(caller.get_hookimpls(), key=lambda i: i.plugin_name):
            given = {"standard": standard, "campaign": campaign}
            specs = impl.function(**{k: v for k, v in given.items() if k in impl.argnames})
            for s in specs or ():
                if not isinstance(s, Specification):
                    raise PluginError(f"plugin {impl.plugin_name!r} returned {s!r} as a "
                                      "specification; return "
                                      "metro.core.uncertainty.conformity.Specification values")
                out.append(s)
        return out

    def expected_values(self, campaign: Campaign, ideal: Mapping[str, Any]) -> dict[str, Any]:
        """The expected values every plugin's ``metro_expected_values`` computes from the noise-free
        quantities a simulated station declares in ``ideal``, merged in plugin-name order."""
        out: dict[str, Any] = {}
        caller = self.pm.hook.metro_expected_values
        for impl in sorted(caller.get_hookimpls(), key=lambda i: i.plugin_name):
            got = impl.function(campaign=campaign, ideal=ideal)
            if got is None:
                continue
            if not isinstance(got, Mapping) or not all(isinstance(k, str) for k in got):
                raise PluginError(f"plugin {impl.plugin_name!r} returned {got!r} as expected "
                                  "values; return a mapping of metric keys to quantities")
            out |= got
        return out

    def reader_for(self, path: Path) -> ReaderInfo:
        reg = self.register_all()
        sfx = path.suffix.lower()
        if sfx not in reg.readers:
            from ..base.errors import DataError

            raise DataError(
                str(path), None,
                f"no reader for files ending in {sfx!r}; readers exist for "
                f"{', '.join(sorted(reg.readers))}",
            )
        return reg.readers[sfx]

    def writer_for(self, suffix: str) -> Callable[..., Any]:
        """The ``write`` of the format registered for files ending in ``suffix`` (``".csv"``);
        a :class:`~metro.core.base.errors.DataError` naming the writable suffixes when none is."""
        reg = self.register_all()
        sfx = suffix.lower() if suffix.startswith(".") else "." + suffix.lower()
        info = reg.readers.get(sfx)
        if info is None or info.write is None:
            from ..base.errors import DataError

            can = sorted(s for s, r in reg.readers.items() if r.write is not None)
            raise DataError(None, None, f"no writer is registered for files ending in {sfx!r}; "
                            f"writers exist for {', '.join(can) or 'no suffix'}",
                            hint="a plugin registers one with registrar.add_reader(..., write=...)")
        return info.write

    def station(self, name: str) -> StationInfo:
        reg = self.register_all()
        if name not in reg.stations:
            raise PluginError(f"unknown station {name!r}; available: "
                              f"{', '.join(sorted(reg.stations))}")
        return reg.stations[name]

    def driver(self, name: str) -> DriverInfo:
        reg = self.register_all()
        if name not in reg.drivers:
            raise PluginError(f"unknown driver {name!r}; available: "
                              f"{', '.join(sorted(reg.drivers)) or 'none'}",
                              hint="`metro plugins` lists the loaded plugins; drivers come from "
                              "metro_register_drivers")
        return reg.drivers[name]

    def drivers_of(self, kind: str) -> list[DriverInfo]:
        """Registered drivers of one kind (``rate-table``, ``dmm``, ``gyro-output``), by name."""
        reg = self.register_all()
        return [d for _, d in sorted(reg.drivers.items()) if d.kind == kind]

    def template_for(self, standard: str | None, kind: str = "report") -> TemplateInfo:
        reg = self.register_all()
        for t in sorted(reg.templates.values(), key=lambda t: t.name):
            if t.standard == standard and t.kind == kind:
                return t
        for t in sorted(reg.templates.values(), key=lambda t: t.name):
            if t.standard is None and t.kind == kind:
                return t
        raise PluginError(f"no {kind} template registered for {standard!r} and no generic one")

    def plugin_packages(self) -> dict[str, str]:
        """{plugin name: the package its module belongs to} (``metro.plugins.gbt45570``; a
        plugin that is a module of a package, or an object, gives that module's package; a
        plugin that is a top-level module belongs to no package and is left out)."""
        out = {}
        for name, obj in sorted(self.pm.list_name_plugin(), key=lambda p: p[0]):
            mod = obj if isinstance(obj,
                                    types.ModuleType) else sys.modules.get(type(obj).__module__)
            package = None if mod is None else (
                mod.__name__ if hasattr(mod, "__path__") else mod.__package__)
            if package:
                out[name] = package
        return out

    def catalog_folders(self) -> dict[str, Any]:
        """{plugin name: its package's ``locale`` folder} for the plugins that ship their own
        message catalogs (``locale/zh/LC_MESSAGES/<name>.po`` next to the package's
        ``__init__.py``; :func:`metro.core.base.locale.add_catalogs`)."""
        out = {}
        for name, package in self.plugin_packages().items():
            try:
                folder = resources.files(package) / "locale"
            except (ImportError, AttributeError, TypeError, ValueError):  # no package on disk
                continue
            if folder.is_dir():
                out[name] = folder
        return out

    def versions(self) -> dict[str, str]:
        """{plugin name: 'distribution version'} for provenance."""
        return {
            n: f"{p.distribution or p.module} {p.version or ''}".strip() for n, p
            in sorted(self.plugins.items())
        }

    # -- lifecycle events -------------------------------------------------------------------
    def campaign_loaded(self, campaign: Campaign) -> None:
        self.pm.hook.metro_campaign_loaded(campaign=campaign)

    def procedure_started(self, procedure: Procedure, campaign: Campaign, ctx: RunContext) -> None:
        self.pm.hook.metro_procedure_started(procedure=procedure, campaign=campaign, ctx=ctx)

    def procedure_finished(self, procedure: Procedure, outcome: Outcome) -> None:
        self.pm.hook.metro_procedure_finished(procedure=procedure, outcome=outcome)

    def extend_report_context(self, record: Any, context: dict) -> None:
        self.pm.hook.metro_extend_report_context(record=record, context=context)

    def report_written(self, path: Path, outcomes: Sequence[Outcome]) -> None:
        self.pm.hook.metro_report_written(path=path, outcomes=list(outcomes))


def get_plugin_manager(
    *, autoload: bool | None = None, block: Iterable[str] = (), extra: Iterable[str] = ()
) -> MetroPluginManager:
    """A loaded, registered plugin manager (the usual way in)."""
    pm = MetroPluginManager().load(autoload=autoload, block=block, extra=extra)
    pm.register_all()
    return pm


@functools.lru_cache(maxsize=1)
def builtin_plugin_manager() -> MetroPluginManager:
    """A registered plugin manager with metro's built-in plugins only (no third-party autoload),
    made once: what code that is given no manager uses (a campaign written without one, a station
    made directly rather than through the registry)."""
    return get_plugin_manager(autoload=False)
