"""Tests of roughgp.ledger.setups: the search claims under several numerical set-ups."""

from __future__ import annotations

import sys
import textwrap

import pytest

from roughgp.ledger import setups
from roughgp.ledger.runner import claim
from roughgp.ledger.types import Outcome


def test_the_search_claims_are_marked_in_the_ledger():
    keys = setups.search_keys()
    assert {"fig7-flaw", "fig7-cause", "fig5-periodicity", "measured-land-check"} <= set(keys)
    assert "eq5-duality" not in keys                       # closed form: nothing to search


def test_a_setup_sets_threads_and_jitter_and_drops_the_results_cache():
    env = setups.Setup(2, 5).environment({"ROUGHGP_RESULTS_CACHE": "/x", "PATH": "/bin"})
    assert env["OPENBLAS_NUM_THREADS"] == env["OMP_NUM_THREADS"] == "2"
    assert env["ROUGHGP_START_JITTER"] == "5" and env["PATH"] == "/bin"
    assert "ROUGHGP_RESULTS_CACHE" not in env
    with pytest.raises(ValueError, match="blas_threads"):
        setups.Setup(0, 0)
    with pytest.raises(ValueError, match="start_jitter"):
        setups.Setup(1, -1)
    with pytest.raises(ValueError, match="at least two"):
        setups.run_setups(["eq5-duality"], [setups.Setup(1, 0)])


def _run(setup, holds, value="v"):
    return setups.SetupRun(setup, [Outcome(claim("eq5-duality"), value, holds, 0.1),
                                   Outcome(claim("fig7-flaw"), value, True, 0.1)], 0.2)


def test_differences_name_the_claim_and_the_setups_on_each_side():
    a, b = setups.Setup(1, 0), setups.Setup(2, 1)
    assert setups.differences([_run(a, True), _run(b, True, "w")]) == []   # values may move
    lines = setups.differences([_run(a, True), _run(b, False)])
    assert len(lines) == 1 and lines[0].startswith("eq5-duality:")
    assert "1 BLAS thread, starts as computed: ok" in lines[0]
    assert "2 BLAS threads, starts jittered (seed 1): REGRESSED" in lines[0]
    table = setups.to_markdown([_run(a, True), _run(b, False)])
    assert table.count("\n") == 4 and "REGRESSED: v" in table


def test_real_claims_under_two_setups_in_their_own_processes():
    runs = setups.run_setups(["eq5-duality", "fig1-acvf"],
                             [setups.Setup(1, 0), setups.Setup(2, 3)], jobs=2)
    assert [r.setup for r in runs] == [setups.Setup(1, 0), setups.Setup(2, 3)]
    assert all(o.status == "ok" for r in runs for o in r.outcomes)
    assert setups.differences(runs) == []


FRAGILE = textwrap.dedent('''
    """A deliberately fragile check: which well of (x^2 - 1)^2 L-BFGS-B reaches from the
    barrier top, under this process's start jitter, reported as the claim eq5-duality."""
    import json, sys
    import numpy as np
    from scipy import optimize
    from roughgp.common import numerics
    x0 = numerics.perturbed_start(np.zeros(1))
    end = optimize.minimize(lambda x: 1e6 * (x[0] ** 2 - 1) ** 2, x0, method="L-BFGS-B").x[0]
    status = "ok" if end > 0.5 else "REGRESSED"
    record = {"key": "eq5-duality", "our_value": f"ends at {end:.3f}", "status": status,
              "seconds": 0.0, "error": None}
    open(sys.argv[1], "w").write(json.dumps({"setup": numerics.setup(), "claims": [record]}))
''')


def test_a_fragile_claim_fails_the_comparison(tmp_path):
    """The comparison says no: a verdict that depends on the start jitter differs between
    set-ups (seeds 1..6 put the start on both sides of the barrier)."""
    script = tmp_path / "fragile.py"
    script.write_text(FRAGILE)
    child = lambda keys, full, out: [sys.executable, str(script), str(out)]  # noqa: E731
    runs = setups.run_setups(["eq5-duality"], [setups.Setup(1, s) for s in range(1, 7)],
                             jobs=2, child=child)
    assert {r.outcomes[0].status for r in runs} == {"ok", "REGRESSED"}
    assert len(setups.differences(runs)) == 1
