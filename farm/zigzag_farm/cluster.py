"""Where jobs run: a LocalCluster on this machine, an existing Dask scheduler, or Slurm.

Every server the LocalCluster starts listens on 127.0.0.1 only: Dask's scheduler and
workers open their HTTP dashboards on 0.0.0.0 unless told otherwise, even with the
dashboard "off" (dask/distributed #6301), hence the explicit dashboard addresses. A Slurm
scheduler must be reached from the nodes: it listens on --interface, with TLS, and its
dashboard on 127.0.0.1.
"""
from __future__ import annotations

import contextlib
import logging
import os
import shutil
import signal

import dask

RENDER_RESOURCE = {"render": 1}  # each worker runs one renderer at a time


def render_slots(worker: dict, default: int = 0) -> int:
    """The renders a worker (an entry of scheduler_info()["workers"]) runs at once."""
    return int(worker.get("resources", {}).get("render", default))


class ClusterError(RuntimeError):
    pass


@contextlib.contextmanager
def local_cluster(workers: int, allowed_failures: int = 3, processes: bool = True,
                  jobs_per_worker: int = 1):
    """workers single-job worker processes here. jobs_per_worker > 1 (the benchmark's
    simulated clusters of many workers that only wait on subprocesses) gives each worker
    that many threads and render slots; processes=False runs the workers in this process."""
    from distributed import Client, LocalCluster
    # Worker processes share the driver's process group, so a terminal's Ctrl-C reaches them
    # too: they ignore it (each would print a KeyboardInterrupt traceback) and the driver,
    # interrupted, shuts them down. In-process workers would make the driver ignore it.
    quiet = {"preload": ["zigzag_farm.worker_setup"]} if processes else {}
    with dask.config.set({"distributed.scheduler.allowed-failures": allowed_failures,
                          "distributed.worker.multiprocessing-method": "spawn"}), \
            _spawned_with_sigint_blocked():
        with _signals_deferred() as replay:
            cluster = LocalCluster(n_workers=workers, threads_per_worker=jobs_per_worker, processes=processes,
                                   protocol="tcp://", host="127.0.0.1", dashboard_address="127.0.0.1:0",
                                   worker_dashboard_address="127.0.0.1:0",
                                   resources={"render": jobs_per_worker}, silence_logs=logging.CRITICAL,
                                   **quiet)
        try:
            replay()  # a Ctrl-C or SIGTERM during the start, taken now that the cluster can close
            with Client(cluster) as client:
                yield client
        finally:
            cluster.close()


@contextlib.contextmanager
def _signals_deferred():
    """SIGINT and SIGTERM recorded, not acted on, in the block; yields replay(), which acts on
    them (their handlers as they were). LocalCluster's constructor interrupted leaves a cluster
    half started that no one holds, and its close at exit fails with a traceback (workers in
    Status.init); so a Ctrl-C while it starts ends the driver once it has started (seconds)."""
    import threading
    if threading.current_thread() is not threading.main_thread():
        yield lambda: None
        return
    caught: list[int] = []
    previous = {}
    for sig in (signal.SIGINT, signal.SIGTERM):
        handler = signal.getsignal(sig)
        if handler not in (signal.SIG_IGN, None):
            previous[sig] = handler
            signal.signal(sig, lambda signum, frame: caught.append(signum))

    def replay():
        for signum in caught:
            handler = previous[signum]
            if callable(handler):
                handler(signum, None)
            else:  # SIG_DFL
                os.kill(os.getpid(), signum)

    try:
        yield replay
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


@contextlib.contextmanager
def _spawned_with_sigint_blocked():
    """Processes multiprocessing spawns meanwhile (the LocalCluster's workers, a nanny's
    restart of one) start with SIGINT blocked: a blocked signal stays blocked across exec, so a
    Ctrl-C while a worker imports stays pending instead of raising KeyboardInterrupt there
    (dozens of lines of tracebacks and "Nanny failed to start"), and worker_setup discards it
    by ignoring SIGINT. Only the spawning thread blocks it, for the spawn: the driver's main
    thread still takes Ctrl-C."""
    import multiprocessing.util as mp_util
    original = mp_util.spawnv_passfds

    def spawnv_passfds(path, args, passfds):
        old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
        try:
            return original(path, args, passfds)
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, old)

    mp_util.spawnv_passfds = spawnv_passfds
    try:
        yield
    finally:
        mp_util.spawnv_passfds = original


