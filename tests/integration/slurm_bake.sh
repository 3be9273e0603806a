# romkit plan --slurm on a single-node Slurm cluster started here: munged with its own key and
# socket, slurmctld and slurmd in the foreground, all in a temp folder (no cgroups: proctrack
# linuxproc, task none). A tiny scene with a training list of two scenes is planned, submit.sh
# submits its training runs as one job array and the basis, cubature and bake chained with
# afterok; the asset must be byte-identical to romkit build's. The job array and the dependencies
# (scontrol show job) are printed into this log. The daemons are stopped on exit, always.
# Needs root and Debian's slurmctld, slurmd and munge (tools/install-deps.sh test); else skips.
. tests/lib.sh
NAME=slurm_bake
[ "$(id -u)" = 0 ] || { echo "skip $NAME: starting a Slurm cluster here needs root"; exit 0; }
for t in munged slurmctld slurmd sbatch squeue sinfo scontrol make; do
    command -v "$t" >/dev/null 2>&1 || [ -x "/usr/sbin/$t" ] || {
        echo "skip $NAME: $t is not installed (tools/install-deps.sh test)"; exit 0; }
done
PATH=$PATH:/usr/sbin
export ROMKIT_THREADS=1
D=$TMP/cluster
mkdir -p "$D/state" "$D/spool" "$D/munge"
chmod 0700 "$D/munge"
stop() {
    for f in "$D/slurmd.pid" "$D/slurmctld.pid" "$D/munged.pid"; do
        [ -s "$f" ] && kill "$(cat "$f")" 2>/dev/null
    done
    for pid in $SLURMD $SLURMCTLD; do kill "$pid" 2>/dev/null; done
    sleep 1
    for pid in $SLURMD $SLURMCTLD; do kill -9 "$pid" 2>/dev/null; done
    [ -s "$D/munged.pid" ] && kill -9 "$(cat "$D/munged.pid")" 2>/dev/null
    rm -rf "$TMP"
}
SLURMD= SLURMCTLD=
trap stop EXIT
trap 'exit 1' INT TERM

# a free TCP port from $1 up (none listening on it in /proc/net/tcp*)
free_port() {
    p=$1
    while grep -qi ":$(printf '%04X' "$p") " /proc/net/tcp /proc/net/tcp6 2>/dev/null; do p=$((p + 1)); done
    echo "$p"
}
base=$((20000 + $$ % 20000))
CTLD_PORT=$(free_port "$base")
SLURMD_PORT=$(free_port $((CTLD_PORT + 1)))
HOST=$(hostname -s)

dd if=/dev/urandom of="$D/munge/munge.key" bs=1024 count=1 2>/dev/null
chmod 0400 "$D/munge/munge.key"
munged --force --key-file="$D/munge/munge.key" --socket="$D/munge/munge.sock" --pid-file="$D/munged.pid" \
    --log-file="$D/munged.log" --seed-file="$D/munge/seed" >"$D/munged.out" 2>&1 ||
    { fail $NAME "munged did not start: $(cat "$D/munged.out" "$D/munged.log" 2>/dev/null | tail -3)"; exit 0; }

export SLURM_CONF=$D/slurm.conf
cat >"$SLURM_CONF" <<CONF
ClusterName=romkit-test
SlurmctldHost=$HOST(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$D/munge/munge.sock
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
StateSaveLocation=$D/state
SlurmdSpoolDir=$D/spool
SlurmctldPidFile=$D/slurmctld.pid
SlurmdPidFile=$D/slurmd.pid
SlurmctldLogFile=$D/slurmctld.log
SlurmdLogFile=$D/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
MinJobAge=600
MailProg=/bin/true
NodeName=$HOST NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=debug Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
CONF
slurmctld -D -f "$SLURM_CONF" >"$D/slurmctld.out" 2>&1 &
SLURMCTLD=$!
slurmd -D -f "$SLURM_CONF" -N "$HOST" >"$D/slurmd.out" 2>&1 &
SLURMD=$!
idle=
for i in $(seq 1 60); do
    state=$(sinfo -h -n "$HOST" -o %t 2>/dev/null)
    case $state in idle*) idle=1; break ;; esac
    sleep 0.5
done
if [ -z "$idle" ]; then
    fail $NAME "the node did not come up idle (sinfo: '$state'): $(tail -3 "$D/slurmctld.log" "$D/slurmd.log" 2>/dev/null)"
    exit 0
fi
echo "# $NAME: node $HOST idle: slurmctld on port $CTLD_PORT, slurmd on $SLURMD_PORT, $(nproc) CPUs"

