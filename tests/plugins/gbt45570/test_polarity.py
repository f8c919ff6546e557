"""GB/T 45570—2025 6.2.6 polarity and its requirement 5.2.9: hand-worked ratio, simulated gyros of
both polarities (truth within U, the verdict), both output kinds, bad input."""

from __future__ import annotations

import attrs
import pytest
from metro.core.uncertainty.conformity import Status
from metro.core.base.errors import DataError
from metro.core.run.runner import merge_steps, run_items
from metro.instruments.simulated import GyroTruth, SimulatedStation
from metro.plugins.gbt45570.polarity import Polarity626, response_ratio


def _run(pm, truth: GyroTruth, **options):
    proc = pm.procedure("gbt45570", "6.2.6")()
    camp = SimulatedStation(truth=truth).acquire(merge_steps([proc.sequence(options)]))
    return camp, run_items(pm, "gbt45570", ["6.2.6"], campaign=camp, options=options)


def test_response_ratio_hand_worked():
    # at rest 0.12 °/h, turning at +10 °/s the gyro indicates 36 000.12 °/h → r = 36 000/36 000 = 1
    assert response_ratio(0.12, 36000.12, 10.0) == pytest.approx(1.0, rel=1e-15)
    # a reversed gyro: the output falls by the same amount
    assert response_ratio(0.12, -35999.88, 10.0) == pytest.approx(-1.0, rel=1e-15)
    # turning clockwise (−5 °/s) a positive gyro's output falls: r is still +1
    assert response_ratio(1.0, 1.0 - 18000.0, -5.0) == pytest.approx(1.0, rel=1e-15)
    with pytest.raises(ValueError, match="zero"):
        response_ratio(0.0, 1.0, 0.0)


@pytest.mark.parametrize("polarity", [1, -1])
@pytest.mark.parametrize("output", ["pulse", "digital"])
def test_polarity_recovered_with_its_verdict(pm, polarity, output):
    camp, rec = _run(pm, GyroTruth(polarity=polarity, output=output, seed=11))
    res = {r.metric.key: r for r in rec.outcomes[0].results}
    r, U = float(res["polarity_ratio"].value.magnitude), float(res["polarity_ratio"].U.magnitude)
    truth = float(camp.expected["polarity_ratio"].magnitude)
    assert abs(r - truth) <= U, (r, truth, U)
    assert float(res["polarity"].value.magnitude) == polarity
    verdict = next(v for v in rec.conformity.verdicts if v.key == "polarity_ratio")
    assert "5.2.9" in verdict.spec.source
    assert verdict.status is (Status.PASS if polarity > 0 else Status.FAIL)
    warned = any("5.2.9 requires a positive polarity" in w for w in rec.outcomes[0].warnings)
    assert warned is (polarity < 0)


def test_reversed_gyro_negates_every_output_column_and_its_digest(pm):
    proc = pm.procedure("gbt45570", "D.5.1")()
    steps = merge_steps([proc.sequence({})])
    st_plus = SimulatedStation(truth=GyroTruth(seed=3), duration_scale=0.01)
    st_minus = SimulatedStation(truth=GyroTruth(seed=3, polarity=-1), duration_scale=0.01)
    a, b = st_plus.acquire(steps).segments[0], st_minus.acquire(steps).segments[0]
    assert (b.columns()["output"][0] == -a.columns()["output"][0]).all()
    assert a.sha256 != b.sha256
    with pytest.raises(ValueError):
        GyroTruth(polarity=0)


def test_missing_rest_segment_is_a_clear_error(pm):
    camp, _ = _run(pm, GyroTruth(seed=5))
    camp = attrs.evolve(camp, segments=[s for s in camp.segments if s.id != "polarity-rest"])
    with pytest.raises(DataError, match="at rest"):
        run_items(pm, "gbt45570", ["6.2.6"], campaign=camp)


def test_a_turn_too_slow_to_read_the_sign_is_an_error_not_a_guess(pm):
    # 1e-6 °/s = 0.0036 °/h, far below the output's noise over a few seconds
    with pytest.raises(DataError, match="cannot be read"):
        _run(pm, GyroTruth(seed=5), rate="1e-6 deg/s", duration="5 s")


def test_plan_lists_rest_then_turn(pm):
    steps = Polarity626().sequence({"rate": "20 deg/s"})
    assert [s.segment for s in steps] == ["polarity-rest", "polarity-turn"]
    assert [s.conditions["rate"] for s in steps] == ["0 deg/s", "20 deg/s"]
