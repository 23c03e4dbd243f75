"""Where frames go during a run: the interface every consumer implements.

The run loop hands each frame (and the filter's result for it, when a filter runs in the
loop) to a list of sinks: the Rerun logger, the frame writer, data-set writers, metrics.
A sink that is not wanted is simply not in the list, and :class:`NullSink` is the
do-nothing twin, so the loop never branches on "is logging on?".

Two hooks are optional (the run loop calls them only on sinks that have them):

- ``on_start(scenario, sim)``: once, before the first frame, with the scenario and the
  :class:`~twsb_sim.simulation.Simulation` (its house and compiled model);
- ``on_state(truth)``: the robot's :class:`~twsb_sim.frame.RobotTruth` every
  ``1 / state_rate_hz`` seconds, for sinks whose ``state_rate_hz`` attribute is set (e.g.
  plots smoother than the 10 Hz frames). The truth is read without recomputing derived
  quantities: pose, rates, torques and commands are current, the IMU readings and the
  sensor pose are those of the previous physics step. With no such sink, the loop adds
  no work.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol

if TYPE_CHECKING:
    from twsb_sim.frame import Frame, RobotTruth
    from twsb_sim.scenario import Scenario
    from twsb_sim.simulation import Simulation
    from twsb_sim.summary import RunSummary


class FrameSink(Protocol):
    """A consumer of a run's frames."""

    def on_frame(self, frame: Frame, filter_result: Any | None) -> None:
        """Called once per LiDAR frame, in time order.

        Args:
            frame: the simulated frame with its ground truth.
            filter_result: what the filter in the loop returned for ``frame.scan``
                (a :class:`pvfilter.FilterResult`), or None when no filter runs.
        """

    def on_event(self, t_s: float, text: str) -> None:
        """A scenario event: a phase starts, a shove begins, the robot falls."""

    def close(self, summary: RunSummary) -> None:
        """The run has ended (normally, by a fall, or interrupted)."""


class NullSink:
    """A sink that does nothing (the twin of every real sink)."""

    state_rate_hz: float | None = None  # no on_state calls

    def on_start(self, scenario: Scenario, sim: Simulation) -> None:
        pass

    def on_state(self, truth: RobotTruth) -> None:
        pass

    def on_frame(self, frame: Frame, filter_result: Any | None) -> None:
        pass

    def on_event(self, t_s: float, text: str) -> None:
        pass

    def close(self, summary: RunSummary) -> None:
        pass
