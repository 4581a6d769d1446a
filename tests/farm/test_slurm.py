"""--slurm: the Slurm job script dask-jobqueue writes for a worker, and the scheduler the
driver starts for them (on the loopback interface here; nothing is submitted)."""
import os

import dask
import pytest
from dask_jobqueue import SLURMCluster

from conftest import listening_sockets
from zigzag_farm.cluster import slurm_options


@pytest.fixture
def loopback_slurm(workdir):
    """A SLURMCluster as --slurm makes it, its scheduler on `lo`; worker credentials in workdir."""
    with dask.config.set({"jobqueue.slurm.shared-temp-directory": workdir}):
        options = slurm_options(queue="render", account="vfx", walltime="04:00:00", memory="64GB",
                                cores=32, interface="lo")
        cluster = SLURMCluster(**options)
        try:
            yield cluster
        finally:
            cluster.close()


def test_a_slurm_worker_offers_one_render_slot_with_all_its_cores(loopback_slurm):
    script = loopback_slurm.job_script()
    assert "#SBATCH -p render" in script and "#SBATCH -A vfx" in script
    assert "#SBATCH --cpus-per-task=32" in script and "#SBATCH -t 04:00:00" in script
    worker = script.strip().splitlines()[-1]
    assert "--resources render=1" in worker
    assert "--nthreads 32" in worker  # one worker per job with the job's cores ...
    assert worker.count("--nthreads") == 1  # ... and render=1 keeps it to one render at a time


def test_the_slurm_scheduler_speaks_tls_and_keeps_its_dashboard_local(loopback_slurm, workdir):
    address = loopback_slurm.scheduler_address
    assert address.startswith("tls://127.0.0.1:"), address
    worker = loopback_slurm.job_script().strip().splitlines()[-1]
    assert address in worker
    for flag in ("--tls-ca-file", "--tls-cert", "--tls-key"):
        assert flag in worker, worker
    # The worker's credentials are files in the shared folder, readable by their owner only.
    key = worker.split("--tls-key ")[1].split()[0]
    assert os.path.dirname(key) == workdir and os.stat(key).st_mode & 0o077 == 0
    socks = listening_sockets({os.getpid()})
    assert len(socks) >= 2  # the scheduler and its dashboard
    assert all(s.laddr.ip == "127.0.0.1" for s in socks), socks
    assert "127.0.0.1" in loopback_slurm.dashboard_link


def test_the_configuration_fills_what_is_not_given(workdir):
    lifetime = ["--lifetime", "55m", "--lifetime-stagger", "4m"]
    with dask.config.set({"jobqueue.slurm.scheduler-options": {"port": 8786},
                          "jobqueue.slurm.worker-extra-args": lifetime}):
        options = slurm_options(cores=8)
    assert options == {"cores": 8, "processes": 1, "worker_extra_args": [*lifetime, "--resources", "render=1"],
                       "security": True,
                       "scheduler_options": {"dashboard_address": "127.0.0.1:0", "port": 8786}}
