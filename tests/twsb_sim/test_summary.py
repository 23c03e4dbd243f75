"""The run summary's printed report (twsb_sim.summary)."""

from __future__ import annotations

import pytest

from twsb_sim.summary import RunSummary


@pytest.mark.parametrize(
    ("simulated_s", "wall_s", "printed"),
    [
        (8.0, 0.4, "(20x real time)"),
        (8.0, 14.4, "(0.6x real time)"),  # a first run compiling the kernels: slower
        (8.0, 1.0, "(8.0x real time)"),
    ],
)
def test_the_real_time_factor_is_printed_without_rounding_a_slow_run_up_to_real_time(
    simulated_s: float, wall_s: float, printed: str
):
    summary = RunSummary("hard_stop", 0, "house1", simulated_s=simulated_s, wall_s=wall_s)
    assert printed in summary.format().splitlines()[1]
