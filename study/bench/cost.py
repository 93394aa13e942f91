"""Estimated against measured case times: ``python -m study.bench.cost CAMPAIGN [...]``.

Runs cases of campaign files in this process, one after the other (as one rank of ``run``
does), and prints a table: campaign, case, the estimate of :mod:`study.campaign.cost` (s), the
measured wall and CPU seconds of the solve, and the ratio measured / estimated.  ``--cases``
picks case numbers of a campaign (``FILE:0,5,11``), so a few cases of an expensive campaign
stand for it; ``--jsonl`` appends one record per case (the iteration totals, grid sizes and
times) for refitting the model's factors; ``--replay`` prints the table of such records again
with the current model and calibration (no solves).

Example::

    python -m study.bench.cost campaigns/quickstart.toml campaigns/fretting_ii.toml:0,4
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from ..campaign import cost
from ..run import calibration as machine

_TOTALS = ("normal_iterations", "slip_iterations", "coupling_iterations", "plastic_iterations")


def _target(text: str) -> tuple[str, list[int] | None]:
    """``FILE`` or ``FILE:n1,n2,...`` -> (file, case numbers or None for all)."""
    path, sep, numbers = text.partition(":")
    if not sep:
        return path, None
    return path, [int(n) for n in numbers.split(",") if n.strip()]


def measure_case(case) -> dict:
    """Solve one :class:`solver.Case` here: iteration totals, wall and CPU seconds."""
    import solver

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        wall, cpu = time.perf_counter(), time.process_time()
        result = solver.solve(case)
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    record = {"wall": wall, "cpu": cpu, "status": result.status}
    for name in _TOTALS:
        record[name] = int(np.sum(result.history[name])) if name in result.history else 0
    return record


def run(targets: list[str], ranks: int = 1, jsonl: str | None = None) -> int:
    """Run the cases of ``targets`` and print the table; 0 when every ratio is within 2x.

    Parameters
    ----------
    targets : list of str
        Campaign files, each optionally ``:n1,n2`` (case numbers).
    ranks : int
        Ranks for the campaign estimate printed per file (list scheduling, :func:`.cost.
        campaign_seconds`).
    jsonl : str, optional
        File to append one JSON record per case to.

    Returns
    -------
    int
        Exit status: 0 when every case is within a factor 2 of its estimate, else 1.
    """
    from ..campaign import load_campaign as load_campaign_file
    from ..run.driver import solver_case

    calibration = machine.calibration()
    print(f"calibration: {machine.describe_calibration(calibration)}")
    header = (
        f"{'campaign':28s} {'case':>4s} {'estimated s':>11s} {'wall s':>8s} {'CPU s':>8s} "
        f"{'ratio':>6s}  label"
    )
    print(header)
    worst = 1.0
    for text in targets:
        path, numbers = _target(text)
        campaign = load_campaign_file(path)
        chosen = [c for c in campaign.cases if numbers is None or c.number in numbers]
        estimates, measured = [], []
        for campaign_case in chosen:
            case = solver_case(campaign_case)
            estimate = cost.case_seconds(case, calibration)
            record = measure_case(case)
            ratio = record["cpu"] / estimate if estimate > 0 else float("nan")
            worst = max(worst, ratio, 1.0 / ratio if ratio > 0 else float("inf"))
            estimates.append(estimate)
            measured.append(record["cpu"])
            print(
                f"{campaign.name:28s} {campaign_case.number:4d} {estimate:11.2f} "
                f"{record['wall']:8.2f} {record['cpu']:8.2f} {ratio:6.2f}  {campaign_case.label}",
                flush=True,
            )
            if jsonl:
                row = {
                    "campaign": campaign.name,
                    "number": campaign_case.number,
                    "label": campaign_case.label,
                    "estimate": estimate,
                    **cost.features(case),
                    **record,
                }
                with Path(jsonl).open("a") as handle:
                    handle.write(json.dumps(row) + "\n")
        _summary(campaign.name, estimates, measured, ranks)
    print(f"worst factor between measured CPU and estimated: {worst:.2f}")
    return 0 if worst <= 2.0 else 1


def _summary(name: str, estimates: list[float], measured: list[float], ranks: int) -> None:
    """A campaign's rows: the sum on one rank, and on ``ranks`` ranks as the driver hands out."""
    if len(estimates) < 2:
        return
    print(
        f"{name:28s}  sum {sum(estimates):11.2f} {'':8s} {sum(measured):8.2f} "
        f"{sum(measured) / sum(estimates):6.2f}  (these {len(estimates)} cases, 1 rank)"
    )
    if ranks > 1:
        planned = cost.campaign_seconds(estimates, ranks)
        # the measured CPU times handed out in the estimated order (what the driver does)
        clock = [0.0] * ranks
        for _, taken in sorted(zip(estimates, measured, strict=True), key=lambda p: -p[0]):
            clock[clock.index(min(clock))] += taken
        print(
            f"{name:28s}  on {ranks} ranks {planned:9.2f} {'':8s} {max(clock):8.2f} "
            f"{max(clock) / planned:6.2f}  (list scheduling, costliest estimate first)"
        )


def replay(records: str, ranks: int = 1) -> int:
    """The table again from ``--jsonl`` records, with the current model and calibration.

    The measured times are the records'; only the estimates are recomputed (after a change
    of the model's factors or a recalibration), from the features the records hold.
    """
    calibration = machine.calibration()
    print(f"calibration: {machine.describe_calibration(calibration)}")
    rows: dict[str, list[tuple[dict, float]]] = {}
    for line in Path(records).read_text().splitlines():
        if line.strip():
            record = json.loads(line)
            estimate = cost.seconds(cost.count_features(record), calibration)
            rows.setdefault(record["campaign"], []).append((record, estimate))
    print(
        f"{'campaign':28s} {'case':>4s} {'estimated s':>11s} {'wall s':>8s} {'CPU s':>8s} "
        f"{'ratio':>6s}  label"
    )
    worst = 1.0
    for name, found in rows.items():
        for record, estimate in found:
            ratio = record["cpu"] / estimate
            worst = max(worst, ratio, 1.0 / ratio)
            print(
                f"{name:28s} {record['number']:4d} {estimate:11.2f} {record['wall']:8.2f} "
                f"{record['cpu']:8.2f} {ratio:6.2f}  {record['label']}"
            )
        estimates = [estimate for _, estimate in found]
        measured = [record["cpu"] for record, _ in found]
        _summary(name, estimates, measured, ranks)
    print(f"worst factor between measured CPU and estimated: {worst:.2f}")
    return 0 if worst <= 2.0 else 1


def main(argv: list[str] | None = None) -> int:
    """Command line of the cost benchmark."""
    parser = argparse.ArgumentParser(
        prog="python -m study.bench.cost", description=__doc__.split("\n\n")[0]
    )
    parser.add_argument("targets", nargs="*", metavar="FILE[:N,...]", help="campaign files")
    parser.add_argument("--jsonl", help="append one JSON record per case to this file")
    parser.add_argument("--ranks", type=int, default=1, help="ranks for campaign estimates")
    parser.add_argument(
        "--replay",
        metavar="JSONL",
        help="print the table of earlier --jsonl records with the current model (no solves)",
    )
    args = parser.parse_args(argv)
    if args.replay:
        return replay(args.replay, args.ranks)
    if not args.targets:
        parser.error("give campaign files, or --replay JSONL")
    return run(args.targets, args.ranks, args.jsonl)


if __name__ == "__main__":
    sys.exit(main())
