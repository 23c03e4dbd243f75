"""Where frames go during a run: the interface every consumer implements.

The run loop hands each frame (and the filter's result for it, when a filter runs in the
loop) to a list of sinks: the Rerun logger, the frame writer, data-set writers, metrics.
A sink that is not wanted is simply not in the list, and :class:`NullSink` is the
do-nothing twin, so the loop never branches on "is logging on?".
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol

if TYPE_CHECKING:
    from twsb_sim.frame import Frame
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

    def on_frame(self, frame: Frame, filter_result: Any | None) -> None:
        pass

    def on_event(self, t_s: float, text: str) -> None:
        pass

    def close(self, summary: RunSummary) -> None:
        pass
