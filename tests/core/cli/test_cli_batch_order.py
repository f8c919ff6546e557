"""`metro batch` with a lab profile numbers the devices' reports in the lot's order, whatever
order the workers finish them in (issue 29: dev2 → 00003, dev1 → 00004 was the finishing order)."""

from __future__ import annotations

import contextlib
import datetime as dt
import threading
import time

import pytest

from metro.core.cli.app import main


@pytest.fixture
def lab(tmp_path, monkeypatch, capsys):
    path = tmp_path / "lab.toml"
    assert main(["lab", "init", str(path)]) == 0
    capsys.readouterr()
    monkeypatch.delenv("METRO_REGISTER", raising=False)
    monkeypatch.delenv("METRO_LAB", raising=False)
    return path


def test_reports_are_numbered_in_lot_order_when_the_first_finishes_last(lab, tmp_path, monkeypatch,
                                                                        campaign_factory):
    """dev1 (first in the lot) is held until dev2 has been evaluated, so dev2 finishes first; the
    register still numbers dev1 before dev2.  The workers are threads of this process (a local
    cluster without processes, reached by its address as an existing cluster would be), so the
    evaluation can be held from here."""
    from distributed import LocalCluster

    import metro.core.cli.batch as batch
    import metro.core.run.runner as runner
    from metro.instruments.simulated import GyroTruth

    manifests = [campaign_factory.write_campaign(tmp_path / "lot" / name, hours=0.3,
                                                 truth=GyroTruth(seed=seed))
                 for name, seed in (("dev1", 21), ("dev2", 22))]
    second_evaluated = threading.Event()
    real = runner.run_items

    def held(pm, standard, items, *args, data=None, **kw):
        if "dev1" in str(data):
            assert second_evaluated.wait(120)
            time.sleep(1.0)  # and, without lot order, dev2's number would be allocated by now
        record = real(pm, standard, items, *args, data=data, **kw)
        if "dev2" in str(data):
            second_evaluated.set()
        return record

    monkeypatch.setattr(runner, "run_items", held)
    # two worker threads at once
    monkeypatch.setattr(batch, "_ONE_AT_A_TIME", contextlib.nullcontext())
    out = tmp_path / "out"
    job = batch.Job("gbt45570", ["D.5.1"], out=str(out), autoload=False, lab=str(lab))
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                      dashboard_address=None) as cluster:
        summary = batch.run_batch(job, manifests, scheduler=cluster.scheduler_address)
    devices = {d["name"]: d for d in summary["devices"]}
    assert [devices[n]["status"] for n in ("dev1", "dev2")] == ["evaluated", "evaluated"], devices
    year = dt.datetime.now(dt.timezone.utc).year
    assert devices["dev1"]["report_number"] == f"EML{year}-00001"
    assert devices["dev2"]["report_number"] == f"EML{year}-00002"
    assert (out / "devices" / "dev1" / f"EML{year}-00001.docx").is_file()
