"""A worker killed mid-run loses only the cases it held; running the batch again completes them."""

from __future__ import annotations

import os
import signal
import sys
import threading

import pytest

from patternbridge.batch import CaseStatus, StageEvent, run_batch
from patternbridge.workflow import FitOptions


def _blas_threads() -> int:
    from threadpoolctl import threadpool_info

    return max((pool["num_threads"] for pool in threadpool_info() if pool["user_api"] == "blas"), default=0)


@pytest.mark.slow
def test_a_killed_worker_loses_only_its_cases_and_a_rerun_completes_them(batch_inputs, tmp_path):
    import dask
    from distributed import Client

    from patternbridge.batch.cluster import local_cluster

    p = batch_inputs
    characters = [str(p["hero"]), str(p["big"])]
    garments = [str(p["skirt"])]
    options = FitOptions(pop_size=20, n_gen=30)
    out = tmp_path / "out"
    # no retries: a case whose worker dies is reported lost at once (by default Dask retries it elsewhere)
    with (
        dask.config.set({"distributed.scheduler.allowed-failures": 0}),
        local_cluster(2, dashboard_address=None) as cluster,
        Client(cluster) as client,
    ):
        # workers keep glibc's sliding mmap threshold (see batch/cluster.py) and one BLAS thread
        environ = client.run(lambda: (os.environ.get("MALLOC_TRIM_THRESHOLD_"), os.environ.get("OMP_NUM_THREADS")))
        assert set(environ.values()) == {(None, "1")}
        # and without the profiler thread sampling every task's stack
        assert set(client.run(lambda: dask.config.get("distributed.worker.profile.enabled")).values()) == {False}
        assert set(client.run(lambda: dask.config.get("distributed.admin.tick.interval")).values()) == {"1s"}
        # forked from this process, they hold its modules, and each runs its BLAS on one thread
        assert all(client.run(lambda: "patternbridge.grade.run" in sys.modules).values())
        assert set(client.run(_blas_threads).values()) == {1}
        pids = client.run(os.getpid)
        killed: dict[str, str] = {}
        lock = threading.Lock()

        def kill_on_grade(event: StageEvent) -> None:
            # kill the worker of the first case that reaches the grader, mid-case
            with lock:
                if event.stage == "grade" and not killed:
                    killed[event.case] = event.worker
                    os.kill(pids[event.worker], signal.SIGKILL)

        first = run_batch(
            characters, garments, out, client=client, seed=5, options=options, stage_progress=kill_on_grade
        )
        assert killed, "no case reached the grader"
        lost = {o.case.key for o in first.outcomes if o.status is CaseStatus.LOST}
        assert lost and set(killed) <= lost
        assert all(o.status is CaseStatus.DONE for o in first.outcomes if o.case.key not in lost)
        for key in lost:
            assert not (out / key).exists()
            assert not (out / key.split("/")[0] / f"{key.split('/')[1]}.failed.json").exists()
        # the re-run goes to whichever workers there are (the nanny restarts the killed one when it can)
        second = run_batch(characters, garments, out, client=client, seed=5, options=options)
    assert second.is_complete
    assert {o.case.key for o in second.outcomes if not o.reused} == lost
    for key in lost:
        assert (out / key / "fit_report.json").is_file()
    assert not [q for q in out.rglob(".part-*")]
