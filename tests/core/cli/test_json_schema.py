"""Every ``--json`` document metro prints carries ``schema_version`` and validates against the
JSON Schema of its command (core/cli/schemas, docs/json.md); option values are written as what
they are (None → null, numbers → numbers, quantities → {"value", "unit"})."""

from __future__ import annotations

import ast
import contextlib
import io
import json
from pathlib import Path

import pytest

jsonschema = pytest.importorskip("jsonschema")

ROOT = Path(__file__).resolve().parents[3]
SIM_GBT = [
    "run",
    "-s",
    "gbt45570",
    "-i",
    "D.5.6",
    "--station-option",
    "duration_scale=0.05",
    "--no-progress",
]


def _main(*argv: str) -> tuple[int, str]:
    from metro.core.cli.app import main

    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        code = main(list(argv))
    return code, out.getvalue()


def _doc(*argv: str) -> dict:
    code, out = _main(*argv, "--json")
    assert out.strip(), (argv, code)

    def refuse(name):  # NaN and Infinity are not JSON
        raise AssertionError(f"{name} in the output of {argv}")

    return json.loads(out, parse_constant=refuse)


@pytest.fixture(scope="module")
def documents(tmp_path_factory) -> dict[str, list[dict]]:
    """Each schema's name → the documents its command printed: runs on the simulated station and
    on a recorded campaign, registered with a lab profile, then every register command."""
    import importlib.util

    tmp = tmp_path_factory.mktemp("json")
    spec = importlib.util.spec_from_file_location(
        "metro_tests_cf_json", ROOT / "tests" / "campaign_factory.py"
    )
    factory = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(factory)
    docs: dict[str, list[dict]] = {}

    def add(name: str, *argv: str) -> dict:
        d = _doc(*argv)
        docs.setdefault(name, []).append(d)
        return d

    with pytest.MonkeyPatch.context() as mp:
        lab = tmp / "lab.toml"
        add("lab-init", "lab", "init", str(lab))
        mp.setenv("METRO_LAB", str(lab))
        mp.delenv("METRO_REGISTER", raising=False)
        add("lab-show", "lab", "show")
        add("plugins", "plugins")
        add("items", "items")
        add("plan", "plan", "-s", "gbt45570", "-i", "D.5.1,D.5.6")
        add("plan", "plan", "-s", "jjf2014", "-i", "7.2.13")
        add("doctor", "doctor")
        out = str(tmp / "out")
        add("run", *SIM_GBT, "--seed", "1", "--no-report")
        add("run", "run", "-s", "ogam", "--all", "--monte-carlo", "--no-progress", "--seed", "1",
            "--no-report")
        sim = add("run", *SIM_GBT, "--seed", "1", "--out", out, "--register-simulated")
        add(
            "run",
            "run",
            "-s",
            "jjf2014",
            "-i",
            "7.2.3",
            "--no-progress",
            "--seed",
            "2",
            "--out",
            out,
        )
        manifest = factory.write_campaign(tmp / "camp", hours=0.3)
        data = add(
            "run", "run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(manifest), "--out", out
        )
        add("register-list", "register", "list")
        add("register-show", "register", "show", sim["report_number"])
        add("register-show", "register", "show", data["report_number"])
        add("report", "report", sim["report_number"], "--out", str(tmp / "again"))
        add("amend", "amend", data["report_number"], "--reason", "customer name corrected")
        add("withdraw", "withdraw", sim["report_number"], "--reason", "wrong device")
        add("register-verify", "register", "verify")
        add("history", "history", "0042", "--out", str(tmp / "history"))
        add("error", "run", "-s", "nosuch", "-i", "D.5.1")
        add("error", "register", "show", "NO-SUCH-NUMBER")
    return docs


def test_every_schema_is_a_2020_12_schema_and_ships_in_docs():
    from metro.core.cli.schemas import SCHEMAS, schema

    folder = ROOT / "core" / "cli" / "schemas"
    names = {p.name.removesuffix(".schema.json") for p in folder.glob("*.schema.json")}
    assert names == {*SCHEMAS, "common"}
    for name in names:
        s = schema(name)
        jsonschema.Draft202012Validator.check_schema(s)
        assert (
            s["$schema"] == "https://json-schema.org/draft/2020-12/schema"
            and s["$id"] == f"urn:metro:json:{name}"
        )
        copy = ROOT / "docs" / "json" / f"{name}.schema.json"
        assert copy.read_text(encoding="utf-8") == (folder / f"{name}.schema.json").read_text(
            encoding="utf-8"
        ), name


