#!/usr/bin/env bash
# Runs docs/sweeps.md's commands as written (the page quotes these lines and
# fixtures/sweep_trike.py, fixtures/slurm_sweep.sh): the trike's sweep on every
# core, on one worker, from Python, on a Dask cluster started by hand on this
# machine (HOME a scratch folder, its ~/symdyn/build/release/python this build's),
# and on one started by the Slurm script, srun running its command once here.
# Each makes the same table, byte for byte.
#   run_sweeps.sh <repo> <symdyn-sim> <python dir of the build> <python> <scratch dir>
set -euo pipefail
repo=$1 sim=$2 python_dir=$3 python=$4 scratch=$5
fail() { echo "error: docs/sweeps.md: $*" >&2; exit 1; }
same_table() {  # the sweep's table, as the first command made it
  cmp -s tyres.csv reference.csv || fail "$1 made another table: $(diff tyres.csv reference.csv | head -5)"
}

rm -rf "$scratch"
mkdir -p "$scratch/home/symdyn/build/release" "$scratch/bin" "$scratch/models"
export HOME=$scratch/home
ln -s "$python_dir" "$HOME/symdyn/build/release/python"
cp -r "$repo/models/sweeps" "$scratch/models/"
cp "$repo/models/sweeps/trike_tyres.json" "$scratch/tyres.json"
cp "$repo/tests/docs/fixtures/sweep_trike.py" "$scratch/"
PATH=$(dirname "$sim"):$PATH
unset SYMDYN_SIM PYTHONPATH
cd "$scratch"

symdyn-sim --sweep models/sweeps/trike_tyres.json               # every core of this machine
symdyn-sim --sweep tyres.json --workers 1                        # one run after the other
mv trike_tyres.csv reference.csv
same_table "--workers 1"
summary=$(PYTHONPATH=$python_dir "$python" sweep_trike.py)
[[ $summary =~ ^"9 runs (9 ok); 9 made in "[0-9:]+" on "[0-9]+" local workers"?$ ]] ||
  fail "sweep_trike.py printed '$summary'"
same_table "symdyn.sweep"

# Dask's background work made rarer; each name is one of Dask's own settings
# (a misspelt one would be taken silently) and the value is the one Dask reads.
export DASK_DISTRIBUTED__WORKER__PROFILE__ENABLED=False DASK_DISTRIBUTED__ADMIN__TICK__INTERVAL=1s \
       DASK_DISTRIBUTED__WORKER__MEMORY__MONITOR_INTERVAL=1s DASK_DISTRIBUTED__ADMIN__SYSTEM_MONITOR__INTERVAL=2s
"$python" - <<'PY' || fail "the DASK_ settings are not Dask's"
import functools, os
import dask.config, distributed  # distributed adds its settings to Dask's defaults
defaults = functools.reduce(dask.config.merge, dask.config.defaults)
for name, value in os.environ.items():
    if name.startswith("DASK_"):
        key = name[5:].lower().replace("__", ".")
        dask.config.get(key, config=defaults)  # KeyError: not a setting of Dask
        assert str(dask.config.get(key)) == value, (key, dask.config.get(key), value)
PY

# By hand: "one machine", "each" and "anywhere" are this one. Each command in a
# process group of its own (set -m), killed whole at the end: the worker's nanny,
# its worker process and their engines.
set -m
trap 'for group in $(jobs -p); do kill -KILL -- -$group 2>/dev/null || true; done' EXIT
dask scheduler --scheduler-file $HOME/scheduler.json --port 0 >scheduler.log 2>&1 &
PYTHONPATH=$HOME/symdyn/build/release/python dask worker --scheduler-file $HOME/scheduler.json --nworkers 1 --nthreads $(nproc) >worker.log 2>&1 &
for _ in $(seq 600); do [ -s "$HOME/scheduler.json" ] && break; sleep 0.1; done
symdyn-sim --sweep tyres.json --scheduler $HOME/scheduler.json  # the workers of a Dask cluster
same_table "the Dask cluster started by hand"
for group in $(jobs -p); do kill -KILL -- -$group; done
set +m
trap - EXIT

# The Slurm script on one node: srun runs its command once, here. timeout leads the
# script's process group, which ends with the script (the scheduler and the worker
# it left behind), as a job's does, or after two minutes.
printf '#!/bin/sh\nexec "$@"\n' >"$scratch/bin/srun"
chmod +x "$scratch/bin/srun"
rm tyres.csv
PATH=$scratch/bin:$PATH SLURM_JOB_ID=7 timeout -s KILL 120 sh "$repo/tests/docs/fixtures/slurm_sweep.sh" >slurm.log 2>&1 &
job=$!
trap 'kill -KILL -- -$job 2>/dev/null || true' EXIT
wait $job || { cat slurm.log; fail "the Slurm script failed"; }
same_table "the Slurm script"
