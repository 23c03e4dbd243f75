"""The paper's two-thread form (III-B): preprocessing + detection, then tracking.

One thread clusters scan t and runs Algorithm 1 while the other tracks scan t-1 and
removes its clusters. The two halves share no state (detection keeps the previous
scan's KD-tree, tracking keeps the queue), and each thread sees the scans in order, so
the results are exactly those of :class:`~pvfilter.paper.PitchVariationFilter`.

With CPython's global interpreter lock the gain is limited to the time numpy and scipy
spend outside it; the form is here because the paper describes it, and for callers that
want the filter off their own thread.
"""

from __future__ import annotations

import queue
import threading
from collections.abc import Iterable, Iterator

from pvfilter.contract import check_scan, params_or_defaults
from pvfilter.paper.filter import PaperResult, PitchVariationFilter
from pvfilter.paper.params import FilterParams
from pvfilter.scan import Scan

_RESET = object()  # a marker passed down the pipeline in scan order
_STOP = object()


class ThreadedPitchVariationFilter:
    """The filter run as two threads in one process; results come back in scan order.

    Use it as a context manager (or call :meth:`close`) so the threads end::

        with ThreadedPitchVariationFilter() as pvf:
            for result in pvf.process_stream(scans):
                ...

    Args:
        params: the parameters; Table I defaults when omitted.
        max_pending: scans that may be in flight before :meth:`submit` blocks.
    """

    def __init__(self, params: FilterParams | None = None, max_pending: int = 8) -> None:
        # (refused as this filter's, before a thread starts)
        params = params_or_defaults(params, FilterParams, "ThreadedPitchVariationFilter")
        self._filter = PitchVariationFilter(params)
        self.max_pending = max_pending
        self._scans: queue.Queue = queue.Queue(maxsize=max_pending)
        self._detections: queue.Queue = queue.Queue(maxsize=max_pending)
        self._results: queue.Queue = queue.Queue()
        self._pending = 0
        self._threads = (
            threading.Thread(target=self._detect_loop, name="pvfilter-detection", daemon=True),
            threading.Thread(target=self._track_loop, name="pvfilter-tracking", daemon=True),
        )
        for thread in self._threads:
            thread.start()

    @property
    def params(self) -> FilterParams:
        """The filter's parameters."""
        return self._filter.params

    def submit(self, scan: Scan) -> None:
        """Queue a scan (in time order); blocks while ``max_pending`` scans are in flight.

        Raises:
            TypeError: ``scan`` is not a Scan (refused here, not in the worker thread).
        """
        check_scan(scan)
        self._scans.put(scan)
        self._pending += 1

    def result(self, timeout: float | None = None) -> PaperResult:
        """The next result, in submission order.

        Raises:
            queue.Empty: nothing arrived within ``timeout`` seconds.
            Exception: whatever processing that scan raised.
        """
        item = self._results.get(timeout=timeout)
        self._pending -= 1
        if isinstance(item, BaseException):
            raise item
        return item

    def process(self, scan: Scan, **robot_inputs: object) -> PaperResult:
        """Filter one scan and wait for its result (no overlap; same API as sequential).

        The robot inputs of :class:`pvfilter.ScanFilter` are accepted and ignored.
        """
        self.submit(scan)
        return self.result()

    def process_stream(self, scans: Iterable[Scan]) -> Iterator[PaperResult]:
        """Filter a sequence with both threads busy; yields one result per scan, in order."""
        for scan in scans:
            if self._pending >= self.max_pending:
                yield self.result()
            self.submit(scan)
        while self._pending:
            yield self.result()

    def reset(self) -> None:
        """Forget the history from the next submitted scan on (a new sequence)."""
        self._scans.put(_RESET)

    def close(self) -> None:
        """Finish the scans in flight and end both threads."""
        if self._threads[0].is_alive():
            self._scans.put(_STOP)
        for thread in self._threads:
            thread.join()

    def __enter__(self) -> ThreadedPitchVariationFilter:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def _detect_loop(self) -> None:
        while (item := self._scans.get()) is not _STOP:
            if item is _RESET:
                self._filter.reset()  # only flags the next scan, read by this thread
                continue
            try:
                item = self._filter.cluster_and_detect(item)
            except Exception as error:  # handed to the caller by result()
                item = error
            self._detections.put(item)
        self._detections.put(_STOP)

    def _track_loop(self) -> None:
        while (item := self._detections.get()) is not _STOP:
            if not isinstance(item, Exception):
                try:
                    item = self._filter.track_and_remove(item)
                except Exception as error:
                    item = error
            self._results.put(item)