def _json_commands() -> set[str]:
    """Every command and subcommand taking --json, as a schema name (``register-list``)."""
    import argparse

    from metro.core.cli.app import build_parser

    found: set[str] = set()

    def walk(parser: argparse.ArgumentParser, path: tuple[str, ...]) -> None:
        if any("--json" in a.option_strings for a in parser._actions):
            found.add("-".join(path))
        for a in parser._actions:
            if isinstance(a, argparse._SubParsersAction):
                for name, sub in a.choices.items():
                    walk(sub, (*path, name))

    walk(build_parser(), ())
    return found


def test_every_json_command_has_a_schema_and_is_validated_here(documents):
    from metro.core.cli.schemas import SCHEMAS

    commands = _json_commands()
    assert commands <= set(SCHEMAS), commands - set(SCHEMAS)
    assert set(SCHEMAS) - commands == {"error"}  # the error document: any command's
    # batch: test_batch_summary_validates; validate: tests/core/cli/test_validate.py
    assert set(documents) == set(SCHEMAS) - {"batch", "validate"}


@pytest.mark.parametrize(
    "name",
    [
        "run",
        "items",
        "plugins",
        "plan",
        "register-list",
        "register-show",
        "register-verify",
        "report",
        "amend",
        "withdraw",
        "history",
        "lab-init",
        "lab-show",
        "doctor",
        "error",
    ],
)
def test_each_command_document_validates_against_its_schema(documents, name):
    from metro.core.cli.schemas import SCHEMA_VERSION, validator

    v = validator(name)
    for doc in documents[name]:
        assert doc["schema_version"] == SCHEMA_VERSION and next(iter(doc)) == "schema_version"
        errors = [f"{list(e.absolute_path)}: {e.message}" for e in v.iter_errors(doc)]
        assert not errors, errors[:5]


def test_a_schema_refuses_what_its_command_does_not_print(documents):
    """The schemas are not placeholders: a field of the wrong type, a missing one or an unknown
    one is refused."""
    from metro.core.cli.schemas import validator

    run = documents["run"][-1]
    v = validator("run")
    for change in (
        lambda d: d["results"][0].__setitem__("value", "0.12"),
        lambda d: d.pop("schema_version"),
        lambda d: d.__setitem__("extra", 1),
        lambda d: d["provenance"].__setitem__("created", "yesterday"),
        lambda d: d["results"][0].__setitem__("unit", ""),
        lambda d: d["site"].__setitem__("latitude", {"value": 39.98}),
    ):
        bad = json.loads(json.dumps(run))
        change(bad)
        assert not v.is_valid(bad)


@pytest.mark.slow
def test_batch_summary_validates(tmp_path, campaign_factory):
    pytest.importorskip("distributed")
    from metro.core.cli.schemas import SCHEMA_VERSION, validator

    manifest = campaign_factory.write_campaign(tmp_path / "lot" / "unit-1", hours=0.2)
    out = tmp_path / "batch"
    doc = _doc(
        "batch",
        "-s",
        "gbt45570",
        "-i",
        "D.5.1",
        "--data",
        str(manifest),
        "--workers",
        "1",
        "--out",
        str(out),
        "--no-progress",
    )
    errors = [f"{list(e.absolute_path)}: {e.message}" for e in validator("batch").iter_errors(doc)]
    assert not errors, errors[:5]
    assert (
        json.loads((out / "lot-summary.json").read_text(encoding="utf-8"))["schema_version"]
        == SCHEMA_VERSION
    )
    (device,) = doc["devices"]
    kept = json.loads(Path(device["json"]).read_text(encoding="utf-8"))
    assert kept["schema_version"] == SCHEMA_VERSION and validator("run").is_valid(kept)


def test_no_command_prints_json_past_the_schema_version():
    """Every JSON document leaves core/cli through metro.core.cli.schemas (print_json, dumps,
    document), which puts schema_version first: no other json.dumps in the command line."""
    offenders = []
    for path in sorted((ROOT / "core" / "cli").rglob("*.py")):
        if path.parent.name == "schemas":
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if (
                isinstance(node, ast.Call)
                and isinstance(node.func, ast.Attribute)
                and node.func.attr == "dumps"
                and isinstance(node.func.value, ast.Name)
                and node.func.value.id == "json"
            ):
                offenders.append(f"{path.relative_to(ROOT)}:{node.lineno}")
    # batch's resume state is metro's own file, read back by metro only
    assert offenders == ["core/cli/batch.py:" + str(_state_writer_line())], offenders


