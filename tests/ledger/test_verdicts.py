"""Each claim's threshold exists once: the verdict functions that the chapters assert and the
ledger's checks judge, tried on cases whose answer is known."""

from types import SimpleNamespace

import numpy as np
import pytest

from roughgp import targets
from roughgp.experiments import measured_surfaces as ms
from roughgp.experiments.prescribed_targets import target_verdicts

GOAL = targets.RoughnessTargets(Sq=0.3, Sal=6.0, Str=0.1, Std=-20.0)


def _values(n=20, seed=0, **shift):
    rng = np.random.default_rng(seed)
    out = {k: getattr(GOAL, k) * (1 + 0.05 * rng.standard_normal(n)) for k in ("Sq", "Sal",
                                                                                "Str")}
    out["Std"] = GOAL.Std + 1.0 * rng.standard_normal(n)
    for k, v in shift.items():
        out[k] = out[k] + v
    return out


def test_prescribed_verdicts_hold_on_target_and_fail_off_it():
    assert all(target_verdicts(GOAL, _values(), (0.3, 0.015)).values())
    off = target_verdicts(GOAL, _values(Sal=1.0), (0.3, 0.015))  # 16 % too long
    assert [k for k, v in off.items() if not v] == [
        "the mean Sal within 4 standard errors of its target"]
    assert not all(target_verdicts(GOAL, _values(Std=5.0), (0.3, 0.015)).values())
    assert not all(target_verdicts(GOAL, _values(), (0.2, 0.015)).values())  # Sq predicted


def _fit(angle_deg, lambda_a, lambda_b):
    hp = {"angle_deg": angle_deg, "lambda_a_um": lambda_a, "lambda_b_um": lambda_b}
    return SimpleNamespace(model=SimpleNamespace(hyperparameters=hp))


@pytest.mark.parametrize("angle, la, lb, holds", [
    (95.0, 30.0, 10.0, True),     # along y, weak anisotropy
    (60.0, 30.0, 10.0, False),    # 30 deg off the striations
    (92.0, 100.0, 1.0, False),    # figure 2's strong anisotropy
])
def test_land_fit_verdicts(angle, la, lb, holds):
    assert all(ms.land_fit_verdicts(_fit(angle, la, lb)).values()) == holds


def _parameter(name, measured, low, high):
    return SimpleNamespace(name=name, measured=measured, low=low, high=high,
                           median=(low + high) / 2, outside=not low <= measured <= high)


@pytest.mark.parametrize("sku, std, str_, sq, holds", [
    (30.0, 90.0, 0.05, 7.0, True),
    (5.0, 90.0, 0.05, 7.0, False),     # Sku outside, but not beyond twice the largest
    (30.0, 10.0, 0.05, 7.0, False),    # Std outside
    (30.0, 90.0, 0.5, 7.0, False),     # Str inside
    (30.0, 90.0, 0.05, 3.5, False),    # Sq outside, but not twice the median
    (30.0, 90.0, 0.05, 2.5, False),    # Sq inside
])
def test_land_check_verdicts(sku, std, str_, sq, holds):
    check = SimpleNamespace(parameters=[_parameter("Sku", sku, 2.5, 4.0),
                                        _parameter("Std", std, 80.0, 100.0),
                                        _parameter("Str", str_, 0.2, 0.4),
                                        _parameter("Sq", sq, 2.0, 3.0)])
    assert all(ms.land_check_verdicts(check).values()) == holds


def test_one_rule_decides_quick_against_full(monkeypatch):
    from roughgp.common import settings
    monkeypatch.delenv("ROUGHGP_FULL", raising=False)
    assert settings.pick(1, 2) == 1 and settings.pick(1, 2, full=True) == 2
    monkeypatch.setenv("ROUGHGP_FULL", "1")
    assert settings.pick(1, 2) == 2 and settings.pick(1, 2, full=False) == 1
    assert settings.resolve_full(None) and not settings.resolve_full(False)
