#!/usr/bin/env python3
"""The scheduler examples of docs/fleet.md (docs/fleet/), checked so that they cannot rot:

- slurm-array.sbatch: `bash -n` (and shellcheck where installed); its #SBATCH --array=0-M covers
  PARTS = M + 1 parts (its default), one GPU each, and the sweep takes --shard
  "$SLURM_ARRAY_TASK_ID/$PARTS". The script itself runs, as array task M, against the built tool
  with SWEEP_ARGS=--dry-run; tests/fleet_slurm_test.sh submits it for real to a local Slurm.
- k8s-indexed-job.yaml: parsed (python3-yaml); an Indexed Job whose completions, parallelism and
  PARTS agree, one GPU a pod, --shard "$JOB_COMPLETION_INDEX/$PARTS"; a merge Job. `kubectl
  --dry-run=client` needs an API server, so the pod's command runs instead, as index M, with
  --dry-run.
- github-actions-matrix.yml: parsed; the sweep job's matrix runs on [self-hosted, gpu] and takes
  --shard "${{ matrix.shard }}/${{ strategy.job-total }}"; the merge job needs it, merges, and has
  the ci-compare step, with the committed noise file and a results history restored from the
  cache before it. The sweep step's command runs, as the matrix's last entry, with --dry-run.

Each dry run prints its part of the fixture's variants and every part's estimate; it must name
the part the example asked for, of as many parts as the example has.

usage: tests/fleet_examples_test.py HYBRIDBENCH SOURCE_DIR"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

try:
    import yaml
except ImportError:
    print("fleet_examples_test: python3-yaml is missing; run scripts/setup.sh (Debian package python3-yaml)",
          file=sys.stderr)
    sys.exit(1)

failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def dry_run(what, argv, env, index, parts):
    """Runs an example's command (argv) with env; it must dry-run part index of parts."""
    r = subprocess.run(argv, env={**os.environ, **env}, capture_output=True, text=True, timeout=300)
    ok = r.returncode == 0 and f"shard {index}/{parts}:" in r.stdout and f"part {parts - 1}/{parts}:" in r.stdout
    ok = ok and "validation:" not in r.stdout + r.stderr  # the Vulkan validation layers said nothing
    check(ok, f"{what}: its sweep runs (--dry-run) as part {index}/{parts}")
    if not ok:
        print(r.stdout[-2000:], r.stderr[-2000:], sep="\n")


