"""``patternbridge batch``: fit every garment to every character on a Dask cluster.

A ``LocalCluster`` (one single-threaded worker process per core) unless
``--scheduler`` names a running one; see docs/batch.md for clusters over
several machines. Writes ``OUT/<character>/<garment>/`` per case,
``OUT/batch.json`` and ``OUT/index.html``. Exit status: 0 when every case is
done, 1 when a case failed or was lost, 3 when all are done but a drape's
verdict is ``failed``.
"""

from __future__ import annotations

import argparse
import logging
import os
import sys

from .fit import add_fit_options, options_from_args

HELP = "fit every garment to every character on a Dask cluster; write OUT/index.html and OUT/batch.json"

__all__ = ["HELP", "add_arguments", "run"]


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "characters",
        nargs="+",
        metavar="CHARACTER",
        help="character meshes (with their .json sidecars) or measurements JSONs",
    )
    parser.add_argument(
        "--garments",
        nargs="+",
        required=True,
        metavar="NAME|FILE",
        help="library garment names or pattern files (JSON, DXF with bridge data)",
    )
    parser.add_argument("-o", "--output", required=True, metavar="OUT/", help="output folder")
    parser.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="address of a running Dask scheduler (tcp://host:8786); default: a local cluster",
    )
    parser.add_argument(
        "--workers",
        type=int,
        default=None,
        metavar="N",
        help="workers of the local cluster (default: the number of cores)",
    )
    parser.add_argument(
        "--memory-limit",
        default="auto",
        metavar="SIZE",
        help="memory limit per local worker, e.g. 4GB (default: the machine's memory / N)",
    )
    parser.add_argument(
        "--retry-failed", action="store_true", help="run again the cases an earlier run recorded as failed"
    )
    add_fit_options(parser)


def _quiet_dask() -> None:
    """Dask logs its cluster's life at INFO on loggers of its own levels; keep warnings and errors."""
    import distributed  # noqa: F401  (configures its loggers)

    for name in list(logging.root.manager.loggerDict):
        if name == "distributed" or name.startswith("distributed."):
            logging.getLogger(name).setLevel(logging.WARNING)


def _client(args: argparse.Namespace, *, drape: bool):
    """``(client, cluster)``: connected to ``--scheduler`` (cluster None) or to a new LocalCluster."""
    from distributed import Client

    from ..batch.cluster import DRAPE_MODULES, FIT_MODULES, local_cluster
    from ..errors import InputError

    if args.scheduler:
        try:
            return Client(args.scheduler, timeout="20s"), None
        except (OSError, TimeoutError) as exc:
            raise InputError(
                f"{args.scheduler}: cannot reach a Dask scheduler ({exc}); start one with "
                "`dask scheduler` and workers with `dask worker ADDRESS` (docs/batch.md)"
            ) from None
    n = args.workers or os.cpu_count() or 1
    if n < 1:
        raise InputError(f"--workers {n}: give at least 1 worker")
    # the workers' own log lines repeat what the batch records per case
    cluster = local_cluster(
        n,
        memory_limit=args.memory_limit,
        silence_logs=logging.CRITICAL if args.verbose < 2 else logging.INFO,
        modules=FIT_MODULES + (DRAPE_MODULES if drape else ()),
    )
    return Client(cluster), cluster


class _Printer:
    """Progress of a batch on stderr: a line per finished case, a line when a running case changes stage."""

    def __init__(self, quiet: bool, verbose: bool) -> None:
        self.quiet, self.verbose = quiet, verbose
        self.stages: dict[str, str] = {}

    def stage(self, event) -> None:
        if self.quiet:
            return
        if self.stages.get(event.case) != event.stage or self.verbose:
            self.stages[event.case] = event.stage
            print(f"[batch] {event.case}: {event.stage} {event.done}/{event.total}", file=sys.stderr, flush=True)

    def case(self, outcome, n_finished: int, n_cases: int) -> None:
        if self.quiet:
            return
        bar = "#" * int(20 * n_finished / max(n_cases, 1))
        what = outcome.status.value + (" (earlier run)" if outcome.reused else "")
        fig = outcome.figures
        detail = outcome.error
        if fig is not None:
            detail = (
                f"measurement {fig.mean_error_cm:.2f} cm, shape {fig.shape_error:.4f} "
                f"(proportional {fig.baseline_shape_error:.4f})"
                + (f", verdict {outcome.verdict.value}" if outcome.verdict else "")
            )
        cost = f"{outcome.seconds:.0f} s"
        if outcome.cpu_seconds:
            cost += f" (CPU {outcome.cpu_seconds:.0f} s, worker peak {outcome.peak_rss_mb:.0f} MB)"
        print(
            f"[batch] [{bar:<20}] {n_finished}/{n_cases} {outcome.case.key}: {what}, {cost}; {detail}",
            file=sys.stderr,
            flush=True,
        )


def run(args: argparse.Namespace) -> int:
    from ..batch import CaseStatus, check_inputs, run_batch
    from ..errors import InputError
    from ..workflow import Verdict

    out = os.path.abspath(args.output)
    if os.path.exists(out) and not os.path.isdir(out):
        raise InputError(f"{args.output}: exists and is not a folder; give a folder for -o")
    options = options_from_args(args)
    check_inputs(args.characters, args.garments)  # before a cluster starts
    # workers on other machines find the files by the same absolute paths (a shared filesystem)
    characters = [os.path.abspath(c) for c in args.characters]
    garments = [os.path.abspath(g) if os.path.isfile(g) else g for g in args.garments]
    if args.verbose < 2:
        _quiet_dask()
    printer = _Printer(quiet=args.quiet > 0, verbose=args.verbose > 0)
    client, cluster = _client(args, drape=options.drape)
    try:
        if not printer.quiet:
            print(
                f"[batch] scheduler {client.scheduler.address}, "
                f"{len(client.scheduler_info().get('workers', {}))} workers; "
                f"dashboard {client.dashboard_link}",
                file=sys.stderr,
                flush=True,
            )
        result = run_batch(
            characters,
            garments,
            out,
            client=client,
            seed=args.seed,
            options=options,
            retry_failed=args.retry_failed,
            stage_progress=printer.stage,
            case_progress=printer.case,
        )
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    n_failed, n_lost = result.count(CaseStatus.FAILED), result.count(CaseStatus.LOST)
    print(
        f"{result.count(CaseStatus.DONE)} of {len(result.outcomes)} cases done, {n_failed} failed, {n_lost} lost "
        f"in {result.seconds:.0f} s; open {os.path.join(out, 'index.html')}"
    )
    if n_failed or n_lost:
        todo = (["run the same command again to complete the lost cases"] if n_lost else []) + (
            ["add --retry-failed to redo the failed ones (OUT/<character>/<garment>.failed.json says why)"]
            if n_failed
            else []
        )
        print("patternbridge: " + "; ".join(todo), file=sys.stderr)
        return 1
    return 3 if any(o.verdict is Verdict.FAILED for o in result.outcomes) else 0
