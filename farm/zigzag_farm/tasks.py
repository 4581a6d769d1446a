"""The functions Dask runs on workers: job.render / job.merge, cancelled with their task.

A running task cannot be interrupted by Dask; instead the job polls its worker's state and
kills its renderer's process group once the scheduler has released the task (the driver
cancelled it, or the driver went away).
"""
from __future__ import annotations

from . import job


def _task_cancelled():
    try:
        from distributed import get_worker
        from distributed.worker import thread_state
        worker, key = get_worker(), thread_state.key
    except (ImportError, ValueError, AttributeError):
        return lambda: False

    def cancelled() -> bool:
        ts = worker.state.tasks.get(key)
        return ts is None or ts.state == "cancelled"
    return cancelled


def render_task(spec: dict) -> dict:
    return job.render(spec, cancelled=_task_cancelled())


def merge_task(spec: dict, *parts_done) -> dict:
    # parts_done: the part jobs' results, passed only so Dask runs the merge after them.
    return job.merge(spec, cancelled=_task_cancelled())
