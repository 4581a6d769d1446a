"""Preloaded into the worker processes of a LocalCluster (cluster.local_cluster).

They share the driver's process group, so Ctrl-C in a terminal sends them SIGINT as well;
each would die printing a KeyboardInterrupt traceback. They ignore it instead: the driver,
interrupted, cancels the jobs and closes the cluster, which ends them (and their renderers).
"""
import signal


def dask_setup(worker):
    signal.signal(signal.SIGINT, signal.SIG_IGN)
