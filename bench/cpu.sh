# Sourced by the bench scripts: cpu FILE COMMAND... runs COMMAND (its output dropped), writing its
# CPU seconds (user + system of the whole process and its children) to FILE, and returns its status.
# On a shared machine the wall time says how the load shared the cores, the CPU time what the run did.
cpu() {
    f=$1
    shift
    python3 -c 'import resource, subprocess, sys
rc = subprocess.call(sys.argv[2:], stdout=subprocess.DEVNULL)
u = resource.getrusage(resource.RUSAGE_CHILDREN)
open(sys.argv[1], "w").write("%.3f\n" % (u.ru_utime + u.ru_stime))
sys.exit(rc)' "$f" "$@"
}
