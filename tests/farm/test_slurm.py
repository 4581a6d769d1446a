"""--slurm: the Slurm job script dask-jobqueue writes for a worker, and the scheduler the
driver starts for them (on the loopback interface here; nothing is submitted)."""
import os
import sys

import dask
import pytest
from dask_jobqueue import SLURMCluster

from conftest import FAKE_ZIGZAG, listening_sockets, write_scene
from zigzag_farm import cli
from zigzag_farm.cluster import ClusterError, check_slurm, slurm_options


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


@pytest.fixture
def no_slurm_configuration(monkeypatch, workdir):
    """No cores or memory in jobqueue.yaml, no sbatch on PATH (the venv's python3 still is)."""
    monkeypatch.chdir(workdir)
    monkeypatch.setenv("PATH", os.path.dirname(sys.executable))
    with dask.config.set({"jobqueue.slurm.cores": None, "jobqueue.slurm.memory": None}):
        yield


@pytest.mark.parametrize("args,message", [
    (["--slurm-memory", "1GB"], "--slurm: how many cores each worker job has is not set: give --slurm-cores or set "
                                "cores in ~/.config/dask/jobqueue.yaml"),
    (["--slurm-cores", "8"], "give --slurm-memory or set memory in ~/.config/dask/jobqueue.yaml"),
    (["--slurm-cores", "8", "--slurm-memory", "lots"], "--slurm-memory lots: 'lots' is not a size (e.g. 8GB)"),
    (["--slurm-cores", "8", "--slurm-memory", "1GB"], "--slurm: sbatch not found on PATH"),
])
def test_slurm_misconfiguration_is_a_usage_error(capsys, no_slurm_configuration, workdir, args, message):
    """Reported as "internal error: ValueError: You must specify ...; a re-run renders the rest"
    (exit 1), and without sbatch a tornado traceback (review)."""
    scene = write_scene(workdir, "still")
    code = cli.main(["render", "-q", scene, "-o", f"{workdir}/out/x.png", "--zigzag", FAKE_ZIGZAG, "--slurm", "1",
                     "--wait", "3", *args])
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.startswith("zigzag-farm: error: ") and message in err, err
    assert "Traceback" not in err and "re-run" not in err and "internal error" not in err
    assert not os.path.exists(f"{workdir}/out")


def test_slurm_memory_from_the_configuration_is_checked_too(no_slurm_configuration):
    with dask.config.set({"jobqueue.slurm.cores": 4, "jobqueue.slurm.memory": "plenty"}):
        with pytest.raises(ClusterError, match=r"memory in ~/.config/dask/jobqueue.yaml: 'plenty' is not a size"):
            check_slurm()
        with pytest.raises(ClusterError, match="sbatch not found on PATH"):
            check_slurm(memory="2GB")