# the scene: a cantilever (60 vertices) trained on two runs under other gravities, pod + cubature
scene() { cantilever "$1" 6 "$2" "$3"; } # tests/lib.sh's cantilever, 60 vertices
mkdir "$TMP/s"
scene "$TMP/s/a.json" -9.81 '{"basis": "modes", "size": 6}'
scene "$TMP/s/b.json" -30 '{"basis": "modes", "size": 6}'
scene "$TMP/s/bake.json" -15 '{"basis": "pod", "size": 5, "cubature": {"tolerance": 0.05}, "training": ["a.json", "b.json"]}'
"$ROMKIT" build "$TMP/s/bake.json" -o "$TMP/ref.rombin" --quiet >/dev/null 2>"$TMP/err" ||
    { fail $NAME "romkit build: $(cat "$TMP/err")"; exit 0; }
"$ROMKIT" plan "$TMP/s/bake.json" -o "$TMP/plan" --slurm >"$TMP/plan.out" 2>&1 ||
    { fail $NAME "romkit plan: $(cat "$TMP/plan.out")"; exit 0; }
if ! sh "$TMP/plan/submit.sh" >"$TMP/submit.out" 2>&1; then
    fail $NAME "submit.sh: $(cat "$TMP/submit.out")"
    exit 0
fi
echo "# submit.sh:"; sed 's/^/#   /' "$TMP/submit.out"
jobs=$(awk '{print $2}' "$TMP/submit.out" | tr '\n' ' ')
train=$(awk '$1 == "train" {print $2}' "$TMP/submit.out")
bake=$(awk '$1 == "bake" {print $2}' "$TMP/submit.out")
echo "# scontrol show job (the array and the afterok chain, while they wait):"
for j in $jobs; do
    scontrol show job "$j" 2>/dev/null | grep -E 'JobId=|JobName=|ArrayJobId|Dependency=|JobState=' | sed 's/^ */#   /'
done
# wait: squeue until none of ours is left (no slurmdbd, so no sacct), at most 60 s
for i in $(seq 1 120); do
    left=$(squeue -h -o %i 2>/dev/null | wc -l)
    [ "$left" -eq 0 ] && break
    sleep 0.5
done
[ "$left" -eq 0 ] && ok slurm_jobs_finished || fail slurm_jobs_finished "$left jobs still queued after 60 s: $(squeue 2>&1 | tail -5)"
echo "# step logs:"
for f in "$TMP/plan/logs"/*.out; do echo "#   $(basename "$f"): $(grep -E ': exit [0-9]+$' "$f" | tail -1)"; done
n_ok=$(cat "$TMP/plan/logs"/*.out 2>/dev/null | grep -c ': exit 0$')
[ "$n_ok" -eq 5 ] && ok slurm_five_steps_exit_0 || fail slurm_five_steps_exit_0 "$n_ok of 5 steps said exit 0: $(tail -n 3 "$TMP/plan/logs"/*.out)"
ls "$TMP/plan/logs"/train-"$train"_0.out "$TMP/plan/logs"/train-"$train"_1.out >/dev/null 2>&1 &&
    ok slurm_training_runs_one_array || fail slurm_training_runs_one_array "no train-${train}_0/1 logs: $(ls "$TMP/plan/logs")"
basis=$(awk '$1 == "basis" {print $2}' "$TMP/submit.out")
cubature=$(awk '$1 == "cubature" {print $2}' "$TMP/submit.out")
grep -qx "basis $basis afterok:$train" "$TMP/submit.out" && grep -qx "cubature $cubature afterok:$train:$basis" "$TMP/submit.out" &&
    grep -qx "bake $bake afterok:$basis:$cubature" "$TMP/submit.out" &&
    ok slurm_afterok_chain || fail slurm_afterok_chain "$(cat "$TMP/submit.out")"
if cmp "$TMP/ref.rombin" "$TMP/plan/asset.rombin"; then ok slurm_asset_identical
else fail slurm_asset_identical "the Slurm bake's asset differs from romkit build's"; fi

# resumption on Slurm: the cubature deleted and everything resubmitted, only the cubature and the
# bake run again (each script asks make -q whether its output is up to date)
rm -f "$TMP/plan/cubature.json" "$TMP/plan/logs"/*.out
sh "$TMP/plan/submit.sh" >"$TMP/submit2.out" 2>&1 || fail slurm_resubmit "$(cat "$TMP/submit2.out")"
for i in $(seq 1 120); do
    left=$(squeue -h -o %i 2>/dev/null | wc -l)
    [ "$left" -eq 0 ] && break
    sleep 0.5
done
skipped=$(cat "$TMP/plan/logs"/*.out 2>/dev/null | grep -c 'is up to date$')
reran=$(cat "$TMP/plan/logs"/*.out 2>/dev/null | grep -c ': exit 0$')
echo "# resubmitted: $skipped steps up to date, $reran ran"
if [ "$skipped" -eq 3 ] && [ "$reran" -eq 2 ] && grep -q '^cubature: exit 0$' "$TMP/plan/logs"/cubature-*.out &&
    cmp -s "$TMP/ref.rombin" "$TMP/plan/asset.rombin"; then ok slurm_resubmit_redoes_only_what_is_missing
else fail slurm_resubmit_redoes_only_what_is_missing "$skipped up to date, $reran ran: $(tail -n 2 "$TMP/plan/logs"/*.out)"; fi