def main():
    if len(sys.argv) != 3:
        print(__doc__.splitlines()[-1], file=sys.stderr)
        return 2
    hb, src = os.path.abspath(sys.argv[1]), sys.argv[2]
    fleet = os.path.join(src, "docs", "fleet")
    fixture = os.path.join(src, "tests", "fixtures", "sweep-shard.json")
    out = tempfile.mkdtemp(prefix="hybridbench_fleet_")
    try:
        # What every dry run shares: the built tool, a small config, a scratch --out (nothing is
        # written by a dry run), the validation layers.
        common = {"HYBRIDBENCH": hb, "CONFIG": fixture, "OUT": out, "SWEEP_ARGS": "--dry-run",
                  "HYBRIDBENCH_VALIDATION": "1"}

        # Slurm.
        sbatch = os.path.join(fleet, "slurm-array.sbatch")
        text = open(sbatch).read()
        check(subprocess.run(["bash", "-n", sbatch]).returncode == 0, "slurm: bash -n")
        if shutil.which("shellcheck"):
            check(subprocess.run(["shellcheck", sbatch]).returncode == 0, "slurm: shellcheck")
        array = re.search(r"^#SBATCH --array=0-(\d+)$", text, re.M)
        parts = re.search(r'^PARTS="\$\{PARTS:-(\d+)\}"$', text, re.M)
        check(bool(array and parts), 'slurm: #SBATCH --array=0-M and PARTS="${PARTS:-N}"')
        if array and parts:
            last, n = int(array.group(1)), int(parts.group(1))
            check(n == last + 1, f"slurm: PARTS={n} is the --array range's size ({last + 1})")
            check(re.search(r"^#SBATCH --gres=gpu:1$", text, re.M) is not None, "slurm: one GPU a task")
            check('--shard "$SLURM_ARRAY_TASK_ID/$PARTS"' in text, "slurm: --shard from $SLURM_ARRAY_TASK_ID")
            dry_run("slurm", ["bash", sbatch], {**common, "SLURM_ARRAY_TASK_ID": str(last),
                                                "SLURM_ARRAY_JOB_ID": "1"}, last, n)

        # Kubernetes.
        docs = list(yaml.safe_load_all(open(os.path.join(fleet, "k8s-indexed-job.yaml"))))
        jobs = {d["metadata"]["name"]: d for d in docs if d and d.get("kind") == "Job"}
        sweep, merge = jobs.get("hybridbench-sweep"), jobs.get("hybridbench-merge")
        check(sweep is not None and merge is not None, "k8s: a sweep Job and a merge Job")
        if sweep and merge:
            spec = sweep["spec"]
            check(spec.get("completionMode") == "Indexed", "k8s: completionMode: Indexed")
            n = spec.get("completions")
            check(isinstance(n, int) and spec.get("parallelism") == n, "k8s: completions = parallelism")
            pod = spec["template"]["spec"]["containers"][0]
            env = {e["name"]: e.get("value") for e in pod.get("env", [])}
            check(env.get("PARTS") == str(n), f"k8s: PARTS is completions ({n})")
            check(pod.get("resources", {}).get("limits", {}).get("nvidia.com/gpu") == 1, "k8s: one GPU a pod")
            command = pod["command"] + pod["args"]
            check(command[:2] == ["sh", "-c"] and '--shard "$JOB_COMPLETION_INDEX/$PARTS"' in command[2],
                  "k8s: sh -c with --shard from $JOB_COMPLETION_INDEX")
            merge_args = " ".join(merge["spec"]["template"]["spec"]["containers"][0]["args"])
            check("hybridbench merge /results/part-*" in merge_args, "k8s: the merge Job merges every part")
            dry_run("k8s", command, {**common, "PARTS": str(n), "JOB_COMPLETION_INDEX": str(n - 1)}, n - 1, n)

        # GitHub Actions.
        wf = yaml.safe_load(open(os.path.join(fleet, "github-actions-matrix.yml")))
        jobs = wf.get("jobs", {})
        sweep, merge = jobs.get("sweep", {}), jobs.get("merge", {})
        check(sweep.get("runs-on") == ["self-hosted", "gpu"], "actions: sweep runs-on [self-hosted, gpu]")
        shards = sweep.get("strategy", {}).get("matrix", {}).get("shard")
        check(isinstance(shards, list) and shards == list(range(len(shards))), "actions: matrix.shard is 0..N-1")
        needs = merge.get("needs")
        check(needs == "sweep" or (isinstance(needs, list) and "sweep" in needs), "actions: merge needs sweep")
        steps = {s.get("name"): s for s in merge.get("steps", [])}
        check("hybridbench merge parts/part-* --out out/merged" in steps.get("merge", {}).get("run", ""),
              "actions: the merge step")
        compare = steps.get("ci-compare", {}).get("run", "")
        check("scripts/ci-compare.sh" in compare and "RESULTS=out/merged/results.json" in compare,
              "actions: the ci-compare step runs scripts/ci-compare.sh on the merged results")
        check("HISTORY=perf-history" in compare and "NOISE=results/noise/noise.json" in compare,
              "actions: the ci-compare step keeps a results history and uses the committed noise file")
        cache = steps.get("results history", {})
        check(cache.get("uses", "").startswith("actions/cache@") and cache.get("with", {}).get("path") == "perf-history"
              and cache.get("with", {}).get("restore-keys") == "perf-history-",
              "actions: the results history is restored before ci-compare and saved after it")
        names = [s.get("name") for s in merge.get("steps", [])]
        check("results history" in names and "ci-compare" in names
              and names.index("results history") < names.index("ci-compare"),
              "actions: the history is restored before ci-compare runs")
        run = next((s["run"] for s in sweep.get("steps", []) if "--shard" in s.get("run", "")), "")
        check('--shard "${{ matrix.shard }}/${{ strategy.job-total }}"' in run,
              "actions: --shard from the matrix and strategy.job-total")
        if shards and run:
            n = len(shards)
            command = (run.replace("${{ matrix.shard }}", str(n - 1)).replace("${{ strategy.job-total }}", str(n))
                       .replace("build/hybridbench", '"$HYBRIDBENCH"').replace('"out/', '"$OUT/'))
            dry_run("actions", ["bash", "-c", command + " --dry-run"], common, n - 1, n)
    finally:
        shutil.rmtree(out, ignore_errors=True)
    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