@contextlib.contextmanager
def existing_scheduler(address: str, wait_s: float):
    from distributed import Client
    try:
        client = Client(address, timeout=wait_s)
    except (OSError, TimeoutError, ValueError) as e:  # ValueError: not an address
        raise ClusterError(f"cannot reach the Dask scheduler at {address}: {e}") from None
    except Exception as e:  # noqa: BLE001 - a service that is no Dask scheduler answered: its
        # bytes read as Dask's frames give anything (a MemoryError for a huge frame length)
        raise ClusterError(f"cannot reach the Dask scheduler at {address}: what answered there is no "
                           f"Dask scheduler ({type(e).__name__}: {' '.join(str(e).split())[:200]})") from None
    # A lost scheduler is the driver's one line (cli.internal_error_line): Dask's client
    # would log its reconnection attempts, tracebacks included, on the way there.
    with contextlib.ExitStack() as restore, client:
        for name in ("distributed", "distributed.client"):  # the second has a level of its own
            log = logging.getLogger(name)
            restore.callback(log.setLevel, log.level)
            log.setLevel(logging.CRITICAL + 1)
        _wait_for_render_workers(client, wait_s,
                                 f"start workers with `dask worker {address} --nthreads 1 "
                                 "--resources render=1 --dashboard-address 127.0.0.1:0`")
        yield client


def slurm_options(*, queue=None, account=None, walltime=None, memory=None, cores=None,
                  interface=None) -> dict:
    """SLURMCluster arguments: one worker per Slurm job, offering render=1 (it may have many
    threads; the resource still lets it run one render at a time, with all the job's cores).
    What is not given comes from the dask-jobqueue configuration (~/.config/dask/jobqueue.yaml,
    section jobqueue.slurm)."""
    options = {k: v for k, v in dict(queue=queue, account=account, walltime=walltime,
                                     memory=memory, cores=cores, interface=interface).items()
               if v is not None}
    options["processes"] = 1
    # Given here, the argument replaces the configuration's worker-extra-args: keep them
    # (e.g. --lifetime, which a Slurm walltime calls for) before our render slot.
    options["worker_extra_args"] = [*(dask.config.get("jobqueue.slurm.worker-extra-args", None) or []),
                                    "--resources", "render=1"]
    # The scheduler must listen where the nodes reach it, so it speaks TLS with credentials
    # made for this run (workers read theirs from jobqueue's shared-temp-directory): no one
    # else on that network can submit work. Its dashboard stays on this machine (jobqueue's
    # default is every interface); the configuration's scheduler-options still win.
    options["security"] = True
    options["scheduler_options"] = {"dashboard_address": "127.0.0.1:0",
                                    **dask.config.get("jobqueue.slurm.scheduler-options", {})}
    return options


JOBQUEUE_YAML = "~/.config/dask/jobqueue.yaml"


def check_slurm(**options) -> None:
    """What --slurm would fail on once started, as a usage error naming where it is set: the
    worker jobs' cores and memory (SLURMCluster's "You must specify ..." and a size it cannot
    read), and sbatch, which submits them (else a traceback from the submitting thread)."""
    from dask.utils import parse_bytes
    for key, flag in (("cores", "--slurm-cores"), ("memory", "--slurm-memory")):
        if options.get(key) is None and dask.config.get(f"jobqueue.slurm.{key}", None) is None:
            raise ClusterError(f"--slurm: how many {key} each worker job has is not set: give {flag} or "
                               f"set {key} in {JOBQUEUE_YAML} (jobqueue: slurm: {key}:)")
    memory = options.get("memory")
    where = f"--slurm-memory {memory}" if memory is not None else f"memory in {JOBQUEUE_YAML}"
    memory = memory if memory is not None else dask.config.get("jobqueue.slurm.memory")
    try:
        parse_bytes(memory)
    except (ValueError, TypeError):
        raise ClusterError(f"{where}: {memory!r} is not a size (e.g. 8GB)") from None
    if shutil.which("sbatch") is None:
        raise ClusterError("--slurm: sbatch not found on PATH (Slurm submits the worker jobs with it: "
                           "run on a machine that submits Slurm jobs)")


@contextlib.contextmanager
def slurm_cluster(jobs: int, wait_s: float, **options):
    """jobs Slurm jobs of one worker each (see slurm_options)."""
    from dask_jobqueue import SLURMCluster
    from distributed import Client
    check_slurm(**options)
    try:
        cluster = SLURMCluster(**slurm_options(**options))
    except ValueError as e:  # what check_slurm does not foresee: still the configuration
        raise ClusterError(f"--slurm: {e} (the --slurm-* options or {JOBQUEUE_YAML})") from None
    try:
        # Adaptive at a fixed size, not scale(): a job that ends (walltime, node failure) is
        # submitted again instead of leaving the batch with fewer workers, or none.
        cluster.adapt(minimum_jobs=jobs, maximum_jobs=jobs)
        with Client(cluster) as client:
            _wait_for_render_workers(client, wait_s, "check `squeue` for the worker jobs")
            yield client
    finally:
        cluster.close()


def _wait_for_render_workers(client, wait_s: float, hint: str) -> None:
    try:
        client.wait_for_workers(1, timeout=wait_s)
    except TimeoutError:
        raise ClusterError(f"no Dask worker joined within {wait_s:g} s: {hint}") from None
    workers = client.scheduler_info()["workers"].values()
    if not any(render_slots(w) >= 1 for w in workers):
        raise ClusterError(f"no worker offers the resource render=1 (jobs would wait forever): {hint}")
