#!/usr/bin/env python3
"""Runs a modia3d sweep file on HyperQueue: one task per shard, then merges the parts.

The shard binary is a program that calls `modia3d::core::sweep_main` with the user's model
registry, e.g. `examples/sweep_shard.rs` (`cargo build --release --example sweep_shard`).
Needs the `hyperqueue` Python package (`pip install hyperqueue==0.27.0`; the wheel carries the
HyperQueue server and worker, so `--local-workers` needs nothing else).

    # On one machine: a local HyperQueue cluster with 2 workers, 8 shards.
    python3 scripts/hq_sweep.py examples/bouncing_sweep.json \\
        --binary target/release/examples/sweep_shard --shards 8 --local-workers 2 \\
        --out out/sweep.csv

    # On a cluster: a server already running (`hq server start` on the login node, workers
    # started by Slurm jobs `hq worker start`); the server directory as `hq` uses it.
    python3 scripts/hq_sweep.py sweep.json --binary ./sweep_shard --shards 64 \\
        --server-dir ~/.hq-server --cpus-per-task 4 --out sweep.csv

Each task runs `<binary> run <sweep> --shard I --of N --out <parts>/part-I.csv` with
`RAYON_NUM_THREADS` set to the task's CPUs; its output goes to `<parts>/shard-I.{out,err}`.
When every task has finished, `<binary> merge` joins the parts in row order into `--out` and
checks that every point is there once. Exit status 0 on success; a failed task is reported
with the paths of its output files.
"""

import argparse
import pathlib
import subprocess
import sys


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("sweep", type=pathlib.Path, help="sweep file (JSON)")
    ap.add_argument("--binary", type=pathlib.Path, required=True, help="the shard binary")
    ap.add_argument("--shards", type=int, required=True, help="number of shards (tasks)")
    ap.add_argument("--out", type=pathlib.Path, required=True, help="merged table (CSV)")
    ap.add_argument(
        "--parts-dir",
        type=pathlib.Path,
        help="where the parts go (default: <out without .csv>-parts/); must be on a file "
        "system the workers share",
    )
    where = ap.add_mutually_exclusive_group()
    where.add_argument(
        "--server-dir", type=pathlib.Path, help="server directory of a running HyperQueue server"
    )
    where.add_argument(
        "--local-workers",
        type=int,
        help="start a local HyperQueue cluster with this many workers instead",
    )
    ap.add_argument("--cpus-per-task", type=int, default=1, help="CPUs of each task (default 1)")
    args = ap.parse_args(argv)
    if args.shards < 1 or args.cpus_per_task < 1:
        ap.error("--shards and --cpus-per-task must be at least 1")
    if args.local_workers is not None and args.local_workers < 1:
        ap.error("--local-workers must be at least 1")
    return args


def make_job(args, parts):
    from hyperqueue import Job
    from hyperqueue.ffi.protocol import ResourceRequest

    binary = str(args.binary.resolve())
    sweep = str(args.sweep.resolve())
    job = Job()
    for i, part in enumerate(parts):
        job.program(
            [binary, "run", sweep, "--shard", str(i), "--of", str(args.shards), "--out", str(part)],
            env={"RAYON_NUM_THREADS": str(args.cpus_per_task)},
            stdout=str(part.parent / f"shard-{i}.out"),
            stderr=str(part.parent / f"shard-{i}.err"),
            resources=ResourceRequest(cpus=args.cpus_per_task),
            name=f"shard-{i}",
        )
    return job


def submit_and_wait(client, job):
    submitted = client.submit(job)
    # Raises FailedJobsException (naming the failed tasks and their output files).
    client.wait_for_jobs([submitted])


def main(argv=None):
    args = parse_args(argv)
    if not args.binary.is_file():
        sys.exit(f"hq_sweep: no shard binary at {args.binary}: build it first "
                 "(cargo build --release --example sweep_shard)")
    parts_dir = args.parts_dir or args.out.with_name(args.out.stem + "-parts")
    parts_dir = parts_dir.resolve()
    parts_dir.mkdir(parents=True, exist_ok=True)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    parts = [parts_dir / f"part-{i}.csv" for i in range(args.shards)]
    for p in parts:
        p.unlink(missing_ok=True)  # a stale part must not be merged
    job = make_job(args, parts)

    from hyperqueue import Client
    from hyperqueue.cluster import LocalCluster, WorkerConfig

    if args.local_workers:
        with LocalCluster() as cluster:
            for _ in range(args.local_workers):
                cluster.start_worker(WorkerConfig(cores=args.cpus_per_task))
            submit_and_wait(cluster.client(), job)
    else:
        submit_and_wait(Client(args.server_dir), job)

    merged = subprocess.run(
        [str(args.binary.resolve()), "merge", str(args.sweep.resolve()), "--out", str(args.out)]
        + [str(p) for p in parts],
        capture_output=True,
        text=True,
    )
    if merged.returncode != 0:
        sys.exit(f"hq_sweep: merge failed:\n{merged.stderr}")
    print(merged.stdout.strip())


if __name__ == "__main__":
    main()
