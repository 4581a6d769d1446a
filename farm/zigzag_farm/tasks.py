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


def _refused(e: job.UsageFailure) -> dict:
    # Returned, not raised: Dask retries every task that raises, and a renderer that refused
    # its options refuses them again. The driver reports the "error" as the job's failure.
    return {"key": None, "error": str(e), "usage": True}


def render_task(spec: dict) -> dict:
    try:
        return job.render(spec, cancelled=_task_cancelled())
    except job.UsageFailure as e:
        return _refused(e)


def merge_task(spec: dict, *parts_done) -> dict:
    # parts_done: the part jobs' results, passed so Dask runs the merge after them.
    if any(isinstance(p, dict) and p.get("error") for p in parts_done):
        return {"key": spec["key"], "error": "a region part failed", "part_failed": True}
    try:
        return job.merge(spec, cancelled=_task_cancelled())
    except job.UsageFailure as e:
        return _refused(e)
