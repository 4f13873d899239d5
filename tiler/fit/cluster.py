"""Run the streamed fit's row bands on a Dask cluster (``lanterna fit --scheduler``).

The stack becomes a ``dask.array`` chunked over row bands (each block read by the worker that
solves it, through its own :class:`~lanterna.tiler.inputs.stack.StackReader`, so the images must be
at the same paths on every worker); each block is solved by the engine's per-band step there.
A bounded window of bands is in flight and the results come back in order, so the client
writes the planes exactly as the local loop does: same bytes, same report.

Each worker opens the files for every band it reads: TIFFs (striped or tiled) are read
directly at any row, while JPEG/PNG decode from the top of the image for every band; on a
cluster, prefer TIFF inputs or tall bands (``--band-rows``).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Iterator, Sequence
from types import TracebackType
from typing import Any

import numpy as np
import numpy.typing as npt

from lanterna.errors import LanternaInputError


def _read_rows(images: Any, y0: int, y1: int) -> npt.NDArray[np.float32]:
    return np.asarray(images[:, y0:y1], np.float32)


def _run_step(step: Callable[[npt.NDArray[np.float32], float, int], Any],
              band: npt.NDArray[np.float32], y0: int) -> Any:
    return step(band, 1.0, y0)


class DaskRunner:
    """Solve row bands on the Dask scheduler at ``address`` (``local`` or ``local:N``: start a
    :class:`dask.distributed.LocalCluster` of N worker processes, default 2).

    Use as a context manager; ``window`` bands per worker thread are in flight at once.
    """

    def __init__(self, address: str, window: int = 2) -> None:
        try:
            from dask.distributed import Client, LocalCluster
        except ImportError:
            raise LanternaInputError(None, "--scheduler needs Dask: pip install "
                                     "'dask[distributed]' (or 'lanterna[cluster]')") from None
        self._cluster: Any = None
        if address == "local" or address.startswith("local:"):
            workers = int(address.partition(":")[2] or 2)
            # the scheduler's HTTP server on a free port: its default, 8787, may be taken by
            # another cluster on the machine (distributed then warns and moves)
            self._cluster = LocalCluster(n_workers=workers, threads_per_worker=1,
                                         processes=True, dashboard_address=":0")
            self.client = Client(self._cluster)
        else:
            try:
                self.client = Client(address, timeout=10)
            except (OSError, TimeoutError) as err:
                raise LanternaInputError(None, f"cannot reach the Dask scheduler at "
                                         f"{address}: {err}") from None
        threads = sum(self.client.nthreads().values()) or 1
        self.in_flight = max(1, window * threads)

    def bands(self, images: Any, spans: Sequence[tuple[int, int]],
              step: Callable[[npt.NDArray[np.float32], float, int], Any]) -> Iterator[Any]:
        """Yield ``step(images[:, y0:y1], 1.0, y0)`` for every span, in order, computed on the
        cluster."""
        import dask.array as da
        from dask.delayed import delayed

        n, _, w, c = images.shape
        blocks = [da.from_delayed(delayed(_read_rows)(images, y0, y1),
                                  shape=(n, y1 - y0, w, c), dtype=np.float32)
                  for y0, y1 in spans]
        stack = da.concatenate(blocks, axis=1)  # one chunk per row band
        step_future = self.client.scatter(step, broadcast=True)
        pending: deque[Any] = deque()
        for i, (y0, _) in enumerate(spans):
            block = stack.blocks[0, i, 0, 0]
            pending.append(self.client.compute(delayed(_run_step)(step_future, block, y0)))
            if len(pending) >= self.in_flight:
                yield pending.popleft().result()
        while pending:
            yield pending.popleft().result()

    def __enter__(self) -> DaskRunner:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.client.close()
        if self._cluster is not None:
            self._cluster.close()
