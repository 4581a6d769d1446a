"""--slurm: the Slurm job script dask-jobqueue writes for a worker (nothing is submitted)."""
from dask_jobqueue.slurm import SLURMJob

from zigzag_farm.cluster import slurm_options


def test_a_slurm_worker_offers_one_render_slot_with_all_its_cores():
    options = slurm_options(queue="render", account="vfx", walltime="04:00:00", memory="64GB", cores=32)
    script = SLURMJob(scheduler="tcp://127.0.0.1:8786", name="zz", **options).job_script()
    assert "#SBATCH -p render" in script and "#SBATCH -A vfx" in script
    assert "#SBATCH --cpus-per-task=32" in script and "#SBATCH -t 04:00:00" in script
    worker = script.strip().splitlines()[-1]
    assert "tcp://127.0.0.1:8786" in worker and "--resources render=1" in worker
    assert "--nthreads 32" in worker  # one worker per job with the job's cores ...
    assert worker.count("--nthreads") == 1  # ... and render=1 keeps it to one render at a time


def test_unset_options_are_left_to_the_jobqueue_configuration():
    options = slurm_options(cores=8)
    assert options == {"cores": 8, "processes": 1, "worker_extra_args": ["--resources", "render=1"]}
