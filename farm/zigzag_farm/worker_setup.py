"""Preloaded into the worker processes of a LocalCluster (cluster.local_cluster).

They share the driver's process group, so Ctrl-C in a terminal sends them SIGINT as well;
each would die printing a KeyboardInterrupt traceback. They ignore it instead: the driver,
interrupted, cancels the jobs and closes the cluster, which ends them (and their renderers).
They are spawned with SIGINT blocked (cluster._spawned_with_sigint_blocked), so a Ctrl-C
before this runs (during their imports) waits, pending, and is discarded here.
"""
import signal


def dask_setup(worker):
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # discards a pending SIGINT
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