def _state_writer_line() -> int:
    text = (ROOT / "core" / "cli" / "batch.py").read_text(encoding="utf-8").splitlines()
    start = next(i for i, ln in enumerate(text) if ln.startswith("def _write_json_atomically"))
    return next(i for i in range(start, len(text)) if "json.dumps" in text[i]) + 1


def test_options_are_written_as_what_they_are(documents):
    """D.5.6's options were written "segment": "None", "min_blocks": "10": None is null, a count
    a number — in the run's document and in the register."""
    sim = documents["run"][0]
    (item,) = sim["items"]
    assert item["options"] == {"segment": None, "min_blocks": 10}
    show = documents["register-show"][0]
    assert show["options"]["D.5.6"] == {"segment": None, "min_blocks": 10}
    plan = documents["plan"][0]
    (step,) = plan["steps"]
    assert step["duration"] == {"value": 8, "unit": "h"} and step["warmup"] == {
        "value": 30,
        "unit": "min",
    }
    assert step["interval"] == {"value": 1, "unit": "s"} and step["conditions"] == {
        "orientation": "IRA up"
    }
    lab = documents["lab-show"][0]
    assert lab["equipment"][0]["U"] == {"value": 5e-06, "unit": "1"}


def test_option_value_reads_an_items_text_back():
    from metro.core.base.units import Q_
    from metro.core.model.record_json import json_value, option_value

    assert option_value("None") is None and option_value("False") is False
    assert (
        option_value("10") == 10
        and isinstance(option_value("10"), int)
        and option_value("-2.5e-3") == -0.0025
    )
    assert option_value("10 s") == {"value": 10, "unit": "s"}
    assert option_value("0.5 deg/h") == {"value": 0.5, "unit": "°/h"}
    for text in (
        "IRA up",
        "10 s, 100 s",
        "-40, -10, 20",
        "static-8h",
        "10 furlongs per fortnight x",
    ):
        assert option_value(text) == text
    assert option_value(Q_(3, "ppm")) == {"value": 3, "unit": "ppm"}
    assert json_value(float("nan")) is None and json_value((1, float("inf"))) == [1, None]
    assert json_value({"t": Q_(20.0, "degC")}) == {"t": {"value": 20.0, "unit": "°C"}}


def test_docs_list_every_schema_and_its_top_level_fields():
    from metro.core.cli.schemas import SCHEMA_VERSION, SCHEMAS, schema

    text = (ROOT / "docs" / "json.md").read_text(encoding="utf-8")
    assert f'"schema_version": "{SCHEMA_VERSION}"' in text
    for name in SCHEMAS:
        assert f"json/{name}.schema.json" in text, name
        section = text.split(f"json/{name}.schema.json", 1)[1].split("\n## ", 1)[0]
        for field in schema(name).get("properties", {}):
            assert f"`{field}`" in section, (name, field)


def _imported(path: Path, node: ast.AST) -> list[str]:
    """The absolute module names an import statement of ``path`` (under core/) names."""
    rel = path.relative_to(ROOT / "core").with_suffix("").parts
    package = ["metro", "core", *rel[:-1]]
    if isinstance(node, ast.Import):
        return [a.name for a in node.names]
    if not isinstance(node, ast.ImportFrom):
        return []
    base = node.module.split(".") if node.level == 0 and node.module else []
    if node.level:
        base = package[: len(package) - (node.level - 1)] + (
            node.module.split(".") if node.module else []
        )
    return [".".join(base)] + [".".join([*base, a.name]) for a in node.names]


def test_no_lower_layer_imports_the_command_line():
    """core/cli is the top layer: nothing below it imports it (the register took the run's JSON
    form from core/cli/present.py; it is metro.core.model.record_json now)."""
    offenders = []
    for layer in ("base", "stats", "uncertainty", "model", "run", "documents", "record"):
        for path in sorted((ROOT / "core" / layer).rglob("*.py")):
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                if any(
                    n == "metro.core.cli" or n.startswith("metro.core.cli.")
                    for n in _imported(path, node)
                ):
                    offenders.append(f"{path.relative_to(ROOT)}:{node.lineno}")
    assert not offenders, offenders
