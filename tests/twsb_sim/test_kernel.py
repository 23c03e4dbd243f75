"""Compiled kernels: a new user is told that the first run compiles them."""

import twsb_sim.runner as runner
from twsb_sim.kernel import FIRST_COMPILE_NOTICE, compiled_on_this_machine
from twsb_sim.scenario import load_scenario

from .test_runner import short


def test_the_first_compile_is_seen_from_numba_s_cache_index(tmp_path):
    assert not compiled_on_this_machine(tmp_path)
    (tmp_path / "__pycache__").mkdir()
    (tmp_path / "__pycache__" / "ray_culling.cast_rays-40.py311.nbi").touch()
    assert compiled_on_this_machine(tmp_path)


def test_a_run_with_a_progress_bar_says_when_it_compiles_first(monkeypatch, capsys):
    scenario = short(load_scenario("scenarios/hard_stop.toml"), 0.2)
    for compiled in (False, True):
        monkeypatch.setattr(runner, "compiled_on_this_machine", lambda done=compiled: done)
        runner.run_scenario(scenario, seed=0, progress=True)
        said = FIRST_COMPILE_NOTICE in capsys.readouterr().err
        assert said is not compiled
